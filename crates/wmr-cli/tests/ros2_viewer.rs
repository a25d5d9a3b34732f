//! What a viewer sees of a ROS 2 file. Its frame tree: in a `--profile both` file of
//! several runs every frame has one parent and hangs from `world` (Foxglove re-parents a
//! frame at each transform naming another parent). Its layout (issue 43: "the generated
//! Foxglove layout shows the robot model"): `layout --profile ros2` and `run --profile ros2 --layout` write the same
//! file, whose 3D panel draws in `map` and shows each run's `/robot_description` (the URDF
//! Foxglove draws on the `/tf` frames), `/goal_pose` and, tracking, `/plan`; every topic,
//! frame and plotted field it names is one the MCAP has (read back here: channels, schemas,
//! the `.msg` fields of `wmr_msgs/msg/Sample`, and the frame names in the `/tf` messages).

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;
use std::process::Command;

use foxglove::messages::FrameTransform;
use prost::Message as _;
use wmr_ros2::cdr::CdrReader;

fn cli(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_wmr-cli")).args(args).output().unwrap();
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
}

/// Topic name -> (schema name, `.msg` text).
type Topics = BTreeMap<String, (String, String)>;

/// The file's topics with their schema names and `.msg` texts, and the `/tf` and
/// `/tf_static` messages (the frame names are CDR strings in them).
fn read(file: &Path) -> (Topics, Vec<Vec<u8>>) {
    let bytes = fs::read(file).unwrap();
    let mut topics = BTreeMap::new();
    let mut tf = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let schema = m.channel.schema.as_ref().unwrap();
        topics.insert(m.channel.topic.clone(), (schema.name.clone(), String::from_utf8(schema.data.to_vec()).unwrap()));
        if m.channel.topic.ends_with("/tf") || m.channel.topic.ends_with("/tf_static") {
            tf.push(m.data.to_vec());
        }
    }
    (topics, tf)
}

fn cdr_string(s: &str) -> Vec<u8> {
    let mut v = ((s.len() + 1) as u32).to_le_bytes().to_vec();
    v.extend_from_slice(s.as_bytes());
    v.push(0);
    v
}

#[test]
fn the_ros2_layout_shows_the_robot_and_names_only_what_the_file_has() {
    let dir = tempfile::tempdir().unwrap();
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
    for (name, runs) in [("odometry-3s.toml", 1), ("two-runs-every-topic.toml", 2)] {
        let scen = fixtures.join(name);
        let (mcap, beside, alone) =
            (dir.path().join("r.mcap"), dir.path().join("beside.json"), dir.path().join("alone.json"));
        let s = |p: &Path| p.to_str().unwrap().to_owned();
        cli(&["run", &s(&scen), "-o", &s(&mcap), "--profile", "ros2", "--layout", &s(&beside)]);
        cli(&["layout", &s(&scen), "-o", &s(&alone), "--profile", "ros2"]);
        assert_eq!(fs::read(&beside).unwrap(), fs::read(&alone).unwrap(), "{name}: run --layout and layout differ");
        let layout: serde_json::Value = serde_json::from_slice(&fs::read(&alone).unwrap()).unwrap();
        let (topics, tf) = read(&mcap);
        let three = &layout["configById"]["3D!wmr-plane"];
        assert_eq!(three["followTf"], "map", "{name}");
        // Frames: each one the /tf messages carry.
        for key in three["transforms"].as_object().unwrap().keys() {
            let frame = key.strip_prefix("frame:").unwrap();
            let needle = cdr_string(frame);
            assert!(tf.iter().any(|m| m.windows(needle.len()).any(|w| w == needle)), "{name}: no frame {frame}");
        }
        // 3D topics: every one in the file, of a type the 3D panel draws; the robot of every run.
        let shown: BTreeSet<&str> = three["topics"].as_object().unwrap().keys().map(String::as_str).collect();
        for t in &shown {
            let (schema, _) = topics.get(*t).unwrap_or_else(|| panic!("{name}: {t} is not in the file"));
            assert!(
                ["std_msgs/msg/String", "geometry_msgs/msg/PoseStamped", "nav_msgs/msg/Path"]
                    .contains(&schema.as_str()),
                "{name}: {t} is a {schema}"
            );
            assert_eq!(three["topics"][*t]["visible"], true);
        }
        let ns = |i: usize| if runs > 1 { format!("/run{i}") } else { String::new() };
        for i in 0..runs {
            assert!(shown.contains(format!("{}/robot_description", ns(i)).as_str()), "{name}: run {i}'s robot");
            assert!(shown.contains(format!("{}/goal_pose", ns(i)).as_str()), "{name}: run {i}'s goal");
        }
        // Plots: every series a field of wmr_msgs/msg/Sample on a run's /wmr/sample.
        let mut plotted = BTreeSet::new();
        for (id, panel) in layout["configById"].as_object().unwrap().iter().filter(|(k, _)| k.starts_with("Plot!")) {
            for p in panel["paths"].as_array().unwrap() {
                let (topic, field) = p["value"].as_str().unwrap().rsplit_once('.').unwrap();
                let (schema, msg) = &topics[topic];
                assert_eq!(schema, "wmr_msgs/msg/Sample", "{name} {id}: {topic}");
                let first = msg.split("\n===").next().unwrap();
                assert!(first.lines().any(|l| l.split_whitespace().nth(1) == Some(field)), "{name} {id}: {field}");
                plotted.insert(topic.to_owned());
            }
        }
        assert_eq!(plotted, (0..runs).map(|i| format!("{}/wmr/sample", ns(i))).collect(), "{name}");
    }
}

/// Every (parent, child) pair of the file's transforms: Foxglove's `FrameTransform`s and
/// ROS 2's `TFMessage`s (`geometry_msgs/TransformStamped`: header (stamp, frame_id),
/// child_frame_id, translation, rotation).
fn frame_edges(file: &Path) -> BTreeSet<(String, String)> {
    let bytes = fs::read(file).unwrap();
    let mut edges = BTreeSet::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let schema = m.channel.schema.as_ref().unwrap().name.clone();
        if schema == "foxglove.FrameTransform" {
            let tf = FrameTransform::decode(&m.data[..]).unwrap();
            edges.insert((tf.parent_frame_id, tf.child_frame_id));
        } else if schema == "tf2_msgs/msg/TFMessage" {
            let mut r = CdrReader::new(&m.data).unwrap();
            for _ in 0..r.seq_len().unwrap() {
                r.time().unwrap();
                let parent = r.string().unwrap();
                let child = r.string().unwrap();
                r.skip_f64(7).unwrap();
                edges.insert((parent, child));
            }
        }
    }
    edges
}

#[test]
fn in_a_both_file_every_frame_has_one_parent_and_hangs_from_world() {
    let dir = tempfile::tempdir().unwrap();
    let scen = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/two-runs-every-topic.toml");
    let s = |p: &Path| p.to_str().unwrap().to_owned();
    let both = dir.path().join("both.mcap");
    cli(&["run", &s(&scen), "-o", &s(&both), "--profile", "both"]);
    let edges = frame_edges(&both);
    let mut parent: BTreeMap<&str, &str> = BTreeMap::new();
    for (p, c) in &edges {
        if let Some(other) = parent.insert(c, p) {
            panic!("{c} has two parents: {other} and {p}");
        }
    }
    for child in parent.keys() {
        let (mut at, mut hops) = (*child, 0);
        while let Some(p) = parent.get(at) {
            (at, hops) = (p, hops + 1);
            assert!(hops < 100, "a cycle through {child}");
        }
        assert_eq!(at, "world", "{child} hangs from {at}, not from world");
    }
    for i in 0..2 {
        assert_eq!(parent[format!("run{i}/base_link").as_str()], format!("run{i}/odom"));
    }
    // The Foxglove profile alone keeps its own tree (world -> runN/base_link).
    let fox = dir.path().join("fox.mcap");
    cli(&["run", &s(&scen), "-o", &s(&fox)]);
    assert!(frame_edges(&fox).contains(&("world".to_owned(), "run1/base_link".to_owned())));
}
