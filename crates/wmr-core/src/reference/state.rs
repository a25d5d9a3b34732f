//! The reference contract: [`Reference`] gives, at each time, the state of the reference
//! point C_ref ([`ReferenceState`]: pose, twist, acceleration) and, for path following,
//! its geometric path ([`super::Path`]).

use super::path::Path;
use crate::Real;
use crate::lane::Lane;
use crate::math::{Pose2, Twist2};

/// The reference point C_ref at one instant: what a law may follow.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReferenceState<T> {
    /// Pose of C_ref: x, y in m, theta in rad (world frame). For point stabilization, the goal.
    pub pose: Pose2<T>,
    /// Twist of C_ref: forward speed v in m/s along `pose.theta`, yaw rate omega in rad/s.
    pub twist: Twist2<T>,
    /// Its time derivative: v' in m/s^2, omega' in rad/s^2.
    pub accel: Twist2<T>,
}

impl<T: Lane> ReferenceState<T> {
    /// C_ref at rest at `pose` (point stabilization): zero twist and acceleration.
    #[inline(always)]
    pub fn at_rest(pose: Pose2<T>) -> Self {
        Self { pose, twist: Twist2::default(), accel: Twist2::default() }
    }

    /// The same state in every lane ([`crate::lane`]): runs side by side that follow one
    /// reference.
    #[inline(always)]
    pub fn splat<L: Lane<Scalar = T>>(&self) -> ReferenceState<L>
    where
        T: Real,
    {
        let twist = |t: Twist2<T>| Twist2 { v: L::splat(t.v), omega: L::splat(t.omega) };
        ReferenceState {
            pose: Pose2::new(L::splat(self.pose.x), L::splat(self.pose.y), L::splat(self.pose.theta)),
            twist: twist(self.twist),
            accel: twist(self.accel),
        }
    }
}

/// The state of C_ref at time t.
pub trait Reference<T: Real> {
    /// Pose, twist and acceleration of C_ref at time `t` (s).
    fn state_at(&self, t: T) -> ReferenceState<T>;

    /// Pose of C_ref (x, y in m, theta in rad, world frame) at time `t` (s): what the
    /// outcome of a run is judged against.
    #[inline(always)]
    fn pose_at(&self, t: T) -> Pose2<T> {
        self.state_at(t).pose
    }

    /// True when the reference never moves: only then can a run that has come to rest be
    /// stopped early ([`crate::settle`]).
    fn fixed(&self) -> bool {
        false
    }

    /// The reference's geometric path (time ignored), for the path-following laws; `None`
    /// for a reference without one (a goal at rest).
    fn path(&self) -> Option<&dyn Path<T>> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lane::Lanes;

    #[test]
    fn splat_puts_every_component_in_every_lane() {
        let s = ReferenceState {
            pose: Pose2::new(1.0, 2.0, 3.0),
            twist: Twist2 { v: 4.0, omega: 5.0 },
            accel: Twist2 { v: 6.0, omega: 7.0 },
        };
        let l: ReferenceState<Lanes<4>> = s.splat();
        for i in 0..4 {
            let got =
                [l.pose.x, l.pose.y, l.pose.theta, l.twist.v, l.twist.omega, l.accel.v, l.accel.omega].map(|c| c.0[i]);
            assert_eq!(got, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        }
    }
}
