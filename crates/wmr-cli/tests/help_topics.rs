//! `wmr-cli help keys` names exactly the MCAP topics a file has, with their schemas
//! (issue 22: the hand-written help had drifted to `/runN/pose`, `/runN/goal`,
//! `/runN/robot`, none of which exist).

use std::collections::BTreeSet;
use std::process::Command;

/// Two runs tracking a reference on odometry, so every kind of topic is written.
const SCENARIO: &str = include_str!("fixtures/two-runs-every-topic.toml");

/// A short MPPI run (a small batch) beside a post: the obstacles and MPPI topics.
const MPPI_AMONG_OBSTACLES: &str = r#"
[controller]
kind = "mppi"
batch_size = 16
time_steps = 10
[[world.obstacle]]
kind = "circle"
center = { x = 1.0, y = 1.0 }
radius = 0.1
[sim]
t_end = 0.5
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
goal = { x = 0.5, y = 0.0, theta_deg = 0.0 }
"#;

/// `(topic, schema)` of every channel in `bytes`, with the run index replaced by `N`.
fn file_topics(bytes: &[u8]) -> BTreeSet<(String, String)> {
    let summary = mcap::read::Summary::read(bytes).unwrap().expect("a summary");
    summary
        .channels
        .values()
        .map(|c| {
            let rest = c.topic.strip_prefix("/run").expect("/runK/...");
            let name = rest.trim_start_matches(|ch: char| ch.is_ascii_digit());
            assert!(name.len() < rest.len(), "{}: no run index", c.topic);
            let schema = c.schema.as_ref().map(|s| s.name.clone()).unwrap_or_default();
            (format!("/runN{name}"), schema)
        })
        .collect()
}

/// Every `/runN/...` topic the help mentions, with the schema written after it on its line.
fn help_topics(help: &str) -> BTreeSet<(String, String)> {
    let mut out = BTreeSet::new();
    for line in help.lines() {
        for (i, _) in line.match_indices("/runN/") {
            let topic: String =
                line[i..].chars().take_while(|c| c.is_ascii_alphanumeric() || matches!(c, '/' | '_')).collect();
            let after = line[i + topic.len()..].trim_start();
            let schema = after.split(|c: char| c == ':' || c.is_whitespace()).next().unwrap_or("").to_owned();
            out.insert((topic, schema));
        }
    }
    out
}

#[test]
fn help_names_exactly_the_topics_of_an_mcap_with_every_topic() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("sensor.toml");
    std::fs::write(&scenario, SCENARIO).unwrap();
    let mcap = dir.path().join("sensor.mcap");
    let o = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .args(["run", scenario.to_str().unwrap(), "-o", mcap.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut in_file = file_topics(&std::fs::read(&mcap).unwrap());
    assert!(in_file.len() >= 9, "{in_file:?}");
    // And the topics of an MPPI run among obstacles (issue 41).
    let mppi = dir.path().join("mppi.toml");
    std::fs::write(&mppi, MPPI_AMONG_OBSTACLES).unwrap();
    let mcap = dir.path().join("mppi.mcap");
    let o = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .args(["run", mppi.to_str().unwrap(), "-o", mcap.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    in_file.extend(file_topics(&std::fs::read(&mcap).unwrap()));

    for args in [&["help", "keys"][..], &["help", "keys", "outputs"]] {
        let o = Command::new(env!("CARGO_BIN_EXE_wmr-cli")).args(args).output().unwrap();
        assert!(o.status.success());
        let in_help = help_topics(&String::from_utf8(o.stdout).unwrap());
        let only_help: Vec<_> = in_help.difference(&in_file).collect();
        let only_file: Vec<_> = in_file.difference(&in_help).collect();
        assert!(
            only_help.is_empty() && only_file.is_empty(),
            "{args:?}: in --help but not in the file: {only_help:?}; in the file but not in --help: {only_file:?}"
        );
    }
}
