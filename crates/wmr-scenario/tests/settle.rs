//! `[sim] stop_when_settled`: a run stopped by the settle rule (`wmr_core::settle`) has
//! the status and time to 1 cm of the full-length run, and its final errors within
//! 1 um and 1e-4 deg, on the starts of `examples/compare.toml` (all four laws).
//!
//! By default a subset of its 1,000 starts that holds every outcome of the paper law
//! (converged 0, 1; unsettled 15, 16; diverged 27, 29) plus every 100th; all of them with
//! `WMR_LONG_TESTS=1 cargo test --release -p wmr-scenario --test integration settle::` (about 2 min).

use wmr_core::{Outcome, Status, Termination};
use wmr_scenario::{Scenario, SimSpec};

const COMPARE: &str = include_str!("../../../examples/compare.toml");

fn full_and_settled(law: usize, start: usize, s: &Scenario) -> (Outcome<f64>, Outcome<f64>) {
    let sweep = s.sweep().expect("a sweep");
    let full: SimSpec = s.sim().with_stop_when_settled(false);
    let settled = s.sim().with_stop_when_settled(true);
    (sweep.run_one(&full, law, start, |_| {}).unwrap(), sweep.run_one(&settled, law, start, |_| {}).unwrap())
}

#[test]
fn settled_runs_equal_full_length_runs_on_compare_toml() {
    let s = Scenario::from_toml_str(COMPARE, "compare").unwrap();
    let n_starts = s.sweep().unwrap().starts.len();
    assert_eq!(n_starts, 1000);
    let starts: Vec<usize> = if std::env::var_os("WMR_LONG_TESTS").is_some() {
        (0..n_starts).collect()
    } else {
        [0, 1, 15, 16, 27, 29].into_iter().chain((100..n_starts).step_by(100)).collect()
    };
    let laws = s.sweep().unwrap().laws.len();
    let jobs: Vec<(usize, usize)> = (0..laws).flat_map(|l| starts.iter().map(move |&i| (l, i))).collect();
    let pairs = wmr_scenario::executor::map_ordered(jobs.len(), |k| full_and_settled(jobs[k].0, jobs[k].1, &s));
    let mut stopped = 0;
    let mut statuses = [0; 3];
    for (&(law, start), (full, early)) in jobs.iter().zip(&pairs) {
        let at = format!("law {law}, start {start}");
        assert_eq!(early.status(), full.status(), "{at}");
        assert_eq!(early.time_to_arrival, full.time_to_arrival, "{at}");
        assert!((early.final_dl - full.final_dl).abs() < 1e-6, "{at}: dl {} vs {}", early.final_dl, full.final_dl);
        let dh = (early.final_heading_error - full.final_heading_error).abs().to_degrees();
        assert!(dh < 1e-4, "{at}: heading differs by {dh} deg");
        if early.termination == Termination::Settled {
            stopped += 1;
            assert_eq!(full.status(), Status::Converged, "{at}");
            assert!(early.t_final < full.t_final, "{at}");
        } else {
            assert_eq!(early.t_final, full.t_final, "{at}");
        }
        statuses[Status::ALL.iter().position(|&st| st == full.status()).unwrap()] += 1;
    }
    // Every outcome is exercised, and the rule does fire.
    assert!(statuses.iter().all(|&n| n > 0), "statuses {statuses:?}");
    let converged = statuses[0];
    assert!(stopped * 10 >= converged * 9, "only {stopped} of {converged} converged runs stopped early");
}

/// The rule never fires with a noisy sensor, nor for a law that never holds.
#[test]
fn noisy_sensors_and_laws_without_a_hold_run_to_the_end() {
    let base =
        "[sim]\nt_end = 60.0\nstop_when_settled = true\n[[run]]\ngoal = { x = 1.0, y = 1.0, theta_deg = 120.0 }\n";
    let quiet = Scenario::from_toml_str(base, "quiet").unwrap();
    assert_eq!(quiet.run(0, |_| {}).unwrap().outcome.termination, Termination::Settled);
    let noisy = format!("[sensor]\nposition_noise = 1e-9\n{base}");
    let noisy = Scenario::from_toml_str(&noisy, "noisy").unwrap();
    assert_eq!(noisy.run(0, |_| {}).unwrap().outcome.termination, Termination::Completed);
    let no_hold = format!("[controller]\nhold_radius = 0.0\n{base}");
    let no_hold = Scenario::from_toml_str(&no_hold, "no_hold").unwrap();
    assert_eq!(no_hold.run(0, |_| {}).unwrap().outcome.termination, Termination::Completed);
}

/// Issue 24: with `servo_ki` > 0 on a slope the held robot still turns while the servos'
/// integrators build up the holding torque; the settle rule waits for that turn
/// (`wmr_core::settle`), so a settled run reports the full-length run's final heading
/// within 0.05 deg (before: up to 0.17 deg here, start 25 of the bidirectional law).
#[test]
fn issue_24_settled_runs_keep_the_heading_with_servo_integrators_on_a_slope() {
    let toml = r#"
[robot]
mass = 5.0
[world]
slope_deg = 10.0
slope_direction_deg = 0.0
[sim]
t_end = 60.0
log_dt = 0.01
stop_when_settled = true
[sweep]
goal = { x = 0.0, y = 0.0, theta_deg = 0.0 }
controllers = [{ kind = "paper", servo_ki = 0.5 }, { kind = "paper_bidirectional", servo_ki = 0.5 }]
random = { n = 40, seed = 2026, radius = 2.0, min_radius = 0.1 }
"#;
    let s = Scenario::from_toml_str(toml, "slope").unwrap();
    let jobs: Vec<(usize, usize)> = (0..2).flat_map(|l| (0..40).map(move |i| (l, i))).collect();
    let pairs = wmr_scenario::executor::map_ordered(jobs.len(), |k| full_and_settled(jobs[k].0, jobs[k].1, &s));
    let mut stopped = 0;
    let mut worst: f64 = 0.0;
    for (&(law, start), (full, early)) in jobs.iter().zip(&pairs) {
        let at = format!("law {law}, start {start}");
        assert_eq!(early.status(), full.status(), "{at}");
        if full.status() != Status::Converged {
            continue;
        }
        let dh = (early.final_heading_error - full.final_heading_error).abs().to_degrees();
        worst = worst.max(dh);
        assert!(dh < 0.05, "{at}: heading differs by {dh} deg");
        stopped += usize::from(early.termination == Termination::Settled);
    }
    // The rule still fires (it is not simply off).
    assert!(stopped > 0, "no run stopped early (worst {worst} deg)");
    eprintln!("{stopped} runs stopped early; worst heading difference {worst} deg");
}
