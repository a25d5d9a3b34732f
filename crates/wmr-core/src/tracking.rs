//! How a tracking or path-following run went, from the true state: the tracking error
//! over time, and the rule that judges it.
//!
//! The error at each plant step is the true distance from C to C_ref at that time
//! ([`TrackingError::Trajectory`]) or, for path following, to the reference's path
//! ([`TrackingError::Path`], the closest point found forward from the last one, the first
//! from the path's beginning, as pure pursuit finds it). Over a
//! run of length t_end:
//!
//! - **converged** when the error stays below the tolerance over the last 10 % of
//!   t_end and, for path following, the robot did not stop on the path short of its
//!   end ([`TrackingOutcome::stalled`]: a robot held on the path by an obstacle is close
//!   to the path, yet follows nothing); **diverged** when the run did; **cannot_follow** when it is not converged
//!   and the reference asked more than the robot can give ([`TrackingOutcome::cannot_follow`]:
//!   wheel speeds above the wheel stage's `wheel_speed_max`, or an error that grew);
//!   **unsettled** otherwise;
//! - RMS and maximum of the error over the last half (t >= t_end / 2);
//! - the time after which the error stays below the tolerance (`None` if it is above
//!   at the end).

use crate::Real;
use crate::lane::Lane;
use crate::math::Pose2;
use crate::reference::{Path, PathCursor, Reference};

/// What the tracking error is measured against.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum TrackingError {
    /// The distance from C to C_ref at the same time (trajectory tracking).
    Trajectory,
    /// The distance from C to the path (path following; time ignored).
    Path,
}

/// The distance step (m) and forward window (m) of the path-distance search: fine against
/// the curvature of the references (radius >= 0.1 m) and wide against one plant step.
const PATH_STEP_M: f64 = 0.02;
const PATH_WINDOW_M: f64 = 0.2;

/// Watches the tracking error of one run, step by step. No alloc.
#[derive(Clone, Copy, Debug)]
pub struct TrackingWatch<T: Real> {
    kind: TrackingError,
    t_end: T,
    tolerance: T,
    cursor: PathCursor<T>,
    sum_sq: T,
    count: u64,
    max: T,
    tail_max: T,
    /// Time of the last step with the error at or above the tolerance.
    last_above: Option<T>,
    last_error: T,
    /// Sum and count of the error over the first and the last tenth of t_end, m.
    first_tenth: (T, u64),
    last_tenth: (T, u64),
    /// (r, R, wheel_speed_max): wheel radius and half track (m) of the robot, the wheel
    /// speed limit (rad/s) the reference is held against ([`TrackingWatch::with_wheel_limit`]).
    wheel_limit: Option<(T, T, T)>,
    /// Largest wheel speed the reference asks, (|v_ref| + R |omega_ref|) / r, rad/s.
    reference_wheel_speed: T,
    /// First time the reference asked more than the limit, s.
    over_limit_at: Option<T>,
    /// The closest path point of the last step (x, y), m (path following).
    last_closest: Option<(T, T)>,
    /// How far the closest path point moved at the last step, m (0 for trajectories).
    closest_step: T,
    /// How far the closest path point moved over the last tenth of t_end, m.
    progress_last_tenth: T,
    /// The path's end point (x, y), m, for a path with an end (path following).
    path_end: Option<(T, T)>,
    /// The true position of C at the last step, m.
    last_position: (T, T),
}

/// The tracking outcome of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackingOutcome<T> {
    /// RMS of the error over the last half of t_end, m.
    pub rms_last_half: T,
    /// Largest error over the last half of t_end, m.
    pub max_last_half: T,
    /// Largest error over the last 10 % of t_end, m: below the tolerance for "converged".
    pub max_last_tenth: T,
    /// The time after which the error stays below the tolerance, s (`None`: above at the end).
    pub time_to_tolerance: Option<T>,
    /// The error at the last step, m.
    pub final_error: T,
    /// The tolerance it was judged with, m.
    pub tolerance: T,
    /// Mean error over the first 10 % of t_end, m.
    pub mean_first_tenth: T,
    /// Mean error over the last 10 % of t_end, m.
    pub mean_last_tenth: T,
    /// Largest wheel speed the reference asks of the robot, (|v_ref| + R |omega_ref|) / r,
    /// rad/s (NaN when the watch was given no wheel limit).
    pub reference_wheel_speed: T,
    /// The wheel speed limit it was held against, rad/s (the wheel stage's
    /// `wheel_speed_max`, the drive's no-load speed by default; infinite: none).
    pub wheel_speed_limit: T,
    /// First time the reference asked wheel speeds above that limit, s (`None`: never).
    pub over_limit_at: Option<T>,
    /// Path following: how far the closest point on the path moved forward over the last
    /// 10 % of t_end, m (NaN for trajectory tracking).
    pub progress_last_tenth: T,
    /// Path following on a path with an end: the distance from C to that end at the last
    /// step, m (NaN for an endless path and for trajectory tracking).
    pub final_distance_to_path_end: T,
}

/// Factor by which the mean error of the last tenth of t_end must exceed that of the
/// first tenth (and the tolerance) for the error to count as growing: a noisy sensor's
/// error wanders around a level (its mean over a tenth of the run barely moves); a
/// reference the robot cannot keep up with leaves it further behind.
pub const GROWTH_FACTOR: f64 = 2.0;

impl<T: Real> TrackingOutcome<T> {
    /// True when the error stayed below the tolerance over the last 10 % of t_end.
    pub fn within_tolerance(&self) -> bool {
        self.max_last_tenth < self.tolerance
    }

    /// True for a path-following run that stopped on the path: its closest point moved
    /// less than the tolerance over the last 10 % of t_end while C ended farther than
    /// `xy_goal_tolerance` (m) from the path's end (an endless path has none). A robot held
    /// in front of an obstacle, or one that gave up, stays close to the path without
    /// following it; a path follower that reached the end and stopped there has done its
    /// job. False for trajectory tracking, whose error already grows when the robot stops.
    pub fn stalled(&self, xy_goal_tolerance: T) -> bool {
        let at_end = self.final_distance_to_path_end <= xy_goal_tolerance;
        self.progress_last_tenth < self.tolerance && !at_end
    }

    /// True when the run followed its reference: within the tolerance over the last 10 %
    /// of t_end ([`Self::within_tolerance`]) and not [`Self::stalled`] short of the path's
    /// end (`xy_goal_tolerance`, m: how close to the end counts as there).
    pub fn followed(&self, xy_goal_tolerance: T) -> bool {
        self.within_tolerance() && !self.stalled(xy_goal_tolerance)
    }

    /// True when the error grew: its mean over the last tenth of t_end above the
    /// tolerance and above [`GROWTH_FACTOR`] times its mean over the first tenth.
    pub fn error_grew(&self) -> bool {
        let last = self.mean_last_tenth;
        last >= self.tolerance && last > T::lit(GROWTH_FACTOR) * self.mean_first_tenth
    }

    /// True for a run that is not within the tolerance at the end because the reference
    /// asks more than the robot can give: wheel speeds above the limit at some time
    /// ([`TrackingOutcome::over_limit_at`]), or an error that grew ([`Self::error_grew`]).
    /// Such a run is reported `cannot_follow`, not `unsettled` (merely slow).
    pub fn cannot_follow(&self) -> bool {
        !self.within_tolerance() && (self.over_limit_at.is_some() || self.error_grew())
    }
}

impl<T: Real> TrackingWatch<T> {
    /// A watch for a run of `t_end` s judged with `tolerance` m.
    pub fn new(kind: TrackingError, t_end: T, tolerance: T) -> Self {
        Self {
            kind,
            t_end,
            tolerance,
            cursor: PathCursor::default(),
            sum_sq: T::zero(),
            count: 0,
            max: T::zero(),
            tail_max: T::zero(),
            last_above: None,
            last_error: T::zero(),
            first_tenth: (T::zero(), 0),
            last_tenth: (T::zero(), 0),
            wheel_limit: None,
            reference_wheel_speed: T::zero(),
            over_limit_at: None,
            last_closest: None,
            closest_step: T::zero(),
            progress_last_tenth: T::zero(),
            path_end: None,
            last_position: (T::zero(), T::zero()),
        }
    }

    /// The watch holding the reference's wheel speeds, (|v_ref| + R |omega_ref|) / r
    /// (rad/s), against `wheel_speed_max` (rad/s) of a robot with wheel radius
    /// `wheel_radius` and half track `half_track` (m): a reference above it cannot be
    /// followed ([`TrackingOutcome::cannot_follow`]). An infinite limit is never passed.
    pub fn with_wheel_limit(mut self, wheel_radius: T, half_track: T, wheel_speed_max: T) -> Self {
        self.wheel_limit = Some((wheel_radius, half_track, wheel_speed_max));
        self
    }

    /// The error of the true pose `pose` at time `t` against `reference`, m.
    pub fn error_of<R: Reference<T>>(&mut self, reference: &R, t: T, pose: &Pose2<T>) -> T {
        match (self.kind, reference.path()) {
            (TrackingError::Path, Some(path)) => self.path_distance(path, pose),
            _ => {
                let r = reference.pose_at(t);
                (r.x - pose.x).hypot_libm(r.y - pose.y)
            }
        }
    }

    fn path_distance(&mut self, path: &dyn Path<T>, pose: &Pose2<T>) -> T {
        let s = self.cursor.advance(path, pose.x, pose.y, T::lit(PATH_WINDOW_M), T::lit(PATH_STEP_M));
        let p = path.pose_on_path(s);
        if self.path_end.is_none()
            && let Some(end) = path.end()
        {
            self.path_end = Some(path.point_on_path(<T as Lane>::splat(end)));
        }
        self.closest_step = self.last_closest.map_or(T::zero(), |(x, y)| (p.x - x).hypot_libm(p.y - y));
        self.last_closest = Some((p.x, p.y));
        (p.x - pose.x).hypot_libm(p.y - pose.y)
    }

    /// Adds the step at time `t` (s) with the true pose `pose`.
    pub fn observe<R: Reference<T>>(&mut self, reference: &R, t: T, pose: &Pose2<T>) {
        let e = self.error_of(reference, t, pose);
        self.last_error = e;
        self.last_position = (pose.x, pose.y);
        // NaN counts as above the tolerance.
        if e >= self.tolerance || e.is_nan() {
            self.last_above = Some(t);
        }
        if t >= self.t_end * T::lit(0.5) {
            self.sum_sq = self.sum_sq + e * e;
            self.count += 1;
            // NaN-propagating max: a non-finite error is never hidden.
            self.max = if e > self.max || e.is_nan() { e } else { self.max };
        }
        if t >= self.t_end * T::lit(0.9) {
            self.tail_max = if e > self.tail_max || e.is_nan() { e } else { self.tail_max };
            self.last_tenth = (self.last_tenth.0 + e, self.last_tenth.1 + 1);
            self.progress_last_tenth = self.progress_last_tenth + self.closest_step;
        }
        if t < self.t_end * T::lit(0.1) {
            self.first_tenth = (self.first_tenth.0 + e, self.first_tenth.1 + 1);
        }
        if let Some((r, big_r, limit)) = self.wheel_limit {
            let tw = reference.state_at(t).twist;
            let w = (tw.v.abs() + big_r * tw.omega.abs()) / r;
            if w > self.reference_wheel_speed {
                self.reference_wheel_speed = w;
            }
            if w > limit && self.over_limit_at.is_none() {
                self.over_limit_at = Some(t);
            }
        }
    }

    /// The outcome so far.
    pub fn finish(&self) -> TrackingOutcome<T> {
        let rms = if self.count > 0 { (self.sum_sq / T::lit(self.count as f64)).sqrt() } else { T::nan() };
        let time_to_tolerance = match self.last_above {
            None => Some(T::zero()),
            Some(t) if self.last_error < self.tolerance => Some(t),
            Some(_) => None,
        };
        TrackingOutcome {
            rms_last_half: rms,
            max_last_half: if self.count > 0 { self.max } else { T::nan() },
            max_last_tenth: if self.count > 0 { self.tail_max } else { T::nan() },
            time_to_tolerance,
            final_error: self.last_error,
            tolerance: self.tolerance,
            mean_first_tenth: mean(self.first_tenth),
            mean_last_tenth: mean(self.last_tenth),
            reference_wheel_speed: if self.wheel_limit.is_some() { self.reference_wheel_speed } else { T::nan() },
            wheel_speed_limit: self.wheel_limit.map_or(T::infinity(), |(_, _, w)| w),
            over_limit_at: self.over_limit_at,
            progress_last_tenth: if self.last_closest.is_some() { self.progress_last_tenth } else { T::nan() },
            final_distance_to_path_end: match self.path_end {
                Some((x, y)) => (x - self.last_position.0).hypot_libm(y - self.last_position.1),
                None => T::nan(),
            },
        }
    }
}

/// Mean of (sum, count); NaN for no samples.
fn mean<T: Real>((sum, n): (T, u64)) -> T {
    if n > 0 { sum / T::lit(n as f64) } else { T::nan() }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outcome(max_last_tenth: f64, first: f64, last: f64, over: Option<f64>) -> TrackingOutcome<f64> {
        TrackingOutcome {
            rms_last_half: last,
            max_last_half: max_last_tenth,
            max_last_tenth,
            time_to_tolerance: None,
            final_error: last,
            tolerance: 0.01,
            mean_first_tenth: first,
            mean_last_tenth: last,
            reference_wheel_speed: 30.0,
            wheel_speed_limit: 20.0,
            over_limit_at: over,
            progress_last_tenth: f64::NAN,
            final_distance_to_path_end: f64::NAN,
        }
    }

    /// Issue 38, item 8: a reference the robot cannot follow is told apart from a run
    /// that is merely slow or noisy.
    #[test]
    fn cannot_follow_needs_a_growing_error_or_a_reference_above_the_limit() {
        // Within the tolerance: never cannot_follow, even above the limit.
        assert!(!outcome(0.005, 0.1, 0.004, Some(1.0)).cannot_follow());
        // Above the limit and not within the tolerance.
        assert!(outcome(0.5, 0.01, 0.3, Some(1.0)).cannot_follow());
        // An error that grew: 19 m at the end from 1 cm.
        assert!(outcome(19.0, 0.01, 18.0, None).error_grew());
        assert!(outcome(19.0, 0.01, 18.0, None).cannot_follow());
        // A noisy sensor's error at a level above the tolerance: unsettled, not growing.
        assert!(!outcome(0.03, 0.012, 0.015, None).cannot_follow());
        // A slow convergence from a 10 cm offset: decreasing.
        assert!(!outcome(0.04, 0.1, 0.03, None).cannot_follow());
    }
}
