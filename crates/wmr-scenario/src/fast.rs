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
use wmr_core::{AnyLaw, Outcome, Pose2};

use crate::assemble::Origin;
use crate::error::ScenarioError;
use crate::executor::map_ordered;
use crate::sim::SimSpec;
use crate::sweep::{SweepOutcome, SweepSpec};

/// Runs stepped side by side: 4 `f64` fill one AVX2 register.
pub const LANES: usize = 4;

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
        let tasks = self.tasks();
        let parts = map_ordered(tasks.len(), |t| {
            let (first, end) = tasks[t];
            let mut drawn = None;
            let exact = self.variation.has_draws() || !self.setup_of(sim, first, &mut drawn)?.sensor.is_perfect();
            if exact {
                let poll = || if stop() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) };
                let mut out = Vec::with_capacity(end - first);
                for k in first..end {
                    let ControlFlow::Continue(o) = self.run_exact(sim, k, poll)? else { return Ok(None) };
                    done();
                    out.push(o);
                }
                Ok(Some(out))
            } else {
                self.run_lanes(sim, first..end, done, stop)
            }
        });
        let mut all = Vec::with_capacity(self.len());
        for part in parts {
            match part? {
                Some(outcomes) => all.extend(outcomes),
                None => return Ok(None),
            }
        }
        Ok(Some(all))
    }

    /// [`SweepSpec::run`] on the fast path.
    pub fn run_fast(&self, sim: &SimSpec, done: &(dyn Fn() + Sync)) -> Result<Vec<SweepOutcome>, ScenarioError> {
        Ok(self.run_fast_until(sim, done, &|| false)?.unwrap_or_default())
    }

    /// The tasks: ranges of at most [`TASK_RUNS`] runs that share law and variant.
    fn tasks(&self) -> Vec<(usize, usize)> {
        let group = self.variation.trials as usize * self.starts.len();
        let mut tasks = Vec::new();
        for g in (0..self.len()).step_by(group.max(1)) {
            let end = (g + group).min(self.len());
            tasks.extend((g..end).step_by(TASK_RUNS).map(|k| (k, (k + TASK_RUNS).min(end))));
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
        let plant = setup.plant(self.goal).map_err(|e| origin.key_of(&e))?;
        let controller =
            setup.controller.build_lanes(setup.model.params(), &setup.drive).map_err(|e| origin.key_of(&e))?;
        let mut batch = Batch::new(plant, controller, self.goal, sim.dt(), sim.n_steps(), sim.stop_when_settled())
            .map_err(|e| origin.key_of(&e))?;
        let mut ks = range.clone();
        let mut outcomes = vec![None; range.len()];
        let mut stopped = false;
        let next = || {
            if stop() {
                stopped = true;
                return None;
            }
            ks.next().map(|k| (k as u64, self.starts[self.index_of(k).start]))
        };
        let finished = |tag: u64, outcome| {
            done();
            outcomes[tag as usize - first] = Some(outcome);
        };
        run_batch(&mut batch, next, finished);
        if stopped {
            return Ok(None);
        }
        Ok(Some(
            range
                .zip(outcomes)
                .map(|(k, outcome)| {
                    let i = self.index_of(k);
                    SweepOutcome {
                        law: i.law,
                        variant: i.variant,
                        trial: i.trial as u32,
                        run: k as u64,
                        start_index: i.start,
                        start: self.starts[i.start],
                        outcome: outcome.expect("every run of the batch ended"),
                    }
                })
                .collect(),
        ))
    }
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
