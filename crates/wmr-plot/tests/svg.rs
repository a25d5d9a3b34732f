//! The SVGs parse as XML, hold one curve per run or series and one marker per sweep
//! start, print at their intended size, keep sub-point coordinates, and keep the axes
//! on what matters.

use crate::common::{points, run};
use wmr_core::{Pose2, Sample, Status};
use wmr_plot::{SweepCell, Trace, errors_svg, paths_svg, region_svg, share_svg, status_color, wheel_speeds_svg};

/// Polylines with more than `min` points (data curves; legend keys are lines).
fn curves<'a>(doc: &'a roxmltree::Document<'a>, min: usize) -> Vec<roxmltree::Node<'a, 'a>> {
    doc.descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .filter(|n| n.attribute("points").is_some_and(|p| p.split_whitespace().count() > min))
        .collect()
}

/// Tick labels along an axis: the text of every `<text>` element that parses as a number.
fn numbers(doc: &roxmltree::Document<'_>) -> Vec<f64> {
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text().and_then(|t| t.replace('\u{2212}', "-").parse().ok()))
        .collect()
}

#[test]
fn paths_plot_one_curve_per_run_in_its_own_colour_with_its_goal_marker() {
    let goal_a = Pose2::new(1.0, 1.0, 120f64.to_radians());
    let goal_b = Pose2::new(1.0, 1.0, 0.0);
    let a = run(Pose2::default(), goal_a, 20);
    let b = run(Pose2::default(), goal_b, 20);
    let traces = [
        Trace { label: "theta_d = 120 deg", goal: goal_a, samples: &a, reference: &[] },
        Trace { label: "theta_d = 0 deg", goal: goal_b, samples: &b, reference: &[] },
    ];
    let svg = paths_svg("Fig. 4", &traces).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("valid XML");
    let lines = curves(&doc, 10);
    assert_eq!(lines.len(), traces.len());
    let colors: Vec<&str> = lines.iter().map(|n| n.attribute("stroke").unwrap()).collect();
    assert_ne!(colors[0], colors[1], "one colour per run");
    for c in &colors {
        // The goal ring of each run is outlined in the run's colour.
        assert!(
            doc.descendants().any(|n| n.has_tag_name("circle") && n.attribute("stroke") == Some(*c)),
            "no goal ring in {c}"
        );
    }
    // The user's label is drawn as written (no subscript markup in it).
    assert!(svg.contains(">theta_d = 120 deg<"));
}

#[test]
fn figures_print_at_their_size_with_fonts_of_at_least_8_pt_and_smooth_curves() {
    let goal = Pose2::new(1.0, 1.0, 120f64.to_radians());
    let s = run(Pose2::default(), goal, 10);
    let trace = Trace { label: "fig7", goal, samples: &s, reference: &[] };
    for svg in [paths_svg("Fig. 7", &[trace]).unwrap(), wheel_speeds_svg("Fig. 8", &trace).unwrap()] {
        let doc = roxmltree::Document::parse(&svg).expect("valid XML");
        let root = doc.root_element();
        let width_mm: f64 = root.attribute("width").unwrap().trim_end_matches("mm").parse().unwrap();
        assert!((width_mm - 141.11).abs() < 0.1, "{width_mm} mm");
        let sizes: Vec<f64> =
            doc.descendants().filter_map(|n| n.attribute("font-size")).filter_map(|f| f.parse().ok()).collect();
        assert!(!sizes.is_empty() && sizes.iter().all(|f| *f >= 8.0), "font sizes {sizes:?}");
        // Curves keep fractions of a point: not rounded to whole units.
        let pts: Vec<(f64, f64)> = curves(&doc, 10).iter().flat_map(points).collect();
        let fractional = pts.iter().filter(|(x, y)| x.fract() != 0.0 || y.fract() != 0.0).count();
        assert!(fractional * 2 > pts.len(), "{fractional} of {} points have fractions", pts.len());
    }
}

#[test]
fn time_plots_have_one_curve_per_series_and_a_detail_panel_after_a_start_up_spike() {
    let goal = Pose2::new(1.0, 1.0, 120f64.to_radians());
    let s = run(Pose2::default(), goal, 30);
    let trace = Trace { label: "fig7", goal, samples: &s, reference: &[] };
    let speeds = wheel_speeds_svg("Fig. 8", &trace).unwrap();
    let doc = roxmltree::Document::parse(&speeds).unwrap();
    // Two wheels, drawn in the full panel and again in the detail panel.
    assert_eq!(curves(&doc, 10).len(), 4);
    assert!(speeds.contains("detail"));
    let errors = errors_svg("Fig. 9", &trace).unwrap();
    let doc = roxmltree::Document::parse(&errors).unwrap();
    assert!(curves(&doc, 10).len() >= 4, "dl, e_s, e_theta, theta_d - theta");
}

#[test]
fn a_run_that_goes_far_is_clipped_and_does_not_stretch_the_axes() {
    let goal = Pose2::new(0.0, 0.0, 0.0);
    let near = run(Pose2::new(-1.0, 0.5, 0.0), goal, 20);
    // A run that leaves for 900 m (a diverged run's samples).
    let far: Vec<Sample<f64>> = (0..200)
        .map(|i| {
            let mut s = near[0];
            s.t = f64::from(i) * 0.1;
            s.state.x = 1.0 + 4.5 * f64::from(i);
            s
        })
        .collect();
    let traces = [
        Trace { label: "near", goal, samples: &near, reference: &[] },
        Trace { label: "far", goal, samples: &far, reference: &[] },
    ];
    let svg = paths_svg("clipped", &traces).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let largest = numbers(&doc).into_iter().filter(|v| v.abs() < 1e6).fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(largest < 10.0, "the axes reach {largest} m");
    assert!(svg.contains("far (leaves the plot)"));
    assert!(doc.descendants().any(|n| n.attribute("clip-path").is_some()), "the data are clipped");
}

#[test]
fn region_map_has_one_marker_per_start_pointing_along_its_heading() {
    let mut cells = Vec::new();
    for i in 0..7 {
        for j in 0..5 {
            let outcome = Status::ALL[(i + j) % 3];
            cells.push(SweepCell { x: i as f64 * 0.3 - 1.0, y: j as f64 * 0.3 - 0.6, theta: 0.0, outcome });
        }
    }
    cells[0].theta = std::f64::consts::FRAC_PI_2;
    let svg = region_svg("paper law", &cells, Pose2::default()).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("valid XML");
    let markers: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("polygon"))
        .filter(|n| n.attribute("fill").is_some_and(|f| Status::ALL.iter().any(|s| status_color(*s) == f)))
        .collect();
    // One per start plus one legend key per outcome; diverged is drawn in black, like the
    // goal's arrowhead and its legend key, so those two add to the black count.
    let black = markers.iter().filter(|n| n.attribute("fill") == Some(status_color(Status::Diverged))).count();
    let diverged = cells.iter().filter(|c| c.outcome == Status::Diverged).count();
    assert_eq!(black, diverged + 1 + 2);
    assert_eq!(markers.len() - black, cells.len() - diverged + 2);
    // The start turned to +90 deg points up the page (smaller y) from its centre.
    let up = markers.iter().map(|n| points_of_polygon(n)).find(|p| {
        let ys: Vec<f64> = p.iter().map(|q| q.1).collect();
        let xs: Vec<f64> = p.iter().map(|q| q.0).collect();
        (xs[1] - xs[2]).abs() > (ys[1] - ys[2]).abs() && ys[0] < ys[1]
    });
    assert!(up.is_some(), "no marker points up");
}

fn points_of_polygon(n: &roxmltree::Node<'_, '_>) -> Vec<(f64, f64)> {
    points(n)
}

#[test]
fn share_curves_one_per_law() {
    let series = [("paper", vec![(0.0, 0.8), (0.01, 0.5)]), ("polar", vec![(0.0, 1.0), (0.01, 0.9)])];
    let svg = share_svg("noise", "sensor.position_noise (m)", &series).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    assert_eq!(curves(&doc, 1).len(), 2);
    // The key is user text: written as is.
    assert!(svg.contains("sensor.position_noise (m)"));
}

/// A sweep of more starts than [`wmr_plot::MAX_MARKERS`] is drawn as bins: no marker per
/// start, a bounded file, each bin the colour of its starts' most common outcome.
#[test]
fn a_region_map_of_many_starts_is_drawn_as_bins() {
    let n = 300;
    let mut cells = Vec::new();
    for i in 0..n {
        for j in 0..n / 3 {
            let x = i as f64 / n as f64 * 4.0 - 2.0;
            let y = j as f64 / (n / 3) as f64 * 4.0 - 2.0;
            // Left half converged, right half diverged.
            let outcome = if x < 0.0 { Status::Converged } else { Status::Diverged };
            cells.push(SweepCell { x, y, theta: 0.0, outcome });
        }
    }
    assert!(cells.len() > wmr_plot::MAX_MARKERS);
    let svg = region_svg("many starts", &cells, Pose2::default()).unwrap();
    assert!(svg.len() < 3_000_000, "{} bytes", svg.len());
    let doc = roxmltree::Document::parse(&svg).expect("valid XML");
    let colour_of = |s: Status| status_color(s);
    let polygons = doc.descendants().filter(|n| n.has_tag_name("polygon")).count();
    assert!(polygons < 10, "{polygons} polygons: markers were drawn");
    let rects: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("rect"))
        .filter(|n| {
            n.attribute("fill").is_some_and(|f| f == colour_of(Status::Converged) || f == colour_of(Status::Diverged))
        })
        .collect();
    // One rectangle per run of one colour in a row: two per row here.
    assert!(rects.len() > 100 && rects.len() <= 2 * wmr_plot::BINS, "{} rectangles", rects.len());
    // Bins left of the goal are converged, right of it diverged.
    let x_of = |n: &roxmltree::Node| n.attribute("x").and_then(|v| v.parse::<f64>().ok()).unwrap();
    let mid = {
        let xs: Vec<f64> = rects.iter().map(x_of).collect();
        (xs.iter().cloned().fold(f64::INFINITY, f64::min) + xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max)) / 2.0
    };
    for r in &rects {
        let expected = if x_of(r) < mid - 5.0 {
            Some(Status::Converged)
        } else if x_of(r) > mid + 5.0 {
            Some(Status::Diverged)
        } else {
            None
        };
        if let Some(s) = expected {
            assert_eq!(r.attribute("fill"), Some(colour_of(s)));
        }
    }
}

/// A tracking run (issue 23): its reference is drawn once, dashed, on top of the runs and
/// one lap long (a second lap over the first would fill its dashes' gaps), with no goal
/// marker; the errors figure measures the true heading against the reference.
#[test]
fn a_tracking_run_has_its_reference_dashed_and_no_goal() {
    let goal = Pose2::new(1.0, 1.0, 0.0);
    let s = run(Pose2::default(), goal, 20);
    // Two laps of a 1 m circle around (0, 1), counter-clockwise, over the samples' times.
    let period = s.last().unwrap().t / 2.0;
    let reference: Vec<Pose2<f64>> = s
        .iter()
        .map(|x| {
            let phi = -std::f64::consts::FRAC_PI_2 + std::f64::consts::TAU * x.t / period;
            Pose2::new(phi.cos(), 1.0 + phi.sin(), phi + std::f64::consts::FRAC_PI_2)
        })
        .collect();
    let trace = Trace { label: "kanayama", goal, samples: &s, reference: &reference };
    let svg = paths_svg("circle", &[trace]).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("valid XML");
    let dashed: Vec<_> =
        curves(&doc, 10).into_iter().filter(|n| n.attribute("stroke-dasharray") == Some("7 4")).collect();
    assert_eq!(dashed.len(), 1, "one dashed reference");
    let n = dashed[0].attribute("points").unwrap().split_whitespace().count();
    assert!(n > s.len() / 3 && n < s.len() * 2 / 3, "one lap of two: {n} of {} points", s.len());
    // Drawn after (on top of) the run's own path.
    let all = curves(&doc, 10);
    assert_eq!(all.last().and_then(|c| c.attribute("stroke-dasharray")), Some("7 4"));
    assert!(svg.contains(">reference<"), "the legend names it");
    assert!(!svg.contains("goal and its heading"), "no goal in a tracking figure");
    assert!(!doc.descendants().any(|n| n.has_tag_name("circle") && n.attribute("fill") == Some("#ffffff")));
    let errors = errors_svg("circle", &trace).unwrap();
    assert!(errors.contains(">ref</tspan>"), "theta_ref - theta");
    assert!(!errors.contains(">d</tspan>"), "not the goal's heading theta_d");
    // Without a reference the goal is back.
    let svg = paths_svg("goal", &[Trace { reference: &[], ..trace }]).unwrap();
    assert!(svg.contains("goal and its heading"));
}

/// Two laws with the same shares (kanayama and backstepping in share-sensor-latency.svg)
/// both show: the curve on top is dashed and its markers are rings around the dots below,
/// so the first colour stays visible (issue 40).
#[test]
fn coinciding_share_curves_both_show() {
    let same = vec![(0.0, 1.0), (0.05, 1.0), (0.1, 0.5)];
    let series = [("kanayama", same.clone()), ("backstepping", same), ("pure_pursuit", vec![(0.0, 0.2), (0.1, 0.1)])];
    let svg = share_svg("latency", "sensor.latency (s)", &series).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let lines = curves(&doc, 1);
    assert_eq!(lines.len(), 3);
    let (first, second) = (&lines[0], &lines[1]);
    assert_eq!(first.attribute("points"), second.attribute("points"));
    assert_ne!(first.attribute("stroke"), second.attribute("stroke"));
    assert!(first.attribute("stroke-dasharray").is_none(), "the first curve is solid");
    assert!(second.attribute("stroke-dasharray").is_some(), "the curve on top is dashed: {svg}");
    assert!(lines[2].attribute("stroke-dasharray").is_none(), "a curve of its own stays solid");
    // At each point both markers show: the first a filled dot, the second a ring around it.
    let at = |stroke: &str| -> Vec<(String, String, String)> {
        doc.descendants()
            .filter(|n| n.has_tag_name("circle"))
            .filter(|n| n.attribute("fill") == Some(stroke) || n.attribute("stroke") == Some(stroke))
            .map(|n| {
                let a = |k| n.attribute(k).unwrap_or_default().to_owned();
                (a("cx"), a("cy"), a("r"))
            })
            .collect()
    };
    let dots = at(first.attribute("stroke").unwrap());
    let rings = at(second.attribute("stroke").unwrap());
    for (cx, cy, r) in &dots[..3] {
        let ring = rings.iter().find(|(x, y, _)| x == cx && y == cy).expect("a ring on every dot");
        assert!(ring.2.parse::<f64>().unwrap() > r.parse::<f64>().unwrap() + 1.0, "{ring:?} hides the dot of r {r}");
    }
}
