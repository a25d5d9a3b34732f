//! Every key the parser accepts (listed by `wmr_scenario::schema`, from the types that
//! read them) is documented in `wmr-cli --help`, in `docs/scenario.md` and, for the
//! Python building blocks, in the stubs, each in its own section; where `--help` and the
//! stubs show a default, it is the real one. The stubs' keyword blocks (every key of
//! `[robot]` and of each controller kind, with its default, unit and doc line) are
//! generated from the schema between markers: `WMR_BLESS=1` rewrites them, and the test
//! fails while they are stale.

use std::path::PathBuf;
use std::process::Command;

use wmr_scenario::{SchemaKey, schema};

fn repo_file(rel: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The part of `text` from the first `start` (after `from`) to the first of `ends` after it.
fn between<'a>(text: &'a str, start: &str, ends: &[&str]) -> &'a str {
    let a = text.find(start).unwrap_or_else(|| panic!("no {start:?}"));
    let rest = &text[a + start.len()..];
    let b = ends.iter().filter_map(|e| rest.find(e)).min().unwrap_or(rest.len());
    &rest[..b]
}

/// True when `key` appears in `text` as a whole word.
fn has_word(text: &str, key: &str) -> bool {
    let is_id = |c: char| c.is_ascii_alphanumeric() || c == '_';
    text.match_indices(key).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + key.len()..].chars().next();
        !before.is_some_and(is_id) && !after.is_some_and(is_id)
    })
}

/// The value written after `key = ` in `text`, if any.
fn shown_default<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    text.lines().find_map(|l| {
        let l = l.trim();
        let rest = l.strip_prefix(key)?.trim_start().strip_prefix('=')?;
        rest.split_whitespace().next()
    })
}

fn same_value(shown: &str, real: &toml::Value) -> bool {
    match real {
        toml::Value::Float(f) => {
            let shown = shown.trim_end_matches(',');
            let v: f64 = match shown {
                "inf" | "math.inf" => f64::INFINITY,
                s => s.parse().unwrap_or(f64::NAN),
            };
            v == *f
        }
        // The stubs spell booleans the Python way.
        toml::Value::Boolean(b) if matches!(shown, "True" | "False") => (shown == "True") == *b,
        other => shown.trim_end_matches(',') == other.to_string(),
    }
}

/// Keys written inside inline tables (`start = { x = .. }`, `grid = { .. }`).
fn inline(k: &SchemaKey) -> bool {
    matches!(k.table, "pose" | "sweep.grid" | "sweep.random" | "sweep.vary") || k.key == "model"
}

/// The `--help` section of a schema table (and kind).
fn help_section<'a>(help: &'a str, k: &SchemaKey) -> &'a str {
    let section = match k.table {
        "" => return between(help, "SCENARIO FILE", &["[robot]"]),
        "robot" => between(help, "\n[robot]", &["\n[drive]"]),
        "drive" => between(help, "\n[drive]", &["\n[controller]"]),
        "controller" => between(help, "\n[controller]", &["\n[sensor]"]),
        "sensor" => between(help, "\n[sensor]", &["\n[world]"]),
        "world" => between(help, "\n[world]", &["\n[reference]"]),
        "reference" => between(help, "\n[reference]", &["\n[sim]"]),
        "sim" => between(help, "\n[sim]", &["\n[[run]]"]),
        "run" | "pose" => between(help, "\n[[run]]", &["\n[sweep]"]),
        _ => between(help, "\n[sweep]", &["\nOUTPUTS"]),
    };
    match k.kind {
        Some(kind) => between(section, &format!("kind = \"{kind}\":"), &["kind = \"", "every kind"]),
        None => section,
    }
}

#[test]
fn help_documents_every_key_with_its_default() {
    let out = Command::new(env!("CARGO_BIN_EXE_wmr-cli")).arg("--help").output().unwrap();
    assert!(out.status.success());
    let help = String::from_utf8(out.stdout).unwrap();
    let keys = schema();
    assert!(keys.len() > 60, "the schema lists {} keys", keys.len());
    for k in &keys {
        let section = help_section(&help, k);
        // Keys of the tables are defined on their own line (`key = default  what`); the
        // pose, grid and random keys are written inside their inline tables.
        // A required `[reference]` key has no default to show: its line names it.
        let required = k.table == "reference" && k.default.is_none();
        let defined =
            if inline(k) || required { has_word(section, k.key) } else { shown_default(section, k.key).is_some() };
        assert!(defined, "--help: {:?} (kind {:?}) lacks {}", k.table, k.kind, k.key);
        // An inline-table default (`center = { x = 0.0, y = 0.0 }`) spans several words.
        if let Some(real) = &k.default
            && !matches!(real, toml::Value::Table(_))
            && let Some(shown) = shown_default(section, k.key)
        {
            assert!(same_value(shown, real), "--help shows {} = {shown}, the default is {real}", k.key);
        }
    }
}

#[test]
fn docs_document_every_key() {
    let doc = repo_file("docs/scenario.md");
    for k in schema() {
        let section = match k.table {
            "" => between(&doc, "## `name`", &["\n## "]),
            "robot" => between(&doc, "## `[robot]`", &["\n## "]),
            "drive" => between(&doc, "## `[drive]`", &["\n## "]),
            "controller" => between(&doc, "## `[controller]`", &["\n## "]),
            "sensor" => between(&doc, "## `[sensor]`", &["\n## "]),
            "world" => between(&doc, "## `[world]`", &["\n## "]),
            "reference" => between(&doc, "## `[reference]`", &["\n## "]),
            "sim" => between(&doc, "## `[sim]`", &["\n## "]),
            "run" | "pose" => between(&doc, "## `[[run]]`", &["\n## "]),
            _ => between(&doc, "## `[sweep]`", &["\n## "]),
        };
        let section = match k.kind {
            Some(kind) => between(section, &format!("### `kind = \"{kind}\"`"), &["\n### "]),
            None => section,
        };
        // A table row per key, except the keys of the inline pose, grid and random tables.
        let defined = if inline(&k) { has_word(section, k.key) } else { section.contains(&format!("| `{}` |", k.key)) };
        assert!(defined, "docs/scenario.md: {:?} (kind {:?}) lacks `{}`", k.table, k.kind, k.key);
    }
}

/// The keyword arguments of `class NAME`'s constructor in a stub (`__new__`, as pyo3
/// classes have it), with their defaults.
fn init_kwargs<'a>(stub: &'a str, class: &str) -> Vec<(&'a str, &'a str)> {
    let init = between(stub, &format!("class {class}:"), &["\nclass "]);
    let init = between(init, "def __new__(", &[") -> Self"]);
    let star = init.find('*').expect("keyword-only arguments");
    init[star..]
        .lines()
        .filter(|l| !l.trim().starts_with('#'))
        .filter_map(|l| {
            let (name, rest) = l.trim().split_once(':')?;
            // `name: type = default,  # [unit] doc`: the default ends at the comma.
            let default = rest.split_once('=').map_or("", |(_, d)| d.split(',').next().unwrap_or("").trim());
            Some((name.trim(), default))
        })
        .collect()
}

#[test]
fn stubs_list_every_robot_and_controller_key_with_its_default() {
    let stub = repo_file("crates/wmr-py/python/wmr_py/_native.pyi");
    let keys = schema();
    let check = |class: &str, expected: Vec<&SchemaKey>| {
        let got = init_kwargs(&stub, class);
        let mut got_names: Vec<&str> = got.iter().map(|(n, _)| *n).collect();
        let mut want: Vec<&str> = expected.iter().map(|k| k.key).collect();
        got_names.sort_unstable();
        want.sort_unstable();
        assert_eq!(got_names, want, "{class}.__init__ keywords");
        for k in expected {
            let shown = got.iter().find(|(n, _)| *n == k.key).map(|(_, d)| *d).unwrap_or("");
            if let Some(real) = &k.default {
                assert!(same_value(shown, real), "{class}: {} = {shown}, the default is {real}", k.key);
            }
        }
    };
    for (class, table, kind) in stub_classes() {
        check(&class, class_keys(&keys, table, kind).iter().collect());
    }
}

/// The stub classes whose `__new__` keywords are the keys of a schema table (and kind):
/// `Robot`, and one class per law of the registry (`wmr_core::for_each_law!`).
fn stub_classes() -> Vec<(String, &'static str, Option<&'static str>)> {
    let laws = wmr_core::LawParams::<f64>::defaults();
    let mut out = vec![("Robot".to_owned(), "robot", None)];
    out.extend(laws.iter().map(|l| (format!("{}Controller", l.name()), "controller", Some(l.kind()))));
    out
}

const GEN_BEGIN: &str =
    "# keys from wmr_scenario::schema(), generated: WMR_BLESS=1 cargo test -p wmr-cli --test keys_documented\n";
const GEN_END: &str = "# end of generated keys\n";

/// The schema keys a stub class takes: the table's keys for every kind and for its own.
/// Python's `Robot` is the core's `RobotParams`: the traction keys of `[robot]`
/// (`wmr_core::TractionParams`, wheels that slip) are read by scenarios only.
fn class_keys(keys: &[SchemaKey], table: &str, kind: Option<&str>) -> Vec<SchemaKey> {
    let traction = |k: &SchemaKey| {
        k.table == "robot"
            && <wmr_core::TractionParams<f64> as wmr_core::describe::Described>::FIELDS.iter().any(|f| f.name == k.key)
    };
    keys.iter()
        .filter(|k| k.table == table && !matches!(k.key, "kind" | "model") && (k.kind.is_none() || k.kind == kind))
        .filter(|k| !traction(k))
        .cloned()
        .collect()
}

/// A default as Python writes it.
fn py_value(v: &toml::Value) -> (&'static str, String) {
    match v {
        toml::Value::Float(f) if f.is_infinite() => {
            ("float", if *f > 0.0 { "math.inf".into() } else { "-math.inf".into() })
        }
        toml::Value::Float(f) => ("float", format!("{f:?}")),
        toml::Value::Integer(i) => ("int", i.to_string()),
        toml::Value::Boolean(b) => ("bool", if *b { "True".into() } else { "False".into() }),
        toml::Value::String(s) => ("str", format!("{s:?}")),
        other => panic!("no Python spelling for the default {other}"),
    }
}

/// The generated keyword lines of a stub class: `name: type = default,  # unit: doc`.
fn keyword_block(keys: &[SchemaKey], indent: &str) -> String {
    let mut out = String::new();
    for k in keys {
        let default = k.default.as_ref().or(k.default_by_drive.first().map(|(_, v)| v));
        let default = default.unwrap_or_else(|| panic!("{} has no default to show", k.key));
        let (ty, value) = py_value(default);
        let unit = if k.unit.is_empty() { String::new() } else { format!(" [{}]", k.unit) };
        out.push_str(&format!("{indent}{}: {ty} = {value},  #{unit} {}\n", k.key, k.doc.trim()));
    }
    out
}

/// The stub with every class's generated block written from the schema.
fn generated_stub(stub: &str) -> String {
    let keys = schema();
    let mut out = stub.to_owned();
    for (class, table, kind) in stub_classes() {
        let start = out.find(&format!("class {class}:")).unwrap_or_else(|| panic!("no class {class}"));
        let a = start + out[start..].find(GEN_BEGIN).unwrap_or_else(|| panic!("{class}: no {GEN_BEGIN:?}"));
        let indent_start = out[..a].rfind('\n').map_or(0, |i| i + 1);
        let indent = out[indent_start..a].to_owned();
        let body = a + GEN_BEGIN.len();
        let b = body + out[body..].find(GEN_END).unwrap_or_else(|| panic!("{class}: no {GEN_END:?}"));
        let b = out[..b].rfind('\n').map_or(b, |i| i + 1);
        out.replace_range(body..b, &keyword_block(&class_keys(&keys, table, kind), &indent));
    }
    out
}

#[test]
fn stub_keywords_are_generated_from_the_schema() {
    let rel = "crates/wmr-py/python/wmr_py/_native.pyi";
    let mut stub = repo_file(rel);
    let want = generated_stub(&stub);
    // Blessing writes the blocks, then checks the file as written (never a silent pass).
    if std::env::var_os("WMR_BLESS").is_some() {
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel);
        std::fs::write(path, &want).unwrap();
        stub = repo_file(rel);
    }
    assert!(
        stub == want,
        "{rel}: the keyword blocks are stale; rerun with WMR_BLESS=1 (first differing line: {:?})",
        stub.lines().zip(want.lines()).find(|(a, b)| a != b)
    );
}
