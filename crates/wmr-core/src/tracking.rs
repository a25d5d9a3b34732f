//! How a tracking or path-following run went, from the true state: the tracking error
//! over time, judged by the rule of wmr issue 23.
//!
//! The error at each plant step is the true distance from C to C_ref at that time
//! ([`TrackingError::Trajectory`]) or, for path following, to the reference's path
//! ([`TrackingError::Path`], the closest point found forward from the last one, the first
//! from the path's beginning, as pure pursuit finds it). Over a
//! run of length t_end:
//!
//! - **converged** when the error stays below the tolerance over the last 10 % of
//!   t_end; **diverged** when the run did; **unsettled** otherwise;
//! - RMS and maximum of the error over the last half (t >= t_end / 2);
//! - the time after which the error stays below the tolerance (`None` if it is above
//!   at the end).

use crate::Real;
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
}

impl<T: Real> TrackingOutcome<T> {
    /// True when the error stayed below the tolerance over the last 10 % of t_end.
    pub fn within_tolerance(&self) -> bool {
        self.max_last_tenth < self.tolerance
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
        }
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
        (p.x - pose.x).hypot_libm(p.y - pose.y)
    }

    /// Adds the step at time `t` (s) with the true pose `pose`.
    pub fn observe<R: Reference<T>>(&mut self, reference: &R, t: T, pose: &Pose2<T>) {
        let e = self.error_of(reference, t, pose);
        self.last_error = e;
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
        }
    }
}
