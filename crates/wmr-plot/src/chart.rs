//! What every figure is built from: the page layout (sizes in pt, fonts for print), data
//! panels with ticked axes, a legend in the panel's emptiest corner (or below the figure
//! when every corner would hide data), arrow sizes, the colours.

use crate::svg::{Anchor, Stroke, Svg, escape, math, text_width};

/// Page width of every figure, pt: 400 pt = 141 mm, a little under a journal's full text
/// width; the fonts below are then 8 to 9 pt on paper.
pub(crate) const PAGE_W: f64 = 400.0;
/// Tick labels and legend text, pt.
pub(crate) const FONT: f64 = 8.0;
/// Axis labels, pt.
pub(crate) const FONT_LABEL: f64 = 8.5;
/// Title, pt.
pub(crate) const FONT_TITLE: f64 = 9.0;
/// Space above the first panel for the title, pt.
pub(crate) const TOP: f64 = 24.0;
/// Left margin: tick labels and the y label, pt.
pub(crate) const LEFT: f64 = 50.0;
/// Below the last panel: tick labels and the x label, pt.
pub(crate) const BOTTOM: f64 = 34.0;
/// Right margin, pt.
pub(crate) const RIGHT: f64 = 8.0;
/// Data line width, pt.
pub(crate) const LINE_W: f64 = 1.1;
/// Head length of a heading arrow, pt: a fixed share of the page (1.75 % of its width), not
/// of the data range, so it prints alike in every figure: 2.5 mm on the 141 mm page,
/// 1.5 mm with the figure scaled to a column (85 mm). Its width is 0.9 times its length.
pub(crate) const HEADING_HEAD: f64 = 0.0175 * PAGE_W;
/// Whole length of a heading arrow along a path, pt.
pub(crate) const HEADING_LEN: f64 = 2.4 * HEADING_HEAD;
/// Head and whole length of a goal's arrow, pt.
pub(crate) const GOAL_HEAD: f64 = 1.25 * HEADING_HEAD;
pub(crate) const GOAL_LEN: f64 = 4.0 * HEADING_HEAD;

/// Axis, grid and text grey.
pub(crate) const GRID: &str = "#d9d9d9";
pub(crate) const AXIS: &str = "#404040";

/// Okabe and Ito's colour-blind-safe palette (yellow left out: too light on white),
/// then two greys: distinct runs, distinct laws.
const PALETTE: [&str; 8] = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000", "#7f7f7f"];

/// The colour of run or law `i` (cycled).
pub(crate) fn color(i: usize) -> &'static str {
    PALETTE[i % PALETTE.len()]
}

/// Dash pattern of run or law `i`: solid for the first eight, then dashed, so a colour
/// reused after eight runs is still told apart.
pub(crate) fn dash(i: usize) -> Option<&'static str> {
    match (i / PALETTE.len()) % 3 {
        0 => None,
        1 => Some("4 2"),
        _ => Some("1 2"),
    }
}

/// Ticks of an axis: a "nice" step (1, 2 or 5 times a power of ten) giving about
/// `target` intervals over [lo, hi], and the decimals to print them with.
pub(crate) fn ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, usize) {
    let span = (hi - lo).abs().max(f64::MIN_POSITIVE);
    let raw = span / target.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    // The candidate whose interval count is nearest the target.
    let target = target.max(1) as f64;
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|k| k * mag)
        .min_by(|a, b| ((span / a) - target).abs().total_cmp(&((span / b) - target).abs()))
        .unwrap_or(mag);
    let decimals = if step >= 1.0 { 0 } else { (-step.log10()).ceil() as usize };
    let unit = 10f64.powi(decimals as i32);
    let first = (lo / step).ceil();
    let mut out = Vec::new();
    let mut k = first;
    while k * step <= hi + 1e-9 * span && out.len() < 100 {
        // Rounded to the printed decimals: 0.6, not 0.6000000000000001.
        let v = (k * step * unit).round() / unit;
        out.push(if v == 0.0 { 0.0 } else { v });
        k += 1.0;
    }
    (out, decimals)
}

/// A tick label: fixed decimals, with a true minus sign.
pub(crate) fn tick_label(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    if let Some(rest) = s.strip_prefix('-') {
        if rest.chars().all(|c| c == '0' || c == '.') { rest.to_owned() } else { format!("\u{2212}{rest}") }
    } else {
        s
    }
}

/// Range (lo, hi) of the finite values, widened by `pad` of the span on each side and to
/// at least `min_span`, so a flat line still gets an axis; (-1, 1) when there are none.
pub(crate) fn padded_range(values: impl Iterator<Item = f64>, pad: f64, min_span: f64) -> (f64, f64) {
    let (lo, hi) =
        values.filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    let span = (hi - lo).max(min_span);
    let mid = 0.5 * (lo + hi);
    (mid - 0.5 * span * (1.0 + 2.0 * pad), mid + 0.5 * span * (1.0 + 2.0 * pad))
}

/// A data panel: a rectangle on the page (pt) and the data ranges it shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Panel {
    /// Left and top edges, pt.
    pub x: f64,
    pub y: f64,
    /// Width and height, pt.
    pub w: f64,
    pub h: f64,
    /// Data range on x and on y.
    pub xr: (f64, f64),
    pub yr: (f64, f64),
}

impl Panel {
    /// Page x (pt) of data x.
    pub fn px(&self, x: f64) -> f64 {
        self.x + (x - self.xr.0) / (self.xr.1 - self.xr.0) * self.w
    }

    /// Page y (pt) of data y (up is up).
    pub fn py(&self, y: f64) -> f64 {
        self.y + self.h - (y - self.yr.0) / (self.yr.1 - self.yr.0) * self.h
    }

    /// Page point of a data point.
    pub fn p(&self, (x, y): (f64, f64)) -> (f64, f64) {
        (self.px(x), self.py(y))
    }

    /// pt per data unit along x.
    pub fn scale_x(&self) -> f64 {
        self.w / (self.xr.1 - self.xr.0)
    }

    /// True when the data point lies inside the panel's ranges.
    pub fn contains(&self, (x, y): (f64, f64)) -> bool {
        x >= self.xr.0 && x <= self.xr.1 && y >= self.yr.0 && y <= self.yr.1
    }

    /// Grid, frame, ticks and their labels, the axis labels (markup: see [`math`] and
    /// [`escape`]; `None` leaves the x axis without tick labels and label, e.g. a time
    /// axis shared with the panel below).
    pub fn axes(&self, svg: &mut Svg, x_label: Option<&str>, y_label: &str) {
        let (xt, xd) = ticks(self.xr.0, self.xr.1, (self.w / 50.0).round().max(3.0) as usize);
        let (yt, yd) = ticks(self.yr.0, self.yr.1, (self.h / 30.0).round().max(3.0) as usize);
        let grid = Stroke::solid(GRID, 0.4);
        let tick = Stroke::solid(AXIS, 0.6);
        for &v in &xt {
            let x = self.px(v);
            svg.line((x, self.y), (x, self.y + self.h), grid);
            svg.line((x, self.y + self.h), (x, self.y + self.h + 3.0), tick);
            if x_label.is_some() {
                svg.text((x, self.y + self.h + 12.0), &tick_label(v, xd), FONT, Anchor::Middle, 0.0, false);
            }
        }
        let mut widest: f64 = 0.0;
        for &v in &yt {
            let y = self.py(v);
            svg.line((self.x, y), (self.x + self.w, y), grid);
            svg.line((self.x - 3.0, y), (self.x, y), tick);
            let label = tick_label(v, yd);
            widest = widest.max(text_width(&label, FONT));
            svg.text((self.x - 5.0, y + 0.35 * FONT), &label, FONT, Anchor::End, 0.0, false);
        }
        svg.rect(self.x, self.y, self.w, self.h, "none", Some(Stroke::solid(AXIS, 0.7)));
        if let Some(xl) = x_label {
            svg.text((self.x + 0.5 * self.w, self.y + self.h + 26.0), xl, FONT_LABEL, Anchor::Middle, 0.0, false);
        }
        let ylx = (self.x - widest - 10.0).max(9.0);
        svg.text((ylx, self.y + 0.5 * self.h), y_label, FONT_LABEL, Anchor::Middle, -90.0, false);
    }

    /// A clip path for the panel's rectangle.
    pub fn clip(&self, svg: &mut Svg) -> String {
        svg.clip_rect(self.x, self.y, self.w, self.h)
    }
}

/// A legend entry: its text and its key. `math` marks the figure's own labels, whose
/// `_x` is a subscript; user text (run labels, law names) is drawn as written.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Entry {
    pub label: String,
    pub key: Key,
    pub math: bool,
}

impl Entry {
    /// User text.
    pub fn user(label: impl Into<String>, key: Key) -> Self {
        Self { label: label.into(), key, math: false }
    }

    /// The figure's own text, `_x` a subscript.
    pub fn math(label: impl Into<String>, key: Key) -> Self {
        Self { label: label.into(), key, math: true }
    }
}

/// What a legend entry shows.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Key {
    /// A line in a colour and dash.
    Line(&'static str, Option<&'static str>),
    /// A line with a dot (curves with markers): colour, dash, and the radius of a hollow
    /// ring drawn instead of the dot (0: the dot; `share::dot`).
    LineDot(&'static str, Option<&'static str>, f64),
    /// A filled triangle (a start with its heading).
    Triangle(&'static str),
    /// A filled dot (a start).
    Dot(&'static str),
    /// A small arrow (the heading along a path).
    Arrow(&'static str),
    /// A ring with an arrow (a goal and its heading).
    GoalArrow(&'static str),
    /// A cross (where a run leaves the plot).
    Cross(&'static str),
    /// A filled square with an outline (an obstacle): fill, outline.
    Patch(&'static str, &'static str),
}

/// Width (pt) a legend of `entries` needs.
pub(crate) fn legend_width(entries: &[Entry]) -> f64 {
    let text = entries.iter().map(|e| text_width(&e.label, FONT)).fold(0.0, f64::max);
    if entries.is_empty() { 0.0 } else { 26.0 + text + 6.0 }
}

/// Height (pt) of a legend of `n` entries.
pub(crate) fn legend_height(n: usize) -> f64 {
    n as f64 * 11.5
}

/// The legend, one entry per line, top-left at (x, y) (pt).
pub(crate) fn legend(svg: &mut Svg, x: f64, y: f64, entries: &[Entry]) {
    for (i, e) in entries.iter().enumerate() {
        let yc = y + 11.5 * i as f64 + 5.0;
        let (k0, k1) = (x, x + 18.0);
        match &e.key {
            Key::Line(c, d) => svg.line((k0, yc), (k1, yc), Stroke { dash: *d, ..Stroke::solid(c, 1.4) }),
            Key::Dot(c) => svg.circle((0.5 * (k0 + k1), yc), 2.4, c, None),
            Key::Arrow(c) => svg.arrow((k0, yc), (k1, yc), HEADING_HEAD, Stroke::solid(c, 0.9)),
            Key::GoalArrow(c) => {
                svg.circle((k0 + 3.0, yc), 2.6, "#ffffff", Some(Stroke::solid(c, 1.1)));
                svg.arrow((k0 + 3.0, yc), (k1 + 2.0, yc), HEADING_HEAD, Stroke::solid(c, 1.1));
            }
            Key::LineDot(c, d, ring) => {
                svg.line((k0, yc), (k1, yc), Stroke { dash: *d, ..Stroke::solid(c, 1.4) });
                crate::share::dot(svg, (0.5 * (k0 + k1), yc), c, *ring);
            }
            Key::Triangle(c) => {
                let cx = 0.5 * (k0 + k1);
                svg.polygon(&[(cx + 5.0, yc), (cx - 3.5, yc - 3.5), (cx - 3.5, yc + 3.5)], c, None);
            }
            Key::Cross(c) => cross(svg, (0.5 * (k0 + k1), yc), 3.0, Stroke::solid(c, 1.2)),
            Key::Patch(fill, ink) => {
                let cx = 0.5 * (k0 + k1);
                svg.rect(cx - 5.0, yc - 4.0, 10.0, 8.0, fill, Some(Stroke::solid(ink, 0.8)));
            }
        }
        let markup = if e.math { math(&e.label) } else { escape(&e.label) };
        svg.text((x + 24.0, yc + 0.35 * FONT), &markup, FONT, Anchor::Start, 0.0, false);
    }
}

/// Height (pt) of the legend `legend_rows` draws for `entries` within `width` pt.
pub(crate) fn rows_height(entries: &[Entry], width: f64) -> f64 {
    legend_height(row_layout(entries, width).iter().map(|(_, row)| *row).max().map_or(0, |r| r + 1))
}

/// Where each entry goes in rows across `width` pt: (x offset, row). The entries are laid
/// on a grid of equal columns, as many as fit (the widest entry sets the column width), so
/// the keys line up from row to row.
fn row_layout(entries: &[Entry], width: f64) -> Vec<(f64, usize)> {
    let col_w = legend_width(entries) + 8.0;
    let cols = ((width / col_w).floor() as usize).clamp(1, entries.len().max(1));
    (0..entries.len()).map(|i| ((i % cols) as f64 * col_w, i / cols)).collect()
}

/// The legend in rows, filling `width` pt from (x, y) (pt), for legends below the data.
pub(crate) fn legend_rows(svg: &mut Svg, x: f64, y: f64, width: f64, entries: &[Entry]) {
    for (e, (dx, row)) in entries.iter().zip(row_layout(entries, width)) {
        legend(svg, x + dx, y + 11.5 * row as f64, std::slice::from_ref(e));
    }
}

/// What a figure draws in a panel, as page points (pt) for placing a legend: every line
/// sampled once per point of its length, and every marker as one point. A legend's cost
/// in a corner is the number of these under it, about the length (pt) of line it hides.
#[derive(Clone, Debug, Default)]
pub(crate) struct Ink(Vec<(f64, f64)>);

impl Ink {
    /// A polyline (pt), sampled every point of its length (and at every vertex).
    pub fn line(&mut self, pts: &[(f64, f64)]) {
        if let Some(first) = pts.first() {
            self.0.push(*first);
        }
        for w in pts.windows(2) {
            let (a, b) = (w[0], w[1]);
            let len = (b.0 - a.0).hypot(b.1 - a.1);
            // A segment leaving the page (a diverging run) is cut at 2,000 pt.
            let n = len.min(2000.0).ceil() as usize;
            for k in 1..=n {
                let f = k as f64 / n as f64;
                self.0.push((a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1)));
            }
        }
    }

    /// A marker (pt).
    pub fn point(&mut self, p: (f64, f64)) {
        self.0.push(p);
    }

    /// Points in the rectangle at (x, y) of w x h (pt).
    pub fn count_in(&self, x: f64, y: f64, w: f64, h: f64) -> usize {
        self.0.iter().filter(|(px, py)| *px >= x && *px <= x + w && *py >= y && *py <= y + h).count()
    }

    /// Points inside the panel.
    pub fn count_on(&self, panel: &Panel) -> usize {
        self.count_in(panel.x, panel.y, panel.w, panel.h)
    }
}

/// Gap between a legend inside a panel and the panel's frame, pt.
const LEGEND_INSET: f64 = 4.0;
/// Padding inside a legend's box, pt.
const LEGEND_PAD: f64 = 4.0;
/// Gap between the columns of a legend, pt.
const LEGEND_COL_GAP: f64 = 6.0;
/// Most of the lines (see [`Ink`]) a legend inside a panel may cover: this share of the
/// panel's, and never more than [`LEGEND_MAX_COVER`] points (about that many pt of line,
/// 5 cm on the page). Under its translucent box a line stays visible, but a legend on the
/// data is still in the way.
pub(crate) const LINES_MAX_SHARE: f64 = 0.02;
const LEGEND_MAX_COVER: usize = 150;

/// A legend inside a panel: its box (pt) and its entries in columns.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LegendBox {
    /// Left and top edges of the box, pt.
    pub x: f64,
    pub y: f64,
    /// Width and height of the box, pt.
    pub w: f64,
    pub h: f64,
    /// Entries per column, column by column.
    pub rows: usize,
    /// Width of each column, pt.
    pub col_w: Vec<f64>,
}

/// Column widths (pt) of `entries` laid out `rows` to a column.
fn columns(entries: &[Entry], rows: usize) -> Vec<f64> {
    entries.chunks(rows.max(1)).map(legend_width).collect()
}

/// The legend's place inside `panel`: of the four corners and one to three columns, the
/// box that covers the least of `ink` (ties: fewer columns, then top right, top left,
/// bottom right, bottom left); `None` when even that one covers more than `max_share` of
/// the panel's ink (see [`LINES_MAX_SHARE`]; 0 for markers, none of which may be hidden)
/// or none fits: the legend then goes below the figure.
pub(crate) fn place_legend(panel: &Panel, entries: &[Entry], ink: &Ink, max_share: f64) -> Option<LegendBox> {
    if entries.is_empty() {
        return None;
    }
    let allowed = ((max_share * ink.count_on(panel) as f64) as usize).min(LEGEND_MAX_COVER);
    let mut best: Option<(usize, LegendBox)> = None;
    for cols in 1..=entries.len().min(3) {
        let rows = entries.len().div_ceil(cols);
        let col_w = columns(entries, rows);
        let w = col_w.iter().sum::<f64>() + LEGEND_COL_GAP * (col_w.len() - 1) as f64 + 2.0 * LEGEND_PAD - 6.0;
        let h = legend_height(rows) + 2.0 * LEGEND_PAD - 1.5;
        if w + 2.0 * LEGEND_INSET > panel.w || h + 2.0 * LEGEND_INSET > panel.h {
            continue;
        }
        let (left, right) = (panel.x + LEGEND_INSET, panel.x + panel.w - LEGEND_INSET - w);
        let (top, bottom) = (panel.y + LEGEND_INSET, panel.y + panel.h - LEGEND_INSET - h);
        for (x, y) in [(right, top), (left, top), (right, bottom), (left, bottom)] {
            // Ink just outside the box counts too: text right against a line is hard to read.
            let cost = ink.count_in(x - 1.5, y - 1.5, w + 3.0, h + 3.0);
            if best.as_ref().is_none_or(|(c, _)| cost < *c) {
                best = Some((cost, LegendBox { x, y, w, h, rows, col_w: col_w.clone() }));
            }
        }
    }
    best.filter(|(cost, _)| *cost <= allowed).map(|(_, b)| b)
}

/// The legend in its box inside a panel: a white, slightly translucent box (a line under
/// it stays visible) with a light outline, the entries in columns on it.
pub(crate) fn legend_boxed(svg: &mut Svg, b: &LegendBox, entries: &[Entry]) {
    svg.rect_class("legend", b.x, b.y, b.w, b.h, "#ffffff", 0.8, Some(Stroke::solid("#bfbfbf", 0.5)));
    let mut x = b.x + LEGEND_PAD;
    for (chunk, w) in entries.chunks(b.rows.max(1)).zip(&b.col_w) {
        legend(svg, x, b.y + LEGEND_PAD, chunk);
        x += w + LEGEND_COL_GAP;
    }
}

/// An x-shaped cross centred at `c` (pt), half-size `r` (pt).
pub(crate) fn cross(svg: &mut Svg, c: (f64, f64), r: f64, s: Stroke<'_>) {
    svg.line((c.0 - r, c.1 - r), (c.0 + r, c.1 + r), s);
    svg.line((c.0 - r, c.1 + r), (c.0 + r, c.1 - r), s);
}

/// The figure's title, centred over the panels.
pub(crate) fn title(svg: &mut Svg, panel_x: f64, panel_w: f64, text: &str) {
    svg.text((panel_x + 0.5 * panel_w, 14.0), &escape(text), FONT_TITLE, Anchor::Middle, 0.0, true);
}

/// A panel as wide as the page between its margins, as tall as the data's aspect allows
/// within `aspect` (min, max, height over width), one data unit as long on both axes.
pub(crate) fn page_wide_panel(xr: (f64, f64), yr: (f64, f64), aspect: (f64, f64)) -> Panel {
    let w = PAGE_W - LEFT - RIGHT;
    let h = w * ((yr.1 - yr.0) / (xr.1 - xr.0)).clamp(aspect.0, aspect.1);
    let (xr, yr) = equal_aspect(xr, yr, w, h);
    Panel { x: LEFT, y: TOP, w, h, xr, yr }
}

/// The legend's box in the emptiest corner of `panel` ([`place_legend`]; `None`: rows
/// below the panel) and the page sized for it, with its title.
pub(crate) fn page_with_legend(
    panel: &Panel,
    entries: &[Entry],
    ink: &Ink,
    title_text: &str,
) -> (Option<LegendBox>, Svg) {
    let inside = place_legend(panel, entries, ink, LINES_MAX_SHARE);
    let height = match inside {
        Some(_) => TOP + panel.h + BOTTOM,
        None => TOP + panel.h + BOTTOM + 4.0 + rows_height(entries, panel.w),
    };
    let mut svg = Svg::new(PAGE_W, height);
    title(&mut svg, panel.x, panel.w, title_text);
    (inside, svg)
}

/// Widens the ranges (lo, hi) of x and y so that one data unit is as long on both axes
/// for a panel of w x h pt: the shorter side grows about its middle.
pub(crate) fn equal_aspect(xr: (f64, f64), yr: (f64, f64), w: f64, h: f64) -> ((f64, f64), (f64, f64)) {
    let (sx, sy) = (xr.1 - xr.0, yr.1 - yr.0);
    if sx / sy > w / h {
        let want = sx * h / w;
        let mid = 0.5 * (yr.0 + yr.1);
        (xr, (mid - 0.5 * want, mid + 0.5 * want))
    } else {
        let want = sy * w / h;
        let mid = 0.5 * (xr.0 + xr.1);
        ((mid - 0.5 * want, mid + 0.5 * want), yr)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_nice_and_cover_the_range() {
        let (t, d) = ticks(0.0, 1.0, 5);
        assert_eq!(t, vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
        assert_eq!(d, 1);
        let (t, d) = ticks(-3.2, 41.0, 4);
        assert_eq!(t, vec![0.0, 10.0, 20.0, 30.0, 40.0]);
        assert_eq!(d, 0);
        assert_eq!(tick_label(-0.5, 1), "\u{2212}0.5");
        assert_eq!(tick_label(-0.0001, 1), "0.0");
    }

    #[test]
    fn equal_aspect_gives_one_scale() {
        let (xr, yr) = equal_aspect((0.0, 4.0), (0.0, 1.0), 300.0, 200.0);
        let sx = 300.0 / (xr.1 - xr.0);
        let sy = 200.0 / (yr.1 - yr.0);
        assert!((sx - sy).abs() < 1e-12, "{sx} {sy}");
        assert_eq!(xr, (0.0, 4.0));
    }
}
