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
