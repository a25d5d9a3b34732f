//! Time-series and path figures of single scenarios (the paper's Figs. 4-9).

use plotters::prelude::*;

use crate::chart::{Frame, draw_goal, svg_chart};
use crate::{PlotError, SIZE, Trace, err, padded_range, palette};

/// Paths of C in the plane, one line per run, with start and goal markers and the goal
/// heading as a short arrow (the paper's Figs. 4-7). Equal scale on x and y.
pub fn paths_svg(title: &str, traces: &[Trace<'_>]) -> Result<String, PlotError> {
    let xs = traces.iter().flat_map(|t| t.samples.iter().map(|s| s.state.x).chain([t.goal.x]));
    let ys = traces.iter().flat_map(|t| t.samples.iter().map(|s| s.state.y).chain([t.goal.y]));
    let (x0, x1) = padded_range(xs, 0.08, 0.5);
    let (y0, y1) = padded_range(ys, 0.08, 0.5);
    // Equal scale: widen the shorter axis to the plot's aspect ratio.
    let aspect = f64::from(SIZE.0 - 90) / f64::from(SIZE.1 - 90);
    let (w, h) = (x1 - x0, y1 - y0);
    let (x0, x1, y0, y1) = if w / h > aspect {
        let extra = (w / aspect - h) / 2.0;
        (x0, x1, y0 - extra, y1 + extra)
    } else {
        let extra = (h * aspect - w) / 2.0;
        (x0 - extra, x1 + extra, y0, y1)
    };
    let arrow = 0.06 * (x1 - x0);
    let frame = Frame {
        title,
        size: SIZE,
        x: x0..x1,
        y: y0..y1,
        desc: ("x (m)", "y (m)"),
        y_label_area: 55,
        legend: Some(SeriesLabelPosition::UpperLeft),
    };
    svg_chart(frame, |chart| {
        for (i, t) in traces.iter().enumerate() {
            let color = palette(i);
            chart
                .draw_series(LineSeries::new(t.samples.iter().map(|s| (s.state.x, s.state.y)), color.stroke_width(2)))
                .map_err(err)?
                .label(t.label)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color.stroke_width(2)));
            if let Some(s0) = t.samples.first() {
                chart.draw_series([Circle::new((s0.state.x, s0.state.y), 4, color.filled())]).map_err(err)?;
            }
            draw_goal(chart, t.goal, arrow, 6, 2)?;
        }
        Ok(())
    })
}

/// Several named series over time in one panel.
fn time_series_svg(title: &str, y_desc: &str, t: &[f64], series: &[(&str, Vec<f64>)]) -> Result<String, PlotError> {
    let t_end = t.last().copied().unwrap_or(1.0).max(1e-9);
    let (y0, y1) = padded_range(series.iter().flat_map(|(_, v)| v.iter().copied()), 0.05, 1e-3);
    let frame = Frame {
        title,
        size: (SIZE.0, SIZE.1 * 3 / 4),
        x: 0.0..t_end,
        y: y0..y1,
        desc: ("t (s)", y_desc),
        y_label_area: 60,
        legend: None,
    };
    svg_chart(frame, |chart| {
        for (i, (name, v)) in series.iter().enumerate() {
            let color = palette(i);
            chart
                .draw_series(LineSeries::new(t.iter().copied().zip(v.iter().copied()), color.stroke_width(2)))
                .map_err(err)?
                .label(*name)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color.stroke_width(2)));
        }
        Ok(())
    })
}

/// Right and left wheel speeds over time, rad/s (the paper's Fig. 8).
pub fn wheel_speeds_svg(title: &str, trace: &Trace<'_>) -> Result<String, PlotError> {
    let t: Vec<f64> = trace.samples.iter().map(|s| s.t).collect();
    let wr = trace.samples.iter().map(|s| s.wheel_speeds.right).collect();
    let wl = trace.samples.iter().map(|s| s.wheel_speeds.left).collect();
    time_series_svg(title, "wheel speed (rad/s)", &t, &[("omega_r", wr), ("omega_l", wl)])
}

/// Position error dl (m), path error e_s (m) and heading error e_theta (rad) over time
/// (the paper's Fig. 9).
pub fn errors_svg(title: &str, trace: &Trace<'_>) -> Result<String, PlotError> {
    let t: Vec<f64> = trace.samples.iter().map(|s| s.t).collect();
    let dl = trace.samples.iter().map(|s| s.errors.dl).collect();
    let es = trace.samples.iter().map(|s| s.errors.e_s).collect();
    let eth = trace.samples.iter().map(|s| s.errors.e_theta).collect();
    time_series_svg(title, "error (m, rad)", &t, &[("dl (m)", dl), ("e_s (m)", es), ("e_theta (rad)", eth)])
}
