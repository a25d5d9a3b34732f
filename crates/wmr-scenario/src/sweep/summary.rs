//! The comparison of the laws of a sweep: per law, the shares of the outcomes and median
//! and worst of the other figures over the converged runs, as values and as a table.

use wmr_core::{Outcome, Status};

use super::outcome::SweepOutcome;
use super::spec::SweepSpec;

/// Median and worst of one figure over a law's runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    /// Median (NaN when no run counts).
    pub median: f64,
    /// Worst: the largest value (NaN when no run counts).
    pub worst: f64,
}

pub(super) fn spread(mut v: Vec<f64>) -> Spread {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return Spread { median: f64::NAN, worst: f64::NAN };
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) };
    Spread { median, worst: v[n - 1] }
}

/// Comparison of one law over all starts. Figures other than the shares are taken over
/// the converged runs only (a diverged run has no meaningful time or heading error).
#[derive(Clone, Debug, PartialEq)]
pub struct LawSummary {
    /// The law's name.
    pub name: String,
    /// Runs.
    pub n: usize,
    /// Share of runs that converged (0..1).
    pub converged: f64,
    /// Share of runs that diverged (0..1): the state stopped being finite or C left the box.
    pub diverged: f64,
    /// Share of runs that are unsettled (0..1): neither converged nor diverged at t_end.
    pub unsettled: f64,
    /// Share of runs whose footprint touched an obstacle (0..1; `[[world.obstacle]]`).
    pub collided: f64,
    /// Time to 1 cm, s.
    pub time_to_1cm: Spread,
    /// |final heading error|, deg.
    pub heading_error_deg: Spread,
    /// Peak wheel speed, rad/s.
    pub peak_wheel_speed: Spread,
    /// Path length, m.
    pub path_length: Spread,
    /// Work of both drives on their wheels, braking counted as positive, J ([`Outcome::abs_work`]).
    pub abs_work: Spread,
}

/// Per-law comparison of sweep outcomes, in law order.
pub fn summarize(spec: &SweepSpec, outcomes: &[SweepOutcome]) -> Vec<LawSummary> {
    spec.laws
        .iter()
        .enumerate()
        .map(|(i, (name, _))| {
            let runs: Vec<&SweepOutcome> = outcomes.iter().filter(|o| o.law == i).collect();
            let ok: Vec<&SweepOutcome> = runs.iter().copied().filter(|o| o.status() == Status::Converged).collect();
            let n = runs.len().max(1) as f64;
            let share = |status: Status| runs.iter().filter(|o| o.status() == status).count() as f64 / n;
            let over = |f: fn(&Outcome<f64>) -> f64| spread(ok.iter().map(|o| f(&o.outcome)).collect());
            LawSummary {
                name: name.clone(),
                n: runs.len(),
                converged: ok.len() as f64 / n,
                diverged: share(Status::Diverged),
                unsettled: share(Status::Unsettled),
                collided: share(Status::Collided),
                time_to_1cm: over(|o| o.time_to_arrival.unwrap_or(f64::NAN)),
                heading_error_deg: over(|o| o.final_heading_error.to_degrees().abs()),
                peak_wheel_speed: over(|o| o.peak_wheel_speed),
                path_length: over(|o| o.path_length),
                abs_work: over(|o| o.abs_work),
            }
        })
        .collect()
}

/// The comparison table as aligned text, one line per law: the shares of the three
/// outcomes, then "median / worst" of the other figures over the converged runs.
pub fn summary_table(rows: &[LawSummary]) -> String {
    let fmt = |s: Spread, prec: usize| {
        if s.median.is_nan() { "-".to_owned() } else { format!("{:.p$} / {:.p$}", s.median, s.worst, p = prec) }
    };
    let w = rows.iter().map(|r| r.name.len()).max().unwrap_or(0).max(3);
    let mut out = format!(
        "{:<w$} {:>6} {:>10} {:>9} {:>10} {:>17} {:>15} {:>15} {:>13} {:>15}\n",
        "law",
        "runs",
        "converged",
        "diverged",
        "unsettled",
        "t_1cm s (med/max)",
        "|e_th| deg",
        "peak w rad/s",
        "path m",
        "|work| J"
    );
    // A sweep with obstacles ends each line with the share that collided.
    let collisions = rows.iter().any(|r| r.collided > 0.0);
    if collisions {
        out.insert_str(out.len() - 1, &format!(" {:>9}", "collided"));
    }
    for r in rows {
        out.push_str(&format!(
            "{:<w$} {:>6} {:>9.1}% {:>8.1}% {:>9.1}% {:>17} {:>15} {:>15} {:>13} {:>15}\n",
            r.name,
            r.n,
            100.0 * r.converged,
            100.0 * r.diverged,
            100.0 * r.unsettled,
            fmt(r.time_to_1cm, 2),
            fmt(r.heading_error_deg, 2),
            fmt(r.peak_wheel_speed, 1),
            fmt(r.path_length, 2),
            fmt(r.abs_work, 1),
        ));
        if collisions {
            out.insert_str(out.len() - 1, &format!(" {:>8.1}%", 100.0 * r.collided));
        }
    }
    out
}

/// The `p`-th percentile (0 < p <= 100) of `sorted` (ascending, finite) by nearest rank:
/// the smallest value with at least p % of the values at or below it; NaN when empty.
pub fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = (p / 100.0 * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

/// p50, p95, p99 and max of one figure over a law's runs (nearest rank, [`percentile`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Percentiles {
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// 99th percentile.
    pub p99: f64,
    /// Largest.
    pub max: f64,
}

impl Percentiles {
    /// The percentiles of the finite values of `v` (NaN when none).
    pub fn of(mut v: Vec<f64>) -> Self {
        v.retain(|x| x.is_finite());
        v.sort_by(f64::total_cmp);
        Self {
            p50: percentile(&v, 50.0),
            p95: percentile(&v, 95.0),
            p99: percentile(&v, 99.0),
            max: percentile(&v, 100.0),
        }
    }
}

/// How one law of a sweep towards a goal docked: the share of its runs that ended within
/// `sim.xy_goal_tolerance` and `sim.yaw_goal_tolerance_deg` (`wmr_core::Outcome::docked`,
/// the CSV's `docked`) and the distribution of its final errors over all its runs (the
/// final state, after settling; a diverged run's last finite state).
#[derive(Clone, Debug, PartialEq)]
pub struct DockingSummary {
    /// The law's name.
    pub name: String,
    /// Runs.
    pub n: usize,
    /// Share of runs docked (0..1).
    pub docked: f64,
    /// Final distance from C to the goal position, m (`final_dl_m`).
    pub final_dl_m: Percentiles,
    /// |final heading error|, deg (`|final_heading_error_deg|`).
    pub final_heading_error_deg: Percentiles,
}

/// Per-law docking of a sweep towards a goal, in law order (empty for a sweep over
/// references, whose runs have no goal to dock at).
pub fn docking_summary(spec: &SweepSpec, outcomes: &[SweepOutcome]) -> Vec<DockingSummary> {
    if spec.tracking.is_some() {
        return Vec::new();
    }
    spec.laws
        .iter()
        .enumerate()
        .map(|(i, (name, _))| {
            let runs: Vec<&Outcome<f64>> = outcomes.iter().filter(|o| o.law == i).map(|o| &o.outcome).collect();
            let docked = runs.iter().filter(|o| o.docked()).count();
            DockingSummary {
                name: name.clone(),
                n: runs.len(),
                docked: docked as f64 / runs.len().max(1) as f64,
                final_dl_m: Percentiles::of(runs.iter().map(|o| o.final_dl).collect()),
                final_heading_error_deg: Percentiles::of(
                    runs.iter().map(|o| o.final_heading_error.to_degrees().abs()).collect(),
                ),
            }
        })
        .collect()
}

/// The docking table as aligned text under a title naming the tolerances (m, deg): per
/// law its runs, the share docked and p50 / p95 / p99 / max of the final distance (mm)
/// and |heading error| (deg). Empty for no rows.
pub fn docking_table(rows: &[DockingSummary], xy_goal_tolerance_m: f64, yaw_goal_tolerance_deg: f64) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let fmt = |p: Percentiles, scale: f64, prec: usize| {
        if p.p50.is_nan() {
            "-".to_owned()
        } else {
            format!(
                "{:.q$} / {:.q$} / {:.q$} / {:.q$}",
                scale * p.p50,
                scale * p.p95,
                scale * p.p99,
                scale * p.max,
                q = prec
            )
        }
    };
    let w = rows.iter().map(|r| r.name.len()).max().unwrap_or(0).max(3);
    let mut out = format!(
        "\ndocked within {} m and {} deg at the end (final errors over all runs: p50 / p95 / p99 / max)\n",
        crate::sweep::csv_num(xy_goal_tolerance_m),
        crate::sweep::csv_num(yaw_goal_tolerance_deg)
    );
    let cells: Vec<(String, String)> =
        rows.iter().map(|r| (fmt(r.final_dl_m, 1000.0, 2), fmt(r.final_heading_error_deg, 1.0, 3))).collect();
    let wd = cells.iter().map(|c| c.0.len()).max().unwrap_or(0).max(14);
    let wh = cells.iter().map(|c| c.1.len()).max().unwrap_or(0).max(14);
    out.push_str(&format!(
        "{:<w$} {:>6} {:>9}  {:>wd$}  {:>wh$}\n",
        "law", "runs", "docked", "final dl mm", "|e_th| deg"
    ));
    for (r, (dl, th)) in rows.iter().zip(cells) {
        out.push_str(&format!("{:<w$} {:>6} {:>8.2}%  {dl:>wd$}  {th:>wh$}\n", r.name, r.n, 100.0 * r.docked));
    }
    out
}
