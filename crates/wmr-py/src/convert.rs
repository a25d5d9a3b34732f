//! Python arguments to fixed-size float arrays, checked: right length, every value finite.
//!
//! A NaN or an infinity never enters the models from Python: it is refused here with a
//! `ParameterError` naming the argument and the component (e.g. `state[3]`: `v must be a finite number`).

use numpy::PyReadonlyArray1;
use numpy::PyUntypedArrayMethods;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error::parameter_error;

/// Reads `N` floats from a 1-D float64 array or any sequence of numbers, each finite.
///
/// `names` gives the component names used in error messages.
pub fn finite_array<const N: usize>(obj: &Bound<'_, PyAny>, arg: &str, names: [&str; N]) -> PyResult<[f64; N]> {
    let values: Vec<f64> = if let Ok(a) = obj.extract::<PyReadonlyArray1<'_, f64>>() {
        if a.len() != N {
            return Err(wrong_length(arg, N, a.len(), &names));
        }
        a.as_array().iter().copied().collect()
    } else if let Ok(v) = obj.extract::<Vec<f64>>() {
        v
    } else {
        return Err(parameter_error(
            arg,
            format_args!("expected {N} numbers ({}), got {}", names.join(", "), type_name(obj)),
        ));
    };
    let out: [f64; N] = values.as_slice().try_into().map_err(|_| wrong_length(arg, N, values.len(), &names))?;
    for (i, (v, name)) in out.iter().zip(names).enumerate() {
        if !v.is_finite() {
            return Err(parameter_error(
                &format!("{arg}[{i}]"),
                format_args!("{name} must be a finite number (got {v})"),
            ));
        }
    }
    Ok(out)
}

fn wrong_length(arg: &str, n: usize, got: usize, names: &[&str]) -> PyErr {
    parameter_error(arg, format_args!("expected {n} numbers ({}), got {got}", names.join(", ")))
}

/// The Python type name of `obj`, for messages.
pub fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "an unknown type".to_owned())
}

/// A finite float argument, e.g. `dt`.
pub fn finite_scalar(value: f64, arg: &str) -> PyResult<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(parameter_error(arg, format_args!("must be a finite number (got {value})")))
    }
}

/// A pose as `(x, y, theta_rad)` or a dict `{"x", "y", "theta"}`/`{"x", "y", "theta_deg"}`
/// turned into the scenario file's pose table (a dict), so that the scenario parser checks
/// it (both `theta` and `theta_deg`, unknown keys, missing values) like a file.
pub fn pose_table<'py>(obj: &Bound<'py, PyAny>, arg: &str) -> PyResult<Bound<'py, PyAny>> {
    if obj.is_instance_of::<PyDict>() {
        return Ok(obj.clone());
    }
    let [x, y, theta] = finite_array(obj, arg, ["x", "y", "theta"])?;
    let d = PyDict::new(obj.py());
    d.set_item("x", x)?;
    d.set_item("y", y)?;
    d.set_item("theta", theta)?;
    Ok(d.into_any())
}
