//! The closed loop: plant stepped by RK4 at `dt`; every `control_dt` the sensor measures,
//! the reference gives its state, the controller updates and its command is held
//! (zero-order hold). Samples go to a caller's sink; the outcome is judged from the
//! true state against the reference. Nothing here allocates.
//!
//! This is the one stepping function of a single run: the scenario runner, the f32 trace
//! (`wmr-cli trace`, replayed on the firmware) and the Python `simulate` all step a
//! [`ClosedLoop`]; each control tick's inputs and outputs are kept as a [`Tick`].
//!
//! ```text
//!   reference.state_at(t) ─────────────┐
//!                                      v
//!   plant.state ─> sensor.measure ─> controller.update(t, m, r) ─> plant.apply(command)
//!        ^                                                                  │
//!        └──────────────────── plant.step(t, dt) (RK4) <────────────────────┘
//! ```

use core::convert::Infallible;
use core::ops::ControlFlow;

use crate::Real;
use crate::arrival::ArrivalWatch;
use crate::clock::StepClock;
use crate::controller::{ControlOutput, Controller, Law};
use crate::error::{ParamError, check};
use crate::obstacle::Obstacles;
use crate::outcome::{Metrics, Outcome, Termination};
use crate::plant::Plant;
use crate::reference::{FixedGoal, Reference, ReferenceState};
use crate::sample::Sample;
use crate::sensor::{Measurement, PerfectSensor, Sensor};
use crate::settle::SettleWatch;

/// One control tick: what the controller was given and what it answered.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tick<T> {
    /// Time of the tick, s.
    pub t: T,
    /// What the sensor gave the controller.
    pub measurement: Measurement<T>,
    /// The reference state at `t`.
    pub reference: ReferenceState<T>,
    /// The drive commands, held until the next tick, and the law's errors.
    pub output: ControlOutput<T>,
}

/// Why a step was refused: the run has diverged, or its footprint touched an obstacle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diverged<T> {
    /// Time of the last good state (of the contact, for a collision), s.
    pub t: T,
    /// Non-finite, out of the box, or collided.
    pub termination: Termination,
}

/// A plant, a sensor, a controller (law `L` and wheel stage) and a reference, closed
/// into one loop.
#[derive(Clone, Debug)]
pub struct ClosedLoop<T: Real, L, S = PerfectSensor, R = FixedGoal<T>> {
    plant: Plant<T>,
    sensor: S,
    controller: Controller<T, L>,
    reference: R,
    clock: StepClock<T>,
    step_index: u64,
    control_every: u32,
    /// Plant steps left until the next control tick (a countdown instead of a `%` per step).
    steps_to_control: u32,
    /// The last control tick.
    tick: Tick<T>,
    diverged: Option<Diverged<T>>,
    /// Stop a run once it has settled ([`crate::settle`]).
    stop_when_settled: bool,
    /// With `stop_when_settled`, stop it as soon as it has arrived ([`crate::arrival`]).
    early_arrival: bool,
    /// What the footprint may not touch ([`crate::obstacle`]); none by default.
    obstacles: Obstacles<T>,
    /// The goal tolerances a run's outcome is judged docked with, m and rad
    /// ([`Outcome::docked`]).
    goal_tolerance: (T, T),
}

impl<T: Real, L: Law<T>, R: Reference<T>> ClosedLoop<T, L, PerfectSensor, R> {
    /// A loop whose controller sees the true state ([`PerfectSensor`]); see
    /// [`ClosedLoop::with_sensor`].
    pub fn new(plant: Plant<T>, controller: Controller<T, L>, reference: R, dt: T) -> Result<Self, ParamError> {
        Self::with_sensor(plant, PerfectSensor, controller, reference, dt)
    }
}

impl<T: Real, L: Law<T>, S: Sensor<T>, R: Reference<T>> ClosedLoop<T, L, S, R> {
    /// A loop with plant step `dt` (s); the controller's `control_dt` must be a whole
    /// multiple of it (errors name `dt` and `control_dt`). Runs the first control tick
    /// at t = 0. The controller's wheel stage is told whether the plant's wheels slip
    /// ([`Controller::with_slipping_wheels`]).
    pub fn with_sensor(
        plant: Plant<T>,
        sensor: S,
        controller: Controller<T, L>,
        reference: R,
        dt: T,
    ) -> Result<Self, ParamError> {
        let control_every = control_every(&plant, controller.control_dt(), dt)?;
        // The speed guard of wheels that slip acts on their own inertia (WheelStage).
        let controller = controller.with_slipping_wheels(plant.slips());
        let mut lp = Self {
            plant,
            sensor,
            controller,
            reference,
            clock: StepClock::new(dt),
            step_index: 0,
            control_every,
            steps_to_control: control_every,
            tick: Tick::default(),
            diverged: None,
            stop_when_settled: false,
            early_arrival: false,
            obstacles: Obstacles::default(),
            goal_tolerance: (
                T::lit(crate::outcome::XY_GOAL_TOLERANCE_M),
                T::lit(crate::outcome::YAW_GOAL_TOLERANCE_DEG * core::f64::consts::PI / 180.0),
            ),
        };
        lp.control_tick();
        Ok(lp)
    }

    /// With `obstacles` on the ground: a step that brings the footprint into contact with
    /// one ends the run there, [`Termination::Collided`] ([`crate::obstacle`]). A start
    /// already in contact collides at the first step.
    pub fn with_obstacles(mut self, obstacles: Obstacles<T>) -> Self {
        self.obstacles = obstacles;
        self
    }

    /// The obstacles ([`ClosedLoop::with_obstacles`]).
    pub fn obstacles(&self) -> &Obstacles<T> {
        &self.obstacles
    }

    /// With `on`, [`ClosedLoop::run`] and [`ClosedLoop::try_run`] stop a run once it
    /// has settled by the rule of [`crate::settle`] (off by default: runs keep their full
    /// length). The outcome's termination is then [`Termination::Settled`].
    pub fn stop_when_settled(mut self, on: bool) -> Self {
        self.stop_when_settled = on;
        self
    }

    /// With `on` (and [`ClosedLoop::stop_when_settled`]), a run also stops as soon as it
    /// has arrived by the shorter test of [`crate::arrival`] (off by default), ending as
    /// [`Termination::Settled`].
    pub fn early_arrival(mut self, on: bool) -> Self {
        self.early_arrival = on;
        self
    }

    /// The goal tolerances the outcome of a run is judged docked with: `xy` (m) on the
    /// final distance to the goal position, `yaw` (rad) on the final |heading error|
    /// ([`Outcome::docked`]; by default [`crate::XY_GOAL_TOLERANCE_M`] and
    /// [`crate::YAW_GOAL_TOLERANCE_DEG`]). Nothing else of the run changes.
    pub fn goal_tolerance(mut self, xy: T, yaw: T) -> Self {
        self.goal_tolerance = (xy, yaw);
        self
    }

    /// The plant (the truth).
    pub fn plant(&self) -> &Plant<T> {
        &self.plant
    }

    /// The controller.
    pub fn controller(&self) -> &Controller<T, L> {
        &self.controller
    }

    /// The sensor.
    pub fn sensor(&self) -> &S {
        &self.sensor
    }

    /// The reference.
    pub fn reference(&self) -> &R {
        &self.reference
    }

    /// The current true state.
    pub fn state(&self) -> &crate::State<T> {
        self.plant.state()
    }

    /// Plant steps taken.
    pub fn steps(&self) -> u64 {
        self.step_index
    }

    /// Current time, s: the step count times dt, so it does not drift. In `f64`, when dt
    /// is a short decimal (1e-3, 2.5e-4, 0.01), the time is the number nearest to the exact
    /// product (step 70 of 1 ms is 0.07 s, not 0.07000000000000001); otherwise it is the
    /// rounded product `steps * dt`.
    #[inline(always)]
    pub fn time(&self) -> T {
        self.clock.time(self.step_index)
    }

    /// Plant step, s.
    pub fn dt(&self) -> T {
        self.clock.dt
    }

    /// Set once a step has been refused.
    pub fn divergence(&self) -> Option<Diverged<T>> {
        self.diverged
    }

    /// The last control tick (the first one runs at t = 0, in the constructor). The
    /// plant's state is still the one measured until the next [`ClosedLoop::step`].
    pub fn last_tick(&self) -> &Tick<T> {
        &self.tick
    }

    fn control_tick(&mut self) {
        let t = self.time();
        // Each wheel's own speed: the body's (v +- R omega) / r for wheels that roll
        // (the same expression, bit for bit), their own state for wheels that slip.
        let wheel_speeds = self.plant.wheel_speeds();
        let measurement = self.sensor.measure_wheels(t, self.plant.state(), wheel_speeds, self.plant.robot().params());
        let reference = self.reference.state_at(t);
        let output = match self.reference.path() {
            Some(path) => self.controller.update_on_path(t, &measurement, &reference, path),
            None => self.controller.update(t, &measurement, &reference),
        };
        self.plant.apply(output.command);
        self.tick = Tick { t, measurement, reference, output };
    }

    /// The sample at the current time.
    #[inline(always)]
    pub fn sample(&self) -> Sample<T> {
        Sample {
            t: self.time(),
            state: *self.plant.state(),
            wheel_speeds: self.plant.wheel_speeds(),
            torque: self.plant.wheel_torque(),
            errors: self.tick.output.errors,
            measured: self.tick.measurement.pose,
            contact: self.plant.contact(),
            odometry: self.sensor.odometry(),
            twist_demand: self.tick.output.twist_demand,
            pose_covariance: self.sensor.pose_covariance(),
            disturbance: self.tick.output.disturbance,
        }
    }

    /// Advances one plant step `dt`, then runs the controller if a control tick is due.
    ///
    /// A step whose result is not finite or leaves the 1 km box is refused: the state
    /// stays at the last good one and this and every later call return [`Diverged`].
    #[inline]
    pub fn step(&mut self) -> Result<(), Diverged<T>> {
        if let Some(d) = self.diverged {
            return Err(d);
        }
        if let Err(termination) = self.plant.step(self.time(), self.clock.dt) {
            let d = Diverged { t: self.time(), termination };
            self.diverged = Some(d);
            return Err(d);
        }
        self.step_index += 1;
        if !self.obstacles.is_empty() {
            let s = self.plant.state();
            if self.obstacles.clearance(s.x, s.y) <= T::zero() {
                let d = Diverged { t: self.time(), termination: Termination::Collided };
                self.diverged = Some(d);
                return Err(d);
            }
        }
        self.steps_to_control -= 1;
        if self.steps_to_control == 0 {
            self.steps_to_control = self.control_every;
            self.control_tick();
        }
        Ok(())
    }

    /// Runs `n_steps` plant steps, handing `sink` the sample at t = 0, every `log_every`
    /// steps, and the last one (at the end, or the last good state of a diverged run).
    /// Returns the run's [`Outcome`], judged from the true state against the reference.
    pub fn run(&mut self, n_steps: u64, log_every: u32, mut sink: impl FnMut(&Sample<T>)) -> Outcome<T> {
        let keep_going = |s: &Sample<T>| -> ControlFlow<Infallible> {
            sink(s);
            ControlFlow::Continue(())
        };
        match self.try_run(n_steps, log_every, keep_going, || ControlFlow::Continue(())) {
            ControlFlow::Continue(outcome) => outcome,
            ControlFlow::Break(never) => match never {},
        }
    }

    /// [`ClosedLoop::run`] that may be stopped: `sink` gets the same samples and may
    /// answer [`ControlFlow::Break`] (an output that failed), and `poll` is asked before
    /// the first step and then every [`POLL_EVERY_STEPS`] steps (about a millisecond of
    /// work) whether to go on (a Ctrl-C, a deadline). A stopped run returns the `Break`
    /// value at once; the loop stays where it stopped. Run to the end, it returns the
    /// same outcome and samples as [`ClosedLoop::run`], bit for bit.
    pub fn try_run<B>(
        &mut self,
        n_steps: u64,
        log_every: u32,
        mut sink: impl FnMut(&Sample<T>) -> ControlFlow<B>,
        mut poll: impl FnMut() -> ControlFlow<B>,
    ) -> ControlFlow<B, Outcome<T>> {
        let log_every = u64::from(log_every.max(1));
        let mut metrics = Metrics::default().judging_heading(self.controller.reaches_heading());
        let mut termination = Termination::Completed;
        let mut last_logged = None;
        let mut done = 0;
        let t_end = T::lit((self.step_index + n_steps) as f64) * self.clock.dt;
        let mut watch = (self.stop_when_settled && self.sensor.deterministic() && self.reference.fixed())
            .then(|| SettleWatch::new(t_end, self.plant.robot().params()));
        let mut arrival = (watch.is_some() && self.early_arrival).then(|| ArrivalWatch::new(t_end));
        'run: while done < n_steps {
            poll()?;
            let chunk = (n_steps - done).min(POLL_EVERY_STEPS);
            for _ in 0..chunk {
                let s = self.sample();
                if self.step_index.is_multiple_of(log_every) {
                    sink(&s)?;
                    last_logged = Some(self.step_index);
                }
                let goal = self.reference.pose_at(s.t);
                metrics.add_step(s.t, &s.state, s.wheel_speeds, s.torque, goal, self.clock.dt);
                if let Some(w) = &mut watch
                    && w.settled(s.t, &s.state, goal, self.controller.holding(), self.controller.integrator_travel())
                {
                    termination = Termination::Settled;
                    break 'run;
                }
                if let Some(a) = &mut arrival
                    && a.arrived(s.t, &s.state, goal, self.controller.holding())
                {
                    termination = Termination::Settled;
                    break 'run;
                }
                if let Err(d) = self.step() {
                    termination = d.termination;
                    break 'run;
                }
            }
            done += chunk;
        }
        let last = self.sample();
        let goal = self.reference.pose_at(last.t);
        metrics.observe(last.t, &last.state, last.wheel_speeds, goal);
        if last_logged != Some(self.step_index) {
            sink(&last)?;
        }
        let (xy, yaw) = self.goal_tolerance;
        ControlFlow::Continue(metrics.finish(last.t, &last.state, goal, termination).with_goal_tolerance(xy, yaw))
    }
}

/// Plant steps between two calls of the `poll` of [`ClosedLoop::try_run`].
pub const POLL_EVERY_STEPS: u64 = 1024;

/// Checks the plant step `dt` (s) against the plant and the control period (s): the
/// plant steps per control tick. Errors name `dt` and `control_dt`.
pub(crate) fn control_every<T: Real>(plant: &Plant<T>, control_dt: T, dt: T) -> Result<u32, ParamError> {
    check::positive("dt", dt)?;
    if plant.substeps(dt).is_none() {
        let reason = if plant.slips() {
            "too large for the slip's contacts: more than 1000 RK4 sub-steps of dt * stiffness <= 0.9 x 2.785 \
             (Plant::substeps)"
        } else {
            "too large for the plant's friction: RK4 is unstable unless dt * stiffness < 2.785 (Plant::stiffness)"
        };
        return Err(check::out_of_range("dt", reason, dt));
    }
    check::whole_multiple("control_dt", control_dt, dt)
}
