//! Region-of-attraction map: the start plane coloured by each start's outcome.

use plotters::prelude::*;

use crate::chart::{Frame, draw_goal, svg_chart};
use crate::{PlotError, SIZE, err, padded_range};
use wmr_core::Pose2;

/// How one start of a sweep ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellOutcome {
    /// Within 1 cm of the goal at the end.
    Converged,
    /// Finite, inside the box, but not within 1 cm at the end.
    Unsettled,
    /// Stopped: non-finite state or left the 1 km box.
    Diverged,
}

impl CellOutcome {
    fn color(self) -> RGBColor {
        match self {
            CellOutcome::Converged => RGBColor(44, 160, 44),
            CellOutcome::Unsettled => RGBColor(255, 165, 0),
            CellOutcome::Diverged => RGBColor(214, 39, 40),
        }
    }

    fn label(self) -> &'static str {
        match self {
            CellOutcome::Converged => "converged",
            CellOutcome::Unsettled => "unsettled",
            CellOutcome::Diverged => "diverged",
        }
    }
}

/// One start of a sweep: start position of C (m) and its outcome.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepCell {
    /// Start x of C, m.
    pub x: f64,
    /// Start y of C, m.
    pub y: f64,
    /// Outcome.
    pub outcome: CellOutcome,
}

/// Map of the start plane for one law: one square marker per start, coloured by outcome,
/// and the goal as a black cross with its heading.
pub fn region_svg(title: &str, cells: &[SweepCell], goal: Pose2<f64>) -> Result<String, PlotError> {
    let (x0, x1) = padded_range(cells.iter().map(|c| c.x).chain([goal.x]), 0.05, 0.5);
    let (y0, y1) = padded_range(cells.iter().map(|c| c.y).chain([goal.y]), 0.05, 0.5);
    let frame = Frame {
        title,
        size: SIZE,
        x: x0..x1,
        y: y0..y1,
        desc: ("start x (m)", "start y (m)"),
        y_label_area: 55,
        legend: None,
    };
    svg_chart(frame, |chart| {
        for kind in [CellOutcome::Converged, CellOutcome::Unsettled, CellOutcome::Diverged] {
            let color = kind.color();
            let n = cells.iter().filter(|c| c.outcome == kind).count();
            chart
                .draw_series(
                    cells
                        .iter()
                        .filter(|c| c.outcome == kind)
                        .map(|c| Rectangle::new(marker(c.x, c.y, x1 - x0, y1 - y0), color.filled())),
                )
                .map_err(err)?
                .label(format!("{} ({n})", kind.label()))
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 10, y + 5)], color.filled()));
        }
        draw_goal(chart, goal, 0.06 * (x1 - x0), 8, 3)
    })
}

/// A small square around (x, y), 0.8% of the plot span.
fn marker(x: f64, y: f64, span_x: f64, span_y: f64) -> [(f64, f64); 2] {
    let (hx, hy) = (0.008 * span_x, 0.008 * span_y);
    [(x - hx, y - hy), (x + hx, y + hy)]
}
