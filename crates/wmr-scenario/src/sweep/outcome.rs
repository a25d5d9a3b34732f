//! The outcome of one run of a sweep, with where it sits in the sweep.

use crate::output::OdometryDrift;
use wmr_core::tracking::TrackingOutcome;
use wmr_core::{Outcome, Pose2, Status};

/// The outcome of one (law, variant, trial, start) run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepOutcome {
    /// Index into [`SweepSpec::laws`](crate::SweepSpec::laws).
    pub law: usize,
    /// Index into [`SweepSpec::variants`](crate::SweepSpec::variants).
    pub variant: usize,
    /// 0-based trial.
    pub trial: u32,
    /// The run's index in the sweep (it selects the sensor noise and the draws).
    pub run: u64,
    /// Index into [`SweepSpec::starts`](crate::SweepSpec::starts).
    pub start_index: usize,
    /// Start pose of C (world frame; m, m, rad).
    pub start: Pose2<f64>,
    /// The core's outcome.
    pub outcome: Outcome<f64>,
    /// Index into the references of a sweep over references
    /// ([`SweepSpec::tracking`](crate::SweepSpec::tracking)); 0 for a sweep towards a goal.
    pub reference: usize,
    /// How the tracking error went, for a sweep over references.
    pub tracking: Option<TrackingOutcome<f64>>,
    /// For a run on odometry (`[sensor] pose = "odometry"`), its drift at the end.
    pub odometry_drift: Option<OdometryDrift>,
}

impl SweepOutcome {
    /// Converged, diverged or unsettled (decided by the core; a tracking run converges
    /// when its error stays below `sim.tracking_tolerance` over the last 10 % of t_end).
    pub fn status(&self) -> Status {
        crate::tracking_run::status(&self.outcome, self.tracking.as_ref())
    }
}
