//! `[sensor]`, `[world]`, `[controller.model]`, `current_max` and `[sweep] vary` as a
//! user writes them: errors name the key, defaults change nothing, a varied run equals
//! the single run with that value written in the file.

use wmr_scenario::Scenario;

const RUN: &str = "[sim]\nt_end = 2.0\n[[run]]\ngoal = { x = 1.0, y = 1.0, theta_deg = 120.0 }\n";

#[test]
fn bad_real_world_keys_are_named() {
    let cases = [
        ("[sensor]\nposition_noise = -0.01\n", "sensor.position_noise"),
        ("[sensor]\nheading_noise_deg = nan\n", "sensor.heading_noise_deg"),
        ("[sensor]\nlatency = 0.0005\n", "sensor.latency"),
        ("[sensor]\nrate_hz = 3000.0\n", "sensor.rate_hz"),
        ("[sensor]\nrate_hz = 0.0\n", "sensor.rate_hz"),
        ("[sensor]\nrate_hz = 10.0\nlatency = 30.0\n", "sensor.latency"),
        ("[sensor]\nencoder_counts = -5\n", "sensor.encoder_counts"),
        ("[sensor]\nnoise = 1\n", "sensor.noise"),
        ("[world]\nslope_deg = 90.0\n", "world.slope_deg"),
        ("[world]\nslope_direction_deg = inf\n", "world.slope_direction_deg"),
        ("[drive]\nkind = \"dc_motor\"\ncurrent_max = 0.0\n", "drive.current_max"),
        ("[controller.model]\nwheel_radius = -0.1\n", "controller.model.wheel_radius"),
        ("[controller.model]\nwheel_size = 0.1\n", "controller.model.wheel_size"),
        ("[robot]\ncoulomb_friction = 0.1\n", "robot.coulomb_speed"),
        ("[robot]\ncoulomb_friction = 0.05\ncoulomb_speed = 0.1\nstatic_friction = 0.04\n", "robot.static_friction"),
        ("[robot]\nstatic_friction = -0.1\n", "robot.static_friction"),
    ];
    for (table, key) in cases {
        let text = format!("{table}{RUN}");
        let e = Scenario::from_toml_str(&text, "x").unwrap_err();
        assert_eq!(e.key, key, "{text:?}: {e}");
        assert!(e.line.is_some(), "{text:?}: no line in {e}");
        println!("{e}");
    }
}

/// A `[sensor]` with every default and a `[controller.model]` equal to `[robot]` run
/// exactly as without them.
#[test]
fn default_sensor_and_equal_model_change_nothing() {
    let plain = Scenario::from_toml_str(RUN, "x").unwrap();
    let with = Scenario::from_toml_str(
        &format!(
            "[sensor]\nseed = 5\n[controller.model]\nwheel_radius = 0.1\nmass = 5.0\n[world]\nslope_deg = 0.0\n{RUN}"
        ),
        "x",
    )
    .unwrap();
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let ra = plain.run(0, |s| a.push(*s)).unwrap();
    let rb = with.run(0, |s| b.push(*s)).unwrap();
    assert_eq!(a, b);
    assert_eq!(ra.outcome, rb.outcome);
    assert!(a.iter().all(|s| s.measured == s.state.pose()));
}

/// A wrong wheel radius in the model changes the run; the same radius in `[robot]` and
/// the model is the nominal run again.
#[test]
fn the_controller_model_is_what_the_controller_uses() {
    let nominal = Scenario::from_toml_str(RUN, "x").unwrap().run(0, |_| {}).unwrap();
    let wrong = Scenario::from_toml_str(&format!("[controller.model]\nwheel_radius = 0.105\n{RUN}"), "x").unwrap();
    assert_eq!(wrong.setup().model.params().wheel_radius, 0.105);
    assert_eq!(wrong.robot().params().wheel_radius, 0.1);
    assert_ne!(wrong.run(0, |_| {}).unwrap().outcome, nominal.outcome);
    let back = Scenario::from_toml_str(&wrong.to_toml(), "y").unwrap();
    assert_eq!(back.setup(), wrong.setup(), "check writes [controller.model] back");
}

/// Each run of a robustness sweep is the single run with the varied value written into
/// the file, bit for bit (noise included: the run index selects the noise stream).
#[test]
fn a_varied_run_equals_the_single_run_with_that_value() {
    let text = r#"
[sim]
t_end = 1.0
[sensor]
seed = 3
position_noise = 0.002
[sweep]
controllers = [{ kind = "polar" }]
random = { n = 3, seed = 1, radius = 1.0, min_radius = 0.2 }
trials = 2
vary = [
  { key = "sensor.latency", values = [0.0, 0.02] },
  { key = "controller.model.wheel_radius", values = [0.095] },
  { key = "world.slope_deg", uniform = [0.0, 8.0] },
]
"#;
    let sc = Scenario::from_toml_str(text, "x").unwrap();
    let spec = sc.sweep().unwrap();
    assert_eq!(spec.len(), 3 * 2 * 3);
    let outcomes = spec.run(sc.sim(), &|| {}).unwrap();
    assert_eq!(outcomes.len(), 18);
    for o in &outcomes {
        let v = spec.varied_values(o);
        // The single run: the same keys written in the file, this start, this run's noise.
        let s = o.start;
        let single = format!(
            "[sim]\nt_end = 1.0\n[sensor]\nseed = 3\nposition_noise = 0.002\nlatency = {}\n\
             [controller]\nkind = \"polar\"\n[controller.model]\nwheel_radius = {}\n[world]\nslope_deg = {}\n\
             [[run]]\nstart = {{ x = {:?}, y = {:?}, theta = {:?} }}\ngoal = {{}}\n",
            v[0], v[1], v[2], s.x, s.y, s.theta
        );
        let one = Scenario::from_toml_str(&single, "one").unwrap();
        // Run index o.run selects the noise: build that run's loop directly.
        let mut lp = wmr_scenario_single_loop(&one, o.run);
        let outcome = lp.run(one.sim().n_steps(), u32::MAX, |_| {});
        assert_eq!(outcome, o.outcome, "run {} ({v:?})", o.run);
    }
    let slopes: Vec<f64> = outcomes.iter().map(|o| spec.varied_values(o)[2]).collect();
    assert!(slopes.iter().all(|s| (0.0..=8.0).contains(s)));
    assert!(slopes.windows(2).any(|w| w[0] != w[1]), "drawn per run");
}

/// The loop of a one-run scenario with the sensor noise stream of run `run`.
fn wmr_scenario_single_loop(sc: &Scenario, run: u64) -> wmr_scenario::RunLoop {
    let r = &sc.runs()[0];
    let setup = sc.setup();
    let plant = setup.plant(r.start).unwrap();
    let sensor = setup.sensor_for(run).unwrap();
    let goal = wmr_core::AnyReference::Goal(wmr_core::FixedGoal::new(r.goal).unwrap());
    wmr_core::ClosedLoop::with_sensor(plant, sensor, setup.built, goal, sc.sim().dt()).unwrap()
}
