//! The 7-number state of the robot and its array form for the integrator.

use crate::kinematics;
use crate::math::{Pose2, Twist2, Wheels};
use crate::{Real, RobotParams};

/// Number of state components.
pub const STATE_LEN: usize = 7;

/// State of the robot (docs/model.md, "The robot"): `[x, y, theta, v, omega, phi_r, phi_l]`.
///
/// (x, y) is point C (axle midpoint) in the world frame, m; theta the heading, rad;
/// v the forward speed of C, m/s; omega = theta', rad/s; phi_r, phi_l the wheel
/// angles, rad (encoder readings, zero at start). `#[repr(C)]`: the C API's `wmr_state`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct State<T> {
    /// x of C, world frame, m.
    pub x: T,
    /// y of C, world frame, m.
    pub y: T,
    /// Heading, rad.
    pub theta: T,
    /// Forward speed of C, body frame, m/s.
    pub v: T,
    /// Yaw rate, rad/s.
    pub omega: T,
    /// Right wheel angle, rad.
    pub phi_r: T,
    /// Left wheel angle, rad.
    pub phi_l: T,
}

impl<T: Real> State<T> {
    /// At rest at `pose`, encoders at zero.
    pub fn at_rest(pose: Pose2<T>) -> Self {
        Self { x: pose.x, y: pose.y, theta: pose.theta, ..Self::zero() }
    }

    /// All zeros.
    pub fn zero() -> Self {
        let z = T::zero();
        Self { x: z, y: z, theta: z, v: z, omega: z, phi_r: z, phi_l: z }
    }

    /// Pose of C.
    #[inline(always)]
    pub fn pose(&self) -> Pose2<T> {
        Pose2::new(self.x, self.y, self.theta)
    }

    /// Body twist (v, omega).
    #[inline(always)]
    pub fn twist(&self) -> Twist2<T> {
        Twist2 { v: self.v, omega: self.omega }
    }

    /// Wheel angles (encoders), rad.
    #[inline(always)]
    pub fn wheel_angles(&self) -> Wheels<T> {
        Wheels::new(self.phi_r, self.phi_l)
    }

    /// Wheel speeds, rad/s, from (v, omega) by the inverse of (1).
    #[inline(always)]
    pub fn wheel_speeds(&self, p: &RobotParams<T>) -> Wheels<T> {
        kinematics::wheel_speeds(p, self.twist())
    }

    /// True when every component is finite.
    pub fn is_finite(&self) -> bool {
        self.to_array().iter().all(|c| c.is_finite())
    }
}

impl<T: Copy> State<T> {
    /// `[x, y, theta, v, omega, phi_r, phi_l]`.
    #[inline(always)]
    pub fn to_array(&self) -> [T; STATE_LEN] {
        [self.x, self.y, self.theta, self.v, self.omega, self.phi_r, self.phi_l]
    }

    /// From `[x, y, theta, v, omega, phi_r, phi_l]`.
    #[inline(always)]
    pub fn from_array(a: [T; STATE_LEN]) -> Self {
        let [x, y, theta, v, omega, phi_r, phi_l] = a;
        Self { x, y, theta, v, omega, phi_r, phi_l }
    }
}
