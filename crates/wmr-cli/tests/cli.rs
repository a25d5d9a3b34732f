//! End-to-end tests of `wmr-cli` on a temp dir (issue 4).

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use wmr_core::{ClosedLoop, ControllerParams, DriveParams, FixedGoal, Plant, Pose2, Robot, Sample};
use wmr_scenario::{CSV_COLUMNS, SAMPLE_COLUMNS, sample_values};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("spawn wmr-cli")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn write(dir: &Path, name: &str, body: &str) -> PathBuf {
    let p = dir.join(name);
    fs::write(&p, body).unwrap();
    p
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<_> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

/// Two runs, 2 s each: short enough for a debug build.
const TWO_RUNS: &str = r#"
[sim]
t_end = 2.0
log_dt = 0.01
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
goal = { x = 1.0, y = 1.0, theta_deg = 120.0 }
[[run]]
label = "second"
start = { x = -0.5, y = 0.2, theta = 0.3 }
goal = { x = 0.0, y = 0.0, theta_deg = 0.0 }
"#;

/// The samples of one run, built with the core alone (no scenario crate).
fn core_samples(start: Pose2<f64>, goal: Pose2<f64>, n_steps: u64, log_every: u32) -> Vec<Sample<f64>> {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let ctrl = ControllerParams::paper().build(robot.params(), &drive).unwrap();
    let plant = Plant::new(robot, drive, start).unwrap();
    let mut lp = ClosedLoop::new(plant, ctrl, FixedGoal::new(goal).unwrap(), 1e-3).unwrap();
    let mut v = Vec::new();
    lp.run(n_steps, log_every, |s| v.push(*s));
    v
}

fn parse_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let body = fs::read_to_string(path).unwrap();
    let mut lines = body.lines();
    let header = lines.next().unwrap().split(',').map(str::to_owned).collect();
    let rows = lines
        .map(|l| l.split(',').map(|f| f.parse::<f64>().unwrap_or_else(|_| panic!("bad number {f:?}"))).collect())
        .collect();
    (header, rows)
}

#[test]
fn csv_equals_the_core_sample_for_sample() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "two.toml", TWO_RUNS);
    let out = dir.path().join("two.csv");
    let o = run(&["run", scen.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let (header, rows) = parse_csv(&out);
    assert_eq!(header, CSV_COLUMNS);
    let expected: Vec<(usize, Sample<f64>)> = [
        (0, core_samples(Pose2::new(0.0, 0.0, 0.0), Pose2::new(1.0, 1.0, 120f64.to_radians()), 2000, 10)),
        (1, core_samples(Pose2::new(-0.5, 0.2, 0.3), Pose2::new(0.0, 0.0, 0.0), 2000, 10)),
    ]
    .into_iter()
    .flat_map(|(i, v)| v.into_iter().map(move |s| (i, s)))
    .collect();
    assert_eq!(rows.len(), expected.len());
    assert_eq!(rows.len(), 2 * 201);
    for (row, (i, s)) in rows.iter().zip(&expected) {
        assert_eq!(row[0], *i as f64);
        // Bit for bit: the CSV text reads back to the very same f64.
        assert_eq!(&row[1..], &sample_values(s)[..], "run {i} t {}", s.t);
    }
    // First row t = 0, last row of each run t = t_end.
    assert_eq!(rows[0][1], 0.0);
    assert_eq!(rows[200][1], 2.0);
    // The summary: one line per run, in run order.
    let stdout = text(&o.stdout);
    let lines: Vec<_> = stdout.lines().collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    assert!(lines[0].starts_with("run 0 [(0, 0, 0 deg) -> (1, 1, 120 deg)]: final dl "), "{stdout}");
    assert!(lines[1].starts_with("run 1 [second]"), "{stdout}");
    assert_eq!(entries(dir.path()), ["two.csv", "two.toml"]);
}

#[test]
fn mcap_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "two.toml", TWO_RUNS);
    let out = dir.path().join("two.mcap");
    let o = run(&["run", scen.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let bytes = fs::read(&out).unwrap();

    // topic -> (schema name, message encoding, log times, messages)
    type Topic = (String, String, Vec<u64>, Vec<Vec<u8>>);
    let mut topics: BTreeMap<String, Topic> = BTreeMap::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let schema = m.channel.schema.as_ref().map(|s| s.name.clone()).unwrap_or_default();
        let e = topics.entry(m.channel.topic.clone()).or_insert((
            schema,
            m.channel.message_encoding.clone(),
            vec![],
            vec![],
        ));
        e.2.push(m.log_time);
        e.3.push(m.data.into_owned());
    }
    let per_sample = 201; // t_end / log_dt + 1
    for run in 0..2 {
        // The topics of crate::foxglove_topics (tests/foxglove.rs checks them in depth).
        let expect = [
            ("tf", "foxglove.FrameTransform", Some(per_sample)),
            ("sample", "wmr.Sample", Some(per_sample)),
            ("scene", "foxglove.SceneUpdate", Some(1)),
            ("path_tip", "foxglove.SceneUpdate", None),
        ];
        for (name, schema, count) in expect {
            let topic = format!("/run{run}/{name}");
            let (s, _, times, _) = topics.get(&topic).unwrap_or_else(|| panic!("missing {topic}: {:?}", topics.keys()));
            assert_eq!(s, schema, "{topic}");
            if let Some(count) = count {
                assert_eq!(times.len(), count, "{topic}");
            }
            assert!(times.windows(2).all(|w| w[0] <= w[1]), "{topic} log times not monotonic");
            if name != "path_tip" {
                assert_eq!(times[0], 0, "{topic} starts at t = 0");
            }
            if count.is_some_and(|c| c > 1) || name == "path_tip" {
                assert_eq!(*times.last().unwrap(), 2_000_000_000, "{topic} ends at t_end");
            }
        }
    }
    for (topic, (_, enc, _, _)) in &topics {
        assert_eq!(enc, "protobuf", "{topic}");
    }

    // The protobuf messages decode and carry the core's pose.
    use foxglove::Decode as _;
    use foxglove::messages::{FrameTransform, SceneUpdate};
    let core = core_samples(Pose2::new(0.0, 0.0, 0.0), Pose2::new(1.0, 1.0, 120f64.to_radians()), 2000, 10);
    let last = core.last().unwrap();
    let tf = FrameTransform::decode(&topics["/run0/tf"].3[200][..]).unwrap();
    assert_eq!((tf.parent_frame_id.as_str(), tf.child_frame_id.as_str()), ("world", "run0/base_link"));
    let t = tf.translation.unwrap();
    assert_eq!((t.x, t.y), (last.state.x, last.state.y));
    let q = tf.rotation.unwrap();
    assert!((2.0 * q.z.atan2(q.w) - last.state.theta).abs() < 1e-12);
    let scene = SceneUpdate::decode(&topics["/run0/scene"].3[0][..]).unwrap();
    let goal = scene.entities.iter().find(|e| e.id == "goal").unwrap();
    assert_eq!(goal.arrows[0].pose.unwrap().position.unwrap().x, 1.0);
    let tip = SceneUpdate::decode(&topics["/run0/path_tip"].3.last().unwrap()[..]).unwrap();
    let end = tip.entities[0].lines[0].points.last().unwrap();
    assert_eq!((end.x, end.y), (last.state.x, last.state.y));

    // The samples (protobuf wmr.Sample: field i + 1 is CSV column i + 1, a double) carry the
    // core's numbers.
    let (_, _, _, msgs) = &topics["/run0/sample"];
    assert_eq!(msgs.len(), core.len());
    for (msg, s) in msgs.iter().zip(&core) {
        assert_eq!(msg.len(), 9 * SAMPLE_COLUMNS.len());
        for (i, (name, x)) in SAMPLE_COLUMNS.iter().zip(sample_values(s)).enumerate() {
            assert_eq!(msg[9 * i], ((i as u8 + 1) << 3) | 1, "{name}: field key");
            let v = f64::from_le_bytes(msg[9 * i + 1..9 * i + 9].try_into().unwrap());
            assert_eq!(v.to_bits(), x.to_bits(), "{name}");
        }
    }
}

#[test]
fn bad_inputs_exit_nonzero_name_the_key_and_write_nothing() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad");
    let mut files: Vec<_> = fs::read_dir(&corpus).unwrap().map(|e| e.unwrap().path()).collect();
    files.sort();
    assert!(files.len() >= 25, "corpus has {} files", files.len());
    let dir = tempfile::tempdir().unwrap();
    // An existing OUT must survive a bad input untouched.
    let kept = write(dir.path(), "kept.csv", "precious\n");
    for f in &files {
        let body = fs::read_to_string(f).unwrap();
        // Every `# expect: <substring>` line must appear in the message.
        let expects: Vec<&str> = body.lines().filter_map(|l| l.strip_prefix("# expect: ")).collect();
        assert!(!expects.is_empty(), "{f:?}: no # expect");
        for out in [dir.path().join("out.csv"), dir.path().join("out.mcap"), kept.clone()] {
            let o = run(&["run", f.to_str().unwrap(), "-o", out.to_str().unwrap()]);
            let err = text(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{f:?}: {err}");
            for expect in &expects {
                assert!(err.contains(expect), "{f:?}: stderr {err:?} lacks {expect:?}");
            }
            assert!(!err.contains("panicked"), "{f:?}: {err}");
            assert_eq!(err.trim_end().lines().count(), 1, "{f:?}: one line: {err}");
            assert!(o.stdout.is_empty(), "{f:?}");
            assert_eq!(entries(dir.path()), ["kept.csv"], "{f:?}");
        }
        let o = run(&["check", f.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{f:?}");
        assert!(expects.iter().all(|e| text(&o.stderr).contains(e)), "{f:?}");
    }
    assert_eq!(fs::read_to_string(&kept).unwrap(), "precious\n");
}

#[test]
fn check_prints_the_resolved_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "two.toml", TWO_RUNS);
    let o = run(&["check", scen.to_str().unwrap()]);
    assert!(o.status.success());
    let dumped = text(&o.stdout);
    for key in ["mass = 5.0", "servo_kp = 14.0", "log_dt = 0.01", "name = \"two\"", "label = \"second\""] {
        assert!(dumped.contains(key), "{key} in {dumped}");
    }
    let a = wmr_scenario::Scenario::from_toml_str(&dumped, "x").unwrap();
    let b = wmr_scenario::Scenario::from_path(&scen).unwrap();
    assert_eq!(a, b);
}

#[test]
fn unknown_output_extension_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "two.toml", TWO_RUNS);
    let o = run(&["run", scen.to_str().unwrap(), "-o", dir.path().join("out.txt").to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("--format"));
    let o =
        run(&["run", scen.to_str().unwrap(), "-o", dir.path().join("out.txt").to_str().unwrap(), "--format", "csv"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(fs::read_to_string(dir.path().join("out.txt")).unwrap().starts_with("run,t,"));
}

/// The paper's law diverges from (1, 0, 0) towards the goal (0, 0, 0) that lies behind
/// it: it leaves the 1 km box at t = 16.42 s (default parameters).
#[test]
fn divergent_run_is_reported_with_finite_rows_only() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(
        dir.path(),
        "div.toml",
        "[sim]\nt_end = 20.0\nlog_dt = 0.1\n[[run]]\nlabel = \"behind\"\nstart = { x = 1.0 }\ngoal = {}\n",
    );
    let out = dir.path().join("div.csv");
    let o = run(&["run", scen.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let summary = text(&o.stdout);
    assert!(summary.contains("[behind]") && summary.contains("diverged at t = 16.4"), "{summary}");
    let (_, rows) = parse_csv(&out);
    assert!(rows.iter().flatten().all(|v| v.is_finite()));
    let last_t = rows.last().unwrap()[1];
    assert!(last_t > 16.0 && last_t < 20.0, "{last_t}");
    assert!(rows.len() < 201);
    assert!(rows.windows(2).all(|w| w[0][1] < w[1][1]));
}

/// A long scenario: 8 runs of 200 s logged every ms (~24 MB of samples per run).
const LONG: &str = "[sim]\nt_end = 200.0\nlog_dt = 0.001\n[[run]]\ngoal = { x = 1.0 }\n[[run]]\ngoal = { x = 1.0 }\n[[run]]\ngoal = { x = 1.0 }\n[[run]]\ngoal = { x = 1.0 }\n[[run]]\ngoal = { x = 1.0 }\n[[run]]\ngoal = { x = 1.0 }\n[[run]]\ngoal = { x = 1.0 }\n[[run]]\ngoal = { x = 1.0 }\n";

/// Spawns a long run, waits until the temporary file has data, then signals it.
fn interrupt_mid_write(signal: &str) -> (tempfile::TempDir, PathBuf, Vec<String>) {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "long.toml", LONG);
    let out = dir.path().join("long.csv");
    fs::write(&out, "old contents\n").unwrap();
    let mut child = bin()
        .args(["run", scen.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let started = Instant::now();
    loop {
        let growing = fs::read_dir(dir.path()).unwrap().flatten().any(|e| {
            e.file_name().to_string_lossy().ends_with(".tmp")
                && e.metadata().map(|m| m.len() > 1_000_000).unwrap_or(false)
        });
        if growing {
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "finished before it could be interrupted");
        assert!(started.elapsed() < Duration::from_secs(120), "no output after 120 s");
        std::thread::sleep(Duration::from_millis(20));
    }
    let pid = child.id().to_string();
    assert!(Command::new("kill").args([signal, &pid]).status().unwrap().success());
    let status = child.wait().unwrap();
    assert!(!status.success());
    let left = entries(dir.path());
    (dir, out, left)
}

#[test]
fn killed_mid_write_leaves_no_out() {
    let (_dir, out, left) = interrupt_mid_write("-KILL");
    // SIGKILL cannot be caught: the temporary file stays, OUT keeps its old contents.
    assert_eq!(fs::read_to_string(&out).unwrap(), "old contents\n");
    assert!(left.iter().all(|n| n == "long.csv" || n == "long.toml" || n.starts_with(".long.csv.")), "{left:?}");
}

#[test]
fn ctrl_c_mid_write_removes_the_temporary_and_keeps_out() {
    let (_dir, out, left) = interrupt_mid_write("-INT");
    assert_eq!(fs::read_to_string(&out).unwrap(), "old contents\n");
    assert_eq!(left, ["long.csv", "long.toml"]);
}

/// The output does not depend on the thread count nor on how runs are buffered:
/// streaming (budget below one run), batches of one run, and all runs at once.
#[test]
fn output_is_the_same_streamed_batched_and_single_threaded() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "two.toml", TWO_RUNS);
    let mut outputs = Vec::new();
    for (i, (budget, threads)) in
        [("1", "2"), ("40000", "2"), ("1000000000", "2"), ("1000000000", "1")].iter().enumerate()
    {
        for ext in ["csv", "mcap"] {
            let out = dir.path().join(format!("out{i}.{ext}"));
            let o = bin()
                .args(["run", scen.to_str().unwrap(), "-o", out.to_str().unwrap()])
                .env("WMR_CLI_BUFFER_BYTES", budget)
                .env("RAYON_NUM_THREADS", threads)
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", text(&o.stderr));
            outputs.push((ext, fs::read(&out).unwrap(), o.stdout));
        }
    }
    for w in outputs.chunks(2).collect::<Vec<_>>().windows(2) {
        for (a, b) in w[0].iter().zip(w[1]) {
            assert_eq!(a.0, b.0);
            assert!(a.1 == b.1, "{} output differs", a.0);
            assert_eq!(a.2, b.2, "summary differs");
        }
    }
}
