//! The contract of an outer law: from (time, measurement, reference state) to a demand
//! on the wheels and the errors it logs. A new law is one file implementing [`Law`] and
//! [`LawSpec`] plus one line in [`super::registry`] (CONTRIBUTING.md).

use crate::describe::Described;
use crate::drive::DriveParams;
use crate::error::ParamError;
use crate::lane::{Lane, Mask};
use crate::math::{Twist2, Wheels};
use crate::obstacle::Obstacles;
use crate::reference::{Path, ReferenceState};
use crate::sensor::Measurement;
use crate::{Real, RobotParams};

/// What a law follows: the registry's `follows` word ([`super::registry`]). It decides
/// what a scenario must give the law (a goal, or a `[reference]`), how a run is judged
/// (settling at the goal, tracking error, distance to the path) and how a law is called
/// (a path-following law receives the reference's path, [`Law::update_on_path`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Follows {
    /// A goal pose at rest: point stabilization.
    Goal,
    /// A moving reference (pose, twist and acceleration at each time): tracking.
    Trajectory,
    /// The geometric path of a reference, its timing ignored: path following.
    Path,
    /// A goal at rest, or the path of a moving reference when the scenario has one (nav2's
    /// MPPI: its goal critics at a goal, its path critics on a path).
    GoalOrPath,
}

impl Follows {
    /// True for a law that needs a moving reference (a trajectory or its path).
    pub fn needs_reference(self) -> bool {
        matches!(self, Follows::Trajectory | Follows::Path)
    }

    /// True for a law that may be given a moving reference.
    pub fn accepts_reference(self) -> bool {
        self != Follows::Goal
    }

    /// True for a law that, given a moving reference, follows its path (its timing
    /// ignored): the law receives the path ([`Law::update_on_path`]) and a run is judged
    /// on its distance to the path.
    pub fn follows_path(self) -> bool {
        matches!(self, Follows::Path | Follows::GoalOrPath)
    }
}

/// What a law's keys declare about the law beside its code, read by every expansion of
/// the registry ([`super::registry`]): how to build it, and what one update costs.
/// Implemented by the law's parameter struct (declared with `params! { words; ... }`).
pub trait LawSpec<T: Real>: Described + Copy + Default + PartialEq {
    /// The law, running `L` (one run, or several side by side: [`crate::lane`]).
    type Law<L: Lane<Scalar = T>>: Law<L> + Copy;

    /// CPU time of a plant step under this law (with these keys) against one under the
    /// paper's law: a sweep's announced duration, and the work a scenario may ask for
    /// (`wmr_scenario`'s step budget weighs each run by it). Measured; the law file says
    /// where.
    fn update_cost(&self) -> f64 {
        1.0
    }

    /// Whether the trace ([`crate::trace`]) carries the law: its keys fit the trace's
    /// law words (16). MPPI's 30 keys do not: `wmr-cli trace` refuses it, and the
    /// firmware does not replay it.
    const TRACED: bool = true;

    /// Whether the law demands a body twist ([`WheelDemand::Twist`]) at every tick, which
    /// the samples then carry (`Sample::twist_demand`, CSV `v_cmd`, `omega_cmd`, ROS 2
    /// `/cmd_vel`); false for a law that demands wheel angles or torques.
    const TWIST_DEMAND: bool = true;

    /// Validates the keys (errors name the key) and builds the law for the controller's
    /// robot model and control period (s).
    fn build<L: Lane<Scalar = T>>(&self, model: &RobotParams<T>, control_dt: T) -> Result<Self::Law<L>, ParamError>;

    /// [`LawSpec::build`] knowing all the controller knows ([`LawContext`]): what a law
    /// that predicts with the whole robot and its surroundings needs (MPPI's dynamic
    /// rollouts and obstacles critic). Every other law keeps this default.
    fn build_in<L: Lane<Scalar = T>>(&self, ctx: &LawContext<'_, T>) -> Result<Self::Law<L>, ParamError> {
        self.build(ctx.model, ctx.control_dt)
    }
}

/// What a controller knows when it builds its law: its model of the robot, the drive it
/// commands, the wheel stage's speed limit, the obstacles on its map, the control period.
#[derive(Clone, Copy, Debug)]
pub struct LawContext<'a, T> {
    /// The controller's robot (`[controller.model]`).
    pub model: &'a RobotParams<T>,
    /// The drive it commands.
    pub drive: &'a DriveParams<T>,
    /// The wheel stage's per-wheel speed limit, rad/s (infinite: none).
    pub wheel_speed_max: T,
    /// The obstacles it knows of, with its footprint ([`crate::obstacle`]).
    pub obstacles: &'a Obstacles<T>,
    /// The control period, s.
    pub control_dt: T,
    /// The run's index, which selects the noise stream of a law that samples (MPPI's
    /// rollouts), as it selects the sensor's (`[sensor] seed` with the run index): run 0
    /// draws from the law's own `seed` key, run k > 0 from that key mixed with k. The
    /// scenario's run index (`[[run]]` k, a sweep's run k), C's `run`, Python's `run`.
    pub run: u64,
}

/// What a law asks of the wheel stage.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum WheelDemand<T> {
    /// Absolute wheel angle references (right, left), rad: the paper's law, (20)^-1.
    Angles(Wheels<T>),
    /// A body twist: v in m/s, omega in rad/s (laws in polar coordinates).
    Twist(Twist2<T>),
    /// Wheel torques (right, left), N m at the wheel: laws that compute the torques from
    /// the robot's dynamic model.
    Torques(Wheels<T>),
}

impl<T: Lane> Default for WheelDemand<T> {
    fn default() -> Self {
        WheelDemand::Twist(Twist2::default())
    }
}

/// Each law's diagnostic errors, logged with every sample (CSV columns `e_s`, `e_theta`,
/// `dl`). What they mean depends on the law:
///
/// | law | dl | e_theta | e_s |
/// |---|---|---|---|
/// | paper | distance to the goal (16) | wrap(theta_R - theta) (21), towards the false target | dl cos(theta_R - theta) (18) |
/// | polar, lyapunov | distance to the goal | wrap(theta_d - theta), the final heading error | (x_d - x) cos(theta) + (y_d - y) sin(theta) |
/// | kanayama, backstepping | distance to C_ref | theta_e = wrap(theta_ref - theta) | x_e, C_ref's offset along the heading |
/// | pure_pursuit | distance to the path | wrap(theta_path - theta) at the closest point | the closest point's offset along the heading |
///
/// All are computed from the measurement the law saw. How a run went is judged
/// elsewhere, from the true state ([`crate::outcome`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ControlErrors<T> {
    /// e_s, m: the law's along-track error.
    pub e_s: T,
    /// e_theta, rad, wrapped into (-pi, pi]: the law's heading error.
    pub e_theta: T,
    /// dl, m: the measured distance from C to the goal position.
    pub dl: T,
}

/// One law update: the wheel demand and the errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawOutput<T> {
    /// What the wheels should do until the next tick.
    pub demand: WheelDemand<T>,
    /// The law's errors, for logging.
    pub errors: ControlErrors<T>,
}

/// An outer law, run once per control period.
pub trait Law<T: Lane> {
    /// The demand on the wheels at time `t` (s) from measurement `m` and the reference
    /// state `r` at `t` (pose in the world frame, twist and acceleration; a stabilization
    /// law reads only `r.pose`, the goal); advances the law's memories by one period.
    fn update(&mut self, t: T, m: &Measurement<T>, r: &ReferenceState<T>) -> LawOutput<T>;

    /// [`Law::update`] when the reference has a geometric path (`path`, see
    /// [`crate::reference::Path`]): a path-following law reads it, every other law keeps
    /// this default and ignores it.
    #[inline(always)]
    fn update_on_path(&mut self, t: T, m: &Measurement<T>, r: &ReferenceState<T>, path: &dyn Path<T>) -> LawOutput<T> {
        let _ = path;
        self.update(t, m, r)
    }

    /// True for a law that follows the reference's geometric path and has nothing to
    /// follow without one (pure pursuit): the lanes ([`crate::batch`]), which carry no
    /// path, refuse it, and a scenario refuses it on a goal at rest.
    fn needs_path(&self) -> bool {
        false
    }

    /// True for a law that reads the reference's geometric path when it has one
    /// ([`Law::update_on_path`]: pure pursuit, MPPI): the lanes, which carry no path,
    /// refuse it on a reference with one rather than run it without.
    fn reads_path(&self) -> bool {
        self.needs_path()
    }

    /// Clears integrators and memories, as at t = 0.
    fn reset(&mut self) {
        self.reset_lanes(T::Mask::splat(true));
    }

    /// [`Law::reset`] of the runs in `lanes` only (several runs side by side: a lane
    /// that takes a new run starts it afresh).
    fn reset_lanes(&mut self, lanes: T::Mask);

    /// The wheel stage saturated at the last tick in `lanes` ([`super::WheelStage::saturated`]):
    /// called before each [`Law::update`]. A law with integrators holds them in those
    /// lanes for the coming update when its anti-windup is on (conditional integration,
    /// docs/model.md, "Anti-windup"); a law without integrators keeps this default.
    #[inline(always)]
    fn wheels_saturated(&mut self, lanes: T::Mask) {
        let _ = lanes;
    }

    /// Whether the integrators stop winding up while the wheel stage saturates: the
    /// law's own ([`Law::wheels_saturated`]) and the wheel servos' (`servo_ki`). On for
    /// every law but the paper's as printed (`[controller] anti_windup`, off by default).
    fn anti_windup(&self) -> bool {
        true
    }

    /// True for a stabilization law built to bring the heading to the goal's too (its
    /// Lyapunov function or its ordering includes it): its runs count as converged only
    /// within [`crate::outcome::ARRIVAL_HEADING_RAD`] of the goal heading. False (the
    /// default) for the paper's law, which leaves several degrees by design, for the
    /// polar law, whose heading lags its distance, and for tracking laws (judged on their
    /// tracking error).
    fn reaches_heading(&self) -> bool {
        false
    }

    /// True when the last update was inside the law's hold: its memories no longer move
    /// and its demand stays the same while the measured pose stays in the hold. A law
    /// without a hold keeps the default, false, and its runs are never stopped early
    /// ([`crate::settle`]).
    /// Per lane when the law runs several runs side by side ([`crate::lane`]).
    fn holding(&self) -> T::Mask {
        T::Mask::splat(false)
    }
}
