//! A tracking run's reference path as the 3D panel draws it: dashes of equal length
//! along the reference's positions on the log grid, so it reads apart from the solid path
//! of C.

use foxglove::messages::Point3;
use wmr_core::{AnyReference, Reference};
use wmr_scenario::SimSpec;

/// The points of a `LINE_LIST` (segments 0-1, 2-3, ...) that draws `reference`'s path
/// over the run as dashes of `dash_m` (m) with gaps of `dash_m`: the path sampled at the
/// log times (those of the CSV's x_ref, y_ref), cut every `dash_m` of arc length. Empty
/// for a path shorter than one dash (a standing reference).
pub(super) fn dashes(reference: &AnyReference<f64>, sim: &SimSpec, dash_m: f64) -> Vec<Point3> {
    let position = |k: u64| {
        let p = reference.state_at((k as f64 * sim.log_dt()).min(sim.t_end())).pose;
        (p.x, p.y)
    };
    let mut out = Vec::new();
    let mut last = position(0);
    // Arc length from the last cut, m.
    let mut run_m = 0.0;
    out.push(Point3 { x: last.0, y: last.1, z: 0.0 });
    for k in 1..sim.n_samples() {
        let p = position(k);
        let step = (p.0 - last.0).hypot(p.1 - last.1);
        // Cut at every multiple of dash_m along the segment last-p.
        let mut along = dash_m - run_m;
        while along <= step && step > 0.0 {
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
