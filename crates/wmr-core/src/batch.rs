//! Many runs of one loop stepped side by side: the fast path of sweeps.
//!
//! A [`LaneBatch`] holds N runs that share the robot, the drive, the world and the plant
//! step (a sweep's runs of one law) and differ in start pose, controller memory, sensor
//! noise stream and reference. The plant, where the time goes, is stepped for all N at
//! once through the same equations as one run ([`crate::lane`], [`Plant`]); each run's
//! controller, sensor, metrics and settle rule are the exact path's, run per lane. A run
//! that ends (t_end reached, settled, diverged) hands back its [`Outcome`] and its lane
//! takes the next run at once, so lanes do not wait for the slowest run.
//!
//! Not bit-identical to [`crate::ClosedLoop`]: the lanes' sin and cos differ from `libm`
//! in the last bits, and a closed loop carries such differences along. Everything else
//! (the clock, the control ticks, the metrics, the three outcomes) is the same code.

use crate::closed_loop::{StepClock, control_every};
use crate::controller::{Controller, Law};
use crate::error::ParamError;
use crate::lane::{Lane, Lanes};
use crate::math::{Pose2, Wheels};
use crate::outcome::{Metrics, Outcome, Termination};
use crate::plant::{DIVERGENCE_BOX_M, Plant};
use crate::reference::Reference;
use crate::sensor::Sensor;
use crate::settle::SettleWatch;
use crate::state::State;

/// One run for a lane: a caller's tag, where it starts, and its own controller (at t = 0),
/// sensor and reference.
#[derive(Clone, Debug)]
pub struct LaneRun<L, S, R> {
    /// The caller's name for the run, handed back with its outcome.
    pub tag: u64,
    /// Start pose of C (m, m, rad), at rest.
    pub start: Pose2<f64>,
    /// The run's controller, at t = 0.
    pub controller: Controller<f64, L>,
    /// The run's sensor.
    pub sensor: S,
    /// The run's reference.
    pub reference: R,
}

/// A run in a lane, with everything [`crate::ClosedLoop::try_run`] keeps per run.
#[derive(Clone, Debug)]
struct Slot<L, S, R> {
    run: LaneRun<L, S, R>,
    step_index: u64,
    steps_to_control: u32,
    metrics: Metrics<f64>,
    watch: Option<SettleWatch<f64>>,
}

/// N runs of one plant stepped side by side (module docs).
#[derive(Clone, Debug)]
pub struct LaneBatch<const N: usize, L, S, R> {
    /// The parameters every lane shares; its own state is not used.
    plant: Plant<f64>,
    clock: StepClock<f64>,
    control_every: u32,
    n_steps: u64,
    stop_when_settled: bool,
    state: State<Lanes<N>>,
    command: Wheels<Lanes<N>>,
    held_torque: Wheels<Lanes<N>>,
    slots: [Option<Slot<L, S, R>>; N],
}

impl<const N: usize, L: Law<f64>, S: Sensor<f64>, R: Reference<f64>> LaneBatch<N, L, S, R> {
    /// Lanes for runs of `n_steps` plant steps of `dt` (s) on `plant`'s robot, drive and
    /// world, with controllers ticking every `control_dt` (s), stopped once settled when
    /// `stop_when_settled` ([`crate::settle`]). Errors as [`crate::ClosedLoop::new`]'s.
    pub fn new(
        plant: Plant<f64>,
        control_dt: f64,
        dt: f64,
        n_steps: u64,
        stop_when_settled: bool,
    ) -> Result<Self, ParamError> {
        let control_every = control_every(&plant, control_dt, dt)?;
        let zero = Lanes::splat(0.0);
        Ok(Self {
            plant,
            clock: StepClock::new(dt),
            control_every,
            n_steps,
            stop_when_settled,
            state: State { x: zero, y: zero, theta: zero, v: zero, omega: zero, phi_r: zero, phi_l: zero },
            command: Wheels::new(zero, zero),
            held_torque: Wheels::new(zero, zero),
            slots: core::array::from_fn(|_| None),
        })
    }

    /// Runs every run `next` gives, N at a time, handing each outcome to `done` with the
    /// run's tag as soon as it ends (not in the order given). Returns when `next` has no
    /// more runs and every lane has finished.
    #[inline(always)]
    pub fn run_all(
        &mut self,
        mut next: impl FnMut() -> Option<LaneRun<L, S, R>>,
        mut done: impl FnMut(u64, Outcome<f64>),
    ) {
        for i in 0..N {
            self.load(i, next());
        }
        let dt = self.clock.dt;
        let bound = Lanes::splat(DIVERGENCE_BOX_M);
        while self.slots.iter().any(Option::is_some) {
            // Before the step: the metrics of the present state; runs at t_end or settled end.
            for i in 0..N {
                let Some(slot) = &mut self.slots[i] else { continue };
                let s = lane(&self.state, i);
                let t = self.clock.time(slot.step_index);
                let goal = slot.run.reference.goal_at(t);
                if slot.step_index == self.n_steps {
                    self.finish(i, Termination::Completed, &mut done);
                    self.load(i, next());
                    continue;
                }
                let speeds = s.wheel_speeds(self.plant.robot().params());
                let torque =
                    self.plant.wheel_torque_lanes(&s, lane_wheels(&self.command, i), lane_wheels(&self.held_torque, i));
                slot.metrics.add_step(t, &s, speeds, torque, goal, dt);
                let holding = slot.run.controller.holding();
                if let Some(w) = &mut slot.watch
                    && w.settled(t, &s, goal, holding)
                {
                    self.finish(i, Termination::Settled, &mut done);
                    self.load(i, next());
                }
            }
            if self.slots.iter().all(Option::is_none) {
                break;
            }
            // One RK4 step of every lane; a lane whose step is not finite or leaves the box
            // keeps its last good state and ends.
            let stepped =
                self.plant.advance(&self.state, self.command, self.held_torque, Lanes::splat(0.0), Lanes::splat(dt));
            let finite =
                stepped.to_array().iter().fold(Lanes::splat(0.0).eq(Lanes::splat(0.0)), |m, c| m & c.is_finite());
            let inside = stepped.x.abs().le(bound) & stepped.y.abs().le(bound);
            let ok = finite & inside;
            self.state = State::from_array(core::array::from_fn(|k| {
                Lanes::select(ok, stepped.to_array()[k], self.state.to_array()[k])
            }));
            for i in 0..N {
                let Some(slot) = &mut self.slots[i] else { continue };
                if !ok.0[i] {
                    let termination = if finite.0[i] { Termination::LeftBox } else { Termination::NonFinite };
                    self.finish(i, termination, &mut done);
                    self.load(i, next());
                    continue;
                }
                slot.step_index += 1;
                slot.steps_to_control -= 1;
                if slot.steps_to_control == 0 {
                    slot.steps_to_control = self.control_every;
                    self.control_tick(i);
                }
            }
        }
    }

    /// Puts `run` (if any) into lane `i` at its start, at rest, and runs its first
    /// control tick at t = 0.
    fn load(&mut self, i: usize, run: Option<LaneRun<L, S, R>>) {
        let start = run.as_ref().map_or(Pose2::default(), |r| r.start);
        set_lane(&mut self.state, i, &State::at_rest(start));
        set_lane_wheels(&mut self.command, i, Wheels::default());
        set_lane_wheels(&mut self.held_torque, i, Wheels::default());
        self.slots[i] = run.map(|run| {
            let fixed = run.reference.fixed();
            let deterministic = run.sensor.deterministic();
            let t_end = self.clock.time(self.n_steps);
            Slot {
                run,
                step_index: 0,
                steps_to_control: self.control_every,
                metrics: Metrics::default(),
                watch: (self.stop_when_settled && deterministic && fixed).then(|| SettleWatch::new(t_end)),
            }
        });
        if self.slots[i].is_some() {
            self.control_tick(i);
        }
    }

    /// Lane `i`'s control tick: its sensor, reference and controller, then its command held.
    fn control_tick(&mut self, i: usize) {
        let Some(slot) = &mut self.slots[i] else { return };
        let s = lane(&self.state, i);
        let t = self.clock.time(slot.step_index);
        let m = slot.run.sensor.measure(t, &s, self.plant.robot().params());
        let goal = slot.run.reference.goal_at(t);
        let command = slot.run.controller.update(t, &m, goal).command;
        set_lane_wheels(&mut self.command, i, command);
        set_lane_wheels(&mut self.held_torque, i, self.plant.held_torque_lanes(command));
    }

    /// Ends lane `i`'s run with `termination` at its present state and frees the lane.
    fn finish(&mut self, i: usize, termination: Termination, done: &mut impl FnMut(u64, Outcome<f64>)) {
        let Some(mut slot) = self.slots[i].take() else { return };
        let s = lane(&self.state, i);
        let t = self.clock.time(slot.step_index);
        let goal = slot.run.reference.goal_at(t);
        slot.metrics.observe(t, &s, s.wheel_speeds(self.plant.robot().params()), goal);
        done(slot.run.tag, slot.metrics.finish(t, &s, goal, termination));
    }
}

/// Lane `i` of a state.
#[inline(always)]
fn lane<const N: usize>(s: &State<Lanes<N>>, i: usize) -> State<f64> {
    State::from_array(s.to_array().map(|c| c.0[i]))
}

/// Sets lane `i` of a state.
#[inline(always)]
fn set_lane<const N: usize>(s: &mut State<Lanes<N>>, i: usize, v: &State<f64>) {
    let mut a = s.to_array();
    for (c, x) in a.iter_mut().zip(v.to_array()) {
        c.0[i] = x;
    }
    *s = State::from_array(a);
}

#[inline(always)]
fn lane_wheels<const N: usize>(w: &Wheels<Lanes<N>>, i: usize) -> Wheels<f64> {
    Wheels::new(w.right.0[i], w.left.0[i])
}

#[inline(always)]
fn set_lane_wheels<const N: usize>(w: &mut Wheels<Lanes<N>>, i: usize, v: Wheels<f64>) {
    w.right.0[i] = v.right;
    w.left.0[i] = v.left;
}
