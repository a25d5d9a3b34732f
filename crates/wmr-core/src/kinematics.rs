//! Kinematics of the differential drive: (1), (2), (6), (7), (9) of the paper.
//!
//! Frames: poses and velocities with `_world` are in the inertial XOY frame; `v` and
//! `omega` are the body-frame forward speed of C and yaw rate.

use crate::lane::Lane;
use crate::math::{Pose2, Twist2, Wheels};
use crate::{Real, RobotParams};

/// Wheel speeds (rad/s) from the body twist of C, the inverse of (1):
/// omega_r = (v + R omega) / r, omega_l = (v - R omega) / r.
#[inline(always)]
pub fn wheel_speeds<T: Real>(p: &RobotParams<T>, twist: Twist2<T>) -> Wheels<T> {
    wheel_speeds_lanes(p, twist.v, twist.omega)
}

/// [`wheel_speeds`] of v (m/s) and omega (rad/s) for one run or several side by side
/// ([`crate::lane`]).
#[inline(always)]
pub fn wheel_speeds_lanes<L: Lane>(p: &RobotParams<L::Scalar>, v: L, omega: L) -> Wheels<L> {
    let (r, big_r) = (p.wheel_radius, L::splat(p.half_track));
    // 1/r is a scalar division, which the compiler takes out of a loop of lane steps.
    let inv_r = <L::Scalar as num_traits::One>::one() / r;
    Wheels::new((v + big_r * omega).div_by(r, inv_r), (v - big_r * omega).div_by(r, inv_r))
}

/// Body twist of C from wheel speeds (rad/s), relation (1):
/// v = r (omega_r + omega_l) / 2, omega = r (omega_r - omega_l) / (2 R).
#[inline(always)]
pub fn twist_from_wheels<T: Real>(p: &RobotParams<T>, w: Wheels<T>) -> Twist2<T> {
    let half_r = p.wheel_radius / T::lit(2.0);
    Twist2 { v: half_r * (w.right + w.left), omega: half_r * (w.right - w.left) / p.half_track }
}

/// Pose of the centre of mass G from the pose of C, relation (2): OG = OC + d e^{j theta}.
pub fn g_from_c<T: Real>(p: &RobotParams<T>, c_world: Pose2<T>) -> Pose2<T> {
    let (s, c) = c_world.theta.sin_cos_libm();
    Pose2::new(c_world.x + p.com_offset * c, c_world.y + p.com_offset * s, c_world.theta)
}

/// Pose of C from the pose of G, the inverse of (2).
pub fn c_from_g<T: Real>(p: &RobotParams<T>, g_world: Pose2<T>) -> Pose2<T> {
    let (s, c) = g_world.theta.sin_cos_libm();
    Pose2::new(g_world.x - p.com_offset * c, g_world.y - p.com_offset * s, g_world.theta)
}

/// The Jacobian S(q_g) of (7), 3x2 row-major: q_g' = S(q_g) [v, omega]^T (8).
pub fn jacobian_s<T: Real>(p: &RobotParams<T>, theta: T) -> [[T; 2]; 3] {
    let (s, c) = theta.sin_cos_libm();
    let d = p.com_offset;
    [[c, -d * s], [s, d * c], [T::zero(), T::one()]]
}

/// Velocity of G in the world frame, (8): q_g' = S(q_g) v. Returns (x_g', y_g', theta').
pub fn g_velocity_world<T: Real>(p: &RobotParams<T>, theta: T, twist: Twist2<T>) -> [T; 3] {
    let s = jacobian_s(p, theta);
    core::array::from_fn(|i| s[i][0] * twist.v + s[i][1] * twist.omega)
}

/// The explicit wheel-to-G map of (9), 3x2 row-major: q_g' = J [omega_r, omega_l]^T.
pub fn wheel_to_g_jacobian<T: Real>(p: &RobotParams<T>, theta: T) -> [[T; 2]; 3] {
    let (s, c) = theta.sin_cos_libm();
    let two = T::lit(2.0);
    let (r, big_r, d) = (p.wheel_radius, p.half_track, p.com_offset);
    let a = r / two;
    let b = r * d / (two * big_r);
    [[a * c - b * s, a * c + b * s], [a * s + b * c, a * s - b * c], [r / (two * big_r), -r / (two * big_r)]]
}

/// Residual of the nonholonomic constraint (6), m/s:
/// x_g' sin(theta) - y_g' cos(theta) + d theta'. Zero for pure rolling without slip.
pub fn constraint_residual<T: Real>(p: &RobotParams<T>, theta: T, q_g_dot: [T; 3]) -> T {
    let (s, c) = theta.sin_cos_libm();
    q_g_dot[0] * s - q_g_dot[1] * c + p.com_offset * q_g_dot[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wheel_speed_round_trip() {
        let p = RobotParams::<f64>::paper();
        let t = Twist2 { v: 0.3, omega: -1.1 };
        let back = twist_from_wheels(&p, wheel_speeds(&p, t));
        assert!((back.v - t.v).abs() < 1e-15 && (back.omega - t.omega).abs() < 1e-15);
    }

    #[test]
    fn map_9_equals_s_times_1() {
        let p = RobotParams::<f64>::paper();
        let w = Wheels::new(3.0, -1.5);
        let theta = 0.7;
        let j = wheel_to_g_jacobian(&p, theta);
        let via9: [f64; 3] = core::array::from_fn(|i| j[i][0] * w.right + j[i][1] * w.left);
        let via8 = g_velocity_world(&p, theta, twist_from_wheels(&p, w));
        for i in 0..3 {
            assert!((via9[i] - via8[i]).abs() < 1e-14);
        }
        assert!(constraint_residual(&p, theta, via8).abs() < 1e-15);
    }
}
