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
        std::fs::read(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/fig7-c4c77d1.csv")).unwrap();
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
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/fig7-c4c77d1.csv"))
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
