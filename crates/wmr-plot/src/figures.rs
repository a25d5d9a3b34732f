//! Path and time-series figures of single runs (the paper's Figs. 4-9) and the path
//! comparison of several laws from one start.

use wmr_core::{Obstacle, Obstacles, Pose2, Sample, wrap_angle};

use crate::chart::{
    BOTTOM, Entry, FONT, GOAL_HEAD, GOAL_LEN, HEADING_HEAD, HEADING_LEN, Ink, Key, LEFT, LINE_W, LINES_MAX_SHARE,
    LegendBox, PAGE_W, Panel, RIGHT, TOP, color, cross, dash, legend_boxed, legend_rows, padded_range, page_wide_panel,
    page_with_legend, place_legend, rows_height, title,
};
use crate::svg::{Anchor, Stroke, Svg, escape, math, text_width};
use crate::{PlotError, Trace};

/// A point on the page, pt.
type Point = (f64, f64);

/// Heading arrows drawn along each path.
const HEADING_TICKS: usize = 7;

/// Farthest a path may go from its goal, m, before it counts as leaving the plot: four
/// times the largest start-to-goal distance plus 1 m.
fn far_radius(traces: &[Trace<'_>]) -> f64 {
    let d = traces
        .iter()
        .filter_map(|t| t.samples.first().map(|s| (t.goal.x - s.state.x).hypot(t.goal.y - s.state.y)))
        .fold(0.0, f64::max);
    4.0 * d + 1.0
}

/// True when the run leaves the disc of radius `far` (m) around its goal, or stops
/// being finite: it is then drawn clipped to the plot, with a cross where it leaves.
fn goes_far(t: &Trace<'_>, far: f64) -> bool {
    t.samples.iter().any(|s| {
        let (x, y) = (s.state.x, s.state.y);
        !(x.is_finite() && y.is_finite()) || (t.goal.x - x).hypot(t.goal.y - y) > far
    })
}

/// Sample indices spread evenly along the path's length (not its time), `n` of them,
/// over the part of the run that moves (until the last sample farther than 2 cm from
/// the goal), for the heading arrows.
fn spread_along_path(samples: &[Sample<f64>], goal: Pose2<f64>, n: usize) -> Vec<usize> {
    let end = samples
        .iter()
        .rposition(|s| (goal.x - s.state.x).hypot(goal.y - s.state.y) > 0.02)
        .map_or(samples.len(), |i| i + 1);
    let mut cum = Vec::with_capacity(end);
    let mut acc = 0.0;
    for (i, s) in samples[..end].iter().enumerate() {
        if i > 0 {
            let p = &samples[i - 1].state;
            let d = (s.state.x - p.x).hypot(s.state.y - p.y);
            if d.is_finite() {
                acc += d;
            }
        }
        cum.push(acc);
    }
    if acc <= 0.0 || n == 0 {
        return vec![0];
    }
    (0..n)
        .map(|k| {
            let target = acc * k as f64 / n as f64;
            cum.iter().position(|c| *c >= target).unwrap_or(0)
        })
        .collect()
}

/// The finite points of a reference path up to where it first comes back to its start
/// pose (one lap of a circle or a figure-eight): a second lap drawn over the first would fill
/// the gaps of its dashes.
fn first_lap(r: &[Pose2<f64>]) -> Vec<Pose2<f64>> {
    let pts: Vec<Pose2<f64>> = r.iter().copied().filter(|p| p.x.is_finite() && p.y.is_finite()).collect();
    let step = pts.windows(2).map(|w| (w[1].x - w[0].x).hypot(w[1].y - w[0].y)).fold(0.0, f64::max);
    let Some(start) = pts.first().copied() else { return pts };
    // At the start with its heading (a figure-eight crosses its start at half a lap).
    let near = |p: &Pose2<f64>| {
        (p.x - start.x).hypot(p.y - start.y) <= 0.5 * step && wrap_angle(p.theta - start.theta).abs() < 0.1
    };
    // Back at the start after having left it (by more than 10 steps).
    let away = pts.iter().position(|p| (p.x - start.x).hypot(p.y - start.y) > 10.0 * step);
    match away.and_then(|a| pts[a..].iter().position(near).map(|k| a + k)) {
        Some(end) => pts[..=end].to_vec(),
        None => pts,
    }
}

/// Ink and dash pattern of a tracking run's reference path: dark grey, long dashes.
const REFERENCE_INK: &str = "#404040";
const REFERENCE_DASH: &str = "7 4";

/// Paths of C in the plane, one colour per run carried to its start dot and goal arrow,
/// with arrows showing the heading along the way (a robot backing up has its arrows
/// pointing against its travel). Equal scale on x and y; the axes fit the starts, the
/// goals and every run that stays near its goal: a run that goes far (or diverges) is
/// clipped at the frame and marked with a cross where it leaves (the paper's Figs. 4-7).
/// Tracking runs ([`Trace::reference`]) have their reference path, dashed, instead of goals.
pub fn paths_svg(title_text: &str, traces: &[Trace<'_>]) -> Result<String, PlotError> {
    paths_among_svg(title_text, traces, &Obstacles::default())
}

/// Fill and outline of an obstacle: light grey, its edge dark grey.
const OBSTACLE_FILL: &str = "#d9d9d9";
const OBSTACLE_INK: &str = "#606060";

/// An obstacle's outline in the plane (m): a polygon's vertices, a circle's as 72 of them.
fn obstacle_outline(o: &Obstacle<'_, f64>) -> Vec<(f64, f64)> {
    match *o {
        Obstacle::Circle { center, radius } => (0..72)
            .map(|k| {
                let a = std::f64::consts::TAU * f64::from(k) / 72.0;
                (center.0 + radius * a.cos(), center.1 + radius * a.sin())
            })
            .collect(),
        Obstacle::Polygon(points) => points.to_vec(),
    }
}

/// [`paths_svg`] with `obstacles` drawn under the paths, filled grey ([`crate`]'s
/// figure of a scenario with `[[world.obstacle]]`); the axes fit them too.
pub fn paths_among_svg(
    title_text: &str,
    traces: &[Trace<'_>],
    obstacles: &Obstacles<f64>,
) -> Result<String, PlotError> {
    if traces.is_empty() {
        return Err(PlotError::new("no run to plot"));
    }
    let far = far_radius(traces);
    let far_runs: Vec<bool> = traces.iter().map(|t| goes_far(t, far)).collect();
    // Tracking runs follow one reference: drawn once, dashed, in place of the goals.
    let reference = traces.iter().map(|t| t.reference).find(|r| !r.is_empty());
    let mut xs: Vec<f64> = reference.iter().flat_map(|r| r.iter().map(|p| p.x)).collect();
    let mut ys: Vec<f64> = reference.iter().flat_map(|r| r.iter().map(|p| p.y)).collect();
    let outlines: Vec<Vec<(f64, f64)>> = obstacles.iter().map(|o| obstacle_outline(&o)).collect();
    xs.extend(outlines.iter().flatten().map(|p| p.0));
    ys.extend(outlines.iter().flatten().map(|p| p.1));
    // The goal arrows' tips too (drawn GOAL_LEN long, about 8 % of the frame's width):
    // 8 % of the starts-to-goals extent, at least 5 cm.
    let reach = 0.08
        * traces
            .iter()
            .filter_map(|t| t.samples.first().map(|s| (t.goal.x - s.state.x).abs().max((t.goal.y - s.state.y).abs())))
            .fold(0.6, f64::max);
    for (t, is_far) in traces.iter().zip(&far_runs) {
        if reference.is_none() {
            xs.extend([t.goal.x, t.goal.x + reach * t.goal.theta.cos()]);
            ys.extend([t.goal.y, t.goal.y + reach * t.goal.theta.sin()]);
        }
        if *is_far {
            if let Some(s) = t.samples.first() {
                xs.push(s.state.x);
                ys.push(s.state.y);
            }
        } else {
            xs.extend(t.samples.iter().map(|s| s.state.x));
            ys.extend(t.samples.iter().map(|s| s.state.y));
        }
    }
    // Room to see a far run set off: more margin when some runs leave.
    let pad = if far_runs.iter().any(|f| *f) { 0.15 } else { 0.06 };
    let xr = padded_range(xs.into_iter(), pad, 0.5);
    let yr = padded_range(ys.into_iter(), pad, 0.5);

    let mut entries: Vec<Entry> = traces
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let mut label = t.label.to_owned();
            if far_runs[i] {
                label.push_str(" (leaves the plot)");
            }
            Entry::user(label, Key::Line(color(i), dash(i)))
        })
        .collect();
    entries.push(Entry::math("start", Key::Dot("#404040")));
    entries.push(Entry::math("heading on the way", Key::Arrow("#404040")));
    if reference.is_some() {
        entries.push(Entry::math("reference", Key::Line(REFERENCE_INK, Some(REFERENCE_DASH))));
    } else {
        entries.push(Entry::math("goal and its heading", Key::GoalArrow("#404040")));
    }
    if far_runs.iter().any(|f| *f) {
        entries.push(Entry::math("leaves the plot", Key::Cross("#404040")));
    }
    if !outlines.is_empty() {
        entries.push(Entry::math("obstacle", Key::Patch(OBSTACLE_FILL, OBSTACLE_INK)));
    }
    // The panel takes the page's width; the legend goes in its emptiest corner.
    let panel = page_wide_panel(xr, yr, (0.55, 1.15));
    let (w, h) = (panel.w, panel.h);

    // Everything drawn in the panel, in page points, before drawing: the legend's place
    // depends on it.
    let paths: Vec<Vec<(f64, f64)>> = traces
        .iter()
        .map(|t| {
            t.samples
                .iter()
                .filter(|s| s.state.x.is_finite() && s.state.y.is_finite())
                .map(|s| panel.p((s.state.x, s.state.y)))
                .collect()
        })
        .collect();
    // Heading arrows: (tail, tip) in pt, a far run's on its part inside the frame.
    let arrows: Vec<Vec<(Point, Point)>> = traces
        .iter()
        .map(|t| {
            let inside =
                t.samples.iter().position(|s| !panel.contains((s.state.x, s.state.y))).unwrap_or(t.samples.len());
            spread_along_path(&t.samples[..inside.max(1)], t.goal, HEADING_TICKS)
                .into_iter()
                .skip(1)
                .map(|k| {
                    let s = &t.samples[k].state;
                    let a = panel.p((s.x, s.y));
                    (a, (a.0 + HEADING_LEN * s.theta.cos(), a.1 - HEADING_LEN * s.theta.sin()))
                })
                .collect()
        })
        .collect();
    let goal_tip = |g: Pose2<f64>| {
        let p = panel.p((g.x, g.y));
        (p, (p.0 + GOAL_LEN * g.theta.cos(), p.1 - GOAL_LEN * g.theta.sin()))
    };
    let reference_path: Vec<Point> =
        reference.map(first_lap).unwrap_or_default().into_iter().map(|p| panel.p((p.x, p.y))).collect();
    let mut ink = Ink::default();
    let shapes: Vec<Vec<Point>> = outlines.iter().map(|o| o.iter().map(|&p| panel.p(p)).collect()).collect();
    for s in &shapes {
        ink.line(s);
    }
    ink.line(&reference_path);
    for (t, path) in traces.iter().zip(&paths) {
        ink.line(path);
        if reference.is_none() {
            let (g, tip) = goal_tip(t.goal);
            ink.line(&[g, tip]);
        }
        if let Some(s) = t.samples.first() {
            ink.point(panel.p((s.state.x, s.state.y)));
        }
    }
    for &(a, b) in arrows.iter().flatten() {
        ink.line(&[a, b]);
    }
    let (inside, mut svg) = page_with_legend(&panel, &entries, &ink, title_text);
    panel.axes(&mut svg, Some("x (m)"), "y (m)");

    let clip = panel.clip(&mut svg);
    svg.begin_clip(&clip);
    for s in &shapes {
        svg.polygon(s, OBSTACLE_FILL, Some(Stroke::solid(OBSTACLE_INK, 0.8)));
    }
    for (i, (path, arrows)) in paths.iter().zip(&arrows).enumerate() {
        svg.polyline(path, Stroke { dash: dash(i), ..Stroke::solid(color(i), LINE_W) });
        for &(a, b) in arrows {
            svg.arrow(a, b, HEADING_HEAD, Stroke { opacity: 0.9, ..Stroke::solid(color(i), 0.9) });
        }
    }
    // On top: a run that tracks well lies on its reference, which must still show.
    if !reference_path.is_empty() {
        svg.polyline(&reference_path, Stroke { dash: Some(REFERENCE_DASH), ..Stroke::solid(REFERENCE_INK, 1.0) });
    }
    svg.end_clip();
    for (i, t) in traces.iter().enumerate() {
        let c = color(i);
        // Where a far run leaves the frame: the last sample inside before the first outside.
        if far_runs[i]
            && let Some(out) = t.samples.iter().position(|s| !panel.contains((s.state.x, s.state.y)))
            && out > 0
        {
            let s = &t.samples[out - 1];
            cross(&mut svg, panel.p((s.state.x, s.state.y)), 3.5, Stroke::solid(c, 1.3));
        }
        // A start shared by several runs (laws compared from one start) is one grey dot.
        if let Some(s) = t.samples.first() {
            let same = |o: &Trace<'_>| o.samples.first().is_some_and(|f| f.state.pose() == s.state.pose());
            let shared = traces.iter().filter(|o| same(o)).count() > 1;
            if !(shared && traces[..i].iter().any(same)) {
                svg.circle(panel.p((s.state.x, s.state.y)), 2.6, if shared { "#404040" } else { c }, None);
            }
        }
        // A goal shared by several runs is drawn once, in dark grey (its colour would be
        // the last run's); a goal of its own takes its run's colour. A tracking run has
        // its reference instead.
        if reference.is_some() {
            continue;
        }
        let shared = traces.iter().filter(|o| o.goal == t.goal).count() > 1;
        if shared && traces[..i].iter().any(|o| o.goal == t.goal) {
            continue;
        }
        let gc = if shared { "#404040" } else { c };
        let (g, tip) = goal_tip(t.goal);
        svg.arrow(g, tip, GOAL_HEAD, Stroke::solid(gc, 1.2));
        svg.circle(g, 3.0, "#ffffff", Some(Stroke::solid(gc, 1.2)));
    }
    match &inside {
        Some(b) => legend_boxed(&mut svg, b, &entries),
        None => legend_rows(&mut svg, LEFT, TOP + h + BOTTOM, w, &entries),
    }
    Ok(svg.finish())
}

/// One curve of a time-series panel: its name, colour index and values (one per time).
struct Series<'a> {
    name: &'a str,
    index: usize,
    values: Vec<f64>,
}

/// The time from which every series stays within a quarter of its largest magnitude:
/// the end of the start-up transient, if the rest is small enough to deserve a detail
/// panel of its own (it spans less than 40 % of the full range and starts before 60 % of
/// the run).
fn detail_from(t: &[f64], series: &[Series<'_>]) -> Option<f64> {
    let full = padded_range(series.iter().flat_map(|s| s.values.iter().copied()), 0.0, 0.0);
    let peak =
        series.iter().flat_map(|s| s.values.iter()).map(|v| v.abs()).filter(|v| v.is_finite()).fold(0.0, f64::max);
    if peak <= 0.0 || t.len() < 4 {
        return None;
    }
    let last_big =
        series.iter().filter_map(|s| s.values.iter().rposition(|v| v.abs() > 0.25 * peak)).max().unwrap_or(0);
    let from = (last_big + 1).min(t.len() - 1);
    let t_end = *t.last()?;
    if t[from] > 0.6 * t_end {
        return None;
    }
    let rest = padded_range(series.iter().flat_map(|s| s.values[from..].iter().copied()), 0.0, 0.0);
    ((rest.1 - rest.0) < 0.4 * (full.1 - full.0)).then_some(t[from])
}

/// Panels of time series sharing the time axis; each requested panel's legend in the
/// emptiest corner of it (or of its detail panel), else below the figure.
fn time_panels(title_text: &str, t: &[f64], panels: &[(&str, Vec<Series<'_>>)]) -> Result<String, PlotError> {
    if t.is_empty() {
        return Err(PlotError::new("no sample to plot"));
    }
    let t_end = t.last().copied().unwrap_or(1.0).max(1e-9);
    // Each requested panel (`group`), and after it a detail panel when its start-up
    // dwarfs the rest.
    struct Pane<'p, 'a> {
        y_label: String,
        series: &'p [Series<'a>],
        from: Option<f64>,
        group: usize,
    }
    let mut panes = Vec::new();
    for (group, (label, series)) in panels.iter().enumerate() {
        panes.push(Pane { y_label: (*label).to_owned(), series, from: None, group });
        if let Some(from) = detail_from(t, series) {
            panes.push(Pane { y_label: format!("{label}, detail"), series, from: Some(from), group });
        }
    }
    let w = PAGE_W - LEFT - RIGHT;
    let h = 118.0;
    let gap = 12.0;
    // Each pane's panel, curves (pt), note and ink.
    struct Drawn {
        panel: Panel,
        curves: Vec<Vec<Point>>,
        note: Option<String>,
        ink: Ink,
    }
    let drawn: Vec<Drawn> = panes
        .iter()
        .enumerate()
        .map(|(k, pane)| {
            let from_idx = pane.from.map_or(0, |f| t.iter().position(|x| *x >= f).unwrap_or(0));
            let yr = padded_range(pane.series.iter().flat_map(|s| s.values[from_idx..].iter().copied()), 0.06, 1e-6);
            let panel = Panel { x: LEFT, y: TOP + k as f64 * (h + gap), w, h, xr: (0.0, t_end), yr };
            let curves: Vec<Vec<(f64, f64)>> = pane
                .series
                .iter()
                .map(|s| {
                    t.iter().zip(&s.values).filter(|(_, v)| v.is_finite()).map(|(t, v)| panel.p((*t, *v))).collect()
                })
                .collect();
            let mut ink = Ink::default();
            for c in &curves {
                ink.line(c);
            }
            let note = pane.from.map(|f| format!("y fitted to t \u{2265} {f:.1} s"));
            if let Some(n) = &note {
                // The note, at the top right, is in a legend's way like a line.
                let (x1, y) = (panel.x + panel.w - 4.0, panel.y + 7.0);
                ink.line(&[(x1 - text_width(n, FONT), y), (x1, y)]);
            }
            Drawn { panel, curves, note, ink }
        })
        .collect();
    // Each group's legend: in the first of its panes where it fits, else below.
    let mut inside: Vec<Option<LegendBox>> = Vec::new();
    let mut below = Vec::new();
    for (group, (_, series)) in panels.iter().enumerate() {
        let entries: Vec<Entry> =
            series.iter().map(|s| Entry::math(s.name, Key::Line(color(s.index), dash(s.index)))).collect();
        let place = panes
            .iter()
            .enumerate()
            .filter(|(_, p)| p.group == group)
            .find_map(|(k, _)| place_legend(&drawn[k].panel, &entries, &drawn[k].ink, LINES_MAX_SHARE));
        if place.is_none() {
            below.extend(entries);
        }
        inside.push(place);
    }
    let panels_end = TOP + panes.len() as f64 * (h + gap) - gap + BOTTOM;
    let height = if below.is_empty() { panels_end } else { panels_end + 4.0 + rows_height(&below, w) };
    let mut svg = Svg::new(PAGE_W, height);
    title(&mut svg, LEFT, w, title_text);
    for (k, (pane, Drawn { panel, curves, note, .. })) in panes.iter().zip(&drawn).enumerate() {
        let last = k + 1 == panes.len();
        panel.axes(&mut svg, last.then_some("t (s)"), &math(&pane.y_label));
        let clip = panel.clip(&mut svg);
        svg.begin_clip(&clip);
        for (s, pts) in pane.series.iter().zip(curves) {
            svg.polyline(pts, Stroke { dash: dash(s.index), ..Stroke::solid(color(s.index), LINE_W) });
        }
        svg.end_clip();
        if let Some(n) = note {
            svg.text((panel.x + panel.w - 4.0, panel.y + 10.0), &escape(n), FONT, Anchor::End, 0.0, false);
        }
    }
    for (group, place) in inside.iter().enumerate() {
        if let Some(b) = place {
            let entries: Vec<Entry> =
                panels[group].1.iter().map(|s| Entry::math(s.name, Key::Line(color(s.index), dash(s.index)))).collect();
            legend_boxed(&mut svg, b, &entries);
        }
    }
    if !below.is_empty() {
        legend_rows(&mut svg, LEFT, panels_end, w, &below);
    }
    Ok(svg.finish())
}

/// Right and left wheel speeds over time, rad/s (the paper's Fig. 8); when the start-up
/// dwarfs the rest, a second panel shows the rest at its own scale.
pub fn wheel_speeds_svg(title_text: &str, trace: &Trace<'_>) -> Result<String, PlotError> {
    let t: Vec<f64> = trace.samples.iter().map(|s| s.t).collect();
    let series = vec![
        Series {
            name: "right wheel ω_r",
            index: 0,
            values: trace.samples.iter().map(|s| s.wheel_speeds.right).collect(),
        },
        Series {
            name: "left wheel ω_l",
            index: 1,
            values: trace.samples.iter().map(|s| s.wheel_speeds.left).collect(),
        },
    ];
    time_panels(title_text, &t, &[("wheel speed (rad/s)", series)])
}

/// The law's errors over time (the paper's Fig. 9): the distance dl and the position error
/// e_s (m) in one panel; the heading error e_theta the law steers by and the true heading
/// error theta_d - theta (deg) in another (for the paper's law e_theta is measured towards
/// the moving false target, so the two differ). A tracking run's distance is to its
/// reference point and its true heading error theta_ref - theta.
pub fn errors_svg(title_text: &str, trace: &Trace<'_>) -> Result<String, PlotError> {
    let t: Vec<f64> = trace.samples.iter().map(|s| s.t).collect();
    let tracking = trace.reference.len() == trace.samples.len() && !trace.samples.is_empty();
    let dist = vec![
        Series {
            name: if tracking { "distance to the reference dl (m)" } else { "distance dl (m)" },
            index: 0,
            values: trace.samples.iter().map(|s| s.errors.dl).collect(),
        },
        Series {
            name: "position error e_s (m)",
            index: 1,
            values: trace.samples.iter().map(|s| s.errors.e_s).collect(),
        },
    ];
    let true_heading: Vec<f64> = if tracking {
        trace
            .samples
            .iter()
            .zip(trace.reference)
            .map(|(s, r)| wrap_angle(r.theta - s.state.theta).to_degrees())
            .collect()
    } else {
        trace.samples.iter().map(|s| wrap_angle(trace.goal.theta - s.state.theta).to_degrees()).collect()
    };
    let heading = vec![
        Series {
            name: "heading error e_θ (deg)",
            index: 2,
            values: trace.samples.iter().map(|s| s.errors.e_theta.to_degrees()).collect(),
        },
        Series {
            name: if tracking { "θ_ref − θ (deg)" } else { "θ_d − θ (deg)" }, index: 3, values: true_heading
        },
    ];
    time_panels(title_text, &t, &[("distance, error (m)", dist), ("heading error (deg)", heading)])
}

/// One run of a replay (`wmr-cli replay --plot`, docs/identify.md): the logged and the
/// replayed wheel speeds, the error per second, and the logged and replayed paths.
#[derive(Clone, Copy, Debug)]
pub struct ReplayRun<'a> {
    /// Time of each compared sample, s.
    pub t_s: &'a [f64],
    /// Logged wheel speeds (right, left), rad/s.
    pub logged_speed: [&'a [f64]; 2],
    /// Replayed wheel speeds (right, left), rad/s.
    pub replayed_speed: [&'a [f64]; 2],
    /// RMS wheel-speed error in each second from the first sample, rad/s.
    pub speed_rms_per_second: &'a [f64],
    /// Logged pose of C (x m, y m, theta rad), if the log has one.
    pub logged_pose: Option<[&'a [f64]; 3]>,
    /// Replayed pose of C (x m, y m, theta rad).
    pub replayed_pose: [&'a [f64]; 3],
}

/// The replay of one run: a page of the wheel speeds (logged and replayed, both wheels)
/// and of the speed error's RMS per second over time, and below it a page of the paths
/// of C, logged and replayed, at equal scale (the replayed one alone when the log has no
/// pose); the two pages stacked in one SVG document.
pub fn replay_svg(title_text: &str, run: &ReplayRun<'_>) -> Result<String, PlotError> {
    let t = run.t_s;
    if t.is_empty() {
        return Err(PlotError::new("no sample to plot"));
    }
    let t0 = t[0];
    let per_sample_error: Vec<f64> = t
        .iter()
        .map(|ti| run.speed_rms_per_second.get((ti - t0).floor().max(0.0) as usize).copied().unwrap_or(f64::NAN))
        .collect();
    let speeds = vec![
        Series { name: "right wheel ω_r, logged", index: 0, values: run.logged_speed[0].to_vec() },
        Series { name: "right wheel ω_r, replayed", index: 1, values: run.replayed_speed[0].to_vec() },
        Series { name: "left wheel ω_l, logged", index: 2, values: run.logged_speed[1].to_vec() },
        Series { name: "left wheel ω_l, replayed", index: 3, values: run.replayed_speed[1].to_vec() },
    ];
    let error = vec![Series { name: "RMS per second of log", index: 4, values: per_sample_error }];
    let top =
        time_panels(title_text, t, &[("wheel speed (rad/s)", speeds), ("speed error, RMS per second (rad/s)", error)])?;
    let samples_of = |pose: [&[f64]; 3]| -> Vec<Sample<f64>> {
        (0..t.len())
            .map(|i| Sample::<f64> {
                t: t[i],
                state: wmr_core::State { x: pose[0][i], y: pose[1][i], theta: pose[2][i], ..Default::default() },
                ..Default::default()
            })
            .collect()
    };
    let replayed = samples_of(run.replayed_pose);
    let logged = run.logged_pose.map(samples_of);
    let end = |s: &[Sample<f64>]| {
        s.last().map_or(Pose2::new(0.0, 0.0, 0.0), |s| Pose2::new(s.state.x, s.state.y, s.state.theta))
    };
    let mut traces = Vec::new();
    if let Some(l) = &logged {
        traces.push(Trace { label: "logged", goal: end(l), samples: l, reference: &[] });
    }
    traces.push(Trace { label: "replayed", goal: end(&replayed), samples: &replayed, reference: &[] });
    let bottom = paths_svg("path of C: logged and replayed (arrows: the final poses)", &traces)?;
    Ok(stack(&[top, bottom]))
}

/// SVG documents of [`Svg::finish`] one above the other in one document.
fn stack(docs: &[String]) -> String {
    // Each document's viewBox size, pt.
    let size = |d: &str| -> (f64, f64) {
        let vb = d.split("viewBox=\"").nth(1).and_then(|r| r.split('"').next()).unwrap_or("0 0 0 0");
        let v: Vec<f64> = vb.split(' ').filter_map(|x| x.parse().ok()).collect();
        (v.get(2).copied().unwrap_or(0.0), v.get(3).copied().unwrap_or(0.0))
    };
    let w = docs.iter().map(|d| size(d).0).fold(0.0, f64::max);
    let h: f64 = docs.iter().map(|d| size(d).1).sum();
    let mut out = Svg::new(w, h).finish();
    let close = out.rfind("</svg>").unwrap_or(out.len());
    out.truncate(close);
    let mut y = 0.0;
    for (k, d) in docs.iter().enumerate() {
        let (dw, dh) = size(d);
        // Inner documents: placed by x, y and sized in pt; their clip ids made unique.
        let inner = d.replacen("<svg ", &format!("<svg x=\"0\" y=\"{y}\" "), 1);
        let inner = inner
            .replacen(&format!("width=\"{}mm\"", num_mm(dw)), &format!("width=\"{dw}\""), 1)
            .replacen(&format!("height=\"{}mm\"", num_mm(dh)), &format!("height=\"{dh}\""), 1)
            .replace("id=\"clip", &format!("id=\"p{k}clip"))
            .replace("url(#clip", &format!("url(#p{k}clip"));
        out.push_str(&inner);
        y += dh;
    }
    out.push_str("</svg>\n");
    out
}

/// A size in pt as [`Svg::finish`] writes it in mm.
fn num_mm(pt: f64) -> String {
    crate::svg::num(pt * 25.4 / 72.0)
}
