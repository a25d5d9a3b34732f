//! Python arguments to fixed-size float arrays and (N, K) batches of them, checked: right
//! length, every value finite.
//!
//! A NaN or an infinity never enters the models from Python: it is refused here with a
//! `ParameterError` naming the argument and the component (e.g. `state[3]`: `v must be a finite number`).

use numpy::ndarray::{Dimension, Ix1};
use numpy::{Element, PyReadonlyArray, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyByteArray, PyBytes, PyDict, PyList, PyString, PyTuple};

use crate::error::parameter_error;

/// `obj` as a read-only numpy array of `T` and dimension `D`, or `None` if it is not
/// one; an unaligned array is copied to an aligned one first.
///
/// Why: numpy allows unaligned arrays (`np.frombuffer` at an odd offset, a record
/// array's field, and pickle-5 buffers as Dask ships arrays to its workers), but a view
/// of one as `&[f64]` is undefined behaviour, and ndarray's debug check panics on it.
/// Every array argument of wmr-py is read through here.
pub fn readonly_array<'py, T: Element, D: Dimension>(
    obj: &Bound<'py, PyAny>,
) -> PyResult<Option<PyReadonlyArray<'py, T, D>>> {
    let Ok(a) = obj.extract::<PyReadonlyArray<'py, T, D>>() else { return Ok(None) };
    if a.is_aligned() {
        return Ok(Some(a));
    }
    drop(a);
    let copy = obj.py().import("numpy")?.call_method1("require", (obj, obj.py().None(), "A"))?;
    Ok(copy.extract::<PyReadonlyArray<'py, T, D>>().ok())
}

/// Reads `N` floats from a 1-D float64 array or any sequence of real numbers, each finite.
///
/// `names` gives the component names used in error messages. Refused with a
/// `ParameterError` naming `arg`: text (`"123"` and `b"abc"` are not three numbers),
/// complex numbers (their imaginary part would be lost), arrays of anything but real
/// numbers, and sequences holding other things.
pub fn finite_array<const N: usize>(obj: &Bound<'_, PyAny>, arg: &str, names: [&str; N]) -> PyResult<[f64; N]> {
    let expected = || format!("expected {N} real numbers ({})", names.join(", "));
    if obj.is_instance_of::<PyString>()
        || obj.is_instance_of::<PyBytes>()
        || obj.is_instance_of::<PyByteArray>()
        || obj.is_instance_of::<PyDict>()
    {
        return Err(parameter_error(arg, format_args!("{}, got {}", expected(), type_name(obj))));
    }
    if let Some(kind) = dtype_kind(obj)
        && !"iuf".contains(kind)
    {
        return Err(parameter_error(arg, format_args!("{}, got an array of {}", expected(), kind_name(kind))));
    }
    let values: Vec<f64> = if let Some(a) = readonly_array::<f64, Ix1>(obj)? {
        if a.len() != N {
            return Err(wrong_length(arg, N, a.len(), &names));
        }
        a.as_array().iter().copied().collect()
    } else if let Ok(items) = obj.try_iter() {
        let mut v = Vec::with_capacity(N);
        for (i, item) in items.enumerate() {
            let item =
                item.map_err(|_| parameter_error(arg, format_args!("{}, got {}", expected(), type_name(obj))))?;
            if i >= N {
                // Counted to say how many, without reading an endless iterator.
                return Err(wrong_length(arg, N, obj.len().unwrap_or(i + 1), &names));
            }
            v.push(real_number(&item, &format!("{arg}[{i}]"))?);
        }
        v
    } else {
        return Err(parameter_error(arg, format_args!("{}, got {}", expected(), type_name(obj))));
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

/// numpy's dtype kind of an array or numpy scalar (`f`, `i`, `u`, `b`, `c`, `U`, `O`,
/// ...), `None` for other objects.
pub fn dtype_kind(obj: &Bound<'_, PyAny>) -> Option<char> {
    let dtype = obj.getattr("dtype").ok()?;
    dtype.getattr("kind").ok()?.extract::<String>().ok()?.chars().next()
}

fn kind_name(kind: char) -> &'static str {
    match kind {
        'c' => "complex numbers",
        'b' => "booleans",
        'U' | 'S' => "strings",
        'O' => "Python objects",
        'M' | 'm' => "dates or times",
        _ => "non-numbers",
    }
}

/// One real number (int, float, numpy's integer and floating scalars); text, complex
/// numbers, None and the like are a `ParameterError` naming `arg`.
pub fn real_number(obj: &Bound<'_, PyAny>, arg: &str) -> PyResult<f64> {
    if !is_real_number(obj) || obj.is_instance_of::<PyBool>() {
        return Err(parameter_error(arg, format_args!("expected a real number, got {}", type_name(obj))));
    }
    obj.extract::<f64>().map_err(|_| parameter_error(arg, format_args!("is too large (more than 1.8e308)")))
}

fn wrong_length(arg: &str, n: usize, got: usize, names: &[&str]) -> PyErr {
    parameter_error(arg, format_args!("expected {n} numbers ({}), got {got}", names.join(", ")))
}

/// The Python type name of `obj`, for messages.
pub fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "an unknown type".to_owned())
}

/// A finite real-number argument, e.g. `dt`; anything else (text, None, complex) is a
/// `ParameterError` naming `arg`.
pub fn finite_scalar(obj: &Bound<'_, PyAny>, arg: &str) -> PyResult<f64> {
    let value = real_number(obj, arg)?;
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

/// True for real numbers Python knows as such (`numbers.Real`: int, float, numpy's
/// integer and floating scalars), not complex ones.
pub fn is_real_number(obj: &Bound<'_, PyAny>) -> bool {
    let py = obj.py();
    py.import("numbers").and_then(|m| m.getattr("Real")).and_then(|real| obj.is_instance(&real)).unwrap_or(false)
}

/// A (N, K) float64 argument of a batched call, or `None` for a single (1-D) one.
///
/// A float64 ndarray is read in place; a 2-D array of other real numbers or a list of
/// rows is converted with numpy. Every value must be finite: `ParameterError` naming
/// `arg[i, j]` otherwise.
pub fn batch_arg<'py, const K: usize>(
    obj: &Bound<'py, PyAny>,
    arg: &str,
    names: [&str; K],
) -> PyResult<Option<PyReadonlyArray2<'py, f64>>> {
    let arr = match readonly_array::<f64, _>(obj)? {
        Some(a) => a,
        None => {
            let ndim = match obj.getattr("ndim") {
                Ok(n) => n.extract::<usize>().unwrap_or(0),
                // A list of rows (lists or arrays) is a batch; a flat list is one robot.
                Err(_) => {
                    let nested = (obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>())
                        && obj.get_item(0).is_ok_and(|r| {
                            r.is_instance_of::<PyList>()
                                || r.is_instance_of::<PyTuple>()
                                || r.hasattr("ndim").unwrap_or(false)
                        });
                    if nested { 2 } else { 1 }
                }
            };
            if ndim != 2 {
                return Ok(None);
            }
            if let Some(kind) = dtype_kind(obj)
                && !"iuf".contains(kind)
            {
                return Err(parameter_error(
                    arg,
                    format_args!("expected an (N, {K}) array of real numbers, got dtype kind {kind:?}"),
                ));
            }
            let np = obj.py().import("numpy")?;
            let converted = np
                .call_method1("asarray", (obj, "float64"))
                .map_err(|e| parameter_error(arg, format_args!("expected an (N, {K}) array of real numbers: {e}")))?;
            readonly_array::<f64, _>(&converted)?.ok_or_else(|| {
                parameter_error(arg, format_args!("expected an (N, {K}) array, got {}", type_name(obj)))
            })?
        }
    };
    let shape = arr.shape();
    if shape[1] != K || shape[0] == 0 {
        return Err(parameter_error(
            arg,
            format_args!("expected shape (N, {K}) of ({}), N >= 1, got {shape:?}", names.join(", ")),
        ));
    }
    let view = arr.as_array();
    if let Some(((i, j), v)) = view.indexed_iter().find(|(_, v)| !v.is_finite()) {
        return Err(parameter_error(
            &format!("{arg}[{i}, {j}]"),
            format_args!("{} must be a finite number (got {v})", names[j]),
        ));
    }
    Ok(Some(arr))
}

/// Checks that a batched argument has `n` rows.
pub fn same_rows(arr: &PyReadonlyArray2<'_, f64>, arg: &str, n: usize, first: &str) -> PyResult<()> {
    let rows = arr.shape()[0];
    if rows != n {
        return Err(parameter_error(arg, format_args!("has {rows} rows but {first} has {n}: one row per robot")));
    }
    Ok(())
}
