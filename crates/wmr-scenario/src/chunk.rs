//! Parts of a sweep or a batch, run on the calling thread: what one worker of an outside
//! executor (a process pool, Dask) runs, so that the parts put together are the whole run
//! bit for bit and no worker starts a thread pool of its own.
//!
//! A run's result depends on its index only through the sensor's noise stream and the
//! per-run draws of `vary`; both take the index the whole run gives it, so a part gives
//! every run its index in the whole.

use std::ops::{ControlFlow, Range};

use wmr_core::Sample;

use crate::assemble::{self, Origin};
use crate::error::ScenarioError;
use crate::output::RunResult;
use crate::scenario::Scenario;
use crate::setup::{Setup, Tables};
use crate::sim::SimSpec;
use crate::sweep::{SweepOutcome, SweepSpec};

impl SweepSpec {
    /// Runs `k` of the sweep (numbered as [`SweepSpec::run_until`] numbers them: law, then
    /// variant, trial and start), one after the other on the calling thread. `poll` is
    /// asked about every millisecond of work whether to go on: `Ok(Break(()))` when it
    /// said stop. The outcomes are those `run_until` gives for the same indices, bit for
    /// bit (tests/chunk.rs).
    pub fn run_range(
        &self,
        sim: &SimSpec,
        range: Range<usize>,
        mut poll: impl FnMut() -> ControlFlow<()>,
    ) -> Result<ControlFlow<(), Vec<SweepOutcome>>, ScenarioError> {
        if range.end > self.len() {
            return Err(ScenarioError::new(
                "sweep",
                format!("runs {}..{} asked of a sweep of {} runs", range.start, range.end, self.len()),
            ));
        }
        let n_starts = self.starts.len();
        let trials = self.variation.trials as usize;
        let n_variants = self.variants.len();
        let mut out = Vec::with_capacity(range.len());
        for k in range {
            let start_index = k % n_starts;
            let trial = (k / n_starts) % trials;
            let variant = (k / (n_starts * trials)) % n_variants;
            let law = k / (n_starts * trials * n_variants);
            let start = self.starts[start_index];
            let run = k as u64;
            let path = format!("sweep.controllers[{law}]");
            let origin = Origin { run: "sweep", controller: &path };
            let drawn;
            let setup = if self.variation.has_draws() {
                let settings = self.variation.settings(self.variants[variant], run);
                let mut t: Tables = self.tables[law].clone();
                for (key, value) in settings {
                    t.set(key, value)?;
                }
                drawn = Setup::resolve(&t, &path)?;
                drawn.check_step(sim.dt())?;
                &drawn
            } else {
                &self.setups[law * n_variants + variant]
            };
            let mut lp = assemble::closed_loop(setup, run, start, self.goal, sim, origin)?;
            let ControlFlow::Continue(outcome) =
                lp.try_run(sim.n_steps(), u32::MAX, |_| ControlFlow::Continue(()), &mut poll)
            else {
                return Ok(ControlFlow::Break(()));
            };
            out.push(SweepOutcome { law, variant, trial: trial as u32, run, start_index, start, outcome });
        }
        Ok(ControlFlow::Continue(out))
    }
}

impl Scenario {
    /// [`Scenario::try_run`] of run `run_index` with the sensor noise of run `stream`: the
    /// run as it goes when it is run `stream` of a larger batch that was split into parts.
    /// `try_run_as(i, i as u64, ..)` is `try_run(i, ..)`, bit for bit.
    pub fn try_run_as<B>(
        &self,
        run_index: usize,
        stream: u64,
        sink: impl FnMut(&Sample<f64>) -> ControlFlow<B>,
        poll: impl FnMut() -> ControlFlow<B>,
    ) -> Result<ControlFlow<B, RunResult>, ScenarioError> {
        let run = self.runs().get(run_index).ok_or_else(|| {
            ScenarioError::new("run", format!("no run {run_index}: the scenario has {}", self.runs().len()))
        })?;
        let path = format!("run[{run_index}]");
        let origin = Origin { run: &path, controller: "controller" };
        let sim = self.sim();
        let mut lp = assemble::closed_loop(self.setup(), stream, run.start, run.goal, sim, origin)?;
        Ok(match lp.try_run(sim.n_steps(), sim.log_every(), sink, poll) {
            ControlFlow::Continue(outcome) => {
                ControlFlow::Continue(RunResult::new(run_index, run.label.clone(), outcome))
            }
            ControlFlow::Break(b) => ControlFlow::Break(b),
        })
    }
}
