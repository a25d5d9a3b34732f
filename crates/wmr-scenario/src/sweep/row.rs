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
