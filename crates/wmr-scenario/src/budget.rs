//! How much work one scenario may ask for, checked before any work starts, so that a
//! file gets one clear error instead of a process that runs for days: at most
//! [`MAX_TOTAL_STEPS`] plant steps over all runs, [`MAX_SWEEP_RUNS`] runs per sweep
//! over at most [`MAX_SWEEP_REFERENCES`] references
//! (and [`crate::MAX_STEPS`] per run, checked with `[sim]`).

use crate::error::ScenarioError;
use crate::sim::SimSpec;

/// Most plant steps (all runs together, or all (law, start) runs of a sweep) one
/// scenario may ask for: 1e11, about 28 hours of one core at the core's ~1 us per step.
/// Larger studies are split into several files.
pub const MAX_TOTAL_STEPS: u64 = 100_000_000_000;

/// Most (law, start) runs one sweep may hold.
pub const MAX_SWEEP_RUNS: usize = 1_000_000;

/// Most references one sweep may follow (`[sweep] references`), counted before any is
/// built: each takes about 19 KB (a reference's fixed-capacity storage), 19 MB for all.
pub const MAX_SWEEP_REFERENCES: usize = 1_000;

/// Plant steps of `runs` runs of `sim` each.
pub(crate) fn steps(sim: &SimSpec, runs: usize) -> u128 {
    u128::from(sim.n_steps()) * runs as u128
}

/// Total work at most [`MAX_TOTAL_STEPS`]: `runs` runs (of `[[run]]` and `[sweep]`
/// together) of `sim` each, which weigh `weighted_runs` runs of the paper's law (each
/// run counted at its law's cost per step, `LawParams::update_cost`).
pub(crate) fn check(sim: &SimSpec, runs: usize, weighted_runs: f64) -> Result<(), ScenarioError> {
    let total = steps(sim, runs);
    let n_steps = sim.n_steps().max(1);
    let weighted = weighted_runs * n_steps as f64;
    if total > u128::from(MAX_TOTAL_STEPS) || weighted > MAX_TOTAL_STEPS as f64 {
        let mean_cost = if runs == 0 { 1.0 } else { (weighted_runs / runs as f64).max(1.0) };
        let most = (MAX_TOTAL_STEPS as f64 / (n_steps as f64 * mean_cost)).floor() as u64;
        // A law dearer per step than the paper's (MPPI's rollouts) says so.
        let weight = if mean_cost > 1.0 {
            format!(", as much work as {weighted:.3e} steps of the paper's law (each law weighed by its cost per step)")
        } else {
            String::new()
        };
        return Err(ScenarioError::new(
            "sim.t_end",
            format!(
                "{runs} runs x {} steps (t_end / dt) = {total:.3e} plant steps{weight}, more than the limit of {:.0e} \
                 (about a day of CPU): shorten sim.t_end, raise sim.dt, or split the {runs} runs into files \
                 of at most {most}",
                sim.n_steps(),
                MAX_TOTAL_STEPS as f64,
            ),
        ));
    }
    Ok(())
}
