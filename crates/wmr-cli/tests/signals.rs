//! Issue 12, defect 4: SIGINT, SIGTERM and SIGHUP (what Ctrl-C, `timeout`, `kill` and
//! systemd send) while OUT is being written: the process ends by that signal, OUT keeps
//! its old contents and no temporary file is left.

use std::fs;
use std::os::unix::process::ExitStatusExt as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Four runs of 200 s logged every ms: long enough to be caught writing.
const LONG: &str = "[sim]\nt_end = 200.0\nlog_dt = 0.001\n[[run]]\ngoal = { x = 1.0 }\n[[run]]\ngoal = { x = 1.0 }\n\
                    [[run]]\ngoal = { x = 1.0 }\n[[run]]\ngoal = { x = 1.0 }\n";

/// A sweep of 400 runs of 60 s: long enough to be caught running.
const SWEEP: &str = "[sim]\nt_end = 60.0\n[sweep]\nrandom = { n = 400, radius = 1.0 }\n";

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<_> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

/// Starts `args` in a fresh folder with OUT = `out` holding old contents, waits until
/// the temporary file beside OUT holds `min_bytes`, sends `signal`; returns the folder,
/// OUT and how the process ended.
fn signal_mid_write(
    scenario: &str,
    args: &[&str],
    out: &str,
    min_bytes: u64,
    signal: i32,
) -> (tempfile::TempDir, PathBuf, std::process::ExitStatus) {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("s.toml"), scenario).unwrap();
    let out = dir.path().join(out);
    fs::write(&out, "old contents\n").unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .current_dir(dir.path())
        .args(args)
        .env("WMR_CLI_BUFFER_BYTES", "1") // stream: bytes reach the temporary file at once
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let started = Instant::now();
    loop {
        let ready = fs::read_dir(dir.path()).unwrap().flatten().any(|e| {
            e.file_name().to_string_lossy().ends_with(".tmp") && e.metadata().is_ok_and(|m| m.len() >= min_bytes)
        });
        if ready {
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "finished before it could be interrupted");
        assert!(started.elapsed() < Duration::from_secs(120), "no temporary file after 120 s");
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(Command::new("kill").args([format!("-{signal}"), child.id().to_string()]).status().unwrap().success());
    let status = child.wait().unwrap();
    (dir, out, status)
}

fn assert_clean(dir: &Path, out: &Path, status: std::process::ExitStatus, signal: i32) {
    assert_eq!(status.signal(), Some(signal), "ended by the signal itself: {status:?}");
    assert_eq!(fs::read_to_string(out).unwrap(), "old contents\n");
    let left = entries(dir);
    assert!(left.iter().all(|n| !n.ends_with(".tmp")), "temporary file left: {left:?}");
}

const SIGHUP: i32 = 1;
const SIGINT: i32 = 2;
const SIGTERM: i32 = 15;

#[test]
fn regression_12_4_sigterm_and_sighup_leave_no_temporary_file() {
    for signal in [SIGINT, SIGTERM, SIGHUP] {
        let (dir, out, status) =
            signal_mid_write(LONG, &["run", "s.toml", "-o", "long.csv"], "long.csv", 1 << 20, signal);
        assert_clean(dir.path(), &out, status, signal);
        assert_eq!(entries(dir.path()), ["long.csv", "s.toml"]);
    }
    let (dir, out, status) = signal_mid_write(LONG, &["run", "s.toml", "-o", "long.mcap"], "long.mcap", 1, SIGTERM);
    assert_clean(dir.path(), &out, status, SIGTERM);
}

#[test]
fn regression_12_4_signals_during_a_sweep_leave_no_temporary_file() {
    for signal in [SIGINT, SIGTERM, SIGHUP] {
        // The sweep's CSV is opened before the runs: its (empty) temporary file exists.
        let (dir, out, status) = signal_mid_write(SWEEP, &["sweep", "s.toml", "-o", "s.csv"], "s.csv", 0, signal);
        assert_clean(dir.path(), &out, status, signal);
        assert_eq!(entries(dir.path()), ["s.csv", "s.toml"]);
    }
}
