//! The paper's Fig. 7 run writes exactly the CSV an earlier version wrote
//! (`tests/fixtures/README.md` gives its provenance): restructuring the loop must not
//! change a single number.

use std::path::PathBuf;
use std::process::Command;

#[test]
fn fig7_csv_is_byte_identical_to_the_fixture() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fig7.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .args(["run", root.join("examples/paper/fig7.toml").to_str().unwrap(), "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let got = std::fs::read(&out).unwrap();
    let want =
        std::fs::read(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/fig7-issue12.csv")).unwrap();
    assert_eq!(got.len(), want.len(), "length differs");
    if let Some(i) = got.iter().zip(&want).position(|(a, b)| a != b) {
        let line = want[..i].iter().filter(|&&b| b == b'\n').count() + 1;
        panic!("first difference at byte {i}, line {line}");
    }
}

/// A `[sensor]` table with every default and a `[controller.model]` equal to `[robot]`
/// change no number: the CSV is the fixture's, plus the measured pose, equal to the true one.
#[test]
fn fig7_with_a_default_sensor_and_an_equal_model_adds_only_the_measured_pose() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = tempfile::tempdir().unwrap();
    let fig7 = std::fs::read_to_string(root.join("examples/paper/fig7.toml")).unwrap();
    let scenario = dir.path().join("fig7-sensor.toml");
    std::fs::write(&scenario, format!("{fig7}\n[sensor]\nseed = 1\n\n[controller.model]\nwheel_radius = 0.1\n"))
        .unwrap();
    let out = dir.path().join("fig7.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .args(["run", scenario.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let got = std::fs::read_to_string(&out).unwrap();
    let want =
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/fig7-issue12.csv"))
            .unwrap();
    assert_eq!(got.lines().count(), want.lines().count());
    for (i, (g, w)) in got.lines().zip(want.lines()).enumerate() {
        let fields: Vec<&str> = g.split(',').collect();
        assert_eq!(fields.len(), 19, "line {}", i + 1);
        assert_eq!(fields[..16].join(","), w, "line {}", i + 1);
        if i == 0 {
            assert_eq!(fields[16..], ["x_meas", "y_meas", "theta_meas"]);
        } else {
            assert_eq!(fields[16..], fields[2..5], "line {}: measured = true pose", i + 1);
        }
    }
}

/// The fixture's `t` column is the exact decimal k / 100 s (log_dt = 10 ms): no float
/// noise such as `0.07000000000000001` (issue 12, defect 15).
#[test]
fn regression_12_15_fixture_times_are_exact_decimals() {
    let want =
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/fig7-issue12.csv"))
            .unwrap();
    for (k, line) in want.lines().skip(1).enumerate() {
        let t = line.split(',').nth(1).unwrap();
        let (whole, frac) = t.split_once('.').unwrap_or((t, ""));
        assert!(frac.len() <= 2, "line {}: t = {t}", k + 2);
        let hundredths: u64 = format!("{whole}{frac:0<2}").parse().unwrap();
        assert_eq!(hundredths, k as u64, "line {}: t = {t}", k + 2);
    }
}
