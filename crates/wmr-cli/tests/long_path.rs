//! Issue 38 item 9: a recorded path of any length. A `[reference] kind = "file"` held at
//! most 64 points (the core's fixed waypoint storage), so a path recorded from a robot
//! (thousands of poses) was refused; now the scenario gives the path storage of its own
//! size (up to `wmr_scenario::reference::MAX_PATH_POINTS`), and only a trace, which the
//! firmware replays in its fixed storage, keeps 64 and says so. Set `WMR_CLI_UNDER_TEST`
//! to another `wmr-cli` (the code before the fix) to see these fail.

use std::path::Path;
use std::process::{Command, Output};

fn bin() -> Command {
    match std::env::var_os("WMR_CLI_UNDER_TEST") {
        Some(b) => Command::new(b),
        None => Command::new(env!("CARGO_BIN_EXE_wmr-cli")),
    }
}

fn run_in(dir: &Path, args: &[&str]) -> Output {
    bin().current_dir(dir).args(args).output().expect("spawn wmr-cli")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// 2,000 poses logged at 50 Hz on three quarters of a circle of 2 m radius about the
/// origin, from (2, 0) to (0, -2), as `t,x,y` (micrometres, as a recorder writes them).
fn recorded_csv() -> String {
    let mut s = String::from("t,x,y\n");
    for i in 0..2000 {
        let a = i as f64 * 1.5 * std::f64::consts::PI / 1999.0;
        s.push_str(&format!("{:.2},{:.6},{:.6}\n", i as f64 * 0.02, 2.0 * a.cos(), 2.0 * a.sin()));
    }
    s
}

fn scenario(law: &str) -> String {
    format!(
        "[reference]\nkind = \"file\"\npath = \"rec.csv\"\nspeed = 0.3\naccel_max = 0.5\n\
         [controller]\nkind = \"{law}\"\n[sim]\nt_end = 45.0\ntracking_tolerance = 0.05\n\
         [[run]]\nstart = {{ x = 2.0, y = 0.0, theta_deg = 90.0 }}\n"
    )
}

/// The last row's (x, y) of a run's CSV.
fn final_xy(csv: &str) -> (f64, f64) {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap_or_else(|| panic!("no column {n}: {header:?}"));
    let (ix, iy) = (col("x"), col("y"));
    let last: Vec<f64> = lines.last().unwrap().split(',').map(|v| v.parse().unwrap_or(f64::NAN)).collect();
    (last[ix], last[iy])
}

#[test]
fn regression_38_9_a_recorded_path_of_2000_points_is_tracked_and_followed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("rec.csv"), recorded_csv()).unwrap();
    for law in ["kanayama", "pure_pursuit"] {
        std::fs::write(d.join("s.toml"), scenario(law)).unwrap();
        let o = run_in(d, &["check", "s.toml"]);
        assert_eq!(o.status.code(), Some(0), "{law}: check: {}", text(&o.stderr));
        assert!(text(&o.stdout).contains("2000 points"), "{law}: {}", text(&o.stdout));
        let o = run_in(d, &["run", "s.toml", "-o", "out.csv"]);
        assert_eq!(o.status.code(), Some(0), "{law}: run: {}", text(&o.stderr));
        assert!(text(&o.stdout).contains("converged"), "{law}: {}", text(&o.stdout));
        // The path ends at (0, -2): the robot is there, 45 s later (the profile takes 32.7 s).
        let (x, y) = final_xy(&std::fs::read_to_string(d.join("out.csv")).unwrap());
        assert!(x.hypot(y + 2.0) < 0.02, "{law}: ends at ({x}, {y}), not (0, -2)");
    }
}

/// A trace is what the firmware replays, in its fixed storage of 64 points: the error
/// names the key, the limit and what to do, on one line, exit 2.
#[test]
fn regression_38_9_a_trace_of_a_long_path_says_the_firmware_holds_64_points() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("rec.csv"), recorded_csv()).unwrap();
    std::fs::write(d.join("s.toml"), scenario("kanayama")).unwrap();
    let o = run_in(d, &["trace", "s.toml", "-o", "t.bin"]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    for w in ["reference.path", "at most 64 points", "thin the path", "2000"] {
        assert!(err.contains(w), "lacks {w:?}: {err}");
    }
    assert!(!d.join("t.bin").exists());
}
