//! Odometry in scenarios and sweeps (issue 24, `issues show 24`): the drift a run reports
//! is its own last sample's, and a vary entry sets the pose source with its fix rate.

use wmr_scenario::Scenario;

const RUN: &str = r#"
[sim]
t_end = 2.0
[sensor]
pose = "odometry"
[controller.model]
wheel_radius = 0.101
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
goal = { x = 1.0, y = 1.0, theta_deg = 120.0 }
"#;

/// The drift in the result is the distance between the last sample's odometry and true
/// positions, and the distance the outcome's path length.
#[test]
fn a_runs_drift_is_its_last_samples() {
    let sc = Scenario::from_toml_str(RUN, "odometry").unwrap();
    let mut last = None;
    let r = sc.run(0, |s| last = Some(*s)).unwrap();
    let s = last.unwrap();
    let odo = s.odometry.expect("a run on odometry logs its odometry");
    let d = r.odometry_drift.expect("and reports its drift");
    assert_eq!(d.drift_m, (odo.x - s.state.x).hypot(odo.y - s.state.y));
    assert!(d.drift_m > 1e-4, "a 1 % radius error drifts: {d:?}");
    assert_eq!(d.distance_m, r.outcome.path_length);
    assert!(r.summary_line().contains("odometry drift"));
    // The same scenario on the absolute sensor reports none.
    let abs = Scenario::from_toml_str(&RUN.replace("\"odometry\"", "\"absolute\""), "abs").unwrap();
    let r = abs.run(0, |s| assert!(s.odometry.is_none())).unwrap();
    assert!(r.odometry_drift.is_none() && !r.summary_line().contains("odometry"));
}

const SWEEP: &str = r#"
[sim]
t_end = 1.0
[sweep]
goal = { x = 0.5, y = 0.0, theta_deg = 0.0 }
controllers = [{ kind = "polar" }]
random = { n = 2, seed = 1, radius = 1.0, min_radius = 0.1 }
vary = [{ key = "sensor.fix_rate_hz", values = [0.0, 1.0], with = { "sensor.pose" = "odometry" } }]
"#;

/// `with` switches each value's variant to odometry; without it a fix rate on the
/// absolute sensor is refused, naming the vary entry and the key.
#[test]
fn a_vary_entry_sets_the_pose_source_with_its_fix_rate() {
    let sc = Scenario::from_toml_str(SWEEP, "sweep").unwrap();
    let sw = sc.sweep().unwrap();
    let outcomes = sw.run(sc.sim(), &|| {}).unwrap();
    assert_eq!(outcomes.len(), 4);
    assert!(outcomes.iter().all(|o| o.odometry_drift.is_some()), "{outcomes:?}");
    let refused = Scenario::from_toml_str(&SWEEP.replace(", with = { \"sensor.pose\" = \"odometry\" }", ""), "s")
        .map(|_| ())
        .unwrap_err();
    assert_eq!(refused.key, "sweep.vary[0]", "{refused}");
    assert!(refused.message.contains("sensor.fix_rate_hz"), "{refused}");
    // `wmr-cli check` writes the entry back as it reads it.
    let again = Scenario::from_toml_str(&sc.to_toml(), "again").unwrap();
    assert_eq!(again.sweep().unwrap().variation, sw.variation);
    let drawn = SWEEP.replace("values = [0.0, 1.0]", "uniform = [0.0, 1.0]");
    let refused = Scenario::from_toml_str(&drawn, "s").map(|_| ()).unwrap_err();
    assert_eq!(refused.key, "sweep.vary[0].with", "{refused}");
}

/// Issue 24, "slip makes it drift more": Fig. 7's first 10 s on odometry with ideal
/// encoders and the exact model. Rolling wheels, the dead reckoning is the true pose to
/// rounding; wheels that slip (`examples/slip.toml`'s geometry, mu 0.8 and 0.3) turn
/// without moving the robot as much, and the odometry drifts centimetres (at 60 s:
/// 0.00 %, 23.6 % and 36.4 % of the distance travelled; docs/model.md).
#[test]
fn slip_makes_the_odometry_drift() {
    let drift = |robot: &str| {
        let text = format!(
            "[robot]\n{robot}\n[sensor]\npose = \"odometry\"\n[sim]\nt_end = 10.0\n[[run]]\n\
             start = {{ x = 0.0, y = 0.0, theta_deg = 0.0 }}\ngoal = {{ x = 1.0, y = 1.0, theta_deg = 120.0 }}\n"
        );
        let r = Scenario::from_toml_str(&text, "slip-odometry").unwrap().run(0, |_| {}).unwrap();
        r.odometry_drift.expect("a run on odometry reports its drift").drift_m
    };
    let rolling = drift("traction = \"rolling\"");
    let slip = |mu: f64| {
        drift(&format!("traction = \"slip\"\nfriction_coefficient = {mu}\ncaster_offset = 0.35\ncom_height = 0.1"))
    };
    let (slip_08, slip_03) = (slip(0.8), slip(0.3));
    eprintln!("drift after 10 s: rolling {rolling:.3e} m, slip mu 0.8 {slip_08:.4} m, mu 0.3 {slip_03:.4} m");
    assert!(rolling < 1e-5, "rolling: {rolling}");
    assert!(slip_08 > 0.01 && slip_03 > 0.01, "{slip_08} {slip_03}");
    assert!(slip_03 > slip_08, "less grip, more drift: {slip_03} vs {slip_08}");
}
