//! Issue 42, docking outcomes: `[sim] xy_goal_tolerance` and `yaw_goal_tolerance_deg`
//! judge every run towards a goal docked or not, on its final state, on the exact and the
//! fast path alike, and change nothing else of the run.

use wmr_scenario::{Scenario, ScenarioError};

/// The repaired paper law on a robot with Coulomb friction from (0.6, -0.4, 50 deg): it
/// ends a few mm and a fraction of a degree off the goal, not on it.
const RUN: &str = r#"
[robot]
coulomb_friction = 0.05
[controller]
kind = "paper_bidirectional"
[sim]
t_end = 30.0
[[run]]
start = { x = 0.6, y = -0.4, theta_deg = 50.0 }
goal = {}
"#;

fn with_sim(keys: &str) -> Result<Scenario, ScenarioError> {
    Scenario::from_toml_str(&RUN.replace("[sim]\n", &format!("[sim]\n{keys}\n")), "docking")
}

fn outcome(keys: &str) -> wmr_core::Outcome<f64> {
    with_sim(keys).unwrap().run(0, |_| {}).unwrap().outcome
}

#[test]
fn a_run_just_inside_each_tolerance_is_docked_and_just_outside_is_not() {
    let base = outcome("");
    let (dl, th_deg) = (base.final_dl, base.final_heading_error.to_degrees().abs());
    assert!(dl > 1e-5 && th_deg > 1e-5, "the run must end off the goal to test its bounds: {dl} m, {th_deg} deg");
    // The tolerances 0.1 % above and below the run's own final errors.
    let (up, down) = (1.001, 0.999);
    let judged = |xy: f64, yaw: f64| {
        let o = outcome(&format!("xy_goal_tolerance = {xy:?}\nyaw_goal_tolerance_deg = {yaw:?}"));
        // The tolerances judge the run; they never change it.
        assert_eq!((o.final_pose, o.t_final, o.termination), (base.final_pose, base.t_final, base.termination));
        assert_eq!((o.xy_goal_tolerance, o.yaw_goal_tolerance), (xy, yaw.to_radians()));
        o.docked()
    };
    assert!(judged(dl * up, th_deg * up), "inside both");
    assert!(!judged(dl * down, th_deg * up), "just outside xy_goal_tolerance");
    assert!(!judged(dl * up, th_deg * down), "just outside yaw_goal_tolerance_deg");
    assert!(!judged(dl * down, th_deg * down));
}

#[test]
fn the_fast_path_judges_with_the_same_tolerances() {
    let text = |keys: &str| {
        format!(
            "[robot]\ncoulomb_friction = 0.05\n[sim]\nt_end = 20.0\n{keys}\n[sweep]\ncontrollers = [{{ kind = \"paper_bidirectional\" }}, \
             {{ kind = \"lyapunov\" }}]\nrandom = {{ n = 16, seed = 4, radius = 1.0 }}\n"
        )
    };
    let keys = "xy_goal_tolerance = 0.004\nyaw_goal_tolerance_deg = 0.3";
    let s = Scenario::from_toml_str(&text(keys), "docking").unwrap();
    let sw = s.sweep().unwrap();
    let exact = sw.run(s.sim(), &|| {}).unwrap();
    let fast = sw.run_fast(s.sim(), &|| {}).unwrap();
    for (e, f) in exact.iter().zip(&fast) {
        assert_eq!((e.outcome.xy_goal_tolerance, e.outcome.yaw_goal_tolerance), (0.004, 0.3f64.to_radians()));
        assert_eq!((f.outcome.xy_goal_tolerance, f.outcome.yaw_goal_tolerance), (0.004, 0.3f64.to_radians()));
    }
    // Some runs dock and some do not at these tolerances (the test means something).
    let docked = exact.iter().filter(|o| o.outcome.docked()).count();
    assert!(0 < docked && docked < exact.len(), "{docked} of {} docked", exact.len());
    // The resolved scenario's text keeps them.
    let again = Scenario::from_toml_str(&s.to_toml(), "again").unwrap();
    assert_eq!((again.sim().xy_goal_tolerance(), again.sim().yaw_goal_tolerance_deg()), (0.004, 0.3));
}

#[test]
fn bad_tolerances_are_refused_naming_the_key() {
    for (keys, key) in [
        ("xy_goal_tolerance = 0.0", "sim.xy_goal_tolerance"),
        ("xy_goal_tolerance = -0.01", "sim.xy_goal_tolerance"),
        ("xy_goal_tolerance = inf", "sim.xy_goal_tolerance"),
        ("yaw_goal_tolerance_deg = nan", "sim.yaw_goal_tolerance_deg"),
        ("yaw_goal_tolerance_deg = 0.0", "sim.yaw_goal_tolerance_deg"),
        ("yaw_goal_tolerance_deg = 180.5", "sim.yaw_goal_tolerance_deg"),
    ] {
        let e = with_sim(keys).unwrap_err();
        assert_eq!(e.key, key, "{keys}: {e}");
    }
    // The defaults: 1 cm and 1 deg.
    let s = with_sim("").unwrap();
    assert_eq!((s.sim().xy_goal_tolerance(), s.sim().yaw_goal_tolerance_deg()), (0.01, 1.0));
}
