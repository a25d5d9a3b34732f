//! docs/scenario.md's key tables, between `<!-- keys:ID begin -->` and
//! `<!-- keys:ID end -->`, from the same descriptions as `wmr-cli help keys`
//! (`wmr_scenario::schema`, which reads the core's `params!` declarations).

use wmr_scenario::SchemaKey;
use wmr_scenario::keys::{toml_scalar, toml_scalar_rounded};

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
pub fn regenerate(doc: &str, keys: &[SchemaKey]) -> (String, Vec<String>) {
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

/// The id of the block that documents `k` (`robot`, `controller.paper`,
/// `controller.every_kind`, ...): every described key must be in one.
pub fn block_of(k: &SchemaKey) -> String {
    match k.kind {
        Some(kind) => format!("{}.{kind}", k.table),
        None if k.table == "controller" && k.key != "kind" => "controller.every_kind".to_owned(),
        None => k.table.to_owned(),
    }
}
