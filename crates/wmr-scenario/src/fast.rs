//! The fast path of sweeps (`wmr-cli sweep --fast`): runs stepped in lanes, several at
//! once ([`wmr_core::batch`]), on every core.
//!
//! The sweep's runs are cut into tasks of [`TASK_RUNS`] consecutive runs of one law and
//! variant (they share a plant and a controller); each task feeds its runs through one
//! [`LaneBatch`] of [`LANES`] lanes. On x86-64 with AVX2 the lanes are compiled for AVX2
//! (chosen at run time). The lanes' controllers see the true state: runs with a real
//! sensor (rate, latency, noise, encoders) take the exact path, as do runs whose values
//! `vary` draws one by one (each has its own plant).
//!
//! Not bit-identical to [`SweepSpec::run`]: the lanes' sin and cos are not `libm`'s.
//! `crates/wmr-scenario/tests/fast.rs` bounds the difference on `examples/compare.toml`.

use std::ops::ControlFlow;

use wmr_core::batch::LaneBatch;
use wmr_core::lane::Lanes;
use wmr_core::{AnyLaw, FixedGoal, Outcome, Pose2};

use crate::assemble::Origin;
use crate::error::ScenarioError;
use crate::executor::map_ordered;
use crate::scenario::Scenario;
use crate::setup::Setup;
use crate::sim::SimSpec;
use crate::sweep::{SweepOutcome, SweepSpec};

/// Runs stepped side by side: two AVX2 registers of 4 `f64` per number (measured: 8
/// lanes take 35 % fewer instructions per run-step than 4, 16 no fewer than 8).
pub const LANES: usize = 8;

/// Runs per parallel task: enough to keep the lanes full, few enough to share the
/// cores evenly and to stop soon after a Ctrl-C.
pub const TASK_RUNS: usize = 64;

type Batch = LaneBatch<LANES, AnyLaw<Lanes<LANES>>>;

impl SweepSpec {
    /// [`SweepSpec::run_until`] on the fast path (module docs): the same runs, in the same
    /// order, with outcomes close to the exact ones.
    pub fn run_fast_until(
        &self,
        sim: &SimSpec,
        done: &(dyn Fn() + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<Vec<SweepOutcome>>, ScenarioError> {
        let tasks = self.tasks(0..self.len());
        let parts = map_ordered(tasks.len(), |t| self.run_task(sim, tasks[t], done, stop));
        gather(parts, self.len())
    }

    /// Runs `range` of the sweep (numbered as [`SweepSpec::run_until`] numbers them) on
    /// the fast path, on the calling thread: what one worker of an outside executor runs
    /// (`wmr_py.sweep(..., fast=True, executor=...)`). The outcomes are those
    /// [`SweepSpec::run_fast`] gives for the same runs, bit for bit: a task never spans
    /// two ranges' worth of lanes differently, since lanes do not interact.
    pub fn run_fast_range(
        &self,
        sim: &SimSpec,
        range: std::ops::Range<usize>,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<Vec<SweepOutcome>>, ScenarioError> {
        if range.end > self.len() || range.start > range.end {
            return Err(ScenarioError::new(
                "sweep",
                format!("runs {}..{} asked of a sweep of {} runs", range.start, range.end, self.len()),
            ));
        }
        let n = range.len();
        let parts = self.tasks(range).into_iter().map(|task| self.run_task(sim, task, &|| {}, stop)).collect();
        gather(parts, n)
    }

    /// One task (module docs): its runs through the lanes, or the exact path.
    fn run_task(
        &self,
        sim: &SimSpec,
        (first, end): (usize, usize),
        done: &(dyn Fn() + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<Vec<SweepOutcome>>, ScenarioError> {
        let mut drawn = None;
        let exact = self.variation.has_draws() || !self.setup_of(sim, first, &mut drawn)?.sensor.is_perfect();
        if !exact {
            return self.run_lanes(sim, first..end, done, stop);
        }
        one_by_one(first..end, done, stop, |k, poll| self.run_exact(sim, k, poll))
    }

    /// [`SweepSpec::run`] on the fast path.
    pub fn run_fast(&self, sim: &SimSpec, done: &(dyn Fn() + Sync)) -> Result<Vec<SweepOutcome>, ScenarioError> {
        Ok(self.run_fast_until(sim, done, &|| false)?.unwrap_or_default())
    }

    /// The tasks of `range`: pieces of at most [`TASK_RUNS`] runs that share law and
    /// variant.
    fn tasks(&self, range: std::ops::Range<usize>) -> Vec<(usize, usize)> {
        let group = (self.variation.trials as usize * self.starts.len()).max(1);
        let mut tasks = Vec::new();
        let mut k = range.start;
        while k < range.end {
            let group_end = (k / group + 1) * group;
            let end = (k + TASK_RUNS).min(group_end).min(range.end);
            tasks.push((k, end));
            k = end;
        }
        tasks
    }

    /// Runs `range` (one law and variant) through a lane batch, in order.
    fn run_lanes(
        &self,
        sim: &SimSpec,
        range: std::ops::Range<usize>,
        done: &(dyn Fn() + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<Vec<SweepOutcome>>, ScenarioError> {
        let first = range.start;
        let i = self.index_of(first);
        let path = self.law_path(i.law);
        let origin = Origin { run: "sweep", controller: &path };
        let mut drawn = None;
        let setup = self.setup_of(sim, first, &mut drawn)?;
        let starts: Vec<Pose2<f64>> = range.clone().map(|k| self.starts[self.index_of(k).start]).collect();
        let Some(outcomes) = lanes(setup, sim, &starts, self.goal, origin, done, stop)? else { return Ok(None) };
        Ok(Some(range.zip(outcomes).map(|(k, outcome)| self.outcome_of(k, outcome)).collect()))
    }
}

impl Scenario {
    /// The outcomes of the scenario's runs `range` on the fast path (module docs), in
    /// order: consecutive runs towards the same goal share lanes; runs with a real sensor
    /// take the exact path, with the sensor noise of their index plus `stream_offset`
    /// (as [`Scenario::try_run_as`]). On rayon's pool when `parallel`, else on the calling
    /// thread (an outside executor's worker). `None` when `stop` said so.
    pub fn run_fast(
        &self,
        range: std::ops::Range<usize>,
        stream_offset: u64,
        parallel: bool,
        done: &(dyn Fn() + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<Vec<Outcome<f64>>>, ScenarioError> {
        let runs = self.runs();
        let mut tasks = Vec::new();
        let mut k = range.start;
        while k < range.end {
            let mut end = k + 1;
            while end < range.end && end - k < TASK_RUNS && runs[end].goal == runs[k].goal {
                end += 1;
            }
            tasks.push((k, end));
            k = end;
        }
        let task = |t: usize| -> Result<Option<Vec<Outcome<f64>>>, ScenarioError> {
            let (first, end) = tasks[t];
            if !self.setup().sensor.is_perfect() {
                return one_by_one(first..end, done, stop, |i, poll| {
                    Ok(match self.try_run_as(i, i as u64 + stream_offset, |_| ControlFlow::Continue(()), poll)? {
                        ControlFlow::Continue(r) => ControlFlow::Continue(r.outcome),
                        ControlFlow::Break(()) => ControlFlow::Break(()),
                    })
                });
            }
            let path = format!("run[{first}]");
            let origin = Origin { run: &path, controller: "controller" };
            let starts: Vec<Pose2<f64>> = runs[first..end].iter().map(|r| r.start).collect();
            lanes(self.setup(), self.sim(), &starts, runs[first].goal, origin, done, stop)
        };
        let parts = if parallel { map_ordered(tasks.len(), task) } else { (0..tasks.len()).map(task).collect() };
        gather(parts, range.len())
    }
}

/// Runs from `starts` towards `goal` with `setup` and `sim` through one lane batch: their
/// outcomes in order, or `None` when `stop` said so.
fn lanes(
    setup: &Setup,
    sim: &SimSpec,
    starts: &[Pose2<f64>],
    goal: Pose2<f64>,
    origin: Origin<'_>,
    done: &(dyn Fn() + Sync),
    stop: &(dyn Fn() -> bool + Sync),
) -> Result<Option<Vec<Outcome<f64>>>, ScenarioError> {
    let plant = setup.plant(goal).map_err(|e| origin.key_of(&e))?;
    let goal = FixedGoal::new(goal).map_err(|e| origin.key_of(&e))?;
    let controller = setup.controller.build_lanes(setup.model.params(), &setup.drive).map_err(|e| origin.key_of(&e))?;
    let mut batch = Batch::new(plant, controller, goal, sim.dt(), sim.n_steps(), sim.stop_when_settled())
        .map_err(|e| origin.key_of(&e))?;
    let mut next_start = starts.iter().enumerate();
    let mut outcomes = vec![None; starts.len()];
    let mut stopped = false;
    let next = || {
        if stop() {
            stopped = true;
            return None;
        }
        next_start.next().map(|(i, &p)| (i as u64, p))
    };
    let finished = |tag: u64, outcome| {
        done();
        outcomes[tag as usize] = Some(outcome);
    };
    run_batch(&mut batch, next, finished);
    if stopped {
        return Ok(None);
    }
    // `run_all` ends every run it takes; a missing outcome would be a bug, reported as one.
    let outcomes: Option<Vec<Outcome<f64>>> = outcomes.into_iter().collect();
    outcomes.map(Some).ok_or_else(|| ScenarioError::new("sweep", "internal error: a run of the lanes did not end"))
}

/// Runs `range` one by one on the exact path (`run(k, poll)`, the runs that lanes cannot
/// take), calling `done` after each: their outcomes in order, or `None` when `stop` said so.
fn one_by_one<O>(
    range: std::ops::Range<usize>,
    done: &(dyn Fn() + Sync),
    stop: &(dyn Fn() -> bool + Sync),
    mut run: impl FnMut(usize, &dyn Fn() -> ControlFlow<()>) -> Result<ControlFlow<(), O>, ScenarioError>,
) -> Result<Option<Vec<O>>, ScenarioError> {
    let poll = || if stop() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) };
    let mut out = Vec::with_capacity(range.len());
    for k in range {
        let ControlFlow::Continue(o) = run(k, &poll)? else { return Ok(None) };
        done();
        out.push(o);
    }
    Ok(Some(out))
}

/// The tasks' outcomes in order, or `None` if one was stopped.
fn gather<O>(parts: Vec<Result<Option<Vec<O>>, ScenarioError>>, n: usize) -> Result<Option<Vec<O>>, ScenarioError> {
    let mut all = Vec::with_capacity(n);
    for part in parts {
        match part? {
            Some(outcomes) => all.extend(outcomes),
            None => return Ok(None),
        }
    }
    Ok(Some(all))
}

/// [`LaneBatch::run_all`], compiled for AVX2 when the processor has it. The one
/// `unsafe` of the crate: calling a function compiled for AVX2, after checking for it.
#[allow(unsafe_code)]
fn run_batch(batch: &mut Batch, next: impl FnMut() -> Option<(u64, Pose2<f64>)>, done: impl FnMut(u64, Outcome<f64>)) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2, checked just above.
        unsafe { run_batch_avx2(batch, next, done) };
        return;
    }
    batch.run_all(next, done);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_batch_avx2(
    batch: &mut Batch,
    next: impl FnMut() -> Option<(u64, Pose2<f64>)>,
    done: impl FnMut(u64, Outcome<f64>),
) {
    batch.run_all(next, done);
}
