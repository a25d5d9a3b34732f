//! Region-of-attraction map: every start of a sweep, drawn as a small arrowhead pointing
//! along its start heading and coloured by how the run ended; beyond [`MAX_MARKERS`]
//! starts (a million-start sweep would make a 100 MB file), a grid of bins, each
//! coloured by the most common outcome of the starts in it.

use wmr_core::{Pose2, Status};

use crate::chart::{
    BOTTOM, Entry, FONT, GOAL_HEAD, GOAL_LEN, Ink, Key, LEFT, PAGE_W, Panel, TOP, legend_boxed, legend_rows,
    padded_range, page_wide_panel, place_legend, rows_height, title,
};
use crate::svg::{Anchor, Stroke, Svg};
use crate::{PlotError, status_color};

/// Most starts drawn one marker each; more are drawn as [`BINS`] x [`BINS`] bins.
pub const MAX_MARKERS: usize = 20_000;

/// Bins per axis of a map of more than [`MAX_MARKERS`] starts.
pub const BINS: usize = 120;

/// How one start of a sweep ended: the core's three outcomes.
pub type CellOutcome = Status;

/// One start of a sweep: start pose of C and how the run from it ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepCell {
    /// Start x of C, m.
    pub x: f64,
    /// Start y of C, m.
    pub y: f64,
    /// Start heading, rad (world frame): the marker points this way.
    pub theta: f64,
    /// How the run ended.
    pub outcome: CellOutcome,
}

/// Map of the start plane for one law, at equal scale on x and y: one arrowhead per start,
/// pointing along its start heading and coloured by outcome (counts in the legend), and
/// the goal with its heading. Rarer outcomes are drawn last, on top.
pub fn region_svg(title_text: &str, cells: &[SweepCell], goal: Pose2<f64>) -> Result<String, PlotError> {
    let xr = padded_range(cells.iter().map(|c| c.x).chain([goal.x]), 0.04, 0.5);
    let yr = padded_range(cells.iter().map(|c| c.y).chain([goal.y]), 0.04, 0.5);
    let count = |s: Status| cells.iter().filter(|c| c.outcome == s).count();
    let mut order = Status::ALL;
    order.sort_by_key(|s| std::cmp::Reverse(count(*s)));
    // cannot_follow (a tracking run's) and collided (a world with obstacles) are listed
    // only where a start has them: a map of runs towards a goal keeps its three entries.
    let mut entries: Vec<Entry> = Status::ALL
        .iter()
        .filter(|s| !matches!(s, Status::CannotFollow | Status::Collided) || count(**s) > 0)
        .map(|s| Entry::math(format!("{} ({})", s.name(), count(*s)), Key::Triangle(status_color(*s))))
        .collect();
    entries.push(Entry::math("goal and its heading", Key::GoalArrow("#000000")));
    // The map takes the page's width; a note goes below it.
    let panel = page_wide_panel(xr, yr, (0.6, 1.0));
    let (w, h) = (panel.w, panel.h);
    // Marker length: about the spacing of the starts (pt), within 3.5 to 8 pt.
    let area = (xr.1 - xr.0) * (yr.1 - yr.0) * panel.scale_x() * panel.scale_x();
    let len = (0.9 * (area / cells.len().max(1) as f64).sqrt()).clamp(3.5, 8.0);
    let binned = cells.len() > MAX_MARKERS;
    // Every start is data, and one hidden under the legend would be a start without its
    // outcome: the legend goes in a corner only where it hides no start (a few starts
    // leave room; a disc of many fills its square to the corners), else below the map.
    let g = panel.p((goal.x, goal.y));
    let tip = (g.0 + GOAL_LEN * goal.theta.cos(), g.1 - GOAL_LEN * goal.theta.sin());
    let mut ink = Ink::default();
    for c in cells {
        ink.point(panel.p((c.x, c.y)));
    }
    ink.line(&[g, tip]);
    let inside = place_legend(&panel, &entries, &ink, 0.0);
    let legend_y = TOP + h + BOTTOM;
    let height = match inside {
        Some(_) => legend_y + 10.0,
        None => legend_y + rows_height(&entries, w) + 16.0,
    };
    let mut svg = Svg::new(PAGE_W, height);
    title(&mut svg, panel.x, panel.w, title_text);
    panel.axes(&mut svg, Some("start x (m)"), "start y (m)");

    let clip = panel.clip(&mut svg);
    svg.begin_clip(&clip);
    if binned {
        draw_bins(&mut svg, &panel, cells);
    }
    for status in order.into_iter().filter(|_| !binned) {
        let fill = status_color(status);
        for c in cells.iter().filter(|c| c.outcome == status) {
            let (cx, cy) = panel.p((c.x, c.y));
            let (ux, uy) = (c.theta.cos(), -c.theta.sin());
            let tip = (cx + 0.6 * len * ux, cy + 0.6 * len * uy);
            let back = (cx - 0.4 * len * ux, cy - 0.4 * len * uy);
            let half = 0.32 * len;
            let left = (back.0 - uy * half, back.1 + ux * half);
            let right = (back.0 + uy * half, back.1 - ux * half);
            svg.polygon(&[tip, left, right], fill, None);
        }
    }
    svg.end_clip();
    // A white halo first: the goal's black arrow stays visible on black (diverged) bins.
    let (ux, uy) = (goal.theta.cos(), -goal.theta.sin());
    svg.arrow(g, (tip.0 + 1.5 * ux, tip.1 + 1.5 * uy), GOAL_HEAD + 3.0, Stroke::solid("#ffffff", 3.8));
    svg.arrow(g, tip, GOAL_HEAD, Stroke::solid("#000000", 1.6));
    svg.circle(g, 5.0, "#ffffff", None);
    svg.circle(g, 3.6, "#ffffff", Some(Stroke::solid("#000000", 1.6)));
    match &inside {
        Some(b) => legend_boxed(&mut svg, b, &entries),
        None => legend_rows(&mut svg, LEFT, legend_y, w, &entries),
    }
    let note = if binned {
        "Each square: the most common outcome of the starts in it."
    } else {
        "Each marker is a start, pointing along the robot's start heading."
    };
    svg.text((LEFT, height - 6.0), note, FONT, Anchor::Start, 0.0, false);
    Ok(svg.finish())
}

/// The starts as a grid of [`BINS`] x [`BINS`] squares over the panel, each coloured by the
/// most common outcome of the starts in it (a tie goes to the outcome listed first in
/// [`Status::ALL`]); empty squares are left blank. Neighbours of one colour in a row are
/// drawn as one rectangle: a map of one outcome is [`BINS`] rectangles, not BINS^2.
fn draw_bins(svg: &mut Svg, panel: &Panel, cells: &[SweepCell]) {
    let mut counts = vec![[0u32; 3]; BINS * BINS];
    let bin =
        |v: f64, (lo, hi): (f64, f64)| (((v - lo) / (hi - lo) * BINS as f64).floor().max(0.0) as usize).min(BINS - 1);
    for c in cells {
        let (i, j) = (bin(c.x, panel.xr), bin(c.y, panel.yr));
        let k = Status::ALL.iter().position(|s| *s == c.outcome).unwrap_or(0);
        counts[j * BINS + i][k] += 1;
    }
    // The outcome drawn in each square, if any start fell in it.
    let shown: Vec<Option<usize>> = counts
        .iter()
        .map(|count| {
            let best = count.iter().enumerate().filter(|(_, c)| **c > 0).max_by_key(|(k, c)| (**c, usize::MAX - k));
            best.map(|(k, _)| k)
        })
        .collect();
    let (bw, bh) = (panel.w / BINS as f64, panel.h / BINS as f64);
    for j in 0..BINS {
        let row = &shown[j * BINS..(j + 1) * BINS];
        let mut i = 0;
        while i < BINS {
            let Some(k) = row[i] else {
                i += 1;
                continue;
            };
            let run = row[i..].iter().take_while(|s| **s == Some(k)).count();
            // Row j counts up from the bottom of the panel (y up). Each rectangle reaches
            // 0.4 pt under its right and upper neighbours (drawn after it, on top), which
            // hides the seams a renderer draws between abutting shapes (0.05 pt did not, in
            // rsvg); the last column and row stay inside the panel.
            let ox = if i + run < BINS { 0.4 } else { 0.0 };
            let oy = if j + 1 < BINS { 0.4 } else { 0.0 };
            let y = panel.y + panel.h - (j + 1) as f64 * bh - oy;
            svg.rect(panel.x + i as f64 * bw, y, run as f64 * bw + ox, bh + oy, status_color(Status::ALL[k]), None);
            i += run;
        }
    }
}
