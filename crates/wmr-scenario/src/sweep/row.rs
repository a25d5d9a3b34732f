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

/// Columns of the CSV of a sweep over references, in order: the law, the reference, the
/// start (its index, its pose, the offset from the reference's pose at t = 0), the
/// status judged by the tracking error, then the tracking figures (the error is the true
/// distance from C to C_ref, or to the path for path following: RMS and maximum over the
/// last half of t_end, final) and the drive figures of [`SWEEP_COLUMNS`].
pub const TRACKING_SWEEP_COLUMNS: [&str; 17] = [
    "law",
    "reference",
    "start",
    "x0",
    "y0",
    "theta0_deg",
    "dx0",
    "dy0",
    "dtheta0_deg",
    "status",
    "time_to_tolerance_s",
    "rms_error_m",
    "max_error_m",
    "final_error_m",
    "peak_wheel_speed_rad_s",
    "path_length_m",
    "energy_j",
];

/// Longest decimal a CSV field holds; a longer one (|v| below about 1e-14, or huge) is
/// written in exponent form.
const MAX_DECIMAL_CHARS: usize = 32;

/// A number as a CSV field: the shortest text that reads back to `v` (Rust's `Display`),
/// or, when that decimal is longer than [`MAX_DECIMAL_CHARS`], its shortest exponent form
/// (`1e300`, not 301 digits; `5e-324`).
pub fn csv_num(v: f64) -> String {
    let d = v.to_string();
    if d.len() > MAX_DECIMAL_CHARS { format!("{v:e}") } else { d }
}

/// One CSV row of a sweep outcome, as strings in [`SWEEP_COLUMNS`] order.
pub fn sweep_row(spec: &SweepSpec, o: &SweepOutcome) -> [String; 12] {
    let out = &o.outcome;
    [
        spec.laws[o.law].0.clone(),
        o.start_index.to_string(),
        csv_num(o.start.x),
        csv_num(o.start.y),
        csv_num(o.start.theta.to_degrees()),
        o.status().name().to_owned(),
        out.time_to_arrival.map(csv_num).unwrap_or_default(),
        csv_num(out.final_dl),
        csv_num(out.final_heading_error.to_degrees()),
        csv_num(out.peak_wheel_speed),
        csv_num(out.path_length),
        csv_num(out.energy),
    ]
}

/// One CSV row of an outcome of a sweep over references, in [`TRACKING_SWEEP_COLUMNS`]
/// order; `None` for an outcome without a tracking outcome.
pub fn tracking_sweep_row(spec: &SweepSpec, o: &SweepOutcome) -> Option<[String; 17]> {
    let (tr, refs) = (o.tracking.as_ref()?, spec.tracking.as_ref()?);
    let out = &o.outcome;
    let offset = spec.starts[o.start_index];
    Some([
        spec.laws[o.law].0.clone(),
        refs.references[o.reference].0.clone(),
        o.start_index.to_string(),
        csv_num(o.start.x),
        csv_num(o.start.y),
        csv_num(o.start.theta.to_degrees()),
        csv_num(offset.x),
        csv_num(offset.y),
        csv_num(offset.theta.to_degrees()),
        o.status().name().to_owned(),
        tr.time_to_tolerance.map(csv_num).unwrap_or_default(),
        csv_num(tr.rms_last_half),
        csv_num(tr.max_last_half),
        csv_num(tr.final_error),
        csv_num(out.peak_wheel_speed),
        csv_num(out.path_length),
        csv_num(out.energy),
    ])
}

#[cfg(test)]
mod tests {
    use super::csv_num;

    #[test]
    fn numbers_read_back_exactly_and_extremes_are_short() {
        for v in [0.0, -0.0, 1.0, 0.1, 4.428662611530858e-9, 192461.71375034112, 1e300, -1e-300, 5e-324, f64::MAX] {
            let s = csv_num(v);
            assert!(s.len() <= 32, "{s}");
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{s}");
        }
        // What every example's values look like: unchanged.
        assert_eq!(csv_num(4.428662611530858e-9), "0.000000004428662611530858");
        assert_eq!(csv_num(1e300), "1e300");
        assert_eq!(csv_num(f64::INFINITY), "inf");
    }
}
