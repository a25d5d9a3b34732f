//! `SweepSpec::run_range` and `Scenario::try_run_as` (the parts an outside executor runs,
//! issue 14) put together are the whole run, bit for bit: with sensor noise (drawn per run
//! index) and `vary` draws (also per run index), where a part that numbered its runs from
//! zero would differ.

use std::ops::ControlFlow;

use wmr_scenario::{RunSpec, Scenario};

const NOISY_SWEEP: &str = r#"
[sim]
t_end = 4.0
[sensor]
position_noise = 0.01
heading_noise_deg = 1.0
seed = 5
[sweep]
goal = { x = 0.0, y = 0.0, theta_deg = 30.0 }
controllers = [{ kind = "paper" }, { kind = "polar" }]
random = { n = 5, seed = 4, radius = 1.5 }
trials = 2
vary = [
  { key = "sensor.latency", values = [0.0, 0.01] },
  { key = "controller.model.wheel_radius", uniform = [0.095, 0.105] },
]
"#;

#[test]
fn sweep_parts_are_the_whole_sweep() {
    let sc = Scenario::from_toml_str(NOISY_SWEEP, "chunk").expect("valid scenario");
    let spec = sc.sweep().expect("a sweep");
    let whole = spec.run(sc.sim(), &|| {}).expect("runs");
    assert_eq!(whole.len(), 2 * 2 * 2 * 5);
    let mut parts = Vec::new();
    for first in (0..spec.len()).step_by(7) {
        let last = (first + 7).min(spec.len());
        let ControlFlow::Continue(part) =
            spec.run_range(sc.sim(), first..last, || ControlFlow::Continue(())).expect("part")
        else {
            panic!("not stopped")
        };
        parts.extend(part);
    }
    assert_eq!(parts, whole);
    // The noise and the draws matter: a part numbered from zero gives other outcomes.
    let ControlFlow::Continue(shifted) = spec.run_range(sc.sim(), 0..7, || ControlFlow::Continue(())).expect("part")
    else {
        panic!("not stopped")
    };
    assert_ne!(
        shifted.iter().map(|o| o.outcome).collect::<Vec<_>>(),
        whole[7..14].iter().map(|o| o.outcome).collect::<Vec<_>>()
    );
    assert!(spec.run_range(sc.sim(), 0..spec.len() + 1, || ControlFlow::Continue(())).is_err());
    let ControlFlow::Break(()) = spec.run_range(sc.sim(), 0..3, || ControlFlow::Break(())).expect("stopped") else {
        panic!("poll said stop")
    };
}

#[test]
fn batch_parts_keep_their_noise_stream() {
    let text = "[sim]\nt_end = 3.0\n[sensor]\nposition_noise = 0.01\nseed = 3\n[[run]]\ngoal = { x = 1.0, y = 0.5 }\n";
    let base = Scenario::from_toml_str(text, "chunk").expect("valid scenario");
    let runs: Vec<RunSpec> = (0..6)
        .map(|i| RunSpec {
            label: format!("start {i}"),
            start: wmr_core::Pose2::new(0.1 * i as f64, 0.0, 0.0),
            goal: base.runs()[0].goal,
        })
        .collect();
    let whole = base.clone().with_runs(runs.clone()).expect("runs");
    let part = base.with_runs(runs[4..].to_vec()).expect("runs");
    let go = || ControlFlow::<()>::Continue(());
    for (j, i) in (4..6).enumerate() {
        let ControlFlow::Continue(a) = whole.try_run(i, |_| go(), go).expect("run") else { panic!() };
        let ControlFlow::Continue(b) = part.try_run_as(j, i as u64, |_| go(), go).expect("run") else { panic!() };
        let ControlFlow::Continue(c) = part.try_run(j, |_| go(), go).expect("run") else { panic!() };
        assert_eq!(a.outcome, b.outcome, "run {i}");
        assert_ne!(a.outcome, c.outcome, "run {i}: the stream is what differs");
    }
}
