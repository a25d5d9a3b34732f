//! The fast path of sweeps (`wmr-cli sweep --fast`): runs stepped in lanes, several at
//! once ([`wmr_core::batch`]), on every core.
//!
//! The sweep's runs are cut into tasks of [`TASK_RUNS`] consecutive runs of one law and
//! variant (they share a plant and a controller); each task feeds its runs through one
//! [`LaneBatch`] of [`LANES`] lanes. On x86-64 the lanes are compiled for AVX-512 and
//! for AVX2, the widest the processor has chosen at run time ([`Kernel`]); without AVX2
//! the lanes do not beat the exact path, and `--fast` runs the exact path. The lanes'
//! controllers see the true state: runs with a real
//! sensor (rate, latency, noise, encoders) take the exact path, as do runs whose values
//! `vary` draws one by one (each has its own plant), runs whose wheels slip (the
//! lanes step the rolling plant only; `wmr-cli sweep --fast` says so), runs with stiction
//! (`robot.static_friction`: its stick/slip switch is per run), runs with pushes or a payload
//! that appears at a time (`world.payload.t`: the plant swaps its robot then), runs of a law
//! that draws its own noise per run (MPPI: one controller per run's seed, and its planning,
//! one lane at a time, is what costs) and the runs of a
//! sweep over references (the lanes follow a fixed goal; [`SweepSpec::fast_refusal`] says so).
//!
//! Not bit-identical to [`SweepSpec::run`]: the lanes' sin and cos are not `libm`'s, and
//! their RK4 carries the heading's cos and sin ([`wmr_core::batch`]).
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
        self.run_fast_on(sim, Kernel::detect()?, done, stop)
    }

    /// [`SweepSpec::run_fast_until`] with the lanes compiled for `kernel` (which the
    /// processor must have: [`Kernel::detect`] says which it has). Every kernel but
    /// [`Kernel::Exact`] gives the same outcomes, bit for bit.
    pub fn run_fast_on(
        &self,
        sim: &SimSpec,
        kernel: Kernel,
        done: &(dyn Fn() + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<Vec<SweepOutcome>>, ScenarioError> {
        let tasks = self.tasks(0..self.len());
        let parts = map_ordered(tasks.len(), |t| self.run_task(sim, kernel, tasks[t], done, stop));
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
        let kernel = Kernel::detect()?;
        let parts = self.tasks(range).into_iter().map(|task| self.run_task(sim, kernel, task, &|| {}, stop)).collect();
        gather(parts, n)
    }

    /// One task (module docs): its runs through the lanes, or the exact path.
    fn run_task(
        &self,
        sim: &SimSpec,
        kernel: Kernel,
        (first, end): (usize, usize),
        done: &(dyn Fn() + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<Vec<SweepOutcome>>, ScenarioError> {
        let mut drawn = None;
        let exact = kernel == Kernel::Exact || self.tracking.is_some() || self.variation.has_draws() || {
            let setup = self.setup_of(sim, first, &mut drawn)?;
            !setup.sensor_is_perfect()
                || setup.slips()
                || setup.robot.has_stiction()
                || !setup.pushes.is_empty()
                || setup.payload.appears_later()
                || setup.samples_noise()
        };
        if !exact {
            return self.run_lanes(sim, kernel, first..end, done, stop);
        }
        one_by_one(first..end, done, stop, |k, poll| self.run_exact(sim, k, poll))
    }

    /// Why `--fast` runs this sweep on the exact path as a whole, if it does: the words
    /// the CLI prints (`None`: the lanes run what they can).
    pub fn fast_refusal(&self) -> Option<&'static str> {
        self.tracking.as_ref().map(|_| {
            "a sweep over a reference runs on the exact path (the lanes follow a fixed goal only): same outcomes as \
             without --fast"
        })
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
        kernel: Kernel,
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
        let Some(outcomes) = lanes(setup, sim, kernel, &starts, self.goal, origin, done, stop)? else {
            return Ok(None);
        };
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
        let kernel = Kernel::detect()?;
        let task = |t: usize| -> Result<Option<Vec<Outcome<f64>>>, ScenarioError> {
            let (first, end) = tasks[t];
            if kernel == Kernel::Exact
                || !self.setup().sensor_is_perfect()
                || self.setup().slips()
                || self.setup().robot.has_stiction()
                || !self.setup().pushes.is_empty()
                || self.setup().payload.appears_later()
                || self.setup().samples_noise()
            {
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
            lanes(self.setup(), self.sim(), kernel, &starts, runs[first].goal, origin, done, stop)
        };
        let parts = if parallel { map_ordered(tasks.len(), task) } else { (0..tasks.len()).map(task).collect() };
        gather(parts, range.len())
    }
}

/// Runs from `starts` towards `goal` with `setup` and `sim` through one lane batch: their
/// outcomes in order, or `None` when `stop` said so.
#[allow(clippy::too_many_arguments)]
fn lanes(
    setup: &Setup,
    sim: &SimSpec,
    kernel: Kernel,
    starts: &[Pose2<f64>],
    goal: Pose2<f64>,
    origin: Origin<'_>,
    done: &(dyn Fn() + Sync),
    stop: &(dyn Fn() -> bool + Sync),
) -> Result<Option<Vec<Outcome<f64>>>, ScenarioError> {
    let plant = setup.plant(goal).map_err(|e| origin.key_of(&e))?;
    let goal = FixedGoal::new(goal).map_err(|e| origin.key_of(&e))?;
    let controller = setup
        .controller
        .build_lanes_in(setup.model.params(), &setup.drive, &setup.obstacles)
        .map_err(|e| origin.key_of(&e))?;
    let mut batch = Batch::new(plant, controller, goal, sim.dt(), sim.n_steps(), sim.stop_when_settled())
        .map_err(|e| origin.key_of(&e))?
        .early_arrival(sim.early_arrival())
        .with_obstacles(setup.obstacles);
    let mut next_start = starts.iter().enumerate();
    let mut outcomes = vec![None; starts.len()];
    let mut stopped = false;
    let mut next = || {
        if stop() {
            stopped = true;
            return None;
        }
        next_start.next().map(|(i, &p)| (i as u64, p))
    };
    let mut finished = |tag: u64, outcome| {
        done();
        outcomes[tag as usize] = Some(sim.judged(outcome));
    };
    run_batch(kernel, &mut batch, &mut next, &mut finished);
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

/// The environment variable that picks a [`Kernel`] by its [`Kernel::name`].
pub const KERNEL_VAR: &str = "WMR_FAST_KERNEL";

/// The vector instructions the fast path runs its lanes with on this processor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Kernel {
    /// AVX-512: one 512-bit register of 8 `f64` per number of the [`LANES`] lanes.
    Avx512,
    /// AVX2: two 256-bit registers of 4 `f64` per number.
    Avx2,
    /// The lanes compiled for the baseline instruction set (SSE2 on x86-64): never
    /// chosen by [`Kernel::detect`] (slower than the exact path where measured), there
    /// for tests, which check that every build gives the same bits.
    Portable,
    /// No vector unit that beats the exact path (no AVX2, or not x86-64): `--fast` runs
    /// the exact path ([`SweepSpec::run`]) and says so.
    Exact,
}

impl Kernel {
    /// Every kernel, in the order [`Kernel::name`]s are listed in messages.
    pub const ALL: [Kernel; 4] = [Kernel::Avx512, Kernel::Avx2, Kernel::Portable, Kernel::Exact];

    /// The kernel `--fast` runs on this processor: the widest it has, AVX-512 or AVX2
    /// (on the AMD EPYC Zen 4 of benches/README.md the AVX-512 build takes 0.76 to 0.85x
    /// the CPU time of the AVX2 one per run-step, by law), else [`Kernel::Exact`];
    /// or the one [`KERNEL_VAR`] (`avx512`, `avx2`, `portable`, `exact`) asks for, when
    /// the processor has it (benches and tests compare them on one machine; one it lacks
    /// gives the default, which `--fast` names). A value that names no kernel is an
    /// error naming the variable, the value and the accepted names, not a silent default.
    pub fn detect() -> Result<Kernel, ScenarioError> {
        Self::choose(std::env::var_os(KERNEL_VAR).as_deref())
    }

    /// [`Kernel::detect`] for the value `asked` of [`KERNEL_VAR`] (`None`: not set).
    pub fn choose(asked: Option<&std::ffi::OsStr>) -> Result<Kernel, ScenarioError> {
        let best = Self::best();
        let Some(asked) = asked else { return Ok(best) };
        let Some(kernel) = Self::ALL.into_iter().find(|k| asked == k.name()) else {
            let names: Vec<&str> = Self::ALL.iter().map(|k| k.name()).collect();
            return Err(ScenarioError::new(
                KERNEL_VAR,
                format!(
                    "unknown kernel {:?}; accepted: {} (or leave it unset for the fastest this processor has)",
                    asked.to_string_lossy(),
                    names.join(", ")
                ),
            ));
        };
        Ok(if kernel.rank() <= best.rank() { kernel } else { best })
    }

    /// The widest kernel this processor has ([`Kernel::Exact`] without AVX2).
    pub fn best() -> Kernel {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                return Kernel::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Kernel::Avx2;
            }
        }
        Kernel::Exact
    }

    fn rank(self) -> u8 {
        match self {
            Kernel::Exact | Kernel::Portable => 0,
            Kernel::Avx2 => 1,
            Kernel::Avx512 => 2,
        }
    }

    /// What `--fast` prints: the instructions and how many `f64` each takes.
    pub fn describe(self) -> &'static str {
        match self {
            Kernel::Avx512 => "AVX-512, 8 f64 lanes per instruction",
            Kernel::Avx2 => "AVX2, 4 f64 lanes per instruction",
            Kernel::Portable => "the lanes without vector extensions (SSE2 on x86-64)",
            Kernel::Exact => {
                "the exact path (no AVX2 on this processor, or WMR_FAST_KERNEL=exact): lanes without vectors do not beat it"
            }
        }
    }

    /// The name `WMR_FAST_KERNEL` takes.
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Avx512 => "avx512",
            Kernel::Avx2 => "avx2",
            Kernel::Portable => "portable",
            Kernel::Exact => "exact",
        }
    }
}

/// [`LaneBatch::run_all`] compiled for the widest vector unit the processor has
/// ([`Kernel::detect`]); without one, the portable build of the same code (callers take
/// the exact path before that). The one `unsafe` of the crate: calling a function
/// compiled for AVX2 or AVX-512, after checking for it. The three builds give the same
/// bits: no FMA contraction, and the same operations in the same order per lane.
///
/// Each build is a function of its own module, so that the compiler's code generation
/// units hold one each and build them in parallel (the three are over a third of this
/// crate's unoptimized code: keep one call site per inlined piece in
/// `LaneBatch::run_all`); `next` and `done` are called once per run, so their dynamic
/// dispatch costs nothing per step.
#[allow(unsafe_code)]
fn run_batch(
    kernel: Kernel,
    batch: &mut Batch,
    next: &mut dyn FnMut() -> Option<(u64, Pose2<f64>)>,
    done: &mut dyn FnMut(u64, Outcome<f64>),
) {
    #[cfg(target_arch = "x86_64")]
    match kernel {
        Kernel::Avx512 if Kernel::best().rank() >= Kernel::Avx512.rank() => {
            // SAFETY: the processor has AVX-512F, checked just above.
            return unsafe { avx512::run_batch(batch, next, done) };
        }
        Kernel::Avx2 if Kernel::best().rank() >= Kernel::Avx2.rank() => {
            // SAFETY: the processor has AVX2, checked just above.
            return unsafe { avx2::run_batch(batch, next, done) };
        }
        _ => {}
    }
    let _ = kernel;
    portable::run_batch(batch, next, done);
}

/// One build of the lanes ([`run_batch`]'s), in a module of its own.
macro_rules! lane_kernel {
    ($(#[$module_attr:meta])* mod $module:ident; $(#[$fn_attr:meta])*) => {
        $(#[$module_attr])*
        mod $module {
            use super::{Batch, Outcome, Pose2};

            $(#[$fn_attr])*
            pub(super) fn run_batch(
                batch: &mut Batch,
                next: &mut dyn FnMut() -> Option<(u64, Pose2<f64>)>,
                done: &mut dyn FnMut(u64, Outcome<f64>),
            ) {
                batch.run_all(next, done);
            }
        }
    };
}

lane_kernel! {
    /// The lanes for the baseline instruction set.
    mod portable;
}

lane_kernel! {
    /// The lanes compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    mod avx2;
    #[target_feature(enable = "avx2")]
}

lane_kernel! {
    /// The lanes compiled for AVX-512.
    #[cfg(target_arch = "x86_64")]
    mod avx512;
    #[target_feature(enable = "avx512f")]
}
