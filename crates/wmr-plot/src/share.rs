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
    let looks = looks(&curves);
    let entries: Vec<Entry> = series
        .iter()
        .zip(&looks)
        .enumerate()
        .map(|(i, ((law, _), look))| Entry::user(*law, Key::LineDot(color(i), look.dash, look.ring)))
        .collect();
    let mut ink = Ink::default();
    for c in &curves {
        ink.line(c);
    }
    let (inside, mut svg) = page_with_legend(&panel, &entries, &ink, title_text);
    panel.axes(&mut svg, Some(&escape(key_desc)), "converged (%)");
    for (i, (pts, look)) in curves.iter().zip(&looks).enumerate() {
        svg.polyline(pts, Stroke { dash: look.dash, ..Stroke::solid(color(i), LINE_W) });
        for p in pts {
            dot(&mut svg, *p, color(i), look.ring);
        }
    }
    match &inside {
        Some(b) => legend_boxed(&mut svg, b, &entries),
        None => legend_rows(&mut svg, LEFT, TOP + h + BOTTOM, w, &entries),
    }
    Ok(svg.finish())
}

/// How a curve is drawn so that one lying on earlier ones does not hide them: the first
/// of a bundle solid with filled dots; the k-th on top dashed (the colours below show in
/// its gaps) with hollow rings of growing radius around the dots below.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Look {
    dash: Option<&'static str>,
    /// Radius (pt) of the hollow ring around each point; 0: a filled dot.
    ring: f64,
}

/// Dash patterns of the curves drawn on top of 1, 2, 3... earlier ones.
const ON_TOP_DASHES: [&str; 3] = ["6 4", "2 3", "8 3 2 3"];

/// Points closer than this (pt) are the same point on the page.
const SAME_POINT_PT: f64 = 0.5;

fn looks(curves: &[Vec<(f64, f64)>]) -> Vec<Look> {
    let same = |a: &[(f64, f64)], b: &[(f64, f64)]| {
        a.len() == b.len()
            && a.iter().zip(b).all(|(p, q)| (p.0 - q.0).abs() < SAME_POINT_PT && (p.1 - q.1).abs() < SAME_POINT_PT)
    };
    curves
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let below = curves[..i].iter().filter(|e| !c.is_empty() && same(e, c)).count();
            match below {
                0 => Look { dash: None, ring: 0.0 },
                k => Look { dash: Some(ON_TOP_DASHES[(k - 1) % ON_TOP_DASHES.len()]), ring: 2.2 + 1.6 * k as f64 },
            }
        })
        .collect()
}

/// A curve's marker at `p`: a filled dot, or a hollow ring of radius `ring`.
pub(crate) fn dot(svg: &mut crate::svg::Svg, p: (f64, f64), c: &'static str, ring: f64) {
    if ring > 0.0 {
        svg.circle(p, ring, "none", Some(Stroke::solid(c, 1.0)));
    } else {
        svg.circle(p, 2.2, c, None);
    }
}
