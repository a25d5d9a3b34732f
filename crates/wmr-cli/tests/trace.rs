//! `wmr-cli trace`: the f32 run it records is `ClosedLoop`'s, tick for tick and bit for
//! bit (Fig. 7, a run with every real-world effect, the tracking laws on moving
//! references); the CSV form holds the same values; bad input exits 2 naming the argument.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use wmr_core::trace::{self, CONFIG_WORDS, Config, HEADER_WORDS, RECORD_WORDS, Record, ReferenceConfig};
use wmr_core::{ClosedLoop, Controller, Plant, Pose2, PoseSensor, SensorParams, WheelStage};

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

/// `ClosedLoop` (f32) from the trace's own config: every tick's true state, reference
/// state and held command must be the recorded ones.
fn check_against_closed_loop(config: &Config, sensor: SensorParams<f32>, run: u64, records: &[Record]) {
    let robot = config.robot.validate().unwrap();
    let model = config.model.validate().unwrap();
    let drive = config.drive.validate(&robot).unwrap();
    let plant = Plant::on(robot, drive, config.world.validate().unwrap(), config.start).unwrap();
    let law = config.law.build(model.params(), config.control_dt).unwrap();
    let wheels = WheelStage::new(&config.wheels, model.params(), &drive, config.control_dt).unwrap();
    let sensor = PoseSensor::<f32>::new(sensor, config.control_dt, run).unwrap();
    let reference = config.reference.build().unwrap();
    let mut sim = ClosedLoop::with_sensor(plant, sensor, Controller::new(law, wheels), reference, config.dt).unwrap();
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
        let at = trace::reference_values(&sim.last_tick().reference);
        assert_eq!(at.map(f32::to_bits), r.reference.map(f32::to_bits), "tick {k}: reference");
    }
}

/// The tracking examples (each tracking law, each moving kind but the line): the trace
/// carries the scenario's reference and law, the records are `ClosedLoop`'s in f32, and
/// the recorded reference is the analytic one (the circle, by hand).
#[test]
fn tracking_traces_are_the_closed_loop_in_f32() {
    let dir = tempfile::tempdir().unwrap();
    for (file, law, kind) in [
        ("circle", "kanayama", "circle"),
        ("figure_eight", "backstepping", "figure_eight"),
        ("waypoints", "pure_pursuit", "waypoints"),
    ] {
        let bin = dir.path().join(format!("{file}.bin"));
        let scenario = repo().join(format!("examples/tracking/{file}.toml"));
        let out = cli(&["trace", scenario.to_str().unwrap(), "-o", bin.to_str().unwrap(), "--run", "1"]);
        assert!(out.status.success(), "{file}: {}", String::from_utf8_lossy(&out.stderr));
        let (config, records) = read_trace(&bin);
        assert_eq!(config.law.kind(), law);
        assert_eq!(config.reference.build().unwrap().kind(), kind);
        check_against_closed_loop(&config, SensorParams::default(), 1, &records);
        if let ReferenceConfig::Circle(c) = config.reference {
            assert_eq!((c.center_x, c.center_y, c.radius, c.speed), (0.0, 0.0, 1.0, 0.3));
            assert_eq!(c.phase, (-90f64).to_radians() as f32);
            // C_ref(t) = center + R (cos phi, sin phi), phi = phase + (v / R) t, heading phi + pi/2.
            for r in records.iter().step_by(1999) {
                let phi = -std::f64::consts::FRAC_PI_2 + 0.3 * f64::from(r.t);
                let want = [phi.cos(), phi.sin(), phi + std::f64::consts::FRAC_PI_2, 0.3, 0.3, 0.0, 0.0];
                for (i, (got, want)) in r.reference.iter().zip(want).enumerate() {
                    let d = (f64::from(*got) - want).abs();
                    let d = if i == 2 {
                        (d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
                    } else {
                        d
                    };
                    assert!(d.abs() < 2e-5, "circle at t = {}: word {i} is {got}, by hand {want}", r.t);
                }
            }
        }
        // The reference moves: it is not the goal at rest of a stabilization trace.
        assert_ne!(records[0].reference[0..3], records[records.len() - 1].reference[0..3], "{file}");
        assert_eq!(config.start, Pose2::new(records[0].state[0], records[0].state[1], records[0].state[2]));
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
    assert_eq!(config.reference, ReferenceConfig::Goal(Pose2::new(1.0, 1.0, 120f64.to_radians() as f32)));
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
# Periods that are exact in f32 (powers of two); issue25_8_trace_accepts_a_50_hz_sensor
# has decimal ones.
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
    assert!(String::from_utf8_lossy(&out.stderr).contains("or pass --format"));
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("-o: cannot tell the trace format"), "{err}");
    let out = cli(&["trace", fig7.to_str().unwrap(), "-o", "/tmp/wmr-trace-test.bin", "--run", "2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--run: no run 2"));
    assert!(!Path::new("/tmp/wmr-trace-test.bin").exists(), "no output on bad input");
}

/// `trace FILE -o OUT ARGS...` in `dir`.
fn trace_in(dir: &Path, file: &Path, out: &str, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .current_dir(dir)
        .args(["trace", file.to_str().unwrap(), "-o", out])
        .args(args)
        .output()
        .expect("wmr-cli runs")
}

/// Exit 2 with one line on stderr containing `what`, and no panic.
fn assert_bad_input(o: &Output, what: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(what), "stderr lacks {what:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// A scenario of Fig. 7's robot with `sensor` (TOML lines of `[sensor]`) and `t_end`.
fn scenario_with(dir: &Path, name: &str, sensor: &str, t_end: f64) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(
        &path,
        format!(
            "[sensor]\n{sensor}\n[sim]\nt_end = {t_end}\n[[run]]\ngoal = {{ x = 1.0, y = 1.0, theta_deg = 120.0 }}\n"
        ),
    )
    .unwrap();
    path
}

/// Issue 25, item 8: `trace` refused a 50 Hz sensor with exit 1 ("does not hold in f32:
/// 1 / rate_hz must be a whole multiple of control_dt (got 0.0199999995)"), and 22 of 40
/// common rate/latency pairs. Now the trace is written and is `ClosedLoop` in f32 with
/// that sensor, tick for tick.
#[test]
fn issue25_8_trace_accepts_a_50_hz_sensor() {
    let dir = tempfile::tempdir().unwrap();
    for (rate, latency) in [(50.0f32, 0.02f32), (20.0, 0.1), (100.0, 0.03), (40.0, 0.025)] {
        let sensor = format!("rate_hz = {rate}\nlatency = {latency}\nposition_noise = 0.002\nseed = 3");
        let toml = scenario_with(dir.path(), "s.toml", &sensor, 2.0);
        let o = trace_in(dir.path(), &toml, "t.bin", &[]);
        assert!(o.status.success(), "{rate} Hz, {latency} s: {}", String::from_utf8_lossy(&o.stderr));
        let (config, records) = read_trace(&dir.path().join("t.bin"));
        assert_eq!(records.len(), 2001);
        let params = SensorParams { rate_hz: rate, latency, position_noise: 0.002, seed: 3, ..SensorParams::default() };
        check_against_closed_loop(&config, params, 0, &records);
    }
}

/// Issue 25, item 8: what does not hold in f32 is bad input (exit 2), not a failure of
/// the work (exit 1): a mass that overflows f32.
#[test]
fn issue25_8_a_scenario_that_overflows_f32_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let toml = dir.path().join("heavy.toml");
    std::fs::write(&toml, "[robot]\nmass = 1e39\n[sim]\nt_end = 1.0\n[[run]]\ngoal = { x = 1.0 }\n").unwrap();
    let o = trace_in(dir.path(), &toml, "t.bin", &[]);
    assert_bad_input(&o, "does not hold in f32");
    assert!(!dir.path().join("t.bin").exists());
}

/// Issue 25, item 9: `-o` was checked only after the whole simulation (and a long run was
/// refused for memory first). Now an OUT that cannot be written is refused at once, by
/// its own reason, even for a run of 1e6 s.
#[test]
fn issue25_9_out_is_checked_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let toml = scenario_with(dir.path(), "long.toml", "", 1e6);
    let o = trace_in(dir.path(), &toml, "missing/t.bin", &[]);
    assert_bad_input(&o, "the directory missing does not exist");
    let o = trace_in(dir.path(), &toml, ".", &["--format", "csv"]);
    assert_bad_input(&o, "is a directory");
}

/// Issue 25, item 9: a character device was refused ("not a regular file"), which the
/// README says is written to as data comes. Now /dev/null and stdout take the trace; the
/// binary trace on stdout is the file's, byte for byte.
#[test]
fn issue25_9_trace_streams_to_devices_and_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let fig7 = repo().join("examples/paper/fig7.toml");
    for format in ["bin", "csv"] {
        let o = trace_in(dir.path(), &fig7, "/dev/null", &["--format", format]);
        assert!(o.status.success(), "{format}: {}", String::from_utf8_lossy(&o.stderr));
        assert!(String::from_utf8_lossy(&o.stdout).starts_with("trace: 60001 ticks"));
        let o = trace_in(dir.path(), &fig7, "-", &["--format", format]);
        assert!(o.status.success(), "{format}: {}", String::from_utf8_lossy(&o.stderr));
        // The summary goes to stderr; stdout is the trace alone.
        assert!(String::from_utf8_lossy(&o.stderr).contains("trace: 60001 ticks"));
        let file = format!("fig7.{format}");
        assert!(trace_in(dir.path(), &fig7, &file, &[]).status.success());
        assert!(o.stdout == std::fs::read(dir.path().join(&file)).unwrap(), "{format}: stdout differs from the file");
    }
}

/// A run that diverges before t_end (a start near the edge of the 1 km box, driven out of
/// it): the binary header counts the ticks written, in a file (rewritten at the end) and
/// on a stream (counted first), and both hold the same bytes.
#[test]
fn a_diverging_trace_has_the_true_tick_count() {
    let dir = tempfile::tempdir().unwrap();
    let toml = dir.path().join("edge.toml");
    std::fs::write(
        &toml,
        "[sim]\nt_end = 60.0\n[[run]]\nstart = { x = 999.9, y = 0.0, theta_deg = 0.0 }\ngoal = { x = 0.0, y = 0.0, theta_deg = 0.0 }\n",
    )
    .unwrap();
    let o = trace_in(dir.path(), &toml, "t.bin", &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let said = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(said.contains("diverged"), "{said}");
    let (_, records) = read_trace(&dir.path().join("t.bin"));
    assert!(records.len() < 60_001 && records.len() > 1, "{} ticks", records.len());
    assert!(said.starts_with(&format!("trace: {} ticks", records.len())), "{said}");
    let o = trace_in(dir.path(), &toml, "-", &["--format", "bin"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.stdout == std::fs::read(dir.path().join("t.bin")).unwrap(), "the stream differs from the file");
}

/// Issue 25, item 9: `trace` allocated every tick at once (9.6 GB for t_end = 1e5 s) and
/// aborted under a 2 GB cap. Now, under `ulimit -v` of 2 GiB, the trace of 1e5 s streams
/// from its first tick: the first 20,000 rows arrive (and are Fig. 7's first ticks) while
/// the run goes on; then the test stops it.
#[test]
fn issue25_9_a_long_trace_streams_in_bounded_memory() {
    use std::io::{BufRead as _, BufReader};
    let dir = tempfile::tempdir().unwrap();
    let toml = scenario_with(dir.path(), "long.toml", "", 1e5);
    let script = format!(
        "ulimit -v 2097152 && exec {} trace {} -o - --format csv",
        env!("CARGO_BIN_EXE_wmr-cli"),
        toml.display()
    );
    let mut child = Command::new("sh")
        .args(["-c", &script])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("sh runs");
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let header = lines.next().expect("a header line").expect("text");
    assert_eq!(header, Record::COLUMNS.join(","));
    let mut t_last = -1.0f32;
    for k in 0..20_000 {
        let Some(Ok(line)) = lines.next() else {
            let _ = child.kill();
            let out = child.wait_with_output().unwrap();
            panic!("the trace ended at row {k}: {}", String::from_utf8_lossy(&out.stderr));
        };
        let values: Vec<f32> = line.split(',').map(|v| v.parse().unwrap()).collect();
        assert_eq!(values.len(), RECORD_WORDS, "row {k}");
        assert!(values[0] > t_last, "row {k}: time goes forward");
        t_last = values[0];
    }
    // 1 ms control ticks from t = 0.
    assert!((t_last - 19.999).abs() < 1e-3, "{t_last}");
    assert_eq!(child.try_wait().unwrap(), None, "the run of 1e5 s is still going");
    child.kill().unwrap();
    child.wait().unwrap();
}
