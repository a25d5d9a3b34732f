//! Issue 25, item 1: the drives' clamp `x.max(-limit).min(limit)` made a NaN command
//! full reverse (the plant then drove at -7.4 m/s after 1 s as if commanded). Now NaN
//! stays NaN, so the plant's step is refused as non-finite; every other command gives
//! the bits of the old expression, written out here as the oracle.

use wmr_core::{DcMotorParams, DriveParams, Plant, Pose2, Robot, Termination, TorqueDriveParams, Wheels};

/// Commands across the range, with the limits and infinities.
fn commands(limit: f64) -> Vec<f64> {
    let mut v = vec![0.0, -0.0, limit, -limit, f64::INFINITY, f64::NEG_INFINITY, f64::MAX, -f64::MAX, 1e-300];
    v.extend((-200..=200).map(|i| f64::from(i) * limit / 97.0));
    v
}

macro_rules! clamp_test {
    ($name:ident, $t:ty) => {
        #[test]
        fn $name() {
            let robot = Robot::<$t>::paper();
            let torque = TorqueDriveParams::<$t>::default();
            let dc = DcMotorParams::<$t> { current_max: 8.0, ..DcMotorParams::default() };
            for params in [DriveParams::Torque(torque), DriveParams::DcMotor(dc)] {
                let drive = params.validate(&robot).unwrap();
                assert!(drive.wheel_torque(<$t>::NAN, 0.0).is_nan(), "{params:?}: NaN became a number");
                for c in commands(12.0) {
                    let c = c as $t;
                    let got = drive.wheel_torque(c, 3.0);
                    // The old expression, by hand, for each drive.
                    let want = match params {
                        DriveParams::Torque(p) => {
                            let k_t = robot.params().gear_ratio;
                            (c * k_t).max(-p.motor_torque_max).min(p.motor_torque_max) / k_t
                        }
                        DriveParams::DcMotor(_) => {
                            // Same voltage -> torque map, fed the old clamp's voltage.
                            let u = c.max(-dc.voltage_max).min(dc.voltage_max);
                            drive.wheel_torque(u, 3.0)
                        }
                        _ => unreachable!(),
                    };
                    assert_eq!(got.to_bits(), want.to_bits(), "{params:?}: command {c}");
                }
                // A NaN command: the plant's step is refused, the state kept.
                let mut plant = Plant::new(robot, drive, Pose2::default()).unwrap();
                plant.apply(Wheels::new(<$t>::NAN, <$t>::NAN));
                assert_eq!(plant.step(0.0, 1e-3), Err(Termination::NonFinite));
                assert_eq!(plant.state().v, 0.0);
            }
        }
    };
}

clamp_test!(issue25_1_nan_command_stays_nan_f64, f64);
clamp_test!(issue25_1_nan_command_stays_nan_f32, f32);
