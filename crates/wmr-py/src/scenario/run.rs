//! `run_scenario`: every `[[run]]` of a scenario in parallel, GIL released, each run's
//! columns collected into a `RunResult`; and `_time_run_rust`, the same work timed
//! inside Rust for the benches.

use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use pyo3::prelude::*;
use wmr_scenario::{RunResult, Scenario, ScenarioError, executor};

use super::run_result::{Columns, PyRunResult};
use super::source::{Source, file_access, scenario_arg_with};
use crate::error::{scenario_error, to_py};
use crate::interrupt::{Progress, Stop, check_memory, interruptible_with};

/// Bytes of the columns of every run of `sc`: n_samples x (its columns, [`Columns::shape`])
/// x 8, summed over the runs.
fn columns_bytes(sc: &Scenario) -> u128 {
    u128::from(sc.sim().n_samples()) * (Columns::shape(sc).len() * 8) as u128 * sc.runs().len() as u128
}

/// Refuses runs whose columns the memory cannot hold, naming `sim.log_dt` and the value
/// that would fit (before anything is allocated).
fn check_columns_memory(sc: &Scenario) -> PyResult<()> {
    let sim = sc.sim();
    check_memory(columns_bytes(sc), "sim.log_dt", |share| {
        let every = (f64::from(sim.log_every()) / share).ceil();
        format!("raise sim.log_dt to at least {:.3e} s (now {} s) or shorten sim.t_end", every * sim.dt(), sim.log_dt())
    })
}

/// Runs run `i` of `sc`, collecting its columns; `None` when `stop` ended it.
/// `done` counts the samples logged (progress).
fn run_one(sc: &Scenario, i: usize, stop: &Stop, done: &AtomicUsize) -> PyResult<Option<(RunResult, Columns)>> {
    let n = usize::try_from(sc.sim().n_samples()).unwrap_or(usize::MAX);
    let mut cols = Columns::try_with_capacity(n, Columns::shape(sc))?;
    let poll = || if stop.requested() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) };
    let flow = sc
        .try_run(
            i,
            |s| {
                cols.push(s);
                done.fetch_add(1, Ordering::Relaxed);
                ControlFlow::Continue(())
            },
            poll,
        )
        .map_err(to_py)?;
    Ok(match flow {
        ControlFlow::Continue(result) => Some((result, cols)),
        ControlFlow::Break(()) => None,
    })
}

/// Runs every `[[run]]` of a scenario and returns one RunResult per run, in run order.
///
/// `scenario`: a path (str or os.PathLike) to a TOML file, TOML text, or a dict with the
/// same keys (docs/scenario.md; None values take the default). Runs go in parallel with the
/// GIL released. Raises ScenarioError (a ValueError) naming the bad key. `progress`: None
/// or a callable given the number of samples logged so far (about every 50 ms) and the
/// total first, as `progress(-total)`. `allow_files_under`: folders whose files the
/// scenario may name besides its own folder's (docs/scenario.md, "Files a scenario names").
#[pyfunction]
#[pyo3(signature = (scenario, progress=None, allow_files_under=None))]
pub fn run_scenario(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    progress: Option<&Bound<'_, PyAny>>,
    allow_files_under: Option<Vec<PathBuf>>,
) -> PyResult<Vec<PyRunResult>> {
    let sc = scenario_arg_with(scenario, &file_access(allow_files_under)?)?;
    if sc.runs().is_empty() {
        return Err(scenario_error(
            "run",
            None,
            "run: the scenario has no [[run]] (it is a [sweep] file: run it with wmr_py.sweep)".to_owned(),
        ));
    }
    check_columns_memory(&sc)?;
    let done = AtomicUsize::new(0);
    if let Some(p) = progress {
        let total = sc.sim().n_samples() as i64 * sc.runs().len() as i64;
        p.call1((-total,))?;
    }
    let runs: PyResult<Vec<_>> =
        interruptible_with(py, progress.map(|callback| Progress { done: &done, callback }), |stop| {
            executor::map_ordered(sc.runs().len(), |i| run_one(&sc, i, stop, &done)).into_iter().collect()
        })?;
    // A run is `None` only when stopped, and then `interruptible` returned the signal's error.
    let runs: Vec<(RunResult, Columns)> = runs?.into_iter().flatten().collect();
    Ok(runs.into_iter().map(|(r, cols)| PyRunResult::new(py, r, cols)).collect())
}

/// Times run 0 of a scenario inside Rust, GIL released, `n` times; returns the best
/// wall time in seconds. The work is what `run_scenario` does in Rust (parse, run,
/// build the columns) without the numpy hand-over: the in-process Rust baseline of
/// bench_fig7.py.
#[pyfunction(name = "_time_run_rust")]
pub fn time_run_rust(py: Python<'_>, scenario: &Bound<'_, PyAny>, n: usize) -> PyResult<f64> {
    let source = Source::from_py(scenario)?;
    let best: PyResult<f64> = py.detach(|| {
        let mut best = f64::INFINITY;
        for _ in 0..n.max(1) {
            let t0 = Instant::now();
            let (sc, _) = source.parse(&wmr_scenario::FileAccess::default()).map_err(to_py)?;
            let (_r, cols) = run_one(&sc, 0, &Stop::new(), &AtomicUsize::new(0))?
                .ok_or_else(|| to_py(ScenarioError::new("", "stopped")))?;
            std::hint::black_box(&cols.cols);
            best = best.min(t0.elapsed().as_secs_f64());
        }
        Ok(best)
    });
    best
}
