//! Robustness curves: the share of runs each law brings to the goal against one varied
//! key (sensor noise, latency, a model mismatch, a slope).

use plotters::prelude::*;

use crate::chart::{Frame, svg_chart};
use crate::{PlotError, SIZE, err, palette};

/// One law's curve: its name and (value of the key, converged share in 0..1) points.
pub type ShareSeries<'a> = (&'a str, Vec<(f64, f64)>);

/// Converged share (%) against the varied key, one line with markers per law.
pub fn share_svg(title: &str, key_desc: &str, series: &[ShareSeries<'_>]) -> Result<String, PlotError> {
    let xs = series.iter().flat_map(|(_, p)| p.iter().map(|(x, _)| *x));
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)));
    let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
    let pad = if hi > lo { 0.05 * (hi - lo) } else { 0.5f64.max(0.05 * lo.abs()) };
    let frame = Frame {
        title,
        size: (SIZE.0, SIZE.1 * 3 / 4),
        x: lo - pad..hi + pad,
        y: -2.0..102.0,
        desc: (key_desc, "converged (%)"),
        y_label_area: 60,
        legend: Some(SeriesLabelPosition::LowerLeft),
    };
    svg_chart(frame, |chart| {
        for (i, (law, points)) in series.iter().enumerate() {
            let color = palette(i);
            let pts: Vec<(f64, f64)> =
                points.iter().filter(|(_, s)| s.is_finite()).map(|(x, s)| (*x, 100.0 * s)).collect();
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), color.stroke_width(2)))
                .map_err(err)?
                .label(*law)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color.stroke_width(2)));
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled()))).map_err(err)?;
        }
        Ok(())
    })
}
