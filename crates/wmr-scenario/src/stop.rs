//! Runs that can be stopped part-way: by their output (a write failed, the disk is
//! full) or from outside (Ctrl-C in Python), within about a millisecond of work
//! ([`wmr_core::closed_loop::POLL_EVERY_STEPS`] plant steps), instead of at the end.

use std::ops::ControlFlow;

use wmr_core::Sample;

use crate::error::ScenarioError;
use crate::output::RunResult;
use crate::scenario::Scenario;

impl Scenario {
    /// [`Scenario::run`] that may be stopped: `sink` gets the same samples and may
    /// answer [`ControlFlow::Break`]; `poll` is asked about every millisecond of work
    /// whether to go on. `Ok(Break(b))`: stopped with `b`, no result. Run to the end, the
    /// samples and the result are those of [`Scenario::run`], bit for bit.
    pub fn try_run<B>(
        &self,
        run_index: usize,
        sink: impl FnMut(&Sample<f64>) -> ControlFlow<B>,
        poll: impl FnMut() -> ControlFlow<B>,
    ) -> Result<ControlFlow<B, RunResult>, ScenarioError> {
        let mut lp = self.closed_loop(run_index)?;
        let sim = self.sim();
        Ok(match lp.try_run(sim.n_steps(), sim.log_every(), sink, poll) {
            ControlFlow::Continue(outcome) => {
                let label = self.runs().get(run_index).map(|r| r.label.clone()).unwrap_or_default();
                ControlFlow::Continue(RunResult::new(run_index, label, outcome))
            }
            ControlFlow::Break(b) => ControlFlow::Break(b),
        })
    }
}
