//! Issue 44, item 1: the fit recovers a known robot from logs wmr makes of it (seeded,
//! 1 % encoder noise, 5 ms timing jitter), and refuses what a log cannot determine.

use wmr_core::{DcMotorParams, DriveParams, RobotParams};
use wmr_identify::excite::{ExciteSettings, Motion, Test};
use wmr_identify::sim::{LogNoise, log_table};
use wmr_identify::{ColumnNames, CommandKind, FitSettings, IdentifyError, Log, Param, fit};

use crate::common::{NOISE, robot, torque_log_of};

fn torque_log(tests: &[Test], noise: LogNoise) -> Log {
    torque_log_of(robot(), tests, noise)
}

/// A blank slate for the fit: the geometry of `robot()`, every fitted value wrong.
fn start() -> RobotParams<f64> {
    RobotParams {
        mass: 1.0,
        wheel_inertia: 0.0,
        platform_inertia: 0.0,
        viscous_friction: 0.0,
        coulomb_friction: 0.0,
        ..robot()
    }
}

fn rel(fitted: f64, truth: f64) -> f64 {
    (fitted - truth).abs() / truth.abs()
}

#[test]
fn issue_44_torque_log_gives_the_robot_within_the_targets() {
    let log = torque_log(&Test::all(), NOISE);
    let f = fit(&log, &FitSettings::new(CommandKind::Torque, start(), DcMotorParams::default())).unwrap();
    let truth = robot();
    let targets = [
        (Param::Mass, truth.mass, 0.02),
        (Param::PlatformInertia, truth.platform_inertia, 0.03),
        (Param::WheelInertia, truth.wheel_inertia, 0.05),
        (Param::CoulombFriction, truth.coulomb_friction, 0.05),
        (Param::ViscousFriction, truth.viscous_friction, 0.05),
    ];
    for (p, t, tol) in targets {
        let e = f.get(p).unwrap();
        eprintln!("{}: {} +- {} (truth {t}, {:.2} %)", p.key(), e.value, e.std_err, 100.0 * rel(e.value, t));
        assert!(!e.held);
        assert!(rel(e.value, t) < tol, "{}: {} against {t}", p.key(), e.value);
        assert!(e.std_err > 0.0 && e.std_err.is_finite());
    }
    eprintln!("rows {} of {}, cond {}, rms {}", f.rows_used, f.rows_total, f.condition, f.rms_residual);
}

fn only(motion: Motion) -> Vec<Test> {
    Test::all().into_iter().filter(|t| t.motion == motion).collect()
}

fn refused(r: Result<wmr_identify::Fit, IdentifyError>) -> (String, String) {
    match r {
        Err(IdentifyError::NotIdentifiable { parameter, detail }) => (parameter, detail),
        other => panic!("expected a refusal, got {other:?}"),
    }
}

/// Straight-line runs only: I_p has nothing to act on. With the mass held (so m and
/// I_m are not confounded), the refusal names platform_inertia; with noise its regressor
/// is encoder noise only (the noise check), without noise it is exactly zero.
#[test]
fn issue_44_platform_inertia_from_straight_runs_is_refused() {
    let mut settings = FitSettings::new(CommandKind::Torque, start(), DcMotorParams::default());
    settings.robot.mass = robot().mass;
    settings.hold = vec![Param::Mass];
    for noise in [NOISE, LogNoise::NONE] {
        let log = torque_log(&only(Motion::Linear), noise);
        let (p, detail) = refused(fit(&log, &settings));
        assert_eq!(p, "platform_inertia", "{detail}");
        let msg = IdentifyError::NotIdentifiable { parameter: p, detail }.to_string();
        assert!(msg.contains("straight-line"), "{msg}");
        assert!(msg.contains("--hold platform_inertia"), "{msg}");
    }
    // Holding I_p too, the rest is fitted.
    settings.robot.platform_inertia = robot().platform_inertia;
    settings.hold.push(Param::PlatformInertia);
    let f = fit(&torque_log(&only(Motion::Linear), NOISE), &settings).unwrap();
    assert!(rel(f.get(Param::WheelInertia).unwrap().value, robot().wheel_inertia) < 0.05);
}

/// Straight-line runs with nothing held: m and I_m enter only as m + 2 I_m / r^2.
#[test]
fn issue_44_mass_and_wheel_inertia_from_straight_runs_are_refused() {
    let log = torque_log(&only(Motion::Linear), NOISE);
    let (p, detail) = refused(fit(&log, &FitSettings::new(CommandKind::Torque, start(), DcMotorParams::default())));
    assert!(p.contains("mass") && p.contains("wheel_inertia"), "{p}: {detail}");
    assert!(detail.contains("condition number"), "{detail}");
}

/// A robot with G on the axle (d = 0): every test together still cannot split m from I_m.
#[test]
fn issue_44_a_centred_robot_cannot_split_mass_from_wheel_inertia() {
    let centred = RobotParams { com_offset: 0.0, ..robot() };
    let log = torque_log_of(centred, &Test::all(), NOISE);
    let settings =
        FitSettings::new(CommandKind::Torque, RobotParams { com_offset: 0.0, ..start() }, DcMotorParams::default());
    let (p, detail) = refused(fit(&log, &settings));
    assert!(p.contains("mass") && p.contains("wheel_inertia"), "{p}: {detail}");
    assert!(detail.contains("m + 2 I_m / r^2"), "{detail}");
    // Held mass: the rest is fitted.
    let mut settings = settings;
    settings.robot.mass = robot().mass;
    settings.hold = vec![Param::Mass];
    let f = fit(&log, &settings).unwrap();
    assert!(rel(f.get(Param::WheelInertia).unwrap().value, robot().wheel_inertia) < 0.05);
    assert!(rel(f.get(Param::PlatformInertia).unwrap().value, robot().platform_inertia) < 0.03);
}

/// A DC motor driven by voltages: mass, viscous friction and R_a held (the defaults),
/// the rest fitted; k_tau and k_e within 3 %.
#[test]
fn issue_44_dc_motor_log_gives_its_constants() {
    let truth = robot();
    let motor = DcMotorParams { current_max: f64::INFINITY, ..DcMotorParams::default() };
    let r = truth.validate().unwrap();
    let drive = DriveParams::DcMotor(motor).validate(&r).unwrap();
    let table = log_table(r, drive, &Test::all(), &ExciteSettings::new(12.0), NOISE).unwrap();
    let log = Log::from_table(&table, &ColumnNames::default(), CommandKind::Voltage).unwrap();
    let wrong_motor = DcMotorParams { torque_constant: 1.0, back_emf_constant: 1.0, ..motor };
    let mut base = start();
    base.mass = truth.mass;
    base.viscous_friction = truth.viscous_friction;
    let f = fit(&log, &FitSettings::new(CommandKind::Voltage, base, wrong_motor)).unwrap();
    for (p, t, tol) in [
        (Param::TorqueConstant, motor.torque_constant, 0.03),
        (Param::BackEmfConstant, motor.back_emf_constant, 0.03),
        (Param::WheelInertia, truth.wheel_inertia, 0.05),
        (Param::PlatformInertia, truth.platform_inertia, 0.03),
        (Param::CoulombFriction, truth.coulomb_friction, 0.05),
    ] {
        let e = f.get(p).unwrap();
        eprintln!("{}: {} +- {} (truth {t}, {:.2} %)", p.key(), e.value, e.std_err, 100.0 * rel(e.value, t));
        assert!(!e.held && rel(e.value, t) < tol, "{}: {} against {t}", p.key(), e.value);
    }
    assert!(f.get(Param::Mass).unwrap().held && f.get(Param::ArmatureResistance).unwrap().held);
    // Nothing mechanical held: the voltage cannot give the scale.
    let mut settings = FitSettings::new(CommandKind::Voltage, start(), wrong_motor);
    settings.hold = vec![Param::ArmatureResistance];
    assert_eq!(refused(fit(&log, &settings)).0, "mass");
    // Viscous friction and back-EMF both free: both multiply the wheel speed.
    let mut settings = FitSettings::new(CommandKind::Voltage, base, wrong_motor);
    settings.hold = vec![Param::Mass, Param::ArmatureResistance];
    let (p, detail) = refused(fit(&log, &settings));
    assert!(p.contains("viscous_friction") && p.contains("back_emf_constant"), "{p}: {detail}");
}

/// The paper's robot has no friction: its viscous friction fits a little below zero
/// (within its standard error) on this seeded log, and is written as 0, said so, so the
/// robot file stays valid (viscous_friction >= 0).
#[test]
fn issue_44_a_friction_fitted_just_below_zero_is_zero() {
    let paper = RobotParams::<f64>::paper();
    let r = paper.validate().unwrap();
    let drive = DriveParams::default().validate(&r).unwrap();
    let noise = LogNoise { encoder_fraction: 0.01, jitter_s: 0.005, seed: 1 };
    let table = log_table(r, drive, &Test::all(), &ExciteSettings::new(2.0), noise).unwrap();
    let log = Log::from_table(&table, &ColumnNames::default(), CommandKind::Torque).unwrap();
    let f = fit(&log, &FitSettings::new(CommandKind::Torque, paper, DcMotorParams::default())).unwrap();
    let e = f.get(Param::ViscousFriction).unwrap();
    assert!(e.zeroed && e.value == 0.0 && e.std_err > 0.0, "{e:?}");
    assert_eq!(f.robot.viscous_friction, 0.0);
    assert!(f.robot.validate().is_ok());
}

/// A TurtleBot3 Burger (robots/turtlebot3_burger.toml: the XL430's reduction of 258.5
/// makes its back-EMF damping so large that its wheels settle in about 2 ms): logged at
/// 100 Hz, the log shows speeds but no accelerations, and before this refusal the fit
/// returned I_p 2.3 times too large. Its inertias are refused, named; logged at 1 kHz
/// (faster than the wheels settle) the check lets the fit through.
#[test]
fn issue_44_wheels_settling_within_one_sample_are_refused() {
    let burger = RobotParams {
        mass: 1.0,
        wheel_radius: 0.033,
        half_track: 0.08,
        com_offset: -0.032,
        wheel_inertia: 1.6e-5,
        platform_inertia: 0.00423,
        gear_ratio: 0.003868472,
        viscous_friction: 0.0,
        coulomb_friction: 0.0,
        coulomb_speed: 1e-3,
        static_friction: 0.0,
    };
    let motor = DcMotorParams {
        voltage_max: 11.1,
        torque_constant: 0.004166,
        back_emf_constant: 0.007194,
        armature_resistance: 8.538,
        current_max: f64::INFINITY,
        ..DcMotorParams::default()
    };
    let (tau_lin, tau_turn) = wmr_identify::fit::time_constants(&burger, &motor, true);
    // Closed form: c = k_tau k_e / (R_a k_t^2), M_r11 r^2 / (2 c) and M_r22 r^2 / (2 R^2 c).
    let c = 0.004166 * 0.007194 / (8.538 * 0.003868472f64.powi(2));
    let m11 = 1.0 + 2.0 * 1.6e-5 / 0.033f64.powi(2);
    let m22 = 0.00423 + 1.0 * 0.032f64.powi(2) + 2.0 * 0.08f64.powi(2) * 1.6e-5 / 0.033f64.powi(2);
    assert!((tau_lin - m11 * 0.033f64.powi(2) / (2.0 * c)).abs() < 1e-15, "{tau_lin}");
    assert!((tau_turn - m22 * 0.033f64.powi(2) / (2.0 * 0.08f64.powi(2) * c)).abs() < 1e-15, "{tau_turn}");
    assert!(tau_lin < 0.01 && tau_turn < 0.01 && tau_turn > 0.001, "{tau_lin} {tau_turn}");
    let r = burger.validate().unwrap();
    let drive = DriveParams::DcMotor(motor).validate(&r).unwrap();
    let log_at = |dt_s: f64| {
        let settings = ExciteSettings { dt_s, ..ExciteSettings::new(11.1) };
        let noise = LogNoise { encoder_fraction: 0.0, jitter_s: 0.0, seed: 44 };
        let table = log_table(r, drive, &Test::all(), &settings, noise).unwrap();
        Log::from_table(&table, &ColumnNames::default(), CommandKind::Voltage).unwrap()
    };
    let settings = FitSettings::new(CommandKind::Voltage, burger, motor);
    let (p, detail) = refused(fit(&log_at(0.01), &settings));
    assert_eq!(p, "platform_inertia", "{detail}");
    assert!(detail.contains("settle faster than one sample"), "{detail}");
    // The straight-line inertia, named when I_p is held.
    let mut held = settings.clone();
    held.hold.push(Param::PlatformInertia);
    let (p, detail) = refused(fit(&log_at(0.01), &held));
    assert_eq!(p, "wheel_inertia", "{detail}");
    // At 1 kHz the wheels' settling shows, and the fit finds I_p.
    let f = fit(&log_at(0.001), &settings).unwrap();
    assert!(rel(f.robot.platform_inertia, 0.00423) < 0.03, "1 kHz: I_p {}", f.robot.platform_inertia);
}
