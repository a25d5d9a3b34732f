//! An unknown payload, `[world.payload]` (wmr issue 42, item "unknown payload"): the
//! composite body against the rigid-body formulas, a payload at C against a heavier robot,
//! and the coupled equations against an independent Newton-Euler integration in the world
//! frame with the wheels' lateral constraint force solved explicitly.

use wmr_core::{
    DriveParams, ParamError, PayloadParams, Plant, Pose2, Real, Robot, RobotParams, State, TorqueDriveParams,
    TractionKind, TractionParams, Wheels, WorldParams,
};

/// The paper's robot: m = 5 kg, r = 0.1 m, R = 0.2 m, d = 0.25 m, I_m = 0.002, I_p = 0.005.
const M: f64 = 5.0;
const D: f64 = 0.25;
const I_P: f64 = 0.005;
const I_M: f64 = 0.002;
const R_WHEEL: f64 = 0.1;
const R_HALF: f64 = 0.2;

fn loaded<T: Real>(mass: f64, x: f64, y: f64) -> Result<Robot<T>, ParamError> {
    PayloadParams { mass: T::lit(mass), x: T::lit(x), y: T::lit(y), t: T::zero() }
        .validate()?
        .carried_by(&Robot::paper())
}

fn f(v: impl Real) -> f64 {
    v.to_f64_lossless()
}

/// Mass, centre of mass and yaw inertia about C of the composite equal those of two
/// bodies summed by hand (first moments and second moments about C, not the parallel-axis
/// route the code takes through G'), and the mass matrix holds them.
fn composite_is_the_two_bodies_summed<T: Real>(tol: f64) {
    for &(big_m, x, y) in &[(2.0, 0.1, 0.05), (1.5, -0.2, -0.12), (3.0, 0.25, 0.0), (0.7, 0.0, 0.3)] {
        let robot = loaded::<T>(big_m, x, y).unwrap();
        let p = robot.params();
        let total = M + big_m;
        // First moments about C.
        let (gx, gy) = ((M * D + big_m * x) / total, (big_m * y) / total);
        // Second moment about C: the platform's about G moved to C, plus the point mass's.
        let i_c = I_P + M * D * D + big_m * (x * x + y * y);
        let close = |what: &str, got: f64, want: f64| {
            assert!((got - want).abs() <= tol * want.abs().max(1.0), "{what}: {got} != {want} (M {big_m} at {x}, {y})");
        };
        close("mass", f(p.mass), total);
        close("com forward", f(p.com_offset), gx);
        close("com left", f(robot.com_lateral()), gy);
        let i_g = f(p.platform_inertia);
        close("inertia about C", i_g + total * (gx * gx + gy * gy), i_c);
        let (m11, m22) = robot.reduced_inertia();
        let wheels = 2.0 * I_M / (R_WHEEL * R_WHEEL);
        close("M_11", f(m11), total + wheels);
        close("M_22", f(m22), i_c + R_HALF * R_HALF * wheels);
        close("M_12", f(robot.mass_coupling()), -total * gy);
        // The kinetic energy of the two bodies moving at (v, omega), C without lateral
        // velocity: each part's 1/2 m |v_G|^2 + 1/2 I omega^2, plus the wheels'.
        let (v, w): (f64, f64) = (0.7, -1.3);
        let body = 0.5 * M * ((v - w * 0.0).powi(2) + (w * D).powi(2)) + 0.5 * I_P * w * w;
        let point = 0.5 * big_m * ((v - w * y).powi(2) + (w * x).powi(2));
        let wheel_energy = 0.5 * I_M * (((v + R_HALF * w) / R_WHEEL).powi(2) + ((v - R_HALF * w) / R_WHEEL).powi(2));
        let s = State { v: T::lit(v), omega: T::lit(w), ..State::default() };
        close("kinetic energy", f(robot.kinetic_energy(&s)), body + point + wheel_energy);
    }
}

#[test]
fn composite_is_the_two_bodies_summed_f64() {
    composite_is_the_two_bodies_summed::<f64>(1e-12);
}

#[test]
fn composite_is_the_two_bodies_summed_f32() {
    composite_is_the_two_bodies_summed::<f32>(1e-5);
}

/// A payload of M at C is a robot of mass m + M whose G has moved to m d / (m + M) and
/// whose inertia about C is unchanged: the plants' derivatives and 2 s of stepping agree
/// to 1e-12 (f64; f32 to its rounding).
fn payload_at_c_is_a_heavier_robot<T: Real>(tol: f64) {
    let big_m = 1.5;
    let total = M + big_m;
    let d_new = M * D / total;
    let heavier = RobotParams::<T> {
        mass: T::lit(total),
        com_offset: T::lit(d_new),
        platform_inertia: T::lit(I_P + M * D * D - total * d_new * d_new),
        viscous_friction: T::lit(0.02),
        ..RobotParams::paper()
    }
    .validate()
    .unwrap();
    let base = RobotParams::<T> { viscous_friction: T::lit(0.02), ..RobotParams::paper() }.validate().unwrap();
    let carried = PayloadParams { mass: T::lit(big_m), x: T::zero(), y: T::zero(), t: T::zero() }
        .validate()
        .unwrap()
        .carried_by(&base)
        .unwrap();
    let world = WorldParams { slope_deg: T::lit(4.0), slope_direction_deg: T::lit(30.0) }.validate().unwrap();
    let drive = DriveParams::<T>::default().validate(&base).unwrap();
    let start = Pose2::new(T::lit(0.2), T::lit(-0.1), T::lit(0.7));
    let mut a = Plant::on(carried, drive, world, start).unwrap();
    let mut b = Plant::on(heavier, drive, world, start).unwrap();
    let cmd = Wheels::new(T::lit(0.4), T::lit(-0.1));
    a.apply(cmd);
    b.apply(cmd);
    let dt = T::lit(1e-3);
    for k in 0..2000 {
        a.step(T::lit(k as f64 * 1e-3), dt).unwrap();
        b.step(T::lit(k as f64 * 1e-3), dt).unwrap();
    }
    let (sa, sb) = (a.state().to_array(), b.state().to_array());
    for i in 0..7 {
        let (x, y) = (f(sa[i]), f(sb[i]));
        assert!((x - y).abs() <= tol * x.abs().max(1.0), "state[{i}]: {x} vs {y}");
    }
    assert!(f(a.state().omega).abs() > 0.1, "the run turns");
}

#[test]
fn payload_at_c_is_a_heavier_robot_f64() {
    payload_at_c_is_a_heavier_robot::<f64>(1e-12);
}

#[test]
fn payload_at_c_is_a_heavier_robot_f32() {
    payload_at_c_is_a_heavier_robot::<f32>(1e-4);
}

/// Solves the 4 x 4 system `a z = b` by Gaussian elimination with partial pivoting.
#[allow(clippy::needless_range_loop)] // the textbook index form of the elimination
fn solve4(mut a: [[f64; 4]; 4], mut b: [f64; 4]) -> [f64; 4] {
    for c in 0..4 {
        let p = (c..4).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs())).unwrap();
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..4 {
            let k = a[r][c] / a[c][c];
            for j in c..4 {
                a[r][j] -= k * a[c][j];
            }
            b[r] -= k * b[c];
        }
    }
    let mut z = [0.0; 4];
    for r in (0..4).rev() {
        let s: f64 = (r + 1..4).map(|j| a[r][j] * z[j]).sum();
        z[r] = (b[r] - s) / a[r][r];
    }
    z
}

/// Newton-Euler of the composite in the world frame, written from scratch: unknowns
/// (X'', Y'', alpha, lambda), C's acceleration, the yaw acceleration and the lateral
/// constraint force at C. Each wheel pushes forward at its contact with
/// (tau_i - I_m phi_i'') / r; the composite (m', I' about G') obeys m' a_G = sum F and
/// I' alpha = sum (p - G') x F; C has no lateral velocity at any time.
/// State: [X, Y, theta, X', Y', omega]; returns its derivative.
fn newton_euler(s: [f64; 6], tau: (f64, f64), big_m: f64, (px, py): (f64, f64)) -> [f64; 6] {
    let [_, _, th, xd, yd, w] = s;
    let total = M + big_m;
    let (a, b) = ((M * D + big_m * px) / total, big_m * py / total);
    let i_g = I_P + M * ((D - a).powi(2) + b * b) + big_m * ((px - a).powi(2) + (py - b).powi(2));
    let (sn, cs) = th.sin_cos();
    let (rx, ry) = (a * cs - b * sn, a * sn + b * cs);
    let v = cs * xd + sn * yd;
    // Wheel forces, linear in the unknowns through v' = cs X'' + sn Y'' and alpha:
    // F_i = (tau_i - I_m (v' + sigma R alpha) / r) / r = f_i + g (cs X'' + sn Y'') + sigma h alpha.
    let g = -I_M / (R_WHEEL * R_WHEEL);
    let h = -I_M * R_HALF / (R_WHEEL * R_WHEEL);
    let (f_r, f_l) = (tau.0 / R_WHEEL, tau.1 / R_WHEEL);
    // Unknowns z = [X'', Y'', alpha, lambda]; F_r + F_l = f_r + f_l + 2 g v' (the h terms cancel).
    let sum_f = [2.0 * g * cs, 2.0 * g * sn, 0.0, 0.0];
    // (1) m' (X'' - alpha r_y - w^2 r_x) = (F_r + F_l) cs - lambda sn
    let mut rows = [[0.0; 4]; 4];
    let mut rhs = [0.0; 4];
    rows[0] = [total - sum_f[0] * cs, -sum_f[1] * cs, -total * ry, sn];
    rhs[0] = (f_r + f_l) * cs + total * w * w * rx;
    // (2) m' (Y'' + alpha r_x - w^2 r_y) = (F_r + F_l) sn + lambda cs
    rows[1] = [-sum_f[0] * sn, total - sum_f[1] * sn, total * rx, -cs];
    rhs[1] = (f_r + f_l) * sn + total * w * w * ry;
    // (3) I' alpha = (R + b) F_r - (R - b) F_l - a lambda
    //   = (R + b)(f_r + g v' + h alpha) - (R - b)(f_l + g v' - h alpha) - a lambda
    let gv = 2.0 * b * g; // coefficient of v' : (R + b) g - (R - b) g
    let ha = 2.0 * R_HALF * h; // coefficient of alpha: (R + b) h + (R - b) h
    rows[2] = [-gv * cs, -gv * sn, i_g - ha, a];
    rhs[2] = (R_HALF + b) * f_r - (R_HALF - b) * f_l;
    // (4) d/dt(-sn X' + cs Y') = -sn X'' + cs Y'' - w v = 0
    rows[3] = [-sn, cs, 0.0, 0.0];
    rhs[3] = w * v;
    let [xdd, ydd, alpha, _] = solve4(rows, rhs);
    [xd, yd, w, xdd, ydd, alpha]
}

fn rk4(s: [f64; 6], dt: f64, fun: impl Fn([f64; 6]) -> [f64; 6]) -> [f64; 6] {
    let add = |a: [f64; 6], k: [f64; 6], h: f64| core::array::from_fn(|i| a[i] + h * k[i]);
    let k1 = fun(s);
    let k2 = fun(add(s, k1, dt / 2.0));
    let k3 = fun(add(s, k2, dt / 2.0));
    let k4 = fun(add(s, k3, dt));
    core::array::from_fn(|i| s[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

/// Equal wheel torques from rest with a payload left of the centreline (y = 0.15 m): the
/// robot turns towards it, as the independent Newton-Euler integration says, to 1e-9
/// (f64) over 1.5 s; with unequal torques too. Without the coupling (the diagonal mass
/// matrix) the equal-torque run would drive straight (omega stays 0).
fn off_centre_payload_turns_as_newton_euler_says<T: Real>(tol: f64) {
    let (big_m, pos) = (2.0, (0.05, 0.15));
    for &tau in &[(0.3, 0.3), (0.25, -0.05), (-0.2, -0.2)] {
        let robot = loaded::<T>(big_m, pos.0, pos.1).unwrap();
        let drive = DriveParams::Torque(TorqueDriveParams::<T> {
            motor_torque_max: T::infinity(),
            ..TorqueDriveParams::default()
        })
        .validate(&robot)
        .unwrap();
        let start = (0.1, -0.2, 0.4);
        let mut plant =
            Plant::new(robot, drive, Pose2::new(T::lit(start.0), T::lit(start.1), T::lit(start.2))).unwrap();
        plant.apply(Wheels::new(T::lit(tau.0), T::lit(tau.1)));
        let mut ne = [start.0, start.1, start.2, 0.0, 0.0, 0.0];
        let dt = 1e-3;
        for k in 0..1500 {
            plant.step(T::lit(k as f64 * dt), T::lit(dt)).unwrap();
            ne = rk4(ne, dt, |s| newton_euler(s, tau, big_m, pos));
        }
        let s = plant.state();
        let (x, y, th) = (f(s.x), f(s.y), f(s.theta));
        assert!((x - ne[0]).abs() < tol && (y - ne[1]).abs() < tol, "tau {tau:?}: C ({x}, {y}) vs {ne:?}");
        assert!((th - ne[2]).abs() < tol, "tau {tau:?}: theta {th} vs {}", ne[2]);
        let v = ne[3] * ne[2].cos() + ne[4] * ne[2].sin();
        assert!((f(s.v) - v).abs() < tol && (f(s.omega) - ne[5]).abs() < tol, "tau {tau:?}: speeds");
        if tau.0 == tau.1 {
            // Equal torques: pushed forward it turns left, towards the payload; pushed back, right.
            assert!((th - start.2) * tau.0.signum() > 1e-3, "tau {tau:?}: theta {th}, turned {}", th - start.2);
        }
    }
}

#[test]
fn off_centre_payload_turns_as_newton_euler_says_f64() {
    off_centre_payload_turns_as_newton_euler_says::<f64>(1e-9);
}

#[test]
fn off_centre_payload_turns_as_newton_euler_says_f32() {
    off_centre_payload_turns_as_newton_euler_says::<f32>(2e-4);
}

/// The coupled plant on a slope keeps its energy balance: without friction, the work of
/// the wheel torques equals the change of kinetic energy (with its -m b v omega term) plus
/// that of the potential energy of G' (to RK4's accuracy at 0.1 ms).
#[test]
fn off_centre_payload_keeps_the_energy_balance() {
    let robot = loaded::<f64>(2.0, -0.1, -0.2).unwrap();
    let world = WorldParams { slope_deg: 3.0, slope_direction_deg: 100.0 }.validate().unwrap();
    let drive = DriveParams::Torque(TorqueDriveParams { motor_torque_max: f64::INFINITY, ..Default::default() })
        .validate(&robot)
        .unwrap();
    let mut plant = Plant::on(robot, drive, world, Pose2::new(0.0, 0.0, 0.3)).unwrap();
    let tau = Wheels::new(0.35, 0.1);
    plant.apply(tau);
    let (mut work, dt) = (0.0, 1e-4);
    let height = |s: &State<f64>| {
        // G' in the world, and its height: the plane descends along 100 deg by 3 deg.
        let (sn, cs) = s.theta.sin_cos();
        let (a, b) = (robot.params().com_offset, robot.com_lateral());
        let (gx, gy) = (s.x + a * cs - b * sn, s.y + a * sn + b * cs);
        let (ds, dc) = 100f64.to_radians().sin_cos();
        -(gx * dc + gy * ds) * 3f64.to_radians().sin()
    };
    let e0 = robot.kinetic_energy(plant.state()) + robot.params().mass * 9.80665 * height(plant.state());
    for k in 0..20_000 {
        let before = plant.state().wheel_speeds(robot.params());
        plant.step(k as f64 * dt, dt).unwrap();
        let after = plant.state().wheel_speeds(robot.params());
        work += dt * 0.5 * (tau.right * (before.right + after.right) + tau.left * (before.left + after.left));
    }
    let e1 = robot.kinetic_energy(plant.state()) + robot.params().mass * 9.80665 * height(plant.state());
    assert!(plant.state().omega.abs() > 0.1, "it turns");
    assert!(((e1 - e0) - work).abs() < 1e-6 * work.abs().max(1.0), "energy gained {} vs work {work}", e1 - e0);
}

/// Bad payloads are refused naming the key: negative or NaN mass, NaN or infinite position.
#[test]
fn bad_payloads_are_refused_naming_the_key() {
    let cases = [
        (-1.0, 0.0, 0.0, "payload.mass"),
        (f64::NAN, 0.0, 0.0, "payload.mass"),
        (1.0, f64::NAN, 0.0, "payload.x"),
        (1.0, 0.0, f64::INFINITY, "payload.y"),
    ];
    for (m, x, y, key) in cases {
        let e = PayloadParams { mass: m, x, y, t: 0.0 }.validate().unwrap_err();
        assert_eq!(e.field, key, "{m} {x} {y}: {e}");
    }
    // The slip plant keeps G on the centreline: a payload off it is refused there.
    let robot = loaded::<f64>(1.0, 0.0, 0.1).unwrap();
    let world = WorldParams::default().validate().unwrap();
    let e = TractionParams { traction: TractionKind::Slip, ..Default::default() }.validate(&robot, &world).unwrap_err();
    assert_eq!(e.field, "payload.y");
    // No payload: the robot itself, bit for bit.
    assert_eq!(PayloadParams::default().validate().unwrap().carried_by(&Robot::<f64>::paper()), Ok(Robot::paper()));
}

/// A payload that appears at a time (`[world.payload] t`): the plant is the robot alone
/// until the step that starts at t, then the composite, whose mass, centre of mass and
/// inertia about C are the rigid-body sums by hand: m' = m + M, a = (m d + M x_p) / m',
/// b = M y_p / m', I_C = I_p + m d^2 + M (x_p^2 + y_p^2). Its dynamics switch with it:
/// equal wheel torques tau from rest on flat ground (omega stays 0 with y_p = 0) give
/// v' = 2 tau / (r M_11), M_11 = m + 2 I_m / r^2 before and m' + 2 I_m / r^2 after, so
/// v gains dt v' per step (RK4 exact for a constant acceleration).
fn payload_switches_at_its_time<T: Real>(tol: f64) {
    let (big_m, xp, yp) = (1.5, 0.252, 0.0);
    let dt = 1.0 / 1024.0;
    let t_s = 256.0 * dt;
    let alone = Robot::<T>::paper();
    let payload =
        PayloadParams { mass: T::lit(big_m), x: T::lit(xp), y: T::lit(yp), t: T::lit(t_s) }.validate().unwrap();
    assert!(payload.appears_later());
    let carrying = payload.carried_by(&alone).unwrap();
    let drive = DriveParams::default().validate(&alone).unwrap();
    let mut plant = Plant::new(alone, drive, Pose2::default()).unwrap().with_payload_at(payload.t(), carrying).unwrap();
    assert_eq!(plant.payload_time().map(f), Some(t_s));
    let tau = 0.3;
    plant.apply(Wheels::new(T::lit(tau), T::lit(tau)));
    let about_c = |r: &Robot<T>| {
        let p = r.params();
        let (a, b) = (f(p.com_offset), f(r.com_lateral()));
        (f(p.mass), a, b, f(p.platform_inertia) + f(p.mass) * (a * a + b * b))
    };
    let before = (M, D, 0.0, I_P + M * D * D);
    let total = M + big_m;
    let after =
        (total, (M * D + big_m * xp) / total, big_m * yp / total, I_P + M * D * D + big_m * (xp * xp + yp * yp));
    let m11 = |m: f64| m + 2.0 * I_M / (R_WHEEL * R_WHEEL);
    let mut v = 0.0;
    for k in 0..512 {
        let t = k as f64 * dt;
        plant.step(T::lit(t), T::lit(dt)).unwrap();
        let expect = if t >= t_s { after } else { before };
        let got = about_c(plant.robot());
        for (name, g, e) in
            [("mass", got.0, expect.0), ("a", got.1, expect.1), ("b", got.2, expect.2), ("I_C", got.3, expect.3)]
        {
            assert!((g - e).abs() <= tol * e.abs().max(1.0), "step from t = {t}: {name} {g} vs {e}");
        }
        v += dt * 2.0 * tau / (R_WHEEL * m11(expect.0));
        assert!(
            (f(plant.state().v) - v).abs() <= tol * v.max(1.0),
            "step from t = {t}: v {} vs {v}",
            f(plant.state().v)
        );
        assert!(f(plant.state().omega).abs() <= tol, "straight");
    }
    // The switch is by the step's time: a plant rewound before t is the robot alone again.
    plant.step(T::lit(0.0), T::lit(dt)).unwrap();
    assert_eq!(f(plant.robot().params().mass), M);
}

#[test]
fn payload_switches_at_its_time_f64() {
    payload_switches_at_its_time::<f64>(1e-12);
}

#[test]
fn payload_switches_at_its_time_f32() {
    payload_switches_at_its_time::<f32>(1e-4);
}

/// `t` is checked naming `payload.t`; the lanes refuse a plant whose payload appears
/// later (they step one robot), as they refuse pushes; a slip plant refuses it too.
#[test]
fn a_payload_that_appears_is_refused_where_it_cannot_be_stepped() {
    for t in [-1.0, f64::NAN, f64::INFINITY] {
        let e = PayloadParams { mass: 1.0, x: 0.0, y: 0.0, t }.validate().unwrap_err();
        assert_eq!(e.field, "payload.t", "{t}: {e}");
    }
    let robot = Robot::<f64>::paper();
    let carrying = loaded::<f64>(1.0, 0.1, 0.0).unwrap();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let plant = Plant::new(robot, drive, Pose2::default()).unwrap().with_payload_at(2.0, carrying).unwrap();
    let controller =
        wmr_core::ControllerParams::paper().build_lanes::<wmr_core::lane::Lanes<4>>(robot.params(), &drive).unwrap();
    let goal = wmr_core::FixedGoal::new(Pose2::default()).unwrap();
    let e = wmr_core::batch::LaneBatch::<4, _, _>::new(plant, controller, goal, 1e-3, 100, true).err().unwrap();
    assert_eq!(e.field, "payload.t", "{e}");
    let world = WorldParams::default().validate().unwrap();
    let slip = TractionParams { traction: TractionKind::Slip, ..Default::default() }.validate(&robot, &world).unwrap();
    let e = Plant::new(robot, drive, Pose2::default()).unwrap().with_traction(slip).with_payload_at(2.0, carrying);
    assert_eq!(e.unwrap_err().field, "payload.t");
}
