//! Odometry as the controller's pose end to end (issue 24, `issues show 24`): the CSV
//! carries the true, fused and dead-reckoned poses, the summary the drift, and the trace
//! refuses a scenario it cannot hold.

use std::fs;
use std::path::Path;
use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wmr-cli")).args(args).output().expect("spawn wmr-cli")
}

/// 3 s of Fig. 7 on odometry with the model's wheel radius 1 % large.
const ON_ODOMETRY: &str = include_str!("fixtures/odometry-3s.toml");

fn write(dir: &Path, body: &str) -> String {
    let p = dir.join("odo.toml");
    fs::write(&p, body).unwrap();
    p.to_str().unwrap().to_owned()
}

#[test]
fn csv_has_true_fused_and_odometry_poses_and_the_summary_the_drift() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), ON_ODOMETRY);
    let out = dir.path().join("odo.csv");
    let o = run(&["run", &file, "-o", out.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let body = fs::read_to_string(&out).unwrap();
    let mut lines = body.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no {name}: {header:?}"));
    let (x, y, xm, ym, xo, yo) = (col("x"), col("y"), col("x_meas"), col("y_meas"), col("x_odom"), col("y_odom"));
    assert_eq!(&header[header.len() - 3..], ["x_odom", "y_odom", "theta_odom"]);
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|f| f.parse().unwrap()).collect()).collect();
    let last = rows.last().unwrap();
    // Without fixes the controller's pose is the odometry itself.
    for r in &rows {
        assert_eq!((r[xm], r[ym]), (r[xo], r[yo]));
    }
    // The radius the controller believes is 1 % large: the odometry runs ahead of the truth,
    // and the drift the summary prints is the CSV's own last row (printed to 4 decimals).
    let drift = (last[xo] - last[x]).hypot(last[yo] - last[y]);
    assert!(drift > 1e-3, "the odometry should drift: {drift}");
    let line = stdout.lines().find(|l| l.contains("odometry drift")).unwrap_or_else(|| panic!("{stdout}"));
    assert!(line.contains(&format!("odometry drift {drift:.4} m (")), "{line} vs {drift}");
    assert!(line.contains("% of "), "{line}");
}

#[test]
fn absolute_runs_keep_their_columns_and_summary() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), &ON_ODOMETRY.replace("pose = \"odometry\"", "pose = \"absolute\""));
    let out = dir.path().join("abs.csv");
    let o = run(&["run", &file, "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let header = fs::read_to_string(&out).unwrap().lines().next().unwrap().to_owned();
    assert!(header.ends_with("x_meas,y_meas,theta_meas"), "{header}");
    assert!(!String::from_utf8_lossy(&o.stdout).contains("odometry"));
}

#[test]
fn trace_refuses_odometry_by_name_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), ON_ODOMETRY);
    let out = dir.path().join("t.bin");
    let o = run(&["trace", &file, "-o", out.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("sensor.pose") && err.contains("odometry"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists());
}

/// A sweep whose odometry is one `with` entry among absolute ones (examples/robustness.toml):
/// the drift table is printed for the key whose runs were on odometry only; the absolute
/// keys had no drift to report (they printed rows of NaN% before).
#[test]
fn drift_table_only_for_the_keys_on_odometry() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "[sim]\nt_end = 2.0\n[sweep]\ngoal = { x = 0.5, y = 0.0, theta_deg = 0.0 }\ncontrollers = [{ kind = \"polar\" }]\n\
         random = { n = 2, seed = 1, radius = 1.0, min_radius = 0.5 }\nvary = [\n\
         { key = \"world.slope_deg\", values = [0.0, 2.0] },\n\
         { key = \"sensor.fix_rate_hz\", values = [0.0, 1.0], with = { \"sensor.pose\" = \"odometry\" } },\n]\n",
    );
    let out = run(&["sweep", &path, "-o", dir.path().join("o.csv").to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        stdout.contains("odometry drift at the end (mean, % of the distance travelled) against sensor.fix_rate_hz")
    );
    assert!(!stdout.contains("odometry drift at the end (mean, % of the distance travelled) against world.slope_deg"));
    assert!(!stdout.contains("NaN"), "{stdout}");
}
