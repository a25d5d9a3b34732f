//! docs/scenario.md's generated parts: its key tables (`crate::docs_keys`, from the
//! schema), its sweep CSV columns and its table of outcome fields, written from the table
//! every output reads (`wmr_core::OUTCOME_FIELDS`).

use wmr_core::{FieldGroup, OUTCOME_FIELDS};
use wmr_scenario::{sweep_columns, tracking_sweep_columns};

use crate::{Generated, repo_root};

/// The file this generator writes parts of.
pub const PATH: &str = "docs/scenario.md";

/// `text` with the lines between `<!-- NAME begin -->` and `<!-- NAME end -->` replaced
/// by `body` (the marker lines kept); unchanged when a marker is missing.
fn between(text: &str, name: &str, body: &str) -> String {
    let (begin, end) = (format!("<!-- {name} begin -->\n"), format!("<!-- {name} end -->"));
    let Some(a) = text.find(&begin).map(|i| i + begin.len()) else { return text.to_owned() };
    let Some(b) = text[a..].find(&end).map(|i| a + i) else { return text.to_owned() };
    format!("{}{body}{}", &text[..a], &text[b..])
}

/// Which outputs carry a field of `group`.
fn carried_by(group: FieldGroup) -> &'static str {
    match group {
        FieldGroup::Final => "Python",
        FieldGroup::Goal => "sweep CSV, Python",
        FieldGroup::Tracking => "sweep CSV over references, Python",
        FieldGroup::TrackingSetting => "Python's RunResult",
        FieldGroup::Drive => "every sweep CSV, Python",
    }
}

/// The outcome fields as a Markdown table.
fn fields_table() -> String {
    let mut out = String::from("| field | unit | in | meaning |\n|---|---|---|---|\n");
    for f in &OUTCOME_FIELDS {
        out.push_str(&format!(
            "| `{}` | {} | {} | {} |\n",
            f.name,
            f.unit,
            carried_by(f.group),
            f.doc.replace('|', "\\|")
        ));
    }
    out
}

/// docs/scenario.md with its generated parts written.
pub fn generate() -> Generated {
    let text = std::fs::read_to_string(repo_root().join(PATH)).unwrap_or_default();
    let text = between(&text, "columns:sweep", &format!("`{}`\n", sweep_columns().join(",")));
    let text = between(&text, "columns:tracking-sweep", &format!("`{}`\n", tracking_sweep_columns().join(",")));
    let text = between(&text, "outcome-fields", &fields_table());
    let (text, _) = crate::docs_keys::regenerate(&text, &wmr_scenario::schema());
    Generated { path: PATH.into(), text }
}
