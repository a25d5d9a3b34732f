//! `run_batch`: one scenario run from many starts (towards one goal or one per start),
//! in parallel or on the calling thread for an outside executor's part, on the exact or
//! the fast path.

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicUsize, Ordering};

use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wmr_core::Pose2;
use wmr_core::plant::DIVERGENCE_BOX_M;
use wmr_scenario::{RunResult, RunSpec, ScenarioError, executor};

use super::outcomes::{add_tracking_arrays, outcome_dict};
use super::source::{file_access, scenario_arg_with};
use crate::alloc::{bytes_of, check_alloc, vec_with_capacity};
use crate::convert::{readonly_array, type_name};
use crate::error::{parameter_error, to_py};
use crate::interrupt::{Progress, interruptible_with};

/// Arrays of the outcome dict, at most (the outcome fields and the tracking ones).
const OUTCOME_ARRAYS: usize = 24;

/// Runs the scenario `base` (a dict or path, validated like `run_scenario`; its runs give
/// the goal if `goals` is None) from every start in `starts` in parallel, GIL released.
///
/// `first`: the index of `starts[0]` in the whole batch when this is a part of it (an
/// outside executor's chunk): run i draws its sensor noise from stream `first + i`, as in
/// the whole. `threads = 1` runs the starts one after the other on one thread (a worker
/// of a process pool or Dask must not start a thread pool per process); 0: rayon's pool.
/// `progress`: as for `run_scenario`, counting runs.
#[pyfunction(name = "_run_batch")]
#[pyo3(signature = (base, starts, goals=None, first=0, threads=0, progress=None, fast=false, allow_files_under=None))]
#[allow(clippy::too_many_arguments)]
pub fn run_batch_native<'py>(
    py: Python<'py>,
    base: &Bound<'py, PyAny>,
    starts: &Bound<'py, PyAny>,
    goals: Option<&Bound<'py, PyAny>>,
    first: usize,
    threads: usize,
    progress: Option<&Bound<'py, PyAny>>,
    fast: bool,
    allow_files_under: Option<Vec<std::path::PathBuf>>,
) -> PyResult<Bound<'py, PyDict>> {
    if threads > 1 {
        return Err(parameter_error("threads", format_args!("0 (rayon's pool) or 1, got {threads}")));
    }
    let sc = scenario_arg_with(base, &file_access(allow_files_under)?)?;
    let poses = |obj: &Bound<'py, PyAny>, arg: &str| -> PyResult<Vec<Pose2<f64>>> {
        let a: PyReadonlyArray2<'py, f64> = readonly_array(obj)?.ok_or_else(|| {
            parameter_error(arg, format_args!("expected a float64 array of shape (N, 3), got {}", type_name(obj)))
        })?;
        let shape = a.shape();
        if shape[1] != 3 {
            return Err(parameter_error(
                arg,
                format_args!("expected shape (N, 3) of (x, y, theta_rad), got {shape:?}"),
            ));
        }
        let arr = a.as_array();
        let names = ["x", "y", "theta"];
        let mut out = vec_with_capacity(shape[0], arg, "the poses")?;
        for (i, row) in arr.rows().into_iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                if !v.is_finite() {
                    return Err(parameter_error(
                        &format!("{arg}[{i}, {j}]"),
                        format_args!("{} must be a finite number (got {v})", names[j]),
                    ));
                }
                if j < 2 && v.abs() > DIVERGENCE_BOX_M {
                    return Err(parameter_error(
                        &format!("{arg}[{i}, {j}]"),
                        format_args!(
                            "{} must be within {DIVERGENCE_BOX_M} m of the origin (got {v:e}): a run that leaves \
                             |x|, |y| <= {DIVERGENCE_BOX_M} m counts as diverged",
                            names[j]
                        ),
                    ));
                }
            }
            out.push(Pose2::new(row[0], row[1], row[2]));
        }
        Ok(out)
    };
    // Every run's start, spec (with its label) and result are held until the arrays are
    // made: refuse, before any of it is allocated, what this process cannot hold.
    let per_run = bytes_of::<Pose2<f64>>(2)
        + bytes_of::<RunSpec>(1)
        + bytes_of::<Option<RunResult>>(1)
        + 32
        + bytes_of::<f64>(OUTCOME_ARRAYS);
    if let Ok(a) = starts.getattr("shape").and_then(|s| s.extract::<Vec<usize>>())
        && let Some(&n) = a.first()
    {
        check_alloc(per_run * n as u128, "starts", || format!("the runs of {n} starts"))?;
    }
    let starts = poses(starts, "starts")?;
    let default_goal = sc.runs().first().map(|r| r.goal).unwrap_or_default();
    let goals = match goals {
        Some(g) => {
            let g = poses(g, "goals")?;
            if g.len() != starts.len() && g.len() != 1 {
                return Err(parameter_error(
                    "goals",
                    format_args!("expected 1 or {} rows (one per start), got {}", starts.len(), g.len()),
                ));
            }
            g
        }
        None => vec![default_goal],
    };
    let mut runs = vec_with_capacity(starts.len(), "starts", "the runs")?;
    runs.extend(starts.iter().enumerate().map(|(i, &start)| RunSpec {
        label: format!("start {i}"),
        start,
        goal: goals[i % goals.len()],
    }));
    let sc = sc.with_runs(runs).map_err(to_py)?;
    let done = AtomicUsize::new(0);
    if let Some(p) = progress {
        p.call1((-(sc.runs().len() as i64),))?;
    }
    // A tracking scenario takes the exact path (the lanes follow a goal at rest), which
    // also gives each run's tracking summary.
    let tracking = sc.tracking().is_some();
    if fast && !tracking {
        let count = || {
            done.fetch_add(1, Ordering::Relaxed);
        };
        let n = sc.runs().len();
        let outcomes = interruptible_with(py, progress.map(|callback| Progress { done: &done, callback }), |stop| {
            sc.run_fast(0..n, first as u64, threads != 1, &count, &|| stop.requested())
        })?
        .map_err(to_py)?;
        // `None` only when stopped, and then `interruptible` returned the signal's error.
        return outcome_dict(py, outcomes.unwrap_or_default().iter());
    }
    let results: Result<Vec<Option<RunResult>>, ScenarioError> =
        interruptible_with(py, progress.map(|callback| Progress { done: &done, callback }), |stop| {
            let poll = || if stop.requested() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) };
            let job = |i: usize| {
                let r = match sc.try_run_as(i, (first + i) as u64, |_| ControlFlow::Continue(()), poll)? {
                    ControlFlow::Continue(r) => Some(r),
                    ControlFlow::Break(()) => None,
                };
                done.fetch_add(1, Ordering::Relaxed);
                Ok(r)
            };
            if threads == 1 {
                (0..sc.runs().len()).map(job).collect()
            } else {
                executor::map_ordered(sc.runs().len(), job).into_iter().collect()
            }
        })?;
    // `None` only when stopped, and then `interruptible` returned the signal's error.
    let results: Vec<RunResult> = results.map_err(to_py)?.into_iter().flatten().collect();
    let d = outcome_dict(py, results.iter().map(|r| &r.outcome))?;
    if tracking {
        // The run's status is the tracking rule's (wmr_scenario::RunResult::status).
        let status: Vec<_> = results.iter().map(RunResult::status).collect();
        add_tracking_arrays(&d, results.iter().map(|r| r.tracking.as_ref()), &status)?;
    }
    Ok(d)
}
