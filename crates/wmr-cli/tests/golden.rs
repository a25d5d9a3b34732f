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
