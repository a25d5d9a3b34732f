//! Sweeps over references (wmr issue 23): every law on every reference from starts given
//! as offsets from the reference's pose at t = 0, each run judged by its tracking error.
//! Checked against the same runs written as `[[run]]`s of a `[reference]` scenario (the
//! run path, which tests/tracking.rs checks against an independent implementation), the
//! offsets against the reference's start pose by hand, and bad input named by key.
//! On the code before sweeps over references every test here fails: such a sweep was
//! refused naming `sweep`.

use wmr_core::Status;
use wmr_scenario::{Scenario, tracking_summary, tracking_sweep_columns, tracking_sweep_row};

const SWEEP: &str = r#"
[sim]
t_end = 8.0
tracking_tolerance = 0.02

[sweep]
controllers = [{ kind = "kanayama" }, { kind = "pure_pursuit" }]
references = [
  { kind = "circle", radius = 1.0, speed = 0.3 },
  { kind = "figure_eight" },
]
grid = { x_min = -0.1, x_max = 0.1, nx = 2, y_min = 0.0, y_max = 0.2, ny = 2, theta_deg = [0.0, 20.0] }
"#;

/// The `[reference]` scenario of reference `r` of [`SWEEP`] with law `law`, one run from `start`.
fn as_run(law: &str, r: usize, start: wmr_core::Pose2<f64>) -> Scenario {
    let reference = ["kind = \"circle\"\nradius = 1.0\nspeed = 0.3", "kind = \"figure_eight\""][r];
    let text = format!(
        "[sim]\nt_end = 8.0\ntracking_tolerance = 0.02\n[reference]\n{reference}\n[controller]\nkind = \"{law}\"\n\
         [[run]]\nstart = {{ x = {:?}, y = {:?}, theta = {:?} }}\n",
        start.x, start.y, start.theta
    );
    Scenario::from_toml_str(&text, "replay").unwrap()
}

#[test]
fn every_law_on_every_reference_is_the_run_of_a_reference_scenario() {
    let sc = Scenario::from_toml_str(SWEEP, "t").unwrap();
    let spec = sc.sweep().unwrap();
    assert_eq!(spec.len(), 2 * 2 * 8);
    let outcomes = spec.run(sc.sim(), &|| {}).unwrap();
    let laws = ["kanayama", "pure_pursuit"];
    for (k, o) in outcomes.iter().enumerate() {
        // Order: law, then reference, then start.
        assert_eq!((o.law, o.reference, o.start_index), (k / 16, (k / 8) % 2, k % 8), "run {k}");
        let replay = as_run(laws[o.law], o.reference, o.start).run(0, |_| {}).unwrap();
        let tr = o.tracking.expect("a tracking outcome");
        let want = replay.tracking.unwrap();
        assert_eq!(tr.rms_last_half.to_bits(), want.rms_last_half.to_bits(), "run {k}");
        assert_eq!(tr.max_last_half.to_bits(), want.max_last_half.to_bits(), "run {k}");
        assert_eq!(tr.time_to_tolerance, want.time_to_tolerance, "run {k}");
        assert_eq!(o.outcome, replay.outcome, "run {k}");
        assert_eq!(o.status(), replay.status(), "run {k}");
        let row = tracking_sweep_row(spec, o).unwrap();
        assert_eq!(row.len(), tracking_sweep_columns().len());
        assert_eq!(row[1], ["circle", "figure_eight"][o.reference]);
        assert_eq!(row[9], o.status().name());
    }
    // The summary's shares count the runs.
    let rows = tracking_summary(spec, &outcomes);
    assert_eq!(rows.len(), 4);
    for (i, r) in rows.iter().enumerate() {
        let runs: Vec<_> = outcomes.iter().filter(|o| o.law == i / 2 && o.reference == i % 2).collect();
        let conv = runs.iter().filter(|o| o.status() == Status::Converged).count() as f64 / runs.len() as f64;
        assert_eq!((r.n, r.converged), (8, conv), "{} on {}", r.law, r.reference);
    }
    // Kanayama on the circle from 10 cm and 20 deg off converges within 8 s.
    assert!(rows[0].converged > 0.99, "{rows:?}");
}

#[test]
fn starts_are_offsets_in_the_frame_of_the_references_start_pose() {
    let sc = Scenario::from_toml_str(SWEEP, "t").unwrap();
    let spec = sc.sweep().unwrap();
    // The circle starts at phase -90 deg: C_ref = (0, -1), heading 0 (counter-clockwise).
    // Grid offset (0.1 ahead, 0.2 left, 20 deg): (0.1, -0.8), 20 deg.
    let i = spec.starts.iter().position(|o| (o.x, o.y, o.theta.to_degrees()) == (0.1, 0.2, 20.0)).unwrap();
    let p = spec.start_pose(0, i);
    assert!((p.x - 0.1).abs() < 1e-12 && (p.y + 0.8).abs() < 1e-12, "{p:?}");
    assert!((p.theta - 20f64.to_radians()).abs() < 1e-12);
    // The figure-eight starts at its center heading atan2(1, 1) = 45 deg: 0.2 m to its
    // left is (-0.2 sin 45, 0.2 cos 45) more.
    let f = spec.start_pose(1, i);
    let (s, c) = std::f64::consts::FRAC_PI_4.sin_cos();
    assert!((f.x - (0.1 * c - 0.2 * s)).abs() < 1e-12 && (f.y - (0.1 * s + 0.2 * c)).abs() < 1e-12, "{f:?}");
}

#[test]
fn the_scenarios_reference_is_the_sweeps_when_it_lists_none() {
    // [controller] is the runs' law (checked against [reference]); the sweep's are its own.
    let text = "[reference]\nkind = \"circle\"\n[controller]\nkind = \"kanayama\"\n[sim]\nt_end = 2.0\n[sweep]\ncontrollers = [{ kind = \"kanayama\" }]\n\
                random = { n = 3, seed = 1, radius = 0.1, max_heading_deg = 10.0 }\n";
    let sc = Scenario::from_toml_str(text, "t").unwrap();
    let spec = sc.sweep().unwrap();
    assert_eq!(spec.tracking.as_ref().unwrap().references.len(), 1);
    assert_eq!(spec.len(), 3);
    assert!(spec.starts.iter().all(|o| o.theta.abs() <= 10f64.to_radians() + 1e-12 && o.x.hypot(o.y) <= 0.1));
    // Written back by `check`, it reads back to the same sweep.
    let again = Scenario::from_toml_str(&sc.to_toml(), "t").unwrap();
    assert_eq!(again.sweep(), sc.sweep());
    let listed = Scenario::from_toml_str(SWEEP, "t").unwrap();
    let again = Scenario::from_toml_str(&listed.to_toml(), "t").unwrap();
    assert_eq!(again.sweep(), listed.sweep());
}

#[test]
fn bad_sweeps_over_references_are_named_by_key_and_line() {
    let err = |text: &str| Scenario::from_toml_str(text, "t").unwrap_err();
    let base = "[sim]\nt_end = 2.0\n[sweep]\n";
    let starts = "random = { n = 2, radius = 0.1 }\n";
    let e = err(&format!("{base}references = [{{ kind = \"circle\" }}]\ngoal = {{ x = 1.0 }}\n{starts}"));
    assert_eq!(e.key, "sweep.goal", "{e}");
    let e = err(&format!(
        "{base}controllers = [{{ kind = \"kanayama\" }}]\nreferences = [\n  {{ kind = \"circle\" }},\n  {{ kind = \"circle\", radius = -1.0 }},\n]\n{starts}"
    ));
    assert_eq!((e.key.as_str(), e.line), ("sweep.references[1].radius", Some(7)), "{e}");
    let e =
        err(&format!("{base}controllers = [{{ kind = \"polar\" }}]\nreferences = [{{ kind = \"circle\" }}]\n{starts}"));
    assert_eq!(e.key, "sweep.controllers[0].kind", "{e}");
    assert!(e.message.contains("point-stabilization"), "{e}");
    let e = err(&format!("{base}references = []\n{starts}"));
    assert_eq!(e.key, "sweep.references", "{e}");
    let e = err(&format!("{base}controllers = [{{ kind = \"kanayama\" }}]\n{starts}"));
    assert_eq!(e.key, "sweep.controllers[0].kind", "a tracking law without a reference: {e}");
    let e = err(&format!(
        "{base}references = [{{ kind = \"circle\" }}]\nrandom = {{ n = 2, radius = 0.1, max_heading_deg = 270.0 }}\n"
    ));
    assert_eq!(e.key, "sweep.random.max_heading_deg", "{e}");
}
