//! Pushes, `[[world.push]]` (wmr issue 42, item "pushes"): on a robot with no drive
//! torque and no friction, a push's impulse is the change of momentum, its angular
//! impulse the change of angular momentum; the rolling plant's wheels take a lateral push
//! (no lateral motion), the slip plant's slide under it.

use wmr_core::{
    DriveParams, Plant, Pose2, PushParams, Pushes, Real, Robot, RobotParams, TractionKind, TractionParams, Wheels,
    WorldParams,
};

fn f(v: impl Real) -> f64 {
    v.to_f64_lossless()
}

fn push<T: Real>(t: f64, duration: f64, (fx, fy): (f64, f64), torque: f64) -> PushParams<T> {
    PushParams {
        t: T::lit(t),
        duration: T::lit(duration),
        force_x: T::lit(fx),
        force_y: T::lit(fy),
        torque: T::lit(torque),
    }
}

/// Steps `plant` (no command) for `n` steps of `dt` (s) from t = 0.
fn coast<T: Real>(plant: &mut Plant<T>, n: usize, dt: f64) {
    plant.apply(Wheels::new(T::zero(), T::zero()));
    for k in 0..n {
        plant.step(T::lit(k as f64 * dt), T::lit(dt)).unwrap();
    }
}

/// The rolling plant, no friction, no command: a forward push of F for T seconds changes
/// the momentum M_11 v by F T (M_11 = m + 2 I_m / r^2: the platform's momentum plus the
/// rotors' angular momentum over r), whatever the alignment of the window with the steps;
/// on a robot with G at C (no Coriolis term), a torque tau over T changes the angular
/// momentum M_22 omega by tau T, and both at once do both.
fn impulse_is_the_change_of_momentum<T: Real>(tol: f64) {
    let dt = 1e-3;
    // The paper's robot (d = 0.25 m), forward push from rest (it does not turn).
    let robot = Robot::<T>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let (fx, dur) = (12.0, 0.2345);
    let pushes = Pushes::new(&[push(0.1007, dur, (fx, 0.0), 0.0)]).unwrap();
    let mut plant = Plant::new(robot, drive, Pose2::default()).unwrap().with_pushes(pushes);
    coast(&mut plant, 500, dt);
    let (m11, m22) = robot.reduced_inertia();
    let p = f(m11) * f(plant.state().v);
    assert!((p - fx * dur).abs() < tol * fx * dur, "momentum {p} vs impulse {}", fx * dur);
    assert_eq!(f(plant.state().omega), 0.0);
    let _ = m22;
    // G at C: the forward and yaw equations are independent; force and torque together.
    let robot = RobotParams::<T> { com_offset: T::zero(), ..RobotParams::paper() }.validate().unwrap();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let (fx, tau, dur) = (-7.0, 0.9, 0.3);
    // Two overlapping pushes that add up to (fx, tau) over [0.05, 0.35].
    let pushes =
        Pushes::new(&[push(0.05, dur, (fx / 2.0, 30.0), tau), push(0.05, dur, (fx / 2.0, -30.0), 0.0)]).unwrap();
    let mut plant =
        Plant::new(robot, drive, Pose2::new(T::zero(), T::zero(), T::lit(0.3))).unwrap().with_pushes(pushes);
    coast(&mut plant, 600, dt);
    let (m11, m22) = robot.reduced_inertia();
    let (p, l) = (f(m11) * f(plant.state().v), f(m22) * f(plant.state().omega));
    assert!((p - fx * dur).abs() < tol * (fx * dur).abs(), "momentum {p} vs impulse {}", fx * dur);
    assert!((l - tau * dur).abs() < tol * tau * dur, "angular momentum {l} vs angular impulse {}", tau * dur);
}

#[test]
fn impulse_is_the_change_of_momentum_f64() {
    impulse_is_the_change_of_momentum::<f64>(1e-12);
}

#[test]
fn impulse_is_the_change_of_momentum_f32() {
    impulse_is_the_change_of_momentum::<f32>(1e-5);
}

/// A slip plant with a near-frictionless ground (mu = 1e-9) is a free body: a push
/// (F_x, F_y, tau) at C for T seconds changes the linear momentum of G (world frame) by the
/// force's impulse (its body-frame components turned by the heading, integrated along the
/// run) and the angular momentum about G, I_G omega, by (tau - d F_y) T.
#[test]
fn a_free_body_takes_the_push_s_impulse() {
    let dt = 1e-3;
    let robot = Robot::<f64>::paper();
    let p = *robot.params();
    let world = WorldParams::default().validate().unwrap();
    let traction = TractionParams {
        traction: TractionKind::Slip,
        friction_coefficient: 1e-9,
        com_height: 0.0,
        ..Default::default()
    }
    .validate(&robot, &world)
    .unwrap();
    let drive = DriveParams::default().validate(&robot).unwrap();
    // The moment about G, tau - d F_y = 0.05 N m, spins it at 2 rad/s: slow enough for the
    // trapezoid of the turned force below.
    let (fx, fy, tau, t0, dur) = (6.0, -4.0, -0.95, 0.1, 0.2);
    let pushes = Pushes::new(&[push(t0, dur, (fx, fy), tau)]).unwrap();
    let mut plant =
        Plant::new(robot, drive, Pose2::new(0.0, 0.0, 0.4)).unwrap().with_traction(traction).with_pushes(pushes);
    plant.apply(Wheels::new(0.0, 0.0));
    // G's world velocity: C's (u, v_lat) plus omega x (d, 0), turned by theta.
    let momentum = |pl: &Plant<f64>| {
        let s = pl.state();
        let (sn, cs) = s.theta.sin_cos();
        let (bx, by) = (s.v, pl.slip_extra().v_lat + s.omega * p.com_offset);
        (p.mass * (bx * cs - by * sn), p.mass * (bx * sn + by * cs))
    };
    let (mut ix, mut iy) = (0.0, 0.0);
    let (px0, py0) = momentum(&plant);
    for k in 0..500 {
        let t = k as f64 * dt;
        let th0 = plant.state().theta;
        plant.step(t, dt).unwrap();
        // The force's world impulse over the step: its share of the window, turned by the
        // heading (trapezoid over the step).
        let share = ((t + dt).min(t0 + dur) - t.max(t0)).max(0.0);
        let turn = |th: f64| (fx * th.cos() - fy * th.sin(), fx * th.sin() + fy * th.cos());
        let (a, b) = (turn(th0), turn(plant.state().theta));
        ix += share * 0.5 * (a.0 + b.0);
        iy += share * 0.5 * (a.1 + b.1);
    }
    let (px, py) = momentum(&plant);
    let scale = fx.hypot(fy) * dur;
    assert!(((px - px0) - ix).abs() < 1e-5 * scale && ((py - py0) - iy).abs() < 1e-5 * scale, "{px} {py} vs {ix} {iy}");
    let l = p.platform_inertia * plant.state().omega;
    let want = (tau - p.com_offset * fy) * dur;
    assert!((l - want).abs() < 1e-5 * want.abs(), "I_G omega {l} vs {want}");
}

/// A lateral push of 60 N for 0.3 s on a robot at rest: the rolling plant's wheels take it
/// (the plant does exactly what it does without it: no lateral motion, no turn), the slip
/// plant, pushed through G (torque d F_y, so that it translates rather than spins),
/// plant's tyres (mu N = 0.8 x 49 N = 39 N < 60 N) let go and it slides sideways.
#[test]
fn a_lateral_push_is_taken_by_rolling_wheels_and_slides_a_slip_plant() {
    let dt = 1e-3;
    let robot = Robot::<f64>::paper();
    let world = WorldParams::default().validate().unwrap();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let pushes = Pushes::new(&[push(0.1, 0.3, (0.0, 60.0), 0.0)]).unwrap();
    let mut rolling = Plant::new(robot, drive, Pose2::default()).unwrap().with_pushes(pushes);
    coast(&mut rolling, 600, dt);
    let s = rolling.state();
    assert_eq!((s.x, s.y, s.theta, s.v, s.omega), (0.0, 0.0, 0.0, 0.0, 0.0), "rolling: {s:?}");
    let traction =
        TractionParams { traction: TractionKind::Slip, ..Default::default() }.validate(&robot, &world).unwrap();
    let through_g = Pushes::new(&[push(0.1, 0.3, (0.0, 60.0), 0.25 * 60.0)]).unwrap();
    let mut slip = Plant::new(robot, drive, Pose2::default()).unwrap().with_traction(traction).with_pushes(through_g);
    coast(&mut slip, 600, dt);
    let s = slip.state();
    assert!(s.y > 0.01, "slip: slid {} m to the left", s.y);
    // Without the push the slip plant stays put.
    let mut still = Plant::new(robot, drive, Pose2::default()).unwrap().with_traction(traction);
    coast(&mut still, 600, dt);
    assert!(still.state().y.abs() < 1e-9);
}

/// Bad pushes are refused naming the key; overlapping pushes are allowed.
#[test]
fn bad_pushes_are_refused_naming_the_key() {
    let cases = [
        (push::<f64>(0.0, -1.0, (1.0, 0.0), 0.0), "push.duration"),
        (push(0.0, 0.0, (1.0, 0.0), 0.0), "push.duration"),
        (push(-0.5, 1.0, (1.0, 0.0), 0.0), "push.t"),
        (push(f64::NAN, 1.0, (1.0, 0.0), 0.0), "push.t"),
        (push(0.0, f64::NAN, (1.0, 0.0), 0.0), "push.duration"),
        (push(0.0, 1.0, (f64::NAN, 0.0), 0.0), "push.force_x"),
        (push(0.0, 1.0, (0.0, f64::INFINITY), 0.0), "push.force_y"),
        (push(0.0, 1.0, (0.0, 0.0), f64::NAN), "push.torque"),
    ];
    for (p, key) in cases {
        assert_eq!(Pushes::new(&[p]).unwrap_err().field, key, "{p:?}");
    }
    let good = push::<f64>(0.0, 1.0, (1.0, 0.0), 0.0);
    assert!(Pushes::new(&[good, good]).is_ok(), "overlapping pushes add");
    assert_eq!(Pushes::new(&[good; 17]).unwrap_err().field, "push");
}
