//! The SVGs parse as XML and hold one line per run and one marker per sweep start.

use wmr_core::{ClosedLoop, ControllerParams, DriveParams, FixedGoal, Plant, Pose2, Robot, Sample};
use wmr_plot::{CellOutcome, SweepCell, Trace, errors_svg, paths_svg, region_svg, wheel_speeds_svg};

fn run(start: Pose2<f64>, goal: Pose2<f64>, secs: u64) -> Vec<Sample<f64>> {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let ctrl = ControllerParams::paper().build(robot.params(), &drive).unwrap();
    let plant = Plant::new(robot, drive, start).unwrap();
    let mut sim = ClosedLoop::new(plant, ctrl, FixedGoal::new(goal).unwrap(), 1e-3).unwrap();
    let mut out = Vec::new();
    sim.run(secs * 1000, 50, |s| out.push(*s));
    out
}

/// Elements with the given tag.
fn count(doc: &roxmltree::Document<'_>, tag: &str) -> usize {
    doc.descendants().filter(|n| n.has_tag_name(tag)).count()
}

#[test]
fn paths_plot_has_one_polyline_per_run() {
    let goal_a = Pose2::new(1.0, 1.0, 120f64.to_radians());
    let goal_b = Pose2::new(1.0, 1.0, 0.0);
    let a = run(Pose2::default(), goal_a, 20);
    let b = run(Pose2::default(), goal_b, 20);
    let traces = [
        Trace { label: "theta_d = 120 deg", goal: goal_a, samples: &a },
        Trace { label: "theta_d = 0 deg", goal: goal_b, samples: &b },
    ];
    let svg = paths_svg("Fig. 4", &traces).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("valid XML");
    // A path with N samples is one polyline with N points; legend entries are 2-point lines.
    let long_lines: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .filter(|n| n.attribute("points").is_some_and(|p| p.split_whitespace().count() > 10))
        .collect();
    assert_eq!(long_lines.len(), traces.len());
    assert!(svg.contains("theta_d = 120 deg"));
}

#[test]
fn time_plots_have_one_polyline_per_series() {
    let goal = Pose2::new(1.0, 1.0, 120f64.to_radians());
    let s = run(Pose2::default(), goal, 10);
    let trace = Trace { label: "fig7", goal, samples: &s };
    for (svg, n) in [(wheel_speeds_svg("Fig. 8", &trace).unwrap(), 2), (errors_svg("Fig. 9", &trace).unwrap(), 3)] {
        let doc = roxmltree::Document::parse(&svg).expect("valid XML");
        let long = doc
            .descendants()
            .filter(|n| {
                n.has_tag_name("polyline") && n.attribute("points").is_some_and(|p| p.split_whitespace().count() > 10)
            })
            .count();
        assert_eq!(long, n);
        assert!(count(&doc, "text") > 5, "axis labels are text");
    }
}

#[test]
fn region_map_has_one_cell_per_start() {
    let mut cells = Vec::new();
    for i in 0..7 {
        for j in 0..5 {
            let outcome = match (i + j) % 3 {
                0 => CellOutcome::Converged,
                1 => CellOutcome::Unsettled,
                _ => CellOutcome::Diverged,
            };
            cells.push(SweepCell { x: i as f64 * 0.3 - 1.0, y: j as f64 * 0.3 - 0.6, outcome });
        }
    }
    let svg = region_svg("paper law", &cells, Pose2::default()).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("valid XML");
    let fills = ["#2CA02C", "#FFA500", "#D62728"];
    let cell_rects = doc
        .descendants()
        .filter(|n| n.has_tag_name("rect"))
        .filter(|n| n.attribute("fill").is_some_and(|f| fills.iter().any(|c| f.eq_ignore_ascii_case(c))))
        .count();
    // One per start plus one legend swatch per outcome kind.
    assert_eq!(cell_rects, cells.len() + 3);
}
