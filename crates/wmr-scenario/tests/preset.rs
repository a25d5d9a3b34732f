//! Robots in files (issue 27): `[robot] from = "robots/NAME.toml"` or a built-in preset
//! name brings a robot and its drive; keys beside it override; `check` (the resolved
//! TOML) says where each value came from; a mistyped key gets a "did you mean".

use std::path::{Path, PathBuf};

use wmr_core::Drive;
use wmr_scenario::{AllowedBy, FileAccess, Scenario};

const RUN: &str = "[sim]\nt_end = 1.0\n[[run]]\ngoal = { x = 1.0, y = 1.0 }\n";

fn robots() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../robots")
}

/// Each preset file's `[robot]` and `[drive]` values, read with a TOML parser of its own.
fn preset_values(name: &str) -> toml::Table {
    let text = std::fs::read_to_string(robots().join(format!("{name}.toml"))).unwrap();
    text.parse::<toml::Table>().unwrap()
}

#[test]
fn a_preset_file_gives_its_robot_and_drive_and_keys_beside_from_override_it() {
    let dir = tempfile::tempdir().unwrap();
    let text = "[robot]\nfrom = \"robots/turtlebot3_burger.toml\"\nmass = 1.2\n".to_owned() + RUN;
    std::fs::create_dir(dir.path().join("robots")).unwrap();
    std::fs::copy(robots().join("turtlebot3_burger.toml"), dir.path().join("robots/turtlebot3_burger.toml")).unwrap();
    let file = dir.path().join("tb.toml");
    std::fs::write(&file, &text).unwrap();
    let s = Scenario::from_path(&file).unwrap();
    let want = preset_values("turtlebot3_burger");
    let r = s.robot().params();
    assert_eq!(r.mass, 1.2, "the key beside from wins");
    assert_eq!(r.wheel_radius, want["robot"]["wheel_radius"].as_float().unwrap());
    assert_eq!(r.half_track, want["robot"]["half_track"].as_float().unwrap());
    assert_eq!(r.gear_ratio, want["robot"]["gear_ratio"].as_float().unwrap());
    match s.drive() {
        Drive::DcMotor(m) => {
            assert_eq!(m.params().voltage_max, want["drive"]["voltage_max"].as_float().unwrap());
            assert_eq!(m.params().armature_resistance, want["drive"]["armature_resistance"].as_float().unwrap());
        }
        other => panic!("the Burger's drive is a DC motor, got {other:?}"),
    }
    // Provenance, as `check` prints it.
    let toml = s.to_toml();
    let line = |key: &str| toml.lines().find(|l| l.starts_with(&format!("{key} = "))).unwrap().to_owned();
    assert!(line("mass").ends_with("# scenario"), "{}", line("mass"));
    assert!(line("wheel_radius").ends_with("# robots/turtlebot3_burger.toml"), "{}", line("wheel_radius"));
    assert!(line("voltage_max").ends_with("# robots/turtlebot3_burger.toml"), "{}", line("voltage_max"));
    assert!(line("coulomb_speed").ends_with("# default"), "{}", line("coulomb_speed"));
    // What check prints reads back to the same scenario.
    assert_eq!(Scenario::from_toml_str(&toml, "tb").unwrap().robot(), s.robot());
}

#[test]
fn built_in_names_are_the_files_of_robots() {
    for name in ["paper", "turtlebot3_burger", "turtlebot3_waffle"] {
        let by_name = Scenario::from_toml_str(&format!("[robot]\nfrom = \"{name}\"\n{RUN}"), "s").unwrap();
        let path = robots().join(format!("{name}.toml"));
        let text = format!("[robot]\nfrom = \"{}\"\n{RUN}", path.display());
        // robots/ is outside the current folder (the crate's): allowed by name.
        let access = FileAccess::under(&[robots()], AllowedBy::Library).unwrap();
        let by_file = Scenario::from_toml_str_with(&text, "s", Path::new(""), &access).unwrap();
        assert_eq!(by_name.robot(), by_file.robot(), "{name}");
        assert_eq!(by_name.drive(), by_file.drive(), "{name}");
        let want = preset_values(name);
        assert_eq!(by_name.robot().params().mass, want["robot"]["mass"].as_float().unwrap(), "{name}");
    }
    // The paper's preset is wmr's default robot and drive.
    let paper = Scenario::from_toml_str(&format!("[robot]\nfrom = \"paper\"\n{RUN}"), "s").unwrap();
    let plain = Scenario::from_toml_str(RUN, "s").unwrap();
    assert_eq!(paper.robot(), plain.robot());
    assert_eq!(paper.drive(), plain.drive());
}

#[test]
fn a_drive_of_another_kind_replaces_the_presets_drive() {
    let text = format!("[robot]\nfrom = \"turtlebot3_waffle\"\n[drive]\nkind = \"torque\"\n{RUN}");
    let s = Scenario::from_toml_str(&text, "s").unwrap();
    assert!(matches!(s.drive(), Drive::Torque(_)), "{:?}", s.drive());
    // Of the same kind, a drive key overrides the preset's.
    let text = format!("[robot]\nfrom = \"turtlebot3_waffle\"\n[drive]\nvoltage_max = 12.0\n{RUN}");
    let s = Scenario::from_toml_str(&text, "s").unwrap();
    match s.drive() {
        Drive::DcMotor(m) => assert_eq!(m.params().voltage_max, 12.0),
        other => panic!("{other:?}"),
    }
    assert!(s.to_toml().lines().any(|l| l.starts_with("voltage_max = 12.0") && l.ends_with("# scenario")));
}

#[test]
fn a_bad_from_is_named_with_its_line_and_reason() {
    let err = |text: &str| Scenario::from_toml_str(text, "s").unwrap_err();
    let e = err(&format!("name = \"x\"\n[robot]\nfrom = \"turtlebot4\"\n{RUN}"));
    assert_eq!(e.key, "robot.from");
    assert_eq!(e.line, Some(3));
    assert!(e.message.contains("turtlebot3_burger"), "{}", e.message);
    let e = err(&format!("[robot]\nfrom = \"no/such.toml\"\n{RUN}"));
    assert_eq!(e.key, "robot.from");
    assert!(e.message.contains("no/such.toml"), "{}", e.message);
    let e = err(&format!("[robot]\nfrom = 3\n{RUN}"));
    assert!(e.message.contains("expected a string"), "{}", e.message);
    // A preset with a mistyped key names the file and the key.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.toml"), "[robot]\nmas = 2.0\n").unwrap();
    let text = format!("[robot]\nfrom = \"bad.toml\"\n{RUN}");
    let e = Scenario::from_toml_str_in(&text, "s", dir.path()).unwrap_err();
    assert_eq!(e.key, "robot.from");
    assert!(e.message.contains("bad.toml: robot.mas: unknown key; did you mean mass?"), "{}", e.message);
    // A relative path starts at the scenario's folder, not the current one.
    std::fs::write(dir.path().join("ok.toml"), "[robot]\nmass = 2.0\n").unwrap();
    let text = format!("[robot]\nfrom = \"ok.toml\"\n{RUN}");
    assert_eq!(Scenario::from_toml_str_in(&text, "s", dir.path()).unwrap().robot().params().mass, 2.0);
    assert!(Scenario::from_toml_str_in(&text, "s", Path::new("/nonexistent")).is_err());
    // A preset holds the robot's traction keys too (a real robot's tyres), not `from`.
    std::fs::write(dir.path().join("tyres.toml"), "[robot]\nfriction_coefficient = 0.6\n").unwrap();
    let text = format!("[robot]\nfrom = \"tyres.toml\"\n{RUN}");
    Scenario::from_toml_str_in(&text, "s", dir.path()).expect("a preset with a traction key");
    std::fs::write(dir.path().join("nested.toml"), "[robot]\nfrom = \"paper\"\n").unwrap();
    let text = format!("[robot]\nfrom = \"nested.toml\"\n{RUN}");
    let e = Scenario::from_toml_str_in(&text, "s", dir.path()).unwrap_err();
    assert!(e.message.contains("nested.toml: robot.from: unknown key"), "{}", e.message);
}

/// Issue 27: `robot.mas: unknown key; did you mean mass?`.
#[test]
fn regression_27_a_mistyped_key_gets_a_did_you_mean() {
    let err = |text: &str| Scenario::from_toml_str(&format!("{text}\n{RUN}"), "s").unwrap_err();
    let e = err("[robot]\nmas = 5.0");
    assert_eq!(e.key, "robot.mas");
    assert!(e.message.starts_with("unknown key; did you mean mass?"), "{}", e.message);
    let e = err("[robot]\nwheel_raduis = 0.1");
    assert!(e.message.starts_with("unknown key; did you mean wheel_radius?"), "{}", e.message);
    let e = err("[world]\nslope_dge = 2.0");
    assert!(e.message.contains("did you mean slope_deg?"), "{}", e.message);
    // Far from every key: the list, no guess.
    let e = err("[robot]\ncolour = 1.0");
    assert!(!e.message.contains("did you mean"), "{}", e.message);
    assert!(e.message.contains("the keys here are caster_offset, com_height, com_offset"), "{}", e.message);
    // [robot] holds the traction keys and `from` too: a near miss of one is named, and the
    // list has them all.
    let e = err("[robot]
friction_coeficient = 0.8");
    assert!(e.message.starts_with("unknown key; did you mean friction_coefficient?"), "{}", e.message);
    let e = err("[robot]
frmo = \"paper\"");
    assert!(e.message.starts_with("unknown key; did you mean from?"), "{}", e.message);
    for key in ["traction", "slip_speed", "from"] {
        assert!(e.message.contains(key), "{key} not listed: {}", e.message);
    }
}

/// Issue 39 item 3: a scenario says which files it read besides its own text (a preset, the
/// CSV of each file reference, each once), with the key that names each, so that a command
/// can refuse to write over them; a built-in preset is no file.
#[test]
fn a_scenario_lists_the_files_it_read_with_the_key_naming_each() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("robots")).unwrap();
    std::fs::copy(robots().join("paper.toml"), d.join("robots/mine.toml")).unwrap();
    std::fs::write(d.join("ref.csv"), "t,x,y\n0,0,0\n1,0.3,0\n2,0.6,0.1\n").unwrap();
    let text = "[robot]\nfrom = \"robots/mine.toml\"\n[reference]\nkind = \"file\"\npath = \"ref.csv\"\n\
                [controller]\nkind = \"kanayama\"\n[sim]\nt_end = 1.0\n[sweep]\n\
                references = [{ kind = \"file\", path = \"ref.csv\" }, { kind = \"circle\" }]\n\
                random = { n = 1, radius = 0.1 }\n[[run]]\nstart = {}\n";
    let file = d.join("s.toml");
    std::fs::write(&file, text).unwrap();
    let s = Scenario::from_path(&file).unwrap();
    let listed: Vec<(PathBuf, &str)> = s.inputs().iter().map(|f| (f.path.clone(), f.key.as_str())).collect();
    assert_eq!(listed, [(d.join("robots/mine.toml"), "robot.from"), (d.join("ref.csv"), "reference.path")]);
    let built_in = Scenario::from_toml_str_in(&text.replace("robots/mine.toml", "paper"), "s", Path::new(d)).unwrap();
    assert_eq!(built_in.inputs().len(), 1, "{:?}", built_in.inputs());
    let none = Scenario::from_toml_str(RUN, "s").unwrap();
    assert!(none.inputs().is_empty());
}

/// Issue 38, item 6: the Burger's XL430-W250 gears 258.5:1 (its datasheet; 257.4:1 is the
/// 2XL430-W250's), with the DYNAMIXEL's published 1.4 N m / 1.3 A at the wheel
/// unchanged; slip can be switched on for both TurtleBots with one key (a centre of mass
/// with mu h <= |d|); a rolling run of the Burger says once that its wheels ask more of
/// the ground than mu N, with the time and the ratio, and a slipping one does not.
#[test]
fn turtlebot_presets_are_physical_and_rolling_runs_say_when_traction_is_exceeded() {
    let burger = Scenario::from_toml_str(&format!("[robot]\nfrom = \"turtlebot3_burger\"\n{RUN}"), "s").unwrap();
    let gear = burger.robot().params().gear_ratio;
    assert!((1.0 / gear - 258.5).abs() < 1e-3, "{}", 1.0 / gear);
    match burger.drive() {
        Drive::DcMotor(m) => {
            let p = m.params();
            // At the wheel: k_tau / k_t = 1.4 N m / 1.3 A, within the file's 4 digits.
            assert!((p.torque_constant / gear - 1.4 / 1.3).abs() < 2e-4, "{}", p.torque_constant / gear);
            // No-load speed at the wheel at 11.1 V: 57 rev/min.
            let no_load = p.voltage_max * gear / p.back_emf_constant;
            assert!((no_load - 57.0 * std::f64::consts::TAU / 60.0).abs() < 1e-3, "{no_load}");
        }
        other => panic!("{other:?}"),
    }
    for name in ["turtlebot3_burger", "turtlebot3_waffle"] {
        // The light robots' stiff tyres need a finer step than the default 1 ms (the
        // error of the default says so, naming sim.dt).
        let text =
            format!("[robot]\nfrom = \"{name}\"\ntraction = \"slip\"\n{}", RUN.replace("[sim]", "[sim]\ndt = 0.0001"));
        let s = Scenario::from_toml_str(&text, name).unwrap_or_else(|e| panic!("{name}: {e}"));
        let r = s.run(0, |_| {}).unwrap();
        assert!(!r.summary_line().contains("traction exceeded"), "{}", r.summary_line());
    }
    // The Burger's servos kick at the first control tick (Lyapunov, derived gains): 4.8
    // times what a tyre holds, said once.
    let run = "[sim]\nt_end = 1.0\n[[run]]\ngoal = { x = 1.0, y = 1.0, theta_deg = 120.0 }\n";
    let burger = "[robot]\nfrom = \"turtlebot3_burger\"\n[controller]\nkind = \"lyapunov\"\n";
    let r = Scenario::from_toml_str(&format!("{burger}{run}"), "tb").unwrap().run(0, |_| {}).unwrap();
    let line = r.summary_line();
    assert_eq!(line.matches("; traction exceeded: from t = ").count(), 1, "{line}");
    // wmr's own robot says nothing unless its tyre, caster or G's height is given: its
    // defaults describe no real robot (the paper's figures keep their summary lines).
    let r = Scenario::from_toml_str(&format!("[controller]\nkind = \"lyapunov\"\n{run}"), "p").unwrap();
    assert!(!r.run(0, |_| {}).unwrap().summary_line().contains("traction"));
    let given = format!("[robot]\ncaster_offset = 0.35\n[controller]\nkind = \"lyapunov\"\n{run}");
    let r = Scenario::from_toml_str(&given, "p").unwrap().run(0, |_| {}).unwrap();
    assert!(r.summary_line().contains("traction exceeded"), "{}", r.summary_line());
    let (t0, r0) = r.traction.first.expect("traction exceeded");
    let (_, peak) = r.traction.peak.unwrap();
    assert!(t0 < 0.1 && r0 > 1.0 && peak >= r0, "{:?}", r.traction);
}
