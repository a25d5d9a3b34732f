//! A tracking run's reference path as the 3D panel draws it: dashes of equal length
//! along the reference's positions on the log grid, so it reads apart from the solid path
//! of C.
//!
//! Both the drawing and the layout's framing read the reference within a budget, whatever
//! the scenario asks (a run of 10^6 s, a reference at 10^5 m/s, a robot 10^-9 m wide): at
//! most [`MAX_REFERENCE_SAMPLES`] positions (the log times, evenly thinned, as `plot` keeps
//! 4,000 samples of a run) and at most [`MAX_DASH_POINTS`] dash ends (a longer path gets
//! longer dashes). An ordinary scenario is within both and drawn as without them.

use foxglove::messages::Point3;
use wmr_core::Reference;
use wmr_scenario::SimSpec;
use wmr_scenario::reference::RunReference;

/// Most reference positions read for a drawing or a layout: the log times of a run, evenly
/// thinned beyond this (1,000 s logged every 10 ms are read whole).
pub const MAX_REFERENCE_SAMPLES: u64 = 100_000;

/// Most points (dash ends) of a drawn reference path: a path longer than this many dashes
/// gets dashes of its length over this count (at most about 600 kB of message).
pub const MAX_DASH_POINTS: usize = 20_000;

/// The reference's positions (x, y) at the log times (those of the CSV's x_ref, y_ref),
/// evenly thinned to at most [`MAX_REFERENCE_SAMPLES`] (and the last one kept).
pub fn log_positions(reference: &RunReference, sim: &SimSpec) -> Vec<(f64, f64)> {
    let position = |k: u64| {
        let p = reference.state_at((k as f64 * sim.log_dt()).min(sim.t_end())).pose;
        (p.x, p.y)
    };
    let n = sim.n_samples();
    let stride = n.div_ceil(MAX_REFERENCE_SAMPLES).max(1);
    let mut out: Vec<(f64, f64)> =
        (0..n).step_by(usize::try_from(stride).unwrap_or(usize::MAX)).map(position).collect();
    if n > 0 && !(n - 1).is_multiple_of(stride) {
        out.push(position(n - 1));
    }
    out
}

/// The points of a `LINE_LIST` (segments 0-1, 2-3, ...) that draws `reference`'s path
/// over the run as dashes of `dash_m` (m) with gaps of `dash_m`: the path through
/// [`log_positions`], cut every `dash_m` of arc length (longer dashes when that would give
/// more than [`MAX_DASH_POINTS`]). Empty for a path shorter than one dash (a standing
/// reference) and for one whose length is not a finite number.
pub(super) fn dashes(reference: &RunReference, sim: &SimSpec, dash_m: f64) -> Vec<Point3> {
    let positions = log_positions(reference, sim);
    let length: f64 = positions.windows(2).map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1)).sum();
    if !length.is_finite() {
        return Vec::new();
    }
    let dash_m = dash_m.max(length / MAX_DASH_POINTS as f64);
    let mut out = Vec::new();
    let Some(&first) = positions.first() else { return out };
    let mut last = first;
    // Arc length from the last cut, m.
    let mut run_m = 0.0;
    out.push(Point3 { x: last.0, y: last.1, z: 0.0 });
    for &p in &positions[1..] {
        let step = (p.0 - last.0).hypot(p.1 - last.1);
        // Cut at every multiple of dash_m along the segment last-p (rounding aside, at
        // most MAX_DASH_POINTS in all: the cap only guards against it).
        let mut along = dash_m - run_m;
        while along <= step && step > 0.0 && out.len() <= MAX_DASH_POINTS {
            let f = along / step;
            out.push(Point3 { x: last.0 + f * (p.0 - last.0), y: last.1 + f * (p.1 - last.1), z: 0.0 });
            along += dash_m;
        }
        run_m = (run_m + step) % dash_m;
        last = p;
    }
    // A dash is a pair of points; a trailing half dash ends at the last position.
    if out.len() % 2 == 1 {
        out.push(Point3 { x: last.0, y: last.1, z: 0.0 });
    }
    if out.len() < 2 || (out.len() == 2 && out[0] == out[1]) {
        out.clear();
    }
    out
}

#[cfg(test)]
mod tests {
    use wmr_core::reference::Circle;

    use super::*;

    fn sim(t_end: f64, log_dt: f64) -> SimSpec {
        SimSpec::resolve(Some(t_end), Some(0.01), Some(log_dt), 0.01).unwrap()
    }

    #[test]
    fn positions_are_the_log_grid_up_to_the_budget_then_thinned_with_the_last() {
        let circle = RunReference::Circle(Circle::new(0.0, 0.0, 1.0, 0.3, 0.0).unwrap());
        let short = sim(40.0, 0.01);
        assert_eq!(log_positions(&circle, &short).len() as u64, short.n_samples());
        let long = sim(1e5, 0.01);
        let p = log_positions(&circle, &long);
        assert!(p.len() as u64 <= MAX_REFERENCE_SAMPLES + 1, "{}", p.len());
        let end = circle.state_at(1e5).pose;
        assert_eq!(*p.last().unwrap(), (end.x, end.y));
    }

    #[test]
    fn dashes_stay_within_the_budget() {
        let circle = RunReference::Circle(Circle::new(0.0, 0.0, 1.0, 0.3, 0.0).unwrap());
        let s = sim(40.0, 0.01);
        // 12 m of 8 cm dashes: cut as ever; 1e-9 m dashes: the budget.
        let ordinary = dashes(&circle, &s, 0.08);
        assert!((140..=160).contains(&ordinary.len()), "{}", ordinary.len());
        let tiny = dashes(&circle, &s, 1e-9);
        assert!(tiny.len() <= MAX_DASH_POINTS + 2 && tiny.len() > MAX_DASH_POINTS / 2, "{}", tiny.len());
    }
}
