//! Robustness curves: the share of runs each law brings to the goal against one varied
//! key (sensor noise, latency, a model mismatch, a slope).

use crate::PlotError;
use crate::chart::{
    BOTTOM, Entry, Ink, Key, LEFT, LINE_W, PAGE_W, Panel, RIGHT, TOP, color, legend_boxed, legend_rows,
    page_with_legend,
};
use crate::svg::{Stroke, escape};

/// One law's curve: its name and (value of the key, converged share in 0..1) points.
pub type ShareSeries<'a> = (&'a str, Vec<(f64, f64)>);

/// Converged share (%) against the varied key, one line with dots per law (colours in
/// law order, as in every other figure), the legend in the panel's emptiest corner, or
/// below it when every corner would hide a curve.
pub fn share_svg(title_text: &str, key_desc: &str, series: &[ShareSeries<'_>]) -> Result<String, PlotError> {
    let xs = series.iter().flat_map(|(_, p)| p.iter().map(|(x, _)| *x)).filter(|x| x.is_finite());
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)));
    let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
    let pad = if hi > lo { 0.04 * (hi - lo) } else { 0.5f64.max(0.05 * lo.abs()) };
    let entries: Vec<Entry> =
        series.iter().enumerate().map(|(i, (law, _))| Entry::user(*law, Key::LineDot(color(i)))).collect();
    let w = PAGE_W - LEFT - RIGHT;
    let h = 150.0;
    let panel = Panel { x: LEFT, y: TOP, w, h, xr: (lo - pad, hi + pad), yr: (-3.0, 103.0) };
    let curves: Vec<Vec<(f64, f64)>> = series
        .iter()
        .map(|(_, points)| {
            points
                .iter()
                .filter(|(x, s)| x.is_finite() && s.is_finite())
                .map(|(x, s)| panel.p((*x, 100.0 * s)))
                .collect()
        })
        .collect();
    let mut ink = Ink::default();
    for c in &curves {
        ink.line(c);
    }
    let (inside, mut svg) = page_with_legend(&panel, &entries, &ink, title_text);
    panel.axes(&mut svg, Some(&escape(key_desc)), "converged (%)");
    for (i, pts) in curves.iter().enumerate() {
        svg.polyline(pts, Stroke::solid(color(i), LINE_W));
        for p in pts {
            svg.circle(*p, 2.2, color(i), None);
        }
    }
    match &inside {
        Some(b) => legend_boxed(&mut svg, b, &entries),
        None => legend_rows(&mut svg, LEFT, TOP + h + BOTTOM, w, &entries),
    }
    Ok(svg.finish())
}
