//! Every invalid parameter is rejected with an error that names its field (the core's own
//! name: `mass`, `servo_kp`, `goal.x`; a scenario reader adds its table's path).

use crate::common::paper_controller;
use wmr_core::{
    ClosedLoop, ControllerParams, DcMotorParams, DriveParams, FixedGoal, LawParams, PaperLaw, PaperParams, Plant,
    Pose2, Reason, Robot, RobotParams, TorqueDriveParams, WheelStage, WheelStageParams,
};

type Setter = fn(&mut RobotParams<f64>, f64);
type Case<P> = (&'static str, fn(&mut P));

const ROBOT_FIELDS: [(&str, Setter, &[f64]); 11] = [
    ("mass", |p, v| p.mass = v, &[0.0, -1.0]),
    ("wheel_radius", |p, v| p.wheel_radius = v, &[0.0, -0.1]),
    ("half_track", |p, v| p.half_track = v, &[0.0, -0.2]),
    ("com_offset", |p, v| p.com_offset = v, &[]),
    ("wheel_inertia", |p, v| p.wheel_inertia = v, &[-0.001]),
    ("platform_inertia", |p, v| p.platform_inertia = v, &[-0.001]),
    ("gear_ratio", |p, v| p.gear_ratio = v, &[0.0, -0.1]),
    ("viscous_friction", |p, v| p.viscous_friction = v, &[-0.01]),
    ("coulomb_friction", |p, v| p.coulomb_friction = v, &[-0.01]),
    ("coulomb_speed", |p, v| p.coulomb_speed = v, &[0.0, -1.0]),
    // Below the paper's coulomb_friction (0) nothing but a negative; the cross rule:
    // static_friction_below_coulomb_is_rejected.
    ("static_friction", |p, v| p.static_friction = v, &[-0.01]),
];

/// Stiction's breakaway torque is at least the sliding friction (issue 42): 0 (off) or
/// >= coulomb_friction.
#[test]
fn static_friction_below_coulomb_is_rejected() {
    let p = RobotParams { coulomb_friction: 0.1, static_friction: 0.09, ..RobotParams::<f64>::paper() };
    let err = p.validate().unwrap_err();
    assert_eq!(err.field, "static_friction");
    assert!(err.to_string().contains("coulomb_friction"), "{err}");
    for ok in [0.0, 0.1, 0.2] {
        let p = RobotParams { coulomb_friction: 0.1, static_friction: ok, ..RobotParams::<f64>::paper() };
        assert_eq!(p.validate().map(|r| r.has_stiction()), Ok(ok > 0.1), "static_friction = {ok}");
    }
}

#[test]
fn every_robot_field_rejects_nan_infinity_and_out_of_range_values() {
    for (field, set, bad) in ROBOT_FIELDS {
        for &v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY].iter().chain(bad) {
            let mut p = RobotParams::paper();
            set(&mut p, v);
            let err = p.validate().expect_err(field);
            assert_eq!(err.field, field, "value {v}");
            let msg = err.to_string();
            assert!(msg.starts_with(field), "message {msg:?} should name {field}");
        }
    }
}

#[test]
fn zero_yaw_inertia_about_c_is_rejected() {
    let p = RobotParams { platform_inertia: 0.0, com_offset: 0.0, ..RobotParams::<f64>::paper() };
    let err = p.validate().unwrap_err();
    assert_eq!(err.field, "platform_inertia");
    assert!(matches!(err.reason, Reason::OutOfRange(_)));
}

#[test]
fn drive_fields_are_checked_and_infinite_torque_is_allowed() {
    let robot = Robot::<f64>::paper();
    let inf =
        DriveParams::Torque(TorqueDriveParams { motor_torque_max: f64::INFINITY, ..TorqueDriveParams::default() });
    assert!(inf.validate(&robot).is_ok());
    for v in [0.0, -1.0, f64::NAN] {
        let e = DriveParams::Torque(TorqueDriveParams { motor_torque_max: v, ..TorqueDriveParams::default() })
            .validate(&robot)
            .unwrap_err();
        assert_eq!(e.field, "motor_torque_max");
    }
    let cases: [Case<DcMotorParams<f64>>; 4] = [
        ("voltage_max", |p| p.voltage_max = 0.0),
        ("torque_constant", |p| p.torque_constant = f64::NAN),
        ("back_emf_constant", |p| p.back_emf_constant = -1.0),
        ("armature_resistance", |p| p.armature_resistance = f64::INFINITY),
    ];
    for (field, set) in cases {
        let mut p = DcMotorParams::default();
        set(&mut p);
        assert_eq!(DriveParams::DcMotor(p).validate(&robot).unwrap_err().field, field);
    }
}

#[test]
fn controller_and_loop_fields_are_checked() {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let model = robot.params();
    let goal = Pose2::new(1.0, 1.0, 0.0);
    // The law's own keys: PaperLaw::new and, through LawParams, ControllerParams::build.
    let cases: [Case<PaperParams<f64>>; 6] = [
        ("kp_theta", |p| p.kp_theta = -2.0),
        ("ki_theta", |p| p.ki_theta = f64::NAN),
        ("kp_s", |p| p.kp_s = f64::INFINITY),
        ("ki_s", |p| p.ki_s = -0.25),
        ("goal_radius", |p| p.goal_radius = -1e-3),
        ("hold_radius", |p| p.hold_radius = f64::NAN),
    ];
    for (field, set) in cases {
        let mut p = PaperParams::paper();
        set(&mut p);
        assert_eq!(PaperLaw::new(p, model, 1e-3).unwrap_err().field, field);
        let params = ControllerParams::with_law(LawParams::Paper(p));
        assert_eq!(params.build(model, &drive).unwrap_err().field, field);
    }
    // The control period and the wheel stage's keys.
    assert_eq!(PaperLaw::new(PaperParams::paper(), model, 0.0).unwrap_err().field, "control_dt");
    let bad_period = ControllerParams { control_dt: 0.0, ..ControllerParams::paper() };
    assert_eq!(bad_period.build(model, &drive).unwrap_err().field, "control_dt");
    let wheel_cases: [Case<WheelStageParams<f64>>; 3] = [
        ("servo_kp", |p| p.servo_kp = 0.0),
        ("servo_kd", |p| p.servo_kd = -1.0),
        ("servo_ki", |p| p.servo_ki = f64::INFINITY),
    ];
    for (field, set) in wheel_cases {
        let mut w = WheelStageParams::default();
        set(&mut w);
        assert_eq!(WheelStage::new(&w, model, &drive, 1e-3).unwrap_err().field, field);
        let params = ControllerParams { wheels: w, ..ControllerParams::paper() };
        assert_eq!(params.build(model, &drive).unwrap_err().field, field);
    }
    assert_eq!(WheelStage::new(&WheelStageParams::default(), model, &drive, 0.0).unwrap_err().field, "control_dt");

    let bad_goal = Pose2::new(f64::NAN, 0.0, 0.0);
    assert_eq!(FixedGoal::new(bad_goal).unwrap_err().field, "goal.x");

    let plant = || Plant::new(robot, drive, Pose2::default()).unwrap();
    let ctrl = || paper_controller(PaperParams::paper(), model, &drive, 1e-3);
    let goal = FixedGoal::new(goal).unwrap();
    assert_eq!(ClosedLoop::new(plant(), ctrl(), goal, 0.0).unwrap_err().field, "dt");
    // 1 ms control period is not a whole multiple of a 0.3 ms plant step.
    let e = ClosedLoop::new(plant(), ctrl(), goal, 3e-4).unwrap_err();
    assert_eq!((e.field, e.reason), ("control_dt", Reason::NotMultipleOfDt));
    assert_eq!(e.to_string(), "control_dt: must be a whole multiple of the plant step dt (got 0.001)");
    // ... but of 0.25 ms it is.
    assert!(ClosedLoop::new(plant(), ctrl(), goal, 2.5e-4).is_ok());
    let bad_start = Pose2::new(0.0, 0.0, f64::INFINITY);
    assert_eq!(Plant::new(robot, drive, bad_start).unwrap_err().field, "start.theta");
}

/// Issue 39 item 10: a core error printed its value with `{}`: 1e300 as 301 digits (in
/// Python's and C's messages too). Now in exponent form beyond 1e16 and below 1e-5.
#[test]
fn regression_39_10_param_errors_print_a_bounded_number() {
    let e = RobotParams::<f64> { mass: -1e300, ..RobotParams::paper() }.validate().unwrap_err();
    assert_eq!(e.to_string(), "mass: must be > 0 (got -1e300)");
    let e = RobotParams::<f64> { mass: -0.5, ..RobotParams::paper() }.validate().unwrap_err();
    assert_eq!(e.to_string(), "mass: must be > 0 (got -0.5)");
}
