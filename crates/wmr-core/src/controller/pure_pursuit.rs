//! Regulated pure pursuit (path following): steer onto the arc through a point one
//! lookahead distance ahead on the path, at a speed lowered in tight turns and near the
//! path's end. Time is ignored: only the reference's geometric path counts.
//!
//! Source: R. C. Coulter, "Implementation of the pure pursuit path tracking algorithm",
//! CMU-RI-TR-92-01, 1992 (the arc of curvature 2 y_L / L^2); S. Macenski, S. Singh,
//! F. Martin, J. Gines, "Regulated pure pursuit for robot path tracking", Autonomous
//! Robots 47, 2023, and nav2's `nav2_regulated_pure_pursuit_controller` (Jazzy:
//! `regulated_pure_pursuit_controller.cpp`, `regulation_functions.hpp`,
//! `path_handler.cpp`, `parameter_handler.cpp`; the keys carry its parameter names and
//! defaults). Per tick, from the measured pose and the encoders' twist
//! v = r (w_r + w_l) / 2, omega = r (w_r - w_l) / (2 R):
//!
//! ```text
//! s_c   = the closest path point, searched from the path's beginning at the first tick
//!         and then forward of the last one, within max_robot_pose_search_dist m of path
//!         ([`crate::reference::PathCursor`]; nav2's path handler)
//! L     = lookahead_dist, or with use_velocity_scaled_lookahead_dist
//!         clamp(lookahead_time |v|, min_lookahead_dist, max_lookahead_dist)      m
//! P_L   = the first path point at distance L from C, searching forward from s_c
//!         (the path's end when none is that far)
//! kappa = 2 y_L / d^2 if d^2 > 0.001 m^2, else 0 (nav2's calculateCurvature: no steering
//!         onto a carrot within 3.2 cm),  (x_L, y_L) = P_L in the robot frame, d = |P_L - C|
//! if use_rotate_to_heading and |atan2(y_L, x_L)| > rotate_to_heading_min_angle:
//!       rotate in place towards the carrot (nav2's rotateToHeading):
//!       v = 0, omega = sgn(angle) rotate_to_heading_angular_vel, clamped to within
//!       max_angular_accel control_dt of the measured omega and to at most
//!       sqrt(2 max_angular_accel |angle|) (stops at the heading without overshoot)
//! else (nav2's applyConstraints):
//!       v_c = speed (r / regulated_linear_scaling_min_radius)  where the radius r = 1/|kappa|
//!             is below regulated_linear_scaling_min_radius, else speed;
//!       v_c = max(v_c, regulated_linear_scaling_min_speed)
//!       if remaining < approach_velocity_scaling_dist:
//!           v_c = min(v_c, max(v_c |P_end| / approach_velocity_scaling_dist,
//!                              min_approach_linear_velocity))
//!       v = clamp(v_c, 0, speed),  omega = v kappa
//! v = omega = 0 once within xy_goal_tolerance of the path's end (and remaining below
//! approach_velocity_scaling_dist)
//! ```
//!
//! `remaining` is the path length from s_c to the end (infinite on an endless path) and
//! |P_end| the straight distance from C to the path's end (nav2: the length of the
//! transformed plan, which starts at the closest pose, and the distance to its last pose).
//! Where wmr differs from nav2: the robot drives forward only (no `allow_reversing`);
//! at the end it stops within xy_goal_tolerance instead of rotating to the path's final
//! heading (nav2's goal checker and rotate-to-goal-heading are not modelled); there is no
//! costmap (no cost regulation, no collision check; the default search window is 1.5 m,
//! what nav2's default 3 m local costmap gives); the curvature is the lookahead point's
//! (no `use_fixed_curvature_lookahead`); no acceleration limits on v. Without a path (a
//! law update given only a reference state, [`Law::update`]) the law stops. The twist
//! goes to the wheels through the wheel stage as Kanayama's does.
//!
//! Logged errors: dl = the distance from C to the path (to the closest point), e_s = the
//! closest point's offset along the robot's heading, e_theta = wrap(theta_path - theta)
//! at the closest point.

use super::law::{ControlErrors, Law, LawOutput, WheelDemand};
use crate::error::{ParamError, check};
use crate::lane::Lane;
use crate::math::{Twist2, wrap_angle};
use crate::reference::path::{PathCursor, lookahead};
use crate::reference::{Path, ReferenceState};
use crate::sensor::Measurement;
use crate::{Real, RobotParams};

crate::params! {
    words;
    /// `[controller] kind = "pure_pursuit"` parameters (nav2's names where the meaning is the same).
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    #[repr(C)]
    pub struct PurePursuitParams<T> {
        /// speed: the forward speed on a straight path (nav2's desired_linear_vel).
        pub speed: T [unit = "m/s", rule = "> 0"],
        /// The fixed lookahead distance (when use_velocity_scaled_lookahead_dist is false).
        pub lookahead_dist: T [unit = "m", rule = "> 0"],
        /// The lookahead distance grows with the measured speed: lookahead_time |v| within min/max_lookahead_dist.
        pub use_velocity_scaled_lookahead_dist: bool [unit = "", rule = "true or false"],
        /// The lookahead distance per m/s of speed (with use_velocity_scaled_lookahead_dist).
        pub lookahead_time: T [unit = "s", rule = ">= 0"],
        /// The shortest velocity-scaled lookahead distance.
        pub min_lookahead_dist: T [unit = "m", rule = "> 0"],
        /// The longest velocity-scaled lookahead distance.
        pub max_lookahead_dist: T [unit = "m", rule = ">= min_lookahead_dist"],
        /// Below this turning radius the speed is scaled down in proportion.
        pub regulated_linear_scaling_min_radius: T [unit = "m", rule = ">= 0"],
        /// The curvature scaling never brings the speed below this.
        pub regulated_linear_scaling_min_speed: T [unit = "m/s", rule = ">= 0"],
        /// Within this path length of the end the speed is scaled by the straight distance to the end over this.
        pub approach_velocity_scaling_dist: T [unit = "m", rule = ">= 0"],
        /// The approach scaling never brings the speed below this.
        pub min_approach_linear_velocity: T [unit = "m/s", rule = ">= 0"],
        /// Rotate in place towards the lookahead point when it is more than rotate_to_heading_min_angle off the heading.
        pub use_rotate_to_heading: bool [unit = "", rule = "true or false"],
        /// The bearing of the lookahead point beyond which the robot rotates in place.
        pub rotate_to_heading_min_angle: T [unit = "rad", rule = ">= 0"],
        /// The yaw rate of a rotation in place.
        pub rotate_to_heading_angular_vel: T [unit = "rad/s", rule = "> 0"],
        /// The yaw acceleration a rotation in place keeps to (and stops with).
        pub max_angular_accel: T [unit = "rad/s^2", rule = "> 0"],
        /// Each closest-point search covers this much path forward of the last closest point (the first from the path's beginning).
        pub max_robot_pose_search_dist: T [unit = "m", rule = "> 0"],
        /// Within this distance of the path's end the law stops.
        pub xy_goal_tolerance: T [unit = "m", rule = "> 0"],
    }
}

impl<T: Real> Default for PurePursuitParams<T> {
    /// nav2's defaults (a fixed 0.6 m lookahead, or lookahead_time 1.5 s within 0.3 to
    /// 0.9 m; min radius 0.9 m, min speed 0.25 m/s; approach over 0.6 m down to 0.05 m/s;
    /// rotate in place beyond 0.785 rad at 1.8 rad/s, 3.2 rad/s^2; the search window
    /// 1.5 m, half nav2's default 3 m local costmap) with speed 0.3 m/s (the references'
    /// default speed) and a 1 cm goal tolerance (the tracking tolerance).
    fn default() -> Self {
        Self {
            speed: T::lit(0.3),
            lookahead_dist: T::lit(0.6),
            use_velocity_scaled_lookahead_dist: false,
            lookahead_time: T::lit(1.5),
            min_lookahead_dist: T::lit(0.3),
            max_lookahead_dist: T::lit(0.9),
            regulated_linear_scaling_min_radius: T::lit(0.9),
            regulated_linear_scaling_min_speed: T::lit(0.25),
            approach_velocity_scaling_dist: T::lit(0.6),
            min_approach_linear_velocity: T::lit(0.05),
            use_rotate_to_heading: true,
            rotate_to_heading_min_angle: T::lit(0.785),
            rotate_to_heading_angular_vel: T::lit(1.8),
            max_angular_accel: T::lit(3.2),
            max_robot_pose_search_dist: T::lit(1.5),
            xy_goal_tolerance: T::lit(0.01),
        }
    }
}

impl<T: Real> super::law::LawSpec<T> for PurePursuitParams<T> {
    type Law<L: Lane<Scalar = T>> = PurePursuitLaw<L>;

    /// Pure pursuit searches the reference's path at every control tick:
    /// `examples/tracking/compare-tracking.toml` (a third of its runs pure pursuit) took
    /// 81 s where 11 s were announced (2026-12-06, 2-core AMD EPYC, idle), its runs about
    /// 20 times the others' per step.
    fn update_cost(&self) -> f64 {
        20.0
    }

    fn build<L: Lane<Scalar = T>>(
        &self,
        model: &RobotParams<T>,
        control_dt: T,
    ) -> Result<PurePursuitLaw<L>, ParamError> {
        PurePursuitLaw::for_lanes(*self, model, control_dt)
    }
}

impl<T: Real> PurePursuitParams<T> {
    /// Checks the keys; errors name them.
    pub fn validate(&self) -> Result<Self, ParamError> {
        check::positive("speed", self.speed)?;
        check::positive("lookahead_dist", self.lookahead_dist)?;
        check::non_negative("lookahead_time", self.lookahead_time)?;
        let lo = check::positive("min_lookahead_dist", self.min_lookahead_dist)?;
        let hi = check::positive("max_lookahead_dist", self.max_lookahead_dist)?;
        if hi < lo {
            return Err(check::out_of_range("max_lookahead_dist", "must be >= min_lookahead_dist", hi));
        }
        check::non_negative("regulated_linear_scaling_min_radius", self.regulated_linear_scaling_min_radius)?;
        check::non_negative("regulated_linear_scaling_min_speed", self.regulated_linear_scaling_min_speed)?;
        check::non_negative("approach_velocity_scaling_dist", self.approach_velocity_scaling_dist)?;
        check::non_negative("min_approach_linear_velocity", self.min_approach_linear_velocity)?;
        check::non_negative("rotate_to_heading_min_angle", self.rotate_to_heading_min_angle)?;
        check::positive("rotate_to_heading_angular_vel", self.rotate_to_heading_angular_vel)?;
        check::positive("max_angular_accel", self.max_angular_accel)?;
        check::positive("max_robot_pose_search_dist", self.max_robot_pose_search_dist)?;
        check::positive("xy_goal_tolerance", self.xy_goal_tolerance)?;
        Ok(*self)
    }

    /// The longest lookahead distance the law can use, m.
    fn lookahead_max(&self) -> T {
        if self.use_velocity_scaled_lookahead_dist { self.max_lookahead_dist } else { self.lookahead_dist }
    }

    /// The shorter of the two lookahead minima, m: what the search step is cut from (the
    /// same step, 6 cm by default, whichever lookahead is in use).
    fn lookahead_min(&self) -> T {
        if self.min_lookahead_dist < self.lookahead_dist { self.min_lookahead_dist } else { self.lookahead_dist }
    }
}

/// nav2's calculateCurvature: no curvature towards a carrot closer than this squared
/// distance, m^2 (0.001 m^2: within 3.16 cm of C).
pub const SMALL_CARROT_DIST2_M2: f64 = 0.001;

/// Regulated pure pursuit. Implements [`Law`] with [`WheelDemand::Twist`]; follows the
/// path given to [`Law::update_on_path`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PurePursuitLaw<T: Lane> {
    params: PurePursuitParams<T::Scalar>,
    /// Wheel radius of the controller's model, m.
    wheel_radius: T::Scalar,
    /// Half the track of the controller's model, m.
    half_track: T::Scalar,
    /// The control period, s (the acceleration limit of a rotation in place).
    control_dt: T::Scalar,
    cursor: PathCursor<T>,
}

impl<T: Lane> PurePursuitLaw<T> {
    /// Checks the keys (errors name them) and builds the law for the controller's model
    /// and control period `control_dt` (s).
    pub fn for_lanes(
        p: PurePursuitParams<T::Scalar>,
        model: &RobotParams<T::Scalar>,
        control_dt: T::Scalar,
    ) -> Result<Self, ParamError> {
        Ok(Self {
            params: p.validate()?,
            wheel_radius: model.wheel_radius,
            half_track: model.half_track,
            control_dt,
            cursor: PathCursor::default(),
        })
    }

    /// The keys.
    pub fn params(&self) -> &PurePursuitParams<T::Scalar> {
        &self.params
    }

    /// The parameter of the path point the law last found closest (see [`Path`]).
    pub fn cursor(&self) -> T {
        self.cursor.s
    }
}

/// The distance step of the path searches: a fifth of the shortest lookahead, m.
pub(crate) fn search_step<S: Real>(shortest_lookahead_m: S) -> S {
    shortest_lookahead_m * S::lit(0.2)
}

impl<T: Lane> Law<T> for PurePursuitLaw<T> {
    /// Without a path there is nothing to follow: a zero twist. `ClosedLoop` gives the
    /// reference's path when it has one ([`Law::update_on_path`]), a scenario refuses
    /// the law on a goal at rest, the lanes, which carry no path, refuse it
    /// ([`Law::needs_path`]), Python passes each run's path, and the C API refuses
    /// `_update` and `_update_reference` of a path-following law.
    fn update(&mut self, _t: T, _m: &Measurement<T>, _r: &ReferenceState<T>) -> LawOutput<T> {
        LawOutput { demand: WheelDemand::Twist(Twist2::default()), errors: ControlErrors::default() }
    }

    fn needs_path(&self) -> bool {
        true
    }

    fn update_on_path(
        &mut self,
        _t: T,
        m: &Measurement<T>,
        _r: &ReferenceState<T>,
        path: &dyn Path<T>,
    ) -> LawOutput<T> {
        let p = &self.params;
        let ds = search_step(p.lookahead_min());
        let (x, y) = (m.pose.x, m.pose.y);
        let s_c = self.cursor.advance(path, x, y, p.max_robot_pose_search_dist, ds);
        let closest = path.pose_on_path(s_c);
        let (ex, ey) = m.pose.body_offset(closest.x, closest.y);
        let errors = ControlErrors { e_s: ex, e_theta: wrap_angle(closest.theta - m.pose.theta), dl: ex.hypot(ey) };

        let r = T::splat(self.wheel_radius);
        let (wr, wl) = (m.wheel_speeds.right, m.wheel_speeds.left);
        let v_meas = r * (wr + wl) * T::lit(0.5);
        let l = if p.use_velocity_scaled_lookahead_dist {
            (T::splat(p.lookahead_time) * v_meas.abs())
                .max(T::splat(p.min_lookahead_dist))
                .min(T::splat(p.max_lookahead_dist))
        } else {
            T::splat(p.lookahead_dist)
        };
        let s_l = lookahead(path, x, y, s_c, l, ds, p.lookahead_max() * <T::Scalar as Real>::lit(2.0));
        let carrot = path.pose_on_path(s_l);
        let (x_l, y_l) = m.pose.body_offset(carrot.x, carrot.y);
        let d2 = x_l * x_l + y_l * y_l;
        let zero = T::default();
        let kappa = T::select(T::lit(SMALL_CARROT_DIST2_M2).lt(d2), T::lit(2.0) * y_l / d2, zero);

        // nav2's curvatureConstraint: v (r / r_min) where the radius r = 1/|kappa| < r_min,
        // then at least regulated_linear_scaling_min_speed.
        let speed = T::splat(p.speed);
        let r_min = T::splat(p.regulated_linear_scaling_min_radius);
        let k_abs = kappa.abs();
        let tight = T::lit(1.0).lt(k_abs * r_min);
        let mut v =
            T::select(tight, speed / (k_abs * r_min), speed).max(T::splat(p.regulated_linear_scaling_min_speed));
        // nav2's approachVelocityConstraint: within approach_velocity_scaling_dist of path
        // left, v scaled by the straight distance to the end over that distance.
        let remaining = path.remaining_length(s_c);
        let approach = T::splat(p.approach_velocity_scaling_dist);
        let near = remaining.lt(approach);
        let end = path.end().map(|e| path.pose_on_path(T::splat(e)));
        if let Some(last) = end {
            let (dxe, dye) = (last.x - x, last.y - y);
            let to_end = dxe.hypot(dye);
            let slow = (v * to_end / approach).max(T::splat(p.min_approach_linear_velocity));
            v = T::select(near, v.min(slow), v);
        }
        // nav2: clamp(|v|, 0, desired_linear_vel).
        v = v.min(speed);
        let mut omega = v * kappa;

        if p.use_rotate_to_heading {
            // nav2's shouldRotateToPath and rotateToHeading.
            let angle = y_l.atan2(x_l);
            let rotate = T::splat(p.rotate_to_heading_min_angle).lt(angle.abs());
            let sign = T::select(zero.lt(angle), T::lit(1.0), T::lit(-1.0));
            let omega_meas = r * (wr - wl) / (T::lit(2.0) * T::splat(self.half_track));
            let dw = T::splat(p.max_angular_accel * self.control_dt);
            let turn = (sign * T::splat(p.rotate_to_heading_angular_vel)).max(omega_meas - dw).min(omega_meas + dw);
            let to_stop = (T::lit(2.0) * T::splat(p.max_angular_accel) * angle.abs()).sqrt();
            let turn = T::select(to_stop.lt(turn.abs()), sign * to_stop, turn);
            v = T::select(rotate, zero, v);
            omega = T::select(rotate, turn, omega);
        }
        // Stop at the end.
        if let Some(last) = end {
            let (dxe, dye) = (last.x - x, last.y - y);
            let tol = T::splat(p.xy_goal_tolerance);
            let arrived = (dxe * dxe + dye * dye).lt(tol * tol) & near;
            v = T::select(arrived, zero, v);
            omega = T::select(arrived, zero, omega);
        }
        LawOutput { demand: WheelDemand::Twist(Twist2 { v, omega }), errors }
    }

    fn reset_lanes(&mut self, lanes: T::Mask) {
        self.cursor.reset_lanes(lanes);
    }
}
