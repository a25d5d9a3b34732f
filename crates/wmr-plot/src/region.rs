//! Region-of-attraction map: the start plane coloured by each start's outcome.

use plotters::prelude::*;

use crate::{PlotError, SIZE, err, padded_range};
use wmr_core::Pose2;

/// How one start of a sweep ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellOutcome {
    /// Within 1 cm of the goal at the end.
    Converged,
    /// Finite but not within 1 cm at the end.
    NotConverged,
    /// Stopped: non-finite state or left the 1 km box.
    Diverged,
}

impl CellOutcome {
    fn color(self) -> RGBColor {
        match self {
            CellOutcome::Converged => RGBColor(44, 160, 44),
            CellOutcome::NotConverged => RGBColor(255, 165, 0),
            CellOutcome::Diverged => RGBColor(214, 39, 40),
        }
    }

    fn label(self) -> &'static str {
        match self {
            CellOutcome::Converged => "converged",
            CellOutcome::NotConverged => "not converged",
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
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(40)
            .y_label_area_size(55)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        chart.configure_mesh().x_desc("start x (m)").y_desc("start y (m)").draw().map_err(err)?;
        for kind in [CellOutcome::Converged, CellOutcome::NotConverged, CellOutcome::Diverged] {
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
        let arrow = 0.06 * (x1 - x0);
        chart.draw_series([Cross::new((goal.x, goal.y), 8, BLACK.stroke_width(3))]).map_err(err)?;
        chart
            .draw_series([PathElement::new(
                [(goal.x, goal.y), (goal.x + arrow * goal.theta.cos(), goal.y + arrow * goal.theta.sin())],
                BLACK.stroke_width(2),
            )])
            .map_err(err)?;
        chart.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw().map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// A small square around (x, y), 0.8% of the plot span.
fn marker(x: f64, y: f64, span_x: f64, span_y: f64) -> [(f64, f64); 2] {
    let (hx, hy) = (0.008 * span_x, 0.008 * span_y);
    [(x - hx, y - hy), (x + hx, y + hy)]
}
