//! The one place where Rust errors become Python exceptions.
//!
//! Two exception types, both `ValueError` subclasses so `except ValueError` catches them:
//!
//! - `ParameterError(ValueError)`: a bad argument or parameter value (a NaN state, a
//!   negative mass, a tuple of the wrong length). `err.key` names the argument or the
//!   scenario key (`"robot.mass"`, `"state[3]"`).
//! - `ScenarioError(ParameterError)`: a bad scenario (file, TOML text or dict): an unknown
//!   key, a wrong type, a missing `run`. `err.key` is the dotted key (`"run[0].start.x"`),
//!   `err.line` the 1-based TOML line when known, else `None`.
//!
//! Every message starts with the key, e.g. `robot.mass: must be > 0 (got -1)`.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

pyo3::create_exception!(
    wmr_py,
    ParameterError,
    PyValueError,
    "A bad argument or parameter value; `key` names it (e.g. `robot.mass`, `state[3]`)."
);
pyo3::create_exception!(
    wmr_py,
    ScenarioError,
    ParameterError,
    "A bad scenario (file, TOML text or dict); `key` is the dotted key, `line` the TOML line or None."
);

/// A `ParameterError` about `key`: the message is `"{key}: {message}"`.
pub fn parameter_error(key: &str, message: impl std::fmt::Display) -> PyErr {
    with_attrs(ParameterError::new_err(format!("{key}: {message}")), key, None)
}

/// A `ScenarioError` about `key` (may be empty for an unreadable file) at `line`.
pub fn scenario_error(key: &str, line: Option<usize>, display: String) -> PyErr {
    with_attrs(ScenarioError::new_err(display), key, line)
}

/// A `wmr_scenario::ScenarioError` as a Python exception: a file that could not be
/// opened as the matching `OSError` (`FileNotFoundError`, `PermissionError`,
/// `IsADirectoryError`, with `errno` and `filename`; `key = "scenario"`), anything else
/// as a `ScenarioError` whose message starts with the key: `robot.mass: must be > 0
/// (got -1) (line 2)`.
pub fn from_scenario(e: &wmr_scenario::ScenarioError, path: Option<&std::path::Path>) -> PyErr {
    use pyo3::exceptions::{PyFileNotFoundError, PyIsADirectoryError, PyPermissionError};
    use std::io::ErrorKind;
    let filename = path.map(|p| p.display().to_string()).unwrap_or_default();
    // As `open()` raises them: `[Errno 2] No such file or directory: 'x.toml'`.
    let os = match e.io {
        Some(ErrorKind::NotFound) => Some(PyFileNotFoundError::new_err((2, "No such file or directory", filename))),
        Some(ErrorKind::PermissionDenied) => Some(PyPermissionError::new_err((13, "Permission denied", filename))),
        Some(ErrorKind::IsADirectory) => Some(PyIsADirectoryError::new_err((21, "Is a directory", filename))),
        _ => None,
    };
    match os {
        Some(err) => with_attrs(err, "scenario", None),
        // Text that is no scenario at all (not TOML, not UTF-8, too large) has no key of
        // its own: the argument is named.
        None if e.key.is_empty() => {
            with_attrs(ScenarioError::new_err(format!("scenario: {}", e.key_first())), "scenario", e.line)
        }
        None => with_attrs(ScenarioError::new_err(e.key_first()), &e.key, e.line),
    }
}

/// Sets `key` and `line` on the exception instance (plain attributes, read by tests
/// and by callers that want to point at the offending key).
fn with_attrs(err: PyErr, key: &str, line: Option<usize>) -> PyErr {
    Python::attach(|py| {
        let value = err.value(py);
        // Setting an attribute on a fresh exception instance cannot fail in practice; if
        // it ever did, the message still names the key, so the error is kept either way.
        let _ = value.setattr("key", key);
        let _ = value.setattr("line", line);
    });
    err
}

/// A `wmr_scenario::ScenarioError` as a Python exception (see [`from_scenario`]), for errors
/// that are about the contents, not a file.
pub fn to_py(e: wmr_scenario::ScenarioError) -> PyErr {
    from_scenario(&e, None)
}

/// A `MemoryError` about the argument `key` that sizes the allocation: the message is
/// `"{key}: {message}"` and `err.key` names it, as for a `ParameterError`.
pub fn memory_error(key: &str, message: impl std::fmt::Display) -> PyErr {
    with_attrs(pyo3::exceptions::PyMemoryError::new_err(format!("{key}: {message}")), key, None)
}
