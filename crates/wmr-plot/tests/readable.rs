//! Readable output everywhere (issue 27): the legend sits inside the plot in its emptiest
//! corner on a light box, or below the figure when every corner would hide data; the plot
//! takes the width the legend freed; heading arrows are sized to the page, big enough to
//! see with the figure scaled to a column; every axis names its unit.

use crate::common::{points, run};
use wmr_core::{Pose2, Sample, Status};
use wmr_plot::{
    ReplayRun, SweepCell, Trace, errors_svg, paths_svg, region_svg, replay_svg, share_svg, wheel_speeds_svg,
};

/// The paper's Fig. 4: from the origin to (1, 1) at six goal headings.
fn fig4_runs() -> Vec<(String, Pose2<f64>, Vec<Sample<f64>>)> {
    [0.0, 45.0, 90.0, 120.0, 180.0, -90.0]
        .into_iter()
        .map(|deg: f64| {
            let goal = Pose2::new(1.0, 1.0, deg.to_radians());
            (format!("theta_d = {deg} deg"), goal, run(Pose2::default(), goal, 30))
        })
        .collect()
}

/// A rectangle on the page, pt.
#[derive(Clone, Copy, Debug)]
struct Rect {
    x: f64,
    y: f64,
    w: f64,
    h: f64,
}

impl Rect {
    fn contains(&self, (x, y): (f64, f64)) -> bool {
        x >= self.x && x <= self.x + self.w && y >= self.y && y <= self.y + self.h
    }

    fn within(&self, o: &Rect) -> bool {
        self.x >= o.x && self.y >= o.y && self.x + self.w <= o.x + o.w && self.y + self.h <= o.y + o.h
    }
}

fn attr(n: &roxmltree::Node<'_, '_>, a: &str) -> f64 {
    n.attribute(a).unwrap_or_else(|| panic!("no {a}")).parse().unwrap()
}

fn rect_of(n: &roxmltree::Node<'_, '_>) -> Rect {
    Rect { x: attr(n, "x"), y: attr(n, "y"), w: attr(n, "width"), h: attr(n, "height") }
}

/// The plot frames: unfilled rectangles with an outline, top to bottom.
fn frames(doc: &roxmltree::Document<'_>) -> Vec<Rect> {
    let mut f: Vec<Rect> = doc
        .descendants()
        .filter(|n| n.has_tag_name("rect") && n.attribute("fill") == Some("none") && n.attribute("stroke").is_some())
        .map(|n| rect_of(&n))
        .collect();
    f.sort_by(|a, b| a.y.total_cmp(&b.y));
    f
}

/// The legend boxes (the project marks them `class="legend"`).
fn legend_boxes(doc: &roxmltree::Document<'_>) -> Vec<Rect> {
    doc.descendants()
        .filter(|n| n.has_tag_name("rect") && n.attribute("class") == Some("legend"))
        .map(|n| rect_of(&n))
        .collect()
}

/// Where the text reading `s` starts (its anchor point, pt).
fn text_at(doc: &roxmltree::Document<'_>, s: &str) -> (f64, f64) {
    let n = doc
        .descendants()
        .find(|n| n.has_tag_name("text") && n.text() == Some(s))
        .unwrap_or_else(|| panic!("no text {s:?}"));
    (attr(&n, "x"), attr(&n, "y"))
}

/// The points of every data curve (polylines of more than 10 points), resampled every
/// 0.5 pt of their length: how much of the data lies under a rectangle.
fn data_ink(doc: &roxmltree::Document<'_>) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for n in doc.descendants().filter(|n| n.has_tag_name("polyline")) {
        let pts: Vec<(f64, f64)> = n
            .attribute("points")
            .unwrap()
            .split_whitespace()
            .map(|p| {
                let (x, y) = p.split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect();
        if pts.len() <= 10 {
            continue;
        }
        for w in pts.windows(2) {
            let (a, b) = (w[0], w[1]);
            let n = ((b.0 - a.0).hypot(b.1 - a.1) / 0.5).ceil().clamp(1.0, 4000.0) as usize;
            out.extend((0..n).map(|k| {
                let f = k as f64 / n as f64;
                (a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1))
            }));
        }
    }
    out
}

fn covered(ink: &[(f64, f64)], r: &Rect) -> usize {
    ink.iter().filter(|p| r.contains(**p)).count()
}

/// The legend box moved to each corner of `frame`, keeping its gap to the frame.
fn corners(frame: &Rect, b: &Rect) -> [Rect; 4] {
    let gap = (b.x - frame.x).min(frame.x + frame.w - b.x - b.w).min(b.y - frame.y).min(frame.y + frame.h - b.y - b.h);
    let (l, r) = (frame.x + gap, frame.x + frame.w - gap - b.w);
    let (t, d) = (frame.y + gap, frame.y + frame.h - gap - b.h);
    [(l, t), (r, t), (l, d), (r, d)].map(|(x, y)| Rect { x, y, w: b.w, h: b.h })
}

/// The legend lies inside `frame`, all of `labels` on it, in the corner that covers the
/// fewest data points, and covers at most 2 % of them.
fn assert_legend_inside(svg: &str, frame_index: usize, labels: &[&str]) {
    let doc = roxmltree::Document::parse(svg).expect("valid XML");
    let frame = frames(&doc)[frame_index];
    for l in labels {
        let at = text_at(&doc, l);
        assert!(frame.contains(at), "legend text {l:?} at {at:?} is outside the plot {frame:?}");
    }
    let boxes = legend_boxes(&doc);
    let b = *boxes
        .iter()
        .find(|b| labels.iter().all(|l| b.contains(text_at(&doc, l))))
        .unwrap_or_else(|| panic!("no legend box holds {labels:?}: {boxes:?}"));
    assert!(b.within(&frame), "legend box {b:?} is not inside the plot {frame:?}");
    let ink = data_ink(&doc);
    let on_frame = ink.iter().filter(|p| frame.contains(**p)).count();
    let here = covered(&ink, &b);
    for c in corners(&frame, &b) {
        assert!(here <= covered(&ink, &c), "the legend covers {here} points; at {c:?} it would cover fewer");
    }
    assert!(here as f64 <= 0.02 * on_frame as f64, "the legend covers {here} of {on_frame} data points");
}

#[test]
fn the_paths_legend_sits_in_the_plot_corner_that_hides_the_fewest_data_points() {
    let runs = fig4_runs();
    let traces: Vec<Trace<'_>> =
        runs.iter().map(|(l, g, s)| Trace { label: l, goal: *g, samples: s, reference: &[] }).collect();
    let svg = paths_svg("Fig. 4", &traces).unwrap();
    let labels: Vec<&str> = runs.iter().map(|(l, _, _)| l.as_str()).chain(["start"]).collect();
    assert_legend_inside(&svg, 0, &labels);
}

#[test]
fn time_plots_and_share_curves_keep_their_legends_inside_the_plot() {
    let goal = Pose2::new(1.0, 1.0, 120f64.to_radians());
    let s = run(Pose2::default(), goal, 30);
    let trace = Trace { label: "fig7", goal, samples: &s, reference: &[] };
    let speeds = wheel_speeds_svg("Fig. 8", &trace).unwrap();
    assert_legend_inside(&speeds, 0, &["right wheel ω", "left wheel ω"]);
    let errors = errors_svg("Fig. 9", &trace).unwrap();
    assert_legend_inside(&errors, 0, &["distance dl (m)", "position error e"]);
    // The heading panel is the last (after the distance panel's detail).
    let doc = roxmltree::Document::parse(&errors).unwrap();
    let last = frames(&doc).len() - 1;
    assert_legend_inside(&errors, last, &["heading error e"]);
    let series = [("paper", vec![(0.0, 0.55), (0.01, 0.5)]), ("polar", vec![(0.0, 0.45), (0.01, 0.4)])];
    let share = share_svg("noise", "sensor.position_noise (m)", &series).unwrap();
    assert_legend_inside(&share, 0, &["paper", "polar"]);
}

#[test]
fn the_plot_takes_the_width_the_legend_freed() {
    let runs = fig4_runs();
    let traces: Vec<Trace<'_>> =
        runs.iter().map(|(l, g, s)| Trace { label: l, goal: *g, samples: s, reference: &[] }).collect();
    let svg = paths_svg("Fig. 4", &traces).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let page_w =
        doc.root_element().attribute("viewBox").unwrap().split_whitespace().nth(2).unwrap().parse::<f64>().unwrap();
    let frame = frames(&doc)[0];
    assert!(frame.w >= 0.8 * page_w, "the plot is {} of {page_w} pt wide", frame.w);
}

/// A map whose starts fill the square leaves no corner for the legend: it goes below.
#[test]
fn a_legend_that_would_hide_data_goes_below_the_plot() {
    let mut cells = Vec::new();
    for i in 0..=40 {
        for j in 0..=40 {
            let (x, y) = (f64::from(i) * 0.1 - 2.0, f64::from(j) * 0.1 - 2.0);
            cells.push(SweepCell { x, y, theta: 0.0, outcome: Status::ALL[(i + j) as usize % 3] });
        }
    }
    let svg = region_svg("full", &cells, Pose2::default()).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let frame = frames(&doc)[0];
    let (_, y) = text_at(&doc, "goal and its heading");
    assert!(y > frame.y + frame.h, "the legend at y = {y} is on the map {frame:?}");
}

/// A start under the legend would be a start without its outcome: on a map of starts
/// over a disc (the corners of its square are nearly empty) the legend hides none.
#[test]
fn a_map_legend_hides_no_start() {
    // 1,000 starts spread uniformly over a disc of radius 2 m (a fixed LCG, any heading),
    // like examples/compare.toml.
    let mut state: u64 = 2026;
    let mut uniform = || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let cells: Vec<SweepCell> = (0..1000)
        .map(|_| {
            let (r, phi, theta) =
                (2.0 * uniform().sqrt(), std::f64::consts::TAU * uniform(), std::f64::consts::TAU * uniform());
            SweepCell { x: r * phi.cos(), y: r * phi.sin(), theta, outcome: Status::Converged }
        })
        .collect();
    let svg = region_svg("disc", &cells, Pose2::default()).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    // The start markers: the triangles drawn in the clipped map (legend keys are outside it).
    let starts: Vec<(f64, f64)> = doc
        .descendants()
        .filter(|n| n.has_tag_name("polygon") && n.ancestors().any(|a| a.attribute("clip-path").is_some()))
        .map(|n| {
            let p = points(&n);
            (p.iter().map(|q| q.0).sum::<f64>() / 3.0, p.iter().map(|q| q.1).sum::<f64>() / 3.0)
        })
        .collect();
    assert_eq!(starts.len(), cells.len());
    for b in legend_boxes(&doc) {
        let hidden = starts.iter().filter(|p| b.contains(**p)).count();
        assert_eq!(hidden, 0, "the legend {b:?} hides {hidden} starts");
    }
}

/// The heads of the arrows along a path and at its goal: at least 1.5 % of the figure's
/// width, so 1.3 mm with the figure scaled to an 85 mm column.
#[test]
fn heading_arrows_are_sized_to_the_page_and_visible_at_column_width() {
    for (start, goal, secs) in [
        (Pose2::default(), Pose2::new(1.0, 1.0, 120f64.to_radians()), 30),
        // A short run: the arrows must not shrink with the data range.
        (Pose2::new(0.0, 0.0, 0.0), Pose2::new(0.1, 0.05, 0.0), 10),
    ] {
        let s = run(start, goal, secs);
        let svg = paths_svg("arrows", &[Trace { label: "run", goal, samples: &s, reference: &[] }]).unwrap();
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let page_w =
            doc.root_element().attribute("viewBox").unwrap().split_whitespace().nth(2).unwrap().parse::<f64>().unwrap();
        let colour = doc
            .descendants()
            .find(|n| n.has_tag_name("polyline") && n.attribute("points").unwrap().split_whitespace().count() > 10)
            .and_then(|n| n.attribute("stroke"))
            .unwrap();
        let heads: Vec<f64> = doc
            .descendants()
            .filter(|n| n.has_tag_name("polygon") && n.attribute("fill") == Some(colour))
            .map(|n| {
                let p = points(&n);
                assert_eq!(p.len(), 3);
                let base = (0.5 * (p[1].0 + p[2].0), 0.5 * (p[1].1 + p[2].1));
                (p[0].0 - base.0).hypot(p[0].1 - base.1)
            })
            .collect();
        assert!(heads.len() >= 4, "{} arrowheads", heads.len());
        for h in heads {
            assert!(h >= 0.015 * page_w, "an arrowhead {h:.2} pt long on a {page_w} pt wide figure");
        }
    }
}

/// A replay of `s` (`wmr-cli replay --plot`): its v and omega as the two "wheel speeds",
/// replayed 1 % larger, an error per second, and its path as both logged and replayed.
fn replay_run(s: &[Sample<f64>]) -> ReplayRunOwned {
    let t: Vec<f64> = s.iter().map(|x| x.t).collect();
    let logged = [s.iter().map(|x| x.state.v).collect::<Vec<_>>(), s.iter().map(|x| x.state.omega).collect()];
    let replayed =
        [logged[0].iter().map(|w| 1.01 * w).collect::<Vec<_>>(), logged[1].iter().map(|w| 1.01 * w).collect()];
    let pose = [
        s.iter().map(|x| x.state.x).collect::<Vec<_>>(),
        s.iter().map(|x| x.state.y).collect(),
        s.iter().map(|x| x.state.theta).collect(),
    ];
    let seconds = (t.last().unwrap() - t[0]).floor() as usize + 1;
    ReplayRunOwned { t, logged, replayed, per_second: vec![0.01; seconds], pose }
}

/// The columns a [`ReplayRun`] borrows.
struct ReplayRunOwned {
    t: Vec<f64>,
    logged: [Vec<f64>; 2],
    replayed: [Vec<f64>; 2],
    per_second: Vec<f64>,
    pose: [Vec<f64>; 3],
}

impl ReplayRunOwned {
    fn view(&self) -> ReplayRun<'_> {
        let p = &self.pose;
        ReplayRun {
            t_s: &self.t,
            logged_speed: [&self.logged[0], &self.logged[1]],
            replayed_speed: [&self.replayed[0], &self.replayed[1]],
            speed_rms_per_second: &self.per_second,
            logged_pose: Some([&p[0], &p[1], &p[2]]),
            replayed_pose: [&p[0], &p[1], &p[2]],
        }
    }
}

/// Axis labels (the 8.5 pt texts) of every kind of figure name a unit in parentheses.
#[test]
fn every_axis_of_every_figure_names_its_unit() {
    let goal = Pose2::new(1.0, 1.0, 120f64.to_radians());
    let s = run(Pose2::default(), goal, 20);
    let trace = Trace { label: "fig7", goal, samples: &s, reference: &[] };
    let cells = [SweepCell { x: 1.0, y: 0.5, theta: 0.0, outcome: Status::Converged }];
    let series = [("paper", vec![(0.0, 0.8), (0.01, 0.5)])];
    let figures = [
        paths_svg("paths", &[trace]).unwrap(),
        wheel_speeds_svg("speeds", &trace).unwrap(),
        errors_svg("errors", &trace).unwrap(),
        region_svg("region", &cells, Pose2::default()).unwrap(),
        share_svg("share", "sensor.latency (s)", &series).unwrap(),
        replay_svg("replay", &replay_run(&s).view()).unwrap(),
    ];
    for svg in &figures {
        let doc = roxmltree::Document::parse(svg).unwrap();
        let labels: Vec<String> = doc
            .descendants()
            .filter(|n| n.has_tag_name("text") && n.attribute("font-size") == Some("8.5"))
            .map(|n| n.descendants().filter_map(|d| d.text()).collect())
            .collect();
        assert!(labels.len() >= 2, "{labels:?}");
        for l in labels {
            let unit = l.split_once('(').and_then(|(_, r)| r.split_once(')')).map(|(u, _)| u.trim());
            assert!(unit.is_some_and(|u| !u.is_empty()), "axis label {l:?} names no unit");
        }
    }
}
