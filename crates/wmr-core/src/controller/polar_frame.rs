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
use crate::lane::{Lane, Mask};
use crate::math::{Pose2, Twist2, wrap_angle};
use crate::reference::ReferenceState;
use crate::sensor::Measurement;
use num_traits::FloatConst;

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

impl<T: Lane> PolarCoords<T> {
    /// Polar coordinates of `goal` seen from `pose` (both in the world frame) in driving
    /// direction `dir`. At rho = 0 the direction phi is taken as atan2(0, 0) = 0.
    #[inline]
    pub fn new(pose: Pose2<T>, goal: Pose2<T>, dir: Direction) -> Self {
        let (phi, rho) = Self::bearing(pose, goal);
        Self::in_frame(phi, rho, pose, goal, T::Mask::splat(dir == Direction::Backward))
    }

    /// phi = atan2(y_d - y, x_d - x) (rad) and rho = hypot(..) (m): the parts that do not
    /// depend on the direction.
    #[inline(always)]
    fn bearing(pose: Pose2<T>, goal: Pose2<T>) -> (T, T) {
        let dx = goal.x - pose.x;
        let dy = goal.y - pose.y;
        (dy.atan2(dx), dx.hypot(dy))
    }

    /// The coordinates from phi and rho, per lane in the backward frame where `backward`.
    #[inline(always)]
    fn in_frame(phi: T, rho: T, pose: Pose2<T>, goal: Pose2<T>, backward: T::Mask) -> Self {
        let pi = T::lit(core::f64::consts::PI);
        let theta = T::select(backward, pose.theta + pi, pose.theta);
        let theta_d = T::select(backward, goal.theta + pi, goal.theta);
        Self { rho, alpha: wrap_angle(phi - theta), beta: wrap_angle(theta_d - phi) }
    }

    /// True for alpha in I1 = (-pi/2, pi/2]: the goal is ahead in this frame.
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub fn goal_ahead(&self) -> T::Mask {
        let half_pi = T::lit(core::f64::consts::FRAC_PI_2);
        (-half_pi).lt(self.alpha) & self.alpha.le(half_pi)
    }

    /// Per lane `a` where `m`, else `b`.
    #[inline(always)]
    fn select(m: T::Mask, a: Self, b: Self) -> Self {
        Self {
            rho: T::select(m, a.rho, b.rho),
            alpha: T::select(m, a.alpha, b.alpha),
            beta: T::select(m, a.beta, b.beta),
        }
    }
}

/// Chooses the driving direction once and switches it only with hysteresis (module docs);
/// per lane for several runs side by side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionSelector<T: Lane> {
    allow_reverse: bool,
    hysteresis: T::Scalar,
    /// The direction in use is backward, where `decided`.
    backward: T::Mask,
    decided: T::Mask,
}

impl<T: Lane> DirectionSelector<T> {
    /// A selector; `allow_reverse = false` always drives forward. `hysteresis` (rad, >= 0)
    /// is the overshoot of |alpha| past pi/2 that triggers a later switch.
    pub fn new(allow_reverse: bool, hysteresis: T::Scalar) -> Self {
        let no = T::Mask::splat(false);
        Self { allow_reverse, hysteresis, backward: no, decided: no }
    }

    /// The direction for this tick (per lane: backward or not) and the polar coordinates
    /// in its frame.
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub fn select(&mut self, pose: Pose2<T>, goal: Pose2<T>) -> (T::Mask, PolarCoords<T>) {
        let (phi, rho) = PolarCoords::bearing(pose, goal);
        let c = PolarCoords::in_frame(phi, rho, pose, goal, self.backward);
        let switch = if self.allow_reverse {
            // First tick: decide from the sign of cos(alpha), I1 = (-pi/2, pi/2].
            let limit = T::splat(<T::Scalar as FloatConst>::FRAC_PI_2() + self.hysteresis);
            (!self.decided & !c.goal_ahead()) | (self.decided & limit.lt(c.alpha.abs()))
        } else {
            T::Mask::splat(false)
        };
        self.decided = T::Mask::splat(true);
        if !switch.any() {
            return (self.backward, c);
        }
        let flipped = (self.backward & !switch) | (!self.backward & switch);
        let c = PolarCoords::select(switch, PolarCoords::in_frame(phi, rho, pose, goal, flipped), c);
        self.backward = flipped;
        (flipped, c)
    }

    /// Forgets the direction: the next tick decides afresh.
    pub fn reset(&mut self) {
        self.reset_lanes(T::Mask::splat(true));
    }

    /// [`DirectionSelector::reset`] of the runs in `lanes` only.
    pub fn reset_lanes(&mut self, lanes: T::Mask) {
        self.backward = self.backward & !lanes;
        self.decided = self.decided & !lanes;
    }
}

impl<T: Real> DirectionSelector<T> {
    /// The direction in use, if one has been chosen since construction or reset.
    pub fn current(&self) -> Option<Direction> {
        let dir = if self.backward { Direction::Backward } else { Direction::Forward };
        self.decided.then_some(dir)
    }
}

/// The errors every polar-coordinate law logs: dl = rho; e_theta = wrap(theta_d - theta);
/// e_s = (x_d - x) cos(theta) + (y_d - y) sin(theta), the signed distance to the goal
/// along the heading.
#[cfg_attr(target_os = "none", inline)]
#[cfg_attr(not(target_os = "none"), inline(always))]
pub fn polar_errors<T: Lane>(pose: Pose2<T>, goal: Pose2<T>) -> ControlErrors<T> {
    let (e_s, _) = pose.body_offset(goal.x, goal.y);
    ControlErrors { e_s, e_theta: wrap_angle(goal.theta - pose.theta), dl: (goal.x - pose.x).hypot(goal.y - pose.y) }
}

/// Stop inside `radius`, resume beyond twice that: returns the new "held" flag.
#[cfg_attr(target_os = "none", inline)]
#[cfg_attr(not(target_os = "none"), inline(always))]
pub(crate) fn goal_hold<T: Lane>(held: T::Mask, dl: T, radius: T::Scalar) -> T::Mask {
    (held & dl.le(T::splat(radius + radius))) | (!held & dl.le(T::splat(radius)))
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
    /// The twist (v in m/s, omega in rad/s) for the goal at `c` in the driving direction
    /// whose `sign` is +1 (forward) or -1 (backward), per lane for several runs.
    fn twist<L: Lane<Scalar = T>>(&self, sign: L, c: &PolarCoords<L>) -> Twist2<L>;
    /// [`Law::reaches_heading`] for the law.
    const REACHES_HEADING: bool;
}

/// A law in polar coordinates with gains `G`: stops within `goal_radius` of the goal
/// (resuming beyond twice that), chooses the driving direction ([`DirectionSelector`]),
/// logs [`polar_errors`]. Implements [`Law`] with [`WheelDemand::Twist`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolarCoordinateLaw<T: Lane, G> {
    gains: G,
    direction: DirectionSelector<T>,
    held: T::Mask,
}

impl<T: Real, G: PolarGains<T>> PolarCoordinateLaw<T, G> {
    /// Validates the gains and the shared keys (`reverse_hysteresis` in [0, pi/2),
    /// `goal_radius` >= 0).
    pub fn new(gains: G) -> Result<Self, ParamError> {
        Self::for_lanes(gains)
    }
}

impl<T: Lane, G: PolarGains<T::Scalar>> PolarCoordinateLaw<T, G> {
    /// [`PolarCoordinateLaw::new`] for several runs side by side ([`crate::lane`]).
    pub fn for_lanes(gains: G) -> Result<Self, ParamError> {
        gains.check_gains()?;
        let st = gains.steering();
        check::non_negative("reverse_hysteresis", st.reverse_hysteresis)?;
        if st.reverse_hysteresis >= <T::Scalar as FloatConst>::FRAC_PI_2() {
            return Err(check::out_of_range("reverse_hysteresis", "must be < pi/2", st.reverse_hysteresis));
        }
        check::non_negative("goal_radius", st.goal_radius)?;
        let direction = DirectionSelector::new(st.reverse, st.reverse_hysteresis);
        Ok(Self { gains, direction, held: T::Mask::splat(false) })
    }

    /// The parameters.
    pub fn params(&self) -> &G {
        &self.gains
    }

    /// The twist (v in m/s, omega in rad/s) for the measured `pose` and the `goal`.
    pub fn twist(&mut self, pose: Pose2<T>, goal: Pose2<T>) -> Twist2<T> {
        self.twist_at(pose, goal, (goal.x - pose.x).hypot(goal.y - pose.y))
    }

    /// [`PolarCoordinateLaw::twist`] with the distance `dl` (m) from `pose` to `goal` known.
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    fn twist_at(&mut self, pose: Pose2<T>, goal: Pose2<T>, dl: T) -> Twist2<T> {
        let held = goal_hold::<T>(self.held, dl, self.gains.steering().goal_radius);
        self.held = held;
        if held.all() {
            return Twist2::default();
        }
        // Lanes that hold keep their direction.
        let before = self.direction;
        let (backward, c) = self.direction.select(pose, goal);
        if held.any() {
            self.direction.backward = (held & before.backward) | (!held & self.direction.backward);
            self.direction.decided = (held & before.decided) | (!held & self.direction.decided);
        }
        let sign = T::select(backward, T::lit(-1.0), T::lit(1.0));
        let twist = self.gains.twist(sign, &c);
        let zero = T::default();
        Twist2 { v: T::select(held, zero, twist.v), omega: T::select(held, zero, twist.omega) }
    }
}

impl<T: Real, G: PolarGains<T>> PolarCoordinateLaw<T, G> {
    /// The driving direction in use (None before the first tick).
    pub fn direction(&self) -> Option<Direction> {
        self.direction.current()
    }
}

impl<T: Lane, G: PolarGains<T::Scalar>> Law<T> for PolarCoordinateLaw<T, G> {
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    fn update(&mut self, _t: T, m: &Measurement<T>, r: &ReferenceState<T>) -> LawOutput<T> {
        let errors = polar_errors(m.pose, r.pose);
        let twist = self.twist_at(m.pose, r.pose, errors.dl);
        LawOutput { demand: WheelDemand::Twist(twist), errors }
    }

    fn reaches_heading(&self) -> bool {
        G::REACHES_HEADING
    }

    fn reset_lanes(&mut self, lanes: T::Mask) {
        self.direction.reset_lanes(lanes);
        self.held = self.held & !lanes;
    }

    fn holding(&self) -> T::Mask {
        self.held
    }
}
