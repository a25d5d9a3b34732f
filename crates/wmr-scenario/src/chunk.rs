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
        let mut out = Vec::with_capacity(range.len());
        for k in range {
            match self.run_exact(sim, k, &mut poll)? {
                ControlFlow::Continue(o) => out.push(o),
                ControlFlow::Break(()) => return Ok(ControlFlow::Break(())),
            }
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
