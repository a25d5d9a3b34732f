//! The fit of a 10-minute log at 100 Hz (issue 44's target: under 10 s on one core):
//! the twelve SysId-style tests of `excite` played 13 times over by the robot of
//! examples/identify/robot.toml (torque drive), 1 % encoder noise, 5 ms jitter, seeded.
//! `cargo bench -p wmr-identify --bench fit`; benches/README.md has the figure.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use wmr_core::{DcMotorParams, DriveParams, RobotParams, TorqueDriveParams};
use wmr_identify::excite::{ExciteSettings, Test};
use wmr_identify::sim::{LogNoise, log_table};
use wmr_identify::{ColumnNames, CommandKind, FitSettings, Log, fit};

fn robot() -> RobotParams<f64> {
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

fn ten_minutes() -> Log {
    let r = robot().validate().unwrap();
    let drive =
        DriveParams::Torque(TorqueDriveParams { motor_torque_max: f64::INFINITY, deadband: 0.0 }).validate(&r).unwrap();
    let tests: Vec<Test> = (0..13).flat_map(|_| Test::all()).collect();
    let noise = LogNoise { encoder_fraction: 0.01, jitter_s: 0.005, seed: 44 };
    let table = log_table(r, drive, &tests, &ExciteSettings::new(2.0), noise).unwrap();
    Log::from_table(&table, &ColumnNames::default(), CommandKind::Torque).unwrap()
}

fn bench(c: &mut Criterion) {
    let log = ten_minutes();
    let span: f64 = log.runs.iter().map(|r| r.t_s.last().unwrap() - r.t_s[0]).sum();
    eprintln!("log: {} samples, {span:.0} s in {} runs", log.samples(), log.runs.len());
    let settings = FitSettings::new(CommandKind::Torque, robot(), DcMotorParams::default());
    let f = fit(&log, &settings).unwrap();
    eprintln!(
        "fit: mass {} wheel_inertia {} platform_inertia {}",
        f.robot.mass, f.robot.wheel_inertia, f.robot.platform_inertia
    );
    let mut g = c.benchmark_group("identify");
    g.sample_size(10);
    g.bench_function("fit_10_min_100_hz", |b| b.iter(|| fit(black_box(&log), black_box(&settings)).unwrap()));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
