//! Property tests of the kinematics: reversibility and the wheel/twist maps.

use proptest::prelude::*;
use wmr_core::integrator::rk4_step;
use wmr_core::kinematics::{c_from_g, g_from_c, twist_from_wheels, wheel_speeds};
use wmr_core::{Pose2, RobotParams, Twist2, Wheels};

/// Integrates the kinematic model (1), (8) at C under constant wheel speeds.
fn drive(p: &RobotParams<f64>, start: Pose2<f64>, w: Wheels<f64>, t: f64) -> Pose2<f64> {
    let tw = twist_from_wheels(p, w);
    let n = 200;
    let h = t / n as f64;
    let mut y = [start.x, start.y, start.theta];
    for k in 0..n {
        y = rk4_step(|_, y| [tw.v * y[2].cos(), tw.v * y[2].sin(), tw.omega], k as f64 * h, &y, h);
    }
    Pose2::new(y[0], y[1], y[2])
}

proptest! {
    /// Reversed wheel speeds bring the robot back to its start pose.
    #[test]
    fn reversed_wheel_speeds_return_to_the_start(
        x in -5.0..5.0f64, y in -5.0..5.0f64, th in -3.0..3.0f64,
        wr in -10.0..10.0f64, wl in -10.0..10.0f64, t in 0.1..3.0f64,
    ) {
        let p = RobotParams::paper();
        let start = Pose2::new(x, y, th);
        let there = drive(&p, start, Wheels::new(wr, wl), t);
        let back = drive(&p, there, Wheels::new(-wr, -wl), t);
        prop_assert!((back.x - x).abs() < 1e-9 && (back.y - y).abs() < 1e-9 && (back.theta - th).abs() < 1e-12);
    }

    /// The constant-twist motion is an arc of radius v / omega about a fixed centre
    /// (closed form), which RK4 reproduces.
    #[test]
    fn constant_wheel_speeds_follow_the_closed_form_arc(
        wr in 0.5..10.0f64, dw in 0.5..5.0f64, t in 0.1..2.0f64,
    ) {
        let p = RobotParams::paper();
        let w = Wheels::new(wr, wr - dw);
        let Twist2 { v, omega } = twist_from_wheels(&p, w);
        let end = drive(&p, Pose2::default(), w, t);
        let rho = v / omega;
        let (ex, ey) = (rho * (omega * t).sin(), rho * (1.0 - (omega * t).cos()));
        prop_assert!((end.x - ex).abs() < 1e-8 && (end.y - ey).abs() < 1e-8, "{:?} vs ({ex}, {ey})", end);
    }

    /// Wheel speeds and twist are inverse maps; G and C poses too.
    #[test]
    fn maps_are_inverse(v in -3.0..3.0f64, om in -5.0..5.0f64, x in -9.0..9.0f64, th in -4.0..4.0f64) {
        let p = RobotParams::paper();
        let back = twist_from_wheels(&p, wheel_speeds(&p, Twist2 { v, omega: om }));
        prop_assert!((back.v - v).abs() < 1e-12 && (back.omega - om).abs() < 1e-12);
        let c = Pose2::new(x, -x, th);
        let c2 = c_from_g(&p, g_from_c(&p, c));
        prop_assert!((c2.x - c.x).abs() < 1e-12 && (c2.y - c.y).abs() < 1e-12);
    }
}
