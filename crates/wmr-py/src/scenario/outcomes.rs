//! The per-run outcome arrays that `run_batch` and `sweep` return, one numpy array per
//! figure, named once here.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wmr_core::tracking::TrackingOutcome;
use wmr_core::{Outcome, Status};

use super::run_result::TRACKING_FIELDS;

/// A float outcome array: its name and how it is read from an outcome.
type FloatField = (&'static str, fn(&Outcome<f64>) -> f64);

/// The float outcome arrays of `run_batch` and `sweep`, in order: each name written once,
/// next to the value it names.
const FLOAT_FIELDS: [FloatField; 10] = [
    ("final_x", |o| o.final_pose.x),
    ("final_y", |o| o.final_pose.y),
    ("final_theta", |o| o.final_pose.theta),
    ("final_dl", |o| o.final_dl),
    ("final_heading_error", |o| o.final_heading_error),
    ("time_to_1cm", |o| o.time_to_arrival.unwrap_or(f64::NAN)),
    ("t_final", |o| o.t_final),
    ("peak_wheel_speed", |o| o.peak_wheel_speed),
    ("path_length", |o| o.path_length),
    ("energy", |o| o.energy),
];

/// The bool outcome arrays, after the float ones: the run's status is this one.
const BOOL_FIELDS: [(&str, Status); 2] = [("converged", Status::Converged), ("diverged", Status::Diverged)];

/// The entry of each run's status word beside the outcome arrays.
const STATUS: &str = "status";

/// Names of the run_batch and sweep outcome arrays, in order (`wmr_py.OUTCOME_FIELDS`).
pub fn outcome_fields() -> impl Iterator<Item = &'static str> {
    FLOAT_FIELDS.iter().map(|f| f.0).chain(BOOL_FIELDS.iter().map(|f| f.0))
}

/// The per-run outcome arrays of `run_batch` and `sweep` ([`outcome_fields`]), one entry
/// per outcome, in order, and `status`: each run's word ([`Status::name`], what the
/// CLI's CSV says), a list of str.
pub(super) fn outcome_dict<'py, 'a>(
    py: Python<'py>,
    outcomes: impl ExactSizeIterator<Item = &'a Outcome<f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let n = outcomes.len();
    let mut cols: [Vec<f64>; FLOAT_FIELDS.len()] = std::array::from_fn(|_| Vec::with_capacity(n));
    let mut flags: [Vec<bool>; BOOL_FIELDS.len()] = std::array::from_fn(|_| Vec::with_capacity(n));
    let mut words = Vec::with_capacity(n);
    for o in outcomes {
        for (c, (_, get)) in cols.iter_mut().zip(FLOAT_FIELDS) {
            c.push(get(o));
        }
        let status = o.status();
        for (c, (_, s)) in flags.iter_mut().zip(BOOL_FIELDS) {
            c.push(status == s);
        }
        words.push(status.name());
    }
    let d = PyDict::new(py);
    for ((name, _), c) in FLOAT_FIELDS.iter().zip(cols) {
        d.set_item(name, PyArray1::from_vec(py, c))?;
    }
    for ((name, _), c) in BOOL_FIELDS.iter().zip(flags) {
        d.set_item(name, PyArray1::from_vec(py, c))?;
    }
    d.set_item(STATUS, words)?;
    Ok(d)
}

/// Adds to `d` (the arrays of [`outcome_dict`]) the tracking summary of each run, one
/// float64 array per [`TRACKING_FIELDS`] entry but the tolerance (NaN where a run has no
/// value: a time never reached), and sets `converged`, `diverged` and `status` from
/// `status`, the tracking rule's outcome of each run (`cannot_follow` among them, issue 38).
pub(super) fn add_tracking_arrays<'a>(
    d: &Bound<'_, PyDict>,
    tracking: impl ExactSizeIterator<Item = Option<&'a TrackingOutcome<f64>>>,
    status: &[Status],
) -> PyResult<()> {
    let py = d.py();
    let n = tracking.len();
    let fields = &TRACKING_FIELDS[..TRACKING_FIELDS.len() - 1];
    let mut cols: Vec<Vec<f64>> = fields.iter().map(|_| Vec::with_capacity(n)).collect();
    for t in tracking {
        for (c, (_, get)) in cols.iter_mut().zip(fields) {
            c.push(t.and_then(get).unwrap_or(f64::NAN));
        }
    }
    for ((name, _), c) in fields.iter().zip(cols) {
        d.set_item(name, PyArray1::from_vec(py, c))?;
    }
    for (name, s) in BOOL_FIELDS {
        d.set_item(name, PyArray1::from_vec(py, status.iter().map(|x| *x == s).collect()))?;
    }
    d.set_item(STATUS, status.iter().map(|s| s.name()).collect::<Vec<_>>())?;
    Ok(())
}

/// Names of the tracking arrays a run_batch of a tracking scenario adds after
/// [`outcome_fields`] (`wmr_py.TRACKING_FIELDS`).
pub fn tracking_fields() -> impl Iterator<Item = &'static str> {
    TRACKING_FIELDS[..TRACKING_FIELDS.len() - 1].iter().map(|f| f.0)
}
