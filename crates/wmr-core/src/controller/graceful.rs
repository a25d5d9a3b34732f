//! Park and Kuipers' smooth control law for graceful motion, as nav2's docking server
//! (`opennav_docking`) drives a robot into its dock with it: a curvature from egocentric
//! polar coordinates, a speed that drops with the curvature, forward or backwards.
//!
//! Source: J. J. Park, B. Kuipers, "A smooth control law for graceful motion of
//! differential wheeled mobile robots in 2D environment", Proc. IEEE ICRA 2011,
//! pp. 4896-4902; in the form of nav2's `nav2_graceful_controller` (`SmoothControlLaw`,
//! `smooth_control_law.cpp`; `EgocentricPolarCoordinates`, `ego_polar_coords.hpp`) as
//! `opennav_docking` calls it (`controller.cpp`, `docking_server.cpp`, `approachDock`),
//! read at ros-navigation/navigation2 a3a97043e (2026). The keys are nav2's, with the
//! docking server's defaults (`controller.k_phi` ... `controller.deceleration_max`).
//!
//! # The target
//!
//! The goal (x_d, y_d, theta_d) is the robot's pose when docked: theta_d its heading then.
//! The robot ends its approach driving along theta_d (forward) or along theta_d + pi
//! (`dock_backwards`, s = -1; s = +1 forward). The law aims at a target p =
//! `target_projection` past the goal along that final direction of motion:
//!
//! ```text
//! x_t = x_d + s p cos(theta_d),  y_t = y_d + s p sin(theta_d)      m
//! ```
//!
//! nav2's docking server projects its target 0.25 m past the dock (its
//! `backward_projection`: "the control law can get jittery when close to the end when
//! atan2's can explode") and ends the approach when the dock reports contact, whatever
//! the robot's lateral offset then. wmr has no dock to touch: the law stops at the goal
//! itself (below), and a robot that passes the goal wider than `goal_radius` goes on to
//! the target and circles it (v never drops below `v_linear_min`). With the default,
//! p = 0, the law aims at the goal: near it the yaw rate bound sets the speed,
//! v = v_angular_max / |kappa|, which falls with r, and the robot creeps into the goal
//! (`crates/wmr-core/tests/graceful.rs` docks from 32 starts around it, forwards and
//! backwards). `target_projection = 0.25` is nav2's target, for comparing with it.
//!
//! The target in the robot's frame (nav2 transforms it into `base_link`), with (x, y,
//! theta) the measured pose:
//!
//! ```text
//! dX =  cos(theta) (x_t - x) + sin(theta) (y_t - y)      m
//! dY = -sin(theta) (x_t - x) + cos(theta) (y_t - y)      m
//! ```
//!
//! # Egocentric polar coordinates (nav2 `EgocentricPolarCoordinates`, robot at the origin)
//!
//! ```text
//! los   = atan2(-dY, dX)   (+ pi when backwards)     rad
//! r     = sqrt(dX^2 + dY^2)                          m, distance to the target
//! phi   = wrap(theta_d - theta + los)                rad, target heading relative to the line of sight
//! delta = wrap(los)                                  rad, robot heading relative to the line of sight
//! ```
//!
//! (Backwards, nav2's dock pose faces away from the robot's docked heading and the docking
//! server turns it by pi before the call, so nav2's coordinates see theta_d, as here, with
//! the line of sight turned: delta is then the heading of the robot's rear.) With the bearing
//! b = atan2(dY, dX) of the target, delta = -b and phi = (theta_d - theta) - b, and the
//! unicycle x' = v cos(theta), y' = v sin(theta), theta' = omega gives Park and Kuipers'
//! kinematics in these coordinates:
//!
//! ```text
//! r'     = -v cos(delta)
//! phi'   =  v sin(delta) / r
//! delta' =  v sin(delta) / r + omega
//! ```
//!
//! # The law (nav2 `calculateCurvature`, `calculateRegularVelocity`)
//!
//! Slow subsystem: if the heading could be set at will, delta = arctan(-k_phi phi) would
//! give phi' = -v k_phi phi / (r sqrt(1 + k_phi^2 phi^2)) and
//! r' = -v / sqrt(1 + k_phi^2 phi^2), so d(ln phi) / d(ln r) = k_phi: phi = phi_0
//! (r / r_0)^k_phi, and the target heading is reached with the target position. Fast
//! subsystem: z = delta - arctan(-k_phi phi) is driven down with z' = -k_delta (v / r) z,
//! which, with the kinematics above, is
//!
//! ```text
//! omega = kappa v,
//! kappa = -(1 / r) [ k_delta (delta - arctan(-k_phi phi)) + (1 + k_phi / (1 + (k_phi phi)^2)) sin(delta) ]   1/m
//! ```
//!
//! (kappa is negated when backwards, since the rear leads). The speed falls with the
//! curvature and near the target, and is bounded:
//!
//! ```text
//! v = v_linear_max / (1 + beta |kappa|^lambda)
//! v = min(v, v_linear_max r / slowdown_radius)
//! v = min(v, sqrt(2 r deceleration_max))
//! v = clamp(v, v_linear_min, v_linear_max),  v = s v
//! omega = clamp(kappa v, -v_angular_max, v_angular_max),  v = omega / kappa (kappa != 0)
//! ```
//!
//! so the robot stays on the curvature the law chose even when the yaw rate is bounded.
//! nav2 holds r, phi and delta in `float`; here they are computed at the loop's
//! precision (f32 or f64). arctan(x) is taken as atan2(x, 1) (the same number in `libm`).
//!
//! # Stopping
//!
//! v never drops below `v_linear_min` while the yaw rate is free, so the law alone never
//! comes to rest: nav2's docking server stops the robot when the dock reports contact.
//! Here the law stops (v = omega = 0, the wheels hold
//! their angles) once C is within `goal_radius` of the goal, and resumes when pushed out
//! to twice that distance (the hold of the polar laws, [`super::polar_frame`]). At r = 0
//! (C exactly on the target, possible only with `target_projection = 0`, where nav2
//! would divide by zero) the twist is zero.
//!
//! The twist goes to the wheels through the wheel stage ([`super::WheelStage`]).
//!
//! Logged errors ([`super::ControlErrors`]), as the polar laws': dl the distance from C to
//! the goal (not the target), e_theta = wrap(theta_d - theta), e_s = (x_d - x) cos(theta) +
//! (y_d - y) sin(theta).

use super::law::{Law, LawOutput, WheelDemand};
use super::polar_frame::{goal_hold, polar_errors};
use crate::error::{ParamError, check};
use crate::lane::{Lane, Mask};
use crate::math::{Pose2, Twist2, wrap_angle};
use crate::reference::ReferenceState;
use crate::sensor::Measurement;
use crate::{Real, RobotParams};

crate::params! {
    words;
    /// `[controller] kind = "graceful"` parameters (nav2 `opennav_docking` `controller.*`).
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    #[repr(C)]
    pub struct GracefulParams<T> {
        /// k_phi: how much faster the target heading error falls than the distance (phi ~ r^k_phi).
        pub k_phi: T [unit = "", rule = ">= 0"],
        /// k_delta: gain of the heading (delta) error feedback.
        pub k_delta: T [unit = "", rule = "> 0"],
        /// beta: how fast the speed drops with the curvature, v_max / (1 + beta |kappa|^lambda).
        pub beta: T [unit = "m^lambda", rule = ">= 0"],
        /// lambda: the exponent of the curvature in the speed rule (higher: sharper curves).
        pub lambda: T [unit = "", rule = ">= 1"],
        /// Lowest forward speed while the yaw rate is within its bound.
        pub v_linear_min: T [unit = "m/s", rule = ">= 0, <= v_linear_max"],
        /// Highest forward speed.
        pub v_linear_max: T [unit = "m/s", rule = "> 0"],
        /// Yaw rate bound; the speed follows it, keeping the curvature.
        pub v_angular_max: T [unit = "rad/s", rule = "> 0"],
        /// Within this distance of the target the speed falls in proportion to it.
        pub slowdown_radius: T [unit = "m", rule = "> 0"],
        /// The speed stays below sqrt(2 r deceleration_max) at distance r from the target.
        pub deceleration_max: T [unit = "m/s^2", rule = "> 0, inf allowed"],
        /// Reach the goal driving backwards (rear first; nav2's dock_backwards).
        pub dock_backwards: bool [unit = "", rule = "true or false"],
        /// The law aims this far past the goal along the final motion (nav2's docking: 0.25).
        pub target_projection: T [unit = "m", rule = ">= 0"],
        /// Within this distance of the goal the law stops; it resumes beyond twice that.
        pub goal_radius: T [unit = "m", rule = ">= 0"],
    }
}

impl<T: Real> Default for GracefulParams<T> {
    /// nav2 `opennav_docking`'s defaults: k_phi = 3, k_delta = 2, beta = 0.4, lambda = 2,
    /// v_linear_min = 0.1 m/s, v_linear_max = 0.25 m/s, v_angular_max = 0.75 rad/s,
    /// slowdown_radius = 0.25 m, deceleration_max = 2.5 m/s^2, forward; wmr's
    /// target_projection = 0 (aim at the goal; nav2's docking server: 0.25 m and a stop
    /// on the dock's contact) and goal_radius = 1 mm (the polar laws').
    fn default() -> Self {
        Self {
            k_phi: T::lit(3.0),
            k_delta: T::lit(2.0),
            beta: T::lit(0.4),
            lambda: T::lit(2.0),
            v_linear_min: T::lit(0.1),
            v_linear_max: T::lit(0.25),
            v_angular_max: T::lit(0.75),
            slowdown_radius: T::lit(0.25),
            deceleration_max: T::lit(2.5),
            dock_backwards: false,
            target_projection: T::zero(),
            goal_radius: T::lit(1e-3),
        }
    }
}

impl<T: Real> super::law::LawSpec<T> for GracefulParams<T> {
    type Law<L: Lane<Scalar = T>> = GracefulLaw<L>;

    fn build<L: Lane<Scalar = T>>(
        &self,
        _model: &RobotParams<T>,
        _control_dt: T,
    ) -> Result<GracefulLaw<L>, ParamError> {
        GracefulLaw::for_lanes(*self)
    }
}

impl<T: Real> GracefulParams<T> {
    /// Checks every key; errors name it.
    pub fn validate(&self) -> Result<Self, ParamError> {
        check::non_negative("k_phi", self.k_phi)?;
        check::positive("k_delta", self.k_delta)?;
        check::non_negative("beta", self.beta)?;
        let lambda = check::finite("lambda", self.lambda)?;
        if lambda < T::one() {
            return Err(check::out_of_range("lambda", "must be >= 1", lambda));
        }
        let v_max = check::positive("v_linear_max", self.v_linear_max)?;
        let v_min = check::non_negative("v_linear_min", self.v_linear_min)?;
        if v_min > v_max {
            return Err(check::out_of_range("v_linear_min", "must be <= v_linear_max", v_min));
        }
        check::positive("v_angular_max", self.v_angular_max)?;
        check::positive("slowdown_radius", self.slowdown_radius)?;
        check::positive_or_inf("deceleration_max", self.deceleration_max)?;
        check::non_negative("target_projection", self.target_projection)?;
        check::non_negative("goal_radius", self.goal_radius)?;
        Ok(*self)
    }

    /// The law's twist (v m/s, omega rad/s) for the measured `pose` and the `goal`, both
    /// in the world frame (module docs: the target, the egocentric coordinates, the
    /// curvature, the speed rule), without the stop at the goal.
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub fn twist<L: Lane<Scalar = T>>(&self, pose: Pose2<L>, goal: Pose2<L>) -> Twist2<L> {
        let backward = self.dock_backwards;
        // The target: the goal moved on by target_projection along the final motion.
        let p = L::splat(if backward { -self.target_projection } else { self.target_projection });
        let (sd, cd) = goal.theta.sin_cos();
        let (xt, yt) = (goal.x + p * cd, goal.y + p * sd);
        // In the robot's frame.
        let (dx, dy) = pose.body_offset(xt, yt);
        // Egocentric polar coordinates; the line of sight turned by pi when backwards.
        let los = (-dy).atan2(dx);
        let los = if backward { los + L::lit(core::f64::consts::PI) } else { los };
        let r = (dx * dx + dy * dy).sqrt();
        let phi = wrap_angle(goal.theta - pose.theta + los);
        let delta = wrap_angle(los);
        // The curvature (1/m).
        let k_phi = L::splat(self.k_phi);
        let one = L::lit(1.0);
        let prop = L::splat(self.k_delta) * (delta - (-k_phi * phi).atan2(one));
        let kp = k_phi * phi;
        let feedback = (one + k_phi / (one + kp * kp)) * delta.sin_cos().0;
        let kappa = -(one / r) * (prop + feedback);
        let kappa = if backward { -kappa } else { kappa };
        // The speed rule.
        let v_max = L::splat(self.v_linear_max);
        let v = v_max / (one + L::splat(self.beta) * kappa.abs().powf(L::splat(self.lambda)));
        let v = (v_max * (r / L::splat(self.slowdown_radius))).min(v);
        let v = (L::lit(2.0) * r * L::splat(self.deceleration_max)).sqrt().min(v);
        let v = v.max(L::splat(self.v_linear_min)).min(v_max);
        let v = if backward { -v } else { v };
        // The yaw rate bound, the curvature kept.
        let w_max = L::splat(self.v_angular_max);
        let omega = (kappa * v).max(-w_max).min(w_max);
        let v = L::select(kappa.eq(L::default()), v, omega / kappa);
        // On the target itself (r = 0) the curvature is undefined: stand still.
        let on_target = r.eq(L::default());
        let zero = L::default();
        Twist2 { v: L::select(on_target, zero, v), omega: L::select(on_target, zero, omega) }
    }
}

/// Park and Kuipers' graceful law. Implements [`Law`] with [`WheelDemand::Twist`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GracefulLaw<T: Lane> {
    params: GracefulParams<T::Scalar>,
    /// Inside the goal hold (per lane).
    held: T::Mask,
}

impl<T: Lane> GracefulLaw<T> {
    /// Checks the keys (errors name the key) and builds the law.
    pub fn for_lanes(p: GracefulParams<T::Scalar>) -> Result<Self, ParamError> {
        Ok(Self { params: p.validate()?, held: T::Mask::splat(false) })
    }

    /// The keys.
    pub fn params(&self) -> &GracefulParams<T::Scalar> {
        &self.params
    }
}

impl<T: Lane> Law<T> for GracefulLaw<T> {
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    fn update(&mut self, _t: T, m: &Measurement<T>, r: &ReferenceState<T>) -> LawOutput<T> {
        let errors = polar_errors(m.pose, r.pose);
        let held = goal_hold::<T>(self.held, errors.dl, self.params.goal_radius);
        self.held = held;
        if held.all() {
            return LawOutput { demand: WheelDemand::Twist(Twist2::default()), errors };
        }
        let twist = self.params.twist(m.pose, r.pose);
        let zero = T::default();
        let twist = Twist2 { v: T::select(held, zero, twist.v), omega: T::select(held, zero, twist.omega) };
        LawOutput { demand: WheelDemand::Twist(twist), errors }
    }

    /// The law brings the heading to the goal's with the position (phi ~ r^k_phi).
    fn reaches_heading(&self) -> bool {
        true
    }

    fn reset_lanes(&mut self, lanes: T::Mask) {
        self.held = self.held & !lanes;
    }

    fn holding(&self) -> T::Mask {
        self.held
    }
}
