//! `sweep`: a scenario's `[sweep]`, every law from every start, in parallel with the GIL
//! released, returned as the outcome arrays with the laws, the varied keys and the
//! comparison table.

use std::sync::atomic::{AtomicUsize, Ordering};

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wmr_scenario::{Scenario, StartsSource, SweepOutcome, SweepSpec};

use super::outcomes::{add_tracking_arrays, outcome_dict};
use super::source::{file_access, scenario_arg_with};
use crate::error::{scenario_error, to_py};
use crate::interrupt::{Progress, interruptible_with};

/// The parsed sweep of a scenario, or a `ScenarioError` naming `sweep`.
pub(super) fn sweep_of(sc: &Scenario) -> PyResult<&SweepSpec> {
    sc.sweep().ok_or_else(|| scenario_error("sweep", None, "sweep: the scenario has no [sweep] table".to_owned()))
}

/// Runs a scenario's `[sweep]` (every law from every start, rayon, GIL released) and
/// returns one entry per (law, start), in law then start order: `law` (list of names),
/// `start` (int64), `x0`, `y0` (m), `theta0` (rad), the outcome arrays of `run_batch`
/// (`final_x` ... `energy`, `converged`, `diverged`), one array per varied key, and
/// `table`, the comparison `wmr-cli sweep` prints; `_meta`: the laws, the varied keys, the
/// resolved scenario (TOML) and the seeds. A sweep over references adds `reference` (the
/// reference's name per run) and the tracking arrays of `run_batch` (`rms_error` ...
/// `final_error`, m and s), its `converged`/`diverged` are the tracking rule's and its
/// `table` is the CLI's tracking table; `_meta` then names the references and the
/// tolerance. `progress`: as for `run_scenario`, counting runs.
#[pyfunction(name = "_sweep")]
#[pyo3(signature = (scenario, progress=None, fast=false, allow_files_under=None))]
pub fn sweep<'py>(
    py: Python<'py>,
    scenario: &Bound<'py, PyAny>,
    progress: Option<&Bound<'py, PyAny>>,
    fast: bool,
    allow_files_under: Option<Vec<std::path::PathBuf>>,
) -> PyResult<Bound<'py, PyDict>> {
    let sc = scenario_arg_with(scenario, &file_access(allow_files_under)?)?;
    let spec = sweep_of(&sc)?;
    let done = AtomicUsize::new(0);
    if let Some(p) = progress {
        p.call1((-(spec.len() as i64),))?;
    }
    let count = || {
        done.fetch_add(1, Ordering::Relaxed);
    };
    let outcomes = interruptible_with(py, progress.map(|callback| Progress { done: &done, callback }), |stop| {
        if fast {
            spec.run_fast_until(sc.sim(), &count, &|| stop.requested())
        } else {
            spec.run_until(sc.sim(), &count, &|| stop.requested())
        }
    })?
    .map_err(to_py)?;
    // `None` only when stopped, and then `interruptible` returned the signal's error.
    sweep_dict(py, &sc, spec, &outcomes.unwrap_or_default())
}

/// The dict `sweep` returns (see there).
pub(super) fn sweep_dict<'py>(
    py: Python<'py>,
    sc: &Scenario,
    spec: &SweepSpec,
    outcomes: &[SweepOutcome],
) -> PyResult<Bound<'py, PyDict>> {
    let d = outcome_dict(py, outcomes.iter().map(|o| &o.outcome))?;
    let law: Vec<String> = outcomes.iter().map(|o| spec.laws[o.law].0.clone()).collect();
    d.set_item("law", law)?;
    d.set_item("start", PyArray1::from_vec(py, outcomes.iter().map(|o| o.start_index as i64).collect()))?;
    d.set_item("x0", PyArray1::from_vec(py, outcomes.iter().map(|o| o.start.x).collect()))?;
    d.set_item("y0", PyArray1::from_vec(py, outcomes.iter().map(|o| o.start.y).collect()))?;
    d.set_item("theta0", PyArray1::from_vec(py, outcomes.iter().map(|o| o.start.theta).collect()))?;
    // One array per varied key of a robustness sweep (`vary`), the value each run used.
    let values: Vec<Vec<f64>> = outcomes.iter().map(|o| spec.varied_values(o)).collect();
    for (j, k) in spec.variation.keys.iter().enumerate() {
        d.set_item(k.key.as_str(), PyArray1::from_vec(py, values.iter().map(|v| v[j]).collect()))?;
    }
    let meta = PyDict::new(py);
    match &spec.tracking {
        None => d.set_item("table", wmr_scenario::summary_table(&wmr_scenario::summarize(spec, outcomes)))?,
        Some(tr) => {
            let names: Vec<&str> = outcomes.iter().map(|o| tr.references[o.reference].0.as_str()).collect();
            d.set_item("reference", names)?;
            let status: Vec<_> = outcomes.iter().map(SweepOutcome::status).collect();
            add_tracking_arrays(&d, outcomes.iter().map(|o| o.tracking.as_ref()), &status)?;
            let summary = wmr_scenario::tracking_summary(spec, outcomes);
            d.set_item("table", wmr_scenario::tracking_summary_table(&summary, tr.tolerance))?;
            meta.set_item("references", tr.references.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>())?;
            meta.set_item("tracking_tolerance_m", tr.tolerance)?;
        }
    }
    meta.set_item("laws", spec.laws.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>())?;
    let varied = PyDict::new(py);
    for k in &spec.variation.keys {
        let kind = match k.spread {
            wmr_scenario::vary::Spread::Values(_) => "values",
            wmr_scenario::vary::Spread::Uniform(..) => "uniform",
            wmr_scenario::vary::Spread::Normal(..) => "normal",
        };
        varied.set_item(k.key.as_str(), kind)?;
    }
    meta.set_item("varied", varied)?;
    meta.set_item("trials", spec.variation.trials)?;
    meta.set_item("trial", PyArray1::from_vec(py, outcomes.iter().map(|o| i64::from(o.trial)).collect()))?;
    meta.set_item("scenario_toml", sc.to_toml())?;
    meta.set_item("seed", spec.variation.seed)?;
    let starts_seed = match &spec.source {
        StartsSource::Random(r) => Some(r.seed),
        StartsSource::Grid(_) => None,
    };
    meta.set_item("starts_seed", starts_seed)?;
    meta.set_item("goal", (spec.goal.x, spec.goal.y, spec.goal.theta))?;
    d.set_item("_meta", meta)?;
    Ok(d)
}
