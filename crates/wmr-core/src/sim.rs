//! The closed-loop stepper: plant by RK4 at `dt`, controller every `control_dt` with a
//! zero-order hold, samples handed to a caller's sink without allocating.

use crate::controller::ControlErrors;
use crate::controller::{ControlOutput, Controller, Measurement};
use crate::drive::Drive;
use crate::dynamics::Model;
use crate::error::{ParamError, check};
use crate::integrator::rk4_step;
use crate::math::{Pose2, Wheels};
use crate::metrics::{Metrics, Outcome, Termination};
use crate::state::{STATE_LEN, State};
use crate::{Real, Robot};

/// Half-width of the box (m) point C must stay in; outside it the run has diverged.
pub const DIVERGENCE_BOX_M: f64 = 1000.0;

/// Everything logged at one instant (SPEC section 6 columns).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample<T> {
    /// Time, s.
    pub t: T,
    /// State at `t`.
    pub state: State<T>,
    /// Wheel speeds at `t`, rad/s.
    pub wheel_speeds: Wheels<T>,
    /// Wheel torques applied from `t` on, N m.
    pub torque: Wheels<T>,
    /// The controller's errors of the last control tick at or before `t`.
    pub errors: ControlErrors<T>,
}

/// Why a step was refused: the run has diverged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diverged<T> {
    /// Time of the last good state, s.
    pub t: T,
    /// Non-finite or out of the box.
    pub termination: Termination,
}

/// A robot, its drive and a controller, closed into one loop.
#[derive(Clone, Debug)]
pub struct ClosedLoop<T, C> {
    robot: Robot<T>,
    /// The robot's equations with their constants precomputed once.
    model: Model<T>,
    drive: Drive<T>,
    controller: C,
    state: State<T>,
    dt: T,
    step_index: u64,
    control_every: u32,
    /// Plant steps left until the next control tick (a countdown instead of a `%` per step).
    steps_to_control: u32,
    output: ControlOutput<T>,
    /// Wheel torques for the current hold when they do not depend on speed.
    held_torque: Wheels<T>,
    diverged: Option<Diverged<T>>,
}

impl<T: Real, C: Controller<T>> ClosedLoop<T, C> {
    /// A loop starting at rest at `start` (m, m, rad) with plant step `dt` (s); the
    /// controller's `control_dt` must be a whole multiple of `dt`. Runs the first
    /// control tick at t = 0.
    pub fn new(robot: Robot<T>, drive: Drive<T>, controller: C, start: Pose2<T>, dt: T) -> Result<Self, ParamError> {
        check::positive("sim.dt", dt)?;
        check::finite("run.start.x", start.x)?;
        check::finite("run.start.y", start.y)?;
        check::finite("run.start.theta", start.theta)?;
        let control_every = check::whole_multiple("controller.control_dt", controller.control_dt(), dt)?;
        let mut lp = Self {
            robot,
            model: Model::new(&robot),
            drive,
            controller,
            state: State::at_rest(start),
            dt,
            step_index: 0,
            control_every,
            steps_to_control: control_every,
            output: ControlOutput::default(),
            held_torque: Wheels::default(),
            diverged: None,
        };
        lp.control_tick();
        Ok(lp)
    }

    /// The robot.
    pub fn robot(&self) -> &Robot<T> {
        &self.robot
    }

    /// The controller.
    pub fn controller(&self) -> &C {
        &self.controller
    }

    /// The current state.
    pub fn state(&self) -> &State<T> {
        &self.state
    }

    /// Plant steps taken.
    pub fn steps(&self) -> u64 {
        self.step_index
    }

    /// Current time, s (step count times dt, so it does not drift).
    #[inline(always)]
    pub fn time(&self) -> T {
        T::lit(self.step_index as f64) * self.dt
    }

    /// Plant step, s.
    pub fn dt(&self) -> T {
        self.dt
    }

    /// Set once a step has been refused.
    pub fn divergence(&self) -> Option<Diverged<T>> {
        self.diverged
    }

    fn control_tick(&mut self) {
        let p = self.robot.params();
        let m = Measurement {
            pose: self.state.pose(),
            wheel_angles: self.state.wheel_angles(),
            wheel_speeds: self.state.wheel_speeds(p),
        };
        self.output = self.controller.update(&m);
        if self.drive.is_speed_independent() {
            let d = self.drive;
            self.held_torque = self.output.command.map(|c| d.wheel_torque(c, T::zero()));
        }
    }

    #[inline(always)]
    fn wheel_torque(&self, s: &State<T>) -> Wheels<T> {
        if self.drive.is_speed_independent() {
            self.held_torque
        } else {
            let w = s.wheel_speeds(self.robot.params());
            let c = self.output.command;
            Wheels::new(self.drive.wheel_torque(c.right, w.right), self.drive.wheel_torque(c.left, w.left))
        }
    }

    /// The sample at the current time.
    #[inline(always)]
    pub fn sample(&self) -> Sample<T> {
        Sample {
            t: self.time(),
            state: self.state,
            wheel_speeds: self.state.wheel_speeds(self.robot.params()),
            torque: self.wheel_torque(&self.state),
            errors: self.output.errors,
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
        let y = self.state.to_array();
        let model = &self.model;
        let next = if self.drive.is_speed_independent() && !model.has_coulomb() {
            // The hot case (torque drive, no Coulomb friction: the defaults). The torques
            // are held over the whole step: pass them by value, and decide the friction
            // once, so the four RK4 stages neither branch nor reload them.
            let tau = self.held_torque;
            let f = |_, y: &[T; STATE_LEN]| model.derivative_with::<false>(&State::from_array(*y), tau).to_array();
            rk4_step(f, self.time(), &y, self.dt)
        } else {
            rk4_step(
                |_, y| {
                    let s = State::from_array(*y);
                    model.derivative(&s, self.wheel_torque(&s)).to_array()
                },
                self.time(),
                &y,
                self.dt,
            )
        };
        let next = State::from_array(next);
        let bound = T::lit(DIVERGENCE_BOX_M);
        let termination = if !all_finite(&next) {
            Some(Termination::NonFinite)
        } else if next.x.abs() > bound || next.y.abs() > bound {
            Some(Termination::LeftBox)
        } else {
            None
        };
        if let Some(termination) = termination {
            let d = Diverged { t: self.time(), termination };
            self.diverged = Some(d);
            return Err(d);
        }
        self.state = next;
        self.step_index += 1;
        self.steps_to_control -= 1;
        if self.steps_to_control == 0 {
            self.steps_to_control = self.control_every;
            self.control_tick();
        }
        Ok(())
    }

    /// Runs `n_steps` plant steps, handing `sink` the sample at t = 0, every `log_every`
    /// steps, and the last one (at the end, or the last good state of a diverged run).
    /// Returns the run's [`Outcome`].
    pub fn run(&mut self, n_steps: u64, log_every: u32, mut sink: impl FnMut(&Sample<T>)) -> Outcome<T> {
        let log_every = u64::from(log_every.max(1));
        let mut metrics = Metrics::new(self.controller.goal());
        let mut termination = Termination::Completed;
        let mut last_logged = None;
        for _ in 0..n_steps {
            let s = self.sample();
            if self.step_index.is_multiple_of(log_every) {
                sink(&s);
                last_logged = Some(self.step_index);
            }
            metrics.add_step(&s, self.dt);
            if let Err(d) = self.step() {
                termination = d.termination;
                break;
            }
        }
        let last = self.sample();
        metrics.observe(&last);
        if last_logged != Some(self.step_index) {
            sink(&last);
        }
        metrics.finish(&last, termination)
    }
}

/// True when every component of `s` is finite: the same test as [`State::is_finite`],
/// written branch-free for the hot path. 0 c is a zero for a finite c and NaN for an
/// infinite or NaN one, and a sum of zeros cannot overflow, so the sum is zero exactly
/// when all seven components are finite.
#[inline(always)]
fn all_finite<T: Real>(s: &State<T>) -> bool {
    let z = T::zero();
    let sum = s.x * z + s.y * z + s.theta * z + s.v * z + s.omega * z + s.phi_r * z + s.phi_l * z;
    sum == z
}
