//! Stiction, `[robot] static_friction` (wmr issue 42, item 1): a wheel at rest stays at
//! rest while the friction that holds it is within the breakaway torque tau_s; checked
//! against hand-computed wheel motion on the paper's robot (m = 5 kg, r = 0.1 m,
//! R = 0.2 m, d = 0.25 m, I_m = 0.002 kg m^2, I_p = 0.005 kg m^2), torque drive, dt = 1 ms.

use wmr_core::{
    DriveParams, Plant, Pose2, Real, RobotParams, TorqueDriveParams, TractionKind, TractionParams, WorldParams,
};

const G: f64 = 9.80665;

/// M_r11 = m + 2 I_m / r^2 and M_r22 = I_p + m d^2 + 2 R^2 I_m / r^2 of the paper's robot,
/// written out from the parameters (kg, kg m^2).
fn reduced_inertia() -> (f64, f64) {
    let (m, r, big_r, d, i_m, i_p) = (5.0, 0.1, 0.2, 0.25, 0.002, 0.005);
    (m + 2.0 * i_m / (r * r), i_p + m * d * d + 2.0 * big_r * big_r * i_m / (r * r))
}

struct Run {
    tau_c: f64,
    tau_s: f64,
    slope_deg: f64,
    slip: bool,
    torque: (f64, f64),
}

/// Runs the paper's robot from rest at the origin (heading 0; on a slope, facing down
/// it) under wheel torques `torque` (N m, no limit) for `t_s` seconds; returns the final
/// state (x, y, theta, v, omega, phi_r, phi_l) as f64.
fn run<T: Real>(c: &Run, t_s: f64) -> [f64; 7] {
    let robot = RobotParams::<T> {
        coulomb_friction: T::lit(c.tau_c),
        coulomb_speed: T::lit(OMEGA_EPS),
        static_friction: T::lit(c.tau_s),
        ..RobotParams::paper()
    }
    .validate()
    .unwrap();
    let world = WorldParams::<T> { slope_deg: T::lit(c.slope_deg), ..WorldParams::default() }.validate().unwrap();
    let drive =
        DriveParams::Torque(TorqueDriveParams::<T> { motor_torque_max: T::infinity(), ..TorqueDriveParams::default() })
            .validate(&robot)
            .unwrap();
    let traction = TractionParams::<T> {
        traction: if c.slip { TractionKind::Slip } else { TractionKind::Rolling },
        ..TractionParams::default()
    }
    .validate(&robot, &world)
    .unwrap();
    let mut plant = Plant::on(robot, drive, world, Pose2::default()).unwrap().with_traction(traction);
    plant.apply(wmr_core::Wheels::new(T::lit(c.torque.0), T::lit(c.torque.1)));
    let dt = T::lit(1e-3);
    for k in 0..(t_s * 1e3).round() as usize {
        plant.step(T::lit(k as f64 * 1e-3), dt).unwrap();
    }
    plant.state().to_array().map(|v| v.to_f64_lossless())
}

/// omega_eps (rad/s) of the runs: the Coulomb friction's tanh, and the band around rest
/// in which stiction catches a wheel; wide enough for RK4 at 1 ms to resolve the rise of
/// tanh (its stiffness 2 tau_c / (r^2 omega_eps M_r11) is 370 1/s at tau_c = 0.1 N m).
const OMEGA_EPS: f64 = 0.01;

/// v(t) (m/s) of the robot driven straight from rest by a free acceleration `a_f`
/// (m/s^2: torques and slope) against Coulomb friction whose full deceleration is
/// b = 2 tau_c / (r M_r11), regularised by tanh(omega / omega_eps): (a_f - b) t plus
/// what the friction misses while tanh rises, with u = v / (r omega_eps), s = tanh u,
/// b int (1 - tanh u) dt = b r omega_eps int_0^1 ds / ((a_f - b s)(1 + s))
///                      = b r omega_eps (ln(a_f / (a_f - b)) + ln 2) / (a_f + b).
fn straight_speed(a_f: f64, b: f64, t: f64) -> f64 {
    let r = 0.1;
    (a_f - b) * t + b * r * OMEGA_EPS * ((a_f / (a_f - b)).ln() + std::f64::consts::LN_2) / (a_f + b)
}

/// b = 2 tau_c / (r M_r11), m/s^2.
fn friction_decel(tau_c: f64) -> f64 {
    2.0 * tau_c / (0.1 * reduced_inertia().0)
}

/// Both wheels driven by the same torque on flat ground, tau_c = 0.05 N m, tau_s = 0.1:
/// 0.099 N m leaves the robot at rest (bit for bit: the wheels are held); without
/// stiction it drives off at v' = 2 (tau - tau_c) / (r M_r11); 0.101 N m breaks away and
/// then slides against tau_c alone: v' = 2 (0.101 - 0.05) / (r M_r11)
/// ([`straight_speed`]).
#[test]
fn a_torque_just_below_breakaway_holds_and_just_above_slides() {
    fn check<T: Real>(tol: f64) {
        let (m11, _) = reduced_inertia();
        let held = run::<T>(&Run { tau_c: 0.05, tau_s: 0.1, slope_deg: 0.0, slip: false, torque: (0.099, 0.099) }, 1.0);
        assert_eq!(held, [0.0; 7], "below breakaway the robot stays at rest");
        let creeps =
            run::<T>(&Run { tau_c: 0.05, tau_s: 0.0, slope_deg: 0.0, slip: false, torque: (0.099, 0.099) }, 1.0);
        let want = straight_speed(2.0 * 0.099 / (0.1 * m11), friction_decel(0.05), 1.0);
        assert!((creeps[3] - want).abs() < tol * want, "without stiction v = {}, want {want}", creeps[3]);
        let slides =
            run::<T>(&Run { tau_c: 0.05, tau_s: 0.1, slope_deg: 0.0, slip: false, torque: (0.101, 0.101) }, 1.0);
        let want = straight_speed(2.0 * 0.101 / (0.1 * m11), friction_decel(0.05), 1.0);
        assert!((slides[3] - want).abs() < tol * want, "above breakaway v = {}, want {want}", slides[3]);
        assert!(slides[4].abs() < 1e-6, "straight: omega = {}", slides[4]);
        // Backwards too.
        let back =
            run::<T>(&Run { tau_c: 0.05, tau_s: 0.1, slope_deg: 0.0, slip: false, torque: (-0.099, -0.099) }, 0.5);
        assert_eq!(back, [0.0; 7]);
    }
    check::<f64>(1e-4);
    check::<f32>(1e-4);
}

/// One wheel driven (0.15 N m, above tau_s = 0.1), the other not, no Coulomb friction:
/// the left wheel's static friction holds it (it needs (a - c) / (a + c) x 0.15 =
/// 0.032 N m), so the robot pivots about the left wheel: v = R omega, and by virtual
/// work (the Coriolis terms do none along (R, 1)) omega' = 2 R tau / (r (M_r11 R^2 +
/// M_r22)), constant; the left wheel's angle stays 0. Without stiction both wheels turn.
#[test]
fn one_driven_wheel_pivots_about_the_held_one() {
    fn check<T: Real>(tol: f64, held_tol: f64) {
        let (m11, m22) = reduced_inertia();
        let (r, big_r, tau, t) = (0.1, 0.2, 0.15, 0.5);
        let accel = 2.0 * big_r * tau / (r * (m11 * big_r * big_r + m22));
        let s = run::<T>(&Run { tau_c: 0.0, tau_s: 0.1, slope_deg: 0.0, slip: false, torque: (tau, 0.0) }, t);
        let [_, _, theta, v, omega, phi_r, phi_l] = s;
        assert!((omega - accel * t).abs() < tol * accel * t, "omega = {omega}, want {}", accel * t);
        assert!((theta - 0.5 * accel * t * t).abs() < tol * accel * t * t, "theta = {theta}");
        assert!((v - big_r * omega).abs() < tol * v.abs(), "v = {v}, R omega = {}", big_r * omega);
        assert!(phi_l.abs() < held_tol, "the held wheel turned {phi_l} rad");
        assert!((phi_r - 2.0 * big_r * theta / r).abs() < tol * phi_r, "phi_r = {phi_r}");
        let free = run::<T>(&Run { tau_c: 0.0, tau_s: 0.0, slope_deg: 0.0, slip: false, torque: (tau, 0.0) }, t);
        assert!(free[6].abs() > 1e-3, "without stiction the left wheel turns: {}", free[6]);
    }
    check::<f64>(1e-9, 1e-12);
    check::<f32>(1e-4, 1e-6);
}

/// Parked facing down a 3 deg slope, no command: gravity's pull F = m g sin(3 deg) =
/// 2.566 N needs F r / 2 = 0.1283 N m of friction at each wheel. Coulomb friction of
/// 0.1 N m alone lets it roll (v' = (F - 2 tau_c / r) / M_r11); a breakaway torque 1 %
/// above F r / 2 holds it at rest, bit for bit, 1 % below lets it go.
#[test]
fn a_robot_parked_on_a_slope_holds_with_stiction() {
    fn check<T: Real>() {
        let (m11, _) = reduced_inertia();
        let f = 5.0 * G * (3.0f64).to_radians().sin();
        let hold = f * 0.1 / 2.0;
        let rolls = run::<T>(&Run { tau_c: 0.1, tau_s: 0.0, slope_deg: 3.0, slip: false, torque: (0.0, 0.0) }, 1.0);
        let want = straight_speed(f / m11, friction_decel(0.1), 1.0);
        assert!((rolls[3] - want).abs() < 1e-4 * want, "without stiction v = {}, want {want}", rolls[3]);
        let held =
            run::<T>(&Run { tau_c: 0.1, tau_s: 1.01 * hold, slope_deg: 3.0, slip: false, torque: (0.0, 0.0) }, 1.0);
        assert_eq!(held, [0.0; 7]);
        let goes =
            run::<T>(&Run { tau_c: 0.1, tau_s: 0.99 * hold, slope_deg: 3.0, slip: false, torque: (0.0, 0.0) }, 1.0);
        assert!((goes[3] - want).abs() < 1e-4 * want, "below breakaway v = {}, want {want}", goes[3]);
    }
    check::<f64>();
    check::<f32>();
}

/// The slip plant on the same slope: its wheels are held while the friction each needs,
/// r F_x of its tyre's force, is within tau_s. The tyres' anchors are springs loaded by a
/// step (gravity at t = 0): their force overshoots F / 2 per wheel by at most a factor 2
/// (an undamped spring under a step load), so tau_s = 2 F r / 2 holds the wheels for the
/// whole transient and the robot rests on its tyres' deflection, within a millimetre,
/// where without stiction it rolls away. (At 1.01 F r / 2 the overshoot breaks them
/// away: stiction does not damp the tyres.)
#[test]
fn a_slip_plant_parked_on_a_slope_holds_with_stiction() {
    fn check<T: Real>() {
        let f = 5.0 * G * (3.0f64).to_radians().sin();
        let hold = f * 0.1 / 2.0;
        let held =
            run::<T>(&Run { tau_c: 0.1, tau_s: 2.0 * hold, slope_deg: 3.0, slip: true, torque: (0.0, 0.0) }, 2.0);
        assert!(held[0].abs() < 1e-3 && held[3].abs() < 1e-3, "held: x = {} m, v = {} m/s", held[0], held[3]);
        assert_eq!((held[5], held[6]), (0.0, 0.0), "the held wheels do not turn");
        let rolls = run::<T>(&Run { tau_c: 0.1, tau_s: 0.0, slope_deg: 3.0, slip: true, torque: (0.0, 0.0) }, 2.0);
        assert!(rolls[0] > 0.05, "without stiction it rolls: x = {} m", rolls[0]);
    }
    check::<f64>();
    check::<f32>();
}
