//! Point stabilization: a goal pose that does not move, the reference at rest.

use super::config::{Configured, KindConfig};
use super::state::{Reference, ReferenceState};
use crate::Real;
use crate::error::{ParamError, check};
use crate::math::Pose2;

/// A goal pose that does not move (point stabilization): the reference at rest.
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

/// A goal is built from its pose: x, y (m), theta (rad), three words.
impl<T: Real> KindConfig<T> for Pose2<T> {
    type Built = FixedGoal<T>;
    const WORDS: usize = 3;

    fn build(&self) -> Result<Self::Built, ParamError> {
        FixedGoal::new(*self)
    }

    fn encode(&self, args: &mut [u32], real: &mut dyn FnMut(T) -> u32) {
        for (w, v) in args.iter_mut().zip([self.x, self.y, self.theta]) {
            *w = real(v);
        }
    }

    fn decode(args: &[u32], real: &mut dyn FnMut(u32) -> T) -> Result<Self, &'static str> {
        match args {
            [x, y, theta, ..] => Ok(Pose2::new(real(*x), real(*y), real(*theta))),
            _ => Err("a goal takes three words"),
        }
    }
}

impl<T: Real> Configured<T> for FixedGoal<T> {
    type Config = Pose2<T>;

    fn config(&self) -> Result<Self::Config, ParamError> {
        Ok(self.0)
    }
}

impl<T: Real> Reference<T> for FixedGoal<T> {
    #[inline(always)]
    fn state_at(&self, _t: T) -> ReferenceState<T> {
        ReferenceState::at_rest(self.0)
    }

    fn fixed(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Twist2;

    #[test]
    fn a_fixed_goal_is_the_reference_at_rest() {
        let g = FixedGoal::new(Pose2::new(1.0, -2.0, 0.5)).unwrap();
        let s = g.state_at(7.0);
        assert_eq!(s.pose, Pose2::new(1.0, -2.0, 0.5));
        assert_eq!(s.twist, Twist2 { v: 0.0, omega: 0.0 });
        assert_eq!(s.accel, Twist2 { v: 0.0, omega: 0.0 });
        assert_eq!(g.pose_at(3.0), s.pose);
        assert!(g.fixed());
    }
}
