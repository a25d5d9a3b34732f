//! The per-run outcome arrays that `run_batch` and `sweep` return, one numpy array per
//! figure, named once here.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wmr_core::Status;

/// Names of the run_batch outputs, in order.
const BATCH_FIELDS: [&str; 12] = [
    "final_x",
    "final_y",
    "final_theta",
    "final_dl",
    "final_heading_error",
    "time_to_1cm",
    "t_final",
    "peak_wheel_speed",
    "path_length",
    "energy",
    "converged",
    "diverged",
];

/// The per-run outcome arrays of `run_batch` and `sweep` ([`BATCH_FIELDS`]), one entry
/// per outcome, in order.
pub(super) fn outcome_dict<'py, 'a>(
    py: Python<'py>,
    outcomes: impl ExactSizeIterator<Item = &'a wmr_core::Outcome<f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let n = outcomes.len();
    let mut cols: [Vec<f64>; 10] = std::array::from_fn(|_| Vec::with_capacity(n));
    let mut converged = Vec::with_capacity(n);
    let mut diverged = Vec::with_capacity(n);
    for o in outcomes {
        let vals = [
            o.final_pose.x,
            o.final_pose.y,
            o.final_pose.theta,
            o.final_dl,
            o.final_heading_error,
            o.time_to_arrival.unwrap_or(f64::NAN),
            o.t_final,
            o.peak_wheel_speed,
            o.path_length,
            o.energy,
        ];
        for (c, v) in cols.iter_mut().zip(vals) {
            c.push(v);
        }
        converged.push(o.status() == Status::Converged);
        diverged.push(o.status() == Status::Diverged);
    }
    let d = PyDict::new(py);
    for (name, c) in BATCH_FIELDS.iter().zip(cols) {
        d.set_item(name, PyArray1::from_vec(py, c))?;
    }
    d.set_item(BATCH_FIELDS[10], PyArray1::from_vec(py, converged))?;
    d.set_item(BATCH_FIELDS[11], PyArray1::from_vec(py, diverged))?;
    Ok(d)
}
