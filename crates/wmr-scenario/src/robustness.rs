//! What a robustness sweep shows: the value of every varied key per run (extra CSV
//! columns), and for each varied key the converged share of each law against its value.

use std::fmt::Write as _;

use wmr_core::Status;

use crate::error::fixed;
use crate::sweep::{SweepOutcome, SweepSpec};
use crate::vary::Spread;

/// Bins of a drawn (uniform or normal) key in the share curves: equal counts of runs.
const DRAW_BINS: usize = 5;

/// The varied keys, in `vary` order: the names of the extra CSV columns.
pub fn varied_columns(spec: &SweepSpec) -> Vec<String> {
    spec.variation.keys.iter().map(|k| k.key.clone()).collect()
}

/// The value of every varied key in run `o`, as CSV fields.
pub fn varied_row(spec: &SweepSpec, o: &SweepOutcome) -> Vec<String> {
    spec.varied_values(o).into_iter().map(crate::sweep::csv_num).collect()
}

/// One law's converged share against one varied key.
#[derive(Clone, Debug, PartialEq)]
pub struct ShareCurve {
    /// The varied key.
    pub key: String,
    /// The law's name (with the reference's, `law / reference`, when a sweep over
    /// references has several).
    pub law: String,
    /// (value of the key, share of runs converged in 0..1, runs): one point per listed
    /// value, or per bin of equal counts (at the bin's mean) for a drawn key.
    pub points: Vec<(f64, f64, usize)>,
}

/// The converged share of each law against each varied key.
pub fn share_curves(spec: &SweepSpec, outcomes: &[SweepOutcome]) -> Vec<ShareCurve> {
    curves(spec, outcomes, |o| if o.status() == Status::Converged { 1.0 } else { 0.0 })
}

/// For a sweep on odometry (`[sensor] pose = "odometry"`), each law's mean odometry drift
/// at the end, in % of the distance travelled, against each varied key: curves whose
/// points hold that mean where [`share_curves`] hold a share. Only the keys whose runs
/// were on odometry (a `with = { "sensor.pose" = "odometry" }` entry among others); empty
/// for other sweeps.
pub fn drift_curves(spec: &SweepSpec, outcomes: &[SweepOutcome]) -> Vec<ShareCurve> {
    if outcomes.iter().all(|o| o.odometry_drift.is_none()) {
        return Vec::new();
    }
    let all = curves(spec, outcomes, |o| o.odometry_drift.and_then(|d| d.percent()).unwrap_or(f64::NAN));
    let on_odometry =
        |key: &str| all.iter().filter(|c| c.key == key).any(|c| c.points.iter().any(|(_, d, _)| d.is_finite()));
    all.iter().filter(|c| on_odometry(&c.key)).cloned().collect()
}

/// The mean of `value` over the runs of each law at each value of each varied key.
fn curves(spec: &SweepSpec, outcomes: &[SweepOutcome], value: impl Fn(&SweepOutcome) -> f64) -> Vec<ShareCurve> {
    let mut curves = Vec::new();
    let values: Vec<Vec<f64>> = outcomes.iter().map(|o| spec.varied_values(o)).collect();
    for (ki, k) in spec.variation.keys.iter().enumerate() {
        let cases = (0..spec.laws.len()).flat_map(|l| (0..spec.n_references()).map(move |r| (l, r)));
        for (li, ri) in cases {
            let law = spec.case_name(li, ri);
            let runs: Vec<(f64, f64)> = outcomes
                .iter()
                .zip(&values)
                .filter(|(o, _)| o.law == li && o.reference == ri)
                .filter(|(o, _)| match &k.spread {
                    // A listed key's curve uses only the variants that set it.
                    Spread::Values(_) => spec.variants[o.variant].is_some_and(|(i, _)| i == ki),
                    _ => true,
                })
                .map(|(o, v)| (v[ki], value(o)))
                .collect();
            let points = match &k.spread {
                Spread::Values(list) => list
                    .iter()
                    .map(|&x| {
                        let at: Vec<f64> = runs.iter().filter(|(v, _)| *v == x).map(|(_, c)| *c).collect();
                        (x, mean(&at), at.len())
                    })
                    .collect(),
                _ => {
                    let mut sorted = runs.clone();
                    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
                    let n = sorted.len();
                    (0..DRAW_BINS.min(n))
                        .map(|b| {
                            let bin = &sorted[b * n / DRAW_BINS.min(n)..(b + 1) * n / DRAW_BINS.min(n)];
                            let mean_x = bin.iter().map(|(v, _)| v).sum::<f64>() / bin.len().max(1) as f64;
                            let conv: Vec<f64> = bin.iter().map(|(_, c)| *c).collect();
                            (mean_x, mean(&conv), bin.len())
                        })
                        .collect()
                }
            };
            curves.push(ShareCurve { key: k.key.clone(), law, points });
        }
    }
    curves
}

/// The mean (NaN for none): of 1s and 0s, the share of 1s, exactly.
fn mean(values: &[f64]) -> f64 {
    if values.is_empty() { f64::NAN } else { values.iter().sum::<f64>() / values.len() as f64 }
}

/// The share curves as text: per varied key, one row per law, one column per value.
pub fn share_table(curves: &[ShareCurve]) -> String {
    table(curves, "converged share against", 100.0, 1)
}

/// The drift curves ([`drift_curves`]) as text, like [`share_table`].
pub fn drift_table(curves: &[ShareCurve]) -> String {
    table(curves, "odometry drift at the end (mean, % of the distance travelled) against", 1.0, 2)
}

/// Curves as text under `title {key}`, each point's value times `scale` in % with
/// `decimals` decimals.
fn table(curves: &[ShareCurve], title: &str, scale: f64, decimals: usize) -> String {
    let mut out = String::new();
    let mut key = "";
    let width = curves.iter().map(|c| c.law.len()).max().unwrap_or(3).max(12);
    for c in curves {
        if c.key != key {
            key = &c.key;
            let _ = write!(out, "\n{title} {key}\n{:<width$}", "law");
            for (x, _, _) in &c.points {
                let _ = write!(out, " {:>9}", format!("{x:.4}").trim_end_matches('0').trim_end_matches('.'));
            }
            out.push('\n');
        }
        let _ = write!(out, "{:<width$}", c.law);
        for (_, s, n) in &c.points {
            // No run at that value, or none that travelled (a drift in % of nothing).
            let cell = match (n, (scale * s).is_finite()) {
                (0, _) => "-".to_owned(),
                (_, false) => "n/a".to_owned(),
                _ => format!("{}%", fixed(scale * s, decimals)),
            };
            let _ = write!(out, " {cell:>9}");
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 39 item 10: a drift mean over runs that did not travel printed `NaN%`; a
    /// value no run had, `NaN%` too. Now `n/a` and `-`; finite cells as before.
    #[test]
    fn non_finite_cells_are_said_in_words() {
        let curve = ShareCurve {
            key: "sensor.fix_rate_hz".to_owned(),
            law: "polar".to_owned(),
            points: vec![(0.0, f64::NAN, 2), (1.0, 1.2345, 2), (2.0, f64::NAN, 0)],
        };
        let text = drift_table(&[curve]);
        let row = text.lines().find(|l| l.starts_with("polar")).unwrap();
        assert_eq!(row, "polar              n/a     1.23%         -", "{text}");
        assert!(!text.contains("NaN"), "{text}");
    }
}
