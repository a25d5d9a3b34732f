//! Issue 24 (laws that survive saturation): `examples/saturation.toml`, the repaired paper
//! law from starts 5 to 20 m away on a 20 kg robot at the torque limit, converges from
//! every start with none diverged. Before the anti-windup 126 of its 150 starts wandered
//! for the whole 240 s (69 of 150 with `wheel_speed_max = 10`).
//!
//! By default every 10th start of both entries (30 runs); all 300 with
//! `WMR_LONG_TESTS=1 cargo test --release -p wmr-scenario --test integration saturation::`.

use wmr_core::Status;
use wmr_scenario::Scenario;

const SATURATION: &str = include_str!("../../../examples/saturation.toml");

#[test]
fn issue_24_far_starts_at_the_torque_limit_all_converge() {
    let s = Scenario::from_toml_str(SATURATION, "saturation").unwrap();
    let sweep = s.sweep().expect("a sweep");
    assert_eq!(sweep.starts.len(), 150);
    let starts: Vec<usize> =
        if std::env::var_os("WMR_LONG_TESTS").is_some() { (0..150).collect() } else { (0..150).step_by(10).collect() };
    let jobs: Vec<(usize, usize)> = (0..sweep.laws.len()).flat_map(|l| starts.iter().map(move |&i| (l, i))).collect();
    let outcomes =
        wmr_scenario::executor::map_ordered(jobs.len(), |k| sweep.run_one(s.sim(), jobs[k].0, jobs[k].1, |_| {}));
    let mut failed = Vec::new();
    for (&(law, start), outcome) in jobs.iter().zip(outcomes) {
        let o = outcome.unwrap();
        // Every start is 5 to 20 m away: a run that converges did drive there.
        let (x0, y0) = (sweep.starts[start].x, sweep.starts[start].y);
        assert!((5.0..=20.0).contains(&x0.hypot(y0)), "law {law}, start {start}: {x0}, {y0}");
        if o.status() != Status::Converged {
            failed.push((law, start, o.status(), o.final_dl));
        }
    }
    // The issue asks for at least 99 % converged and none diverged; every run converges.
    assert!(failed.is_empty(), "{} of {} runs did not converge: {failed:?}", failed.len(), jobs.len());
}
