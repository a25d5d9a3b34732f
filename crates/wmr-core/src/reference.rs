//! Where the robot should be: a [`Reference`] gives the goal pose at each time.
//!
//! Point stabilization needs only a [`FixedGoal`]; a time-varying reference (a moving
//! target, a path) is another implementation, and the laws, which receive the goal at
//! every tick, do not change.

use crate::Real;
use crate::error::{ParamError, check};
use crate::math::Pose2;

/// The goal pose of C at time t.
pub trait Reference<T: Real> {
    /// Goal pose of C (x, y in m, theta in rad, world frame) at time `t` (s).
    fn goal_at(&self, t: T) -> Pose2<T>;

    /// True when the goal never moves: only then can a run that has come to rest be
    /// stopped early ([`crate::settle`]).
    fn fixed(&self) -> bool {
        false
    }
}

/// A goal pose that does not move (point stabilization).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FixedGoal<T>(Pose2<T>);

impl<T: Real> FixedGoal<T> {
    /// Checks the goal pose (m, m, rad); errors name `goal.x`, `goal.y` or `goal.theta`.
    pub fn new(goal: Pose2<T>) -> Result<Self, ParamError> {
        check::finite("goal.x", goal.x)?;
        check::finite("goal.y", goal.y)?;
        check::finite("goal.theta", goal.theta)?;
        Ok(Self(goal))
    }

    /// The goal pose.
    pub fn pose(&self) -> Pose2<T> {
        self.0
    }
}

impl<T: Real> Reference<T> for FixedGoal<T> {
    #[inline(always)]
    fn goal_at(&self, _t: T) -> Pose2<T> {
        self.0
    }

    fn fixed(&self) -> bool {
        true
    }
}
