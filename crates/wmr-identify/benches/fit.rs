//! The fit of a 10-minute log at 100 Hz (issue 44's target: under 10 s on one core):
//! the twelve SysId-style tests of `excite` played 13 times over by the robot of
//! examples/identify/robot.toml (torque drive), 1 % encoder noise, 5 ms jitter, seeded.
//! `cargo bench -p wmr-identify --bench fit`; benches/README.md has the figure.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use wmr_core::DcMotorParams;
use wmr_identify::excite::Test;
use wmr_identify::{CommandKind, FitSettings, Log, fit};

#[path = "../tests/common/mod.rs"]
mod common;
use common::{NOISE, robot, torque_log_of};

fn ten_minutes() -> Log {
    let tests: Vec<Test> = (0..13).flat_map(|_| Test::all()).collect();
    torque_log_of(robot(), &tests, NOISE)
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
