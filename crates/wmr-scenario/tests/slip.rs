//! `[robot] traction = "slip"` through the scenario (issue 24, traction): keys read and
//! refused by name, the step checked against the slip's stiffness, the contact logged.

use wmr_scenario::{CONTACT_COLUMNS, Scenario, contact_values};

fn scenario(robot: &str, sim: &str) -> Result<Scenario, wmr_scenario::ScenarioError> {
    let text = format!(
        "[robot]\n{robot}\n[sim]\nt_end = 3.0\n{sim}\n[[run]]\ngoal = {{ x = 1.0, y = 1.0, theta_deg = 120.0 }}\n"
    );
    Scenario::from_toml_str(&text, "slip")
}

#[track_caller]
fn refused(robot: &str, sim: &str, key: &str) -> String {
    match scenario(robot, sim) {
        Ok(_) => panic!("accepted: {robot} {sim}"),
        Err(e) => {
            assert_eq!(e.key, key, "{e}");
            e.message
        }
    }
}

#[test]
fn issue24_traction_keys_are_refused_by_name() {
    let m = refused("traction = \"skid\"", "", "robot.traction");
    assert!(m.contains("rolling") && m.contains("slip"), "{m}");
    refused("traction = \"slip\"\nfriction_coefficient = -0.1", "", "robot.friction_coefficient");
    refused("traction = \"slip\"\ncaster_offset = 0.1", "", "robot.caster_offset");
    refused("traction = \"slip\"\ncom_height = 1.0", "", "robot.com_height");
    refused("traction = \"slip\"\nfriction_coefficient = nan", "", "robot.friction_coefficient");
    refused("friction_coefficient = nan", "", "robot.friction_coefficient"); // rolling too
    refused("traction = \"slip\"\nfriction_coefficent = 0.3", "", "robot.friction_coefficent"); // typo
}

/// The step is checked against the slip's stiffness (Plant::stiffness): the paper's robot
/// on asphalt integrates up to dt = 1.53 ms with the default slip_speed 0.2 m/s, up to
/// 0.70 ms with 0.1 m/s: at dt = 1 ms that is refused, naming slip_speed and saying what
/// would do; the advice, taken, is accepted. A contact too stiff for any slip_speed
/// (stiction_length 1e-6 m) is advised a longer stiction_length, which, taken, is accepted.
#[test]
fn issue24_a_step_too_large_for_the_slip_is_refused() {
    assert!(scenario("traction = \"slip\"", "dt = 1e-3").is_ok());
    let m = refused("traction = \"slip\"\nslip_speed = 0.1", "dt = 1e-3", "robot.slip_speed");
    assert!(m.contains("sim.dt") && m.contains("2.785"), "{m}");
    // "raise robot.slip_speed to X m/s or more"
    let advised: f64 =
        m.split("raise robot.slip_speed to ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    assert!((0.1..0.2).contains(&advised), "{m}");
    assert!(scenario(&format!("traction = \"slip\"\nslip_speed = {advised}"), "dt = 1e-3").is_ok(), "{m}");
    let m = refused("traction = \"slip\"\nstiction_length = 1e-6", "dt = 1e-3", "robot.slip_speed");
    let advised: f64 =
        m.split("raise robot.stiction_length to ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    assert!(advised > 1e-6, "{m}");
    assert!(scenario(&format!("traction = \"slip\"\nstiction_length = {advised}"), "dt = 1e-3").is_ok(), "{m}");
}

/// A slip run logs its contact; the slip velocity is the wheel's rim speed minus the
/// ground speed under it, replayed by hand from the logged columns.
#[test]
fn issue24_slip_runs_log_the_contact() {
    let sc = scenario("traction = \"slip\"\nfriction_coefficient = 0.3", "").unwrap();
    assert!(sc.setup().slips());
    let (r, big_r) = (sc.setup().robot.params().wheel_radius, sc.setup().robot.params().half_track);
    let mut worst: f64 = 0.0;
    let mut most_slip: f64 = 0.0;
    let mut n = 0;
    sc.run(0, |s| {
        let c = contact_values(s);
        assert_eq!(c.len(), CONTACT_COLUMNS.len());
        let by_hand = r * s.wheel_speeds.right - (s.state.v + big_r * s.state.omega);
        worst = worst.max((c[0] - by_hand).abs());
        most_slip = most_slip.max(c[0].abs());
        n += 1;
    })
    .unwrap();
    assert!(n > 100);
    assert!(worst < 1e-12, "slip_r off by {worst}");
    assert!(most_slip > 0.1, "the wheels hardly slipped on mu 0.3: {most_slip} m/s");
    assert!(!scenario("", "").unwrap().setup().slips());
}

/// Issue 38 (items 2 and 7): a gentle 1 m circle at 0.3 m/s (`examples/tracking/circle.toml`'s
/// first run, Kanayama's law) on `examples/slip.toml`'s robot on asphalt, on odometry
/// with ideal encoders. The tyres carry the turn's 0.45 N of centripetal force against
/// 11 N of grip: the contacts stick, so the robot does not slide sideways (after the
/// first second |v_y| stays below 1e-4 m/s, a sideslip under 0.02 deg: only the
/// deflections' changes as the forces change, 6.7e-6 m/s measured) and the odometry,
/// which cannot see a slip, drifts
/// under 1 % of the 12 m travelled (0.16 % measured, the controller's own excursions).
/// The regularised law before slipped to carry any force: |v_y| up to 7.6e-3 m/s (a
/// sideslip of 1.5 deg) and 15.6 % of drift on this run (1.3 deg and 12.65 % in issue
/// 38's check).
#[test]
fn issue38_a_gentle_circle_does_not_slip() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let circle = std::fs::read_to_string(root.join("examples/tracking/circle.toml")).unwrap();
    let first_run_only = &circle[..circle.find("[[run]]\nlabel = \"20 cm outside").unwrap()];
    let text = format!(
        "{first_run_only}\n[robot]\ntraction = \"slip\"\nfriction_coefficient = 0.8\ncaster_offset = 0.35\n\
         com_height = 0.1\n\n[sensor]\npose = \"odometry\"\n"
    );
    let sc = Scenario::from_toml_str(&text, "circle-slip").unwrap();
    assert!(sc.setup().slips());
    let mut lateral: f64 = 0.0;
    let r = sc
        .run(0, |s| {
            if s.t > 1.0 {
                lateral = lateral.max(contact_values(s)[2].abs());
            }
        })
        .unwrap();
    let drift = r.odometry_drift.expect("a run on odometry reports its drift");
    let share = drift.drift_m / drift.distance_m;
    eprintln!(
        "circle on slip: |v_y| at most {lateral:.2e} m/s after 1 s; odometry drift {:.4} m, {:.2} % of {:.2} m",
        drift.drift_m,
        100.0 * share,
        drift.distance_m
    );
    assert!(drift.distance_m > 10.0, "{drift:?}");
    assert!(lateral < 1e-4, "slid sideways at {lateral} m/s");
    assert!(share < 0.01, "odometry drift {share}");
}
