//! A circle driven at constant speed: C_ref = center + radius (cos phi, sin phi), with
//! phi(t) = phase + (speed / radius) t.
//!
//! ```text
//! theta_ref = phi + pi/2 (speed > 0, counter-clockwise)  or  phi - pi/2 (speed < 0)
//! v_ref     = |speed|,  omega_ref = speed / radius,  v_ref' = omega_ref' = 0
//! ```
//!
//! theta_ref is not wrapped: it grows with t, as the robot's heading does. The path
//! parameter ([`super::Path`]) is the arc length from the start, in m.

use super::config::{Configured, config_by_words};
use super::path::Path;
use super::state::{Reference, ReferenceState};
use crate::Real;
use crate::error::{ParamError, check};
use crate::math::{Pose2, Twist2};

crate::params! {
    words;
    /// `[reference] kind = "circle"`: its fields are also what builds it
    /// ([`Circle::new`], the trace's words).
    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct Circle<T> {
        /// Center, world frame.
        pub center_x: T [unit = "m", rule = "finite"],
        /// Center, world frame.
        pub center_y: T [unit = "m", rule = "finite"],
        /// Radius.
        pub radius: T [unit = "m", rule = "> 0"],
        /// Speed along the circle: > 0 counter-clockwise, < 0 clockwise.
        pub speed: T [unit = "m/s", rule = "finite, not 0"],
        /// Angle of (C_ref - center) at t = 0.
        pub phase: T [unit = "rad", rule = "finite"],
    }
}

config_by_words!(Circle => Circle, |c| Circle::new(c.center_x, c.center_y, c.radius, c.speed, c.phase));

impl<T: Real> Configured<T> for Circle<T> {
    type Config = Circle<T>;

    fn config(&self) -> Result<Self::Config, ParamError> {
        Ok(*self)
    }
}

impl<T: Real> Circle<T> {
    /// Checks the keys: errors name `center.x`, `center.y`, `radius` (> 0), `speed`
    /// (finite, not 0) and `phase_deg` (the phase is given in rad here).
    pub fn new(center_x: T, center_y: T, radius: T, speed: T, phase: T) -> Result<Self, ParamError> {
        check::finite("center.x", center_x)?;
        check::finite("center.y", center_y)?;
        check::positive("radius", radius)?;
        check::finite("speed", speed)?;
        if speed == T::zero() {
            return Err(check::out_of_range("speed", "must not be 0 (a circle at rest is a goal)", speed));
        }
        check::finite("phase_deg", phase)?;
        Ok(Self { center_x, center_y, radius, speed, phase })
    }

    /// phi at `t`, rad.
    #[inline(always)]
    fn phi(&self, t: T) -> T {
        self.phase + (self.speed / self.radius) * t
    }

    /// The pose at angle `phi`, heading along the direction of travel.
    #[inline(always)]
    fn pose_at_phi(&self, phi: T) -> Pose2<T> {
        let (s, c) = phi.sin_cos_libm();
        let quarter = if self.speed > T::zero() { T::FRAC_PI_2() } else { -T::FRAC_PI_2() };
        Pose2::new(self.center_x + self.radius * c, self.center_y + self.radius * s, phi + quarter)
    }
}

impl<T: Real> Reference<T> for Circle<T> {
    fn state_at(&self, t: T) -> ReferenceState<T> {
        ReferenceState {
            pose: self.pose_at_phi(self.phi(t)),
            twist: Twist2 { v: self.speed.abs(), omega: self.speed / self.radius },
            accel: Twist2::default(),
        }
    }

    fn path(&self) -> Option<&dyn Path<T>> {
        Some(self)
    }
}

impl<T: Real> Path<T> for Circle<T> {
    /// s = arc length from the start, m.
    fn pose_on_path(&self, s: T) -> Pose2<T> {
        let s = s.max(T::zero());
        self.pose_at_phi(self.phase + s / self.radius * self.speed.signum())
    }
    fn end(&self) -> Option<T> {
        None
    }
    fn rate_bounds(&self) -> (T, T) {
        (T::one(), T::one())
    }
    fn remaining_length(&self, _s: T) -> T {
        T::infinity()
    }
}
