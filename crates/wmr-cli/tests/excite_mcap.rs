//! Issue 44, last item: `wmr-cli excite --speed-max` writes the profile as body twists, a
//! CSV or a ROS 2 MCAP of /cmd_vel (geometry_msgs/msg/Twist, CDR) that `ros2 bag play`
//! plays: every message is the CSV's row, at the profile's time; bad flags are refused
//! naming the flag, exit 2. (crates/wmr-py/tests/test_excite_mcap.py reads the same file
//! with `rosbags` and `mcap_ros2`.)

use std::collections::BTreeMap;
use std::fs;

use crate::identify_common::{ok, refused, run};

/// The CSV's rows by run: (t, v_cmd, omega_cmd).
fn csv_rows(text: &str) -> BTreeMap<usize, Vec<[f64; 3]>> {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("run,t,v_cmd,omega_cmd"));
    let mut runs: BTreeMap<usize, Vec<[f64; 3]>> = BTreeMap::new();
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        let v = |i: usize| f[i].parse::<f64>().unwrap();
        runs.entry(f[0].parse().unwrap()).or_default().push([v(1), v(2), v(3)]);
    }
    runs
}

/// geometry_msgs/Twist in CDR by hand: the 4-byte header 00 01 00 00, then six f64
/// (linear x, y, z, angular x, y, z), little-endian, 8-aligned from the header's end.
fn twist(data: &[u8]) -> [f64; 6] {
    assert_eq!(data.len(), 4 + 48);
    assert_eq!(&data[..4], &[0, 1, 0, 0]);
    let mut out = [0.0; 6];
    for (i, o) in out.iter_mut().enumerate() {
        *o = f64::from_le_bytes(data[4 + 8 * i..12 + 8 * i].try_into().unwrap());
    }
    out
}

#[test]
fn issue_44_excite_writes_cmd_vel_as_the_csvs_rows() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fs::create_dir(d.join("bag")).unwrap();
    let robot = format!("{}/../../examples/identify/robot.toml", env!("CARGO_MANIFEST_DIR"));
    let start: u64 = 1_700_000_000_000_000_000;
    let out_csv = ok(&run(d, &["excite", "--robot", &robot, "--speed-max", "0.4", "-o", "twist.csv"]));
    let out_mcap = ok(&run(
        d,
        &[
            "excite",
            "--robot",
            &robot,
            "--speed-max",
            "0.4",
            "-o",
            "bag/twist.mcap",
            "--start-ns",
            &start.to_string(),
            "--pause",
            "2.5",
            "--rosbag2",
        ],
    ));
    // The same table (the safe distances of the twists) before the "wrote" lines.
    let table = |s: &str| s.lines().filter(|l| !l.starts_with("wrote")).map(str::to_owned).collect::<Vec<_>>();
    assert_eq!(table(&out_csv), table(&out_mcap));
    assert!(out_mcap.contains("ros2 bag play bag"), "{out_mcap}");
    let rows = csv_rows(&fs::read_to_string(d.join("twist.csv")).unwrap());
    assert_eq!(rows.len(), 12);

    let bytes = fs::read(d.join("bag/twist.mcap")).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    assert_eq!(summary.channels.len(), 1);
    let channel = summary.channels.values().next().unwrap();
    assert_eq!((channel.topic.as_str(), channel.message_encoding.as_str()), ("/cmd_vel", "cdr"));
    let schema = channel.schema.as_ref().unwrap();
    assert_eq!((schema.name.as_str(), schema.encoding.as_str()), ("geometry_msgs/msg/Twist", "ros2msg"));
    assert!(String::from_utf8_lossy(&schema.data).starts_with("Vector3  linear\nVector3  angular\n"));
    let messages: Vec<_> = mcap::MessageStream::new(&bytes).unwrap().map(Result::unwrap).collect();
    assert_eq!(messages.len(), rows.values().map(Vec::len).sum::<usize>());
    // Run k's row i at start + base_k + i * 10 ms; base_0 = 0, each next base 2.5 s after
    // the last message of the one before. Log time = publish time.
    let mut it = messages.iter();
    let mut base = start;
    for run_rows in rows.values() {
        for (i, r) in run_rows.iter().enumerate() {
            let m = it.next().unwrap();
            assert_eq!(m.log_time, base + i as u64 * 10_000_000);
            assert_eq!(m.log_time, (r[0] * 1e9).round() as u64 + base);
            assert_eq!(m.publish_time, m.log_time);
            let tw = twist(&m.data);
            assert_eq!(tw, [r[1], 0.0, 0.0, 0.0, 0.0, r[2]]);
        }
        // Each test ends on a zero twist (the base is told to stop).
        assert_eq!(run_rows.last().unwrap()[1..], [0.0, 0.0]);
        base += (run_rows.len() as u64 - 1) * 10_000_000 + 2_500_000_000;
    }
    // The twists against the profile's definition: dynamic-linear-forward (run 6) steps to
    // 7/12 of 0.4 m/s; quasistatic-turning-forward (run 2) ramps omega at 0.4 / 12 / R.
    let half_track = 0.2;
    assert!(rows[&6][..rows[&6].len() - 1].iter().all(|r| r[1] == 0.4 * (7.0 / 12.0) && r[2] == 0.0));
    let last = rows[&2][rows[&2].len() - 2];
    assert!((last[2] - 0.4 * 6.0 / 12.0 / half_track).abs() < 1e-12 && last[1] == 0.0, "{last:?}");

    // metadata.yaml as `run --rosbag2` writes it, from the file's own summary.
    let meta = fs::read_to_string(d.join("bag/metadata.yaml")).unwrap();
    assert!(meta.contains("name: \"/cmd_vel\"") && meta.contains("type: \"geometry_msgs/msg/Twist\""), "{meta}");
    assert!(meta.contains(&format!("message_count: {}", messages.len())), "{meta}");
    assert!(meta.contains(&format!("nanoseconds_since_epoch: {start}")), "{meta}");

    // identify fits efforts from /joint_states: a bag of /cmd_vel alone is refused so.
    let e = refused(&run(d, &["identify", "bag/twist.mcap", "-o", "x.toml"]));
    assert!(e.contains("no /joint_states messages"), "{e}");
    // log2csv (the ROS 2 reader identify uses) reads the twists back as v_cmd, omega_cmd.
    let back = ok(&run(d, &["log2csv", "bag/twist.mcap"]));
    let header: Vec<&str> = back.lines().next().unwrap().split(',').collect();
    let (iv, iw) =
        (header.iter().position(|c| *c == "v_cmd").unwrap(), header.iter().position(|c| *c == "omega_cmd").unwrap());
    let read: Vec<[f64; 2]> = back
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            [f[iv].parse().unwrap(), f[iw].parse().unwrap()]
        })
        .collect();
    let want: Vec<[f64; 2]> = rows.values().flatten().map(|r| [r[1], r[2]]).collect();
    assert_eq!(read, want);
}

#[test]
fn issue_44_bad_excite_flags_are_refused_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases: &[(&[&str], &str)] = &[
        (&["-o", "p.mcap"], "--speed-max: a /cmd_vel profile"),
        (&["-o", "p.csv", "--speed-max=-1"], "--speed-max must be > 0 and finite"),
        (&["-o", "p.mcap", "--speed-max", "nan"], "--speed-max must be > 0 and finite"),
        (&["-o", "p.csv", "--start-ns", "5"], "--start-ns describes the /cmd_vel MCAP"),
        (&["-o", "p.csv", "--pause", "1"], "--pause describes the /cmd_vel MCAP"),
        (&["-o", "p.csv", "--rosbag2"], "--rosbag2 describes the /cmd_vel MCAP"),
        (&["-o", "p.mcap", "--speed-max", "1", "--pause", "0"], "--pause must be from the profile's step"),
        (
            &["-o", "p.mcap", "--speed-max", "1", "--start-ns", "18446744073709551615"],
            "--start-ns 18446744073709551615",
        ),
        (&["-o", "p.csv", "--speed-max", "1", "--log", "l.csv"], "--log simulates ROBOT on the wheel commands"),
        (
            &["-o", "-", "--format", "mcap", "--speed-max", "1", "--rosbag2"],
            "--rosbag2 writes metadata.yaml beside OUT",
        ),
    ];
    for (args, expected) in cases {
        let mut all = vec!["excite"];
        all.extend_from_slice(args);
        let o = run(d, &all);
        let e = refused(&o);
        assert!(e.contains(expected), "{args:?}: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(o.stdout.is_empty(), "{args:?}: printed before refusing");
    }
    assert_eq!(fs::read_dir(d).unwrap().count(), 0, "a refused excite wrote a file");
}
