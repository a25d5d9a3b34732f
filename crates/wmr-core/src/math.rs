//! Shared planar geometry types: poses, twists, wheel pairs and angle wrapping.

use crate::Real;
use crate::lane::{Lane, Mask};

/// A planar pose in the world frame: position of point C (m) and heading (rad, from +x, CCW).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose2<T> {
    /// x of C in the world frame, m.
    pub x: T,
    /// y of C in the world frame, m.
    pub y: T,
    /// Heading theta, rad, counter-clockwise from the world x axis.
    pub theta: T,
}

impl<T> Pose2<T> {
    /// A pose from x (m), y (m) and heading (rad).
    pub fn new(x: T, y: T, theta: T) -> Self {
        Self { x, y, theta }
    }
}

impl<T: Real> Pose2<T> {
    /// True when all three components are finite.
    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.theta.is_finite()
    }
}

/// Body-frame velocity of point C: forward speed `v` (m/s) and yaw rate `omega` (rad/s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Twist2<T> {
    /// Forward speed of C along the heading, m/s.
    pub v: T,
    /// Yaw rate theta-dot, rad/s.
    pub omega: T,
}

/// One value per driven wheel (angles, speeds, torques, commands).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Wheels<T> {
    /// Right wheel.
    pub right: T,
    /// Left wheel.
    pub left: T,
}

impl<T: Copy> Wheels<T> {
    /// A pair from right and left values.
    pub const fn new(right: T, left: T) -> Self {
        Self { right, left }
    }

    /// Applies `f` to both wheels.
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub fn map<U>(self, mut f: impl FnMut(T) -> U) -> Wheels<U> {
        Wheels { right: f(self.right), left: f(self.left) }
    }
}

/// Wraps an angle (rad) into (-pi, pi].
#[cfg_attr(target_os = "none", inline)]
#[cfg_attr(not(target_os = "none"), inline(always))]
pub fn wrap_angle<L: Lane>(a: L) -> L {
    let pi = L::lit(core::f64::consts::PI);
    // Fast path, bit-identical to the reduction below for these inputs: most angles a
    // controller wraps are already in range, and `floor` is a library call on some targets.
    let in_range = (-pi).lt(a) & a.le(pi);
    if in_range.all() {
        return a;
    }
    let two_pi = pi + pi;
    // rem_euclid-style reduction into [-pi, pi), then -pi -> +pi.
    let w = a - two_pi * ((a + pi) / two_pi).floor();
    let w = L::select(w.le(-pi), w + two_pi, w);
    L::select(in_range, a, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_angle_range() {
        let pi = core::f64::consts::PI;
        for &(a, w) in &[(0.0, 0.0), (pi, pi), (-pi, pi), (3.0 * pi, pi), (2.5 * pi, 0.5 * pi), (-0.5 * pi, -0.5 * pi)]
        {
            assert!((wrap_angle(a) - w).abs() < 1e-12, "{a} -> {} not {w}", wrap_angle(a));
        }
    }
}
