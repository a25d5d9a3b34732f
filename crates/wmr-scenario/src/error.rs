//! The one error of a scenario: which key is wrong, why, and on which line.

use std::fmt;
use std::io;
use std::path::Path;

use wmr_core::ParamError;

/// A rejected scenario: the key (e.g. `robot.mass`, `run[2].start.x`), what is wrong
/// with it, and the 1-based line of the TOML file when it is known.
///
/// Displays as one line, e.g. `line 4: robot.mass: must be > 0 (got -1)`. Text that
/// came from the file (keys, quoted source) is shown with control characters escaped
/// (see [`escape_controls`]), so a file cannot inject terminal escapes or break the line.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct ScenarioError {
    /// The scenario key, dotted, runs indexed: `sim.dt`, `run[0].goal.theta_deg`, `run`.
    /// Empty when the file could not be read or parsed at all.
    pub key: String,
    /// What is wrong, without the key.
    pub message: String,
    /// 1-based line in the TOML text, when known.
    pub line: Option<usize>,
    /// Set when the file could not be read: the operating system's reason (not found,
    /// permission denied, ...), so a caller can map it to its own file errors (Python's
    /// `FileNotFoundError`). `None` for every error about the contents.
    pub io: Option<io::ErrorKind>,
}

impl ScenarioError {
    /// An error about `key`.
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> Self {
        Self { key: key.into(), message: message.into(), line: None, io: None }
    }

    /// A file that could not be read: `message` names the path and the reason.
    pub fn unreadable(kind: io::ErrorKind, message: impl Into<String>) -> Self {
        Self { io: Some(kind), ..Self::new("", message) }
    }

    /// The same error with a line number.
    pub fn at_line(mut self, line: Option<usize>) -> Self {
        self.line = line;
        self
    }

    /// A core parameter error about the value the scenario holds at `key` (the core
    /// names only its own field; the caller knows the path, e.g. `run[2].goal.x`).
    pub fn from_param(e: &ParamError, key: &str) -> Self {
        Self::new(key, format!("{} (got {})", e.reason, num(e.value)))
    }

    /// One line that starts with the key: `robot.mass: must be > 0 (got -1) (line 4)`;
    /// without a key, the message and the line. Control characters are escaped. (The
    /// [`Display`](fmt::Display) form puts the line first, as compilers do, for the CLI.)
    pub fn key_first(&self) -> String {
        let mut s = if self.key.is_empty() {
            escape_controls(&self.message)
        } else {
            format!("{}: {}", escape_controls(&self.key), escape_controls(&self.message))
        };
        if let Some(line) = self.line {
            s.push_str(&format!(" (line {line})"));
        }
        s
    }
}

impl fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(line) = self.line {
            write!(f, "line {line}: ")?;
        }
        let message = escape_controls(&self.message);
        if self.key.is_empty() { f.write_str(&message) } else { write!(f, "{}: {message}", escape_controls(&self.key)) }
    }
}

impl std::error::Error for ScenarioError {}

/// A number for a message: the shortest text that reads back to `v`, in exponent form
/// when it is very large or very small (`1e300`, not 301 digits; `1e-320`).
pub fn num(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-5..1e16).contains(&a) { format!("{v}") } else { format!("{v:e}") }
}

/// A value for a summary with `decimals` fixed decimals and a bounded width: fixed form
/// below 1e6 in magnitude, exponent form above (`1.234e300`, not 301 digits), NaN and the
/// infinities in words (`not a number`, `infinite`, `-infinite`).
pub fn fixed(v: f64, decimals: usize) -> String {
    if v.is_nan() {
        "not a number".to_owned()
    } else if v.is_infinite() {
        if v > 0.0 { "infinite" } else { "-infinite" }.to_owned()
    } else if v.abs() < 1e6 {
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

/// A length in millimetres for a summary, from metres: three decimals, to the micrometre (`3.215 mm`), bounded
/// as [`fixed`] is (`1.000e303 mm`); a non-finite one in words alone (`not a number`).
pub fn millimetres(v_m: f64) -> String {
    if v_m.is_finite() { format!("{} mm", fixed(1000.0 * v_m, 3)) } else { fixed(v_m, 0) }
}

/// True for characters that must not reach a terminal raw: C0 and C1 controls (ESC,
/// NUL, CR, LF, ...), DEL, and the Unicode bidirectional and invisible format
/// characters (U+200B-U+200F, U+202A-U+202E, U+2060-U+2069, U+FEFF) that can make a
/// line read differently from what it holds.
pub fn is_unsafe_char(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{200B}'..='\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2060}'..='\u{2069}' | '\u{FEFF}')
}

/// `text` with every [`is_unsafe_char`] written as an escape: `\n`, `\r`, `\t`, `\0`,
/// `\x1b` (below U+0100), `\u{202e}` (above); every other character as it is. Safe to
/// print on a terminal, and always a single line.
pub fn escape_controls(text: &str) -> String {
    if !text.chars().any(is_unsafe_char) {
        return text.to_owned();
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            '\0' => out.push_str("\\0"),
            c if is_unsafe_char(c) && (c as u32) < 0x100 => out.push_str(&format!("\\x{:02x}", c as u32)),
            c if is_unsafe_char(c) => out.push_str(&format!("\\u{{{:04x}}}", c as u32)),
            c => out.push(c),
        }
    }
    out
}

/// A path as it may be shown in a message: control characters escaped.
pub fn shown(path: &Path) -> String {
    escape_controls(&path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_terminal_controls_and_bidi_overrides() {
        assert_eq!(escape_controls("[[ru\x1b[31mn]]"), "[[ru\\x1b[31mn]]");
        assert_eq!(escape_controls("a\0b\r\nc\u{202e}d\u{7f}"), "a\\0b\\r\\nc\\u{202e}d\\x7f");
        assert_eq!(escape_controls("plain ü ß 日本"), "plain ü ß 日本");
        assert_eq!(num(1e300), "1e300");
        assert_eq!(num(-1.7e308), "-1.7e308");
        assert_eq!(num(0.001), "0.001");
        assert_eq!(num(f64::INFINITY), "inf");
        // Issue 39 item 10: summaries bounded, non-finite values in words.
        assert_eq!(fixed(1.23456, 3), "1.235");
        assert_eq!(fixed(5e300, 6), "5.000e300");
        assert_eq!(fixed(f64::NAN, 6), "not a number");
        assert_eq!(fixed(f64::NEG_INFINITY, 6), "-infinite");
        assert_eq!(millimetres(0.000492), "0.492 mm");
        assert_eq!(millimetres(f64::INFINITY), "infinite");
        let e = ScenarioError::new("run[0].la\x1bbel", "bad\nvalue").at_line(Some(3));
        assert_eq!(e.to_string(), "line 3: run[0].la\\x1bbel: bad\\nvalue");
        assert_eq!(e.key_first(), "run[0].la\\x1bbel: bad\\nvalue (line 3)");
    }
}
