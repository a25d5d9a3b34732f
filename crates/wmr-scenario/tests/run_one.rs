//! `SweepSpec::run_one` (what `wmr-cli plot` draws for a sweep) is the sweep's own run:
//! the same outcome, bit for bit, for every law and start.

use wmr_scenario::Scenario;

#[test]
fn run_one_is_the_sweeps_run() {
    let text = r#"
[sim]
t_end = 8.0
[sweep]
goal = { x = 0.0, y = 0.0, theta_deg = 30.0 }
random = { n = 3, seed = 4, radius = 1.5 }
"#;
    let sc = Scenario::from_toml_str(text, "run_one").expect("valid scenario");
    let spec = sc.sweep().expect("a sweep");
    let outcomes = spec.run(sc.sim(), &|| {}).expect("runs");
    assert_eq!(outcomes.len(), spec.laws.len() * spec.starts.len());
    for o in &outcomes {
        let mut samples = 0;
        let one = spec.run_one(sc.sim(), o.law, o.start_index, |_| samples += 1).expect("one run");
        assert_eq!(one, o.outcome, "law {} start {}", spec.laws[o.law].0, o.start_index);
        assert_eq!(samples, sc.sim().n_samples(), "every log_dt sample");
    }
    assert!(spec.run_one(sc.sim(), spec.laws.len(), 0, |_| {}).is_err());
}
