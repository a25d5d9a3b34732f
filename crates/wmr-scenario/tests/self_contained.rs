//! Issue 39, item 8: the resolved scenario (`wmr-cli check`, Python's `scenario_toml`,
//! the text an outside executor ships to its workers) is self-contained: a preset's keys
//! are written out and a file reference's points inlined, so it reads back to the same
//! scenario in another folder, after the scenario's files are gone.

use std::path::PathBuf;

use wmr_scenario::Scenario;

/// A scenario folder with a preset and a reference file, under a fresh temp folder.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("wmr-self-contained-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("robots")).unwrap();
    std::fs::write(dir.join("robots/mine.toml"), "[robot]\nmass = 7.5\nwheel_radius = 0.08\n").unwrap();
    std::fs::write(dir.join("ref.csv"), "t,x,y\n0,0.0,0.0\n1,0.5,0.0\n2,1.0,0.25\n3,1.5,0.75\n").unwrap();
    dir
}

const TRACKING: &str = "[robot]\nfrom = \"robots/mine.toml\"\n[controller]\nkind = \"kanayama\"\n\
[reference]\nkind = \"file\"\npath = \"ref.csv\"\nspeed = 0.25\n[sim]\nt_end = 1.0\n[[run]]\n";

const SWEEP: &str = "[robot]\nfrom = \"robots/mine.toml\"\n[sim]\nt_end = 1.0\n[sweep]\n\
controllers = [{ kind = \"kanayama\" }, { kind = \"pure_pursuit\" }]\n\
references = [{ kind = \"file\", path = \"ref.csv\" }, { kind = \"circle\" }, { kind = \"file\", path = \"ref.csv\", speed = 0.2 }]\n\
random = { n = 3, seed = 2, radius = 0.1, max_heading_deg = 10.0 }\n";

#[test]
fn regression_39_8_resolved_text_runs_without_the_scenarios_files() {
    for (name, text) in [("tracking", TRACKING), ("sweep", SWEEP)] {
        let dir = folder(name);
        std::fs::write(dir.join("s.toml"), text).unwrap();
        let sc = Scenario::from_path(dir.join("s.toml")).unwrap();
        let resolved = sc.to_toml();
        assert!(!resolved.lines().any(|l| l.starts_with("from")), "{resolved}");
        assert!(resolved.contains("points = [[0.0, 0.0], [0.5, 0.0], [1.0, 0.25], [1.5, 0.75]]"), "{resolved}");
        // The files gone, read from the current folder (not the scenario's).
        std::fs::remove_dir_all(&dir).unwrap();
        let again = Scenario::from_toml_str(&resolved, "again").unwrap_or_else(|e| panic!("{e}\n{resolved}"));
        assert_eq!(again, sc, "{resolved}");
        // Written out again: the same text, but for the comments on where values came from.
        let strip = |t: &str| t.lines().map(|l| l.split('#').next().unwrap().trim_end().to_owned()).collect::<Vec<_>>();
        assert_eq!(strip(&again.to_toml()), strip(&resolved));
        if let Some(spec) = sc.sweep() {
            let names: Vec<&str> = spec.tracking.as_ref().unwrap().references.iter().map(|(n, _)| n.as_str()).collect();
            assert_eq!(names, ["file", "circle", "file#2"]);
            assert_eq!(again.sweep(), sc.sweep());
        } else {
            // The same run, bit for bit.
            let (a, b) = (sc.run(0, |_| {}).unwrap(), again.run(0, |_| {}).unwrap());
            assert_eq!(format!("{:?}", a.outcome), format!("{:?}", b.outcome));
        }
    }
}
