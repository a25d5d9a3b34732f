//! The geometric path of a reference (time ignored) and the two queries path following
//! asks of it: the closest point to C, searching forward from a cursor, and the first
//! point at a given distance from C beyond it.
//!
//! A path is a curve p(s) over a parameter s in [0, s_end] (s_end infinite for an
//! endless path), with |dp/ds| between two known bounds ([`Path::rate_bounds`]): the
//! searches step s so that no step moves the point farther than a given distance. Each
//! kind says what its s is (the arc length for a circle, a line and the waypoints'
//! spline; the time for the figure-eight). Every search takes a fixed number of steps
//! decided by parameters alone, so it runs unchanged over several runs side by side
//! ([`crate::lane`]).

use crate::lane::{Lane, Mask};
use crate::math::Pose2;

/// A reference's geometric path: what [`crate::controller::PurePursuitLaw`] follows and
/// what the outcome of a path-following run is judged against.
pub trait Path<T: Lane> {
    /// The point of the path at parameter `s` (clamped into [0, s_end]): x, y in m
    /// (world frame) and theta, rad, the direction of travel along the path.
    fn pose_on_path(&self, s: T) -> Pose2<T>;

    /// The last parameter value, `None` for an endless path (a circle, a line).
    fn end(&self) -> Option<T::Scalar>;

    /// (min, max) of |dp/ds| over the path, in m per unit of s; both > 0.
    fn rate_bounds(&self) -> (T::Scalar, T::Scalar);

    /// The path's length from `s` to its end, m (infinite for an endless path).
    fn remaining_length(&self, s: T) -> T;

    /// The position of [`Path::pose_on_path`] alone (x, y in m, world frame), the same
    /// numbers: what the distance searches ask for, without the heading (an `atan2`
    /// costs as much as the rest of a search step).
    #[inline(always)]
    fn point_on_path(&self, s: T) -> (T, T) {
        let p = self.pose_on_path(s);
        (p.x, p.y)
    }
}

/// Squared distance (m^2) from (x, y) to the path point at `s`.
#[inline(always)]
fn dist2<T: Lane>(path: &dyn Path<T>, s: T, x: T, y: T) -> T {
    let (px, py) = path.point_on_path(s);
    let (dx, dy) = (px - x, py - y);
    dx * dx + dy * dy
}

/// `s` clamped into the path's range.
#[inline(always)]
fn clamp_s<T: Lane>(path: &dyn Path<T>, s: T) -> T {
    let s = s.max(T::default());
    match path.end() {
        Some(end) => s.min(T::splat(end)),
        None => s,
    }
}

/// Whole steps of `step` that cover `span` (at least one).
fn steps<T: Lane>(span: T::Scalar, step: T::Scalar) -> u32 {
    let n = num_traits::Float::ceil(span / step);
    let n = <T::Scalar as num_traits::ToPrimitive>::to_u32(&n).unwrap_or(1);
    n.clamp(1, 4096)
}

/// Golden-section iterations of [`closest`]: shrinks the bracket to 0.618^24 = 1e-5 of a step.
const GOLDEN_ITERATIONS: u32 = 24;
/// Bisection iterations of [`lookahead`]: 2^-24 of a step.
const BISECTIONS: u32 = 24;

/// The parameter of the path point closest to (x, y) within `span` (in s) forward of
/// `from`: a scan of the whole span at steps that move the path point by at most `ds`
/// (m), then a golden-section search in the step either side of the best sample (kept
/// at or after `from`). `ds` must be small against the path's radius of curvature for
/// the answer to be the closest point and not a nearby local minimum. The brute-force
/// search: [`closest_forward`] is the one a cursor makes from tick to tick.
pub fn closest<T: Lane>(path: &dyn Path<T>, x: T, y: T, from: T, span: T::Scalar, ds: T::Scalar) -> T {
    scan_and_refine(path, x, y, from, span, ds, false)
}

/// [`closest`] that ends its scan, lane by lane, at the first sample farther from (x, y)
/// than the one before it (the first local minimum forward of `from`, as nav2's regulated
/// pure pursuit takes the closest pose of the pruned plan from its last one): the same
/// answer wherever the distance along the span falls to one minimum and rises after it
/// (a robot near the path, a window shorter than the radius of curvature), in a few
/// steps instead of the whole span. `tests/path_search.rs` checks it against [`closest`].
pub fn closest_forward<T: Lane>(path: &dyn Path<T>, x: T, y: T, from: T, span: T::Scalar, ds: T::Scalar) -> T {
    scan_and_refine(path, x, y, from, span, ds, true)
}

#[inline(always)]
fn scan_and_refine<T: Lane>(
    path: &dyn Path<T>,
    x: T,
    y: T,
    from: T,
    span: T::Scalar,
    ds: T::Scalar,
    stop_at_rise: bool,
) -> T {
    let (_, rate_max) = path.rate_bounds();
    let step = ds / rate_max;
    let n = steps::<T>(span, step);
    let from = clamp_s(path, from);
    let mut best = from;
    let mut best_d2 = dist2(path, from, x, y);
    let mut rising = T::Mask::splat(false);
    for k in 1..=n {
        let s = clamp_s(path, from + T::splat(step) * T::lit(f64::from(k)));
        let d2 = dist2(path, s, x, y);
        // A lane past its first minimum keeps its best (the scan goes on for the others).
        let better = d2.lt(best_d2) & !rising;
        best = T::select(better, s, best);
        best_d2 = T::select(better, d2, best_d2);
        if stop_at_rise {
            rising = rising | best_d2.lt(d2);
            if rising.all() {
                break;
            }
        }
    }
    // Golden section on [best - step, best + step] within [from, end].
    let mut a = clamp_s(path, (best - T::splat(step)).max(from));
    let mut b = clamp_s(path, best + T::splat(step));
    let g = T::lit(0.618_033_988_749_894_8);
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let mut fc = dist2(path, c, x, y);
    let mut fd = dist2(path, d, x, y);
    for _ in 0..GOLDEN_ITERATIONS {
        // f(c) < f(d): the minimum is in [a, d], d becomes the old c; otherwise in
        // [c, b], c becomes the old d. One new point per iteration, chosen per lane.
        let left = fc.lt(fd);
        let (na, nb) = (T::select(left, a, c), T::select(left, d, b));
        a = na;
        b = nb;
        let fresh = T::select(left, b - g * (b - a), a + g * (b - a));
        let f_fresh = dist2(path, fresh, x, y);
        let (oc, ofc, od, ofd) = (c, fc, d, fd);
        c = T::select(left, fresh, od);
        fc = T::select(left, f_fresh, ofd);
        d = T::select(left, oc, fresh);
        fd = T::select(left, ofc, f_fresh);
    }
    let mid = (a + b) * T::lit(0.5);
    let dm = dist2(path, mid, x, y);
    // Keep the scan's sample when the refinement did no better (a minimum at the bracket's end).
    T::select(dm.lt(best_d2), mid, best)
}

/// The first path point at distance `l` (m) from (x, y), searching forward from the
/// parameter `from` (the closest point) in steps that move the path point by at most `ds`
/// (m), up to `reach` m of path; bisected to the crossing. When the point at `from` is
/// already at least `l` away, `from`; when no point within reach is far enough, the last
/// point searched (the path's end, for a short path). Returns the parameter.
pub fn lookahead<T: Lane>(path: &dyn Path<T>, x: T, y: T, from: T, l: T, ds: T::Scalar, reach: T::Scalar) -> T {
    let (rate_min, rate_max) = path.rate_bounds();
    let step = ds / rate_max;
    let n = steps::<T>(reach / rate_min, step);
    let l2 = l * l;
    let from = clamp_s(path, from);
    let mut found = l2.le(dist2(path, from, x, y));
    let mut lo = from;
    let mut hi = from;
    let mut prev = from;
    for k in 1..=n {
        let s = clamp_s(path, from + T::splat(step) * T::lit(f64::from(k)));
        let crossing = !found & l2.le(dist2(path, s, x, y));
        lo = T::select(crossing, prev, lo);
        hi = T::select(crossing, s, hi);
        found = found | crossing;
        // Not found yet: the search's last point so far.
        hi = T::select(found, hi, s);
        lo = T::select(found, lo, s);
        prev = s;
        if found.all() {
            break;
        }
    }
    for _ in 0..BISECTIONS {
        let mid = (lo + hi) * T::lit(0.5);
        let beyond = l2.le(dist2(path, mid, x, y));
        hi = T::select(beyond, mid, hi);
        lo = T::select(beyond, lo, mid);
    }
    hi
}

/// Follows the closest point of a path from tick to tick as nav2 prunes its plan: the
/// first search starts at the path's beginning, every search covers `window` m of path
/// forward of the last closest point (nav2's `max_robot_pose_search_dist`), and the cursor
/// only moves forward ([`closest_forward`] near the path, the whole window farther from it).
/// A route that ends near its start (a patrol loop) or crosses itself (a figure-eight) is
/// so taken from its beginning, not joined where it ends or on its other branch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathCursor<T: Lane> {
    /// Parameter of the last closest point.
    pub s: T,
    /// False until the first search (which starts at s = 0).
    pub started: T::Mask,
}

impl<T: Lane> Default for PathCursor<T> {
    /// Not started: the first search starts at s = 0.
    fn default() -> Self {
        Self { s: T::default(), started: T::Mask::splat(false) }
    }
}

impl<T: Lane> PathCursor<T> {
    /// The closest path point to (x, y) (m), searching forward from the last one (the
    /// first time from s = 0) over `window` m of path, in steps of at most `ds` m; moves
    /// the cursor there and returns the parameter.
    pub fn advance(&mut self, path: &dyn Path<T>, x: T, y: T, window: T::Scalar, ds: T::Scalar) -> T {
        let (rate_min, _) = path.rate_bounds();
        let span = window / rate_min;
        let from = T::select(self.started, self.s, T::default());
        // The first search scans its whole window from the path's beginning (nav2's
        // closest pose among the plan's poses up to max_robot_pose_search_dist). After
        // it, near the path the closest point moves on from the last one: the search
        // stops at its first minimum. Farther than `2 ds` from the path (a start off it,
        // a corner cut), where the distance along the window may have several minima,
        // the whole window is scanned, as the first minimum could be behind the robot.
        self.s = if self.started.all() {
            let near = closest_forward(path, x, y, from, span, ds);
            let (px, py) = path.point_on_path(near);
            let (dx, dy) = (px - x, py - y);
            let reach = T::splat(ds * <T::Scalar as crate::Real>::lit(2.0));
            let far = (reach * reach).lt(dx * dx + dy * dy);
            if far.any() { T::select(far, closest(path, x, y, from, span, ds), near) } else { near }
        } else {
            closest(path, x, y, from, span, ds)
        };
        self.started = T::Mask::splat(true);
        self.s
    }

    /// Forgets the cursor in `lanes` (as at t = 0).
    pub fn reset_lanes(&mut self, lanes: T::Mask) {
        self.started = self.started & !lanes;
        self.s = T::select(lanes, T::default(), self.s);
    }
}
