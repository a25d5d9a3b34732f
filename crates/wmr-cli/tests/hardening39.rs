//! Issue 39: what a fourth attack broke, one test per defect (`regression_39_N_...`).
//! Set `WMR_CLI_UNDER_TEST` to a `wmr-cli` binary to run them against another build (the
//! code before a fix, to see a test fail).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use crate::skip;
use crate::wait;

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

/// Issue 39 item 14: a scenario's `[robot] from` and `[reference] path` could name any
/// file on the machine (`..`, absolute paths, links). Now they are read from the
/// scenario's folder and below only, unless `--allow-files-under DIR` allows another:
/// every subcommand that reads a scenario refuses the others in one line naming the key,
/// the file, why, and the flag; nothing is written.
#[test]
fn regression_39_14_file_references_stay_in_the_scenario_folder() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fs::create_dir_all(d.join("project/robots")).unwrap();
    fs::create_dir_all(d.join("project/scenarios/robots")).unwrap();
    let preset = fs::read_to_string(repo("robots/paper.toml")).unwrap();
    write(d, "project/robots/mine.toml", &preset);
    write(d, "project/scenarios/robots/mine.toml", &preset);
    write(d, "secret.csv", REF_CSV);
    write(d, "project/scenarios/ref.csv", REF_CSV);
    std::os::unix::fs::symlink(d.join("secret.csv"), d.join("project/scenarios/link.csv")).unwrap();
    let secret = d.join("secret.csv").canonicalize().unwrap();
    let s = d.join("project/scenarios");
    let tracking = |path: &str| TRACK.replace("ref.csv", path);
    write(&s, "inside.toml", PRESET);
    write(&s, "up.toml", &PRESET.replace("robots/mine.toml", "../robots/mine.toml"));
    write(&s, "absolute.toml", &tracking(&secret.display().to_string()));
    write(&s, "link.toml", &tracking("link.csv"));
    write(&s, "sweep.toml", &SWEEP_TRACK.replace("ref.csv", "../../secret.csv"));
    write(&s, "fine.toml", &tracking("./robots/../ref.csv"));
    let flag = "--allow-files-under";
    let robots = d.join("project/robots").canonicalize().unwrap();
    let cases: [(&str, &str, &str, &Path); 4] = [
        ("up.toml", "robot.from", "../robots/mine.toml", &robots),
        ("absolute.toml", "reference.path", "secret.csv", d),
        ("link.toml", "reference.path", "link.csv", d),
        ("sweep.toml", "sweep.references[1].path", "../../secret.csv", d),
    ];
    for (file, key, named, allow) in cases {
        let subcommands: Vec<Vec<&str>> = if file == "sweep.toml" {
            vec![vec!["check"], vec!["sweep", "-o", "out.csv"]]
        } else {
            vec![
                vec!["check"],
                vec!["run"],
                vec!["run", "-o", "out.csv"],
                vec!["trace", "-o", "out.csv"],
                vec!["layout", "-o", "out.json"],
                vec!["plot", "-o", "plots"],
            ]
        };
        for sub in subcommands {
            let mut args = vec![sub[0], file];
            args.extend(&sub[1..]);
            let what = args.join(" ");
            let before = entries(&s);
            let o = run_in(&s, &args);
            assert_one_line_error(&o, &what, &[key, named, "outside the scenario's folder", flag]);
            assert_eq!(entries(&s), before, "{what}: wrote something");
            // Allowed by the flag (the folder the error names), the same command runs.
            let allow = allow.canonicalize().unwrap();
            let allowed: Vec<&str> = args.iter().copied().chain([flag, allow.to_str().unwrap()]).collect();
            let o = run_in(&s, &allowed);
            assert!(o.status.success(), "{}: {}", allowed.join(" "), text(&o.stderr));
            let _ = fs::remove_file(s.join("out.csv"));
            let _ = fs::remove_file(s.join("out.json"));
            let _ = fs::remove_dir_all(s.join("plots"));
        }
    }
    // The error names the folder to allow: robots/, not the whole machine.
    let o = run_in(&s, &["check", "up.toml"]);
    assert!(text(&o.stderr).contains(&format!("{flag} {}", robots.display())), "{}", text(&o.stderr));
    // Files in the folder and below, `..` that stays inside, and built-in presets run.
    for file in ["inside.toml", "fine.toml"] {
        let o = run_in(&s, &["check", file]);
        assert!(o.status.success(), "{file}: {}", text(&o.stderr));
    }
    let o = run_in(&repo(""), &["check", "examples/turtlebot3.toml"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    // A folder to allow that does not exist is one line too.
    let o = run_in(&s, &["check", "up.toml", flag, "no/such/dir"]);
    assert_one_line_error(&o, "a missing DIR", &[flag, "no/such/dir"]);
}

/// `wmr-cli ARGS` in `dir` under a 1.5 GB address-space cap, awaited for at most 120 s:
/// its exit status and stderr. `None` when prlimit is missing (the skip is recorded).
fn capped(dir: &Path, args: &[&str]) -> Option<(std::process::ExitStatus, String)> {
    capped_at(dir, args, 1_500_000_000)
}

/// [`capped`] under a cap of `bytes` of address space.
fn capped_at(dir: &Path, args: &[&str], bytes: u64) -> Option<(std::process::ExitStatus, String)> {
    if Command::new("prlimit").arg("--version").output().is_err() {
        skip::missing("prlimit", "prlimit (util-linux) is missing: the memory cap cannot be set");
        return None;
    }
    let program = std::env::var_os("WMR_CLI_UNDER_TEST").unwrap_or_else(|| env!("CARGO_BIN_EXE_wmr-cli").into());
    let mut child = Command::new("prlimit")
        .arg(format!("--as={bytes}"))
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
        // The attack's line at 1e5 m/s and figure 1e300 m wide leave the 1 km box and are
        // refused since item 5 (regression_39_5): the largest drawings inside it instead.
        (
            "fast.toml",
            track("kind = \"line\"\nspeed = 9e4", "[sim]\nt_end = 0.01\n", "x = 0.0, y = 0.0, theta_deg = 0.0"),
        ),
        (
            "wide.toml",
            track(
                "kind = \"figure_eight\"\nwidth = 1998.0\nheight = 1998.0\nperiod = 0.01",
                "[robot]\nhalf_track = 1e-9\n",
                "x = 0.0, y = 0.0, theta_deg = 45.0",
            ),
        ),
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

/// A short Kanayama tracking run of the `[reference]` lines `reference`.
fn tracking(reference: &str) -> String {
    format!(
        "[reference]\n{reference}\n[controller]\nkind = \"kanayama\"\n[sim]\nt_end = 1.0\n\
         [[run]]\nstart = {{ x = 0.0, y = 0.0, theta_deg = 0.0 }}\n"
    )
}

/// Issue 39 item 5: references whose keys are each valid but whose state is not finite
/// (a figure-eight's omega_ref = 0/0) or that leave the 1 km box passed `check` and put
/// NaN in every output; they are refused at the key that sets them (f32 in `trace`).
#[test]
fn regression_39_5_references_are_checked_for_what_they_produce() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases = [
        ("kind = \"figure_eight\"\nperiod = 1e300", "reference.period", "line 3"),
        ("kind = \"figure_eight\"\nperiod = 1e-300", "reference.period", "line 3"),
        ("kind = \"figure_eight\"\nwidth = 1e-300\nheight = 1e-300", "reference.width", "line 3"),
        ("kind = \"figure_eight\"\nwidth = 2.1e3", "reference.width", "1050 m"),
        ("kind = \"waypoints\"\npoints = [[0.0, 0.0], [5000.0, 0.0]]", "reference.points[1]", "(5000, 0) m"),
        ("kind = \"line\"\nspeed = 1e300", "reference.speed", "1000 m"),
        ("kind = \"circle\"\nradius = 1e300", "reference.radius", "1e300 m"),
    ];
    for (reference, key, word) in cases {
        write(d, "r.toml", &tracking(reference));
        for cmd in [&["check", "r.toml"][..], &["run", "r.toml", "-o", "r.csv"], &["trace", "r.toml", "-o", "r.bin"]] {
            let o = run_in(d, cmd);
            assert_one_line_error(&o, &format!("{cmd:?} {reference}"), &[key, word]);
        }
        assert!(!d.join("r.csv").exists() && !d.join("r.bin").exists(), "{reference}");
    }
    // A sweep's own references, by their index.
    let sweep = "[sim]\nt_end = 0.5\n[sweep]\ncontrollers = [{ kind = \"kanayama\" }]\n\
                 references = [{ kind = \"circle\" }, { kind = \"figure_eight\", period = 1e300 }]\n\
                 random = { n = 2, radius = 0.1 }\n";
    write(d, "s.toml", sweep);
    assert_one_line_error(&run_in(d, &["check", "s.toml"]), "sweep", &["sweep.references[1].period", "line 5"]);
    // Valid in f64, not in f32: the trace refuses it by the key, and nothing is written.
    write(d, "r.toml", &tracking("kind = \"figure_eight\"\nperiod = 1e25"));
    assert!(run_in(d, &["check", "r.toml"]).status.success());
    let o = run_in(d, &["trace", "r.toml", "-o", "r.bin"]);
    assert_one_line_error(&o, "trace f32", &["reference.period", "f32", "1e25"]);
    assert!(!d.join("r.bin").exists());
}

/// Issue 39 item 9 (references): a reference outside the 1 km box was refused as
/// `run[0].goal.x` at the `[[run]]` line, waypoints at +-1.7e308 as "run[0].goal.x: must be
/// a finite number (got NaN)"; both are named where the value is written.
#[test]
fn regression_39_9_a_reference_outside_the_box_is_named_at_its_key() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases = [
        ("kind = \"circle\"\ncenter = { x = 5000.0 }", "line 3: reference.center.x", "5000 m"),
        ("kind = \"waypoints\"\npoints = [[-1.7e308, 0.0], [1.7e308, 0.0]]", "line 3: reference.points[0]", "-1.7e308"),
    ];
    for (reference, key, word) in cases {
        write(d, "r.toml", &tracking(reference));
        let o = run_in(d, &["check", "r.toml"]);
        assert_one_line_error(&o, reference, &[key, word]);
        assert!(!text(&o.stderr).contains("goal"), "{}", text(&o.stderr));
    }
}

/// Issue 39 item 9 (presets): a bad value inside a preset was reported at the scenario's
/// line with no word of the preset file; now the scenario's `from` line, the preset and
/// the preset's own line. A value the scenario writes over the preset stays the
/// scenario's.
#[test]
fn regression_39_9_a_bad_value_in_a_preset_names_the_preset_and_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let preset = std::fs::read_to_string(repo("robots/turtlebot3_burger.toml")).unwrap();
    let line = 1 + preset.lines().position(|l| l.starts_with("wheel_radius")).expect("the preset gives wheel_radius");
    let bad: String = preset
        .lines()
        .map(|l| if l.starts_with("wheel_radius") { "wheel_radius = -0.033".to_owned() } else { l.to_owned() })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::create_dir_all(d.join("robots")).unwrap();
    write(d, "robots/mine.toml", &bad);
    let run = "[[run]]\nstart = { x = 1.0, y = 1.0, theta_deg = 0.0 }\n";
    write(d, "s.toml", &format!("# my robot\n[robot]\nfrom = \"robots/mine.toml\"\n{run}"));
    let o = run_in(d, &["check", "s.toml"]);
    assert_one_line_error(
        &o,
        "preset value",
        &["line 3: robot.wheel_radius", "-0.033", "robots/mine.toml", &format!("line {line}")],
    );
    // Written over in the scenario: the scenario's value and line, no word of the preset.
    write(d, "s.toml", &format!("[robot]\nfrom = \"robots/mine.toml\"\nwheel_radius = -0.5\n{run}"));
    let o = run_in(d, &["check", "s.toml"]);
    assert_one_line_error(&o, "scenario value", &["line 3: robot.wheel_radius", "-0.5"]);
    assert!(!text(&o.stderr).contains("preset"), "{}", text(&o.stderr));
}

/// Issue 39 item 10 and issue 40 (reporting): a tracking summary printed metres with six
/// decimals and "below 0.01 m after never", the sweep's table a `t_10 mm s` column; now
/// millimetres to the micrometre, "within 10 mm after 1.225 s" or "never within 10 mm",
/// and "s to 10 mm".
#[test]
fn regression_39_10_tracking_summaries_read_in_millimetres() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = "[reference]\nkind = \"circle\"\n[controller]\nkind = \"kanayama\"\n[sim]\nt_end = 3.0\n\
               [[run]]\nstart = { x = 0.3, y = -1.0, theta_deg = 90.0 }\n\
               [[run]]\nstart = { x = -1.5, y = 1.5, theta_deg = 0.0 }\n";
    write(d, "t.toml", two);
    let o = run_in(d, &["run", "t.toml", "-o", "t.csv"]);
    let out = text(&o.stdout);
    assert!(o.status.success(), "{out}{}", text(&o.stderr));
    let lines: Vec<&str> = out.lines().collect();
    let words = ["RMS ", " mm, max ", " mm, final ", " mm, within 10 mm after 1.225 s, converged"];
    assert!(words.iter().all(|w| lines[0].contains(w)), "{out}");
    assert!(lines[1].contains("never within 10 mm"), "{out}");
    assert!(!out.contains(" m,") && !out.contains("0.01 m"), "{out}");
    let sweep = "[sim]\nt_end = 1.0\n[sweep]\ncontrollers = [{ kind = \"kanayama\" }]\n\
                 references = [{ kind = \"circle\" }]\nrandom = { n = 2, radius = 0.1 }\n";
    write(d, "s.toml", sweep);
    let o = run_in(d, &["sweep", "s.toml", "-o", "s.csv"]);
    let out = text(&o.stdout);
    assert!(o.status.success(), "{out}{}", text(&o.stderr));
    assert!(out.contains("s to 10 mm") && !out.contains("t_10"), "{out}");
}

/// Issue 39 item 2: a sweep's `references` were all built (each as large as a reference of
/// 64 waypoints) and named in quadratic time before the run limit was checked: 20,000
/// circles took 28 s and 770 MB to `check`, 200,000 aborted under 4 GB. Now they are
/// counted first: under a 500 MB cap each list ends at once, refused by
/// `sweep.references` (exit 2), and a sweep at the limit still runs.
#[test]
fn regression_39_2_sweep_references_are_counted_before_they_are_built() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sweep = |n: usize, starts: u32| {
        format!(
            "[sim]\nt_end = 0.01\n[sweep]\ncontrollers = [{{ kind = \"kanayama\" }}]\nreferences = [{}]\n\
             random = {{ n = {starts}, radius = 0.1 }}\n",
            vec!["{ kind = \"circle\" }"; n].join(", ")
        )
    };
    for (n, starts, word) in [
        (20_000, 1, "20000 references, more than the limit of 1000"),
        (200_000, 1, "200000 references, more than the limit of 1000"),
        (1_000, 1001, "1000 references x 1001 starts x 1 laws x 1 trials is more than 1000000 runs"),
    ] {
        write(d, "many.toml", &sweep(n, starts));
        let Some((status, err)) = capped_at(d, &["check", "many.toml"], 500_000_000) else { return };
        assert_eq!(status.code(), Some(2), "{n} references: {status:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.starts_with("wmr-cli: error: many.toml: line 5: sweep.references: "), "{err}");
        assert!(err.contains(word), "{err}");
    }
    // At the limit: 1,000 references (two kinds, named circle ... circle#500) are checked
    // and swept under the same cap.
    let at_limit = sweep(1_000, 1).replacen("{ kind = \"circle\" }", "{ kind = \"figure_eight\" }", 500);
    write(d, "limit.toml", &at_limit);
    let Some((status, err)) = capped_at(d, &["sweep", "limit.toml", "-o", "limit.csv"], 500_000_000) else { return };
    assert_eq!(status.code(), Some(0), "{status:?}: {err}");
    let csv = fs::read_to_string(d.join("limit.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1_001, "a row per run");
    assert!(csv.contains("circle#500") && csv.contains("figure_eight#500") && !csv.contains("circle#501"));
}

/// A `run s.toml --live 127.0.0.1:0` of `bin()` in `dir`, killed when dropped.
struct LiveServer {
    child: std::process::Child,
    port: u16,
    stderr: std::sync::mpsc::Receiver<String>,
}

impl Drop for LiveServer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Longest any live test here awaits anything.
const LIVE_DEADLINE: Duration = Duration::from_secs(60);

impl LiveServer {
    /// Starts the server on `scenario` and awaits its `live on` line.
    fn start(dir: &Path, scenario: &str, args: &[&str]) -> Self {
        use std::io::BufRead as _;
        write(dir, "s.toml", scenario);
        let mut child = bin()
            .current_dir(dir)
            .args(["run", "s.toml", "--live", "127.0.0.1:0"])
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let (tx, stderr) = std::sync::mpsc::channel();
        let pipe = child.stderr.take().unwrap();
        std::thread::spawn(move || {
            for line in std::io::BufReader::new(pipe).lines().map_while(Result::ok) {
                let _ = tx.send(line);
            }
        });
        let mut live = LiveServer { child, port: 0, stderr };
        let line = live.await_line("live on ws://127.0.0.1:");
        let rest = line.split("live on ws://127.0.0.1:").nth(1).unwrap();
        live.port = rest.split(|c: char| !c.is_ascii_digit()).next().unwrap().parse().unwrap();
        live
    }

    fn await_line(&mut self, what: &str) -> String {
        let t0 = std::time::Instant::now();
        let mut seen = Vec::new();
        loop {
            match self.stderr.recv_timeout(LIVE_DEADLINE.saturating_sub(t0.elapsed())) {
                Ok(line) if line.contains(what) => return line,
                Ok(line) => seen.push(line),
                Err(_) => panic!("no stderr line with {what:?} within {LIVE_DEADLINE:?}: {seen:?}"),
            }
        }
    }

    fn tcp(&self) -> std::net::TcpStream {
        let s = std::net::TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        s.set_read_timeout(Some(LIVE_DEADLINE)).unwrap();
        s.set_write_timeout(Some(LIVE_DEADLINE)).unwrap();
        s
    }

    /// A WebSocket handshake offering `protocols`: the socket and the subprotocol chosen,
    /// or the HTTP status of the refusal.
    fn handshake(&self, protocols: &str) -> Result<(tungstenite::WebSocket<std::net::TcpStream>, String), u16> {
        use tungstenite::client::IntoClientRequest as _;
        let mut req = format!("ws://127.0.0.1:{}", self.port).into_client_request().unwrap();
        req.headers_mut().insert("sec-websocket-protocol", protocols.parse().unwrap());
        match tungstenite::client(req, self.tcp()) {
            Ok((ws, resp)) => {
                let chosen = resp.headers().get("sec-websocket-protocol").unwrap().to_str().unwrap().to_owned();
                Ok((ws, chosen))
            }
            Err(tungstenite::HandshakeError::Failure(tungstenite::Error::Http(r))) => Err(r.status().as_u16()),
            Err(e) => panic!("handshake: {e}"),
        }
    }

    /// Ctrl-C, awaited: exit 130.
    fn interrupt(mut self) {
        assert!(Command::new("kill").args(["-INT", &self.child.id().to_string()]).status().unwrap().success());
        let (status, _) = wait::exit_within(&mut self.child, LIVE_DEADLINE, "Ctrl-C");
        assert_eq!(status.code(), Some(130));
    }
}

/// Reads until the server closes the connection (EOF, a reset, or a WebSocket close);
/// fails past [`LIVE_DEADLINE`] (the socket's read timeout).
fn await_closed_by_server(s: &mut std::net::TcpStream, what: &str) {
    use std::io::Read as _;
    let mut buf = [0u8; 4096];
    loop {
        match s.read(&mut buf) {
            Ok(0) => return,
            // A close frame (0x88), or the reply to a request: read on to the EOF.
            Ok(_) => {}
            Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {
                panic!("{what}: the server kept the connection {LIVE_DEADLINE:?}")
            }
            Err(_) => return,
        }
    }
}

/// Issue 39 item 6: the handshake's 5 s timeout applied per read, so 16 sockets sending
/// a byte every second held every slot for as long as they liked (a viewer got HTTP 503),
/// and 16 clients that never subscribe did the same (the session never started); a client
/// offering 17 subprotocols with ours last got HTTP 400. Now the whole handshake has a
/// deadline, a client that never subscribes has an idle limit, a new connection at the
/// limit takes the slot of the oldest such client, and every offer is looked at.
#[test]
fn regression_39_6_slow_and_idle_clients_never_lock_a_viewer_out() {
    use std::io::Write as _;
    use tungstenite::Message;
    let dir = tempfile::tempdir().unwrap();
    let live = LiveServer::start(dir.path(), "[sim]\nt_end = 600.0\nlog_dt = 0.1\n[[run]]\ngoal = { x = 1.0 }\n", &[]);
    // 17 subprotocols, ours last.
    let offer: Vec<String> = (0..16).map(|i| format!("x{i}")).chain(["foxglove.sdk.v1".to_owned()]).collect();
    let (ws, chosen) = live.handshake(&offer.join(", ")).expect("17 offers, ours last: served");
    assert_eq!(chosen, "foxglove.sdk.v1");
    drop(ws);
    // 16 sockets trickling a request, a byte a second (each read well within 5 s).
    let mut slow: Vec<std::net::TcpStream> = (0..16).map(|_| live.tcp()).collect();
    for s in &mut slow {
        s.write_all(b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ").unwrap();
    }
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let trickle = {
        let (stop, socks) = (stop.clone(), slow.iter().map(|s| s.try_clone().unwrap()).collect::<Vec<_>>());
        std::thread::spawn(move || {
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                for mut s in &socks {
                    let _ = s.write_all(b"a");
                }
                std::thread::sleep(Duration::from_secs(1));
            }
        })
    };
    for (i, s) in slow.iter_mut().enumerate() {
        await_closed_by_server(s, &format!("trickling socket {i}"));
    }
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    trickle.join().unwrap();
    // 16 clients that finish the handshake and never subscribe.
    let mut idle: Vec<_> =
        (0..16).map(|i| live.handshake("foxglove.sdk.v1").unwrap_or_else(|c| panic!("idle {i}: {c}")).0).collect();
    // A viewer gets a slot (a 503 is retried: the slot frees within the idle limit), and
    // its subscription starts the session.
    let t0 = std::time::Instant::now();
    let mut viewer = loop {
        match live.handshake("foxglove.websocket.v1") {
            Ok((ws, _)) => break ws,
            // Retried at a modest pace: the event awaited is a reply that serves it.
            Err(503) if t0.elapsed() < LIVE_DEADLINE => std::thread::sleep(Duration::from_millis(50)),
            Err(code) => panic!("the viewer got HTTP {code} for {:?}", t0.elapsed()),
        }
    };
    viewer.send(Message::text(r#"{"op":"subscribe","subscriptions":[{"id":1,"channelId":0}]}"#)).unwrap();
    let mut data = 0;
    while data < 3 {
        if let Message::Binary(b) = viewer.read().expect("the stream") {
            data += usize::from(b[0] == 1);
        }
    }
    // Every idle client is sent away (a close frame, then the end of the connection).
    for (i, ws) in idle.iter_mut().enumerate() {
        await_closed_by_server(ws.get_mut(), &format!("idle client {i}"));
    }
    live.interrupt();
}

/// A tmpfs of `size` mounted on a fresh folder (tests/disk_full.rs), unmounted when
/// dropped; `None` after recording a skip where mounting is not allowed.
struct Tmpfs {
    dir: tempfile::TempDir,
}

impl Tmpfs {
    fn mount(size: &str) -> Option<Self> {
        let dir = tempfile::tempdir().unwrap();
        let o = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
            .arg(dir.path())
            .output();
        match o {
            Ok(o) if o.status.success() => Some(Self { dir }),
            Ok(o) => {
                skip::missing("tmpfs", &format!("cannot mount a tmpfs (needs root): {}", text(&o.stderr).trim()));
                None
            }
            Err(e) => {
                skip::missing("tmpfs", &format!("cannot run mount: {e}"));
                None
            }
        }
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }
}

impl Drop for Tmpfs {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.dir.path()).status();
    }
}

/// Issue 39 item 13 (live): `run --live --layout lay.json` stopped by Ctrl-C before any
/// client left lay.json behind, and had replaced an existing one. The layout is still
/// written before the server waits (to be imported meanwhile), and undone on Ctrl-C: the
/// new file removed, or the old one put back.
#[test]
fn regression_39_13_live_layout_is_undone_by_ctrl_c() {
    let scenario = "[sim]\nt_end = 60.0\n[[run]]\ngoal = { x = 1.0 }\n";
    for old in [None, Some("my own layout\n")] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        if let Some(old) = old {
            write(d, "lay.json", old);
        }
        let live = LiveServer::start(d, scenario, &["--layout", "lay.json"]);
        let written = fs::read_to_string(d.join("lay.json")).unwrap();
        assert!(written.contains("wmr-plane"), "the layout is there to import while the server waits: {written}");
        live.interrupt();
        match old {
            None => assert_eq!(entries(d), ["s.toml"], "no layout left"),
            Some(old) => {
                assert_eq!(entries(d), ["lay.json", "s.toml"]);
                assert_eq!(fs::read_to_string(d.join("lay.json")).unwrap(), old, "the old layout put back");
            }
        }
    }
}

/// Issue 39 item 13 (plot): `plot -o DIR` left an empty DIR after a signal (the folder
/// is made before the runs) and after a full disk. A folder plot made is removed again;
/// one that existed stays.
#[test]
fn regression_39_13_plot_leaves_no_new_folder_after_a_signal_or_a_full_disk() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Long enough to be caught simulating: four runs of 2,000 s.
    let long = "[sim]\nt_end = 2000.0\n[[run]]\ngoal = { x = 1.0 }\n[[run]]\ngoal = { x = -1.0 }\n\
                [[run]]\ngoal = { y = 1.0 }\n[[run]]\ngoal = { y = -1.0 }\n";
    write(d, "long.toml", long);
    let mut child = bin()
        .current_dir(d)
        .args(["plot", "long.toml", "-o", "figs"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The event: the folder exists (made before the runs).
    let t0 = std::time::Instant::now();
    while !d.join("figs").exists() {
        assert!(child.try_wait().unwrap().is_none(), "plot ended before it could be interrupted");
        assert!(t0.elapsed() < LIVE_DEADLINE, "no folder figs after {LIVE_DEADLINE:?}");
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap().success());
    let (status, err) = wait::exit_within(&mut child, LIVE_DEADLINE, "plot after SIGINT");
    assert!(!status.success(), "{err}");
    assert_eq!(entries(d), ["long.toml"], "no folder left: {err}");
    // A full disk: the SVGs do not fit in 8 kB.
    let Some(full) = Tmpfs::mount("8k") else { return };
    write(d, "short.toml", "[sim]\nt_end = 5.0\n[[run]]\ngoal = { x = 1.0 }\n");
    let figs = full.path().join("figs");
    let o = run_in(d, &["plot", "short.toml", "-o", figs.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("No space left on device"), "{}", text(&o.stderr));
    assert!(entries(full.path()).is_empty(), "{:?}", entries(full.path()));
    // An existing folder stays, with what it held.
    fs::create_dir(&figs).unwrap();
    write(&figs, "mine.txt", "x");
    let o = run_in(d, &["plot", "short.toml", "-o", figs.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    assert_eq!(entries(&figs), ["mine.txt"]);
}

/// Issue 39 item 13 (sweep): `sweep -o s.csv --plots DIR` whose figures failed on a full
/// disk exited 1 after s.csv had been renamed into place. Now the CSV is renamed last:
/// s.csv keeps its old contents, and the new DIR is gone.
#[test]
fn regression_39_13_a_failed_sweep_leaves_its_csv_as_it_was() {
    let Some(full) = Tmpfs::mount("8k") else { return };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "s.toml", "[sim]\nt_end = 1.0\n[sweep]\nrandom = { n = 20, radius = 1.0 }\n");
    write(d, "s.csv", "old\n");
    let plots = full.path().join("plots");
    let o = run_in(d, &["sweep", "s.toml", "-o", "s.csv", "--plots", plots.to_str().unwrap()]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("No space left on device"), "{err}");
    let csv = fs::read_to_string(d.join("s.csv")).unwrap();
    assert!(csv == "old\n", "s.csv replaced by a failed sweep ({} bytes)", csv.len());
    assert_eq!(entries(d), ["s.csv", "s.toml"], "no temporary file left");
    assert!(entries(full.path()).is_empty(), "{:?}", entries(full.path()));
}
