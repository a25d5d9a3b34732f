//! Regulated pure pursuit (path following): steer onto the arc through a point one
//! lookahead distance ahead on the path, at a speed lowered in tight turns and near the
//! path's end. Time is ignored: only the reference's geometric path counts.
//!
//! Source: R. C. Coulter, "Implementation of the pure pursuit path tracking algorithm",
//! CMU-RI-TR-92-01, 1992 (the arc of curvature 2 y_L / L^2); S. Macenski, S. Singh,
//! F. Martin, J. Gines, "Regulated pure pursuit for robot path tracking", Autonomous
//! Robots 47, 2023, and nav2's `nav2_regulated_pure_pursuit_controller` (the keys below
//! carry its parameter names where the meaning is the same). Per tick, from the measured
//! pose and the encoders' speed v = r (w_r + w_l) / 2:
//!
//! ```text
//! s_c   = the closest path point, searched forward from the last one ([`crate::reference::PathCursor`])
//! L     = clamp(lookahead_time |v|, min_lookahead_dist, max_lookahead_dist)      m
//! P_L   = the first path point at distance L from C, searching forward from s_c
//!         (the path's end when none is that far)
//! kappa = 2 y_L / d^2,  (x_L, y_L) = P_L in the robot frame, d = |P_L - C| (= L but at the end)
//! v_cmd = speed, then
//!         if 1/|kappa| < regulated_linear_scaling_min_radius:
//!             v_cmd = max(v_cmd (1/|kappa|) / min_radius, regulated_linear_scaling_min_speed)
//!         if remaining < approach_velocity_scaling_dist:
//!             v_cmd = min(v_cmd, max(speed remaining / approach_velocity_scaling_dist,
//!                                    min_approach_linear_velocity))
//! omega = v_cmd kappa;  v = omega = 0 once within xy_goal_tolerance of the path's end
//! ```
//!
//! `remaining` is the path length from s_c to the end (infinite on an endless path).
//! The robot drives forward only. Without a path (a law update given only a reference
//! state, [`Law::update`]) the law stops. The twist goes to the wheels through the wheel
//! stage as Kanayama's does.
//!
//! Logged errors: dl = the distance from C to the path (to the closest point), e_s = the
//! closest point's offset along the robot's heading, e_theta = wrap(theta_path - theta)
//! at the closest point.

use super::law::{ControlErrors, Law, LawOutput, WheelDemand};
use crate::error::{ParamError, check};
use crate::lane::Lane;
use crate::math::{Twist2, wrap_angle};
use crate::reference::path::{PathCursor, in_body_frame, lookahead};
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
        /// The lookahead distance per m/s of speed.
        pub lookahead_time: T [unit = "s", rule = ">= 0"],
        /// The shortest lookahead distance.
        pub min_lookahead_dist: T [unit = "m", rule = "> 0"],
        /// The longest lookahead distance.
        pub max_lookahead_dist: T [unit = "m", rule = ">= min_lookahead_dist"],
        /// Below this turning radius the speed is scaled down in proportion.
        pub regulated_linear_scaling_min_radius: T [unit = "m", rule = ">= 0"],
        /// The curvature scaling never brings the speed below this.
        pub regulated_linear_scaling_min_speed: T [unit = "m/s", rule = ">= 0"],
        /// Within this path length of the end the speed is scaled down in proportion.
        pub approach_velocity_scaling_dist: T [unit = "m", rule = ">= 0"],
        /// The approach scaling never brings the speed below this.
        pub min_approach_linear_velocity: T [unit = "m/s", rule = ">= 0"],
        /// Within this distance of the path's end the law stops.
        pub xy_goal_tolerance: T [unit = "m", rule = "> 0"],
    }
}

impl<T: Real> Default for PurePursuitParams<T> {
    /// nav2's defaults (lookahead_time 1.5 s, 0.3 to 0.9 m, min radius 0.9 m, min speed
    /// 0.25 m/s, approach over 0.6 m down to 0.05 m/s) with speed 0.3 m/s (the
    /// references' default speed) and a 1 cm goal tolerance (the tracking tolerance).
    fn default() -> Self {
        Self {
            speed: T::lit(0.3),
            lookahead_time: T::lit(1.5),
            min_lookahead_dist: T::lit(0.3),
            max_lookahead_dist: T::lit(0.9),
            regulated_linear_scaling_min_radius: T::lit(0.9),
            regulated_linear_scaling_min_speed: T::lit(0.25),
            approach_velocity_scaling_dist: T::lit(0.6),
            min_approach_linear_velocity: T::lit(0.05),
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
    const UPDATE_COST: f64 = 20.0;

    fn build<L: Lane<Scalar = T>>(
        &self,
        model: &RobotParams<T>,
        _control_dt: T,
    ) -> Result<PurePursuitLaw<L>, ParamError> {
        PurePursuitLaw::for_lanes(*self, model)
    }
}

impl<T: Real> PurePursuitParams<T> {
    /// Checks the keys; errors name them.
    pub fn validate(&self) -> Result<Self, ParamError> {
        check::positive("speed", self.speed)?;
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
        check::positive("xy_goal_tolerance", self.xy_goal_tolerance)?;
        Ok(*self)
    }
}

/// Regulated pure pursuit. Implements [`Law`] with [`WheelDemand::Twist`]; follows the
/// path given to [`Law::update_on_path`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PurePursuitLaw<T: Lane> {
    params: PurePursuitParams<T::Scalar>,
    /// Wheel radius of the controller's model, m.
    wheel_radius: T::Scalar,
    cursor: PathCursor<T>,
}

impl<T: Lane> PurePursuitLaw<T> {
    /// Checks the keys (errors name them) and builds the law for the controller's model.
    pub fn for_lanes(p: PurePursuitParams<T::Scalar>, model: &RobotParams<T::Scalar>) -> Result<Self, ParamError> {
        Ok(Self { params: p.validate()?, wheel_radius: model.wheel_radius, cursor: PathCursor::default() })
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
pub(crate) fn search_step<S: Real>(min_lookahead_dist: S) -> S {
    min_lookahead_dist * S::lit(0.2)
}

impl<T: Lane> Law<T> for PurePursuitLaw<T> {
    fn update(&mut self, _t: T, _m: &Measurement<T>, _r: &ReferenceState<T>) -> LawOutput<T> {
        LawOutput { demand: WheelDemand::Twist(Twist2::default()), errors: ControlErrors::default() }
    }

    fn update_on_path(
        &mut self,
        _t: T,
        m: &Measurement<T>,
        _r: &ReferenceState<T>,
        path: &dyn Path<T>,
    ) -> LawOutput<T> {
        let p = &self.params;
        let ds = search_step(p.min_lookahead_dist);
        let (x, y) = (m.pose.x, m.pose.y);
        let s_c = self.cursor.advance(path, x, y, p.max_lookahead_dist, ds);
        let closest = path.pose_on_path(s_c);
        let (ex, ey) = in_body_frame(&m.pose, &closest);
        let errors = ControlErrors { e_s: ex, e_theta: wrap_angle(closest.theta - m.pose.theta), dl: ex.hypot(ey) };

        let v_meas = T::splat(self.wheel_radius) * (m.wheel_speeds.right + m.wheel_speeds.left) * T::lit(0.5);
        let l = (T::splat(p.lookahead_time) * v_meas.abs())
            .max(T::splat(p.min_lookahead_dist))
            .min(T::splat(p.max_lookahead_dist));
        let s_l = lookahead(path, x, y, s_c, l, ds, p.max_lookahead_dist * <T::Scalar as Real>::lit(2.0));
        let carrot = path.pose_on_path(s_l);
        let (_, y_l) = in_body_frame(&m.pose, &carrot);
        let (dxl, dyl) = (carrot.x - x, carrot.y - y);
        let d2 = dxl * dxl + dyl * dyl;
        let zero = T::default();
        let kappa = T::select(zero.lt(d2), T::lit(2.0) * y_l / d2, zero);

        // Curvature regulation: v (r / r_min) where the radius r = 1/|kappa| < r_min.
        let speed = T::splat(p.speed);
        let r_min = T::splat(p.regulated_linear_scaling_min_radius);
        let k_abs = kappa.abs();
        let tight = T::lit(1.0).lt(k_abs * r_min);
        let scaled = (speed / (k_abs * r_min)).max(T::splat(p.regulated_linear_scaling_min_speed));
        let mut v = T::select(tight, scaled.min(speed), speed);
        // Approach regulation near the end.
        let remaining = path.remaining_length(s_c);
        let approach = T::splat(p.approach_velocity_scaling_dist);
        let near = remaining.lt(approach);
        let slow = (speed * remaining / approach).max(T::splat(p.min_approach_linear_velocity));
        v = T::select(near, v.min(slow), v);
        // Stop at the end.
        if let Some(end) = path.end() {
            let last = path.pose_on_path(T::splat(end));
            let (dxe, dye) = (last.x - x, last.y - y);
            let tol = T::splat(p.xy_goal_tolerance);
            let arrived = (dxe * dxe + dye * dye).lt(tol * tol) & near;
            v = T::select(arrived, zero, v);
        }
        LawOutput { demand: WheelDemand::Twist(Twist2 { v, omega: v * kappa }), errors }
    }

    fn reset_lanes(&mut self, lanes: T::Mask) {
        self.cursor.reset_lanes(lanes);
    }
}
