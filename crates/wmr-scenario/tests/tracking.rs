//! `[reference]` scenarios (wmr issue 23): the samples against an independent
//! implementation of the circle, the figure-eight and Kanayama's errors; the tracking
//! outcome against a replay of the rule; bad input named by key and line.

use wmr_core::Status;
use wmr_scenario::Scenario;

const PI: f64 = std::f64::consts::PI;

fn wrap(a: f64) -> f64 {
    let mut a = a % (2.0 * PI);
    if a > PI {
        a -= 2.0 * PI;
    } else if a <= -PI {
        a += 2.0 * PI;
    }
    a
}

/// Kanayama's logged errors (x_e, theta_e, |C_ref - C|), by the issue's formulas.
fn errors_by_hand(x: f64, y: f64, th: f64, xr: f64, yr: f64, thr: f64) -> [f64; 3] {
    let xe = th.cos() * (xr - x) + th.sin() * (yr - y);
    [xe, wrap(thr - th), (xr - x).hypot(yr - y)]
}

const CIRCLE: &str = r#"
[reference]
kind = "circle"
center = { x = 0.5, y = -0.25 }
radius = 0.8
speed = -0.25
phase_deg = 30.0

[controller]
kind = "kanayama"

[sim]
t_end = 20.0

[[run]]
start = { x = 1.1, y = 0.2, theta_deg = -70.0 }
"#;

#[test]
fn circle_samples_match_an_independent_implementation() {
    let sc = Scenario::from_toml_str(CIRCLE, "c").unwrap();
    let reference = sc.tracking().unwrap().reference.built.clone();
    let mut n = 0;
    let result = sc
        .run(0, |s| {
            // The reference columns: phi = phase + (speed / radius) t, clockwise.
            let phi = 30f64.to_radians() + (-0.25 / 0.8) * s.t;
            let (xr, yr, thr) = (0.5 + 0.8 * phi.cos(), -0.25 + 0.8 * phi.sin(), phi - PI / 2.0);
            let r = wmr_core::Reference::state_at(&reference, s.t);
            let got = wmr_scenario::reference_values(&r);
            for (g, w) in got.iter().zip([xr, yr, thr, 0.25, -0.25 / 0.8]) {
                assert!((g - w).abs() <= 1e-12, "t = {}: {g} vs {w}", s.t);
            }
            // control_dt = dt and a perfect sensor: the last tick measured the sample's state.
            let want = errors_by_hand(s.state.x, s.state.y, s.state.theta, xr, yr, thr);
            let e = [s.errors.e_s, s.errors.e_theta, s.errors.dl];
            for (g, w) in e.iter().zip(want) {
                assert!((g - w).abs() <= 1e-9, "t = {}: {g} vs {w}", s.t);
            }
            n += 1;
        })
        .unwrap();
    assert_eq!(n, 2001);
    let tr = result.tracking.expect("a tracking run has a tracking outcome");
    assert!(result.converged(), "{}", result.summary_line());
    assert!(tr.rms_last_half < 1e-3 && tr.max_last_half >= tr.rms_last_half, "{}", result.summary_line());
    assert!(result.summary_line().contains("tracking error over the last half RMS"));
}

#[test]
fn figure_eight_reference_matches_an_independent_implementation() {
    let text = CIRCLE.replace(
        "kind = \"circle\"\ncenter = { x = 0.5, y = -0.25 }\nradius = 0.8\nspeed = -0.25\nphase_deg = 30.0",
        "kind = \"figure_eight\"\ncenter = { x = 0.1, y = 0.2 }\nwidth = 2.0\nheight = 1.2\nperiod = 25.0",
    );
    let sc = Scenario::from_toml_str(&text, "f").unwrap();
    let reference = sc.tracking().unwrap().reference.built.clone();
    let a = 2.0 * PI / 25.0;
    for k in 0..=2000 {
        let t = f64::from(k) * 0.0125;
        let (xd, yd) = (1.0 * a * (a * t).cos(), 1.2 * a * (2.0 * a * t).cos());
        let (xdd, ydd) = (-(a * a) * (a * t).sin(), -2.0 * 1.2 * a * a * (2.0 * a * t).sin());
        let want = [
            0.1 + 1.0 * (a * t).sin(),
            0.2 + 0.6 * (2.0 * a * t).sin(),
            yd.atan2(xd),
            xd.hypot(yd),
            (xd * ydd - yd * xdd) / (xd * xd + yd * yd),
        ];
        let got = wmr_scenario::reference_values(&wmr_core::Reference::state_at(&reference, t));
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() <= 1e-12, "t = {t}: {g} vs {w}");
        }
    }
}

#[test]
fn the_tracking_outcome_follows_the_rule_replayed_from_the_samples() {
    // log_dt = dt: every step is a sample, so the rule can be replayed from them.
    let text = CIRCLE.replace("t_end = 20.0", "t_end = 6.0\ndt = 0.001\nlog_dt = 0.001\ntracking_tolerance = 0.02");
    let sc = Scenario::from_toml_str(&text, "c").unwrap();
    let reference = sc.tracking().unwrap().reference.built.clone();
    let mut errs = Vec::new();
    let result = sc
        .run(0, |s| {
            let r = wmr_core::Reference::state_at(&reference, s.t).pose;
            errs.push((s.t, (r.x - s.state.x).hypot(r.y - s.state.y)));
        })
        .unwrap();
    let tr = result.tracking.unwrap();
    let half: Vec<f64> = errs.iter().filter(|(t, _)| *t >= 3.0).map(|(_, e)| *e).collect();
    let rms = (half.iter().map(|e| e * e).sum::<f64>() / half.len() as f64).sqrt();
    let max = half.iter().cloned().fold(0.0, f64::max);
    assert!((tr.rms_last_half - rms).abs() <= 1e-12 * rms.max(1e-300), "{} vs {rms}", tr.rms_last_half);
    assert!((tr.max_last_half - max).abs() <= 1e-15 * max, "{} vs {max}", tr.max_last_half);
    let last_above = errs.iter().filter(|(_, e)| *e >= 0.02).map(|(t, _)| *t).fold(None, |_, t| Some(t));
    assert_eq!(tr.time_to_tolerance, Some(last_above.unwrap_or(0.0)));
    let tail_ok = errs.iter().filter(|(t, _)| *t >= 5.4).all(|(_, e)| *e < 0.02);
    assert_eq!(result.converged(), tail_ok);
}

fn err_of(text: &str) -> wmr_scenario::ScenarioError {
    Scenario::from_toml_str(text, "bad").expect_err("a bad scenario was accepted")
}

#[test]
fn bad_references_and_mismatched_laws_are_named() {
    let e = err_of(&CIRCLE.replace("radius = 0.8", "radius = -0.8"));
    assert_eq!((e.key.as_str(), e.line), ("reference.radius", Some(5)), "{e}");
    let e = err_of(&CIRCLE.replace("kind = \"kanayama\"", "kind = \"polar\""));
    assert_eq!(e.key, "controller.kind", "{e}");
    assert!(e.message.contains("point-stabilization"), "{e}");
    let e = err_of("[controller]\nkind = \"backstepping\"\n[[run]]\ngoal = { x = 1.0 }\n");
    assert_eq!(e.key, "controller.kind", "{e}");
    let e = err_of(&CIRCLE.replace("start = {", "goal = { x = 1.0 }\nstart = {"));
    assert_eq!(e.key, "run[0].goal", "{e}");
    let e = err_of(&CIRCLE.replace("phase_deg = 30.0", "phase_deg = 30.0\nwidth = 2.0"));
    assert_eq!(e.key, "reference.width", "{e}");
    let e = err_of(&CIRCLE.replace("kind = \"circle\"", "kind = \"spiral\""));
    assert_eq!(e.key, "reference.kind", "{e}");
    let e = err_of(&CIRCLE.replace("t_end = 20.0", "t_end = 20.0\ntracking_tolerance = -1.0"));
    assert_eq!(e.key, "sim.tracking_tolerance", "{e}");
    let w = "[reference]\nkind = \"waypoints\"\npoints = [[0.0, 0.0], [0.0, 0.0]]\n[controller]\nkind = \"pure_pursuit\"\n[[run]]\n";
    assert_eq!(err_of(w).key, "reference.points", "{}", err_of(w));
}

#[test]
fn a_file_reference_reads_its_csv_relative_to_the_scenario_file() {
    let dir = std::env::temp_dir().join(format!("wmr-tracking-file-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::write(dir.join("sub/ref.csv"), "t,x,y\n0,0,0\n1,1,0\n2,2,1\n").unwrap();
    let toml = "[reference]\nkind = \"file\"\npath = \"ref.csv\"\n[controller]\nkind = \"kanayama\"\n[sim]\nt_end = 1.0\n[[run]]\n";
    std::fs::write(dir.join("sub/s.toml"), toml).unwrap();
    let sc = Scenario::from_path(dir.join("sub/s.toml")).unwrap();
    let r = sc.tracking().unwrap().reference.built.clone();
    assert_eq!(r.kind(), "waypoints");
    assert_eq!(r.start_pose().x, 0.0);
    // t not increasing: refused naming reference.path, with the file's line.
    std::fs::write(dir.join("sub/ref.csv"), "t,x,y\n0,0,0\n0,1,0\n").unwrap();
    let e = Scenario::from_path(dir.join("sub/s.toml")).unwrap_err();
    assert_eq!(e.key, "reference.path", "{e}");
    assert!(e.message.contains("line 3"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A figure-eight given by its peak speed (issue 40): the period is pi sqrt(w^2 + 4 h^2) /
/// speed, so the largest speed over a period, by finite differences of the positions (not
/// the reference's own twist), is the one asked for; period and speed together, or a
/// speed <= 0, are refused naming `reference.speed`.
#[test]
fn a_figure_eight_by_speed_peaks_at_that_speed() {
    let text = "[reference]\nkind = \"figure_eight\"\nwidth = 3.0\nheight = 1.2\nspeed = 0.4\n\
                [controller]\nkind = \"kanayama\"\n[[run]]\n";
    let sc = Scenario::from_toml_str(text, "by-speed").unwrap();
    let reference = sc.tracking().unwrap().reference.built.clone();
    let period = PI * 3.0f64.hypot(2.4) / 0.4;
    let at = |t: f64| wmr_core::Reference::state_at(&reference, t).pose;
    // One period later, the same pose; half a period later, the centre again.
    let (p0, p1) = (at(0.0), at(period));
    assert!((p0.x - p1.x).abs() < 1e-9 && (p0.y - p1.y).abs() < 1e-9, "{p0:?} {p1:?}");
    let h = 1e-4;
    let peak = (0..4000)
        .map(|k| {
            let t = period * f64::from(k) / 4000.0;
            let (a, b) = (at(t - h), at(t + h));
            (b.x - a.x).hypot(b.y - a.y) / (2.0 * h)
        })
        .fold(0.0f64, f64::max);
    assert!((peak - 0.4).abs() < 1e-6, "peak speed {peak}");
    // `check` keeps the speed as given and writes no default period beside it.
    let dump = sc.to_toml();
    assert!(dump.contains("speed = 0.4") && !dump.contains("period ="), "{dump}");
    Scenario::from_toml_str(&dump, "again").expect("check's output reads back");

    let e = err_of(&text.replace("speed = 0.4", "speed = 0.4\nperiod = 30.0"));
    assert_eq!(e.key, "reference.speed", "{e}");
    assert!(e.message.contains("not both"), "{e}");
    let e = err_of(&text.replace("speed = 0.4", "speed = -0.4"));
    assert_eq!(e.key, "reference.speed", "{e}");
}

/// A `[reference]` without a `[controller]` (or one without `kind`) is followed by a law
/// that follows it, not refused for `paper`, a law the user never wrote (issue 40); `check`
/// says where the kind came from. A `[controller]` with a stabilization law's keys keeps
/// the old refusal, naming `controller.kind`.
#[test]
fn a_reference_without_a_controller_is_followed_by_a_tracking_law() {
    let text = "[reference]\nkind = \"circle\"\n[[run]]\n";
    let sc = Scenario::from_toml_str(text, "no-controller").expect("a [reference] alone is a scenario");
    let kind = sc.setup().controller.law.kind();
    assert_eq!(kind, wmr_scenario::tracking_law_kinds()[0]);
    let dump = sc.to_toml();
    let line =
        dump.lines().find(|l| l.starts_with("kind = \"") && l.contains(kind)).unwrap_or_else(|| panic!("{dump}"));
    assert!(line.contains("# default with a [reference]"), "{line}");
    // With kind's own keys and no kind: the same default.
    let sc = Scenario::from_toml_str(&text.replace("[[run]]", "[controller]\nkx = 2.0\n[[run]]"), "x").unwrap();
    assert_eq!(sc.setup().controller.law.kind(), kind);
    let e = err_of(&text.replace("[[run]]", "[controller]\nkp_s = 2.0\n[[run]]"));
    assert!(e.key.starts_with("controller"), "{e}");
}

/// `check` fills in and marks every default, not only `[robot]`'s (issue 40): a
/// figure-eight's default `center`, `width`, `height` and `period`, and the defaults of
/// `[controller]` and `[world]`, each line saying `# default` or `# scenario`.
#[test]
fn check_fills_in_and_marks_the_defaults_of_every_table() {
    let text = "[reference]\nkind = \"figure_eight\"\nwidth = 3.0\n[controller]\nkind = \"kanayama\"\n\
                [world]\nslope_deg = 1.0\n[[run]]\n";
    let sc = Scenario::from_toml_str(text, "defaults").unwrap();
    let dump = sc.to_toml();
    let line = |key: &str| {
        let section_start = dump.find("[reference]").unwrap();
        dump[section_start..]
            .lines()
            .find(|l| l.starts_with(&format!("{key} =")))
            .unwrap_or_else(|| panic!("{key}: {dump}"))
    };
    for key in ["center", "height", "period"] {
        assert!(line(key).ends_with("# default"), "{}", line(key));
    }
    assert!(line("center").starts_with("center = { x = 0.0, y = 0.0 }"), "{}", line("center"));
    assert!(line("width").ends_with("# scenario"), "{}", line("width"));
    let in_table = |table: &str, key: &str| {
        let at = dump.find(&format!("\n[{table}]\n")).unwrap();
        dump[at..].lines().find(|l| l.starts_with(&format!("{key} ="))).unwrap_or_default().to_owned()
    };
    assert!(in_table("world", "slope_deg").ends_with("# scenario"), "{dump}");
    assert!(in_table("controller", "kx").ends_with("# default"), "{dump}");
    assert!(in_table("controller", "kind").ends_with("# scenario"), "{dump}");
    // Read back, the same robot, laws and reference (its table now lists every key).
    let again = Scenario::from_toml_str(&dump, "again").unwrap();
    assert_eq!(again.setup(), sc.setup());
    assert_eq!(again.tracking().unwrap().reference.built, sc.tracking().unwrap().reference.built);
}

/// MPPI follows a goal or a `[reference]`'s path (issue 41): with a circle it runs, is
/// judged on the distance to the path (the tracking outcome replayed here from the
/// samples against the circle's equation: the distance to a circle is | |C - c| - r |),
/// and a point-stabilization law's refusal names it among the laws that follow one.
#[test]
fn mppi_follows_a_references_path_and_is_judged_on_the_distance_to_it() {
    let text = CIRCLE
        .replace(
            "kind = \"kanayama\"",
            "kind = \"mppi\"\nbatch_size = 200\npath_align_offset_from_furthest = 5\npath_align_cost_weight = 30.0",
        )
        .replace("t_end = 20.0", "t_end = 12.0\ndt = 0.001\nlog_dt = 0.001\ntracking_tolerance = 0.05");
    let sc = Scenario::from_toml_str(&text, "c").unwrap();
    let mut errs = Vec::new();
    let result = sc.run(0, |s| errs.push((s.t, ((s.state.x - 0.5).hypot(s.state.y + 0.25) - 0.8).abs()))).unwrap();
    let tr = result.tracking.unwrap();
    let half: Vec<f64> = errs.iter().filter(|(t, _)| *t >= 6.0).map(|(_, e)| *e).collect();
    let max = half.iter().cloned().fold(0.0, f64::max);
    // The watch finds the closest point by search (to 1e-5 of a step): close, not equal.
    assert!((tr.max_last_half - max).abs() < 1e-6, "{} vs {max}", tr.max_last_half);
    assert!(max < 0.05 && result.converged(), "{max} m off the circle");
    let e = err_of(&CIRCLE.replace("kind = \"kanayama\"", "kind = \"polar\""));
    assert!(e.message.contains("mppi"), "{e}");
}

/// A path follower held on its path by a wall across it is close to the path all along,
/// yet follows nothing: `unsettled`, with the reason, not `converged` (as it was judged
/// before the rule asked for progress along the path or its end).
#[test]
fn mppi_held_on_its_path_by_a_wall_is_not_converged() {
    let text = r#"
[reference]
kind = "line"
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
speed = 0.3

[controller]
kind = "mppi"
batch_size = 200

[robot]
footprint_radius = 0.15

[sim]
t_end = 15.0
tracking_tolerance = 0.05

[[world.obstacle]]
kind = "polygon"
points = [[1.0, -1.0], [1.1, -1.0], [1.1, 1.0], [1.0, 1.0]]

[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
"#;
    let sc = Scenario::from_toml_str(text, "wall").unwrap();
    let mut x_max = f64::NEG_INFINITY;
    let result = sc.run(0, |s| x_max = x_max.max(s.state.x)).unwrap();
    let tr = result.tracking.unwrap();
    assert!(x_max < 1.0 - 0.15, "it drove into the wall: x = {x_max} m");
    assert!(tr.within_tolerance(), "{} m from the path over the last tenth", tr.max_last_tenth);
    assert!(tr.progress_last_tenth < 0.05, "{} m along the path", tr.progress_last_tenth);
    assert_eq!(result.status(), Status::Unsettled, "{}", result.summary_line());
    assert!(result.summary_line().contains("(stopped on the path: "), "{}", result.summary_line());
}
