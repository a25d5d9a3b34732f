//! What Foxglove reads from `wmr-cli run ... -o OUT.mcap` and `wmr-cli layout` (issue 13):
//! the topics and their schemas, samples equal to the CSV bit for bit on the exact log
//! grid, the path the 3D panel shows after a seek (Foxglove reads back only the latest
//! message of each topic), the bytes a seek decompresses, and a layout that names only
//! topics and fields the file has. The file is also read by Foxglove's own TypeScript
//! readers (`tests/foxglove-js/check.mjs`); where node or its packages are missing that
//! test records a skip, a failure under `WMR_REQUIRE=node` (`tests/skip/mod.rs`).

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use foxglove::messages::{FrameTransform, PoseInFrame, SceneUpdate};
use prost::Message as _;
use prost_types::FileDescriptorSet;
use prost_types::field_descriptor_proto::Type;
use wmr_scenario::{MEASURED_COLUMNS, SAMPLE_COLUMNS};

use crate::skip;

pub(crate) fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wmr-cli")).args(args).output().expect("spawn wmr-cli")
}

pub(crate) fn ok(args: &[&str]) -> Output {
    let o = run(args);
    assert!(o.status.success(), "wmr-cli {args:?}: {}", String::from_utf8_lossy(&o.stderr));
    o
}

pub(crate) fn write(dir: &Path, name: &str, body: &str) -> PathBuf {
    let p = dir.join(name);
    fs::write(&p, body).unwrap();
    p
}

pub(crate) fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Two runs of 2 s at 10 ms: short enough for a debug build.
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

/// A late, noisy sensor at 20 Hz: the measured pose changes every 50 ms.
const WITH_SENSOR: &str = r#"
[sim]
t_end = 3.0
log_dt = 0.01
[sensor]
rate_hz = 20.0
latency = 0.02
position_noise = 0.002
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
goal = { x = 1.0, y = 1.0, theta_deg = 120.0 }
"#;

fn fig7() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/paper/fig7.toml")
}

/// One message of a file.
pub(crate) struct Msg {
    pub(crate) topic: String,
    pub(crate) schema: String,
    pub(crate) log_time: u64,
    pub(crate) data: Vec<u8>,
}

pub(crate) fn messages(path: &Path) -> Vec<Msg> {
    let bytes = fs::read(path).unwrap();
    mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| {
            let m = m.unwrap();
            Msg {
                topic: m.channel.topic.clone(),
                schema: m.channel.schema.as_ref().map(|s| s.name.clone()).unwrap_or_default(),
                log_time: m.log_time,
                data: m.data.into_owned(),
            }
        })
        .collect()
}

/// A `wmr.Sample` message as field number -> f64 (every field is a double, wire type 1).
fn sample_fields(mut b: &[u8]) -> BTreeMap<u32, f64> {
    let mut out = BTreeMap::new();
    while !b.is_empty() {
        let (mut key, mut shift) = (0u32, 0);
        loop {
            let byte = b[0];
            b = &b[1..];
            key |= u32::from(byte & 0x7f) << shift;
            shift += 7;
            if byte < 0x80 {
                break;
            }
        }
        assert_eq!(key & 7, 1, "every wmr.Sample field is a double");
        out.insert(key >> 3, f64::from_le_bytes(b[..8].try_into().unwrap()));
        b = &b[8..];
    }
    out
}

fn csv_rows(path: &Path) -> Vec<Vec<f64>> {
    fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect()
}

#[test]
fn topics_schemas_and_samples_equal_the_csv_on_the_exact_log_grid() {
    let dir = tempfile::tempdir().unwrap();
    for (name, body, measured) in [("two", TWO_RUNS, false), ("sensor", WITH_SENSOR, true)] {
        let scen = write(dir.path(), &format!("{name}.toml"), body);
        let mcap_path = dir.path().join(format!("{name}.mcap"));
        let csv_path = dir.path().join(format!("{name}.csv"));
        ok(&["run", s(&scen), "-o", s(&mcap_path)]);
        ok(&["run", s(&scen), "-o", s(&csv_path)]);
        let msgs = messages(&mcap_path);
        let rows = csv_rows(&csv_path);
        let runs = if measured { 1 } else { 2 };

        // Topics and schemas.
        let bytes = fs::read(&mcap_path).unwrap();
        let summary = mcap::read::Summary::read(&bytes).unwrap().unwrap();
        let mut topics: BTreeMap<String, (String, String)> = BTreeMap::new();
        for c in summary.channels.values() {
            let schema = c.schema.as_ref().unwrap();
            assert_eq!(
                (c.message_encoding.as_str(), schema.encoding.as_str()),
                ("protobuf", "protobuf"),
                "{}",
                c.topic
            );
            topics.insert(c.topic.clone(), (schema.name.clone(), c.message_encoding.clone()));
        }
        let mut want = BTreeMap::new();
        for r in 0..runs {
            for (t, schema) in [
                ("tf", "foxglove.FrameTransform"),
                ("sample", "wmr.Sample"),
                ("scene", "foxglove.SceneUpdate"),
                ("path", "foxglove.SceneUpdate"),
                ("path_tip", "foxglove.SceneUpdate"),
            ]
            .into_iter()
            .chain(measured.then_some(("pose_meas", "foxglove.PoseInFrame")))
            {
                want.insert(format!("/run{r}/{t}"), (schema.to_owned(), "protobuf".to_owned()));
            }
        }
        assert_eq!(topics, want);

        // wmr.Sample is strict: exactly the CSV's columns (and the measured pose), doubles.
        let schema = summary.schemas.values().find(|s| s.name == "wmr.Sample").unwrap();
        let set = FileDescriptorSet::decode(&schema.data[..]).unwrap();
        assert_eq!(set.file.len(), 1);
        let file = &set.file[0];
        assert_eq!((file.package(), file.message_type.len()), ("wmr", 1));
        let fields: Vec<(String, i32, Type)> =
            file.message_type[0].field.iter().map(|f| (f.name().to_owned(), f.number(), f.r#type())).collect();
        let names: Vec<&str> =
            SAMPLE_COLUMNS.iter().chain(if measured { &MEASURED_COLUMNS[..] } else { &[] }).copied().collect();
        let expect: Vec<(String, i32, Type)> =
            names.iter().enumerate().map(|(i, n)| ((*n).to_owned(), i as i32 + 1, Type::Double)).collect();
        assert_eq!(fields, expect);

        // Samples: the CSV's numbers bit for bit, log time exactly k * 10 ms.
        let samples: Vec<&Msg> = msgs.iter().filter(|m| m.schema == "wmr.Sample").collect();
        assert_eq!(samples.len(), rows.len());
        let mut k_of_run = vec![0u64; runs];
        for (m, row) in samples.iter().zip(&rows) {
            let r = row[0] as usize;
            assert_eq!(m.topic, format!("/run{r}/sample"));
            let f = sample_fields(&m.data);
            assert_eq!(f.len(), names.len());
            for (i, v) in f.values().enumerate() {
                assert_eq!(v.to_bits(), row[1 + i].to_bits(), "{} {} at t = {}", m.topic, names[i], row[1]);
            }
            assert_eq!(m.log_time, k_of_run[r] * 10_000_000, "{} sample {} off the log grid", m.topic, k_of_run[r]);
            k_of_run[r] += 1;
        }

        // tf: one per sample, same log time, stamp = log time, the sample's pose.
        for r in 0..runs {
            let tfs: Vec<&Msg> = msgs.iter().filter(|m| m.topic == format!("/run{r}/tf")).collect();
            let mine: Vec<&Vec<f64>> = rows.iter().filter(|row| row[0] as usize == r).collect();
            assert_eq!(tfs.len(), mine.len());
            for (m, row) in tfs.iter().zip(&mine) {
                let tf = FrameTransform::decode(&m.data[..]).unwrap();
                assert_eq!(
                    (tf.parent_frame_id.as_str(), tf.child_frame_id.clone()),
                    ("world", format!("run{r}/base_link"))
                );
                let st = tf.timestamp.unwrap();
                assert_eq!(u64::from(st.sec()) * 1_000_000_000 + u64::from(st.nsec()), m.log_time);
                let t = tf.translation.unwrap();
                assert_eq!((t.x, t.y, t.z), (row[2], row[3], 0.0));
                let q = tf.rotation.unwrap();
                let dtheta = 2.0 * q.z.atan2(q.w) - row[4];
                assert!((dtheta - std::f64::consts::TAU * (dtheta / std::f64::consts::TAU).round()).abs() < 1e-12);
            }
        }

        // pose_meas: sent when the measured pose changes, and only then.
        if measured {
            let meas: Vec<&Msg> = msgs.iter().filter(|m| m.topic == "/run0/pose_meas").collect();
            let mut changes = Vec::new();
            let mut last: Option<[u64; 3]> = None;
            for row in &rows {
                let p = [row[16].to_bits(), row[17].to_bits(), row[18].to_bits()];
                if last != Some(p) {
                    changes.push(row);
                    last = Some(p);
                }
            }
            assert!(changes.len() > 10 && changes.len() < rows.len() / 3, "{} changes", changes.len());
            assert_eq!(meas.len(), changes.len());
            for (m, row) in meas.iter().zip(&changes) {
                let p = PoseInFrame::decode(&m.data[..]).unwrap().pose.unwrap();
                assert_eq!((p.position.unwrap().x, p.position.unwrap().y), (row[16], row[17]));
                assert_eq!(m.log_time, (row[1] * 1e9).round() as u64);
            }
        }

        // The scene: at t = 0 the body (locked to base_link) and the goal arrow of each run.
        for r in 0..runs {
            let scene = msgs.iter().find(|m| m.topic == format!("/run{r}/scene")).unwrap();
            assert_eq!(scene.log_time, 0);
            let u = SceneUpdate::decode(&scene.data[..]).unwrap();
            let body = u.entities.iter().find(|e| e.id == "body").unwrap();
            assert!(body.frame_locked);
            assert_eq!(body.frame_id, format!("run{r}/base_link"));
            let goal = u.entities.iter().find(|e| e.id == "goal").unwrap();
            let gp = goal.arrows[0].pose.unwrap().position.unwrap();
            let expect = if r == 0 { (1.0, 1.0) } else { (0.0, 0.0) };
            assert_eq!((gp.x, gp.y), expect);
        }
    }
}

/// 3 s of Fig. 7 whose wheels slip on asphalt (examples/slip.toml's robot).
const SLIPPING: &str = include_str!("fixtures/slip-3s.toml");

/// 3 s of two runs tracking a figure-eight (examples/tracking/figure_eight.toml, shorter).
const TRACKING: &str = r#"
[reference]
kind = "figure_eight"
width = 2.0
height = 1.0
period = 30.0
[controller]
kind = "kanayama"
[sim]
t_end = 3.0
log_dt = 0.01
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 45.0 }
[[run]]
start = { x = 0.1, y = -0.1, theta_deg = 65.0 }
"#;

/// Every column group at once: tracking on odometry, on wheels that slip.
const EVERYTHING: &str = r#"
[robot]
traction = "slip"
friction_coefficient = 0.8
caster_offset = 0.35
com_height = 0.1
[sensor]
pose = "odometry"
encoder_counts = 4096
[reference]
kind = "figure_eight"
width = 2.0
height = 1.0
period = 30.0
[controller]
kind = "kanayama"
[sim]
t_end = 2.0
log_dt = 0.01
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 45.0 }
"#;

fn odometry_3s() -> String {
    fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/odometry-3s.toml")).unwrap()
}

/// The names of `wmr.Sample`'s fields in an MCAP file, in field-number order (checked to be
/// doubles numbered 1, 2, ...).
fn sample_schema_fields(bytes: &[u8]) -> Vec<String> {
    let summary = mcap::read::Summary::read(bytes).unwrap().unwrap();
    let schema = summary.schemas.values().find(|s| s.name == "wmr.Sample").unwrap();
    let set = FileDescriptorSet::decode(&schema.data[..]).unwrap();
    let fields = &set.file[0].message_type[0].field;
    for (i, f) in fields.iter().enumerate() {
        assert_eq!((f.number(), f.r#type()), (i as i32 + 1, Type::Double), "{}", f.name());
    }
    fields.iter().map(|f| f.name().to_owned()).collect()
}

/// Issue text: "The CSV and MCAP carry the true pose, the odometry pose and the fused pose
/// as separate columns and channels", and a tracking run's reference: every CSV column is
/// a field of `/runN/sample` in the CSV's order with the same f64, for runs on odometry,
/// with wheels that slip, tracking a reference, and all three at once; and the new topics
/// (`pose_odom`, `tf_ref`, `reference`) are there exactly when they should be.
#[test]
fn every_csv_column_of_odometry_slip_and_tracking_runs_is_in_the_sample_topic() {
    let dir = tempfile::tempdir().unwrap();
    let odometry = odometry_3s();
    let cases: [(&str, &str, usize, &[&str]); 4] = [
        ("odometry", &odometry, 1, &["pose_meas", "pose_odom"]),
        ("slip", SLIPPING, 1, &[]),
        ("tracking", TRACKING, 2, &["tf_ref", "reference"]),
        ("everything", EVERYTHING, 1, &["pose_meas", "pose_odom", "tf_ref", "reference"]),
    ];
    for (name, body, runs, extra_topics) in cases {
        let scen = write(dir.path(), &format!("{name}.toml"), body);
        let mcap_path = dir.path().join(format!("{name}.mcap"));
        let csv_path = dir.path().join(format!("{name}.csv"));
        ok(&["run", s(&scen), "-o", s(&mcap_path)]);
        ok(&["run", s(&csv_path.with_extension("toml")), "-o", s(&csv_path)]);
        let text = fs::read_to_string(&csv_path).unwrap();
        let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
        let rows = csv_rows(&csv_path);
        let bytes = fs::read(&mcap_path).unwrap();

        // The schema: the CSV header after `run`, in order.
        assert_eq!(sample_schema_fields(&bytes), header[1..], "{name}: wmr.Sample fields");
        let group = |cols: &[&str]| cols.iter().all(|c| header.contains(c));
        match name {
            "odometry" => assert!(group(&["x_meas", "x_odom", "theta_odom"]) && !group(&["slip_r"])),
            "slip" => assert!(group(&["slip_r", "n_l"]) && !group(&["x_odom"])),
            "tracking" => assert!(group(&["x_ref", "omega_ref"]) && !group(&["x_meas"])),
            _ => assert!(group(&["x_meas", "x_odom", "slip_r", "n_l", "x_ref", "omega_ref"])),
        }

        // The topics: the five of every run and those of this kind of run, no others.
        let summary = mcap::read::Summary::read(&bytes).unwrap().unwrap();
        let topics: BTreeMap<String, String> =
            summary.channels.values().map(|c| (c.topic.clone(), c.schema.as_ref().unwrap().name.clone())).collect();
        let mut want = BTreeMap::new();
        for r in 0..runs {
            for t in ["tf", "sample", "scene", "path", "path_tip"].iter().chain(extra_topics) {
                let schema = match *t {
                    "tf" | "tf_ref" => "foxglove.FrameTransform",
                    "sample" => "wmr.Sample",
                    "pose_meas" | "pose_odom" => "foxglove.PoseInFrame",
                    _ => "foxglove.SceneUpdate",
                };
                want.insert(format!("/run{r}/{t}"), schema.to_owned());
            }
        }
        assert_eq!(topics, want, "{name}");

        // Every sample: the CSV row's numbers bit for bit.
        let msgs = messages(&mcap_path);
        let samples: Vec<&Msg> = msgs.iter().filter(|m| m.schema == "wmr.Sample").collect();
        assert_eq!(samples.len(), rows.len(), "{name}");
        for (m, row) in samples.iter().zip(&rows) {
            assert_eq!(m.topic, format!("/run{}/sample", row[0]));
            let f: Vec<f64> = sample_fields(&m.data).into_values().collect();
            assert_eq!(f.len(), header.len() - 1, "{name}");
            for (i, v) in f.iter().enumerate() {
                // The same f64 (the CSV writes -0 as 0: its one value that reads back otherwise).
                let same = v.to_bits() == row[1 + i].to_bits() || (*v == 0.0 && row[1 + i] == 0.0);
                assert!(same, "{name} {} {} at t = {}: {v} vs {}", m.topic, header[1 + i], row[1], row[1 + i]);
            }
        }
        let col = |c: &str| header.iter().position(|h| *h == c).unwrap();

        // pose_odom: the dead-reckoned pose whenever it changes, apart from pose_meas (fused).
        if extra_topics.contains(&"pose_odom") {
            let (x, y) = (col("x_odom"), col("y_odom"));
            let mut changes = Vec::new();
            for row in &rows {
                if changes.last().is_none_or(|c: &&Vec<f64>| (c[x], c[y]) != (row[x], row[y])) {
                    changes.push(row);
                }
            }
            let odom: Vec<&Msg> = msgs.iter().filter(|m| m.topic == "/run0/pose_odom").collect();
            assert!(changes.len() > 10, "{name}: {} changes", changes.len());
            assert_eq!(odom.len(), changes.len(), "{name}: one pose_odom message per change");
            for (m, row) in odom.iter().zip(&changes) {
                let p = PoseInFrame::decode(&m.data[..]).unwrap();
                assert_eq!(p.frame_id, "world");
                let at = p.pose.unwrap().position.unwrap();
                assert_eq!((at.x, at.y), (row[x], row[y]), "{name}");
                assert_eq!(m.log_time, (row[1] * 1e9).round() as u64);
            }
            let meas = msgs.iter().filter(|m| m.topic == "/run0/pose_meas").count();
            assert!(meas > 0, "{name}: no fused pose");
        }

        // A reference: tf_ref every sample at (x_ref, y_ref, theta_ref); `reference` once at
        // t = 0 with the dashed path on the reference's positions and the ghost on its frame.
        if extra_topics.contains(&"reference") {
            let (x, y, th) = (col("x_ref"), col("y_ref"), col("theta_ref"));
            for r in 0..runs {
                let mine: Vec<&Vec<f64>> = rows.iter().filter(|row| row[0] as usize == r).collect();
                let tfs: Vec<&Msg> = msgs.iter().filter(|m| m.topic == format!("/run{r}/tf_ref")).collect();
                assert_eq!(tfs.len(), mine.len(), "{name} run {r}");
                for (m, row) in tfs.iter().zip(&mine) {
                    let tf = FrameTransform::decode(&m.data[..]).unwrap();
                    assert_eq!(
                        (tf.parent_frame_id.as_str(), tf.child_frame_id.clone()),
                        ("world", format!("run{r}/reference"))
                    );
                    let t = tf.translation.unwrap();
                    assert_eq!((t.x, t.y), (row[x], row[y]));
                    let q = tf.rotation.unwrap();
                    let d = 2.0 * q.z.atan2(q.w) - row[th];
                    assert!((d - std::f64::consts::TAU * (d / std::f64::consts::TAU).round()).abs() < 1e-12);
                }
                let refs: Vec<&Msg> = msgs.iter().filter(|m| m.topic == format!("/run{r}/reference")).collect();
                assert_eq!((refs.len(), refs[0].log_time), (1, 0), "{name} run {r}: drawn once, at t = 0");
                let u = SceneUpdate::decode(&refs[0].data[..]).unwrap();
                let ghost = u.entities.iter().find(|e| e.id == "ghost").unwrap();
                assert!(ghost.frame_locked && ghost.frame_id == format!("run{r}/reference"));
                assert!(ghost.cubes[0].color.unwrap().a < 0.5, "the ghost is translucent");
                let path = u.entities.iter().find(|e| e.id == "reference_path").unwrap();
                assert_eq!(path.frame_id, "world");
                let line = &path.lines[0];
                assert_eq!(line.r#type, 2, "LINE_LIST: dashes");
                assert!(line.points.len() >= 4 && line.points.len() % 2 == 0, "{} points", line.points.len());
                // Every dash end lies on the reference's logged positions (within 1 mm).
                let logged: Vec<(f64, f64)> = mine.iter().map(|row| (row[x], row[y])).collect();
                for p in &line.points {
                    let d = logged.windows(2).map(|w| seg_dist((p.x, p.y), w[0], w[1])).fold(f64::INFINITY, f64::min);
                    assert!(d < 1e-3, "{name} run {r}: dash end ({}, {}) {d} m off the reference", p.x, p.y);
                }
            }
        }
    }
}

/// Distance from `p` to segment a-b, m.
fn seg_dist(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let l2 = dx * dx + dy * dy;
    let t = if l2 == 0.0 { 0.0 } else { (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / l2).clamp(0.0, 1.0) };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

/// Segments bucketed on a grid of `CELL` m, for distances up to `CELL`; each segment
/// carries its index along its polyline.
struct Grid(HashMap<(i64, i64), Vec<Seg>>);

/// A segment (m) and its index along its polyline.
type Seg = ((f64, f64), (f64, f64), usize);

/// A polyline, m.
type Line = Vec<(f64, f64)>;

const CELL: f64 = 0.02;

impl Grid {
    fn new(lines: &[Vec<(f64, f64)>]) -> Self {
        let mut g: HashMap<_, Vec<_>> = HashMap::new();
        for line in lines {
            let segs: Vec<_> = if line.len() == 1 {
                vec![(line[0], line[0])]
            } else {
                line.windows(2).map(|w| (w[0], w[1])).collect()
            };
            for (k, (a, b)) in segs.into_iter().enumerate() {
                let (i0, i1) = ((a.0.min(b.0) / CELL).floor() as i64, (a.0.max(b.0) / CELL).floor() as i64);
                let (j0, j1) = ((a.1.min(b.1) / CELL).floor() as i64, (a.1.max(b.1) / CELL).floor() as i64);
                for i in i0..=i1 {
                    for j in j0..=j1 {
                        g.entry((i, j)).or_default().push((a, b, k));
                    }
                }
            }
        }
        Grid(g)
    }

    /// Distance from `p` to the nearest segment of index below `upto`, or `CELL` when none
    /// is that close.
    fn dist(&self, p: (f64, f64), upto: usize) -> f64 {
        let (i, j) = ((p.0 / CELL).floor() as i64, (p.1 / CELL).floor() as i64);
        let mut best = CELL;
        for di in -1..=1 {
            for dj in -1..=1 {
                for (a, b, _) in self.0.get(&(i + di, j + dj)).into_iter().flatten().filter(|s| s.2 < upto) {
                    best = best.min(seg_dist(p, *a, *b));
                }
            }
        }
        best
    }
}

/// Logged positions closer than this (m) to the previous one are left out of the checks.
const SAME_M: f64 = 2e-4;

/// A run's logged positions and the line strips of its path topics, decoded once.
struct PathView {
    /// (log time, x, y) of the samples, leaving out those within [`SAME_M`] of the last
    /// one kept (C stands nearly still for most of Fig. 7): at most that much is missed.
    truth: Vec<(u64, (f64, f64))>,
    /// Grid over the logged path (segment k ends at sample k + 1).
    truth_grid: Grid,
    /// Per topic `scene`, `path`, `path_tip`: (log time, line strips after the message).
    pieces: Vec<Vec<(u64, Vec<Line>)>>,
}

impl PathView {
    fn new(msgs: &[Msg], r: usize) -> Self {
        let mut truth: Vec<(u64, (f64, f64))> = Vec::new();
        for m in msgs.iter().filter(|m| m.topic == format!("/run{r}/sample")) {
            let f = sample_fields(&m.data);
            let p = (f[&2], f[&3]);
            if truth.last().is_none_or(|l| (l.1.0 - p.0).hypot(l.1.1 - p.1) >= SAME_M) {
                truth.push((m.log_time, p));
            }
        }
        let truth_grid = Grid::new(&[truth.iter().map(|t| t.1).collect()]);
        let pieces = ["scene", "path", "path_tip"]
            .iter()
            .map(|name| {
                let topic = format!("/run{r}/{name}");
                msgs.iter()
                    .filter(|m| m.topic == topic)
                    .map(|m| {
                        // A seek clears the scene and applies only this message.
                        let u = SceneUpdate::decode(&m.data[..]).unwrap();
                        let mut entities = BTreeMap::new();
                        for d in &u.deletions {
                            if d.r#type == 1 {
                                entities.clear();
                            } else {
                                entities.remove(&d.id);
                            }
                        }
                        for e in u.entities {
                            entities.insert(e.id.clone(), e);
                        }
                        let mut lines = Vec::new();
                        for e in entities.values() {
                            for l in &e.lines {
                                assert_eq!(e.frame_id, "world");
                                lines.push(l.points.iter().map(|p| (p.x, p.y)).collect());
                            }
                        }
                        (m.log_time, lines)
                    })
                    .collect()
            })
            .collect();
        Self { truth, truth_grid, pieces }
    }

    /// What the 3D panel shows of the path after a seek to `t`: the line strips of the
    /// latest `scene`, `path` and `path_tip` messages at or before `t`.
    fn drawn_after_seek(&self, t: u64) -> Vec<Vec<(f64, f64)>> {
        let mut lines = Vec::new();
        for piece in &self.pieces {
            let n = piece.partition_point(|(lt, _)| *lt <= t);
            if n > 0 {
                lines.extend(piece[n - 1].1.iter().cloned());
            }
        }
        lines
    }

    /// The largest distance of a logged position (up to `t`) from the drawn path, and of
    /// a drawn point (every 2 mm along the drawn strips) from the logged path up to `t`.
    fn seek_errors(&self, t: u64) -> (f64, f64) {
        let n = self.truth.partition_point(|(lt, _)| *lt <= t);
        let truth = &self.truth[..n];
        let drawn = self.drawn_after_seek(t);
        if drawn.is_empty() {
            // Nothing is drawn until C has moved a few millimetres.
            let moved = truth.iter().map(|p| (p.1.0 - truth[0].1.0).hypot(p.1.1 - truth[0].1.1)).fold(0.0, f64::max);
            return (moved, 0.0);
        }
        let segs: Vec<((f64, f64), (f64, f64))> =
            drawn.iter().flat_map(|l| l.windows(2).map(|w| (w[0], w[1]))).collect();
        let missing = truth
            .iter()
            .map(|&(_, p)| segs.iter().map(|&(a, b)| seg_dist(p, a, b)).fold(f64::INFINITY, f64::min))
            .fold(0.0, f64::max);
        let mut extra: f64 = 0.0;
        for line in &drawn {
            for w in line.windows(2) {
                let k = ((w[1].0 - w[0].0).hypot(w[1].1 - w[0].1) / 2e-3).ceil().max(1.0) as usize;
                for i in 0..=k {
                    let f = i as f64 / k as f64;
                    let p = (w[0].0 + f * (w[1].0 - w[0].0), w[0].1 + f * (w[1].1 - w[0].1));
                    extra = extra.max(self.truth_grid.dist(p, n.saturating_sub(1).max(1)));
                }
            }
        }
        (missing, extra)
    }
}

#[test]
fn after_a_seek_the_3d_panel_shows_the_path_travelled_within_a_centimetre() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fig7.mcap");
    ok(&["run", s(&fig7()), "-o", s(&out)]);
    let msgs = messages(&out);
    let view = PathView::new(&msgs, 0);
    let tip_times: Vec<u64> = view.pieces[2].iter().map(|p| p.0).collect();
    assert!(tip_times.len() > 50, "{} path_tip messages", tip_times.len());
    // Seeks every 0.5 s, and just before and at every 10th path_tip message.
    let mut seeks: Vec<u64> = (0..=120).map(|k| k * 500_000_000).collect();
    seeks.extend(tip_times.iter().step_by(10).flat_map(|&t| [t.saturating_sub(1), t]));
    let mut worst = (0.0f64, 0.0f64);
    for &t in &seeks {
        let (missing, extra) = view.seek_errors(t);
        assert!(missing <= 0.01 && extra <= 0.01, "seek to {t} ns: path off by {missing} m / {extra} m");
        worst = (worst.0.max(missing), worst.1.max(extra));
    }
    eprintln!(
        "Fig. 7, {} seeks: logged positions within {:.4} m of the drawn path, drawn path within {:.4} m of the logged one",
        seeks.len(),
        worst.0,
        worst.1
    );
    assert!(worst.0 > 0.0);
    // The bytes for the path are small next to the samples'.
    let path_bytes: usize =
        msgs.iter().filter(|m| m.topic.contains("path") || m.topic.ends_with("scene")).map(|m| m.data.len()).sum();
    let sample_bytes: usize = msgs.iter().filter(|m| m.topic.ends_with("/sample")).map(|m| m.data.len()).sum();
    assert!(path_bytes * 4 < sample_bytes, "path {path_bytes} B vs samples {sample_bytes} B");
}

/// The chunk a topic's latest message at or before `t` lives in, as Foxglove's backfill
/// finds it (one reverse read per topic; no chunk is shared between topics).
fn seek_cost(bytes: &[u8], t: u64) -> (u64, usize) {
    let summary = mcap::read::Summary::read(bytes).unwrap().unwrap();
    let mut latest: HashMap<u16, (u64, u64, u64)> = HashMap::new(); // channel -> (log time, offset, size)
    for ci in &summary.chunk_indexes {
        if ci.message_start_time > t {
            continue;
        }
        for (ch, entries) in summary.read_message_indexes(bytes, ci).unwrap() {
            if let Some(e) = entries.iter().filter(|e| e.log_time <= t).max_by_key(|e| e.log_time) {
                let cand = (e.log_time, ci.chunk_start_offset, ci.uncompressed_size);
                let slot = latest.entry(ch.id).or_insert(cand);
                if (cand.0, cand.1) > (slot.0, slot.1) {
                    *slot = cand;
                }
            }
        }
    }
    (latest.values().map(|v| v.2).sum(), latest.len())
}

#[test]
fn with_30_runs_a_seek_decompresses_one_small_chunk_per_topic_and_no_chunk_spans_two_runs() {
    let dir = tempfile::tempdir().unwrap();
    let mut body = String::from("[sim]\nt_end = 8.0\nlog_dt = 0.01\n");
    for k in 0..30 {
        let a = (k as f64 * 12.0).to_radians();
        body += &format!(
            "[[run]]\nstart = {{ x = {}, y = {}, theta = {} }}\ngoal = {{ x = 0.0, y = 0.0, theta_deg = 90.0 }}\n",
            a.cos(),
            a.sin(),
            a + std::f64::consts::PI
        );
    }
    let scen = write(dir.path(), "ring.toml", &body);
    let out = dir.path().join("ring.mcap");
    ok(&["run", s(&scen), "-o", s(&out)]);
    let bytes = fs::read(&out).unwrap();
    let summary = mcap::read::Summary::read(&bytes).unwrap().unwrap();
    let run_of = |ch: &u16| -> usize {
        let topic = &summary.channels[ch].topic;
        topic[4..].split('/').next().unwrap().parse().unwrap()
    };
    for ci in &summary.chunk_indexes {
        let runs: BTreeSet<usize> = ci.message_index_offsets.keys().map(run_of).collect();
        assert_eq!(
            runs.len(),
            1,
            "a chunk spans runs {runs:?} ({} to {} ns)",
            ci.message_start_time,
            ci.message_end_time
        );
        assert!(ci.uncompressed_size <= 70 * 1024, "chunk of {} B", ci.uncompressed_size);
    }
    let mut worst = 0;
    for k in 1..=16u64 {
        let (cost, topics) = seek_cost(&bytes, k * 500_000_000);
        assert!(topics >= 30 * 4, "{topics} topics have a message by then");
        assert!(cost <= topics as u64 * 70 * 1024, "seek decompresses {cost} B for {topics} topics");
        worst = worst.max(cost);
    }
    assert!(worst < 20_000_000);
    eprintln!("30 runs: a seek decompresses at most {worst} B");
}

/// Foxglove's panels read these keys; the layout must use them and name only what the
/// file has.
fn check_layout(layout: &serde_json::Value, file: &Path, runs: usize) {
    let msgs = &messages(file)[..];
    let bytes = fs::read(file).unwrap();
    let sample_fields = sample_schema_fields(&bytes);
    // The file's topics (a channel may have no message yet in a short run).
    let summary = mcap::read::Summary::read(&bytes).unwrap().unwrap();
    let topics: BTreeMap<&str, &str> = summary
        .channels
        .values()
        .map(|c| (c.topic.as_str(), c.schema.as_ref().map_or("", |s| s.name.as_str())))
        .collect();
    let cfg = &layout["configById"];
    let three = &cfg["3D!wmr-plane"];
    // Frame settings where FrameAxes.ts reads them.
    assert!(three["scene"]["transforms"]["labelSize"].as_f64().unwrap() > 0.0);
    assert!(three["scene"]["transforms"]["axisScale"].as_f64().unwrap() > 0.0);
    let frames = three["transforms"].as_object().unwrap();
    assert!(frames.keys().all(|k| k.starts_with("frame:")), "{:?}", frames.keys());
    let mut want_frames: BTreeSet<String> = BTreeSet::from(["frame:world".to_owned()]);
    for m in msgs.iter().filter(|m| m.schema == "foxglove.FrameTransform") {
        want_frames.insert(format!("frame:{}", FrameTransform::decode(&m.data[..]).unwrap().child_frame_id));
    }
    assert_eq!(frames.keys().cloned().collect::<BTreeSet<_>>(), want_frames);
    // Every 3D topic of the file is shown, and the layout names no other.
    let shown: BTreeMap<&str, &serde_json::Value> =
        three["topics"].as_object().unwrap().iter().map(|(k, v)| (k.as_str(), v)).collect();
    let drawable: BTreeSet<&str> = topics
        .iter()
        .filter(|(_, s)| **s == "foxglove.SceneUpdate" || **s == "foxglove.PoseInFrame")
        .map(|(t, _)| *t)
        .collect();
    assert_eq!(shown.keys().copied().collect::<BTreeSet<_>>(), drawable);
    assert!(shown.values().all(|v| v["visible"] == true));
    // Plots: titles (with units) under Foxglove's key; every series a field of the file.
    let mut per_run_colour: BTreeMap<usize, BTreeSet<String>> = BTreeMap::new();
    let mut plotted_runs = BTreeSet::new();
    for (id, panel) in cfg.as_object().unwrap().iter().filter(|(k, _)| k.starts_with("Plot!")) {
        assert!(panel.get("title").is_none(), "{id}: Foxglove ignores `title`");
        let title = panel["foxglovePanelTitle"].as_str().unwrap();
        assert!(title.contains("(m") || title.contains("(rad"), "{id}: no unit in {title:?}");
        for p in panel["paths"].as_array().unwrap() {
            let value = p["value"].as_str().unwrap();
            let (topic, field) = value.split_once('.').unwrap();
            assert_eq!(topics.get(topic), Some(&"wmr.Sample"), "{id}: {value}");
            assert!(sample_fields.iter().any(|f| f == field), "{id}: {value}: no such field");
            if title.contains("every run") {
                let r: usize = topic[4..].split('/').next().unwrap().parse().unwrap();
                plotted_runs.insert(r);
                per_run_colour.entry(r).or_default().insert(p["color"].as_str().unwrap().to_owned());
            }
        }
    }
    assert_eq!(plotted_runs, (0..runs).collect());
    // A run's plot colour is its path's colour in the 3D panel.
    for r in 0..runs {
        let colours = &per_run_colour[&r];
        assert_eq!(colours.len(), 1, "run {r}: {colours:?}");
        let tip = msgs.iter().find(|m| m.topic == format!("/run{r}/path_tip")).unwrap();
        let c = SceneUpdate::decode(&tip.data[..]).unwrap().entities[0].lines[0].color.unwrap();
        let hex = format!(
            "#{:02x}{:02x}{:02x}",
            (c.r * 255.0).round() as u8,
            (c.g * 255.0).round() as u8,
            (c.b * 255.0).round() as u8
        );
        assert_eq!(colours.iter().next().unwrap(), &hex, "run {r}");
    }
    // Every panel of the mosaic is configured.
    let mut ids = Vec::new();
    fn leaves<'a>(v: &'a serde_json::Value, out: &mut Vec<&'a str>) {
        match v {
            serde_json::Value::String(s) => out.push(s),
            v => {
                leaves(&v["first"], out);
                leaves(&v["second"], out);
            }
        }
    }
    leaves(&layout["layout"], &mut ids);
    assert_eq!(
        ids.iter().copied().collect::<BTreeSet<_>>(),
        cfg.as_object().unwrap().keys().map(String::as_str).collect()
    );
}

#[test]
fn the_layout_names_what_the_file_has_and_matches_its_colours() {
    let dir = tempfile::tempdir().unwrap();
    let mut body = String::from("[sim]\nt_end = 2.0\nlog_dt = 0.01\n");
    for k in 0..12 {
        body += &format!(
            "[[run]]\nstart = {{ x = {}, y = 0.0, theta = 0.0 }}\ngoal = {{ x = 1.0, y = 1.0, theta = 0.0 }}\n",
            -0.1 * k as f64
        );
    }
    for (name, body, runs) in [("twelve", body.as_str(), 12), ("sensor", WITH_SENSOR, 1)] {
        let scen = write(dir.path(), &format!("{name}.toml"), body);
        let out = dir.path().join(format!("{name}.mcap"));
        let beside = dir.path().join(format!("{name}.layout.json"));
        let alone = dir.path().join(format!("{name}-alone.json"));
        ok(&["run", s(&scen), "-o", s(&out), "--layout", s(&beside)]);
        ok(&["layout", s(&scen), "-o", s(&alone)]);
        assert_eq!(fs::read(&beside).unwrap(), fs::read(&alone).unwrap(), "run --layout and layout differ");
        let layout: serde_json::Value = serde_json::from_slice(&fs::read(&alone).unwrap()).unwrap();
        check_layout(&layout, &out, runs);
    }
    // --layout with a CSV output is a usage error.
    let scen = dir.path().join("twelve.toml");
    let o = run(&["run", s(&scen), "-o", s(&dir.path().join("x.csv")), "--layout", s(&dir.path().join("x.json"))]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!dir.path().join("x.csv").exists() && !dir.path().join("x.json").exists());
    // A LAYOUT that cannot be written is refused before the run: exit 2, no OUT.
    let out = dir.path().join("y.mcap");
    for layout in [out.clone(), dir.path().to_path_buf(), dir.path().join("missing/y.json")] {
        let o = run(&["run", s(&scen), "-o", s(&out), "--layout", s(&layout)]);
        assert_eq!(o.status.code(), Some(2), "--layout {}: {}", layout.display(), String::from_utf8_lossy(&o.stderr));
        assert!(!out.exists(), "--layout {}: OUT written", layout.display());
    }
}

/// The plots of a layout, by panel id, and the topics its 3D panel shows.
fn plots_and_3d_topics(layout: &serde_json::Value) -> (BTreeSet<String>, BTreeSet<String>) {
    let cfg = layout["configById"].as_object().unwrap();
    let plots = cfg.keys().filter(|k| k.starts_with("Plot!")).cloned().collect();
    let topics = cfg["3D!wmr-plane"]["topics"].as_object().unwrap().keys().cloned().collect();
    (plots, topics)
}

/// Issue text: Foxglove "shows the three [poses] in the 3D panel and a drift plot"; for
/// tracking "the reference path in the 3D panel (...), the generated layout plots tracking
/// error and reference vs actual speed". The layout of a run on odometry has the drift plot
/// (true against dead-reckoned position) and shows pose_odom; a tracking layout has the
/// tracking-error and speed plots (v_ref against v) and shows the reference; a plain run's
/// has neither; and each names only what its file has.
#[test]
fn the_layout_has_the_drift_tracking_and_speed_plots_only_where_the_scenario_has_them() {
    let dir = tempfile::tempdir().unwrap();
    let odometry = odometry_3s();
    let base: BTreeSet<String> = ["Plot!wmr-heading", "Plot!wmr-wheels"].map(String::from).into();
    for (name, body, runs) in [("plain", TWO_RUNS, 2), ("odometry", odometry.as_str(), 1), ("tracking", TRACKING, 2)] {
        let scen = write(dir.path(), &format!("{name}.toml"), body);
        let out = dir.path().join(format!("{name}.mcap"));
        let json = dir.path().join(format!("{name}.json"));
        ok(&["run", s(&scen), "-o", s(&out), "--layout", s(&json)]);
        let layout: serde_json::Value = serde_json::from_slice(&fs::read(&json).unwrap()).unwrap();
        check_layout(&layout, &out, runs);
        let (plots, topics) = plots_and_3d_topics(&layout);
        let extra: BTreeSet<String> = plots.difference(&base).cloned().collect();
        let want: &[&str] = match name {
            "plain" => &["Plot!wmr-dl"],
            "odometry" => &["Plot!wmr-dl", "Plot!wmr-sensor", "Plot!wmr-odometry"],
            _ => &["Plot!wmr-tracking-error", "Plot!wmr-speed"],
        };
        assert_eq!(extra, want.iter().map(|s| s.to_string()).collect(), "{name}");
        let cfg = &layout["configById"];
        let fields = |id: &str| -> Vec<String> {
            cfg[id]["paths"].as_array().unwrap().iter().map(|p| p["value"].as_str().unwrap().to_owned()).collect()
        };
        match name {
            "odometry" => {
                assert_eq!(
                    fields("Plot!wmr-odometry"),
                    ["x", "x_odom", "y", "y_odom"].map(|f| format!("/run0/sample.{f}"))
                );
                assert!(topics.contains("/run0/pose_odom") && topics.contains("/run0/pose_meas"));
                assert_eq!(cfg["3D!wmr-plane"]["topics"]["/run0/pose_odom"]["type"], "arrow");
            }
            "tracking" => {
                assert_eq!(fields("Plot!wmr-speed"), ["v_ref", "v"].map(|f| format!("/run0/sample.{f}")));
                assert_eq!(fields("Plot!wmr-tracking-error"), ["/run0/sample.dl", "/run1/sample.dl"]);
                for r in 0..2 {
                    assert!(topics.contains(&format!("/run{r}/reference")));
                    assert_eq!(cfg["3D!wmr-plane"]["transforms"][format!("frame:run{r}/reference")]["visible"], true);
                }
            }
            _ => assert!(!topics.iter().any(|t| t.ends_with("pose_odom") || t.ends_with("reference"))),
        }
    }
}

#[test]
fn examples_foxglove_holds_the_generated_layouts() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = tempfile::tempdir().unwrap();
    for (toml, layout) in [
        ("examples/paper/fig7.toml", "examples/foxglove/fig7.layout.json"),
        ("examples/foxglove/ring30.toml", "examples/foxglove/ring30.layout.json"),
    ] {
        let fresh = dir.path().join("fresh.json");
        ok(&["layout", s(&root.join(toml)), "-o", s(&fresh)]);
        assert_eq!(
            fs::read_to_string(root.join(layout)).unwrap(),
            fs::read_to_string(&fresh).unwrap(),
            "{layout} is stale: regenerate it with `wmr-cli layout {toml} -o {layout}`"
        );
    }
}

#[test]
fn foxglove_typescript_readers_read_every_message() {
    let js = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/foxglove-js");
    let node_ok = Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success());
    if !node_ok || !js.join("node_modules/@mcap/core").is_dir() {
        let what = if node_ok { "Foxglove's npm packages are not installed" } else { "node is not on PATH" };
        skip::missing("node", &format!("{what} (needs node, then `npm ci --ignore-scripts` in {})", js.display()));
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for (name, body) in [("two", TWO_RUNS), ("sensor", WITH_SENSOR)] {
        let scen = write(dir.path(), &format!("{name}.toml"), body);
        let out = dir.path().join(format!("{name}.mcap"));
        ok(&["run", s(&scen), "-o", s(&out)]);
        let o = Command::new("node").arg(js.join("check.mjs")).arg(&out).output().unwrap();
        assert!(o.status.success(), "check.mjs {name}: {}", String::from_utf8_lossy(&o.stderr));
        let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let n = messages(&out).len() as u64;
        assert_eq!(report["messages"].as_u64(), Some(n));
        assert!(report["pathAfterSeekMaxMissingM"].as_f64().unwrap() <= 0.01);
    }
}
