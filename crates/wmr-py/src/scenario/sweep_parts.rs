//! A sweep for an outside executor (a process pool, Dask): the plan (the scenario's text
//! and its number of runs), the parts each worker runs on one thread (rows of floats
//! that carry every outcome exactly), and the whole put together from them, the same
//! as `sweep` gives.

use std::ops::ControlFlow;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wmr_core::tracking::TrackingOutcome;
use wmr_core::{Outcome, Pose2, Termination};
use wmr_scenario::{Scenario, SweepOutcome};

use super::source::{file_access, scenario_arg_with};
use super::sweep_run::{sweep_dict, sweep_of};
use crate::convert::{readonly_array, type_name};
use crate::error::{parameter_error, to_py};
use crate::interrupt::interruptible;

/// Checks a sweep scenario for an outside executor: `(text, runs)`, the resolved
/// scenario's text and the number of runs of the sweep. The text is self-contained: a
/// preset's keys are written out and a file reference's points inlined
/// ([`Scenario::to_toml`]), so each worker parses it again in any folder, on any machine,
/// without the scenario's files; it reads back to the same sweep, bit for bit.
#[pyfunction(name = "_sweep_plan")]
#[pyo3(signature = (scenario, allow_files_under=None))]
pub fn sweep_plan(
    scenario: &Bound<'_, PyAny>,
    allow_files_under: Option<Vec<std::path::PathBuf>>,
) -> PyResult<(String, usize)> {
    let sc = scenario_arg_with(scenario, &file_access(allow_files_under)?)?;
    Ok((sc.to_toml(), sweep_of(&sc)?.len()))
}

/// Values per run in the rows of `_sweep_part` (see `outcome_row`).
pub const SWEEP_ROW_LEN: usize = 40;
const ROW_LEN: usize = SWEEP_ROW_LEN;

/// One sweep outcome as floats (exact: indices below 2^53, f64 values as they are):
/// law, variant, trial, run, start index, start (3), diverged, t_final, final pose (3),
/// goal (3), final_dl, final heading error, time to 1 cm (NaN: never), peak wheel speed,
/// path length, energy; then the reference's index, 1 when the run has a tracking outcome
/// (0: none, the 6 values after it NaN), and that outcome: RMS and max error over the last
/// half, max over the last tenth, time to the tolerance (NaN: never), final error,
/// tolerance; then the outcome's heading tolerance (inf: the law is judged on the
/// distance alone); last the tracking outcome's mean error over the first and the last
/// tenth, the reference's peak wheel speed, the wheel speed limit and the time it was
/// first passed (NaN: never; all NaN without a tracking outcome); then the goal
/// tolerances the outcome is judged docked with (m, rad); last the tracking outcome's
/// progress along the path over the last tenth and final distance to the path's end
/// (NaN: none).
fn outcome_row(o: &SweepOutcome) -> [f64; ROW_LEN] {
    let u = &o.outcome;
    let termination = f64::from(u.termination.code());
    let t = o.tracking.as_ref();
    let tr = |get: fn(&TrackingOutcome<f64>) -> f64| t.map_or(f64::NAN, get);
    [
        o.law as f64,
        o.variant as f64,
        f64::from(o.trial),
        o.run as f64,
        o.start_index as f64,
        o.start.x,
        o.start.y,
        o.start.theta,
        termination,
        u.t_final,
        u.final_pose.x,
        u.final_pose.y,
        u.final_pose.theta,
        u.goal.x,
        u.goal.y,
        u.goal.theta,
        u.final_dl,
        u.final_heading_error,
        u.time_to_arrival.unwrap_or(f64::NAN),
        u.peak_wheel_speed,
        u.path_length,
        u.abs_work,
        o.reference as f64,
        f64::from(u8::from(t.is_some())),
        tr(|t| t.rms_last_half),
        tr(|t| t.max_last_half),
        tr(|t| t.max_last_tenth),
        tr(|t| t.time_to_tolerance.unwrap_or(f64::NAN)),
        tr(|t| t.final_error),
        tr(|t| t.tolerance),
        u.heading_tolerance,
        tr(|t| t.mean_first_tenth),
        tr(|t| t.mean_last_tenth),
        tr(|t| t.reference_wheel_speed),
        tr(|t| t.wheel_speed_limit),
        tr(|t| t.over_limit_at.unwrap_or(f64::NAN)),
        u.xy_goal_tolerance,
        u.yaw_goal_tolerance,
        tr(|t| t.progress_last_tenth),
        tr(|t| t.final_distance_to_path_end),
    ]
}

/// The outcome a row of [`outcome_row`] holds, or `None` for a row that is no outcome.
fn row_outcome(r: &[f64]) -> Option<SweepOutcome> {
    let index = |v: f64| (v >= 0.0 && v.fract() == 0.0 && v < 9.0e15).then_some(v as usize);
    let termination = Termination::of_code(r[8] as u8)?;
    Some(SweepOutcome {
        law: index(r[0])?,
        variant: index(r[1])?,
        trial: u32::try_from(index(r[2])?).ok()?,
        run: index(r[3])? as u64,
        start_index: index(r[4])?,
        start: Pose2::new(r[5], r[6], r[7]),
        outcome: Outcome {
            termination,
            t_final: r[9],
            final_pose: Pose2::new(r[10], r[11], r[12]),
            goal: Pose2::new(r[13], r[14], r[15]),
            final_dl: r[16],
            final_heading_error: r[17],
            heading_tolerance: r[30],
            time_to_arrival: (!r[18].is_nan()).then_some(r[18]),
            peak_wheel_speed: r[19],
            xy_goal_tolerance: r[36],
            yaw_goal_tolerance: r[37],
            path_length: r[20],
            abs_work: r[21],
        },
        reference: index(r[22])?,
        tracking: match r[23] {
            0.0 => None,
            1.0 => Some(TrackingOutcome {
                rms_last_half: r[24],
                max_last_half: r[25],
                max_last_tenth: r[26],
                time_to_tolerance: (!r[27].is_nan()).then_some(r[27]),
                final_error: r[28],
                tolerance: r[29],
                mean_first_tenth: r[31],
                mean_last_tenth: r[32],
                reference_wheel_speed: r[33],
                wheel_speed_limit: r[34],
                over_limit_at: (!r[35].is_nan()).then_some(r[35]),
                progress_last_tenth: r[38],
                final_distance_to_path_end: r[39],
            }),
            _ => return None,
        },
        // The rows of an outside executor's parts carry the outcome only (not the drift).
        odometry_drift: None,
    })
}

/// Parses the text `_sweep_plan` gave (no warnings: the caller had them).
fn parse_text(text: &str) -> PyResult<Scenario> {
    Scenario::from_toml_str(text, "scenario").map_err(to_py)
}

/// Runs `first..last` of the sweep of `text` (from `_sweep_plan`) on one thread, GIL
/// released: the work of one outside executor's task. Returns an (n, 30) float64 array,
/// one row per run, which `_sweep_gather` puts together.
#[pyfunction(name = "_sweep_part")]
#[pyo3(signature = (text, first, last, fast=false))]
pub fn sweep_part<'py>(
    py: Python<'py>,
    text: &str,
    first: usize,
    last: usize,
    fast: bool,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let sc = parse_text(text)?;
    let spec = sweep_of(&sc)?;
    if first > last {
        return Err(parameter_error("first", format_args!("must be <= last ({first} > {last})")));
    }
    let flow = interruptible(py, |stop| {
        if fast {
            return spec
                .run_fast_range(sc.sim(), first..last, &|| stop.requested())
                .map(|o| o.map_or(ControlFlow::Break(()), ControlFlow::Continue));
        }
        spec.run_range(sc.sim(), first..last, || {
            if stop.requested() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
        })
    })?
    .map_err(to_py)?;
    // Stopped only when `interruptible` returned the signal's error.
    let outcomes = match flow {
        ControlFlow::Continue(o) => o,
        ControlFlow::Break(()) => Vec::new(),
    };
    let mut rows = Array2::<f64>::zeros((outcomes.len(), ROW_LEN));
    for (mut row, o) in rows.rows_mut().into_iter().zip(&outcomes) {
        row.iter_mut().zip(outcome_row(o)).for_each(|(a, v)| *a = v);
    }
    Ok(rows.into_pyarray(py))
}

/// The result of `sweep` from the rows of every part (`_sweep_part`), in run order.
#[pyfunction(name = "_sweep_gather")]
pub fn sweep_gather<'py>(py: Python<'py>, text: &str, rows: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    let rows: PyReadonlyArray2<'py, f64> = readonly_array(rows)?.ok_or_else(|| {
        parameter_error("rows", format_args!("expected a 2-D float64 array, got {}", type_name(rows)))
    })?;
    let sc = parse_text(text)?;
    let spec = sweep_of(&sc)?;
    let rows = rows.as_array();
    if rows.ncols() != ROW_LEN || rows.nrows() != spec.len() {
        return Err(parameter_error(
            "rows",
            format_args!("expected ({}, {ROW_LEN}) rows, got {:?}", spec.len(), rows.shape()),
        ));
    }
    let mut outcomes = Vec::with_capacity(rows.nrows());
    for (k, r) in rows.rows().into_iter().enumerate() {
        let r = r.to_vec();
        let o = row_outcome(&r).filter(|o| {
            o.run == k as u64
                && o.law < spec.laws.len()
                && o.variant < spec.variants.len()
                && o.reference < spec.n_references()
                && o.tracking.is_some() == spec.tracking.is_some()
        });
        outcomes.push(
            o.ok_or_else(|| parameter_error(&format!("rows[{k}]"), format_args!("is not the outcome of run {k}")))?,
        );
    }
    let d = sweep_dict(py, &sc, spec, &outcomes)?;
    // The resolved scenario is the text `_sweep_plan` made (with the comments saying
    // where each robot value came from), not that text parsed and written again.
    if let Some(meta) = d.get_item("_meta")? {
        meta.set_item("scenario_toml", text)?;
    }
    Ok(d)
}
