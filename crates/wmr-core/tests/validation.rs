//! Every invalid parameter is rejected with an error that names its scenario key.

mod common;

use wmr_core::{
    ClosedLoop, DcMotorParams, DriveParams, PaperController, PaperParams, Pose2, Reason, Robot, RobotParams,
    TorqueDriveParams,
};

type Setter = fn(&mut RobotParams<f64>, f64);
type Case<P> = (&'static str, fn(&mut P));

const ROBOT_FIELDS: [(&str, Setter, &[f64]); 10] = [
    ("robot.mass", |p, v| p.mass = v, &[0.0, -1.0]),
    ("robot.wheel_radius", |p, v| p.wheel_radius = v, &[0.0, -0.1]),
    ("robot.half_track", |p, v| p.half_track = v, &[0.0, -0.2]),
    ("robot.com_offset", |p, v| p.com_offset = v, &[]),
    ("robot.wheel_inertia", |p, v| p.wheel_inertia = v, &[-0.001]),
    ("robot.platform_inertia", |p, v| p.platform_inertia = v, &[-0.001]),
    ("robot.gear_ratio", |p, v| p.gear_ratio = v, &[0.0, -0.1]),
    ("robot.viscous_friction", |p, v| p.viscous_friction = v, &[-0.01]),
    ("robot.coulomb_friction", |p, v| p.coulomb_friction = v, &[-0.01]),
    ("robot.coulomb_speed", |p, v| p.coulomb_speed = v, &[0.0, -1.0]),
];

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
    assert_eq!(err.field, "robot.platform_inertia");
    assert!(matches!(err.reason, Reason::OutOfRange(_)));
}

#[test]
fn drive_fields_are_checked_and_infinite_torque_is_allowed() {
    let robot = Robot::<f64>::paper();
    let inf = DriveParams::Torque(TorqueDriveParams { motor_torque_max: f64::INFINITY });
    assert!(inf.validate(&robot).is_ok());
    for v in [0.0, -1.0, f64::NAN] {
        let e = DriveParams::Torque(TorqueDriveParams { motor_torque_max: v }).validate(&robot).unwrap_err();
        assert_eq!(e.field, "drive.motor_torque_max");
    }
    let cases: [Case<DcMotorParams<f64>>; 4] = [
        ("drive.voltage_max", |p| p.voltage_max = 0.0),
        ("drive.torque_constant", |p| p.torque_constant = f64::NAN),
        ("drive.back_emf_constant", |p| p.back_emf_constant = -1.0),
        ("drive.armature_resistance", |p| p.armature_resistance = f64::INFINITY),
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
    let goal = Pose2::new(1.0, 1.0, 0.0);
    let cases: [Case<PaperParams<f64>>; 10] = [
        ("controller.kp_theta", |p| p.kp_theta = -2.0),
        ("controller.ki_theta", |p| p.ki_theta = f64::NAN),
        ("controller.kp_s", |p| p.kp_s = f64::INFINITY),
        ("controller.ki_s", |p| p.ki_s = -0.25),
        ("controller.goal_radius", |p| p.goal_radius = -1e-3),
        ("controller.hold_radius", |p| p.hold_radius = f64::NAN),
        ("controller.control_dt", |p| p.control_dt = 0.0),
        ("controller.servo_kp", |p| p.servo.kp = 0.0),
        ("controller.servo_kd", |p| p.servo.kd = -1.0),
        ("controller.servo_ki", |p| p.servo.ki = f64::INFINITY),
    ];
    for (field, set) in cases {
        let mut p = PaperParams::paper();
        set(&mut p);
        assert_eq!(PaperController::new(p, &robot, &drive, goal).unwrap_err().field, field);
    }
    let bad_goal = Pose2::new(f64::NAN, 0.0, 0.0);
    assert_eq!(PaperController::new(PaperParams::paper(), &robot, &drive, bad_goal).unwrap_err().field, "run.goal.x");

    let ctrl = || PaperController::new(PaperParams::paper(), &robot, &drive, goal).unwrap();
    let start = Pose2::default();
    assert_eq!(ClosedLoop::new(robot, drive, ctrl(), start, 0.0).unwrap_err().field, "sim.dt");
    // 1 ms control period is not a whole multiple of a 0.3 ms plant step.
    assert_eq!(ClosedLoop::new(robot, drive, ctrl(), start, 3e-4).unwrap_err().field, "controller.control_dt");
    // ... but of 0.25 ms it is.
    assert!(ClosedLoop::new(robot, drive, ctrl(), start, 2.5e-4).is_ok());
    let bad_start = Pose2::new(0.0, 0.0, f64::INFINITY);
    assert_eq!(ClosedLoop::new(robot, drive, ctrl(), bad_start, 1e-3).unwrap_err().field, "run.start.theta");
}
