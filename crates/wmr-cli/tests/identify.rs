//! Issue 44, item 2: `wmr-cli excite`, `identify` and `replay` end to end: a log of a
//! known robot identified into a robot file that `[robot] from` reads, and bad logs
//! refused naming the column or the time, exit 2.

use std::fs;

use crate::identify_common::{ok, refused, run};

/// The replay's table of the wheel-speed error RMS in each second (`run  from_s` then
/// ten seconds a line): a row per run, `durations_s[run]` values (one per started second
/// of the run's compared samples), and the run's RMS over all its seconds lies between
/// the smallest and the largest of them (an RMS pooled from parts is within their range).
fn per_second_table_bounds_each_run(out: &str, durations_s: &[f64]) {
    let rms: Vec<f64> = out
        .lines()
        .skip_while(|l| !l.starts_with("run  samples"))
        .skip(1)
        .take_while(|l| !l.starts_with("all"))
        .map(|l| l.split_whitespace().nth(2).unwrap().parse().unwrap())
        .collect();
    assert_eq!(rms.len(), durations_s.len(), "{out}");
    let table: Vec<&str> = out.lines().skip_while(|l| *l != "run  from_s").skip(1).collect();
    let mut runs: Vec<Vec<f64>> = Vec::new();
    for line in table {
        let words: Vec<&str> = line.split_whitespace().collect();
        if !line.starts_with(' ') {
            assert_eq!(words[0], runs.len().to_string(), "{line}");
            runs.push(Vec::new());
        }
        let values = &words[if line.starts_with(' ') { 1 } else { 2 }..];
        let from: usize = words[if line.starts_with(' ') { 0 } else { 1 }].parse().unwrap();
        let run = runs.last_mut().unwrap();
        assert_eq!(from, run.len(), "{line}");
        assert!(values.len() <= 10, "{line}");
        run.extend(values.iter().map(|v| v.parse::<f64>().unwrap()));
    }
    assert_eq!(runs.len(), durations_s.len(), "{out}");
    for (k, (seconds, dur)) in runs.iter().zip(durations_s).enumerate() {
        // The compared samples start after the filter's first samples: the run's seconds
        // are its duration's, the last one partly.
        assert!((seconds.len() as f64 - dur).abs() <= 1.0, "run {k}: {} seconds, {dur} s", seconds.len());
        let (lo, hi) = seconds.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
        // Printed to 3 digits: half a unit of the last on each side.
        assert!(lo * (1.0 - 5e-3) <= rms[k] && rms[k] <= hi * (1.0 + 5e-3), "run {k}: {} not in [{lo}, {hi}]", rms[k]);
    }
}

/// The robot of crates/wmr-identify/tests/fit.rs, torque drive without a limit.
const TRUTH: &str = "[robot]
mass = 10.0
wheel_radius = 0.05
half_track = 0.2
com_offset = 0.1
wheel_inertia = 0.004
platform_inertia = 0.3
gear_ratio = 0.1
viscous_friction = 0.02
coulomb_friction = 0.1

[drive]
kind = \"torque\"
motor_torque_max = 0.3
";

/// Its geometry only: every fitted value wrong.
const GEOMETRY: &str = "[robot]
mass = 1.0
wheel_radius = 0.05
half_track = 0.2
com_offset = 0.1
wheel_inertia = 0.0
platform_inertia = 1.0
gear_ratio = 0.1
";

fn value(toml: &str, key: &str) -> f64 {
    let line = toml.lines().find(|l| l.starts_with(&format!("{key} ="))).unwrap_or_else(|| panic!("{key} in {toml}"));
    line.split('=').nth(1).unwrap().split('#').next().unwrap().trim().parse().unwrap()
}

#[test]
fn issue_44_excite_identify_replay_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fs::write(d.join("truth.toml"), TRUTH).unwrap();
    fs::write(d.join("geometry.toml"), GEOMETRY).unwrap();
    let out = ok(&run(
        d,
        &[
            "excite",
            "-o",
            "profile.csv",
            "--robot",
            "truth.toml",
            "--log",
            "sim.csv",
            "--encoder-noise",
            "0.01",
            "--jitter",
            "0.005",
            "--seed",
            "44",
        ],
    ));
    assert!(out.contains("quasistatic-linear-forward") && out.contains("safe_distance_m"), "{out}");
    let profile = fs::read_to_string(d.join("profile.csv")).unwrap();
    assert!(profile.starts_with("run,t,tau_r,tau_l\n"), "{}", &profile[..40]);
    // 12 tests: 6 of 6 s and 6 of 2 s at 100 Hz, each with its first sample.
    assert_eq!(profile.lines().count(), 1 + 6 * 601 + 6 * 201);

    let out = ok(&run(d, &["identify", "sim.csv", "-o", "fitted.toml", "--robot", "geometry.toml"]));
    assert!(out.contains("mass") && out.contains("+-"), "{out}");
    let fitted = fs::read_to_string(d.join("fitted.toml")).unwrap();
    assert!(fitted.contains("fitted: +-") && fitted.contains("from sim.csv"), "{fitted}");
    for (key, truth, tol) in [
        ("mass", 10.0, 0.02),
        ("platform_inertia", 0.3, 0.03),
        ("wheel_inertia", 0.004, 0.05),
        ("coulomb_friction", 0.1, 0.05),
        ("viscous_friction", 0.02, 0.05),
    ] {
        let v = value(&fitted, key);
        assert!((v - truth).abs() < tol * truth, "{key} = {v}, truth {truth}");
    }
    // Usable with [robot] from (a step short enough for its stiff Coulomb friction).
    fs::write(d.join("s.toml"), "[robot]\nfrom = \"fitted.toml\"\n\n[sim]\ndt = 0.0001\n\n[[run]]\ngoal = { x = 1.0, y = 0.0, theta_deg = 0.0 }\n").unwrap();
    let check = ok(&run(d, &["check", "s.toml"]));
    assert!(check.contains("mass = 9.9") || check.contains("mass = 10.0"), "{check}");
    // `check` shows each fitted value's standard error and the log it came from, as the
    // robot file says them; a held key (the geometry) is only the file's.
    for key in ["mass", "wheel_inertia", "platform_inertia", "viscous_friction", "coulomb_friction"] {
        let line = check.lines().find(|l| l.starts_with(&format!("{key} = "))).unwrap();
        let in_file = fitted.lines().find(|l| l.starts_with(&format!("{key} = "))).unwrap();
        let note = &in_file[in_file.find("fitted: +- ").unwrap()..];
        assert!(note.ends_with("(standard error), from sim.csv"), "{in_file}");
        assert!(line.ends_with(&format!(" # fitted.toml, {note}")), "{line}");
    }
    let line = check.lines().find(|l| l.starts_with("wheel_radius = ")).unwrap();
    assert!(line.ends_with("# fitted.toml"), "{line}");

    // The replay of the fitted robot over 1 s horizons follows the log closely.
    let out = ok(&run(d, &["replay", "sim.csv", "--robot", "fitted.toml", "--horizon", "1"]));
    let all = out.lines().find(|l| l.starts_with("all")).unwrap();
    let pct: f64 = all.split_whitespace().nth(3).unwrap().parse().unwrap();
    assert!(pct < 2.0, "{out}");
    per_second_table_bounds_each_run(&out, &[6.0, 6.0, 6.0, 6.0, 6.0, 6.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0]);
    // --plot draws one run: its wheel speeds (logged, replayed), the error per second and
    // the paths, as one SVG of two pages; a run the log does not have is refused.
    let out = ok(&run(d, &["replay", "sim.csv", "--robot", "fitted.toml", "--plot", "replay.svg", "--plot-run", "7"]));
    assert!(out.ends_with("wrote replay.svg (run 7)\n"), "{out}");
    let svg = fs::read_to_string(d.join("replay.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("valid XML");
    let ids: Vec<&str> = doc.descendants().filter_map(|n| n.attribute("id")).collect();
    let unique: std::collections::BTreeSet<&str> = ids.iter().copied().collect();
    assert_eq!(unique.len(), ids.len(), "ids repeat across the pages: {ids:?}");
    // The texts as read (a subscript's tspan joined to its text: `ω_r` reads `ωr`).
    let texts: Vec<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.descendants().filter(|d| d.is_text()).filter_map(|d| d.text()).collect())
        .collect();
    for label in [
        "right wheel ωr, logged",
        "right wheel ωr, replayed",
        "left wheel ωl, logged",
        "left wheel ωl, replayed",
        "RMS per second of log",
        "logged",
        "replayed",
    ] {
        assert!(texts.iter().any(|t| t == label), "{label} not in {texts:?}");
    }
    assert!(svg.contains("replay of fitted.toml on run 7 of sim.csv"));
    let err = refused(&run(d, &["replay", "sim.csv", "--robot", "fitted.toml", "--plot", "r.svg", "--plot-run", "12"]));
    assert!(err.contains("--plot-run 12: sim.csv has no such run (its runs: 0, 1, 2"), "{err}");
    assert!(!d.join("r.svg").exists());
    let err = refused(&run(d, &["replay", "sim.csv", "--robot", "fitted.toml", "--plot", "sim.csv"]));
    assert!(err.contains("sim.csv"), "{err}");
    // The wrong robot does not.
    let out = ok(&run(d, &["replay", "sim.csv", "--robot", "geometry.toml", "--horizon", "1"]));
    let all = out.lines().find(|l| l.starts_with("all")).unwrap();
    let pct_wrong: f64 = all.split_whitespace().nth(3).unwrap().parse().unwrap();
    assert!(pct_wrong > 10.0 * pct, "{out}");
}

fn log_of(rows: &[[f64; 5]]) -> String {
    let mut s = String::from("t,tau_r,tau_l,phi_r,phi_l\n");
    for r in rows {
        s += &format!("{},{},{},{},{}\n", r[0], r[1], r[2], r[3], r[4]);
    }
    s
}

#[test]
fn issue_44_bad_logs_are_refused_naming_the_column_or_the_time() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good: Vec<[f64; 5]> = (0..100).map(|i| [i as f64 * 0.01, 1.0, 1.0, 0.0, 0.0]).collect();
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "missing.csv",
            "t,tau_r,tau_l,phi_r\n0,1,1,0\n".to_owned(),
            "missing column `phi_l or position_l (or omega_l or velocity_l)`",
        ),
        (
            "back.csv",
            log_of(&[[0.0, 1.0, 1.0, 0.0, 0.0], [0.02, 1.0, 1.0, 0.0, 0.0], [0.01, 1.0, 1.0, 0.0, 0.0]]),
            "column `t` at t = 0.01 s (row 3): time does not increase",
        ),
        (
            "nan.csv",
            log_of(&[[0.0, 1.0, 1.0, 0.0, 0.0], [0.01, f64::NAN, 1.0, 0.0, 0.0]]),
            "column `tau_r` at t = 0.01 s (row 2): not a finite number",
        ),
        ("still.csv", log_of(&good), "no excitation in column `phi_r`: the wheels never turn"),
    ];
    for (name, body, expected) in cases {
        fs::write(d.join(name), body).unwrap();
        let err = refused(&run(d, &["identify", name, "-o", "out.toml"]));
        assert!(err.contains(expected), "{name}: {err}");
        assert!(!d.join("out.toml").exists());
    }
    fs::write(d.join("log.csv"), log_of(&good)).unwrap();
    let err = refused(&run(d, &["identify", "log.csv", "-o", "out.toml", "--hold", "mass,bogus"]));
    assert!(err.contains("--hold: unknown parameter `bogus`"), "{err}");
    let err = refused(&run(d, &["identify", "log.csv", "-o", "out.toml", "--drive", "dc_motor"]));
    assert!(err.contains("missing column `u_r or voltage_r`"), "{err}");
    // An output that is an input is refused before any work (nothing printed).
    let o = run(d, &["identify", "log.csv", "-o", "log.csv"]);
    assert!(refused(&o).contains("refusing to overwrite"));
    fs::write(d.join("r.toml"), TRUTH).unwrap();
    let o = run(d, &["excite", "-o", "r.toml", "--robot", "r.toml"]);
    assert!(refused(&o).contains("refusing to overwrite") && o.stdout.is_empty());
    assert_eq!(fs::read_to_string(d.join("r.toml")).unwrap(), TRUTH);
    let err = refused(&run(d, &["replay", "log.csv", "--robot", "none.toml"]));
    assert!(err.contains("none.toml"), "{err}");
}

/// A log is read into memory whole: one larger than the bound (1 GiB; WMR_MAX_LOG_BYTES
/// sets it) is refused naming the file, its size and the bound, exit 2, before anything
/// is allocated for it: a sparse file of 2 GiB costs no disk and no time.
#[test]
fn issue_44_a_log_larger_than_the_bound_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fs::write(d.join("robot.toml"), "[robot]\nmass = 5.0\n").unwrap();
    for name in ["big.csv", "big.mcap"] {
        let f = fs::File::create(d.join(name)).unwrap();
        f.set_len(2 << 30).unwrap();
        let err = refused(&run(d, &["identify", name, "-o", "r.toml"]));
        assert!(
            err.contains(&format!("{name}: 2147483648 bytes, more than the 1073741824 bytes a log may have")),
            "{err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
        let err = refused(&run(d, &["replay", name, "--robot", "robot.toml"]));
        assert!(err.contains(&format!("{name}: 2147483648 bytes")), "{err}");
    }
    let err = refused(&run(d, &["log2csv", "big.mcap"]));
    assert!(err.contains("big.mcap: 2147483648 bytes, more than the 1073741824 bytes"), "{err}");
    // A small bound set by the environment: a log of a few hundred bytes is over it.
    fs::write(d.join("small.csv"), log_of(&[[0.0, 1.0, 1.0, 0.0, 0.0]; 20])).unwrap();
    let len = fs::metadata(d.join("small.csv")).unwrap().len();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .current_dir(d)
        .env("WMR_MAX_LOG_BYTES", "100")
        .args(["identify", "small.csv", "-o", "r.toml"])
        .output()
        .unwrap();
    let err = refused(&o);
    assert!(err.contains(&format!("small.csv: {len} bytes, more than the 100 bytes a log may have")), "{err}");
    // A bound that is not a number of bytes is bad input naming the variable.
    for bad in ["1GiB", "-1", ""] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
            .current_dir(d)
            .env("WMR_MAX_LOG_BYTES", bad)
            .args(["replay", "small.csv", "--robot", "robot.toml"])
            .output()
            .unwrap();
        let err = refused(&o);
        assert!(err.contains(&format!("WMR_MAX_LOG_BYTES: {bad:?} is not a whole number of bytes")), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}
