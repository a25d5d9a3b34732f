//! The comparison of a sweep over references: per (law, reference), the shares of the
//! four outcomes (converged: the tracking error stays below `sim.tracking_tolerance`
//! over the last 10 % of t_end) and median and worst of the tracking figures over the
//! runs that did not diverge, as values and as a table.

use crate::error::{fixed, num};
use wmr_core::Status;

use super::outcome::SweepOutcome;
use super::spec::SweepSpec;
use super::summary::{Spread, spread};

/// Comparison of one law on one reference over all starts.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackingSummary {
    /// The law's name.
    pub law: String,
    /// The reference's name.
    pub reference: String,
    /// Runs.
    pub n: usize,
    /// Share of runs that converged (0..1).
    pub converged: f64,
    /// Share of runs that diverged (0..1).
    pub diverged: f64,
    /// Share of runs that are unsettled (0..1).
    pub unsettled: f64,
    /// Share of runs whose footprint touched an obstacle (0..1; `[[world.obstacle]]`).
    pub collided: f64,
    /// Share of runs whose reference asked more than the robot can give (0..1):
    /// [`wmr_core::tracking::TrackingOutcome::cannot_follow`].
    pub cannot_follow: f64,
    /// RMS of the tracking error over the last half of t_end, m, over the runs that did
    /// not diverge.
    pub rms_error: Spread,
    /// Largest tracking error over the last half of t_end, m, same runs.
    pub max_error: Spread,
    /// Time after which the error stays below the tolerance, s, over the converged runs.
    pub time_to_tolerance: Spread,
}

/// Per (law, reference) comparison of the outcomes of a sweep over references, in run
/// order (law, then reference); empty for a sweep towards a goal.
pub fn tracking_summary(spec: &SweepSpec, outcomes: &[SweepOutcome]) -> Vec<TrackingSummary> {
    let Some(tr) = &spec.tracking else { return Vec::new() };
    let mut rows = Vec::with_capacity(spec.laws.len() * tr.references.len());
    for (li, (law, _)) in spec.laws.iter().enumerate() {
        for (ri, (reference, _)) in tr.references.iter().enumerate() {
            let runs: Vec<&SweepOutcome> = outcomes.iter().filter(|o| o.law == li && o.reference == ri).collect();
            let n = runs.len().max(1) as f64;
            let share = |status: Status| runs.iter().filter(|o| o.status() == status).count() as f64 / n;
            let alive: Vec<_> =
                runs.iter().filter(|o| o.status() != Status::Diverged).filter_map(|o| o.tracking).collect();
            let converged: Vec<_> =
                runs.iter().filter(|o| o.status() == Status::Converged).filter_map(|o| o.tracking).collect();
            rows.push(TrackingSummary {
                law: law.clone(),
                reference: reference.clone(),
                n: runs.len(),
                converged: share(Status::Converged),
                diverged: share(Status::Diverged),
                unsettled: share(Status::Unsettled),
                collided: share(Status::Collided),
                cannot_follow: share(Status::CannotFollow),
                rms_error: spread(alive.iter().map(|t| t.rms_last_half).collect()),
                max_error: spread(alive.iter().map(|t| t.max_last_half).collect()),
                time_to_tolerance: spread(converged.iter().map(|t| t.time_to_tolerance.unwrap_or(f64::NAN)).collect()),
            });
        }
    }
    rows
}

/// The comparison as aligned text, one line per (law, reference): the shares of the four
/// outcomes, then "median / worst" of the RMS and maximum error (mm) and of the time to
/// the tolerance (s).
pub fn tracking_summary_table(rows: &[TrackingSummary], tolerance_m: f64) -> String {
    let fmt = |s: Spread, scale: f64, prec: usize| {
        if s.median.is_nan() {
            "-".to_owned()
        } else {
            format!("{} / {}", fixed(scale * s.median, prec), fixed(scale * s.worst, prec))
        }
    };
    let w = rows.iter().map(|r| r.law.len()).max().unwrap_or(0).max(3);
    let wr = rows.iter().map(|r| r.reference.len()).max().unwrap_or(0).max(9);
    // The time to the tolerance, in s; the tolerance as written, in mm (0.01 m: `10 mm`).
    let tol = format!("s to {} mm", num((tolerance_m * 1e9).round() / 1e6));
    let mut out = format!(
        "{:<w$} {:<wr$} {:>6} {:>10} {:>9} {:>10} {:>14} {:>19} {:>19} {:>15}\n",
        "law",
        "reference",
        "runs",
        "converged",
        "diverged",
        "unsettled",
        "cannot_follow",
        "RMS mm (med/max)",
        "max mm (med/max)",
        tol
    );
    // A sweep with obstacles ends each line with the share that collided.
    let collisions = rows.iter().any(|r| r.collided > 0.0);
    if collisions {
        out.insert_str(out.len() - 1, &format!(" {:>9}", "collided"));
    }
    for r in rows {
        out.push_str(&format!(
            "{:<w$} {:<wr$} {:>6} {:>9.1}% {:>8.1}% {:>9.1}% {:>13.1}% {:>19} {:>19} {:>15}\n",
            r.law,
            r.reference,
            r.n,
            100.0 * r.converged,
            100.0 * r.diverged,
            100.0 * r.unsettled,
            100.0 * r.cannot_follow,
            fmt(r.rms_error, 1000.0, 2),
            fmt(r.max_error, 1000.0, 2),
            fmt(r.time_to_tolerance, 1.0, 2),
        ));
        if collisions {
            out.insert_str(out.len() - 1, &format!(" {:>8.1}%", 100.0 * r.collided));
        }
    }
    out
}
