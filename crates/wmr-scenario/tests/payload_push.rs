//! `[world.payload]` and `[[world.push]]` in a scenario (wmr issue 42): in the plant only,
//! bad input refused naming the key.

use wmr_scenario::Scenario;

const BASE: &str = "[sim]\nt_end = 4.0\n[[run]]\ngoal = { x = 0.5, y = 0.2, theta_deg = 30.0 }\n";

/// The payload goes into the plant's robot and not into the controller's model.
#[test]
fn the_payload_is_the_plants_alone() {
    let s = Scenario::from_toml_str(&format!("[world.payload]\nmass = 1.5\nx = 0.1\ny = 0.05\n{BASE}"), "x").unwrap();
    let setup = s.setup();
    assert_eq!(setup.model.params().mass, 5.0, "the controller believes the robot it was given");
    assert_eq!(setup.truth.params().mass, 6.5);
    assert!((setup.truth.com_lateral() - 1.5 * 0.05 / 6.5).abs() < 1e-15);
    let plant = setup.plant(wmr_core::Pose2::default()).unwrap();
    assert_eq!(plant.robot().params().mass, 6.5);
    // The runs differ from the same scenario without it.
    let plain = Scenario::from_toml_str(BASE, "x").unwrap();
    let (a, b) = (s.run(0, |_| {}).unwrap(), plain.run(0, |_| {}).unwrap());
    assert_ne!(a.outcome.final_dl, b.outcome.final_dl);
    // Dotted keys in [world] are the same table.
    let dotted = Scenario::from_toml_str(
        &format!("[world]\npayload.mass = 1.5\npayload.x = 0.1\npayload.y = 0.05\n{BASE}"),
        "x",
    )
    .unwrap();
    assert_eq!(dotted.setup().truth, setup.truth);
}

/// The pushes reach the plant; a run with one differs from one without.
#[test]
fn pushes_reach_the_plant() {
    let text =
        format!("[[world.push]]\nt = 0.5\nduration = 0.2\nforce = {{ x = 20.0, y = 5.0 }}\ntorque = 1.0\n{BASE}");
    let s = Scenario::from_toml_str(&text, "x").unwrap();
    assert_eq!(s.setup().pushes.as_slice().len(), 1);
    assert_eq!(s.setup().pushes.as_slice()[0].force_y, 5.0);
    let plain = Scenario::from_toml_str(BASE, "x").unwrap();
    let (a, b) = (s.run(0, |_| {}).unwrap(), plain.run(0, |_| {}).unwrap());
    assert_ne!(a.outcome.final_dl, b.outcome.final_dl);
}

#[test]
fn bad_payloads_and_pushes_name_the_key() {
    let cases: &[(&str, &str)] = &[
        ("[world.payload]\nmass = -1.0\n", "world.payload.mass"),
        ("[world.payload]\nmass = nan\n", "world.payload.mass"),
        ("[world.payload]\nmass = 1.0\ny = nan\n", "world.payload.y"),
        ("[world.payload]\nmass = 1.0\nz = 0.1\n", "world.payload.z"),
        ("[world]\npayload = 3.0\n", "world.payload"),
        ("[robot]\ntraction = \"slip\"\n[world.payload]\nmass = 1.0\ny = 0.1\n", "world.payload.y"),
        ("[[world.push]]\nt = 1.0\nduration = -0.1\n", "world.push[0].duration"),
        ("[[world.push]]\nt = 1.0\nduration = 0.1\n[[world.push]]\nt = nan\nduration = 0.1\n", "world.push[1].t"),
        ("[[world.push]]\nt = 1.0\nduration = 0.1\nforce = { x = nan }\n", "world.push[0].force.x"),
        ("[[world.push]]\nt = 1.0\nduration = 0.1\nforce = { z = 1.0 }\n", "world.push[0].force.z"),
        ("[[world.push]]\nt = 1.0\nduration = 0.1\ntorque = inf\n", "world.push[0].torque"),
        ("[[world.push]]\nduration = 0.1\n", "world.push[0].t"),
        ("[world]\npush = 1.0\n", "world.push"),
        ("[world.payload]\nmass = 1.0\nt = -1.0\n", "world.payload.t"),
        ("[world.payload]\nmass = 1.0\nt = inf\n", "world.payload.t"),
        ("[robot]\ntraction = \"slip\"\n[world.payload]\nmass = 1.0\nt = 2.0\n", "world.payload.t"),
    ];
    for (text, key) in cases {
        let e = Scenario::from_toml_str(&format!("{text}{BASE}"), "x").unwrap_err();
        assert_eq!(&e.key, key, "{text:?}: {e}");
        assert!(!e.to_string().contains('\n'), "one line: {e}");
    }
    // Overlapping pushes are allowed.
    let two = "[[world.push]]\nt = 1.0\nduration = 0.5\n[[world.push]]\nt = 1.2\nduration = 0.5\n";
    assert!(Scenario::from_toml_str(&format!("{two}{BASE}"), "x").is_ok());
}

/// The plant's robot under a payload, against the rigid-body formulas worked by hand.
/// The paper's robot (m = 5 kg, d = 0.25 m, I_p = 0.005 kg m^2, r = 0.1 m, R = 0.2 m,
/// I_m = 0.002 kg m^2) carrying M = 2 kg at (x, y) = (-0.1, 0.07) m:
///
/// ```text
/// m' = 7 kg
/// a  = (5 * 0.25 + 2 * -0.1) / 7 = 0.15 m          b = 2 * 0.07 / 7 = 0.02 m
/// I' = 0.005 + 5 (0.1^2 + 0.02^2) + 2 (0.25^2 + 0.05^2) = 0.187 kg m^2      (about G')
/// I_C = 0.005 + 5 * 0.25^2 + 2 (0.1^2 + 0.07^2) = 0.3473 kg m^2             (about C)
/// M_11 = 7 + 2 * 0.002 / 0.01 = 7.4 kg,   M_22 = 0.3473 + 2 * 0.04 * 0.002 / 0.01 = 0.3633 kg m^2
/// M_12 = -m' b = -0.14 kg m
/// ```
#[test]
fn a_payload_changes_mass_and_inertia_by_the_parallel_axis_theorem() {
    let text = format!("[world.payload]\nmass = 2.0\nx = -0.1\ny = 0.07\n{BASE}");
    let s = Scenario::from_toml_str(&text, "x").unwrap();
    let truth = s.setup().truth;
    let close = |got: f64, want: f64, what: &str| assert!((got - want).abs() < 1e-12, "{what}: {got} vs {want}");
    close(truth.params().mass, 7.0, "m'");
    close(truth.params().com_offset, 0.15, "a");
    close(truth.com_lateral(), 0.02, "b");
    close(truth.params().platform_inertia, 0.187, "I' about G'");
    let (m11, m22) = truth.reduced_inertia();
    close(m11, 7.4, "M_11");
    close(m22, 0.3633, "M_22");
    close(truth.mass_coupling(), -0.14, "M_12");
    // The controller's model is the robot without it.
    assert_eq!(s.setup().model.reduced_inertia(), wmr_core::Robot::<f64>::paper().reduced_inertia());
    // A payload at C adds to the mass only: M_22 (the inertia about C) is unchanged.
    let at_c = Scenario::from_toml_str(&format!("[world.payload]\nmass = 2.0\n{BASE}"), "x").unwrap();
    let (m11, m22) = at_c.setup().truth.reduced_inertia();
    close(m11, 7.4, "M_11 (payload at C)");
    close(m22, wmr_core::Robot::<f64>::paper().reduced_inertia().1, "M_22 (payload at C)");
    assert_eq!(at_c.setup().truth.com_lateral(), 0.0);
    // `wmr-cli check`'s resolved scenario reads back to the same one.
    assert_eq!(Scenario::from_toml_str(&s.to_toml(), "x").unwrap(), s);
}

/// A push read from the scenario, on the scenario's plant with no drive torque and no
/// friction (a free rolling robot, G at C so the forward and yaw equations are
/// independent): the momentum M_11 v changes by F_x T and the angular momentum
/// M_22 omega by tau T (T the duration; the window off the step grid).
#[test]
fn a_pushs_impulse_is_the_change_of_momentum_of_a_free_robot() {
    let (fx, tau, t0, dur) = (12.0, 0.9, 0.1007, 0.2345);
    let text = format!(
        "[robot]\ncom_offset = 0.0\n[[world.push]]\nt = {t0}\nduration = {dur}\nforce = {{ x = {fx}, y = 3.0 }}\n\
         torque = {tau}\n{BASE}"
    );
    let s = Scenario::from_toml_str(&text, "x").unwrap();
    let mut plant = s.setup().plant(wmr_core::Pose2::new(0.0, 0.0, 0.4)).unwrap();
    plant.apply(wmr_core::Wheels::new(0.0, 0.0));
    let dt = s.sim().dt();
    for k in 0..(0.5 / dt).round() as usize {
        plant.step(k as f64 * dt, dt).unwrap();
    }
    let (m11, m22) = plant.robot().reduced_inertia();
    let (p, l) = (m11 * plant.state().v, m22 * plant.state().omega);
    assert!((p - fx * dur).abs() < 1e-12, "momentum {p} vs impulse {}", fx * dur);
    assert!((l - tau * dur).abs() < 1e-12, "angular momentum {l} vs angular impulse {}", tau * dur);
    // `wmr-cli check`'s resolved scenario keeps the push.
    assert_eq!(Scenario::from_toml_str(&s.to_toml(), "x").unwrap(), s);
}

/// `[world.payload] t`: the plant is the robot alone until t, then carries the payload;
/// t = 0 (the default) is the payload from the start, the same run to the bit.
#[test]
fn a_payload_put_on_at_a_time_reaches_the_plant_then() {
    let on_at = |t: f64| {
        let text = format!("[world]\nslope_deg = 3.0\n[world.payload]\nmass = 1.5\nx = 0.252\nt = {t}\n{BASE}");
        Scenario::from_toml_str(&text, "x").unwrap()
    };
    let later = on_at(1.0);
    let mut plant = later.setup().plant(wmr_core::Pose2::default()).unwrap();
    assert_eq!(plant.payload_time(), Some(1.0));
    assert_eq!(plant.robot().params().mass, 5.0, "alone before t");
    plant.step(1.0, 1e-3).unwrap();
    assert_eq!(plant.robot().params().mass, 6.5, "carrying from t");
    let from_start = Scenario::from_toml_str(
        &format!("[world]\nslope_deg = 3.0\n[world.payload]\nmass = 1.5\nx = 0.252\n{BASE}"),
        "x",
    )
    .unwrap();
    let (a, b, c) =
        (on_at(0.0).run(0, |_| {}).unwrap(), from_start.run(0, |_| {}).unwrap(), later.run(0, |_| {}).unwrap());
    assert_eq!(a.outcome.final_dl.to_bits(), b.outcome.final_dl.to_bits(), "t = 0 is the default");
    assert_ne!(a.outcome.final_dl, c.outcome.final_dl, "a payload at 1 s is another run");
}
