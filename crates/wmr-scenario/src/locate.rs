//! Maps between scenario keys (`run[2].start.x`) and places in the TOML text, so every
//! error names its key and its line.

use std::ops::Range;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::error::ScenarioError;

/// 1-based line of a byte offset.
pub(crate) fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes().iter().take(offset).filter(|&&b| b == b'\n').count() + 1
}

/// One step of a key path.
enum Seg<'a> {
    Key(&'a str),
    Index(usize),
}

fn parse_key(key: &str) -> Vec<Seg<'_>> {
    let mut segs = Vec::new();
    for part in key.split('.') {
        let (name, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if !name.is_empty() {
            segs.push(Seg::Key(name));
        }
        while let Some(r) = rest.strip_prefix('[') {
            let Some(end) = r.find(']') else { break };
            if let Ok(i) = r[..end].parse() {
                segs.push(Seg::Index(i));
            }
            rest = &r[end + 1..];
        }
    }
    segs
}

/// Byte span of `key` in the document, or of its deepest parent that is written.
pub(crate) fn span_of_key(text: &str, key: &str) -> Option<Range<usize>> {
    let doc = DeTable::parse(text).ok()?;
    let root = DeValue::Table(doc.into_inner());
    let mut best = None;
    let mut cur = &root;
    for seg in parse_key(key) {
        let next: Option<&Spanned<DeValue<'_>>> = match (seg, cur) {
            (Seg::Key(k), DeValue::Table(t)) => {
                t.iter().find(|(name, _)| name.get_ref().as_ref() == k).map(|(name, v)| {
                    best = Some(name.span());
                    v
                })
            }
            (Seg::Index(i), DeValue::Array(a)) => a.get(i).inspect(|v| {
                if best.is_none() || !matches!(v.get_ref(), DeValue::Table(_)) {
                    best = Some(v.span());
                } else if let DeValue::Table(t) = v.get_ref() {
                    // An array-of-tables entry: point at its first key, if any.
                    if let Some((name, _)) = t.iter().min_by_key(|(n, _)| n.span().start) {
                        best = Some(name.span());
                    }
                }
            }),
            _ => None,
        };
        match next {
            Some(v) => cur = v.get_ref(),
            None => break,
        }
    }
    best
}

/// The deepest key whose entry contains byte `offset`, e.g. `run[1].goal.x`.
pub(crate) fn key_at(text: &str, offset: usize) -> Option<String> {
    let doc = DeTable::parse(text).ok()?;
    let mut path = String::new();
    let mut table: DeTable<'_> = doc.into_inner();
    loop {
        let mut found: Option<Spanned<DeValue<'_>>> = None;
        for (name, v) in table.iter() {
            let ks = name.span();
            let vs = v.span();
            let (lo, hi) = (ks.start.min(vs.start), ks.end.max(vs.end));
            if lo <= offset && offset < hi.max(lo + 1) {
                if !path.is_empty() {
                    path.push('.');
                }
                path.push_str(name.get_ref());
                found = Some(v.clone());
                break;
            }
        }
        let Some(v) = found else { break };
        match v.into_inner() {
            DeValue::Table(t) => table = t,
            DeValue::Array(a) => {
                let mut next = None;
                for (i, item) in a.into_iter().enumerate() {
                    let s = item.span();
                    let inside = s.start <= offset && offset < s.end;
                    let (item_table, in_table) = match item.into_inner() {
                        DeValue::Table(t) => {
                            let hit = t.iter().any(|(n, v)| {
                                let lo = n.span().start.min(v.span().start);
                                let hi = n.span().end.max(v.span().end);
                                lo <= offset && offset < hi
                            });
                            (Some(t), hit)
                        }
                        _ => (None, false),
                    };
                    if inside || in_table {
                        path.push_str(&format!("[{i}]"));
                        next = item_table;
                        break;
                    }
                }
                match next {
                    Some(t) => table = t,
                    None => break,
                }
            }
            _ => break,
        }
    }
    (!path.is_empty()).then_some(path)
}

/// Turns a deserialization error of the file's own tables into a [`ScenarioError`]:
/// the key is serde's path (for an unknown key it ends with that key), the message is
/// serde's, passed on as the reason.
pub(crate) fn deser_error(path: &str, message: &str, span: Option<Range<usize>>, text: &str) -> ScenarioError {
    let mut key = if path == "." { String::new() } else { path.to_owned() };
    // The first line only: toml's own message may carry a snippet we replace by the key.
    let message = plain_words(&path.replace(".[", "["), message.trim().lines().next().unwrap_or(""));
    let line = if key.is_empty() {
        span.map(|s| {
            if let Some(k) = key_at(text, s.start) {
                key = k;
            }
            line_of(text, s.start)
        })
    } else {
        span_of_key(text, &key).or(span).map(|s| line_of(text, s.start))
    };
    ScenarioError::new(key, message).at_line(line)
}

/// What the file's own tables are, in the words of docs/scenario.md (serde names the
/// Rust types: `struct PoseFile with 4 elements`).
const TABLE_WORDS: [(&str, &str); 7] = [
    ("PoseFile", "a pose table such as { x = 1.0, y = 1.0, theta_deg = 90.0 } (m, m, and theta in rad or theta_deg)"),
    ("SimFile", "a [sim] table"),
    ("RunFile", "a [[run]] table"),
    ("SweepFile", "a [sweep] table"),
    ("GridFile", "a grid table { x_min, x_max, nx, y_min, y_max, ny, theta_deg }"),
    ("RandomFile", "a random table { n, seed, radius, min_radius }"),
    ("ScenarioFile", "a scenario (a TOML table)"),
];

/// Serde's message in the scenario's words: no Rust type names (`struct PoseFile`,
/// `u32`, `f64`), TOML's names for its values (table, array), and `[run]` written for
/// `[[run]]` explained.
pub(crate) fn plain_words(key: &str, message: &str) -> String {
    if key == "run" && message.starts_with("invalid type: map") {
        return "must be an array of tables: write [[run]] (two brackets) for each run, not [run]".to_owned();
    }
    let mut m = message.to_owned();
    // `invalid length 3, expected struct PoseFile with 4 elements`: an array for a table.
    if let Some(rest) = m.strip_prefix("invalid length ")
        && let Some((n, expected)) = rest.split_once(", expected ")
        && expected.starts_with("struct ")
    {
        m = format!("invalid type: an array of {n} values, expected {expected}");
    }
    if let Some(i) = m.find(" with ")
        && m[i..].ends_with(" elements")
        && m[..i].contains("expected struct ")
    {
        m.truncate(i);
    }
    for (name, words) in TABLE_WORDS {
        m = m.replace(&format!("struct {name}"), words);
    }
    // Any other struct the file layout may gain: a table.
    while let Some(i) = m.find("expected struct ") {
        let start = i + "expected ".len();
        let end = m[start + "struct ".len()..]
            .find(|c: char| !c.is_alphanumeric() && c != '_')
            .map_or(m.len(), |e| start + "struct ".len() + e);
        m.replace_range(start..end, "a table");
    }
    let words = [
        ("expected u8", "expected a whole number from 0 to 255"),
        ("expected u16", "expected a whole number from 0 to 65535"),
        ("expected u32", "expected a whole number from 0 to 4294967295"),
        ("expected u64", "expected a whole number from 0 to 18446744073709551615"),
        ("expected usize", "expected a whole number from 0 to 18446744073709551615"),
        ("expected i64", "expected a whole number"),
        ("expected f64", "expected a number"),
        ("expected f32", "expected a number"),
        ("expected a sequence", "expected an array"),
        ("expected a map", "expected a table"),
        ("invalid type: map", "invalid type: table"),
        ("invalid type: sequence", "invalid type: array"),
    ];
    for (from, to) in words {
        if let Some(i) = m.find(from) {
            let end = i + from.len();
            // Whole words only: `expected u32` but not `expected u320`.
            if m[end..].chars().next().is_none_or(|c| !c.is_alphanumeric()) {
                m.replace_range(i..end, to);
            }
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::plain_words;

    #[test]
    fn serde_messages_lose_the_rust_type_names() {
        assert_eq!(
            plain_words("run[0].goal", "invalid length 3, expected struct PoseFile with 4 elements"),
            "invalid type: an array of 3 values, expected a pose table such as { x = 1.0, y = 1.0, theta_deg = 90.0 } (m, m, and theta in rad or theta_deg)"
        );
        assert_eq!(
            plain_words("run", "invalid type: map, expected a sequence"),
            "must be an array of tables: write [[run]] (two brackets) for each run, not [run]"
        );
        assert_eq!(
            plain_words("sim", "invalid type: integer `3`, expected struct SimFile"),
            "invalid type: integer `3`, expected a [sim] table"
        );
        assert_eq!(
            plain_words("x", "invalid type: integer `3`, expected struct NewFile"),
            "invalid type: integer `3`, expected a table"
        );
        assert_eq!(
            plain_words("sweep.grid.nx", "invalid value: integer `-1`, expected u32"),
            "invalid value: integer `-1`, expected a whole number from 0 to 4294967295"
        );
        assert_eq!(
            plain_words("sweep.controllers", "invalid type: integer `3`, expected a sequence"),
            "invalid type: integer `3`, expected an array"
        );
        for m in ["missing field `radius`", "unknown field `foo`, expected one of `x`, `y`"] {
            assert_eq!(plain_words("k", m), m);
        }
    }
}
