//! SVG plots of simulation runs: paths (the paper's Figs. 4-7), wheel speeds (Fig. 8),
//! position and heading errors (Fig. 9), and region-of-attraction maps of sweeps.
//!
//! Every function returns the SVG document as a `String`; writing it (atomically) is the
//! caller's job, so this crate does no file I/O. Text is emitted as SVG `<text>`, rendered
//! by the viewer: no font library is needed.

mod chart;
mod figures;
mod region;
mod share;

pub use figures::{errors_svg, paths_svg, wheel_speeds_svg};
pub use region::{CellOutcome, SweepCell, region_svg};
pub use share::{ShareSeries, share_svg};

use wmr_core::{Pose2, Sample};

/// One run to plot: its label, goal and logged samples.
#[derive(Clone, Copy, Debug)]
pub struct Trace<'a> {
    /// Legend label.
    pub label: &'a str,
    /// Goal pose of C (m, m, rad).
    pub goal: Pose2<f64>,
    /// Logged samples, in time order.
    pub samples: &'a [Sample<f64>],
}

/// A plot could not be drawn.
#[derive(Debug)]
pub struct PlotError(String);

impl core::fmt::Display for PlotError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "plot: {}", self.0)
    }
}

impl std::error::Error for PlotError {}

fn err<E: core::fmt::Debug>(e: E) -> PlotError {
    PlotError(format!("{e:?}"))
}

/// Figure size, px.
const SIZE: (u32, u32) = (900, 700);

/// Distinct line colours, cycled over runs.
fn palette(i: usize) -> plotters::style::RGBColor {
    use plotters::style::RGBColor;
    const COLORS: [RGBColor; 8] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(23, 190, 207),
    ];
    COLORS[i % COLORS.len()]
}

/// Range (lo, hi) of an iterator of finite values, padded by `pad` of the span (and at
/// least `min_span`), so a flat line still gets a visible axis.
fn padded_range(values: impl Iterator<Item = f64>, pad: f64, min_span: f64) -> (f64, f64) {
    let (lo, hi) =
        values.filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    let span = (hi - lo).max(min_span);
    let mid = 0.5 * (lo + hi);
    (mid - 0.5 * span * (1.0 + 2.0 * pad), mid + 0.5 * span * (1.0 + 2.0 * pad))
}
