//! Disturbances the controller does not know (wmr issue 42, item 2), in the plant only,
//! each checked against a hand computation on the paper's robot (m = 5 kg, r = 0.1 m,
//! I_m = 0.002 kg m^2, k_t = 0.1; M_r11 = m + 2 I_m / r^2 = 5.4 kg).
//!
//! The driver's deadband (`[drive] deadband`): a command below deadband times the largest
//! command gives the wheel nothing, any other passes unchanged.

use wmr_core::{
    ControllerParams, DcMotorParams, DriveParams, LawParams, Measurement, Plant, Pose2, Real, ReferenceState, Robot,
    TorqueDriveParams, Wheels,
};

/// The paper's robot at rest at the origin with drive `drive`, commanded `command` for
/// `steps` plant steps of 1 ms: its final (x m, v m/s).
fn push_wheels<T: Real>(drive: DriveParams<T>, command: f64, steps: usize) -> (f64, f64) {
    let robot = Robot::<T>::paper();
    let drive = drive.validate(&robot).unwrap();
    let mut plant = Plant::new(robot, drive, Pose2::default()).unwrap();
    plant.apply(Wheels::new(T::lit(command), T::lit(command)));
    let mut t = T::zero();
    for _ in 0..steps {
        plant.step(t, T::lit(1e-3)).unwrap();
        t = t + T::lit(1e-3);
    }
    (plant.state().x.to_f64_lossless(), plant.state().v.to_f64_lossless())
}

fn torque<T: Real>(deadband: f64) -> DriveParams<T> {
    DriveParams::Torque(TorqueDriveParams { deadband: T::lit(deadband), ..TorqueDriveParams::default() })
}

fn dc_motor<T: Real>(deadband: f64) -> DriveParams<T> {
    DriveParams::DcMotor(DcMotorParams { deadband: T::lit(deadband), ..DcMotorParams::default() })
}

/// Torque drive, largest wheel torque 0.2 / 0.1 = 2 N m, deadband 5 %: 0.1 N m. A demand
/// of 0.09 N m at both wheels leaves the robot at rest (without the deadband it drives
/// off at 2 * 0.09 / r / M_r11 = 1/3 m/s^2); 0.2 N m gives v' = 2 * 0.2 / r / M_r11 =
/// 0.7407 m/s^2, the same as without a deadband, so v(0.5 s) = 0.37037 m/s (RK4 is exact
/// for a constant acceleration).
#[test]
fn torque_deadband_against_hand_computation() {
    fn check<T: Real>(tol: f64) {
        assert_eq!(push_wheels::<T>(torque(0.05), 0.09, 500), (0.0, 0.0));
        let (_, v) = push_wheels::<T>(torque(0.0), 0.09, 500);
        assert!((v - 2.0 * 0.09 / 0.1 / 5.4 * 0.5).abs() < tol, "no deadband: v = {v}");
        let want = 2.0 * 0.2 / 0.1 / 5.4 * 0.5;
        let (x, v) = push_wheels::<T>(torque(0.05), 0.2, 500);
        assert!((v - want).abs() < tol, "v = {v}, want {want}");
        assert!((x - want * 0.25).abs() < tol, "x = {x}, want {}", want * 0.25);
        // Just above and below the threshold, in reverse too.
        assert_eq!(push_wheels::<T>(torque(0.05), -0.0999, 100), (0.0, 0.0));
        assert!(push_wheels::<T>(torque(0.05), -0.1001, 100).1 < 0.0);
    }
    check::<f64>(1e-12);
    check::<f32>(1e-5);
}

/// DC motor, voltage_max 12 V, deadband 10 %: 1.2 V. 1.1 V leaves the robot at rest; at
/// 2 V the stalled motor gives each wheel k_tau u / (R_a k_t) = 0.03744 * 2 / (2.18 * 0.1)
/// = 0.3435 N m, as without a deadband.
#[test]
fn dc_motor_deadband_against_hand_computation() {
    fn check<T: Real>(tol: f64) {
        assert_eq!(push_wheels::<T>(dc_motor(0.1), 1.1, 500), (0.0, 0.0));
        let robot = Robot::<T>::paper();
        let drive = dc_motor::<T>(0.1).validate(&robot).unwrap();
        let mut plant = Plant::new(robot, drive, Pose2::default()).unwrap();
        plant.apply(Wheels::new(T::lit(2.0), T::lit(2.0)));
        let want = 0.03744 * 2.0 / (2.18 * 0.1);
        let got = plant.wheel_torque().right.to_f64_lossless();
        assert!((got - want).abs() < tol, "{got} N m, want {want}");
        plant.apply(Wheels::new(T::lit(1.1), T::lit(-1.1)));
        assert_eq!(plant.wheel_torque(), Wheels::new(T::zero(), T::zero()));
    }
    check::<f64>(1e-12);
    check::<f32>(1e-6);
}

/// The controller does not see the deadband: built with a drive that has one, it asks
/// for the very commands it asks without.
#[test]
fn the_controller_does_not_see_the_deadband() {
    let robot = Robot::<f64>::paper();
    for (with, without) in [(torque(0.3), torque(0.0)), (dc_motor(0.3), dc_motor(0.0))] {
        let commands = |drive: DriveParams<f64>| {
            let drive = drive.validate(&robot).unwrap();
            let mut c = ControllerParams::with_law(LawParams::<f64>::default()).build(robot.params(), &drive).unwrap();
            let m = Measurement { t: 0.0, pose: Pose2::new(0.1, -0.2, 0.3), ..Default::default() };
            c.update(0.0, &m, &ReferenceState::at_rest(Pose2::new(1.0, 1.0, 2.0))).command
        };
        assert_eq!(commands(with), commands(without));
    }
}

/// Bad deadbands are refused naming the key.
#[test]
fn bad_deadbands_are_refused_by_name() {
    let robot = Robot::<f64>::paper();
    for d in [-0.1, 1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(torque(d).validate(&robot).unwrap_err().field, "deadband", "{d}");
        assert_eq!(dc_motor(d).validate(&robot).unwrap_err().field, "deadband", "{d}");
    }
    let inf = DriveParams::Torque(TorqueDriveParams { motor_torque_max: f64::INFINITY, deadband: 0.05 });
    assert_eq!(inf.validate(&robot).unwrap_err().field, "deadband");
}
