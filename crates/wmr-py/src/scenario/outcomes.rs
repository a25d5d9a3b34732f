//! The per-run outcome arrays that `run_batch` and `sweep` return, one numpy array per
//! figure, named once here.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wmr_core::outcome_fields::{FieldGroup, OUTCOME_FIELDS, OutcomeField, Read, fields_of};
use wmr_core::tracking::TrackingOutcome;
use wmr_core::{Outcome, Status};

/// Whether a field of the table has an array in `run_batch` and `sweep` (every run's:
/// the final pose and time, the figures towards a goal, the drive's; a tracking
/// scenario's arrays add [`tracking_fields`]).
fn is_array(f: &OutcomeField) -> bool {
    matches!(f.group, FieldGroup::Final | FieldGroup::Goal | FieldGroup::Drive)
}

/// The float outcome arrays of `run_batch` and `sweep`, in table order (NaN where a run
/// has none: a time never reached).
fn float_fields() -> impl Iterator<Item = &'static OutcomeField> {
    OUTCOME_FIELDS.iter().filter(|f| is_array(f))
}

/// The tracking arrays of a tracking scenario's `run_batch` and `sweep`, in table order.
fn tracking_array_fields() -> impl Iterator<Item = &'static OutcomeField> {
    fields_of(FieldGroup::Tracking)
}

/// The bool outcome arrays, after the float ones: the run's status is this one.
const BOOL_FIELDS: [(&str, Status); 3] =
    [("converged", Status::Converged), ("diverged", Status::Diverged), ("collided", Status::Collided)];

/// The entry of each run's status word beside the outcome arrays.
const STATUS: &str = "status";

/// Names of the run_batch and sweep outcome arrays, in order (`wmr_py.OUTCOME_FIELDS`).
pub fn outcome_fields() -> impl Iterator<Item = &'static str> {
    float_fields().map(|f| f.name).chain(BOOL_FIELDS.iter().map(|f| f.0))
}

/// The per-run outcome arrays of `run_batch` and `sweep` ([`outcome_fields`]), one entry
/// per outcome, in order, and `status`: each run's word ([`Status::name`], what the
/// CLI's CSV says), a list of str.
pub(super) fn outcome_dict<'py, 'a>(
    py: Python<'py>,
    outcomes: impl ExactSizeIterator<Item = &'a Outcome<f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let n = outcomes.len();
    let mut cols: Vec<Vec<f64>> = float_fields().map(|_| Vec::with_capacity(n)).collect();
    let mut flags: [Vec<bool>; BOOL_FIELDS.len()] = std::array::from_fn(|_| Vec::with_capacity(n));
    let mut words = Vec::with_capacity(n);
    for o in outcomes {
        for (c, f) in cols.iter_mut().zip(float_fields()) {
            c.push(f.value(o, None).unwrap_or(f64::NAN));
        }
        let status = o.status();
        for (c, (_, s)) in flags.iter_mut().zip(BOOL_FIELDS) {
            c.push(status == s);
        }
        words.push(status.name());
    }
    let d = PyDict::new(py);
    for (f, c) in float_fields().zip(cols) {
        d.set_item(f.name, PyArray1::from_vec(py, c))?;
    }
    for ((name, _), c) in BOOL_FIELDS.iter().zip(flags) {
        d.set_item(name, PyArray1::from_vec(py, c))?;
    }
    d.set_item(STATUS, words)?;
    Ok(d)
}

/// Adds to `d` (the arrays of [`outcome_dict`]) the tracking summary of each run, one
/// float64 array per [`tracking_fields`] entry (NaN where a run has no value: a time never
/// reached), and sets `converged`, `diverged` and `status` from `status`, the tracking
/// rule's outcome of each run (`cannot_follow` among them, issue 38).
pub(super) fn add_tracking_arrays<'a>(
    d: &Bound<'_, PyDict>,
    tracking: impl ExactSizeIterator<Item = Option<&'a TrackingOutcome<f64>>>,
    status: &[Status],
) -> PyResult<()> {
    let py = d.py();
    let n = tracking.len();
    let mut cols: Vec<Vec<f64>> = tracking_array_fields().map(|_| Vec::with_capacity(n)).collect();
    for t in tracking {
        for (c, f) in cols.iter_mut().zip(tracking_array_fields()) {
            let v = match (f.read, t) {
                (Read::Tracking(get), Some(t)) => get(t),
                _ => None,
            };
            c.push(v.unwrap_or(f64::NAN));
        }
    }
    for (f, c) in tracking_array_fields().zip(cols) {
        d.set_item(f.name, PyArray1::from_vec(py, c))?;
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
    tracking_array_fields().map(|f| f.name)
}
