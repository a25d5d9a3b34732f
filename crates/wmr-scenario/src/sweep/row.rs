//! A sweep outcome as one row of the sweep CSV.

use wmr_core::outcome_fields::sweep_csv_fields;

use super::outcome::SweepOutcome;
use super::spec::SweepSpec;

/// The columns of a sweep CSV before its outcome columns: the law, the start (its index
/// and pose).
const SWEEP_HEAD: [&str; 5] = ["law", "start", "x0", "y0", "theta0_deg"];

/// The columns of the CSV of a sweep over references before its outcome columns: the
/// law, the reference, the start (its index, its pose, the offset from the reference's
/// pose at t = 0).
const TRACKING_SWEEP_HEAD: [&str; 9] =
    ["law", "reference", "start", "x0", "y0", "theta0_deg", "dx0", "dy0", "dtheta0_deg"];

/// Columns of the sweep CSV, in order: the start, the status, then the outcome columns
/// of a run towards a goal ([`sweep_csv_fields`]).
pub fn sweep_columns() -> Vec<&'static str> {
    SWEEP_HEAD.into_iter().chain(["status"]).chain(sweep_csv_fields(false).map(|f| f.name)).collect()
}

/// Columns of the CSV of a sweep over references, in order: the start and its offset,
/// the status judged by the tracking error, then the outcome columns of a tracking run
/// ([`sweep_csv_fields`]: the error is the true distance from C to C_ref, or to the path
/// for path following: its time below the tolerance, RMS and maximum over the last half
/// of t_end, final; then the drive figures).
pub fn tracking_sweep_columns() -> Vec<&'static str> {
    TRACKING_SWEEP_HEAD.into_iter().chain(["status"]).chain(sweep_csv_fields(true).map(|f| f.name)).collect()
}

/// A figure as a CSV field: empty where the run has none.
fn field(v: Option<f64>) -> String {
    v.map(csv_num).unwrap_or_default()
}

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

/// One CSV row of a sweep outcome, as strings in [`sweep_columns`] order.
pub fn sweep_row(spec: &SweepSpec, o: &SweepOutcome) -> Vec<String> {
    let mut row = vec![
        spec.laws[o.law].0.clone(),
        o.start_index.to_string(),
        csv_num(o.start.x),
        csv_num(o.start.y),
        csv_num(o.start.theta.to_degrees()),
        o.status().name().to_owned(),
    ];
    row.extend(sweep_csv_fields(false).map(|f| field(f.value(&o.outcome, o.tracking.as_ref()))));
    row
}

/// One CSV row of an outcome of a sweep over references, in [`tracking_sweep_columns`]
/// order; `None` for an outcome without a tracking outcome.
pub fn tracking_sweep_row(spec: &SweepSpec, o: &SweepOutcome) -> Option<Vec<String>> {
    let (tr, refs) = (o.tracking.as_ref()?, spec.tracking.as_ref()?);
    let offset = spec.starts[o.start_index];
    let mut row = vec![
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
    ];
    row.extend(sweep_csv_fields(true).map(|f| field(f.value(&o.outcome, Some(tr)))));
    Some(row)
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
