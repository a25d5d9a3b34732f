//! Maps between scenario keys (`run[2].start.x`) and places in the TOML text, so every
//! error names its key and its line.

use std::ops::Range;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::ScenarioError;
use crate::file::tagged::{KEY_MARK, unknown_field};

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

/// Turns a deserialization error (with its serde path) into a [`ScenarioError`].
pub(crate) fn deser_error(path: &str, message: &str, span: Option<Range<usize>>, text: Option<&str>) -> ScenarioError {
    let mut key = if path == "." { String::new() } else { path.to_owned() };
    // The first line only: toml's own message may carry a snippet we replace by the key.
    let mut message = message.trim().to_owned();
    // Keys marked by the `kind`-tagged tables: `\x1fkey\x1fmessage`.
    if let Some(rest) = message.strip_prefix(KEY_MARK)
        && let Some((inner, msg)) = rest.split_once(KEY_MARK)
    {
        key = if key.is_empty() { inner.to_owned() } else { format!("{key}.{inner}") };
        message = msg.to_owned();
    } else if let Some(field) = unknown_field(&message) {
        // serde_path_to_error already ends the path with the unknown key itself.
        if !(key == field || key.ends_with(&format!(".{field}"))) {
            key = if key.is_empty() { field.to_owned() } else { format!("{key}.{field}") };
        }
        message = format!("unknown key; {message}");
    }
    let line = match (text, span.clone()) {
        (Some(text), _) if !key.is_empty() => span_of_key(text, &key).or(span).map(|s| line_of(text, s.start)),
        (Some(text), Some(s)) => {
            if key.is_empty()
                && let Some(k) = key_at(text, s.start)
            {
                key = k;
            }
            Some(line_of(text, s.start))
        }
        _ => None,
    };
    ScenarioError::new(key, message).at_line(line)
}
