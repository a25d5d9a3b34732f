//! A sweep run on the exact path (the closed loop of the core, bit-identical to a
//! scenario's run; `crate::fast` is the fast one): every run in parallel with results in
//! a fixed order, a range of runs on the calling thread, or one run with its samples.

use std::ops::{ControlFlow, Range};

use wmr_core::Outcome;

use super::outcome::SweepOutcome;
use super::spec::{SweepSpec, with_settings};
use crate::assemble::{self, Origin};
use crate::error::ScenarioError;
use crate::executor::map_ordered;
use crate::output::OdometryDrift;
use crate::setup::Setup;
use crate::sim::SimSpec;
use crate::tracking_run;

impl SweepSpec {
    /// Runs every (law, variant, trial, start) in parallel with the scenario's `[sim]`;
    /// `done` is called once per finished run (from worker threads). Results are ordered
    /// by law, then variant, trial and start.
    pub fn run(&self, sim: &SimSpec, done: &(dyn Fn() + Sync)) -> Result<Vec<SweepOutcome>, ScenarioError> {
        Ok(self.run_until(sim, done, &|| false)?.unwrap_or_default())
    }

    /// [`SweepSpec::run`] that stops soon after `stop` answers true (every run asks it
    /// about every millisecond of work): `Ok(None)` then.
    pub fn run_until(
        &self,
        sim: &SimSpec,
        done: &(dyn Fn() + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<Vec<SweepOutcome>>, ScenarioError> {
        let poll = || if stop() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) };
        let runs: Result<Vec<Option<SweepOutcome>>, ScenarioError> = map_ordered(self.len(), |k| {
            let ControlFlow::Continue(outcome) = self.run_exact(sim, k, poll)? else {
                return Ok(None);
            };
            done();
            Ok(Some(outcome))
        })
        .into_iter()
        .collect();
        Ok(runs?.into_iter().collect())
    }

    /// Runs `k` of the sweep (numbered as [`SweepSpec::run_until`] numbers them: law, then
    /// variant, trial and start), one after the other on the calling thread. `poll` is
    /// asked about every millisecond of work whether to go on: `Ok(Break(()))` when it
    /// said stop. The outcomes are those `run_until` gives for the same indices, bit for
    /// bit (tests/chunk.rs): the draws of `vary` and the sensor noise take the run's index
    /// in the whole sweep, so parts put together are the whole. What one worker of an
    /// outside executor (a process pool, Dask) runs, without a thread pool of its own.
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

    /// Run `k` of the sweep through the exact closed loop, asking `poll` about every
    /// millisecond of work whether to go on. A run of a sweep over references follows
    /// its reference and is judged by its tracking error, as a scenario's run is.
    pub(crate) fn run_exact(
        &self,
        sim: &SimSpec,
        k: usize,
        poll: impl FnMut() -> ControlFlow<()>,
    ) -> Result<ControlFlow<(), SweepOutcome>, ScenarioError> {
        let i = self.index_of(k);
        let path = self.law_path(i.law);
        let origin = Origin { run: "sweep", controller: &path };
        let mut drawn = None;
        let setup = self.setup_of(sim, k, &mut drawn)?;
        let start = self.start_pose(i.reference, i.start);
        let (lp, run) = match &self.tracking {
            None => {
                let mut lp = assemble::closed_loop(setup, k as u64, start, self.goal, sim, origin)?;
                let run = lp.try_run(sim.n_steps(), u32::MAX, |_| ControlFlow::Continue(()), poll);
                (lp, run.map_continue(|outcome| (outcome, None)))
            }
            Some(tr) => {
                let reference = tr.references[i.reference].1.built.clone();
                let mut lp = assemble::closed_loop_to(setup, k as u64, start, reference, sim, origin)?;
                let path_following = setup.controller.law.follows().follows_path();
                // Only the outcome counts: the samples go nowhere (every plant step is watched).
                let run =
                    tracking_run::run(&mut lp, sim, tr.tolerance, path_following, |_| ControlFlow::Continue(()), poll);
                (lp, run.map_continue(|(outcome, tracking)| (outcome, Some(tracking))))
            }
        };
        Ok(run.map_continue(|(outcome, tracking)| SweepOutcome {
            tracking,
            odometry_drift: OdometryDrift::of(&lp, &outcome),
            ..self.outcome_of(k, outcome)
        }))
    }

    /// Run `k`'s outcome with where it sits in the sweep.
    pub(crate) fn outcome_of(&self, k: usize, outcome: Outcome<f64>) -> SweepOutcome {
        let i = self.index_of(k);
        SweepOutcome {
            law: i.law,
            variant: i.variant,
            trial: i.trial as u32,
            run: k as u64,
            start_index: i.start,
            start: self.start_pose(i.reference, i.start),
            outcome,
            reference: i.reference,
            tracking: None,
            odometry_drift: None,
        }
    }

    /// One run of law `law` from start `start_index` (the first reference, variant and
    /// trial, as the sweep runs it), handing `sink` every `sim.log_dt` sample: what
    /// `wmr-cli plot` draws to compare the laws from one start.
    pub fn run_one(
        &self,
        sim: &SimSpec,
        law: usize,
        start_index: usize,
        sink: impl FnMut(&wmr_core::Sample<f64>),
    ) -> Result<Outcome<f64>, ScenarioError> {
        let n_starts = self.starts.len();
        let trials = self.variation.trials as usize;
        let n_variants = self.variants.len();
        if law >= self.laws.len() || start_index >= n_starts {
            return Err(ScenarioError::new("sweep", format!("no run of law {law} from start {start_index}")));
        }
        // The run's index as `run_until` numbers it (reference 0, variant 0, trial 0).
        let run = (law * self.n_references() * n_variants * trials * n_starts + start_index) as u64;
        let path = format!("sweep.controllers[{law}]");
        let origin = Origin { run: "sweep", controller: &path };
        let drawn;
        let setup = if self.variation.has_draws() {
            let settings = self.variation.settings(self.variants[0], run);
            drawn = Setup::resolve(&with_settings(&self.tables[law], &settings)?, &path)?;
            drawn.check_step(sim.dt())?;
            &drawn
        } else {
            &self.setups[law * n_variants]
        };
        let start = self.start_pose(0, start_index);
        let mut lp = match &self.tracking {
            None => assemble::closed_loop(setup, run, start, self.goal, sim, origin)?,
            Some(tr) => assemble::closed_loop_to(setup, run, start, tr.references[0].1.built.clone(), sim, origin)?,
        };
        Ok(lp.run(sim.n_steps(), sim.log_every(), sink))
    }
}
