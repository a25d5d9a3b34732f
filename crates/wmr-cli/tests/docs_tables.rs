//! The key tables of `docs/scenario.md` are generated, between `<!-- keys:ID begin -->`
//! and `<!-- keys:ID end -->`, from the same descriptions as `wmr-cli help keys`
//! (`wmr_scenario::schema`, which reads the core's `params!` declarations); the test
//! fails when the file is stale. Regenerate with
//! `WMR_BLESS=1 cargo test -p wmr-cli --test docs_tables`.
//!
//! It also shows that a robot key is declared once: every `RobotParams::FIELDS` entry is
//! in the schema, in `--help` and in the docs table, in the same order, with its unit,
//! rule and doc line.

use std::path::PathBuf;
use std::process::Command;

use wmr_core::describe::Described;
use wmr_core::{RobotParams, TractionParams};
use wmr_scenario::keys::{toml_scalar, toml_scalar_rounded};
use wmr_scenario::{SchemaKey, schema};

const BLESS: &str = "WMR_BLESS=1 cargo test -p wmr-cli --test docs_tables";

fn doc_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/scenario.md")
}

/// The keys of block `id`: `robot`, `drive` (its `kind`), `drive.torque`, `controller`
/// (its `kind`), `controller.paper`, `controller.every_kind` (the wheel stage and
/// `control_dt`), `sensor`, `world`.
fn block_keys<'a>(keys: &'a [SchemaKey], id: &str) -> Vec<&'a SchemaKey> {
    let (table, sub) = id.split_once('.').map_or((id, None), |(t, s)| (t, Some(s)));
    keys.iter()
        .filter(|k| k.table == table)
        .filter(|k| match sub {
            None if matches!(table, "drive" | "controller") => k.key == "kind",
            None => true,
            Some("every_kind") => k.kind.is_none() && !matches!(k.key, "kind" | "model"),
            Some(kind) => k.kind == Some(kind),
        })
        .collect()
}

/// A Markdown cell: `|` escaped.
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

fn default_cell(k: &SchemaKey) -> String {
    let show = |v: &toml::Value| match v {
        toml::Value::String(_) => format!("`{v}`"),
        v => toml_scalar(v),
    };
    match &k.default {
        Some(v) => show(v),
        None => {
            let shown = |v: &toml::Value| if v.is_float() { toml_scalar_rounded(v) } else { show(v) };
            k.default_by_drive.iter().map(|(kind, v)| format!("{} ({kind})", shown(v))).collect::<Vec<_>>().join(", ")
        }
    }
}

/// The table of `keys`.
fn table(keys: &[&SchemaKey]) -> String {
    let mut out = String::from("| key | unit | default | valid | meaning |\n|---|---|---|---|---|\n");
    for k in keys {
        out.push_str(&format!(
            "| `{}` | {} | {} | {} | {} |\n",
            k.key,
            cell(k.unit),
            default_cell(k),
            cell(&k.rule),
            cell(k.doc)
        ));
    }
    out
}

/// `doc` with every block regenerated; the ids found, in order.
fn regenerate(doc: &str, keys: &[SchemaKey]) -> (String, Vec<String>) {
    let mut out = String::new();
    let mut ids = Vec::new();
    let mut rest = doc;
    while let Some(a) = rest.find("<!-- keys:") {
        let id_end = rest[a..].find(" begin -->").map(|i| a + i).expect("a begin marker");
        let id = &rest[a + "<!-- keys:".len()..id_end];
        let begin = format!("<!-- keys:{id} begin -->\n");
        let end = format!("<!-- keys:{id} end -->");
        let b = rest.find(&end).unwrap_or_else(|| panic!("no {end}"));
        let keys = block_keys(keys, id);
        assert!(!keys.is_empty(), "block {id} has no keys");
        out.push_str(&rest[..a]);
        out.push_str(&begin);
        out.push_str(&table(&keys));
        out.push_str(&end);
        rest = &rest[b + end.len()..];
        ids.push(id.to_owned());
    }
    out.push_str(rest);
    (out, ids)
}

#[test]
fn docs_key_tables_are_generated_from_the_schema() {
    let path = doc_path();
    let doc = std::fs::read_to_string(&path).unwrap();
    let keys = schema();
    let (fresh, ids) = regenerate(&doc, &keys);
    // Every described key is in some block.
    for k in keys.iter().filter(|k| k.is_described() && k.key != "model") {
        let id = match k.kind {
            Some(kind) => format!("{}.{kind}", k.table),
            None if k.table == "controller" && k.key != "kind" => "controller.every_kind".to_owned(),
            None => k.table.to_owned(),
        };
        assert!(ids.contains(&id), "docs/scenario.md has no block keys:{id} for {}", k.key);
    }
    // Blessing writes the tables, then checks the file as written (never a silent pass).
    let doc = if std::env::var_os("WMR_BLESS").is_some() {
        std::fs::write(&path, &fresh).unwrap();
        std::fs::read_to_string(&path).unwrap()
    } else {
        doc
    };
    assert!(fresh == doc, "docs/scenario.md's key tables are stale; regenerate with `{BLESS}`");
}

/// The `[robot]` lines of `wmr-cli help keys`: (key, the rest of the line and its continuations).
fn help_robot_lines() -> Vec<(String, String)> {
    let out = Command::new(env!("CARGO_BIN_EXE_wmr-cli")).args(["help", "keys"]).output().unwrap();
    let help = String::from_utf8(out.stdout).unwrap();
    let section = &help[help.find("\n[robot]").unwrap()..help.find("\n[drive]").unwrap()];
    let mut lines: Vec<(String, String)> = Vec::new();
    for line in section.lines().skip(2) {
        match line.strip_prefix("  ").and_then(|l| l.split_once(" = ")) {
            Some((key, rest)) if !key.starts_with(' ') => lines.push((key.to_owned(), rest.to_owned())),
            _ => lines.last_mut().expect("a key line first").1.push_str(&format!(" {}", line.trim())),
        }
    }
    lines
}

/// A robot key is declared once (`RobotParams`, then the traction keys of
/// `TractionParams`, in wmr-core) and appears, in declaration order, in the schema, in
/// `--help` and in the docs table, with its unit, rule and doc.
#[test]
fn every_robot_field_is_in_the_schema_the_help_and_the_docs_in_order() {
    let fields: Vec<_> = RobotParams::<f64>::FIELDS.iter().chain(TractionParams::<f64>::FIELDS).collect();
    let declared: Vec<&str> = fields.iter().map(|f| f.name).collect();
    let keys = schema();

    let in_schema: Vec<&str> = keys.iter().filter(|k| k.table == "robot").map(|k| k.key).collect();
    assert_eq!(in_schema, declared, "schema");

    let help = help_robot_lines();
    let in_help: Vec<&str> = help.iter().map(|(k, _)| k.as_str()).collect();
    assert_eq!(in_help, declared, "--help [robot]");

    let doc = std::fs::read_to_string(doc_path()).unwrap();
    let block = &doc[doc.find("<!-- keys:robot begin -->").unwrap()..doc.find("<!-- keys:robot end -->").unwrap()];
    let rows: Vec<Vec<&str>> =
        block.lines().skip(3).map(|l| l.trim_matches('|').split(" | ").map(str::trim).collect()).collect();
    let in_docs: Vec<&str> = rows.iter().map(|r| r[0].trim_matches('`')).collect();
    assert_eq!(in_docs, declared, "docs/scenario.md robot table");

    // The words of a line, so that --help's wrapping does not matter.
    let words = |s: &str| s.split_whitespace().collect::<Vec<_>>().join(" ");
    for ((f, (_, help_text)), row) in fields.iter().zip(&help).zip(&rows) {
        let help_text = words(help_text);
        for part in [f.unit, f.rule, f.doc.trim_end_matches('.')] {
            assert!(help_text.contains(&words(part)), "--help {}: {help_text:?} lacks {part:?}", f.name);
        }
        assert_eq!(row[1..], [f.unit, row[2], f.rule, f.doc], "docs row of {}", f.name);
    }
}
