//! The test robot of wmr-identify's tests and its bench (`benches/fit.rs` includes this
//! file by path), and the log it makes: one definition for both.

#![allow(dead_code)]

use wmr_core::{DriveParams, RobotParams, TorqueDriveParams};
use wmr_identify::excite::{ExciteSettings, Test};
use wmr_identify::sim::{LogNoise, log_table};
use wmr_identify::{ColumnNames, CommandKind, Log};

/// A robot whose every parameter matters: 10 kg with G 0.1 m ahead of the axle, wheels
/// of 5 cm whose rotor adds a quarter of the mass to the straight-line inertia, a
/// platform inertia about half of the turning inertia, and both frictions (the `[robot]`
/// of examples/identify/robot.toml).
pub fn robot() -> RobotParams<f64> {
    RobotParams {
        mass: 10.0,
        wheel_radius: 0.05,
        half_track: 0.2,
        com_offset: 0.1,
        wheel_inertia: 0.004,
        platform_inertia: 0.3,
        gear_ratio: 0.1,
        viscous_friction: 0.02,
        coulomb_friction: 0.1,
        coulomb_speed: 1e-3,
        static_friction: 0.0,
    }
}

/// The noise: 1 % encoder noise, up to 5 ms of timing jitter, seeded.
pub const NOISE: LogNoise = LogNoise { encoder_fraction: 0.01, jitter_s: 0.005, seed: 44 };

/// The log of `robot` (a torque drive without a limit) playing `tests` with commands up
/// to 2 N m.
pub fn torque_log_of(robot: RobotParams<f64>, tests: &[Test], noise: LogNoise) -> Log {
    let robot = robot.validate().unwrap();
    let drive = DriveParams::Torque(TorqueDriveParams { motor_torque_max: f64::INFINITY, deadband: 0.0 })
        .validate(&robot)
        .unwrap();
    let table = log_table(robot, drive, tests, &ExciteSettings::new(2.0), noise).unwrap();
    Log::from_table(&table, &ColumnNames::default(), CommandKind::Torque).unwrap()
}
