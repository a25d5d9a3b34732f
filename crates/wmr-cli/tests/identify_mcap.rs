//! Issue 44: `wmr-cli identify` and `replay` read a ROS 2 MCAP (issue 43's reader): a wmr
//! run written both as CSV and as `--profile ros2` MCAP fits to the same robot file, and
//! an MCAP without what the fit needs is refused naming the topic or field, exit 2.

use std::collections::BTreeMap;
use std::fs;
use std::io::BufWriter;
use std::path::Path;

use crate::identify_common::{ok, refused, run};

fn fig7() -> String {
    format!("{}/../../examples/paper/fig7.toml", env!("CARGO_MANIFEST_DIR"))
}

/// The file's `key = value` lines (comments, which name the log, dropped).
fn values(toml: &str) -> Vec<String> {
    toml.lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split('#').next().unwrap().trim().to_owned())
        .filter(|l| !l.is_empty())
        .collect()
}

#[test]
fn issue_44_a_ros2_mcap_fits_as_its_csv_does() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&run(d, &["run", &fig7(), "-o", "run.csv"]));
    ok(&run(d, &["run", &fig7(), "-o", "run.mcap", "--profile", "ros2"]));
    // Also an MCAP not named .mcap: found by its magic.
    fs::copy(d.join("run.mcap"), d.join("run.bag")).unwrap();
    let from_csv = ok(&run(d, &["identify", "run.csv", "-o", "csv.toml"]));
    let from_mcap = ok(&run(d, &["identify", "run.mcap", "-o", "mcap.toml"]));
    ok(&run(d, &["identify", "run.bag", "-o", "bag.toml"]));
    // The same numbers, bit for bit: /joint_states carries the f64 values of the CSV and
    // the stamps are the sample times to the ns (the fit only takes time differences).
    let csv = fs::read_to_string(d.join("csv.toml")).unwrap();
    let mcap = fs::read_to_string(d.join("mcap.toml")).unwrap();
    assert!(mcap.contains("from run.mcap"), "{mcap}");
    assert_eq!(values(&csv), values(&mcap));
    assert_eq!(values(&csv), values(&fs::read_to_string(d.join("bag.toml")).unwrap()));
    assert!(values(&csv).iter().any(|l| l.starts_with("mass = ")), "{csv}");
    let summary = |s: &str| s.lines().filter(|l| !l.starts_with("wrote")).map(str::to_owned).collect::<Vec<_>>();
    assert_eq!(summary(&from_csv), summary(&from_mcap));
    // replay: the same errors, the pose from /odom (measured = true pose in fig7).
    let r_csv = ok(&run(d, &["replay", "run.csv", "--robot", "csv.toml", "--horizon", "1"]));
    let r_mcap = ok(&run(d, &["replay", "run.mcap", "--robot", "csv.toml", "--horizon", "1"]));
    let body = |s: &str| s.lines().skip(1).map(str::to_owned).collect::<Vec<_>>();
    assert_eq!(body(&r_csv), body(&r_mcap));
    assert!(!r_mcap.lines().nth(2).unwrap().trim_end().ends_with('-'), "no pose read from /odom: {r_mcap}");
    // --namespace picks a robot; a namespace without one is refused naming /joint_states.
    ok(&run(d, &["identify", "run.mcap", "--namespace", "/", "-o", "ns.toml"]));
    let e = refused(&run(d, &["identify", "run.mcap", "--namespace", "/run9", "-o", "x.toml"]));
    assert!(e.contains("run.mcap: no /joint_states messages"), "{e}");
    // A voltage fit: JointState has no voltage.
    let e = refused(&run(d, &["identify", "run.mcap", "--drive", "dc_motor", "-o", "x.toml"]));
    assert!(e.contains("per-wheel voltage is not in a ROS 2 log") && e.contains("JointState"), "{e}");
    // --namespace is for an MCAP only.
    let e = refused(&run(d, &["identify", "run.csv", "--namespace", "/run1", "-o", "x.toml"]));
    assert!(e.contains("--namespace"), "{e}");
    assert!(!d.join("x.toml").exists());
}

/// A `sensor_msgs/msg/JointState` in CDR (little endian), every array given in full.
fn joint_state(ns: u64, names: &[&str], position: &[f64], velocity: &[f64], effort: &[f64]) -> Vec<u8> {
    let mut b = vec![0u8, 1, 0, 0];
    let align = |b: &mut Vec<u8>, n: usize| {
        while !(b.len() - 4).is_multiple_of(n) {
            b.push(0);
        }
    };
    let u32 = |b: &mut Vec<u8>, v: u32| {
        align(b, 4);
        b.extend_from_slice(&v.to_le_bytes());
    };
    let string = |b: &mut Vec<u8>, s: &str| {
        u32(b, s.len() as u32 + 1);
        b.extend_from_slice(s.as_bytes());
        b.push(0);
    };
    u32(&mut b, (ns / 1_000_000_000) as u32);
    u32(&mut b, (ns % 1_000_000_000) as u32);
    string(&mut b, "");
    u32(&mut b, names.len() as u32);
    for n in names {
        string(&mut b, n);
    }
    for seq in [position, velocity, effort] {
        u32(&mut b, seq.len() as u32);
        for x in seq {
            align(&mut b, 8);
            b.extend_from_slice(&x.to_le_bytes());
        }
    }
    b
}

fn write_mcap(path: &Path, messages: &[Vec<u8>]) {
    let mut w = mcap::Writer::new(BufWriter::new(fs::File::create(path).unwrap())).unwrap();
    let schema = w.add_schema("sensor_msgs/msg/JointState", "ros2msg", b"string[] name\n").unwrap();
    let channel = w.add_channel(schema, "/joint_states", "cdr", &BTreeMap::new()).unwrap();
    for (i, data) in messages.iter().enumerate() {
        let t = i as u64 * 10_000_000;
        let header =
            mcap::records::MessageHeader { channel_id: channel, sequence: i as u32, log_time: t, publish_time: t };
        w.write_to_known_channel(&header, data).unwrap();
    }
    w.finish().unwrap();
}

#[test]
fn issue_44_a_ros2_mcap_without_what_the_fit_needs_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let wheels = ["wheel_left_joint", "wheel_right_joint"];
    let ns = |i: u64| i * 10_000_000;
    // No efforts: the wheel torques are missing.
    let msgs: Vec<Vec<u8>> =
        (0..20).map(|i| joint_state(ns(i), &wheels, &[0.1 * i as f64; 2], &[1.0; 2], &[])).collect();
    write_mcap(&d.join("no-effort.mcap"), &msgs);
    let e = refused(&run(d, &["identify", "no-effort.mcap", "-o", "x.toml"]));
    assert!(e.contains("no-effort.mcap: /joint_states: no effort"), "{e}");
    // Efforts but neither positions nor velocities.
    let msgs: Vec<Vec<u8>> = (0..20).map(|i| joint_state(ns(i), &wheels, &[], &[], &[0.1; 2])).collect();
    write_mcap(&d.join("no-wheels.mcap"), &msgs);
    let e = refused(&run(d, &["identify", "no-wheels.mcap", "-o", "x.toml"]));
    assert!(e.contains("/joint_states: neither position nor velocity"), "{e}");
    // A joint missing: no left wheel.
    let msgs: Vec<Vec<u8>> =
        (0..20).map(|i| joint_state(ns(i), &["wheel_right_joint", "arm"], &[0.0; 2], &[0.0; 2], &[0.1; 2])).collect();
    write_mcap(&d.join("one-wheel.mcap"), &msgs);
    let e = refused(&run(d, &["replay", "one-wheel.mcap", "--robot", "robot.toml"]));
    // (the robot file is read first: give one)
    assert!(e.contains("robot.toml"), "{e}");
    fs::write(d.join("robot.toml"), "[robot]\nmass = 5.0\n").unwrap();
    let e = refused(&run(d, &["replay", "one-wheel.mcap", "--robot", "robot.toml"]));
    assert!(e.contains("/joint_states") && e.contains("no left and right wheel"), "{e}");
    assert!(!d.join("x.toml").exists());
}
