//! Issue 39: what a fourth attack broke, one test per defect (`regression_39_N_...`).
//! Set `WMR_CLI_UNDER_TEST` to a `wmr-cli` binary to run them against another build (the
//! code before a fix, to see a test fail).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

mod wait;

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

fn write(dir: &Path, name: &str, body: &str) -> PathBuf {
    let p = dir.join(name);
    fs::write(&p, body).unwrap();
    p
}

/// Exit 2, one line on stderr starting `wmr-cli: error:` and holding each of `words`,
/// no panic.
fn assert_one_line_error(o: &Output, what: &str, words: &[&str]) {
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{what}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{what}: one line: {err}");
    assert!(err.starts_with("wmr-cli: error: "), "{what}: {err}");
    for w in words {
        assert!(err.contains(w), "{what}: stderr lacks {w:?}: {err}");
    }
    assert!(!err.contains("panicked"), "{what}: {err}");
}

/// A short run of the robot of preset `robots/mine.toml` (`paper` for the built-in one).
const PRESET: &str = "[robot]\nfrom = \"robots/mine.toml\"\n[sim]\nt_end = 1.0\n[[run]]\ngoal = { x = 1.0, y = 1.0, theta_deg = 90.0 }\n";

/// Issue 39 item 14: `read_text` checked the path's metadata, then opened the path again:
/// a file swapped for a FIFO in between blocked `check` for ever. Now the path is opened
/// once, without blocking, and the opened handle is checked: each `check` of a path that
/// flips between a scenario and a FIFO ends at once, read or refused.
#[test]
fn regression_39_14_a_file_swapped_for_a_fifo_never_blocks_a_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_path_buf();
    write(&d, "real.toml", &PRESET.replace("robots/mine.toml", "paper"));
    let fifo = d.join("pipe");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    std::os::unix::fs::symlink("real.toml", d.join("s.toml")).unwrap();
    // Flip s.toml between the two as fast as renames go, until told to stop.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flipper = {
        let (stop, d) = (stop.clone(), d.clone());
        std::thread::spawn(move || {
            let mut flips = 0u64;
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                let target = if flips.is_multiple_of(2) { "pipe" } else { "real.toml" };
                let tmp = d.join("next.link");
                let _ = fs::remove_file(&tmp);
                std::os::unix::fs::symlink(target, &tmp).unwrap();
                fs::rename(&tmp, d.join("s.toml")).unwrap();
                flips += 1;
            }
            flips
        })
    };
    let (mut read, mut refused) = (0, 0);
    for i in 0..300 {
        let mut child = bin()
            .current_dir(&d)
            .args(["check", "s.toml"])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let limit = Duration::from_secs(20);
        let (status, err) = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            wait::exit_within(&mut child, limit, &format!("check #{i} of a path flipping to a FIFO"))
        })) {
            Ok(done) => done,
            Err(e) => {
                stop.store(true, std::sync::atomic::Ordering::Relaxed);
                std::panic::resume_unwind(e)
            }
        };
        match status.code() {
            Some(0) => read += 1,
            Some(2) => {
                assert!(err.contains("not a regular file") || err.contains("No such file"), "{err}");
                refused += 1;
            }
            c => panic!("check #{i}: exit {c:?}: {err}"),
        }
    }
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    let flips = flipper.join().unwrap();
    assert!(flips > 300, "{flips} flips");
    assert!(read > 0 && refused > 0, "{read} read, {refused} refused");
    // A FIFO and a folder named directly are refused at once too.
    for name in ["pipe", "."] {
        let o = run_in(&d, &["check", name]);
        assert_one_line_error(&o, name, &["cannot read"]);
    }
}
