//! Issue 39: what a fourth attack broke, one test per defect (`regression_39_N_...`).
//! Set `WMR_CLI_UNDER_TEST` to a `wmr-cli` binary to run them against another build (the
//! code before a fix, to see a test fail).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

mod skip;
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

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(p)
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<_> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
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

/// A reference CSV (`[reference] kind = "file"`).
const REF_CSV: &str = "t,x,y\n0,0,0\n1,0.3,0\n2,0.6,0.1\n3,0.9,0.3\n";

/// A short tracking run along `ref.csv`.
const TRACK: &str = "[reference]\nkind = \"file\"\npath = \"ref.csv\"\n[controller]\nkind = \"kanayama\"\n\
                     [sim]\nt_end = 1.0\n[[run]]\nstart = { x = 0.0, y = 0.0, theta_deg = 0.0 }\n";

/// A short sweep along `ref.csv`.
const SWEEP_TRACK: &str = "[sim]\nt_end = 0.5\n[sweep]\ncontrollers = [{ kind = \"kanayama\" }]\n\
                           references = [{ kind = \"circle\" }, { kind = \"file\", path = \"ref.csv\" }]\n\
                           random = { n = 2, radius = 0.1 }\n";

/// A short run of the robot of preset `robots/mine.toml` (`paper` for the built-in one).
const PRESET: &str = "[robot]\nfrom = \"robots/mine.toml\"\n[sim]\nt_end = 1.0\n[[run]]\ngoal = { x = 1.0, y = 1.0, theta_deg = 90.0 }\n";

/// Issue 39 item 3: `-o` and `--layout` replaced the files a scenario names (a reference
/// CSV, a robot preset), also through a link; only the scenario file itself was protected.
#[test]
fn regression_39_3_outputs_never_replace_a_file_the_scenario_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "trk.toml", TRACK);
    write(d, "sw.toml", SWEEP_TRACK);
    write(d, "pre.toml", PRESET);
    let csv = write(d, "ref.csv", REF_CSV);
    fs::create_dir(d.join("robots")).unwrap();
    let preset_text = fs::read_to_string(repo("robots/paper.toml")).unwrap();
    let preset = write(d, "robots/mine.toml", &preset_text);
    std::os::unix::fs::symlink("ref.csv", d.join("link.csv")).unwrap();
    fs::hard_link(&csv, d.join("hard.csv")).unwrap();
    fs::hard_link(&preset, d.join("hard.toml")).unwrap();
    let before = entries(d);
    let reference = ["ref.csv", "reference.path", "trk.toml"];
    for (args, words) in [
        (vec!["run", "trk.toml", "-o", "ref.csv"], &reference[..]),
        (vec!["run", "trk.toml", "-o", "link.csv"], &reference),
        (vec!["run", "trk.toml", "-o", "hard.csv"], &reference),
        (vec!["run", "trk.toml", "-o", "./ref.csv", "--format", "mcap"], &reference),
        (vec!["run", "trk.toml", "-o", "out.mcap", "--layout", "ref.csv"], &reference),
        (vec!["run", "trk.toml", "-o", "out.mcap", "--layout", "link.csv"], &reference),
        (vec!["trace", "trk.toml", "-o", "ref.csv", "--format", "csv"], &reference),
        (vec!["layout", "trk.toml", "-o", "ref.csv"], &reference),
        (vec!["sweep", "sw.toml", "-o", "ref.csv"], &["ref.csv", "sweep.references[1].path", "sw.toml"]),
        (vec!["run", "pre.toml", "-o", "robots/mine.toml", "--format", "csv"], &["robots/mine.toml", "robot.from"]),
        (vec!["run", "pre.toml", "-o", "hard.toml", "--format", "csv"], &["robots/mine.toml", "robot.from"]),
        (vec!["run", "pre.toml", "-o", "out.mcap", "--layout", "robots/mine.toml"], &["robot.from"]),
        (vec!["layout", "pre.toml", "-o", "robots/mine.toml"], &["robot.from"]),
    ] {
        let what = args.join(" ");
        let o = run_in(d, &args);
        assert_one_line_error(&o, &what, &["is the input file"]);
        assert_one_line_error(&o, &what, words);
        assert_eq!(fs::read_to_string(&csv).unwrap(), REF_CSV, "{what}: ref.csv changed");
        assert_eq!(fs::read_to_string(&preset).unwrap(), preset_text, "{what}: the preset changed");
        assert_eq!(entries(d), before, "{what}: files left or removed");
    }
    assert!(fs::symlink_metadata(d.join("link.csv")).unwrap().file_type().is_symlink());
    // Live view: LAYOUT is refused before the server starts (it used to be replaced, then
    // the server waited for a viewer).
    let mut child = bin()
        .current_dir(d)
        .args(["run", "trk.toml", "--live", "127.0.0.1:0", "--layout", "ref.csv"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (status, err) = wait::exit_within(&mut child, Duration::from_secs(60), "run --live --layout ref.csv");
    assert_eq!(status.code(), Some(2), "{err}");
    assert!(err.contains("is the input file ref.csv (reference.path in trk.toml)"), "{err}");
    assert_eq!(fs::read_to_string(&csv).unwrap(), REF_CSV);
    assert_eq!(entries(d), before);
    // What the scenario did not read stays writable: a built-in preset names no file.
    write(d, "builtin.toml", &PRESET.replace("robots/mine.toml", "paper"));
    let o = run_in(d, &["run", "builtin.toml", "-o", "out.csv"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
}

/// Issue 39 item 12: clap's errors were 4 to 7 lines without the `wmr-cli: error:`
/// prefix; now one line with it, exit 2. Help and the version print as before, exit 0.
#[test]
fn regression_39_12_command_line_errors_are_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "s.toml", PRESET.replace("robots/mine.toml", "paper").as_str());
    for (args, word) in [
        (vec!["run"], "FILE"),
        // `run s.toml` prints the summary (issue 40); --format without -o is an error.
        (vec!["run", "s.toml", "--format", "csv"], "-o OUT"),
        (vec!["run", "s.toml", "-o", "x.csv", "--bogus"], "--bogus"),
        (vec!["frobnicate", "s.toml"], "frobnicate"),
        (vec!["trace", "s.toml", "-o", "x.bin", "--run", "first"], "--run"),
        (vec!["run", "s.toml", "--live", "not-an-address"], "--live"),
        (vec!["run", "s.toml", "-o", "x.csv", "--format", "json"], "json"),
        (vec!["run", "s.toml", "-o", "x.csv", "--speed", "2"], "--speed"),
        (vec!["run", "s.toml", "-o", "x.csv", "--layout", "x.json"], "--layout"),
        (vec!["run", "s.toml", "--live", "127.0.0.1:0", "-o", "x.csv"], "--live"),
        (vec!["check", "s.toml", "extra"], "extra"),
        (vec!["check", "s.toml", "--\u{1b}[31mred"], "red"),
    ] {
        let what = args.join(" ");
        let o = run_in(d, &args);
        assert_one_line_error(&o, &what, &[word]);
        assert!(o.stdout.is_empty(), "{what}: {}", text(&o.stdout));
        assert_eq!(entries(d), ["s.toml"], "{what}");
    }
    for args in [vec!["--help"], vec!["run", "--help"], vec!["help", "sweep"], vec!["-h"], vec!["--version"]] {
        let o = run_in(d, &args);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", text(&o.stderr));
        assert!(o.stderr.is_empty(), "{args:?}: {}", text(&o.stderr));
        let out = text(&o.stdout);
        assert!(out.starts_with("wmr-cli") || out.contains("Usage: wmr-cli"), "{args:?}: {out}");
        assert!(args[0] == "--version" || out.lines().count() > 5, "{args:?}: {out}");
    }
}

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

/// `wmr-cli ARGS` in `dir` under a 1.5 GB address-space cap, awaited for at most 120 s:
/// its exit status and stderr. `None` when prlimit is missing (the skip is recorded).
fn capped(dir: &Path, args: &[&str]) -> Option<(std::process::ExitStatus, String)> {
    if Command::new("prlimit").arg("--version").output().is_err() {
        skip::missing("prlimit", "prlimit (util-linux) is missing: the memory cap cannot be set");
        return None;
    }
    let program = std::env::var_os("WMR_CLI_UNDER_TEST").unwrap_or_else(|| env!("CARGO_BIN_EXE_wmr-cli").into());
    let mut child = Command::new("prlimit")
        .arg("--as=1500000000")
        .arg(program)
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    Some(wait::exit_within(&mut child, Duration::from_secs(120), &args.join(" ")))
}

/// Issue 39 items 1 and 4: the MCAP (and `--live`) drawing of a tracking run's reference
/// cut it into dashes of half a half-track along the whole path, all held at once, and
/// `layout` read the reference at every log time: a robot 1e-9 m wide, a line at 1e5 m/s,
/// a figure-eight 1e300 m wide and a run of 1e6 s aborted under a memory cap (SIGABRT),
/// leaving their temporary files. Both now read a bounded number of points.
#[test]
fn regression_39_1_4_reference_drawings_and_layouts_are_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let track = |reference: &str, extra: &str, start: &str| {
        format!("{extra}[reference]\n{reference}\n[controller]\nkind = \"kanayama\"\n[[run]]\nstart = {{ {start} }}\n")
    };
    let on_circle = "x = 0.0, y = -1.0, theta_deg = 0.0";
    let cases = [
        ("thin.toml", track("kind = \"circle\"", "[robot]\nhalf_track = 1e-9\n", on_circle)),
        ("fast.toml", track("kind = \"line\"\nspeed = 1e5", "", "x = 0.0, y = 0.0, theta_deg = 0.0")),
        ("wide.toml", track("kind = \"figure_eight\"\nwidth = 1e300", "", "x = 0.0, y = 0.0, theta_deg = 45.0")),
    ];
    for (name, body) in &cases {
        write(d, name, body);
        let out = name.replace(".toml", ".mcap");
        let Some((status, err)) = capped(d, &["run", name, "-o", &out]) else { return };
        assert_eq!(status.code(), Some(0), "run {name}: {status:?}: {err}");
        assert!(fs::metadata(d.join(&out)).unwrap().len() < 50 << 20, "{out}: too large");
        let Some((status, err)) = capped(d, &["layout", name, "-o", &name.replace(".toml", ".json")]) else { return };
        assert_eq!(status.code(), Some(0), "layout {name}: {status:?}: {err}");
    }
    write(d, "long.toml", &track("kind = \"circle\"", "[sim]\nt_end = 1e6\n", on_circle));
    let Some((status, err)) = capped(d, &["layout", "long.toml", "-o", "long.json"]) else { return };
    assert_eq!(status.code(), Some(0), "layout long.toml: {status:?}: {err}");
    let layout: serde_json::Value = serde_json::from_slice(&fs::read(d.join("long.json")).unwrap()).unwrap();
    assert!(layout["configById"]["3D!wmr-plane"].is_object(), "{layout}");
    let mut want: Vec<String> = ["fast", "long", "thin", "wide"]
        .iter()
        .flat_map(|n| [format!("{n}.json"), format!("{n}.mcap"), format!("{n}.toml")])
        .collect();
    want.retain(|f| f != "long.mcap");
    assert_eq!(entries(d), want, "no temporary file left");
}
