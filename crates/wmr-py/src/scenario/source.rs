//! The scenario argument of every call: a path (str or os.PathLike), TOML text or a
//! dict, turned into TOML and parsed and checked by `wmr-scenario` once; its warnings
//! become Python `UserWarning`s.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use wmr_scenario::{AllowedBy, FileAccess, Scenario, ScenarioError};

use crate::convert::{is_real_number, type_name};
use crate::error::{from_scenario, scenario_error};

/// A str argument as Rust text; a str that is not valid Unicode (a lone surrogate such as
/// "\udcff", which cannot be encoded) is a `ScenarioError` naming `key`.
fn text_arg(obj: &Bound<'_, PyAny>, key: &str) -> PyResult<String> {
    obj.extract::<String>().map_err(|_| {
        let shown = if key.is_empty() { "scenario" } else { key };
        scenario_error(shown, None, format!("{shown}: not valid Unicode text (it holds a lone surrogate)"))
    })
}

/// A Python value as TOML, for the scenario parser. `None` values are left out (the key
/// takes its default); keys must be strings; numbers, strings, bools, lists, tuples and
/// dicts are accepted. `key` is the dotted path for error messages.
pub(crate) fn to_toml(obj: &Bound<'_, PyAny>, key: &str) -> PyResult<Option<toml::Value>> {
    if obj.is_none() {
        return Ok(None);
    }
    let named = if key.is_empty() { "scenario" } else { key };
    let bad = |what: String| scenario_error(named, None, format!("{named}: {what}"));
    let v = if obj.is_instance_of::<PyBool>() {
        toml::Value::Boolean(obj.extract::<bool>()?)
    } else if obj.is_instance_of::<PyInt>() {
        match obj.extract::<i64>() {
            Ok(i) => toml::Value::Integer(i),
            // Beyond i64: as a float when it is one, else too large for any key.
            Err(_) => match obj.extract::<f64>() {
                Ok(f) => toml::Value::Float(f),
                Err(_) => return Err(bad("the integer is too large (more than 1.8e308)".to_owned())),
            },
        }
    } else if obj.is_instance_of::<PyFloat>() {
        toml::Value::Float(obj.extract::<f64>()?)
    } else if obj.is_instance_of::<PyString>() {
        toml::Value::String(text_arg(obj, key)?)
    } else if let Ok(d) = obj.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            if !k.is_instance_of::<PyString>() {
                return Err(bad(format!("keys must be strings, got {}", type_name(&k))));
            }
            let k = text_arg(&k, key)?;
            let sub = if key.is_empty() { k.clone() } else { format!("{key}.{k}") };
            if let Some(v) = to_toml(&v, &sub)? {
                table.insert(k, v);
            }
        }
        toml::Value::Table(table)
    } else if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (i, item) in obj.try_iter()?.enumerate() {
            if let Some(v) = to_toml(&item?, &format!("{key}[{i}]"))? {
                items.push(v);
            }
        }
        toml::Value::Array(items)
    } else if is_real_number(obj) {
        // numpy's real scalars (float64, int32, ...), not complex ones.
        match obj.extract::<f64>() {
            Ok(f) => toml::Value::Float(f),
            Err(_) => return Err(bad(format!("cannot read {} as a number", type_name(obj)))),
        }
    } else {
        return Err(bad(format!("unsupported value of type {}", type_name(obj))));
    };
    Ok(Some(v))
}

/// Where a scenario comes from.
pub(super) enum Source {
    /// A TOML file.
    Path(PathBuf),
    /// TOML text given by the caller (its line numbers mean something to them).
    Text(String),
    /// TOML text made here from a dict (line numbers dropped from errors).
    Dict(String),
}

impl Source {
    /// A path (str or os.PathLike), TOML text, or a dict. A str is a path if such a file
    /// exists or it cannot be TOML text (no '=' and no newline); otherwise TOML text.
    pub(super) fn from_py(obj: &Bound<'_, PyAny>) -> PyResult<Self> {
        if obj.is_instance_of::<PyDict>() {
            let Some(toml::Value::Table(table)) = to_toml(obj, "")? else {
                return Err(scenario_error("scenario", None, "scenario: expected a dict".to_owned()));
            };
            let text = toml::to_string(&table).map_err(|e| {
                scenario_error("scenario", None, format!("scenario: cannot express the dict as a scenario: {e}"))
            })?;
            return Ok(Source::Dict(text));
        }
        if obj.is_instance_of::<PyString>() {
            let s = text_arg(obj, "scenario")?;
            let is_path = std::path::Path::new(&s).is_file() || !(s.contains('=') || s.contains('\n'));
            return Ok(if is_path { Source::Path(s.into()) } else { Source::Text(s) });
        }
        obj.extract::<PathBuf>().map(Source::Path).map_err(|_| {
            scenario_error(
                "scenario",
                None,
                format!("scenario: expected a path, TOML text or a dict, got {}", type_name(obj)),
            )
        })
    }

    /// Parses and checks the scenario (no Python involved: may run without the GIL), with
    /// the warnings about its text (a heading of 90 rad).
    /// The files it names are read from its folder (the current one for text and dicts)
    /// and below, and from the folders `access` allows.
    pub(super) fn parse(&self, access: &FileAccess) -> Result<(Scenario, Vec<ScenarioError>), ScenarioError> {
        let (text, name, dir) = match self {
            Source::Path(p) => {
                let dir = p.parent().unwrap_or(std::path::Path::new("")).to_path_buf();
                (wmr_scenario::read_text(p)?, wmr_scenario::default_name(p), dir)
            }
            Source::Text(t) | Source::Dict(t) => (t.clone(), "scenario".to_owned(), PathBuf::new()),
        };
        // A `[robot] from = "robots/NAME.toml"` is relative to the scenario file's folder
        // (to the current folder for text and dicts).
        let parsed = Scenario::from_toml_str_with(&text, &name, &dir, access);
        let (sc, warnings) = match self {
            Source::Dict(_) => (
                parsed.map_err(|e| e.at_line(None))?,
                // Written by Python code (a dict, a pose tuple): the hint in Python's words.
                wmr_scenario::warnings_for(&text, wmr_scenario::Writer::Python)
                    .into_iter()
                    .map(|w| w.at_line(None))
                    .collect(),
            ),
            _ => (parsed?, wmr_scenario::warnings(&text)),
        };
        Ok((sc, warnings))
    }

    /// The file, for an error about it.
    pub(super) fn path(&self) -> Option<&std::path::Path> {
        match self {
            Source::Path(p) => Some(p),
            _ => None,
        }
    }
}

/// Parses a scenario from a path (str or os.PathLike), TOML text, or a dict; its
/// warnings become Python `UserWarning`s.
pub fn scenario_arg(obj: &Bound<'_, PyAny>) -> PyResult<Scenario> {
    scenario_arg_with(obj, &file_access(None)?)
}

/// The `allow_files_under` keyword: the folders, besides the scenario's own, whose files
/// a scenario may name (issue 39 item 14); a folder that does not exist raises
/// ScenarioError naming `allow_files_under`.
pub fn file_access(dirs: Option<Vec<PathBuf>>) -> PyResult<FileAccess> {
    FileAccess::under(&dirs.unwrap_or_default(), AllowedBy::Python).map_err(|e| from_scenario(&e, None))
}

/// [`scenario_arg`], the files the scenario names read from the folders `access` allows
/// too.
pub fn scenario_arg_with(obj: &Bound<'_, PyAny>, access: &FileAccess) -> PyResult<Scenario> {
    let source = Source::from_py(obj)?;
    let (sc, warnings) = source.parse(access).map_err(|e| from_scenario(&e, source.path()))?;
    let py = obj.py();
    for w in warnings {
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        let message = std::ffi::CString::new(w.key_first().replace('\0', "\\0")).unwrap_or_default();
        PyErr::warn(py, &category, &message, 1)?;
    }
    Ok(sc)
}
