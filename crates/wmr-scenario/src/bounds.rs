//! The box a run may not leave ([`wmr_core::plant::DIVERGENCE_BOX_M`]): every start and
//! goal must lie inside it, checked before any work starts (a run outside it would count
//! as diverged at its first step).

use wmr_core::plant::DIVERGENCE_BOX_M;
use wmr_core::reference::Reference;
use wmr_core::{AnyReference, Pose2};

use crate::error::{ScenarioError, num};
use crate::reference::RunReference;
use crate::run::RunSpec;

/// Checks that a pose of C lies inside the box a run may not leave; `key` is the pose's
/// path (`run[0].start`).
pub(crate) fn check_in_box(key: &str, pose: Pose2<f64>) -> Result<(), ScenarioError> {
    for (axis, v) in [("x", pose.x), ("y", pose.y)] {
        if !v.is_finite() {
            return Err(ScenarioError::new(
                format!("{key}.{axis}"),
                format!("must be a finite number (got {})", num(v)),
            ));
        }
        if v.abs() > DIVERGENCE_BOX_M {
            return Err(ScenarioError::new(
                format!("{key}.{axis}"),
                format!(
                    "must be within {DIVERGENCE_BOX_M} m of the origin (got {}): a run whose |x| or |y| \
                     passes {DIVERGENCE_BOX_M} m counts as diverged",
                    num(v)
                ),
            ));
        }
    }
    Ok(())
}

/// Every run's start and goal inside the box.
pub(crate) fn check_runs(runs: &[RunSpec]) -> Result<(), ScenarioError> {
    for (i, run) in runs.iter().enumerate() {
        check_in_box(&format!("run[{i}].start"), run.start)?;
        check_in_box(&format!("run[{i}].goal"), run.goal)?;
    }
    Ok(())
}

/// Checks what a reference produces over a run of `t_end` s, besides its keys (which its
/// constructor checked): every point of its figure inside the box (a circle's and a
/// figure-eight's extent, each waypoint, a line's reach at `t_end`), then a finite state
/// inside the box at 1,025 times spread over the run. Errors name the key that sets the
/// value: `prefix` is `reference` or `sweep.references[2]`; `file` says a `waypoints`
/// reference came from a `path` CSV.
pub(crate) fn check_reference(prefix: &str, r: &RunReference, file: bool, t_end: f64) -> Result<(), ScenarioError> {
    let key = |k: &str| format!("{prefix}.{k}");
    let outside = |k: String, what: String| {
        Err(ScenarioError::new(
            k,
            format!(
                "{what}, outside the box a run may not leave (|x|, |y| <= {DIVERGENCE_BOX_M} m): a run whose |x| \
                 or |y| passes {DIVERGENCE_BOX_M} m counts as diverged"
            ),
        ))
    };
    let beyond = |v: f64| v.abs() > DIVERGENCE_BOX_M;
    // A figure's own anchor first (its center, a line's start): that key is to blame.
    let anchor = match r {
        AnyReference::Circle(c) => Some(("center", c.center_x, c.center_y)),
        AnyReference::FigureEight(f) => Some(("center", f.center_x, f.center_y)),
        AnyReference::Line(l) => Some(("start", l.start.x, l.start.y)),
        _ => None,
    };
    if let Some((k, x, y)) = anchor {
        for (axis, v) in [("x", x), ("y", y)] {
            if beyond(v) {
                return outside(key(&format!("{k}.{axis}")), format!("the {k} is at {} m", num(v)));
            }
        }
    }
    // The key the sampled check blames: the one that sets how far and how fast it goes.
    let main_key = match r {
        AnyReference::Circle(c) => {
            let reach = c.center_x.abs().max(c.center_y.abs()) + c.radius;
            if beyond(reach) {
                return outside(key("radius"), format!("the circle reaches {} m from the origin", num(reach)));
            }
            "radius"
        }
        AnyReference::FigureEight(f) => {
            for (k, c, half) in [("width", f.center_x, f.width / 2.0), ("height", f.center_y, f.height / 2.0)] {
                if beyond(c.abs() + half) {
                    return outside(key(k), format!("the figure reaches {} m from the origin", num(c.abs() + half)));
                }
            }
            "period"
        }
        AnyReference::Line(_) => "speed",
        AnyReference::Waypoints(w) => {
            for i in 0..w.len() {
                let [x, y] = w.point(i);
                if beyond(x) || beyond(y) {
                    let (k, which) = if file {
                        (key("path"), format!("point {} of the file is ({}, {}) m", i + 1, num(x), num(y)))
                    } else {
                        (format!("{prefix}.points[{i}]"), format!("the point is ({}, {}) m", num(x), num(y)))
                    };
                    return outside(k, which);
                }
            }
            if file { "path" } else { "points" }
        }
        _ => return Ok(()),
    };
    for k in 0..=1024_u32 {
        let t = t_end * f64::from(k) / 1024.0;
        let s = r.state_at(t);
        let values = [s.pose.x, s.pose.y, s.pose.theta, s.twist.v, s.twist.omega, s.accel.v, s.accel.omega];
        if values.iter().any(|v| !v.is_finite()) {
            return Err(ScenarioError::new(
                key(main_key),
                format!("gives a reference state that is not a finite number at t = {} s", num(t)),
            ));
        }
        if beyond(s.pose.x) || beyond(s.pose.y) {
            return outside(
                key(main_key),
                format!("the reference reaches ({}, {}) m at t = {} s", num(s.pose.x), num(s.pose.y), num(t)),
            );
        }
    }
    Ok(())
}
