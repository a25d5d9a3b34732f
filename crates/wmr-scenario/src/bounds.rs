//! The box a run may not leave ([`wmr_core::plant::DIVERGENCE_BOX_M`]): every start and
//! goal must lie inside it, checked before any work starts (a run outside it would count
//! as diverged at its first step).

use wmr_core::Pose2;
use wmr_core::plant::DIVERGENCE_BOX_M;

use crate::error::{ScenarioError, num};
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
