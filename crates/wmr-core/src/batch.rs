//! Many runs of one loop stepped side by side: the fast path of sweeps.
//!
//! A [`LaneBatch`] holds N runs that share the robot, the drive, the world, the
//! controller's keys, the plant step and the reference (a sweep's runs of one law) and
//! differ in their start pose. Each lane reads the reference at its own run's time (a
//! fixed goal is read once). The plant and the controller run for all N at once through the
//! same code as one run ([`crate::lane`]): [`Plant`]'s RK4 step and a
//! [`Controller`]`<Lanes<N>, _>`, whose memories are per lane. The controller sees the
//! true state, as with [`crate::PerfectSensor`]. Each run's metrics and settle rule are
//! the exact path's ([`crate::outcome`], [`crate::settle`]), per lane.
//!
//! A run that ends (t_end reached, settled, diverged) hands back its [`Outcome`] and its
//! lane takes the next run at the next control tick, so lanes do not wait for the
//! slowest run.
//!
//! Not bit-identical to [`crate::ClosedLoop`]: the lanes' sin, cos and atan2 differ from
//! `libm` in the last bits, the plant's RK4 carries the heading's cos and sin as states
//! (`Plant::advance_carrying_heading`: no sine per stage), and a closed loop carries
//! such differences along. The clock,
//! the control ticks, the metrics and the three outcomes are the same code.

use crate::arrival::ArrivalWatch;
use crate::clock::StepClock;
use crate::closed_loop::control_every;
use crate::controller::{Controller, Law};
use crate::error::{ParamError, check};
use crate::kinematics::wheel_speeds_lanes;
use crate::lane::{Lane, LaneMask, Lanes, Mask};
use crate::math::{Pose2, Twist2, Wheels};
use crate::obstacle::Obstacles;
use crate::outcome::{Metrics, Outcome, Termination};
use crate::plant::{DIVERGENCE_BOX_M, Plant, all_finite};
use crate::real::Real;
use crate::reference::{FixedGoal, Reference, ReferenceState};
use crate::sensor::Measurement;
use crate::settle::SettleWatch;
use crate::state::State;

/// N runs of one plant and controller stepped side by side (module docs).
#[derive(Clone, Debug)]
pub struct LaneBatch<const N: usize, L, R = FixedGoal<f64>> {
    /// The parameters every lane shares; its own state is not used.
    plant: Plant<f64>,
    controller: Controller<Lanes<N>, L>,
    reference: R,
    /// The reference in every lane when it is fixed (read once).
    fixed: Option<ReferenceState<Lanes<N>>>,
    clock: StepClock<f64>,
    control_every: u32,
    n_steps: u64,
    stop_when_settled: bool,
    /// Plant steps since the batch started: control ticks fall on multiples of
    /// `control_every`, for every lane at once.
    global_step: u64,
    state: State<Lanes<N>>,
    /// (cos, sin) of each lane's heading, carried through the plant's steps
    /// ([`Plant::advance_carrying_heading`]).
    heading: (Lanes<N>, Lanes<N>),
    command: Wheels<Lanes<N>>,
    held_torque: Wheels<Lanes<N>>,
    /// Each lane's metrics and settle rule, as [`crate::ClosedLoop::try_run`] keeps them.
    metrics: Metrics<Lanes<N>>,
    watch: SettleWatch<Lanes<N>>,
    /// Stop a settling run as soon as it has arrived ([`crate::arrival`]).
    early_arrival: bool,
    arrival: ArrivalWatch<Lanes<N>>,
    /// The plant steps each lane's run has taken, as whole `f64`s (0 in a free lane):
    /// vector arithmetic for the clock and the t_end check.
    steps: Lanes<N>,
    /// The lanes that hold a run.
    active: LaneMask<N>,
    /// The caller's tag of each lane's run.
    tags: [u64; N],
    /// What the footprint may not touch ([`crate::obstacle`]); none by default.
    obstacles: Obstacles<f64>,
}

impl<const N: usize, L: Law<Lanes<N>>, R: Reference<f64>> LaneBatch<N, L, R> {
    /// Lanes for runs following `reference` for `n_steps` plant steps of `dt` (s) on
    /// `plant`'s robot, drive and world, under `controller` (at t = 0; built for lanes
    /// with [`crate::ControllerParams::build_lanes`]), stopped once settled when
    /// `stop_when_settled` ([`crate::settle`]). Errors as [`crate::ClosedLoop::new`]'s.
    pub fn new(
        plant: Plant<f64>,
        controller: Controller<Lanes<N>, L>,
        reference: R,
        dt: f64,
        n_steps: u64,
        stop_when_settled: bool,
    ) -> Result<Self, ParamError> {
        let control_every = control_every(&plant, controller.control_dt(), dt)?;
        // The lanes hand the laws the reference's state, not its path (Law::reads_path).
        let law = controller.law();
        if law.needs_path() || (law.reads_path() && reference.path().is_some()) {
            return Err(check::out_of_range(
                "kind",
                "the lanes do not carry the reference's path, which this law follows (run it on the exact path)",
                0.0,
            ));
        }
        // The lanes step the Coulomb model; stiction's stick/slip switch is per run.
        if plant.robot().has_stiction() {
            return Err(check::out_of_range(
                "static_friction",
                "the lanes do not step stiction (run such a plant on the exact path)",
                plant.robot().params().static_friction,
            ));
        }
        // The lanes step without the pushes' time windows (crate::push).
        if !plant.pushes().is_empty() {
            return Err(check::out_of_range(
                "push",
                "the lanes do not step pushes (run such a plant on the exact path)",
                plant.pushes().as_slice().len() as f64,
            ));
        }
        // The lanes step one robot; a payload that appears swaps it per run (crate::Plant).
        if let Some(t) = plant.payload_time() {
            return Err(check::out_of_range(
                "payload.t",
                "the lanes do not step a payload that appears at a time (run such a plant on the exact path)",
                t,
            ));
        }
        // Each lane counts its steps in an f64, exact up to 2^53 (a scenario allows 1e9).
        if n_steps > 1 << 53 {
            return Err(check::out_of_range("t_end", "more than 2^53 plant steps", n_steps as f64));
        }
        // t_end as the exact loop computes it (ClosedLoop::try_run from step 0).
        let watch = SettleWatch::new(n_steps as f64 * dt, plant.robot().params());
        let zero = Lanes::splat(0.0);
        let metrics = Metrics::default().judging_heading(controller.reaches_heading());
        Ok(Self {
            plant,
            controller,
            fixed: reference.fixed().then(|| reference.state_at(0.0).splat()),
            // The settle rule needs a reference that does not move.
            stop_when_settled: stop_when_settled && reference.fixed(),
            reference,
            clock: StepClock::new(dt),
            control_every,
            n_steps,
            global_step: 0,
            state: State::from_array([zero; 7]),
            heading: (Lanes::splat(1.0), zero),
            command: Wheels::new(zero, zero),
            held_torque: Wheels::new(zero, zero),
            metrics,
            watch,
            early_arrival: false,
            arrival: ArrivalWatch::new(n_steps as f64 * dt),
            steps: zero,
            active: LaneMask::splat(false),
            tags: [0; N],
            obstacles: Obstacles::default(),
        })
    }

    /// With `obstacles` on the ground: a lane whose footprint touches one ends there,
    /// [`Termination::Collided`], as [`crate::ClosedLoop::with_obstacles`].
    pub fn with_obstacles(mut self, obstacles: Obstacles<f64>) -> Self {
        self.obstacles = obstacles;
        self
    }

    /// With `on` (and `stop_when_settled`), a run also stops as soon as it has arrived
    /// by the shorter test of [`crate::arrival`] (off by default), ending as
    /// [`Termination::Settled`].
    pub fn early_arrival(mut self, on: bool) -> Self {
        self.early_arrival = on;
        self
    }

    /// Runs every start pose `next` gives (with the caller's tag), N at a time, handing
    /// each outcome to `done` with its tag as soon as the run ends (not in the order
    /// given). Returns when `next` has no more and every lane has finished.
    #[inline(always)]
    pub fn run_all(
        &mut self,
        mut next: impl FnMut() -> Option<(u64, Pose2<f64>)>,
        mut done: impl FnMut(u64, Outcome<f64>),
    ) {
        let dt = self.clock.dt;
        let bound = Lanes::splat(DIVERGENCE_BOX_M);
        // Exact as an f64: `new` refuses more than 2^53 steps.
        let last_step = Lanes::splat(self.n_steps as f64);
        let (one, zero) = (Lanes::splat(1.0), Lanes::splat(0.0));
        // One call site of the control tick (inlined into each kernel of `wmr-scenario`,
        // it is half of the loop's code: two sites built it twice, a third of each
        // kernel's unoptimized code): the first tick, before the first step, and then
        // every `control_every` steps.
        let mut more = true;
        let mut tick = true;
        loop {
            if tick {
                if more {
                    more = self.load(&mut next);
                }
                self.control_tick();
            }
            // Before the step: a run at t_end ends; the metrics of the present state; a
            // settled run ends.
            let ended = self.active & self.steps.eq(last_step);
            if ended.any() {
                for i in (0..N).filter(|&i| ended.lane(i)) {
                    self.finish(i, Termination::Completed, &mut done);
                }
            }
            let t = self.clock.time_lanes(self.steps);
            let goal = self.reference_lanes(t).pose;
            let speeds = wheel_speeds_lanes(self.plant.robot().params(), self.state.v, self.state.omega);
            let torque = self.plant.wheel_torque_lanes(&self.state, self.command, self.held_torque);
            self.metrics.add_step(t, &self.state, speeds, torque, goal, Lanes::splat(dt));
            if self.stop_when_settled {
                let mut settled = self.watch.settled(
                    t,
                    &self.state,
                    goal,
                    self.controller.holding(),
                    self.controller.integrator_travel(),
                );
                if self.early_arrival {
                    settled = settled | self.arrival.arrived(t, &self.state, goal, self.controller.holding());
                }
                if settled.any() {
                    for i in (0..N).filter(|&i| settled.lane(i)) {
                        self.finish(i, Termination::Settled, &mut done);
                    }
                }
            }
            let busy = self.active.any();
            if !busy && !more {
                break;
            }
            if busy {
                // One RK4 step of every lane; a lane whose step is not finite or leaves
                // the box keeps its last good state and ends.
                let (stepped, heading) = self.plant.advance_carrying_heading(
                    &self.state,
                    self.heading,
                    self.command,
                    self.held_torque,
                    Lanes::splat(dt),
                );
                let finite = all_finite(&stepped);
                let inside = stepped.x.abs().le(bound) & stepped.y.abs().le(bound);
                let ok = finite & inside;
                let mut state = self.state.to_array();
                for (c, new) in state.iter_mut().zip(stepped.to_array()) {
                    c.assign_where(ok, new);
                }
                self.state = State::from_array(state);
                self.heading.0.assign_where(ok, heading.0);
                self.heading.1.assign_where(ok, heading.1);
                self.steps = self.steps + Lanes::select(ok & self.active, one, zero);
                let failed = self.active & !ok;
                if failed.any() {
                    for i in (0..N).filter(|&i| failed.lane(i)) {
                        let termination = if finite.lane(i) { Termination::LeftBox } else { Termination::NonFinite };
                        self.finish(i, termination, &mut done);
                    }
                }
                if !self.obstacles.is_empty() {
                    let hit = self.active & self.obstacles.clearance(self.state.x, self.state.y).le(zero);
                    if hit.any() {
                        for i in (0..N).filter(|&i| hit.lane(i)) {
                            self.finish(i, Termination::Collided, &mut done);
                        }
                    }
                }
            }
            self.global_step += 1;
            tick = self.global_step.is_multiple_of(u64::from(self.control_every));
        }
    }

    /// Puts the next runs into the free lanes, each at its start at rest with its
    /// controller memories cleared; false once `next` has no more.
    fn load(&mut self, next: &mut impl FnMut() -> Option<(u64, Pose2<f64>)>) -> bool {
        if self.active.all() {
            return true;
        }
        let mut fresh = [false; N];
        let mut more = true;
        for (i, fresh) in fresh.iter_mut().enumerate() {
            if self.active.lane(i) {
                continue;
            }
            let Some((tag, start)) = next() else {
                more = false;
                break;
            };
            self.set_lane(i, &State::at_rest(start));
            self.tags[i] = tag;
            self.steps.0[i] = 0.0;
            *fresh = true;
        }
        let fresh = LaneMask::from_bools(fresh);
        self.active = self.active | fresh;
        self.metrics.reset_lanes(fresh);
        self.watch.reset_lanes(fresh);
        self.arrival.reset_lanes(fresh);
        self.controller.reset_lanes(fresh);
        more
    }

    /// The control tick of every lane: the true state measured, the controller updated,
    /// its commands held.
    #[inline(always)]
    fn control_tick(&mut self) {
        let t = self.clock.time_lanes(self.steps);
        let s = &self.state;
        let m = Measurement {
            t,
            pose: Pose2::new(s.x, s.y, s.theta),
            wheel_angles: Wheels::new(s.phi_r, s.phi_l),
            wheel_speeds: wheel_speeds_lanes(self.plant.robot().params(), s.v, s.omega),
        };
        let r = self.reference_lanes(t);
        self.command = self.plant.drive().deadband(self.controller.update(t, &m, &r).command);
        self.held_torque = self.plant.held_torque_lanes(self.command);
    }

    /// The reference state of every lane at its own time `t` (s).
    #[inline(always)]
    fn reference_lanes(&self, t: Lanes<N>) -> ReferenceState<Lanes<N>> {
        if let Some(fixed) = self.fixed {
            return fixed;
        }
        let at: [ReferenceState<f64>; N] = core::array::from_fn(|i| self.reference.state_at(t.0[i]));
        let lanes = |f: fn(&ReferenceState<f64>) -> f64| Lanes(core::array::from_fn(|i| f(&at[i])));
        ReferenceState {
            pose: Pose2::new(lanes(|r| r.pose.x), lanes(|r| r.pose.y), lanes(|r| r.pose.theta)),
            twist: Twist2 { v: lanes(|r| r.twist.v), omega: lanes(|r| r.twist.omega) },
            accel: Twist2 { v: lanes(|r| r.accel.v), omega: lanes(|r| r.accel.omega) },
        }
    }

    /// Ends lane `i`'s run with `termination` at its present state and frees the lane.
    fn finish(&mut self, i: usize, termination: Termination, done: &mut impl FnMut(u64, Outcome<f64>)) {
        if !self.active.lane(i) {
            return;
        }
        self.active = self.active & !LaneMask::lane_only(i);
        let s = lane(&self.state, i);
        // Whole and below 2^53: the cast is exact.
        let t = self.clock.time(self.steps.0[i] as u64);
        let mut metrics = self.metrics.lane(i);
        let goal = self.reference.pose_at(t);
        metrics.observe(t, &s, s.wheel_speeds(self.plant.robot().params()), goal);
        done(self.tags[i], metrics.finish(t, &s, goal, termination));
        // A benign state until the lane takes its next run.
        self.set_lane(i, &State::at_rest(goal));
    }

    /// Sets lane `i`'s state to `s`, with its heading's (cos, sin).
    fn set_lane(&mut self, i: usize, s: &State<f64>) {
        set_lane(&mut self.state, i, s);
        let (sin, cos) = s.theta.sin_cos_libm();
        (self.heading.0.0[i], self.heading.1.0[i]) = (cos, sin);
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
