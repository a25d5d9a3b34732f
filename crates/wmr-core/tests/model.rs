//! The dynamic model against closed-form solutions, a conserved quantity and RK4's order.

use crate::common::assert_close;
use wmr_core::integrator::rk4_step;
use wmr_core::kinematics::{constraint_residual, g_velocity_world, jacobian_s};
use wmr_core::{DcMotorParams, DriveParams, Pose2, Robot, RobotParams, State, Wheels};

/// Integrates the model open loop under constant wheel torques for `t_end` s.
fn integrate(robot: &Robot<f64>, s0: State<f64>, tau: Wheels<f64>, dt: f64, t_end: f64) -> State<f64> {
    let n = (t_end / dt).round() as usize;
    let mut y = s0.to_array();
    for k in 0..n {
        y = rk4_step(|_, y| robot.derivative(&State::from_array(*y), tau).to_array(), k as f64 * dt, &y, dt);
    }
    State::from_array(y)
}

/// Equal torques from rest: v(t) = 2 tau t / (r M_r11), omega = 0, a straight line
/// x(t) = tau t^2 / (r M_r11). RK4 is exact on this quadratic, so only rounding remains.
#[test]
fn equal_torques_drive_straight_with_constant_acceleration() {
    let robot = Robot::<f64>::paper();
    let (m11, _) = robot.reduced_inertia();
    let r = robot.params().wheel_radius;
    let tau = 0.3;
    let t = 2.0;
    let theta0 = 0.4;
    let s = integrate(&robot, State::at_rest(Pose2::new(0.0, 0.0, theta0)), Wheels::new(tau, tau), 1e-3, t);
    let v = 2.0 * tau * t / (r * m11);
    let dist = tau * t * t / (r * m11);
    assert_close("v", s.v, v, 1e-12, 0.0);
    assert_close("omega", s.omega, 0.0, 0.0, 1e-15);
    assert_close("theta", s.theta, theta0, 0.0, 1e-15);
    assert_close("x", s.x, dist * theta0.cos(), 1e-10, 0.0);
    assert_close("y", s.y, dist * theta0.sin(), 1e-10, 0.0);
    // Both wheels turned by the distance over the radius.
    assert_close("phi_r", s.phi_r, dist / r, 1e-10, 0.0);
    assert_close("phi_l", s.phi_l, dist / r, 1e-10, 0.0);
}

/// Opposite torques with d = 0: pure rotation about C, omega(t) = 2 R tau t / (r M_r22).
#[test]
fn opposite_torques_with_centred_mass_spin_about_c() {
    let robot = RobotParams { com_offset: 0.0, ..RobotParams::<f64>::paper() }.validate().unwrap();
    let (_, m22) = robot.reduced_inertia();
    let p = *robot.params();
    let tau = 0.2;
    let t = 1.5;
    let s = integrate(&robot, State::at_rest(Pose2::new(0.3, -0.2, 1.0)), Wheels::new(tau, -tau), 1e-3, t);
    let omega = 2.0 * p.half_track * tau * t / (p.wheel_radius * m22);
    assert_close("omega", s.omega, omega, 1e-12, 0.0);
    assert_close("theta", s.theta, 1.0 + 0.5 * omega * t, 1e-12, 0.0);
    assert_close("v", s.v, 0.0, 0.0, 1e-15);
    assert_close("x", s.x, 0.3, 0.0, 1e-15);
    assert_close("y", s.y, -0.2, 0.0, 1e-15);
}

/// With zero torque and zero friction the Coriolis terms do no work, so
/// T = 1/2 M_r11 v^2 + 1/2 M_r22 omega^2 is conserved, even with d != 0.
#[test]
fn kinetic_energy_is_conserved_without_torque_or_friction() {
    let robot = Robot::<f64>::paper();
    assert!(robot.params().com_offset != 0.0);
    let s0 = State { v: 0.4, omega: 1.2, ..State::zero() };
    let e0 = robot.kinetic_energy(&s0);
    let dt = 1e-3;
    let mut y = s0.to_array();
    let mut worst: f64 = 0.0;
    for k in 0..60_000 {
        y = rk4_step(
            |_, y| robot.derivative(&State::from_array(*y), Wheels::new(0.0, 0.0)).to_array(),
            k as f64 * dt,
            &y,
            dt,
        );
        let e = robot.kinetic_energy(&State::from_array(y));
        worst = worst.max(((e - e0) / e0).abs());
    }
    // The motion is not trivial: v and omega exchange energy through the Coriolis terms.
    let s = State::from_array(y);
    assert!((s.v - s0.v).abs() > 1e-3, "v should change, got {}", s.v);
    assert!(worst < 1e-10, "relative energy drift {worst:e}");
    println!("energy: worst relative drift over 60 s at dt = 1 ms: {worst:e}");
}

/// Observed order of RK4 on the full model (friction, d != 0, DC motor torques that
/// depend on the wheel speeds): halving dt divides the error by 2^4.
#[test]
fn rk4_converges_with_order_four_on_the_full_model() {
    let robot =
        RobotParams { viscous_friction: 0.01, coulomb_friction: 0.05, coulomb_speed: 0.5, ..RobotParams::paper() }
            .validate()
            .unwrap();
    let drive = DriveParams::DcMotor(DcMotorParams::<f64>::default()).validate(&robot).unwrap();
    let volts = Wheels::new(3.0, -1.0);
    let f = |s: &State<f64>| {
        let w = s.wheel_speeds(robot.params());
        let tau = Wheels::new(drive.wheel_torque(volts.right, w.right), drive.wheel_torque(volts.left, w.left));
        robot.derivative(s, tau)
    };
    let run = |dt: f64| {
        let n = (0.4 / dt).round() as usize;
        let mut y = State { v: 0.2, omega: -0.5, ..State::zero() }.to_array();
        for k in 0..n {
            y = rk4_step(|_, y| f(&State::from_array(*y)).to_array(), k as f64 * dt, &y, dt);
        }
        y
    };
    let reference = run(1e-5);
    let err = |dt: f64| {
        let y = run(dt);
        y.iter().zip(reference.iter()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
    };
    let (e1, e2, e3) = (err(0.008), err(0.004), err(0.002));
    let p1 = (e1 / e2).log2();
    let p2 = (e2 / e3).log2();
    println!("rk4: errors {e1:e} {e2:e} {e3:e}, observed orders {p1:.3} {p2:.3}");
    for p in [p1, p2] {
        assert!((3.9..=4.1).contains(&p), "observed order {p}");
    }
}

/// The nonholonomic constraint (6) holds for the model's own velocity of G, and S(q_g)
/// of (7) agrees with the derivative of G = C + d e^{j theta}.
#[test]
fn model_velocity_of_g_satisfies_the_constraint() {
    let robot = Robot::<f64>::paper();
    let p = *robot.params();
    let s = State { x: 0.1, y: 0.2, theta: 2.0, v: 0.7, omega: -1.3, phi_r: 0.0, phi_l: 0.0 };
    let ds = robot.derivative(&s, Wheels::new(0.4, -0.1));
    // d/dt (C + d e^{j theta}) from the model's C velocity.
    let xg_dot = ds.x - p.com_offset * s.theta.sin() * ds.theta;
    let yg_dot = ds.y + p.com_offset * s.theta.cos() * ds.theta;
    let via_s = g_velocity_world(&p, s.theta, s.twist());
    assert_close("x_g'", xg_dot, via_s[0], 1e-15, 1e-15);
    assert_close("y_g'", yg_dot, via_s[1], 1e-15, 1e-15);
    assert!(constraint_residual(&p, s.theta, [xg_dot, yg_dot, ds.theta]).abs() < 1e-15);
    // A sideways velocity of G violates it by exactly its size.
    let j = jacobian_s(&p, s.theta);
    let sideways = [via_s[0] + s.theta.sin(), via_s[1] - s.theta.cos(), j[2][1] * s.omega];
    assert_close("residual of 1 m/s sideways slip", constraint_residual(&p, s.theta, sideways), 1.0, 1e-12, 0.0);
}
