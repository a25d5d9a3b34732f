//! The one error of a scenario: which key is wrong, why, and on which line.

use std::fmt;

use wmr_core::ParamError;

/// A rejected scenario: the key (e.g. `robot.mass`, `run[2].start.x`), what is wrong
/// with it, and the 1-based line of the TOML file when it is known.
///
/// Displays as one line, e.g. `line 4: robot.mass: must be > 0 (got -1)`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScenarioError {
    /// The scenario key, dotted, runs indexed: `sim.dt`, `run[0].goal.theta_deg`, `run`.
    /// Empty when the file could not be read or parsed at all.
    pub key: String,
    /// What is wrong, without the key.
    pub message: String,
    /// 1-based line in the TOML text, when known.
    pub line: Option<usize>,
}

impl ScenarioError {
    /// An error about `key`.
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> Self {
        Self { key: key.into(), message: message.into(), line: None }
    }

    /// The same error with a line number.
    pub fn at_line(mut self, line: Option<usize>) -> Self {
        self.line = line;
        self
    }

    /// A core parameter error about the value the scenario holds at `key` (the core
    /// names only its own field; the caller knows the path, e.g. `run[2].goal.x`).
    pub fn from_param(e: &ParamError, key: &str) -> Self {
        Self::new(key, format!("{} (got {})", e.reason, e.value))
    }
}

impl fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(line) = self.line {
            write!(f, "line {line}: ")?;
        }
        if self.key.is_empty() { f.write_str(&self.message) } else { write!(f, "{}: {}", self.key, self.message) }
    }
}

impl std::error::Error for ScenarioError {}
