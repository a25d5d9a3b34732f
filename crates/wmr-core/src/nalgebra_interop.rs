//! nalgebra types for the core's (feature `nalgebra`; `no_std`, builds for Cortex-M):
//! [`Pose2`] and [`Isometry2`], [`Twist2`] and [`Vector2`], the Jacobian S(q_g) of (7) as
//! a [`Matrix3x2`] and the reduced inertia matrix M_r of (15) as a [`Matrix2`].
//!
//! The rotation's sine and cosine come from the same `libm` functions as the rest of the
//! core (`Real::sin_cos_libm`, `Real::atan2_libm`), so a conversion gives the same bits in
//! every build, whatever math library nalgebra itself is configured with.

use nalgebra::{Isometry2, Matrix2, Matrix3x2, RealField, Translation2, UnitComplex, Vector2};

use crate::kinematics;
use crate::math::{Pose2, Twist2};
use crate::{Real, Robot, RobotParams};

/// The rigid transform from the body frame of C to the world frame: rotation by theta,
/// then translation by (x, y) (m).
///
/// ```
/// use nalgebra::{Isometry2, Point2};
/// use wmr_core::Pose2;
///
/// let pose = Pose2::new(1.0, 2.0, core::f64::consts::FRAC_PI_2);
/// let iso: Isometry2<f64> = pose.into();
/// // A point 1 m ahead of C (body x) is 1 m along world y when theta = 90 deg.
/// let ahead = iso * Point2::new(1.0, 0.0);
/// assert!((ahead.x - 1.0).abs() < 1e-15 && (ahead.y - 3.0).abs() < 1e-15);
/// // And back: the same pose, the heading to within an ulp.
/// let back = Pose2::from(iso);
/// assert_eq!((back.x, back.y), (1.0, 2.0));
/// assert!((back.theta - pose.theta).abs() <= f64::EPSILON * 2.0);
/// ```
impl<T: Real + RealField> From<Pose2<T>> for Isometry2<T> {
    fn from(p: Pose2<T>) -> Self {
        let (sin, cos) = p.theta.sin_cos_libm();
        Isometry2::from_parts(Translation2::new(p.x, p.y), UnitComplex::from_cos_sin_unchecked(cos, sin))
    }
}

/// The pose of an isometry: its translation (m) and its rotation angle in (-pi, pi] (rad).
impl<T: Real + RealField> From<Isometry2<T>> for Pose2<T> {
    fn from(iso: Isometry2<T>) -> Self {
        let r = iso.rotation;
        Pose2::new(iso.translation.x, iso.translation.y, r.sin_angle().atan2_libm(r.cos_angle()))
    }
}

/// `[v, omega]`: forward speed (m/s) and yaw rate (rad/s), the velocity vector of (7)-(8).
///
/// ```
/// use nalgebra::Vector2;
/// use wmr_core::Twist2;
///
/// let twist = Twist2 { v: 0.5, omega: -0.25 };
/// let v: Vector2<f64> = twist.into();
/// assert_eq!(v, Vector2::new(0.5, -0.25));
/// assert_eq!(Twist2::from(v), twist);
/// ```
impl<T: Real + RealField> From<Twist2<T>> for Vector2<T> {
    fn from(t: Twist2<T>) -> Self {
        Vector2::new(t.v, t.omega)
    }
}

/// A twist from `[v, omega]` (m/s, rad/s).
impl<T: Real + RealField> From<Vector2<T>> for Twist2<T> {
    fn from(v: Vector2<T>) -> Self {
        Twist2 { v: v.x, omega: v.y }
    }
}

/// The Jacobian S(q_g) of (7) at heading `theta` (rad): q_g' = S(q_g) [v, omega]^T (8),
/// the velocity of the centre of mass G in the world frame (m/s, m/s, rad/s).
///
/// ```
/// use nalgebra::{RowVector3, Vector2};
/// use wmr_core::{RobotParams, Twist2, kinematics, nalgebra_interop::jacobian_s};
///
/// let p = RobotParams::<f64>::paper();
/// let theta = 0.7;
/// let s = jacobian_s(&p, theta);
/// // S spans the motions the wheels allow: the no-slip constraint (6),
/// // A(q) = [sin(theta), -cos(theta), d], annihilates both of its columns.
/// let a = RowVector3::new(theta.sin(), -theta.cos(), p.com_offset);
/// assert!((a * s).norm() < 1e-16);
/// // And S v is the velocity of G of (8).
/// let twist = Twist2 { v: 0.4, omega: 1.5 };
/// let g_dot = s * Vector2::from(twist);
/// let expected = kinematics::g_velocity_world(&p, theta, twist);
/// for i in 0..3 {
///     assert!((g_dot[i] - expected[i]).abs() < 1e-15);
/// }
/// ```
pub fn jacobian_s<T: Real + RealField>(p: &RobotParams<T>, theta: T) -> Matrix3x2<T> {
    let s = kinematics::jacobian_s(p, theta);
    Matrix3x2::new(s[0][0], s[0][1], s[1][0], s[1][1], s[2][0], s[2][1])
}

/// The reduced inertia matrix M_r of (15), diag(m + 2 I_m / r^2, I_p + 2 R^2 I_m / r^2 +
/// m d^2) (kg, kg m^2): the kinetic energy is 1/2 [v omega] M_r [v omega]^T.
///
/// ```
/// use nalgebra::Vector2;
/// use wmr_core::{Robot, State, nalgebra_interop::reduced_inertia};
///
/// let robot = Robot::<f64>::paper();
/// let m = reduced_inertia(&robot);
/// // The paper's robot: m = 5 kg, I_m = 0.002, r = 0.1 m -> M_r11 = 5.4 kg.
/// assert!((m[(0, 0)] - 5.4).abs() < 1e-12);
/// assert_eq!((m[(0, 1)], m[(1, 0)]), (0.0, 0.0));
/// // Kinetic energy through M_r equals the core's own formula.
/// let s = State { v: 0.3, omega: -0.8, ..State::zero() };
/// let w = Vector2::new(s.v, s.omega);
/// let energy = 0.5 * w.dot(&(m * w));
/// assert!((energy - robot.kinetic_energy(&s)).abs() < 1e-15);
/// ```
pub fn reduced_inertia<T: Real + RealField>(robot: &Robot<T>) -> Matrix2<T> {
    let (m11, m22) = robot.reduced_inertia();
    Matrix2::new(m11, T::zero(), T::zero(), m22)
}
