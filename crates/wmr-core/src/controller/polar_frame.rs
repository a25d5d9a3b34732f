//! Polar coordinates of the goal seen from the robot, the choice of driving direction,
//! and [`PolarCoordinateLaw`], the shell every law in these coordinates shares (stop at
//! the goal, pick the direction, log the errors): such a law is its gains and a twist.
//!
//! Shared by the polar-coordinate laws ([`super::PolarLaw`],
//! [`super::LyapunovLaw`]). With (x, y, theta) the pose of C and
//! (x_d, y_d, theta_d) the goal, all in the world frame:
//!
//! ```text
//! phi   = atan2(y_d - y, x_d - x)        direction from C to the goal, rad (world frame)
//! rho   = hypot(x_d - x, y_d - y)        distance from C to the goal, m
//! alpha = wrap(phi - theta)              goal direction seen from the heading, rad
//! beta  = wrap(theta_d - phi)            goal heading seen from the goal direction, rad
//! ```
//!
//! so that alpha + beta = theta_d - theta (mod 2 pi) is the heading error. These are the
//! (rho, alpha, beta) of Siegwart, Nourbakhsh and Scaramuzza, "Introduction to Autonomous
//! Mobile Robots", 2nd ed., section 3.6.2.4 (after Astolfi 1999), written for a goal that
//! need not be at the origin; Aicardi et al. (1995) use the same e = rho and alpha, and
//! their goal-frame angle is theta_A = -beta.
//!
//! # Backward driving
//!
//! The laws converge only for alpha in I1 = (-pi/2, pi/2] (goal ahead). When the goal
//! lies behind (alpha in I2 = (-pi, -pi/2] or (pi/2, pi]) the robot drives backwards:
//! the "front" is redefined as the rear, i.e. both the heading and the goal heading are
//! turned by pi,
//!
//! ```text
//! alpha_b = wrap(phi - (theta + pi)),  beta_b = wrap((theta_d + pi) - phi),  v = -v_law
//! ```
//!
//! while omega is unchanged (turning the body frame by pi does not change theta-dot).
//! The goal is then reached rear first, with the true heading theta_d.
//!
//! The direction is decided once, at the first tick after construction or reset, from
//! the sign of cos(alpha) (Siegwart: "by redefining the forward direction of the robot
//! at t = 0"). Under the strong-stability gain condition the kinematic closed loop keeps
//! alpha in I1, so no switch is needed; on the dynamic robot alpha can overshoot
//! slightly, so a later switch happens only when |alpha| in the current direction
//! exceeds pi/2 + `hysteresis`. Just after a switch |alpha| < pi/2 - hysteresis in the
//! new direction, so the decision cannot chatter.
//!
//! Measured on the paper's robot (torque drive, no wheel speed limit), polar law from
//! (5, 9, 0) to (5, 5, 90 deg), where the goal is exactly abeam (alpha = -pi/2): the law
//! starts backwards with a large yaw-rate step; the torque-limited wheels cannot stop the
//! yaw (the m d v omega coupling of (15) pushes it while reversing), alpha overshoots
//! past pi/2 + pi/6 and the direction switches once, at 0.92 s, then never again. With
//! `wheel_speed_max = 20` rad/s there is no switch.

use super::law::{ControlErrors, Law, LawOutput, WheelDemand};
use crate::Real;
use crate::error::{ParamError, check};
use crate::math::{Pose2, Twist2, wrap_angle};
use crate::sensor::Measurement;

/// Which end of the robot leads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Direction {
    /// The heading theta points the way the robot drives (v >= 0 while approaching).
    #[default]
    Forward,
    /// The rear leads: heading and goal heading are turned by pi, v = -v_law.
    Backward,
}

impl Direction {
    /// +1 forward, -1 backward: the factor from the law's forward speed to v.
    #[inline]
    pub fn sign<T: Real>(self) -> T {
        match self {
            Direction::Forward => T::one(),
            Direction::Backward => -T::one(),
        }
    }

    /// The other direction.
    #[inline]
    pub fn flipped(self) -> Self {
        match self {
            Direction::Forward => Direction::Backward,
            Direction::Backward => Direction::Forward,
        }
    }
}

/// The goal in polar coordinates, in the driving frame of a [`Direction`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PolarCoords<T> {
    /// rho, distance from C to the goal position, m.
    pub rho: T,
    /// alpha, direction to the goal relative to the (driving-frame) heading, rad, in (-pi, pi].
    pub alpha: T,
    /// beta, goal heading relative to the direction to the goal, rad, in (-pi, pi].
    pub beta: T,
}

impl<T: Real> PolarCoords<T> {
    /// Polar coordinates of `goal` seen from `pose` (both in the world frame) in driving
    /// direction `dir`. At rho = 0 the direction phi is taken as atan2(0, 0) = 0.
    #[inline]
    pub fn new(pose: Pose2<T>, goal: Pose2<T>, dir: Direction) -> Self {
        let dx = goal.x - pose.x;
        let dy = goal.y - pose.y;
        let phi = dy.atan2_libm(dx);
        let (theta, theta_d) = match dir {
            Direction::Forward => (pose.theta, goal.theta),
            Direction::Backward => (pose.theta + T::PI(), goal.theta + T::PI()),
        };
        Self { rho: dx.hypot_libm(dy), alpha: wrap_angle(phi - theta), beta: wrap_angle(theta_d - phi) }
    }

    /// True for alpha in I1 = (-pi/2, pi/2]: the goal is ahead in this frame.
    #[inline]
    pub fn goal_ahead(&self) -> bool {
        let half_pi = T::FRAC_PI_2();
        self.alpha > -half_pi && self.alpha <= half_pi
    }
}

/// Chooses the driving direction once and switches it only with hysteresis (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionSelector<T> {
    allow_reverse: bool,
    hysteresis: T,
    current: Option<Direction>,
}

impl<T: Real> DirectionSelector<T> {
    /// A selector; `allow_reverse = false` always drives forward. `hysteresis` (rad, >= 0)
    /// is the overshoot of |alpha| past pi/2 that triggers a later switch.
    pub fn new(allow_reverse: bool, hysteresis: T) -> Self {
        Self { allow_reverse, hysteresis, current: None }
    }

    /// The direction in use, if one has been chosen since construction or reset.
    pub fn current(&self) -> Option<Direction> {
        self.current
    }

    /// The direction for this tick and the polar coordinates in its frame.
    #[inline]
    pub fn select(&mut self, pose: Pose2<T>, goal: Pose2<T>) -> (Direction, PolarCoords<T>) {
        let dir = self.current.unwrap_or(Direction::Forward);
        let c = PolarCoords::new(pose, goal, dir);
        let switch = self.allow_reverse
            && match self.current {
                // First tick: decide from the sign of cos(alpha), I1 = (-pi/2, pi/2].
                None => !c.goal_ahead(),
                Some(_) => c.alpha.abs() > T::FRAC_PI_2() + self.hysteresis,
            };
        let (dir, c) = if switch { (dir.flipped(), PolarCoords::new(pose, goal, dir.flipped())) } else { (dir, c) };
        self.current = Some(dir);
        (dir, c)
    }

    /// Forgets the direction: the next tick decides afresh.
    pub fn reset(&mut self) {
        self.current = None;
    }
}

/// The errors every polar-coordinate law logs: dl = rho; e_theta = wrap(theta_d - theta);
/// e_s = (x_d - x) cos(theta) + (y_d - y) sin(theta), the signed distance to the goal
/// along the heading.
#[inline]
pub fn polar_errors<T: Real>(pose: Pose2<T>, goal: Pose2<T>) -> ControlErrors<T> {
    let dx = goal.x - pose.x;
    let dy = goal.y - pose.y;
    let (s, c) = pose.theta.sin_cos_libm();
    ControlErrors { e_s: dx * c + dy * s, e_theta: wrap_angle(goal.theta - pose.theta), dl: dx.hypot_libm(dy) }
}

/// Stop inside `radius`, resume beyond twice that: returns the new "held" flag.
#[inline]
fn goal_hold<T: Real>(held: bool, dl: T, radius: T) -> bool {
    if held { dl <= radius + radius } else { dl <= radius }
}

/// The keys every law in polar coordinates has: how it picks its direction and where it stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Steering<T> {
    /// Drive backwards when the goal is behind (`reverse`).
    pub reverse: bool,
    /// Overshoot of |alpha| past pi/2, rad, before a later direction switch (`reverse_hysteresis`).
    pub reverse_hysteresis: T,
    /// Within this distance of the goal, m, the law stops (`goal_radius`).
    pub goal_radius: T,
}

/// What distinguishes one law in polar coordinates from another: its gains and its twist.
pub trait PolarGains<T: Real>: Copy {
    /// Checks the law's own gains; errors name the key and the violated condition.
    fn check_gains(&self) -> Result<(), ParamError>;
    /// The keys it shares with every polar law.
    fn steering(&self) -> Steering<T>;
    /// The twist (v in m/s, omega in rad/s) for the goal at `c` in driving direction `dir`.
    fn twist(&self, dir: Direction, c: &PolarCoords<T>) -> Twist2<T>;
}

/// A law in polar coordinates with gains `G`: stops within `goal_radius` of the goal
/// (resuming beyond twice that), chooses the driving direction ([`DirectionSelector`]),
/// logs [`polar_errors`]. Implements [`Law`] with [`WheelDemand::Twist`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolarCoordinateLaw<T, G> {
    gains: G,
    direction: DirectionSelector<T>,
    held: bool,
}

impl<T: Real, G: PolarGains<T>> PolarCoordinateLaw<T, G> {
    /// Validates the gains and the shared keys (`reverse_hysteresis` in [0, pi/2),
    /// `goal_radius` >= 0).
    pub fn new(gains: G) -> Result<Self, ParamError> {
        gains.check_gains()?;
        let st = gains.steering();
        check::non_negative("reverse_hysteresis", st.reverse_hysteresis)?;
        if st.reverse_hysteresis >= T::FRAC_PI_2() {
            return Err(check::out_of_range("reverse_hysteresis", "must be < pi/2", st.reverse_hysteresis));
        }
        check::non_negative("goal_radius", st.goal_radius)?;
        let direction = DirectionSelector::new(st.reverse, st.reverse_hysteresis);
        Ok(Self { gains, direction, held: false })
    }

    /// The parameters.
    pub fn params(&self) -> &G {
        &self.gains
    }

    /// The driving direction in use (None before the first tick).
    pub fn direction(&self) -> Option<Direction> {
        self.direction.current()
    }

    /// The twist (v in m/s, omega in rad/s) for the measured `pose` and the `goal`.
    pub fn twist(&mut self, pose: Pose2<T>, goal: Pose2<T>) -> Twist2<T> {
        self.twist_at(pose, goal, (goal.x - pose.x).hypot_libm(goal.y - pose.y))
    }

    /// [`PolarCoordinateLaw::twist`] with the distance `dl` (m) from `pose` to `goal` known.
    #[inline]
    fn twist_at(&mut self, pose: Pose2<T>, goal: Pose2<T>, dl: T) -> Twist2<T> {
        self.held = goal_hold(self.held, dl, self.gains.steering().goal_radius);
        if self.held {
            return Twist2::default();
        }
        let (dir, c) = self.direction.select(pose, goal);
        self.gains.twist(dir, &c)
    }
}

impl<T: Real, G: PolarGains<T>> Law<T> for PolarCoordinateLaw<T, G> {
    #[inline]
    fn update(&mut self, _t: T, m: &Measurement<T>, goal: Pose2<T>) -> LawOutput<T> {
        let errors = polar_errors(m.pose, goal);
        let twist = self.twist_at(m.pose, goal, errors.dl);
        LawOutput { demand: WheelDemand::Twist(twist), errors }
    }

    fn reset(&mut self) {
        self.direction.reset();
        self.held = false;
    }

    fn holding(&self) -> bool {
        self.held
    }
}
