//! `[controller.observer] kind = "disturbance"` in a scenario (wmr issue 42, item 2): read
//! as a table or inline (a sweep's `controllers`), off by default, written back by
//! `wmr-cli check`, bad keys refused naming them, and a run with it differs from one
//! without only where there is a disturbance to reject.

use wmr_scenario::Scenario;

const BASE: &str = "[sim]\nt_end = 3.0\n[[run]]\ngoal = { x = 0.5, y = 0.2, theta_deg = 30.0 }\n";

#[test]
fn the_observer_is_read_off_by_default_and_written_back() {
    let plain = Scenario::from_toml_str(BASE, "x").unwrap();
    assert_eq!(plain.controller().observer, None, "off by default");
    let s = Scenario::from_toml_str(
        &format!("[controller.observer]\nkind = \"disturbance\"\nbandwidth = 80.0\n{BASE}"),
        "x",
    )
    .unwrap();
    assert_eq!(s.controller().observer.map(|o| o.bandwidth), Some(80.0));
    // Inline, and `kind` defaults to "disturbance"; bandwidth to 50 rad/s.
    let inline = Scenario::from_toml_str(&format!("[controller]\nobserver = {{}}\n{BASE}"), "x").unwrap();
    assert_eq!(inline.controller().observer.map(|o| o.bandwidth), Some(50.0));
    // `wmr-cli check`'s resolved scenario reads back to the same one.
    assert_eq!(Scenario::from_toml_str(&s.to_toml(), "x").unwrap(), s);
    assert_eq!(Scenario::from_toml_str(&plain.to_toml(), "x").unwrap(), plain);
}

/// With the observer, a run on a robot pushed while it stabilizes ends elsewhere than the
/// same run without; each run's samples carry the estimate (N m per wheel) only when on.
#[test]
fn the_estimate_reaches_the_samples() {
    let push = "[[world.push]]\nt = 0.5\nduration = 1.0\nforce = { x = 6.0 }\ntorque = 0.4\n";
    let on = Scenario::from_toml_str(&format!("{push}[controller.observer]\n{BASE}"), "x").unwrap();
    let off = Scenario::from_toml_str(&format!("{push}{BASE}"), "x").unwrap();
    let mut estimates = Vec::new();
    let a = on.run(0, |s| estimates.push(s.disturbance)).unwrap();
    let mut none = true;
    let b = off.run(0, |s| none &= s.disturbance.is_none()).unwrap();
    assert!(none, "no estimate without the observer");
    assert!(estimates.iter().all(Option::is_some), "every sample carries the estimate");
    assert_ne!(a.outcome.final_dl, b.outcome.final_dl);
    // While pushed the estimate is a forward push: both wheels' estimates positive.
    let mid = estimates[estimates.len() / 3].unwrap();
    assert!(mid.right > 0.1 && mid.left > 0.1, "{mid:?}");
}

#[test]
fn bad_observer_keys_name_the_key() {
    let cases: &[(&str, &str)] = &[
        ("[controller.observer]\nbandwidth = -1.0\n", "controller.observer.bandwidth"),
        ("[controller.observer]\nbandwidth = 0.0\n", "controller.observer.bandwidth"),
        ("[controller.observer]\nbandwidth = nan\n", "controller.observer.bandwidth"),
        ("[controller.observer]\nbandwidth = \"fast\"\n", "controller.observer.bandwidth"),
        ("[controller.observer]\nkind = \"eso\"\n", "controller.observer.kind"),
        ("[controller.observer]\ngain = 3.0\n", "controller.observer.gain"),
        ("[controller]\nobserver = 3.0\n", "controller.observer"),
    ];
    for (text, key) in cases {
        let e = Scenario::from_toml_str(&format!("{text}{BASE}"), "x").unwrap_err();
        assert_eq!(&e.key, key, "{text:?}: {e}");
        assert!(!e.to_string().contains('\n'), "one line: {e}");
    }
}
