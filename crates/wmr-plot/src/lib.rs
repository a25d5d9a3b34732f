//! SVG figures of simulation runs, made for print: paths (the paper's Figs. 4-7, and the
//! paths of several laws from one start), wheel speeds (Fig. 8), the law's errors (Fig. 9),
//! region-of-attraction maps of sweeps, and converged-share curves of robustness sweeps.
//!
//! Every figure is 141 mm wide (400 pt) with 8 to 9 pt text, coordinates written to a
//! hundredth of a point (smooth curves at any resolution), colours from Okabe and Ito's
//! colour-blind-safe palette (one per run, carried to its start and goal markers),
//! legends inside the plot in the corner where they hide the least data (on a light box),
//! or below the figure when every corner would hide too much, arrows sized to the page
//! (legible with the figure scaled to a column), and equal scale on both axes of every map.
//! Every function returns the SVG document as a `String`; writing it (atomically) is the
//! caller's job, so this crate does no file I/O. Text is SVG `<text>`, set by the viewer
//! in DejaVu Sans, Helvetica or Arial: no font library is needed.

mod chart;
mod figures;
mod region;
mod share;
mod svg;

pub use figures::{ReplayRun, errors_svg, paths_among_svg, paths_svg, replay_svg, wheel_speeds_svg};
pub use region::{BINS, CellOutcome, MAX_MARKERS, SweepCell, region_svg};
pub use share::{ShareSeries, share_svg};

use wmr_core::{Pose2, Sample, Status};

/// One run to plot: its label, goal and logged samples.
#[derive(Clone, Copy, Debug)]
pub struct Trace<'a> {
    /// Legend label.
    pub label: &'a str,
    /// Goal pose of C (m, m, rad).
    pub goal: Pose2<f64>,
    /// Logged samples, in time order.
    pub samples: &'a [Sample<f64>],
    /// A tracking run's reference pose of C at each sample's time (m, m, rad); empty for a
    /// run to a goal. The path figure draws it dashed instead of the goal, the errors
    /// figure measures the heading against it.
    pub reference: &'a [Pose2<f64>],
}

/// A plot could not be drawn.
#[derive(Debug)]
pub struct PlotError(String);

impl PlotError {
    fn new(msg: impl Into<String>) -> Self {
        Self(msg.into())
    }
}

impl core::fmt::Display for PlotError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "plot: {}", self.0)
    }
}

impl std::error::Error for PlotError {}

/// The colour of an outcome in every figure: bluish green converged, orange unsettled,
/// reddish purple cannot_follow, vermillion collided (Okabe and Ito), black diverged (the
/// worst, and told apart from the others by anyone).
pub fn status_color(s: Status) -> &'static str {
    match s {
        Status::Converged => "#009E73",
        Status::Diverged => "#000000",
        Status::Unsettled => "#E69F00",
        Status::CannotFollow => "#CC79A7",
        Status::Collided => "#D55E00",
        // A status added later: grey until it is given a colour of its own.
        _ => "#999999",
    }
}
