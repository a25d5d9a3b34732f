//! `wmr-cli trace`: the f32 run it records is `ClosedLoop`'s, tick for tick and bit for
//! bit (Fig. 7, and a run with every real-world effect); the CSV form holds the same
//! values; bad input exits 2 naming the argument.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use wmr_core::trace::{self, CONFIG_WORDS, Config, HEADER_WORDS, RECORD_WORDS, Record};
use wmr_core::{ClosedLoop, Controller, FixedGoal, Plant, PoseSensor, SensorParams, WheelStage};

fn cli(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wmr-cli")).args(args).output().expect("wmr-cli runs")
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Reads a binary trace: its config and records.
fn read_trace(path: &Path) -> (Config, Vec<Record>) {
    let bytes = std::fs::read(path).expect("trace file");
    assert_eq!(bytes.len() % 4, 0);
    let words: Vec<u32> = bytes.chunks(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    let ticks = trace::read_header(words[..HEADER_WORDS].try_into().unwrap()).expect("header");
    let config = Config::decode(words[HEADER_WORDS..HEADER_WORDS + CONFIG_WORDS].try_into().unwrap()).expect("config");
    let body = &words[HEADER_WORDS + CONFIG_WORDS..];
    assert_eq!(body.len(), ticks as usize * RECORD_WORDS, "record count matches the header");
    let records = body.chunks(RECORD_WORDS).map(|c| Record::decode(c.try_into().unwrap())).collect();
    (config, records)
}

/// `ClosedLoop` (f32) from the trace's own config: every tick's true state and held
/// command must be the recorded ones.
fn check_against_closed_loop(config: &Config, sensor: SensorParams<f32>, run: u64, records: &[Record]) {
    let robot = config.robot.validate().unwrap();
    let model = config.model.validate().unwrap();
    let drive = config.drive.validate(&robot).unwrap();
    let plant = Plant::on(robot, drive, config.world.validate().unwrap(), config.start).unwrap();
    let law = config.law.build(model.params(), config.control_dt).unwrap();
    let wheels = WheelStage::new(&config.wheels, model.params(), &drive, config.control_dt).unwrap();
    let sensor = PoseSensor::<f32>::new(sensor, config.control_dt, run).unwrap();
    let goal = FixedGoal::new(config.goal).unwrap();
    let mut sim = ClosedLoop::with_sensor(plant, sensor, Controller::new(law, wheels), goal, config.dt).unwrap();
    for (k, r) in records.iter().enumerate() {
        if k > 0 {
            for _ in 0..config.steps_per_tick {
                sim.step().unwrap();
            }
        }
        assert_eq!(sim.time().to_bits(), r.t.to_bits(), "tick {k}: time");
        let s = sim.state().to_array();
        assert_eq!(s.map(f32::to_bits), r.state.map(f32::to_bits), "tick {k}: state");
        let c = sim.plant().command();
        assert_eq!([c.right.to_bits(), c.left.to_bits()], r.command.map(f32::to_bits), "tick {k}: command");
    }
}

#[test]
fn fig7_trace_is_the_closed_loop_in_f32() {
    let dir = tempfile::tempdir().unwrap();
    let bin = dir.path().join("fig7.bin");
    let out = cli(&["trace", repo().join("examples/paper/fig7.toml").to_str().unwrap(), "-o", bin.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("trace: 60001 ticks of paper (f32)"));
    let (config, records) = read_trace(&bin);
    assert_eq!(records.len(), 60_001);
    assert_eq!(config.goal.theta, 120f64.to_radians() as f32);
    assert_eq!(config.steps_per_tick, 1);
    check_against_closed_loop(&config, SensorParams::default(), 0, &records);
    // The perfect sensor: the measurement is the true pose.
    let last = records.last().unwrap();
    assert_eq!(last.measurement[1..4], last.state[0..3]);

    // The CSV holds the same values, each reading back to the same f32.
    let csv = dir.path().join("fig7.csv");
    let out = cli(&["trace", repo().join("examples/paper/fig7.toml").to_str().unwrap(), "-o", csv.to_str().unwrap()]);
    assert!(out.status.success());
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), Record::COLUMNS.join(","));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), records.len());
    for (k, (row, r)) in rows.iter().zip(&records).enumerate().step_by(997) {
        let values: Vec<u32> = row.split(',').map(|v| v.parse::<f32>().unwrap().to_bits()).collect();
        assert_eq!(values, r.values().map(f32::to_bits).to_vec(), "row {k}");
    }
}

#[test]
fn real_world_trace_is_the_closed_loop_in_f32() {
    let dir = tempfile::tempdir().unwrap();
    let toml = dir.path().join("rw.toml");
    std::fs::write(
        &toml,
        r#"
[robot]
viscous_friction = 0.01
[drive]
kind = "dc_motor"
current_max = 8.0
[world]
slope_deg = 4.0
slope_direction_deg = 60.0
# Periods that are exact in f32 (powers of two): the core's whole-multiple check has a
# relative tolerance of 1e-9, tighter than f32 rounding, so 1 / 50 Hz against 2 ms fails
# in f32.
[sensor]
rate_hz = 64.0
latency = 0.03125
position_noise = 0.003
heading_noise_deg = 0.4
encoder_counts = 1024
seed = 11
[controller]
kind = "lyapunov"
control_dt = 0.001953125
[controller.model]
mass = 5.5
[sim]
t_end = 3.0
dt = 0.0009765625
log_dt = 0.015625
[[run]]
goal = { x = 0.5, y = -0.4, theta_deg = -30.0 }
[[run]]
start = { x = 0.2, y = 0.1, theta_deg = 170.0 }
goal = { x = -0.6, y = 0.4, theta_deg = 45.0 }
"#,
    )
    .unwrap();
    let bin = dir.path().join("rw.bin");
    let out = cli(&["trace", toml.to_str().unwrap(), "-o", bin.to_str().unwrap(), "--run", "1"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (config, records) = read_trace(&bin);
    assert_eq!(records.len(), 1537);
    assert_eq!(config.steps_per_tick, 2);
    assert_eq!(config.model.mass, 5.5);
    assert_eq!(config.law.kind(), "lyapunov");
    let sensor = SensorParams {
        rate_hz: 64.0,
        latency: 0.03125,
        position_noise: 0.003,
        heading_noise_deg: 0.4,
        encoder_counts: 1024,
        seed: 11,
    };
    check_against_closed_loop(&config, sensor, 1, &records);
    // A noisy, late sensor: the measured pose is not the true one.
    assert!(records.iter().any(|r| r.measurement[1] != r.state[0]));
}

#[test]
fn bad_arguments_exit_2_naming_them() {
    let fig7 = repo().join("examples/paper/fig7.toml");
    let out = cli(&["trace", fig7.to_str().unwrap(), "-o", "/tmp/wmr-trace-test.txt"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("-o: cannot tell the trace format"), "{err}");
    let out = cli(&["trace", fig7.to_str().unwrap(), "-o", "/tmp/wmr-trace-test.bin", "--run", "2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--run: no run 2"));
    assert!(!Path::new("/tmp/wmr-trace-test.bin").exists(), "no output on bad input");
}
