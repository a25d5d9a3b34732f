//! What Foxglove shows of obstacles and of MPPI (issue 41), read back from `wmr-cli run
//! ... -o OUT.mcap` with the `mcap` crate and Foxglove's protobuf messages (as
//! tests/foxglove.rs reads the other topics): `/runN/obstacles` draws the scenario's
//! obstacles at t = 0 and, at a collision, the obstacle touched in red with the footprint
//! there; the generated layout shows the topic.

use std::fs;
use std::path::Path;

use foxglove::messages::{SceneUpdate, line_primitive};
use prost::Message as _;

// The helpers of the other Foxglove tests (one test binary: tests/integration.rs).
use crate::foxglove::{Msg, messages, ok, s, write};

/// The post and the wall, as the scenario below gives them.
const POST: ((f64, f64), f64) = ((1.0, 0.0), 0.15);
const WALL: [(f64, f64); 4] = [(0.6, 0.45), (1.4, 0.45), (1.4, 0.6), (0.6, 0.6)];
const FOOTPRINT_M: f64 = 0.1;

/// The default law drives run 0 straight into the post; run 1 stays clear below it.
const OBSTACLES: &str = r#"
[robot]
footprint_radius = 0.1
[[world.obstacle]]
kind = "polygon"
points = [[0.6, 0.45], [1.4, 0.45], [1.4, 0.6], [0.6, 0.6]]
[[world.obstacle]]
kind = "circle"
center = { x = 1.0, y = 0.0 }
radius = 0.15
[sim]
t_end = 3.0
log_dt = 0.01
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
goal = { x = 2.0, y = 0.0, theta_deg = 0.0 }
[[run]]
start = { x = 0.0, y = -0.5, theta_deg = 0.0 }
goal = { x = 0.5, y = -0.5, theta_deg = 0.0 }
"#;

fn near(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12
}

fn is_red(c: &foxglove::messages::Color) -> bool {
    c.r > 0.8 && c.g < 0.2 && c.b < 0.2
}

#[test]
fn the_obstacles_topic_draws_the_scenarios_obstacles_and_the_collision() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "obstacles.toml", OBSTACLES);
    let out = dir.path().join("obstacles.mcap");
    let json = dir.path().join("obstacles.json");
    let summary = ok(&["run", s(&scen), "-o", s(&out), "--layout", s(&json)]);
    let summary = String::from_utf8_lossy(&summary.stdout).into_owned();
    let msgs = messages(&out);
    for run in 0..2 {
        let topic = format!("/run{run}/obstacles");
        let mine: Vec<&Msg> = msgs.iter().filter(|m| m.topic == topic).collect();
        assert!(!mine.is_empty(), "{topic}: no message");
        assert!(mine.iter().all(|m| m.schema == "foxglove.SceneUpdate"), "{topic}");
        // At t = 0: every obstacle, in the summary's order (circles first), in the world frame.
        assert_eq!(mine[0].log_time, 0, "{topic}");
        let scene = SceneUpdate::decode(&mine[0].data[..]).unwrap();
        let ids: Vec<&str> = scene.entities.iter().map(|e| e.id.as_str()).collect();
        assert_eq!(ids, ["obstacle0", "obstacle1"], "{topic}");
        assert!(scene.entities.iter().all(|e| e.frame_id == "world"));
        let disc = &scene.entities[0].cylinders;
        assert_eq!(disc.len(), 1, "{topic}: the post is one cylinder");
        let p = disc[0].pose.unwrap().position.unwrap();
        let size = disc[0].size.unwrap();
        assert!(near(p.x, POST.0.0) && near(p.y, POST.0.1), "{topic}: post at ({}, {})", p.x, p.y);
        assert!(near(size.x, 2.0 * POST.1) && near(size.y, 2.0 * POST.1), "{topic}: post {size:?}");
        let wall = &scene.entities[1].lines;
        assert_eq!(wall.len(), 1);
        assert_eq!(wall[0].r#type, line_primitive::Type::LineLoop as i32);
        let pts: Vec<(f64, f64)> = wall[0].points.iter().map(|q| (q.x, q.y)).collect();
        assert_eq!(pts, WALL, "{topic}: the wall's outline");
        assert!(!is_red(&disc[0].color.unwrap()) && !is_red(&wall[0].color.unwrap()));
        // The collision: run 0 only, at its last sample, the post in red and the footprint
        // there, which an independent distance finds touching the post.
        let last_sample = msgs.iter().filter(|m| m.topic == format!("/run{run}/sample")).map(|m| m.log_time).max();
        if run == 0 {
            assert!(summary.contains("collided at t = ") && summary.contains("with obstacle 0"), "{summary}");
            assert_eq!(mine.len(), 2, "{topic}: t = 0 and the collision");
            assert_eq!(Some(mine[1].log_time), last_sample);
            let hit = SceneUpdate::decode(&mine[1].data[..]).unwrap();
            let post = hit.entities.iter().find(|e| e.id == "obstacle0").expect("the post again");
            assert!(is_red(&post.cylinders[0].color.unwrap()));
            let foot = hit.entities.iter().find(|e| e.id == "footprint").expect("the footprint");
            let ring = &foot.lines[0].points;
            let (cx, cy) = (
                ring.iter().map(|q| q.x).sum::<f64>() / ring.len() as f64,
                ring.iter().map(|q| q.y).sum::<f64>() / ring.len() as f64,
            );
            let gap = (cx - POST.0.0).hypot(cy - POST.0.1) - POST.1 - FOOTPRINT_M;
            assert!((-0.01..=1e-9).contains(&gap), "footprint {gap} m from the post");
        } else {
            assert!(!summary.lines().nth(1).unwrap_or("").contains("collided"), "{summary}");
            assert_eq!(mine.len(), 1, "{topic}: no collision, one message");
        }
    }
    // The layout's 3D panel shows every run's obstacles.
    let layout: serde_json::Value = serde_json::from_slice(&fs::read(&json).unwrap()).unwrap();
    for run in 0..2 {
        assert_eq!(layout["configById"]["3D!wmr-plane"]["topics"][format!("/run{run}/obstacles")]["visible"], true);
    }
}

#[test]
fn a_world_without_obstacles_has_no_obstacles_topic() {
    let dir = tempfile::tempdir().unwrap();
    let body: String = OBSTACLES.lines().skip_while(|l| !l.starts_with("[sim]")).collect::<Vec<_>>().join("\n");
    let scen = write(dir.path(), "plain.toml", &body);
    let out = dir.path().join("plain.mcap");
    ok(&["run", s(&scen), "-o", s(&out)]);
    assert!(!messages(&out).iter().any(|m| m.topic.ends_with("/obstacles")));
}

/// A short MPPI run (a small batch, for a debug build) with a perfect sensor: the
/// measured pose is the true one.
const MPPI: &str = r#"
[controller]
kind = "mppi"
batch_size = 64
time_steps = 20
[sim]
t_end = 2.0
log_dt = 0.01
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
goal = { x = 1.0, y = 0.2, theta_deg = 11.5 }
"#;
const MODEL_DT_NS: u64 = 50_000_000;
const TIME_STEPS: usize = 20;
const VX_MAX: f64 = 0.5;

/// The CSV's (t, x, y) by log time (ns).
fn positions(csv: &Path) -> std::collections::BTreeMap<u64, (f64, f64)> {
    let text = fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (t, x, y) = (col("t"), col("x"), col("y"));
    lines
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            ((f[t] * 1e9).round() as u64, (f[x], f[y]))
        })
        .collect()
}

#[test]
fn mppi_writes_its_optimal_trajectory_every_cycle_and_a_sample_of_its_rollouts() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "mppi.toml", MPPI);
    let out = dir.path().join("mppi.mcap");
    let csv = dir.path().join("mppi.csv");
    let json = dir.path().join("mppi.json");
    ok(&["run", s(&scen), "-o", s(&out), "--layout", s(&json)]);
    ok(&["run", s(&scen), "-o", s(&csv)]);
    let at = positions(&csv);
    let msgs = messages(&out);
    let optimal: Vec<&Msg> = msgs.iter().filter(|m| m.topic == "/run0/mppi/optimal").collect();
    // One per planning cycle, model_dt apart, from t = 0 to t_end.
    assert_eq!(optimal.len(), 41);
    for (k, m) in optimal.iter().enumerate() {
        assert_eq!(m.schema, "foxglove.PosesInFrame");
        assert_eq!(m.log_time, k as u64 * MODEL_DT_NS);
        let path = foxglove::messages::PosesInFrame::decode(&m.data[..]).unwrap();
        assert_eq!(path.frame_id, "world");
        let xy: Vec<(f64, f64)> = path.poses.iter().map(|p| p.position.unwrap()).map(|v| (v.x, v.y)).collect();
        assert_eq!(xy.len(), TIME_STEPS + 1);
        // The first pose is the measured (here the true) pose at the cycle.
        assert_eq!(xy[0], at[&m.log_time], "cycle {k}");
        // Steps of model_dt at speeds within vx_max.
        for w in xy.windows(2) {
            let v = (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1) / 0.05;
            assert!(v <= VX_MAX * (1.0 + 1e-9), "cycle {k}: {v} m/s");
        }
        // One model_dt later the robot is where the plan's first step put it: the
        // prediction on the law's model of the command the robot then follows.
        if let Some(&(x, y)) = at.get(&(m.log_time + MODEL_DT_NS)) {
            let miss = (xy[1].0 - x).hypot(xy[1].1 - y);
            assert!(miss < 2e-3, "cycle {k}: first step {miss} m from the robot");
        }
    }
    // The rollouts: every 4th cycle from the 5th, 16 line strips from the measured pose.
    let rollouts: Vec<&Msg> = msgs.iter().filter(|m| m.topic == "/run0/mppi/rollouts").collect();
    assert_eq!(
        rollouts.iter().map(|m| m.log_time / MODEL_DT_NS).collect::<Vec<_>>(),
        (1..=10).map(|k| 4 * k).collect::<Vec<_>>()
    );
    for m in &rollouts {
        let update = SceneUpdate::decode(&m.data[..]).unwrap();
        let lines = &update.entities[0].lines;
        assert_eq!(lines.len(), 16);
        for l in lines {
            assert_eq!(l.points.len(), TIME_STEPS + 1);
            assert_eq!((l.points[0].x, l.points[0].y), at[&m.log_time]);
        }
    }
    let layout: serde_json::Value = serde_json::from_slice(&fs::read(&json).unwrap()).unwrap();
    let shown = &layout["configById"]["3D!wmr-plane"]["topics"];
    assert_eq!(shown["/run0/mppi/optimal"]["type"], "line");
    assert_eq!(shown["/run0/mppi/rollouts"]["visible"], true);
}
