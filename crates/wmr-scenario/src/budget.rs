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
/// together) of `sim` each.
pub(crate) fn check(sim: &SimSpec, runs: usize) -> Result<(), ScenarioError> {
    let total = steps(sim, runs);
    if total > u128::from(MAX_TOTAL_STEPS) {
        let most = MAX_TOTAL_STEPS / sim.n_steps().max(1);
        return Err(ScenarioError::new(
            "sim.t_end",
            format!(
                "{runs} runs x {} steps (t_end / dt) = {total:.3e} plant steps, more than the limit of {:.0e} \
                 (about a day of CPU): shorten sim.t_end, raise sim.dt, or split the {runs} runs into files \
                 of at most {most}",
                sim.n_steps(),
                MAX_TOTAL_STEPS as f64,
            ),
        ));
    }
    Ok(())
}
