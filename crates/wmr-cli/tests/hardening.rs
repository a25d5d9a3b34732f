//! Issue 12: what an attack on the CLI broke, one test per defect (`regression_12_N_...`),
//! plus the siblings found while fixing them. Signals and a full disk are in
//! `signals.rs` and `disk_full.rs`, the fuzz test in `fuzz.rs`.

use std::fs;
use std::io::Read as _;
use std::os::unix::fs::FileTypeExt as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::skip;
use crate::wait;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
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

fn repo(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(p).display().to_string()
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<_> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

/// Exit 2, one line on stderr naming `key`, nothing on stdout, no panic.
fn assert_bad_input(o: &Output, key: &str) {
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(key), "stderr lacks {key:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// 2 s runs, logged every 10 ms: short enough for a debug build.
const SHORT: &str = "[sim]\nt_end = 2.0\n[[run]]\ngoal = { x = 1.0, y = 1.0, theta_deg = 120.0 }\n";

const SWEEP: &str =
    "[sim]\nt_end = 0.5\n[sweep]\ncontrollers = [{ kind = \"paper\" }]\nrandom = { n = 3, radius = 1.0 }\n";

fn is_root() -> bool {
    Command::new("id").arg("-u").output().map(|o| text(&o.stdout).trim() == "0").unwrap_or(false)
}

#[test]
fn regression_12_1_output_is_a_device_node() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "s.toml", SHORT);
    let null = dir.path().join("mynull");
    if is_root() {
        // A character device (major 1, minor 3: the null device) made here.
        assert!(
            Command::new("mknod")
                .args(["-m", "666", null.to_str().unwrap(), "c", "1", "3"])
                .status()
                .unwrap()
                .success()
        );
    } else {
        std::os::unix::fs::symlink("/dev/null", &null).unwrap();
        skip::missing("root", "not root: no device node made, a link to /dev/null tested instead");
    }
    let o = run_in(dir.path(), &["run", scen.to_str().unwrap(), "-o", null.to_str().unwrap(), "--format", "csv"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(fs::metadata(&null).unwrap().file_type().is_char_device(), "the device was replaced by a file");
    assert!(entries(dir.path()).iter().all(|n| !n.ends_with(".tmp")), "{:?}", entries(dir.path()));

    // The MCAP writer streams to a device too (not the system's /dev/null: a regressed
    // binary run by these tests as root would replace it, as the attack's did).
    let o = run_in(dir.path(), &["run", scen.to_str().unwrap(), "-o", null.to_str().unwrap(), "--format", "mcap"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(fs::metadata(&null).unwrap().file_type().is_char_device());
}

#[test]
fn regression_12_1_output_streams_to_a_fifo_and_to_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "s.toml", SHORT);
    let reference = dir.path().join("ref.csv");
    let o = run_in(dir.path(), &["run", scen.to_str().unwrap(), "-o", reference.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let want = fs::read(&reference).unwrap();

    // `-o -`: the CSV on stdout, the summary on stderr.
    let o = run_in(dir.path(), &["run", scen.to_str().unwrap(), "-o", "-", "--format", "csv"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(o.stdout == want, "stdout differs from the file");
    assert!(text(&o.stderr).contains("run 0 ["), "summary on stderr: {}", text(&o.stderr));

    // MCAP to stdout: written front to back without seeking, the same bytes as the file.
    let mcap = dir.path().join("ref.mcap");
    let o = run_in(dir.path(), &["run", scen.to_str().unwrap(), "-o", mcap.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = run_in(dir.path(), &["run", scen.to_str().unwrap(), "-o", "-", "--format", "mcap"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(o.stdout == fs::read(&mcap).unwrap(), "streamed MCAP differs from the file");

    // A FIFO: streamed to a reader, never replaced.
    let fifo = dir.path().join("pipe");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            let mut got = Vec::new();
            fs::File::open(&fifo).unwrap().read_to_end(&mut got).unwrap();
            got
        })
    };
    let o = run_in(dir.path(), &["run", scen.to_str().unwrap(), "-o", fifo.to_str().unwrap(), "--format", "csv"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(reader.join().unwrap() == want, "the FIFO's reader got other bytes");
    assert!(fs::metadata(&fifo).unwrap().file_type().is_fifo());
}

#[test]
fn regression_12_1_output_equal_to_an_input_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let same = write(dir.path(), "same.toml", SHORT);
    let cmp = write(dir.path(), "cmp.toml", SWEEP);
    std::os::unix::fs::symlink(&same, dir.path().join("link.toml")).unwrap();
    fs::hard_link(&cmp, dir.path().join("hard.csv")).unwrap();
    for args in [
        vec!["run", "same.toml", "-o", "same.toml", "--format", "csv"],
        vec!["run", "same.toml", "-o", "link.toml", "--format", "csv"],
        vec!["run", "same.toml", "-o", "./same.toml", "--format", "mcap"],
        vec!["sweep", "cmp.toml", "-o", "cmp.toml"],
        vec!["sweep", "cmp.toml", "-o", "hard.csv"],
    ] {
        let o = run_in(dir.path(), &args);
        assert_bad_input(&o, "is the input file");
    }
    assert_eq!(fs::read_to_string(&same).unwrap(), SHORT);
    assert_eq!(fs::read_to_string(&cmp).unwrap(), SWEEP);
    assert!(fs::symlink_metadata(dir.path().join("link.toml")).unwrap().file_type().is_symlink());
    assert_eq!(entries(dir.path()), ["cmp.toml", "hard.csv", "link.toml", "same.toml"]);
}

#[test]
fn regression_12_1_a_link_to_a_file_is_followed_not_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "s.toml", SHORT);
    let real = write(dir.path(), "real.csv", "old\n");
    std::os::unix::fs::symlink(&real, dir.path().join("link.csv")).unwrap();
    let o = run_in(dir.path(), &["run", scen.to_str().unwrap(), "-o", "link.csv"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(fs::symlink_metadata(dir.path().join("link.csv")).unwrap().file_type().is_symlink());
    assert!(fs::read_to_string(&real).unwrap().starts_with("run,t,"));
}

#[test]
fn regression_12_2_grid_count_does_not_wrap() {
    let dir = tempfile::tempdir().unwrap();
    let grid = "[sim]\nt_end = 1.0\n[sweep]\ngrid = { x_min = 0, x_max = 1, nx = 2147483648, y_min = 0, y_max = 1, \
                ny = 2147483648, theta_deg = [0, 1, 2, 3] }\n";
    let f = write(dir.path(), "g.toml", grid);
    for cmd in ["check", "sweep"] {
        let o = run_in(dir.path(), &[cmd, f.to_str().unwrap()]);
        assert_bad_input(&o, "sweep.grid: nx x ny x headings = 2147483648 x 2147483648 x 4 = 18446744073709551616");
    }
    let f = write(dir.path(), "g2.toml", &grid.replace("2147483648", "4294967295"));
    let o = run_in(dir.path(), &["check", f.to_str().unwrap()]);
    assert_bad_input(&o, "= 73786976260478468100 starts");
    assert!(!text(&o.stderr).contains("18446744056529682434"));
    assert_eq!(entries(dir.path()), ["g.toml", "g2.toml"]);
}

/// Peak resident memory of a process, kB (Linux).
fn vm_hwm_kb(pid: u32) -> Option<u64> {
    let status = fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    status.lines().find(|l| l.starts_with("VmHWM:"))?.split_whitespace().nth(1)?.parse().ok()
}

/// CPU time a process has used, in all its threads, s (Linux: utime + stime of
/// `/proc/PID/stat`, in clock ticks of 1/100 s, the `USER_HZ` of every Linux ABI).
fn cpu_seconds(pid: u32) -> Option<f64> {
    let stat = fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // After the command name in parentheses: field 3 (state) onwards; utime and stime are
    // fields 14 and 15.
    let mut rest = stat.rsplit_once(')')?.1.split_whitespace().skip(11);
    let (utime, stime): (u64, u64) = (rest.next()?.parse().ok()?, rest.next()?.parse().ok()?);
    Some((utime + stime) as f64 / 100.0)
}

#[test]
fn regression_12_3_plot_of_a_long_run_neither_aborts_nor_holds_every_sample() {
    let dir = tempfile::tempdir().unwrap();
    // 1e9 samples of 1e9 steps: the attack's `memory allocation of 120000000120 bytes
    // failed` came at once. Now the plot runs in bounded memory: stopped after 3 s of its
    // own CPU time (whatever the load: wall time on a busy machine may be no work at all).
    let f = write(dir.path(), "long.toml", "[sim]\nt_end = 1e6\nlog_dt = 1e-3\n[[run]]\ngoal = { x = 1.0 }\n");
    let mut child = bin()
        .current_dir(dir.path())
        .args(["plot", f.to_str().unwrap(), "-o", "figs"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    let peak = loop {
        let worked = cpu_seconds(child.id());
        assert!(child.try_wait().unwrap().is_none(), "plot ended early: {:?}", child.wait_with_output());
        let worked = worked.expect("utime and stime in /proc/PID/stat");
        if worked >= 3.0 {
            // Read after the 3 s: the peak of at least that much work.
            break vm_hwm_kb(child.id()).expect("VmHWM in /proc/PID/status");
        }
        assert!(started.elapsed() < Duration::from_secs(120), "only {worked} s of CPU time in 120 s");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap().success());
    let o = child.wait_with_output().unwrap();
    assert!(peak < 200_000, "peak memory {peak} kB");
    assert!(!text(&o.stderr).contains("memory allocation"), "{}", text(&o.stderr));

    // A finished plot of 200,001 samples draws at most 4,001 points per curve (and a real
    // curve: the figures simplify smooth stretches further, so the count varies).
    let f = write(dir.path(), "mid.toml", "[sim]\nt_end = 200.0\nlog_dt = 1e-3\n[[run]]\ngoal = { x = 1.0 }\n");
    let o = run_in(dir.path(), &["plot", f.to_str().unwrap(), "-o", "mid"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for svg in ["paths.svg", "run0-wheel-speeds.svg", "run0-errors.svg"] {
        let body = fs::read_to_string(dir.path().join("mid").join(svg)).unwrap();
        let doc = roxmltree::Document::parse(&body).unwrap();
        let longest = doc
            .descendants()
            .filter(|n| n.has_tag_name("polyline"))
            .map(|n| n.attribute("points").unwrap_or("").split_whitespace().count())
            .max()
            .unwrap();
        assert!((100..=4001).contains(&longest), "{svg}: {longest} points");
    }
}

/// A sibling of defect 3 in `trace`, which kept every control tick: 1e9 ticks aborted
/// with `memory allocation of ... failed`. `trace` now streams its records (issue 25,
/// item 9: tests/trace.rs); what is refused before the run is a trace larger than the
/// free space where it goes: 1e9 ticks of 112 bytes in the binary form.
#[test]
fn regression_12_3_trace_of_a_long_run_is_refused_not_aborted() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(dir.path(), "long.toml", "[sim]\nt_end = 1e6\n[[run]]\ngoal = { x = 1.0 }\n");
    let df = Command::new("df").args(["--output=avail", "-B1"]).arg(dir.path()).output().expect("df runs");
    let free: u64 = text(&df.stdout).lines().nth(1).and_then(|l| l.trim().parse().ok()).expect("df's free bytes");
    // The binary form's size, from the format's own constants (version 3: 112 bytes a tick).
    use wmr_core::trace::{CONFIG_WORDS, HEADER_WORDS, RECORD_WORDS};
    let bytes = 4 * ((HEADER_WORDS + CONFIG_WORDS) as u64 + 1_000_000_001u64 * RECORD_WORDS as u64);
    if free >= bytes {
        skip::missing("small-disk", &format!("{free} bytes free hold the 1e6 s trace ({bytes} bytes): it would run"));
        return;
    }
    let o = run_in(dir.path(), &["trace", f.to_str().unwrap(), "-o", "t.bin"]);
    assert_bad_input(&o, &format!("sim.t_end: a trace of 1000000001 ticks to t.bin takes at least {bytes} bytes"));
    assert_eq!(entries(dir.path()), ["long.toml"]);
}

#[test]
fn regression_12_7_huge_jobs_are_refused_before_they_start() {
    let dir = tempfile::tempdir().unwrap();
    // 1,000 runs of 1e9 steps, and a sweep of 1e6 runs of 1e9 steps: more than 1e11 steps.
    let mut many = String::from("[sim]\nt_end = 1e6\n");
    for _ in 0..1000 {
        many.push_str("[[run]]\ngoal = { x = 1.0 }\n");
    }
    let f = write(dir.path(), "many.toml", &many);
    for args in
        [vec!["check", "many.toml"], vec!["run", "many.toml", "-o", "x.csv"], vec!["plot", "many.toml", "-o", "d"]]
    {
        let started = Instant::now();
        let o = run_in(dir.path(), &args);
        assert_bad_input(&o, "sim.t_end: 1000 runs x 1000000000 steps");
        assert!(started.elapsed() < Duration::from_secs(20));
    }
    let _ = f;
    write(
        dir.path(),
        "sw.toml",
        "[sim]\nt_end = 1e6\n[sweep]\ncontrollers = [{ kind = \"paper\" }]\nrandom = { n = 1000000, radius = 1 }\n",
    );
    let o = run_in(dir.path(), &["sweep", "sw.toml", "-o", "x.csv"]);
    assert_bad_input(&o, "sim.t_end: 1000000 runs x 1000000000 steps");
    assert_eq!(entries(dir.path()), ["many.toml", "sw.toml"]);
}

#[test]
fn regression_12_8_a_closed_stdout_ends_the_command_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let mut many = String::from("[sim]\nt_end = 0.01\n");
    for _ in 0..3000 {
        many.push_str("[[run]]\ngoal = { x = 1.0 }\n");
    }
    let f = write(dir.path(), "many.toml", &many);
    // `| head -c 10`: the reader takes 10 bytes and goes away.
    for args in [
        vec!["run", f.to_str().unwrap(), "-o", "x.csv"],
        vec!["check", f.to_str().unwrap()],
        vec!["run", f.to_str().unwrap(), "-o", "-", "--format", "csv"],
    ] {
        let mut child =
            bin().current_dir(dir.path()).args(&args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
        let mut head = [0u8; 10];
        child.stdout.take().unwrap().read_exact(&mut head).unwrap();
        // The pipe's read end is dropped here.
        let o = child.wait_with_output().unwrap();
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
        assert!(!err.contains("panicked") && !err.contains("Broken pipe"), "{args:?}: {err}");
    }
    // OUT of the first command is complete.
    assert_eq!(fs::read_to_string(dir.path().join("x.csv")).unwrap().lines().count(), 1 + 3000 * 2);
    // stdout = /dev/full: one error line, exit 1, no panic.
    let full = fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
    let o = bin().current_dir(dir.path()).args(["check", f.to_str().unwrap()]).stdout(full).output().unwrap();
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("No space left on device") && !err.contains("panicked"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    // stderr = /dev/full: no panic either (the message is lost, the code stays).
    let full = fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
    let o = bin().current_dir(dir.path()).args(["check", "missing.toml"]).stderr(full).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn regression_12_9_sweep_writes_its_default_output_in_the_working_directory() {
    let dir = tempfile::tempdir().unwrap();
    let evil = dir.path().join("elsewhere").join("wmr-evil");
    fs::create_dir(dir.path().join("elsewhere")).unwrap();
    let work = dir.path().join("work");
    fs::create_dir(&work).unwrap();
    let body = format!("name = {:?}\n{SWEEP}", evil.to_str().unwrap());
    let f = write(dir.path(), "down loaded.toml", &body);
    let o = run_in(&work, &["sweep", f.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(entries(&work), ["down_loaded-sweep.csv"]);
    assert!(entries(&dir.path().join("elsewhere")).is_empty(), "the file's name chose a path");
}

#[test]
fn regression_12_10_check_runs_every_validation_sweep_runs() {
    let dir = tempfile::tempdir().unwrap();
    for (body, key) in [
        ("[sweep]\nrandom = { n = 10, radius = 1e308 }\n", "line 2: sweep.random.radius"),
        (
            "[sweep]\ngrid = { x_min = -1.7e308, x_max = 1.7e308, nx = 3, y_min = 0, y_max = 1, ny = 1 }\n",
            "line 2: sweep.grid.x_min",
        ),
        ("[sweep]\ngoal = { x = 5000.0 }\nrandom = { n = 10, radius = 1 }\n", "line 2: sweep.goal.x"),
        ("[sweep]\ngoal = { x = 999.5 }\nrandom = { n = 10, radius = 1 }\n", "line 3: sweep.random.radius"),
    ] {
        let f = write(dir.path(), "s.toml", body);
        for args in [vec!["check", "s.toml"], vec!["sweep", "s.toml", "-o", "o.csv"]] {
            let o = run_in(dir.path(), &args);
            assert_bad_input(&o, key);
            assert!(!text(&o.stderr).contains("inf") && !text(&o.stderr).contains("NaN"), "{}", text(&o.stderr));
        }
        let _ = f;
    }
    assert_eq!(entries(dir.path()), ["s.toml"]);
}

#[test]
fn regression_12_11_bad_input_exits_2_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sweep = repo("examples/compare.toml");
    let fig7 = repo("examples/paper/fig7.toml");
    for (args, says) in [
        (vec!["run", sweep.as_str(), "-o", "x.csv"], "compare.toml: run: the file has no [[run]]"),
        (vec!["sweep", fig7.as_str(), "-o", "x.csv"], "fig7.toml: sweep: the file has no [sweep]"),
        (vec!["plot", sweep.as_str(), "-o", "figs"], "compare.toml: run: the file has no [[run]]"),
        (vec!["run", fig7.as_str(), "-o", "noext"], "--format"),
        (vec!["run", fig7.as_str(), "-o", "a/b/x.csv"], "the directory a/b does not exist"),
        (vec!["sweep", sweep.as_str(), "-o", "a/b/x.csv"], "the directory a/b does not exist"),
        (vec!["sweep", sweep.as_str(), "-o", "x.csv", "--plots", "a/b"], "the directory a does not exist"),
        (vec!["plot", fig7.as_str(), "-o", "a/b"], "the directory a does not exist"),
        (vec!["plot", fig7.as_str(), "-o", "x.svg"], "looks like a file"),
        (vec!["run", fig7.as_str(), "-o", ".", "--format", "csv"], "is a directory"),
        (vec!["check", "missing.toml"], "cannot read missing.toml"),
    ] {
        let o = run_in(d, &args);
        assert_bad_input(&o, says);
        assert!(!text(&o.stderr).contains(".tmp"), "{}", text(&o.stderr));
    }
    assert!(entries(d).is_empty(), "{:?}", entries(d));
    // An existing file where plot wants a folder.
    write(d, "taken", "x");
    assert_bad_input(&run_in(d, &["plot", fig7.as_str(), "-o", "taken"]), "is not a directory");
    assert_eq!(entries(d), ["taken"]);
}

#[test]
fn regression_12_12_control_characters_are_escaped() {
    let dir = tempfile::tempdir().unwrap();
    for (body, shown) in [
        ("[[ru\u{1b}[31mn]]\ngoal = {}\n", "\\x1b[31m"),
        ("[robot]\nma\u{202e}ss = 1.0\n[[run]]\ngoal = {}\n", "\\u{202e}"),
        ("[robot]\nmass = \"a\u{0}b\"\n[[run]]\ngoal = {}\n", "\\0"),
        ("[robot]\nmass = -1.0\r\n[[run]]\ngoal = {}\n", "robot.mass"),
        ("[robot]\r\nm\rass = 1\n", "\\r"),
    ] {
        let f = write(dir.path(), "c.toml", body);
        let o = run_in(dir.path(), &["check", f.to_str().unwrap()]);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(shown), "{shown:?} in {err:?}");
        let line = err.strip_suffix('\n').unwrap_or(&err);
        assert!(!line.chars().any(|c| c.is_control() || ('\u{202a}'..='\u{202e}').contains(&c)), "raw: {err:?}");
    }
    // A label from the file reaches stdout (the summary) escaped too.
    let f = write(dir.path(), "l.toml", "[sim]\nt_end = 0.01\n[[run]]\nlabel = \"\\u001b[2Jred\\u202e\"\ngoal = {}\n");
    let o = run_in(dir.path(), &["run", f.to_str().unwrap(), "-o", "x.csv"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert!(out.contains("[\\x1b[2Jred\\u{202e}]"), "{out:?}");
    assert!(!out.contains('\u{1b}') && !out.contains('\u{202e}'));
    // And `check` prints it as a TOML escape.
    let o = run_in(dir.path(), &["check", f.to_str().unwrap()]);
    let out = text(&o.stdout);
    assert!(out.contains("\\u001B[2Jred\\u202E"), "{out}");
}

#[test]
fn regression_12_13_input_size_is_capped_and_special_files_refused() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo.toml");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let big = dir.path().join("big.toml");
    fs::write(&big, format!("# {}\n", "x".repeat(17 << 20))).unwrap();
    for (file, says) in [
        ("/dev/zero", "not a regular file"),
        (fifo.to_str().unwrap(), "not a regular file"),
        (big.to_str().unwrap(), "a scenario file may be at most 16 MiB"),
        (dir.path().to_str().unwrap(), "is a directory"),
    ] {
        let started = Instant::now();
        let o = run_in(dir.path(), &["check", file]);
        assert_bad_input(&o, says);
        assert!(started.elapsed() < Duration::from_secs(10), "{file}");
    }
    // Not UTF-8: one line with the line number.
    let f = dir.path().join("latin1.toml");
    fs::write(&f, b"[[run]]\ngoal = {}\nlabel = \"caf\xe9\"\n").unwrap();
    assert_bad_input(&run_in(dir.path(), &["check", f.to_str().unwrap()]), "line 3: ");
}

#[test]
fn regression_12_15_small_defects() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (body, says) in [
        ("[[run]]\nstart = { x = 5000.0 }\ngoal = {}\n", "line 2: run[0].start.x: must be within 1000 m"),
        ("[[run]]\ngoal = { x = 1e300 }\n", "run[0].goal.x: must be within 1000 m of the origin (got 1e300)"),
        ("[[run]]\ngoal = [1, 1, 0]\n", "run[0].goal: invalid type: an array of 3 values, expected a pose table"),
        ("[run]\ngoal = { x = 1.0 }\n", "run: must be an array of tables: write [[run]]"),
        ("[sim]\ndt = 0.003\n[[run]]\ngoal = {}\n", "line 2: sim.dt: 0.003 s does not divide the default sim.log_dt"),
        ("[controller]\ncontrol_dt = 0.003\n[[run]]\ngoal = {}\n", "controller.control_dt: 0.003 s does not divide"),
        ("[sweep]\ngrid = 3\n", "sweep.grid: invalid type: integer `3`, expected a grid table"),
    ] {
        let f = write(d, "s.toml", body);
        let o = run_in(d, &["check", f.to_str().unwrap()]);
        assert_bad_input(&o, says);
        for internal in ["PoseFile", "GridFile", "struct", "sequence", "u32"] {
            assert!(!text(&o.stderr).contains(internal), "{internal}: {}", text(&o.stderr));
        }
    }
    // theta = 90 (radians) is valid but warned about.
    let f = write(d, "w.toml", "[sim]\nt_end = 0.01\n[[run]]\ngoal = { x = 1.0, theta = 90 }\n");
    let o = run_in(d, &["check", f.to_str().unwrap()]);
    assert!(o.status.success());
    assert!(
        text(&o.stderr).contains("warning: ") && text(&o.stderr).contains("run[0].goal.theta: 90 rad is 14.3 turns")
    );
    assert!(text(&o.stderr).contains("theta_deg = 90"));
    // A diverged run has fewer samples: the summary does not claim t_end / log_dt + 1 for all.
    let f = write(
        d,
        "div.toml",
        "[sim]\nt_end = 20.0\nlog_dt = 0.1\n[[run]]\nstart = { x = 1.0 }\ngoal = {}\n[[run]]\ngoal = { x = 0.5 }\n",
    );
    let o = run_in(d, &["run", f.to_str().unwrap(), "-o", "div.csv"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let rows = fs::read_to_string(d.join("div.csv")).unwrap().lines().count() - 1;
    let err = text(&o.stderr);
    assert!(err.contains(&format!("{rows} samples in all")) && !err.contains("201 samples each"), "{rows}: {err}");
}

/// A sweep of 500 random starts whose `vary` entry draws `spread` for `key`.
fn drawn_sweep(key: &str, spread: &str) -> String {
    format!(
        "[sim]\nt_end = 0.5\n[sweep]\nrandom = {{ n = 500, radius = 1.0 }}\nvary = [{{ key = \"{key}\", {spread} }}]\n"
    )
}

/// Issue 25 item 6: `check` validated only run 0's draws, so `sweep` refused a draw after
/// all the work, naming a key the file lacks and no line. Now both refuse every bad draw
/// before running, naming the `vary` entry (file, line), the run and the drawn value.
#[test]
fn regression_25_6_check_and_sweep_refuse_every_bad_draw_before_running() {
    let dir = tempfile::tempdir().unwrap();
    for (key, spread) in [
        ("robot.mass", "normal = [5, 1.5]"),
        ("controller.model.wheel_radius", "normal = [0.1, 0.05]"),
        ("sensor.position_noise", "uniform = [-0.01, 0.01]"),
        ("drive.motor_torque_max", "normal = [1.0, 1.5]"),
    ] {
        write(dir.path(), "v.toml", &drawn_sweep(key, spread));
        let check = run_in(dir.path(), &["check", "v.toml"]);
        let err = text(&check.stderr);
        assert_eq!(check.status.code(), Some(2), "{key}: check must refuse: {err}");
        // The entry on line 5, the run, the drawn value, the key and the reason.
        assert!(err.contains("v.toml: line 5: sweep.vary[0]: run "), "{key}: {err}");
        assert!(err.contains(&format!("draws {key} = ")) && err.contains("must be"), "{key}: {err}");
        let sweep = run_in(dir.path(), &["sweep", "v.toml", "-o", "v.csv"]);
        assert_eq!(sweep.status.code(), Some(2), "{key}");
        assert_eq!(text(&sweep.stderr), err, "{key}: sweep says what check says");
        assert_eq!(entries(dir.path()), ["v.toml"], "{key}: nothing written");
    }
    // Draws that are all good pass, and the sweep runs.
    write(dir.path(), "ok.toml", &drawn_sweep("robot.mass", "normal = [5, 0.1]"));
    assert!(run_in(dir.path(), &["check", "ok.toml"]).status.success());
}

/// Issue 25 item 12: `normal` and `uniform` dropped elements past the second silently.
#[test]
fn regression_25_12_uniform_and_normal_take_exactly_two_numbers() {
    let dir = tempfile::tempdir().unwrap();
    for (spread, field) in [
        ("normal = [5, 0.1, 99]", "normal"),
        ("normal = [5]", "normal"),
        ("uniform = [4, 6, 8]", "uniform"),
        ("uniform = []", "uniform"),
    ] {
        write(dir.path(), "v.toml", &drawn_sweep("robot.mass", spread));
        let o = run_in(dir.path(), &["check", "v.toml"]);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{spread}: {err}");
        assert!(err.contains(&format!("sweep.vary[0].{field}: give exactly two numbers")), "{spread}: {err}");
    }
}

/// Issue 25 item 7: a `vary` list of a million values (10 MB, under the size cap) was
/// checked value by value before the run count: 47.5 s and 3.9 GB, an abort under a 3 GB
/// cap. Now the count comes first: refused (exit 2) within 1.5 GB of address space.
#[test]
fn regression_25_7_a_huge_values_list_is_counted_before_it_is_checked() {
    let dir = tempfile::tempdir().unwrap();
    let values: Vec<String> = (0..1_000_000).map(|i| format!("{}", 5.0 + f64::from(i) * 1e-6)).collect();
    write(
        dir.path(),
        "big.toml",
        &format!(
            "[sim]\nt_end = 1.0\n[sweep]\nrandom = {{ n = 10, radius = 1.0 }}\n\
             vary = [{{ key = \"robot.mass\", values = [{}] }}]\n",
            values.join(", ")
        ),
    );
    if Command::new("prlimit").arg("--version").output().is_err() {
        skip::missing("prlimit", "prlimit (util-linux) is missing: the memory cap cannot be set");
        return;
    }
    let mut child = Command::new("prlimit")
        .arg("--as=1500000000")
        .arg(env!("CARGO_BIN_EXE_wmr-cli"))
        .args(["check", "big.toml"])
        .current_dir(dir.path())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (status, err) = wait::exit_within(&mut child, Duration::from_secs(120), "check of a million values");
    assert_eq!(status.code(), Some(2), "{status:?}: {err}");
    assert!(err.contains("1000000 variants") && err.contains("more than 1000000 runs"), "{err}");
}

/// Issue 25 item 11: `position_noise = 1e308` was accepted and wrote `inf` into the CSV;
/// item 13: latency x rate of 250 to 254 was accepted though documented as below 250.
#[test]
fn regression_25_11_absurd_noise_and_latency_at_the_bound_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let bad = [
        ("position_noise = 1e308", "sensor.position_noise: must be at most 1000 m"),
        ("position_noise = 1000.5", "sensor.position_noise: must be at most 1000 m"),
        ("heading_noise_deg = 1e300", "sensor.heading_noise_deg: must be at most 3600 deg"),
        ("rate_hz = 1000.0\nlatency = 0.25", "sensor.latency: "),
        ("rate_hz = 1000.0\nlatency = 0.254", "sensor.latency: "),
    ];
    for (sensor, want) in bad {
        write(
            dir.path(),
            "n.toml",
            &format!("[sim]\nt_end = 0.5\n[sensor]\n{sensor}\n[[run]]\ngoal = {{ x = 1.0 }}\n"),
        );
        let o = run_in(dir.path(), &["run", "n.toml", "-o", "n.csv"]);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{sensor}: {err}");
        assert!(err.contains(want), "{sensor}: {err}");
        assert_eq!(entries(dir.path()), ["n.toml"], "{sensor}");
    }
    // At the bounds: accepted, and every value written is finite.
    for sensor in ["position_noise = 1000.0\nseed = 3", "rate_hz = 1000.0\nlatency = 0.249"] {
        write(
            dir.path(),
            "n.toml",
            &format!("[sim]\nt_end = 0.5\n[sensor]\n{sensor}\n[[run]]\ngoal = {{ x = 1.0 }}\n"),
        );
        let o = run_in(dir.path(), &["run", "n.toml", "-o", "n.csv"]);
        assert!(o.status.success(), "{sensor}: {}", text(&o.stderr));
        let csv = fs::read_to_string(dir.path().join("n.csv")).unwrap();
        assert!(!csv.contains("inf") && !csv.contains("NaN"), "{sensor}: a non-finite value was written");
        fs::remove_file(dir.path().join("n.csv")).unwrap();
    }
}

/// Issue 25 item 13: paths the system refuses for what they are (a part that is a file, a
/// loop of links, a name over 255 bytes, a link to a missing folder for `plot`) exited 1,
/// as for a failed write; they are bad input, exit 2, and nothing is written.
#[test]
fn regression_25_13_unusable_output_paths_are_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let scen = write(dir.path(), "s.toml", "[sim]\nt_end = 0.2\n[[run]]\ngoal = { x = 1.0 }\n");
    write(dir.path(), "afile", "x");
    std::os::unix::fs::symlink("loop2.csv", dir.path().join("loop1.csv")).unwrap();
    std::os::unix::fs::symlink("loop1.csv", dir.path().join("loop2.csv")).unwrap();
    std::os::unix::fs::symlink("dloop2", dir.path().join("dloop1")).unwrap();
    std::os::unix::fs::symlink("dloop1", dir.path().join("dloop2")).unwrap();
    std::os::unix::fs::symlink("missing-folder", dir.path().join("dangling")).unwrap();
    let long = format!("{}.csv", "n".repeat(300));
    let s = scen.display().to_string();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["run", &s, "-o", "afile/out.csv"], "is a file, not a directory"),
        (vec!["run", &s, "-o", "loop1.csv"], "loop of symbolic links"),
        (vec!["run", &s, "-o", "dloop1/out.csv"], "loop of symbolic links"),
        (vec!["run", &s, "-o", &long], "longer than the file system allows"),
        (vec!["plot", &s, "-o", "dangling"], "symbolic link to a missing folder"),
        (vec!["plot", &s, "-o", "afile/plots"], "is a file, not a directory"),
        (vec!["plot", &s, "-o", "dloop1"], "loop of symbolic links"),
    ];
    for (args, want) in cases {
        let o = run_in(dir.path(), &args);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
    assert_eq!(entries(dir.path()), ["afile", "dangling", "dloop1", "dloop2", "loop1.csv", "loop2.csv", "s.toml"]);
}

/// Issue 25 item 13: the summary said "fewer for runs that diverged early" when runs had
/// stopped once settled.
#[test]
fn regression_25_13_the_summary_says_why_runs_wrote_fewer_samples() {
    let dir = tempfile::tempdir().unwrap();
    // Run 0 starts at its goal and settles at once; run 1 travels the whole t_end.
    write(
        dir.path(),
        "s.toml",
        "[sim]\nt_end = 2.0\nstop_when_settled = true\n[[run]]\ngoal = { x = 0.0 }\n[[run]]\ngoal = { x = 1.0 }\n",
    );
    let o = run_in(dir.path(), &["run", "s.toml", "-o", "s.csv"]);
    let err = text(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("fewer for the 1 run(s) that stopped once settled"), "{err}");
    assert!(!err.contains("diverged"), "{err}");
}

/// Issue 25 item 13: the sweep CSV wrote extreme values as 300-digit decimals; now the
/// shortest round-trip text, in exponent form past 32 characters (the example sweeps'
/// bytes are unchanged: /work/bits.sh).
#[test]
fn regression_25_13_sweep_csv_writes_extreme_values_short_and_exact() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "s.toml",
        "[sim]\nt_end = 0.1\n[sweep]\ncontrollers = [{ kind = \"paper\" }]\n\
         grid = { x_min = 1e-300, x_max = 2e-300, nx = 2, y_min = 0.5, y_max = 0.5, ny = 1 }\n",
    );
    let o = run_in(dir.path(), &["sweep", "s.toml", "-o", "s.csv"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let csv = fs::read_to_string(dir.path().join("s.csv")).unwrap();
    let x0: Vec<&str> = csv.lines().skip(1).map(|l| l.split(',').nth(2).unwrap()).collect();
    assert_eq!(x0, ["1e-300", "2e-300"], "{csv}");
    assert!(csv.lines().all(|l| l.split(',').all(|f| f.len() <= 32)), "{csv}");
}

/// Issue 26: `WMR_FAST_KERNEL` with a value that names no kernel fell back silently to
/// the default; now `sweep --fast` refuses it before opening any output (exit 2, one
/// line naming the variable, the value and the accepted names). Without `--fast` the
/// variable is not read.
#[test]
fn regression_26_an_unknown_fast_kernel_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "s.toml", SWEEP);
    let o = bin()
        .current_dir(dir.path())
        .env("WMR_FAST_KERNEL", "avx3")
        .args(["sweep", "s.toml", "--fast", "-o", "s.csv"])
        .output()
        .expect("spawn wmr-cli");
    assert_bad_input(&o, "WMR_FAST_KERNEL");
    let err = text(&o.stderr);
    for word in ["\"avx3\"", "avx512", "avx2", "portable", "exact"] {
        assert!(err.contains(word), "stderr lacks {word}: {err}");
    }
    assert_eq!(entries(dir.path()), ["s.toml"], "no output written");
    for (env, args) in
        [("avx2", &["sweep", "s.toml", "--fast", "-o", "s.csv"][..]), ("avx3", &["sweep", "s.toml", "-o", "t.csv"])]
    {
        let o = bin().current_dir(dir.path()).env("WMR_FAST_KERNEL", env).args(args).output().expect("spawn wmr-cli");
        assert!(o.status.success(), "{env} {args:?}: {}", text(&o.stderr));
    }
}
