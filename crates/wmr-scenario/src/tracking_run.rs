//! One tracking run: the loop stepped as [`wmr_core::ClosedLoop::try_run`] steps it, with
//! the tracking error of every plant step watched ([`wmr_core::tracking`]) and the
//! caller's sink handed the same samples a plain run gives it (t = 0, every `log_every`
//! steps, and the last one).

use std::ops::ControlFlow;

use wmr_core::tracking::{TrackingError, TrackingOutcome, TrackingWatch};
use wmr_core::{Outcome, Sample, Status};

use crate::assemble::RunLoop;
use crate::sim::SimSpec;

/// Runs `lp` for `sim`'s steps; returns the core's outcome and the tracking outcome.
pub(crate) fn run<B>(
    lp: &mut RunLoop,
    sim: &SimSpec,
    tolerance: f64,
    path_following: bool,
    mut sink: impl FnMut(&Sample<f64>) -> ControlFlow<B>,
    poll: impl FnMut() -> ControlFlow<B>,
) -> ControlFlow<B, (Outcome<f64>, TrackingOutcome<f64>)> {
    let kind = if path_following { TrackingError::Path } else { TrackingError::Trajectory };
    let robot = lp.plant().robot().params();
    let limit = lp.controller().wheels().wheel_speed_max();
    let mut watch =
        TrackingWatch::new(kind, sim.t_end(), tolerance).with_wheel_limit(robot.wheel_radius, robot.half_track, limit);
    let reference = lp.reference().clone();
    let every = u64::from(sim.log_every().max(1));
    // The inner run logs every step; the step index of each sample is its place in that
    // stream. A sample is handed on when it is on the log grid, and the last one always
    // (held back one step to know it is the last).
    let mut k: u64 = 0;
    let mut held: Option<(u64, Sample<f64>)> = None;
    let outcome = lp.try_run(
        sim.n_steps(),
        1,
        |s| {
            watch.observe(&reference, s.t, &s.state.pose());
            if let Some((i, h)) = held.take()
                && i % every == 0
            {
                sink(&h)?;
            }
            held = Some((k, *s));
            k += 1;
            ControlFlow::Continue(())
        },
        poll,
    )?;
    if let Some((_, h)) = held {
        sink(&h)?;
    }
    ControlFlow::Continue((outcome, watch.finish()))
}

/// The status of a run: the core's for a run towards a goal; for a tracking run
/// (`tracking` given) diverged or collided as the core says, else converged when the tracking error
/// stayed below the tolerance over the last 10 % of t_end (and a path follower did not stop
/// on the path farther than `sim.xy_goal_tolerance` from its end:
/// [`TrackingOutcome::followed`]), else cannot_follow when the
/// reference asked more than the robot can give ([`TrackingOutcome::cannot_follow`]),
/// else unsettled. The one rule for a scenario's runs and a sweep's.
pub(crate) fn status(outcome: &Outcome<f64>, tracking: Option<&TrackingOutcome<f64>>) -> Status {
    match (tracking, outcome.status()) {
        (_, Status::Diverged) => Status::Diverged,
        (_, Status::Collided) => Status::Collided,
        (Some(t), _) if t.followed(outcome.xy_goal_tolerance) => Status::Converged,
        (Some(t), _) if t.cannot_follow() => Status::CannotFollow,
        (Some(_), _) => Status::Unsettled,
        (None, s) => s,
    }
}
