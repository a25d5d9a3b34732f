//! Keys, read through the core's own parameter types: a table given in a file is laid
//! over the serialized defaults, every key checked against the type's fields, and read
//! back with serde. Nothing here spells a key; the types do.

use serde::de::{self, DeserializeOwned, Deserializer, Visitor};
use serde::{Deserialize, Serialize};
use toml::{Table, Value};

use crate::error::ScenarioError;

/// The field names a serde struct declares, in declaration order (what its derived
/// `Deserialize` asks the format for).
pub fn fields_of<'de, T: Deserialize<'de>>() -> &'static [&'static str] {
    fields_read_by(|probe| T::deserialize(probe).map(|_| ()))
}

/// The field names of the first struct that `read` asks a deserializer for (e.g. the
/// variant a tagged enum's `deserialize_variant` picks).
pub fn fields_read_by(read: impl FnOnce(&mut FieldProbe) -> Result<(), Probed>) -> &'static [&'static str] {
    let mut probe = FieldProbe(None);
    let _ = read(&mut probe);
    probe.0.unwrap_or(&[])
}

/// A deserializer that records the fields of the first struct asked for, then stops.
pub struct FieldProbe(Option<&'static [&'static str]>);

/// The probe's "error": it has seen what it needed.
#[derive(Debug)]
pub struct Probed;

impl std::fmt::Display for Probed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("probed")
    }
}

impl std::error::Error for Probed {}

impl de::Error for Probed {
    fn custom<M: std::fmt::Display>(_msg: M) -> Self {
        Probed
    }
}

impl<'de> Deserializer<'de> for &mut FieldProbe {
    type Error = Probed;

    fn deserialize_any<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Probed> {
        Err(Probed)
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        _visitor: V,
    ) -> Result<V::Value, Probed> {
        self.0 = Some(fields);
        Err(Probed)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier ignored_any
    }
}

/// The keys and values of `value` serialized as a table (e.g. a parameter struct's defaults).
pub fn to_table<P: Serialize>(value: &P) -> Table {
    // Parameter structs are flat tables of numbers, strings and bools, which TOML always holds.
    Table::try_from(value).unwrap_or_default()
}

/// `path.key`, or `key` at the top.
pub fn join(path: &str, key: &str) -> String {
    if path.is_empty() { key.to_owned() } else { format!("{path}.{key}") }
}

/// The error for a key that `accepted` does not list: `unknown key; did you mean mass?`
/// when one accepted key is a near miss (see [`did_you_mean`]), the list of them otherwise.
pub fn unknown_key<'a>(path: &str, key: &str, accepted: impl IntoIterator<Item = &'a str>) -> ScenarioError {
    let list: Vec<&str> = accepted.into_iter().collect();
    let message = match did_you_mean(key, &list) {
        Some(near) => format!("unknown key; did you mean {near}? (the keys here are {})", list.join(", ")),
        None => format!("unknown key; the keys here are {}", list.join(", ")),
    };
    ScenarioError::new(join(path, key), message)
}

/// The one key of `accepted` that `key` is a near miss of: within edit distance 1 for
/// keys of up to 4 characters, 2 up to 8, 3 beyond (a typo, a dropped or swapped letter);
/// `None` when none is that near, or when two are equally near.
pub fn did_you_mean<'a>(key: &str, accepted: &[&'a str]) -> Option<&'a str> {
    let limit = match key.chars().count() {
        0..=4 => 1,
        5..=8 => 2,
        _ => 3,
    };
    let mut best: Option<(usize, &str)> = None;
    let mut tie = false;
    for &a in accepted {
        let d = edit_distance(key, a);
        match best {
            Some((b, _)) if d == b => tie = true,
            Some((b, _)) if d > b => {}
            _ => (best, tie) = (Some((d, a)), false),
        }
    }
    best.filter(|&(d, _)| d <= limit && !tie).map(|(_, a)| a)
}

/// Levenshtein distance with adjacent transpositions (optimal string alignment), in chars.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let w = b.len() + 1;
    let mut d: Vec<usize> = (0..(a.len() + 1) * w)
        .map(|k| {
            if k < w {
                k
            } else if k % w == 0 {
                k / w
            } else {
                0
            }
        })
        .collect();
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[(i - 1) * w + j] + 1).min(d[i * w + j - 1] + 1).min(d[(i - 1) * w + j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[(i - 2) * w + j - 2] + 1);
            }
            d[i * w + j] = v;
        }
    }
    d[a.len() * w + b.len()]
}

/// Reads `value` with `read`, naming the key of a type error by its path under `path`.
pub fn read_with<T>(
    path: &str,
    value: Value,
    read: impl for<'a, 'b> Fn(serde_path_to_error::Deserializer<'a, 'b, Value>) -> Result<T, toml::de::Error>,
) -> Result<T, ScenarioError> {
    let mut track = serde_path_to_error::Track::new();
    let out = read(serde_path_to_error::Deserializer::new(value.clone(), &mut track));
    out.map_err(|e| {
        let inner = track.path().to_string();
        let key = if inner == "." { path.to_owned() } else { join(path, &inner) };
        let message = e.message().trim();
        // A number or a flag where a name belongs: serde says "invalid type: unit variant,
        // expected string only", which names neither. Read again with a name no enum has
        // to learn the names it takes, and say what was written.
        let names = || {
            let mut probe = value.clone();
            let slot = inner.split('.').try_fold(&mut probe, |v, k| v.as_table_mut()?.get_mut(k))?;
            let written = std::mem::replace(slot, Value::String("\u{0}".into()));
            let again = read(serde_path_to_error::Deserializer::new(probe, &mut serde_path_to_error::Track::new()));
            let expected = again.err()?.message().split_once("expected ")?.1.trim().to_owned();
            Some(format!("expected {expected} (a string), got {written}"))
        };
        match message.ends_with("expected string only").then(names).flatten() {
            Some(better) => ScenarioError::new(key, better),
            None => ScenarioError::new(key, message.to_owned()),
        }
    })
}

/// `given` laid over `defaults` (both tables): every given key must be a default key.
pub fn overlay_table(defaults: &Table, given: &Table, path: &str) -> Result<Table, ScenarioError> {
    let mut merged = defaults.clone();
    for (k, v) in given {
        if !defaults.contains_key(k) {
            return Err(unknown_key(path, k, defaults.keys().map(String::as_str)));
        }
        merged.insert(k.clone(), v.clone());
    }
    Ok(merged)
}

/// A parameter struct read from `given` over `default`: missing keys keep the default,
/// unknown keys and wrong types are errors naming `path.key`.
pub fn overlay<P: Serialize + DeserializeOwned>(default: &P, given: &Table, path: &str) -> Result<P, ScenarioError> {
    let merged = overlay_table(&to_table(default), given, path)?;
    read_with(path, Value::Table(merged), |d| P::deserialize(d))
}

/// The `kind` of a tagged table (`default_kind` when absent), checked against `kinds`.
pub fn kind_of<'a>(
    given: &Table,
    path: &str,
    default_kind: &'a str,
    kinds: &[&'a str],
) -> Result<&'a str, ScenarioError> {
    let key = join(path, "kind");
    match given.get("kind") {
        None => Ok(default_kind),
        Some(Value::String(s)) => kinds
            .iter()
            .copied()
            .find(|k| k == s)
            .ok_or_else(|| ScenarioError::new(key, format!("unknown kind \"{s}\", expected one of {kinds:?}"))),
        Some(other) => Err(ScenarioError::new(key, format!("expected a string, got {}", other.type_str()))),
    }
}

/// A float as TOML: the shortest representation that reads back to the same f64.
pub fn toml_f64(v: f64) -> String {
    if v.is_nan() {
        "nan".to_owned()
    } else if v.is_infinite() {
        if v > 0.0 { "inf".to_owned() } else { "-inf".to_owned() }
    } else {
        // Debug always has a '.' or an exponent, so TOML reads it as a float.
        format!("{v:?}")
    }
}

/// A scalar TOML value as text (floats exact, strings quoted).
pub fn toml_scalar(v: &Value) -> String {
    match v {
        Value::Float(f) => toml_f64(*f),
        other => other.to_string(),
    }
}

/// [`toml_scalar`] for a reader: a float of more than 4 significant digits rounded to 4
/// (a default derived from other keys, such as a DC motor's servo gains: 81.52).
pub fn toml_scalar_rounded(v: &Value) -> String {
    match v {
        Value::Float(f) if f.is_finite() && *f != 0.0 => {
            let digits = (3 - f.abs().log10().floor() as i32).max(0) as usize;
            let rounded: f64 = format!("{f:.digits$}").parse().unwrap_or(*f);
            toml_f64(rounded)
        }
        other => toml_scalar(other),
    }
}

/// `key = value` lines for `table`, in the order of `order` (then any other key).
pub fn write_keys(out: &mut String, table: &Table, order: &[&str]) {
    write_keys_noted(out, table, order, |_| None);
}

/// [`write_keys`] with a comment after each line that `note` gives one for
/// (`mass = 1.0  # robots/turtlebot3_burger.toml`).
pub fn write_keys_noted(out: &mut String, table: &Table, order: &[&str], note: impl Fn(&str) -> Option<String>) {
    use std::fmt::Write as _;
    let rest = table.keys().map(String::as_str).filter(|k| !order.contains(k));
    for k in order.iter().copied().chain(rest) {
        if let Some(v) = table.get(k) {
            let line = format!("{k} = {}", toml_scalar(v));
            let _ = match note(k) {
                // At least one space before the note, however long the value.
                Some(n) => writeln!(out, "{line:<31} # {n}"),
                None => writeln!(out, "{line}"),
            };
        }
    }
}
