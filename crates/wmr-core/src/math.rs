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

    /// `self` then `local`: the pose `local`, given in the frame of `self`, in `self`'s
    /// parent frame (rigid transforms of SE(2); heading wrapped into (-pi, pi]).
    pub fn compose(&self, local: &Pose2<T>) -> Pose2<T> {
        let (s, c) = self.theta.sin_cos_libm();
        Pose2 {
            x: self.x + c * local.x - s * local.y,
            y: self.y + s * local.x + c * local.y,
            theta: wrap_angle(self.theta + local.theta),
        }
    }

    /// The inverse transform: the parent frame's origin seen from `self`, so that
    /// `p.compose(&p.inverse())` is the identity (up to rounding).
    pub fn inverse(&self) -> Pose2<T> {
        let (s, c) = self.theta.sin_cos_libm();
        Pose2 { x: -c * self.x - s * self.y, y: s * self.x - c * self.y, theta: wrap_angle(-self.theta) }
    }

    /// `self` in the frame of `frame` (`frame.inverse().compose(self)`): e.g. a
    /// reference pose in the robot's body frame, the tracking error of Kanayama et al.
    pub fn relative_to(&self, frame: &Pose2<T>) -> Pose2<T> {
        let (s, c) = frame.theta.sin_cos_libm();
        let (dx, dy) = (self.x - frame.x, self.y - frame.y);
        Pose2 { x: c * dx + s * dy, y: -s * dx + c * dy, theta: wrap_angle(self.theta - frame.theta) }
    }
}

impl<T: Lane> Pose2<T> {
    /// The world point (`x`, `y`) (m) in this pose's body frame (m: ahead, to the left):
    /// the offset of a goal, a reference point or a path point from the robot, one robot
    /// or several side by side ([`crate::lane`]). Every law's body-frame transform.
    #[inline(always)]
    pub fn body_offset(&self, x: T, y: T) -> (T, T) {
        let (s, c) = self.theta.sin_cos();
        let (dx, dy) = (x - self.x, y - self.y);
        (c * dx + s * dy, -s * dx + c * dy)
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

    fn close(a: Pose2<f64>, b: Pose2<f64>) -> bool {
        (a.x - b.x).abs() < 1e-12 && (a.y - b.y).abs() < 1e-12 && wrap_angle(a.theta - b.theta).abs() < 1e-12
    }

    #[test]
    fn compose_and_inverse_against_hand_computed_transforms() {
        let h = core::f64::consts::FRAC_PI_2;
        // A frame at (1, 2) facing +y: one metre ahead in it is (1, 3) in the world,
        // one metre to its left is (0, 2).
        let a = Pose2::new(1.0, 2.0, h);
        assert!(close(a.compose(&Pose2::new(1.0, 0.0, 0.0)), Pose2::new(1.0, 3.0, h)));
        assert!(close(a.compose(&Pose2::new(0.0, 1.0, h)), Pose2::new(0.0, 2.0, core::f64::consts::PI)));
        // Its inverse: the world origin seen from it is 2 m behind and 1 m to the left.
        assert!(close(a.inverse(), Pose2::new(-2.0, 1.0, -h)));
        // (3, 4, 0.3) seen from a frame at (3, 4) turned by 0.3: the frame's own origin.
        let b = Pose2::new(3.0, 4.0, 0.3);
        assert!(close(b.relative_to(&b), Pose2::default()));
        // The world point (1, 3) relative to a: 1 m straight ahead.
        assert!(close(Pose2::new(1.0, 3.0, 0.0).relative_to(&a), Pose2::new(1.0, 0.0, -h)));
        // Identities and the group law, on a few poses.
        let poses = [a, b, Pose2::new(-0.7, 0.2, -2.9), Pose2::new(5.0, -1.0, 3.1)];
        for p in poses {
            assert!(close(p.compose(&p.inverse()), Pose2::default()));
            assert!(close(p.inverse().compose(&p), Pose2::default()));
            for q in poses {
                assert!(close(q.relative_to(&p), p.inverse().compose(&q)));
                assert!(close(p.compose(&q.relative_to(&p)), q));
                for r in poses {
                    assert!(close(p.compose(&q).compose(&r), p.compose(&q.compose(&r))));
                }
            }
        }
    }

    #[test]
    fn wrap_angle_range() {
        let pi = core::f64::consts::PI;
        for &(a, w) in &[(0.0, 0.0), (pi, pi), (-pi, pi), (3.0 * pi, pi), (2.5 * pi, 0.5 * pi), (-0.5 * pi, -0.5 * pi)]
        {
            assert!((wrap_angle(a) - w).abs() < 1e-12, "{a} -> {} not {w}", wrap_angle(a));
        }
    }
}
