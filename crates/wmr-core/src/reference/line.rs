//! A straight line driven at constant speed from `start` along its heading:
//! C_ref = (x0, y0) + speed t (cos theta0, sin theta0), theta_ref = theta0,
//! v_ref = speed (signed: < 0 drives backwards along the heading), omega_ref = 0, no
//! acceleration. The path parameter ([`super::Path`]) is the distance travelled, m.

use super::config::{Configured, config_by_words};
use super::path::Path;
use super::state::{Reference, ReferenceState};
use crate::Real;
use crate::error::{ParamError, check};
use crate::math::{Pose2, Twist2};

crate::params! {
    words;
    /// What builds a [`Line`] ([`Line::new`], the trace's words).
    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct LineParams<T> {
        /// x at t = 0, world frame.
        pub start_x: T [unit = "m", rule = "finite"],
        /// y at t = 0, world frame.
        pub start_y: T [unit = "m", rule = "finite"],
        /// The heading, world frame.
        pub start_theta: T [unit = "rad", rule = "finite"],
        /// Speed along the heading (< 0 backwards).
        pub speed: T [unit = "m/s", rule = "finite, not 0"],
    }
}

config_by_words!(LineParams => Line, |c| Line::new(Pose2::new(c.start_x, c.start_y, c.start_theta), c.speed));

impl<T: Real> Configured<T> for Line<T> {
    type Config = LineParams<T>;

    fn config(&self) -> Result<Self::Config, ParamError> {
        let Pose2 { x: start_x, y: start_y, theta: start_theta } = self.start;
        Ok(LineParams { start_x, start_y, start_theta, speed: self.speed })
    }
}

/// `[reference] kind = "line"`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line<T> {
    /// The pose at t = 0: x, y in m, theta in rad (world frame).
    pub start: Pose2<T>,
    /// Speed along the heading, m/s.
    pub speed: T,
}

impl<T: Real> Line<T> {
    /// Checks the keys: errors name `start.x`, `start.y`, `start.theta_deg` and `speed`
    /// (finite, not 0).
    pub fn new(start: Pose2<T>, speed: T) -> Result<Self, ParamError> {
        check::finite("start.x", start.x)?;
        check::finite("start.y", start.y)?;
        check::finite("start.theta_deg", start.theta)?;
        check::finite("speed", speed)?;
        if speed == T::zero() {
            return Err(check::out_of_range("speed", "must not be 0 (a line at rest is a goal)", speed));
        }
        Ok(Self { start, speed })
    }
}

impl<T: Real> Reference<T> for Line<T> {
    fn state_at(&self, t: T) -> ReferenceState<T> {
        let (s, c) = self.start.theta.sin_cos_libm();
        let d = self.speed * t;
        ReferenceState {
            pose: Pose2::new(self.start.x + d * c, self.start.y + d * s, self.start.theta),
            twist: Twist2 { v: self.speed, omega: T::zero() },
            accel: Twist2::default(),
        }
    }

    fn path(&self) -> Option<&dyn Path<T>> {
        Some(self)
    }
}

impl<T: Real> Path<T> for Line<T> {
    /// s = distance travelled, m; theta the direction of travel (theta0 + pi backwards).
    fn pose_on_path(&self, s: T) -> Pose2<T> {
        let s = s.max(T::zero());
        let (sn, c) = self.start.theta.sin_cos_libm();
        let d = s * self.speed.signum();
        let heading = if self.speed > T::zero() { self.start.theta } else { self.start.theta + T::PI() };
        Pose2::new(self.start.x + d * c, self.start.y + d * sn, heading)
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
