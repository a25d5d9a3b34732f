//! A sweep outcome as one row of the sweep CSV.

use super::outcome::SweepOutcome;
use super::spec::SweepSpec;

/// Columns of the sweep CSV, in order.
pub const SWEEP_COLUMNS: [&str; 12] = [
    "law",
    "start",
    "x0",
    "y0",
    "theta0_deg",
    "status",
    "time_to_1cm_s",
    "final_dl_m",
    "final_heading_error_deg",
    "peak_wheel_speed_rad_s",
    "path_length_m",
    "energy_j",
];

/// One CSV row of a sweep outcome, as strings in [`SWEEP_COLUMNS`] order.
pub fn sweep_row(spec: &SweepSpec, o: &SweepOutcome) -> [String; 12] {
    let out = &o.outcome;
    [
        spec.laws[o.law].0.clone(),
        o.start_index.to_string(),
        o.start.x.to_string(),
        o.start.y.to_string(),
        o.start.theta.to_degrees().to_string(),
        o.status().name().to_owned(),
        out.time_to_arrival.map(|t| t.to_string()).unwrap_or_default(),
        out.final_dl.to_string(),
        out.final_heading_error.to_degrees().to_string(),
        out.peak_wheel_speed.to_string(),
        out.path_length.to_string(),
        out.energy.to_string(),
    ]
}
