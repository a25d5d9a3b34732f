//! `wmr-cli sweep` and `wmr-cli plot` end to end (issue 7).

use std::path::Path;
use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wmr-cli")).args(args).output().expect("wmr-cli starts")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn repo(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(p).display().to_string()
}

/// Polylines with more than `min_points` points: plotted data, not axis ticks or legend swatches.
fn long_polylines(svg: &str, min_points: usize) -> usize {
    let doc = roxmltree::Document::parse(svg).expect("SVG is XML");
    doc.descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .filter(|n| n.attribute("points").is_some_and(|p| p.split_whitespace().count() > min_points))
        .count()
}

#[test]
fn sweep_writes_one_row_per_law_and_start_and_a_table() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("s.toml");
    std::fs::write(
        &file,
        "[sim]\nt_end = 8.0\n[sweep]\ncontrollers = [{ kind = \"paper\" }, { kind = \"lyapunov\" }]\n\
         grid = { x_min = -1.0, x_max = 1.0, nx = 3, y_min = -1.0, y_max = 1.0, ny = 2 }\n",
    )
    .unwrap();
    let csv = dir.path().join("out.csv");
    let plots = dir.path().join("plots");
    let out = run(&["sweep", file.to_str().unwrap(), "-o", csv.to_str().unwrap(), "--plots", plots.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("paper") && stdout.contains("lyapunov"), "{stdout}");
    let body = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = body.lines().collect();
    assert!(lines[0].starts_with("law,start,x0,y0,theta0_deg,status,time_to_1cm_s"));
    assert_eq!(lines.len(), 1 + 2 * 6);
    for law in ["paper", "lyapunov"] {
        let svg = std::fs::read_to_string(plots.join(format!("region-{law}.svg"))).unwrap();
        let doc = roxmltree::Document::parse(&svg).expect("SVG is XML");
        // One triangle per start in its outcome's colour (converged green, unsettled
        // orange; diverged is black like the goal marker, so it is left out of the count),
        // plus one legend triangle for each of the two colours.
        let coloured = ["#009E73", "#E69F00"];
        let triangles = doc
            .descendants()
            .filter(|n| n.has_tag_name("polygon"))
            .filter(|n| n.attribute("fill").is_some_and(|f| coloured.iter().any(|c| f.eq_ignore_ascii_case(c))))
            .count();
        let not_diverged =
            lines[1..].iter().filter(|l| l.starts_with(&format!("{law},")) && !l.contains(",diverged,")).count();
        assert_eq!(triangles, not_diverged + 2, "one marker per start that did not diverge, plus two legend keys");
    }
}

#[test]
fn sweep_without_a_sweep_table_fails_and_run_without_runs_fails() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("out.csv");
    let out = run(&["sweep", &repo("examples/paper/fig7.toml"), "-o", csv.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("[sweep]"));
    assert!(!csv.exists());
    let out = run(&["run", &repo("examples/compare.toml"), "-o", csv.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("[[run]]"));
    assert!(!csv.exists());
}

#[test]
fn plot_writes_the_paper_figures_with_one_path_per_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(&["plot", &repo("examples/paper/fig4.toml"), "-o", dir.path().to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let paths = std::fs::read_to_string(dir.path().join("paths.svg")).unwrap();
    let n_runs = std::fs::read_to_string(repo("examples/paper/fig4.toml")).unwrap().matches("[[run]]").count();
    assert_eq!(long_polylines(&paths, 50), n_runs);
    for i in 0..n_runs {
        let w = std::fs::read_to_string(dir.path().join(format!("run{i}-wheel-speeds.svg"))).unwrap();
        // omega_r and omega_l in the main panel, and again in a detail panel when the
        // start-up dwarfs the rest.
        let n = long_polylines(&w, 50);
        assert!(n == 2 || n == 4, "omega_r and omega_l: {n} curves");
        let e = std::fs::read_to_string(dir.path().join(format!("run{i}-errors.svg"))).unwrap();
        // dl, e_s, e_theta (and the true heading error), in panels and detail panels.
        let n = long_polylines(&e, 50);
        assert!((3..=12).contains(&n), "dl, e_s and e_theta: {n} curves");
    }
}

/// Every axis names its unit (issue 27): a varied key without one is a pure number, and
/// its share curve's axis says so.
#[test]
fn a_share_curve_of_a_key_without_a_unit_says_it_is_dimensionless() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("s.toml");
    std::fs::write(
        &file,
        "[sim]\nt_end = 1.0\n[sweep]\ncontrollers = [{ kind = \"polar\" }]\n\
         grid = { x_min = -1.0, x_max = 1.0, nx = 2, y_min = 0.0, y_max = 0.0, ny = 1 }\n\
         vary = [{ key = \"robot.gear_ratio\", values = [1.0, 2.0] }, { key = \"sensor.latency\", values = [0.0, 0.01] }]\n",
    )
    .unwrap();
    let csv = dir.path().join("out.csv");
    let plots = dir.path().join("plots");
    let out = run(&["sweep", file.to_str().unwrap(), "-o", csv.to_str().unwrap(), "--plots", plots.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let gear = std::fs::read_to_string(plots.join("share-robot-gear_ratio.svg")).unwrap();
    assert!(gear.contains(">robot.gear_ratio (dimensionless)<"), "no unit on the gear ratio's axis");
    let latency = std::fs::read_to_string(plots.join("share-sensor-latency.svg")).unwrap();
    assert!(latency.contains(">sensor.latency (s)<"));
}
