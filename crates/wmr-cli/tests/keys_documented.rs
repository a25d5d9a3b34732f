//! Every key the parser accepts (listed by `wmr_scenario::schema`, from the types that
//! read them) is documented in `wmr-cli help keys`, in `docs/scenario.md` and, for the
//! Python building blocks, in the stubs (written by `cargo xtask gen` and checked by
//! xtask's tests), each in its own section; where `help keys` shows a default, it is the
//! real one.

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
    let out = Command::new(env!("CARGO_BIN_EXE_wmr-cli")).args(["help", "keys"]).output().unwrap();
    assert!(out.status.success());
    let help = String::from_utf8(out.stdout).unwrap();
    let keys = schema();
    assert!(keys.len() > 60, "the schema lists {} keys", keys.len());
    for k in &keys {
        let section = help_section(&help, k);
        // Keys of the tables are defined on their own line (`key = default  what`); the
        // pose, grid and random keys are written inside their inline tables.
        // A required `[reference]` key has no default to show: its line names it; nor has
        // `[robot] footprint_radius`, whose default is the robot's half_track.
        let required = matches!(k.table, "reference" | "world" | "robot") && k.default.is_none();
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
