//! The frame every figure is drawn in: an SVG with a titled Cartesian chart, its axes
//! described, series drawn by the caller, a legend; and the goal marker.

use std::ops::Range;

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use wmr_core::Pose2;

use crate::{PlotError, err};

/// The chart a figure draws its series on: f64 axes in an SVG.
pub type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// How a figure is framed.
pub struct Frame<'a> {
    /// Caption.
    pub title: &'a str,
    /// Size, px.
    pub size: (u32, u32),
    /// Axis ranges.
    pub x: Range<f64>,
    /// Axis ranges.
    pub y: Range<f64>,
    /// Axis descriptions (x, y), with units.
    pub desc: (&'a str, &'a str),
    /// Width of the y label area, px.
    pub y_label_area: u32,
    /// Where the legend goes (plotters' default when `None`).
    pub legend: Option<SeriesLabelPosition>,
}

/// The SVG of `frame` with what `draw` puts on the chart.
pub fn svg_chart(
    frame: Frame<'_>,
    draw: impl FnOnce(&mut Chart<'_, '_>) -> Result<(), PlotError>,
) -> Result<String, PlotError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, frame.size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(frame.title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(40)
            .y_label_area_size(frame.y_label_area)
            .build_cartesian_2d(frame.x, frame.y)
            .map_err(err)?;
        chart.configure_mesh().x_desc(frame.desc.0).y_desc(frame.desc.1).draw().map_err(err)?;
        draw(&mut chart)?;
        let mut labels = chart.configure_series_labels();
        labels.background_style(WHITE.mix(0.8)).border_style(BLACK);
        if let Some(position) = frame.legend {
            labels.position(position);
        }
        labels.draw().map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// The goal as a black cross of `size` px with its heading as a line `arrow` long (m).
pub fn draw_goal(
    chart: &mut Chart<'_, '_>,
    goal: Pose2<f64>,
    arrow: f64,
    size: i32,
    stroke: u32,
) -> Result<(), PlotError> {
    let tip = (goal.x + arrow * goal.theta.cos(), goal.y + arrow * goal.theta.sin());
    chart.draw_series([Cross::new((goal.x, goal.y), size, BLACK.stroke_width(stroke))]).map_err(err)?;
    chart.draw_series([PathElement::new([(goal.x, goal.y), tip], BLACK.stroke_width(stroke - 1))]).map_err(err)?;
    Ok(())
}
