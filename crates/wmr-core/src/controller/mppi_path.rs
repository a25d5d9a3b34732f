//! MPPI on a path: the local plan (nav2's path handler) and the three path critics
//! (nav2 `PathAlignCritic`, `PathFollowCritic`, `PathAngleCritic`, read at
//! ros-navigation/navigation2 a3a97043e), which [`super::mppi`] adds to its goal critics
//! when the scenario's reference moves.
//!
//! # The local plan, every planning cycle
//!
//! nav2 follows a global plan given as poses at the costmap's resolution, pruned to the
//! part from the pose closest to the robot on, `prune_distance` m long. wmr's references
//! are curves, so the plan is made from the curve the same way: from the point closest to
//! C (a [`crate::reference::PathCursor`] searching forward within
//! `max_robot_pose_search_dist`, as pure pursuit's), points `path_resolution` m apart
//! (straight-line distance) for at most `prune_distance` m of plan and
//! [`MAX_PLAN_POINTS`] points, the path's end included when it is that close. A point is
//! *valid* when the footprint placed on it touches no obstacle (nav2: its cost is below
//! the inscribed cost). L = the plan's length, nav2's `local_path_length`, gates the
//! critics (and, in [`super::mppi`], the goal critics, whose goal is then the path's end).
//!
//! # The critics, with P_0 .. P_(K-1) the plan and F the furthest reached point (below)
//!
//! For a rollout q_1 .. q_T (the poses after each step):
//!
//! | critic | x | on when |
//! |---|---|---|
//! | `path_align` | mean over j = 1, 2, .. of \|q_(1 + j s) - P_m\|, s = `trajectory_point_step`, m the point of P_0 .. P_(F-1) whose distance along the plan is nearest to the rollout's along its strided points up to q_(1 + j s) (searched forward from the last m), invalid P_m skipped | L >= threshold, F >= `offset_from_furthest`, not more than `max_path_occupancy_ratio` of P_0 .. P_(F-1) invalid (or at most 2) |
//! | `path_follow` | \|q_T - P_m\|, m = min(F + offset, K - 1), moved on past invalid points (up to K - 2) | K >= 2, L >= threshold |
//! | `path_angle` | \|wrap(atan2(P_m - q_T) - yaw_T)\|, m = min(F + offset, K - 1); `mode` 1: the nearer of that and its reverse; 2: the direction P_m's heading allows | L >= threshold, C's bearing to P_m more than `max_angle_to_furthest` off its heading (in the same sense) |
//!
//! each as (weight x)^power for power > 1, else weight x. (nav2's path_align option
//! `use_path_orientations`, the heading error counted in the distance, is not offered.)
//!
//! F (nav2 `findPathFurthestReachedPoint`) is the largest, over the batch, of the plan
//! point nearest a rollout's last pose among those not farther along the plan than the
//! rollout is long.
//!
//! # Where wmr differs from nav2
//!
//! nav2 scores a batch it holds in memory, so F comes from the rollouts being scored. wmr
//! scores each rollout as it is made ([`super::mppi`]: nothing is stored), so **F is that
//! of the previous cycle's last iteration** (as a point on the path, found again in the new
//! plan), 0 at the first cycle: one `model_dt` late, while the robot moves at most
//! `vx_max * model_dt` (2.5 cm at nav2's defaults, half a plan step).

use num_traits::Float;

use crate::Real;
use crate::lane::Lane;
#[cfg(test)]
use crate::lane::Lanes;
use crate::math::{Pose2, wrap_angle};
use crate::obstacle::Obstacles;
use crate::reference::Path;
use crate::reference::path::lookahead;

use super::mppi::MppiParams;
use super::rollout::{ROLLOUT_LANES, Wide};

/// Most points of a local plan: `prune_distance / path_resolution` is validated below it.
pub const MAX_PLAN_POINTS: usize = 64;

/// The part of the reference's path the critics score against this cycle (module docs):
/// positions in m (world frame), headings in rad (the direction of travel), the path
/// parameter of each point and the distance along the plan from its first, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LocalPlan {
    len: usize,
    x: [f64; MAX_PLAN_POINTS],
    y: [f64; MAX_PLAN_POINTS],
    yaw: [f64; MAX_PLAN_POINTS],
    s: [f64; MAX_PLAN_POINTS],
    dist: [f64; MAX_PLAN_POINTS],
    valid: [bool; MAX_PLAN_POINTS],
}

impl LocalPlan {
    /// The plan of lane `lane` of `path` from the path parameter `s_c` (the point closest
    /// to C), its points `resolution` m apart up to `prune` m, each checked against
    /// `obstacles`.
    pub(super) fn along<L: Lane>(
        path: &dyn Path<L>,
        lane: usize,
        s_c: L::Scalar,
        resolution: L::Scalar,
        prune: f64,
        obstacles: &Obstacles<f64>,
    ) -> Self {
        let mut plan = Self {
            len: 0,
            x: [0.0; MAX_PLAN_POINTS],
            y: [0.0; MAX_PLAN_POINTS],
            yaw: [0.0; MAX_PLAN_POINTS],
            s: [0.0; MAX_PLAN_POINTS],
            dist: [0.0; MAX_PLAN_POINTS],
            valid: [true; MAX_PLAN_POINTS],
        };
        let f = |x: L::Scalar| x.to_f64_lossless();
        let at = |s: L::Scalar| {
            let p = path.pose_on_path(L::splat(s));
            (p.x.lane(lane), p.y.lane(lane), p.theta.lane(lane))
        };
        // The searches step the path point by a quarter of the spacing.
        let ds = resolution * <L::Scalar as Real>::lit(0.25);
        let reach = resolution * <L::Scalar as Real>::lit(2.0);
        let (mut s, (mut px, mut py, theta)) = (s_c, at(s_c));
        plan.push(f(s), f(px), f(py), f(theta), 0.0);
        while plan.len < MAX_PLAN_POINTS {
            let next =
                lookahead(path, L::splat(px), L::splat(py), L::splat(s), L::splat(resolution), ds, reach).lane(lane);
            if next <= s {
                break; // the path's end
            }
            let (x, y, theta) = at(next);
            let step = Real::hypot_libm(f(x - px), f(y - py));
            let along = plan.length() + step;
            if step <= 0.0 || along > prune {
                break;
            }
            plan.push(f(next), f(x), f(y), f(theta), along);
            (s, px, py) = (next, x, y);
        }
        if !obstacles.is_empty() {
            let points = plan.x.iter().zip(&plan.y).take(plan.len);
            for (valid, (&x, &y)) in plan.valid.iter_mut().zip(points) {
                *valid = obstacles.clearance(x, y) > 0.0;
            }
        }
        plan
    }

    // Every index through `get`: no panic path (the firmware's C library is checked for them).
    fn push(&mut self, s: f64, x: f64, y: f64, yaw: f64, dist: f64) {
        let k = self.len;
        if let (Some(ps), Some(px), Some(py), Some(pyaw), Some(pd)) =
            (self.s.get_mut(k), self.x.get_mut(k), self.y.get_mut(k), self.yaw.get_mut(k), self.dist.get_mut(k))
        {
            (*ps, *px, *py, *pyaw, *pd) = (s, x, y, yaw, dist);
            self.len += 1;
        }
    }

    /// Point `k` (x, y, yaw), the last one for `k` beyond.
    fn point(&self, k: usize) -> (f64, f64, f64) {
        let k = k.min(self.len.saturating_sub(1));
        let at = |a: &[f64; MAX_PLAN_POINTS]| a.get(k).copied().unwrap_or(0.0);
        (at(&self.x), at(&self.y), at(&self.yaw))
    }

    /// Whether point `k` is free of obstacles (false beyond the plan).
    fn free(&self, k: usize) -> bool {
        k < self.len && self.valid.get(k).copied().unwrap_or(false)
    }

    /// The number of points, K >= 1.
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// L, m: nav2's `local_path_length`.
    pub(super) fn length(&self) -> f64 {
        self.len.checked_sub(1).and_then(|k| self.dist.get(k)).copied().unwrap_or(0.0)
    }

    /// The plan's last point (the goal of the goal critics on a path).
    pub(super) fn last(&self) -> Pose2<f64> {
        let (x, y, theta) = self.point(self.len.saturating_sub(1));
        Pose2 { x, y, theta }
    }

    /// The path parameter of point `k`.
    pub(super) fn s(&self, k: usize) -> f64 {
        self.s.get(k.min(self.len.saturating_sub(1))).copied().unwrap_or(0.0)
    }

    /// The index of the last point at or before the path parameter `s` (0 when none).
    pub(super) fn index_at(&self, s: f64) -> usize {
        // A loop, not `rposition`: no panic path.
        let mut found = 0;
        for (k, &sk) in self.s.iter().enumerate().take(self.len) {
            if sk <= s {
                found = k;
            }
        }
        found
    }

    /// nav2 `findClosestPathPt`: among points 0 .. `count`, the one whose distance along the
    /// plan is nearest `along` (m), searching forward from `from`.
    fn closest_along(&self, count: usize, along: f64, from: usize) -> usize {
        let size = count.min(self.len);
        let mut before = if from != 0 { self.dist.get(from).copied().unwrap_or(0.0) } else { 0.0 };
        for (i, &d) in self.dist.iter().enumerate().take(size).skip(from.saturating_add(1)) {
            if d > along {
                return if along - before < d - along { i.saturating_sub(1) } else { i };
            }
            before = d;
        }
        size.saturating_sub(1)
    }

    /// nav2 `findPathFurthestReachedPoint` for one rollout: the point nearest its last
    /// position (`x`, `y`) among those not farther along the plan than its length `along`.
    fn reached(&self, along: f64, x: f64, y: f64) -> usize {
        // std::lower_bound: the first point at least `along` along the plan.
        let last = self.len.saturating_sub(1);
        let mut reachable = last;
        for (k, &d) in self.dist.iter().enumerate().take(self.len) {
            if d >= along {
                reachable = k;
                break;
            }
        }
        let mut best = (0, f64::INFINITY);
        for (k, (&px, &py)) in self.x.iter().zip(&self.y).enumerate().take(reachable.saturating_add(1)) {
            let d2 = (px - x) * (px - x) + (py - y) * (py - y);
            if d2 < best.1 {
                best = (k, d2);
            }
        }
        best.0
    }
}

/// What the path critics need from a cycle, fixed before its rollouts: which critics are
/// on and the points they aim at.
#[derive(Clone, Copy, Debug)]
pub(super) struct PathTargets<'a> {
    plan: &'a LocalPlan,
    /// F, the furthest reached point of the last cycle, in this plan.
    furthest: usize,
    /// path_align: on, and over points 0 .. F.
    align: bool,
    step: usize,
    /// path_follow: the point the rollout's end should reach.
    follow: Option<(f64, f64)>,
    /// path_angle: the point the rollout's end should face, its heading, and the mode.
    angle: Option<(f64, f64, f64, u32)>,
}

impl<'a> PathTargets<'a> {
    /// The targets of a cycle from C's `pose` (world frame) on `plan`, F = `furthest`.
    pub(super) fn new<T: Real>(p: &MppiParams<T>, plan: &'a LocalPlan, furthest: usize, pose: Pose2<f64>) -> Self {
        let f = |x: T| x.to_f64_lossless();
        let length = plan.length();
        let k = plan.len();
        let last = k.saturating_sub(1);
        let align = p.path_align_cost_weight > T::zero()
            && length >= f(p.path_align_threshold_to_consider)
            && furthest >= p.path_align_offset_from_furthest as usize
            && {
                // nav2: off while obstacles block a share of the plan up to F.
                let ratio = f(p.path_align_max_path_occupancy_ratio);
                let mut invalid = 0.0;
                let mut blocked = false;
                for &v in plan.valid.iter().take(furthest.min(k)) {
                    if !v {
                        invalid += 1.0;
                    }
                    if invalid / furthest as f64 > ratio && invalid > 2.0 {
                        blocked = true;
                        break;
                    }
                }
                !blocked
            };
        let follow = (p.path_follow_cost_weight > T::zero()
            && k >= 2
            && length >= f(p.path_follow_threshold_to_consider))
        .then(|| {
            let mut m = furthest.saturating_add(p.path_follow_offset_from_furthest as usize).min(last);
            // Past points an obstacle blocks (nav2: drive past it, not through it).
            while !plan.free(m) && m + 1 < last {
                m += 1;
            }
            let (x, y, _) = plan.point(m);
            (x, y)
        });
        let angle = (p.path_angle_cost_weight > T::zero() && length >= f(p.path_angle_threshold_to_consider))
            .then(|| plan.point(furthest.saturating_add(p.path_angle_offset_from_furthest as usize).min(last)))
            .and_then(|(gx, gy, gyaw)| {
                // nav2: no directional preference needs reversing (vx_min < 0).
                let mode = if p.path_angle_mode == 1 && p.vx_min >= T::zero() { 0 } else { p.path_angle_mode };
                let bearing = Real::atan2_libm(gy - pose.y, gx - pose.x);
                let off = match mode {
                    0 => wrap_angle(pose.theta - bearing).abs(),
                    1 => wrap_angle(pose.theta - bearing)
                        .abs()
                        .min(wrap_angle(wrap_angle(pose.theta + core::f64::consts::PI) - bearing).abs()),
                    _ => {
                        let b = if wrap_angle(gyaw - bearing).abs() > core::f64::consts::FRAC_PI_2 {
                            wrap_angle(bearing + core::f64::consts::PI)
                        } else {
                            bearing
                        };
                        wrap_angle(pose.theta - b).abs()
                    }
                };
                (off >= f(p.path_angle_max_angle_to_furthest)).then_some((gx, gy, gyaw, mode))
            });
        Self { plan, furthest, align, step: (p.path_align_trajectory_point_step as usize).max(1), follow, angle }
    }
}

/// The path critics' raw costs of one rollout (before weight and power) and its F.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct PathCosts {
    /// path_align's mean distance, m (`None`: off this cycle).
    pub align: Option<f64>,
    /// path_follow's distance, m.
    pub follow: Option<f64>,
    /// path_angle's angle, rad.
    pub angle: Option<f64>,
    /// The plan point this rollout reached (its share of F).
    pub reached: usize,
}

/// The path critics' sums over [`ROLLOUT_LANES`] rollouts made side by side: fed each
/// step's poses ([`PathSums::add`]), read at the end ([`PathSums::finish`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct PathSums {
    /// The last pose seen and the one before it.
    last: Pose2<Wide>,
    /// The rollout's length over all its steps (from q_1), m.
    length: Wide,
    /// path_align: the last strided point, the length along the strided points, the last
    /// plan point matched, the sum of distances and their number.
    strided: (Wide, Wide),
    strided_length: Wide,
    matched: [usize; ROLLOUT_LANES],
    sum: [f64; ROLLOUT_LANES],
    count: [u32; ROLLOUT_LANES],
}

impl PathSums {
    pub(super) fn new() -> Self {
        let zero = Wide::default();
        Self {
            last: Pose2 { x: zero, y: zero, theta: zero },
            length: zero,
            strided: (zero, zero),
            strided_length: zero,
            matched: [0; ROLLOUT_LANES],
            sum: [0.0; ROLLOUT_LANES],
            count: [0; ROLLOUT_LANES],
        }
    }

    /// Step `i` (0-based: q_(i+1)) of the rollouts, at `pose`.
    #[inline(always)]
    pub(super) fn add(&mut self, t: &PathTargets<'_>, i: usize, pose: Pose2<Wide>) {
        if i > 0 {
            self.length = self.length + (pose.x - self.last.x).hypot(pose.y - self.last.y);
        }
        self.last = pose;
        if !t.align || !i.is_multiple_of(t.step) {
            return;
        }
        if i == 0 {
            self.strided = (pose.x, pose.y);
            return;
        }
        self.strided_length = self.strided_length + (pose.x - self.strided.0).hypot(pose.y - self.strided.1);
        self.strided = (pose.x, pose.y);
        let plan = t.plan;
        for j in 0..ROLLOUT_LANES {
            let m = plan.closest_along(t.furthest, self.strided_length.lane(j), self.matched[j]);
            self.matched[j] = m;
            if plan.free(m) {
                let (px, py, _) = plan.point(m);
                let (dx, dy) = (px - pose.x.lane(j), py - pose.y.lane(j));
                self.sum[j] += Float::sqrt(dx * dx + dy * dy);
                self.count[j] += 1;
            }
        }
    }

    /// Each rollout's raw costs and the plan point it reached.
    pub(super) fn finish(&self, t: &PathTargets<'_>) -> [PathCosts; ROLLOUT_LANES] {
        core::array::from_fn(|j| {
            // `get`, not `Lane::lane`: no panic path where the closure is not inlined.
            let lane = |w: Wide| w.0.get(j).copied().unwrap_or(0.0);
            let (x, y, yaw) = (lane(self.last.x), lane(self.last.y), lane(self.last.theta));
            PathCosts {
                align: t.align.then(|| {
                    let (sum, count) =
                        (self.sum.get(j).copied().unwrap_or(0.0), self.count.get(j).copied().unwrap_or(0));
                    if count > 0 { sum / f64::from(count) } else { 0.0 }
                }),
                follow: t.follow.map(|(gx, gy)| Real::hypot_libm(x - gx, y - gy)),
                angle: t.angle.map(|(gx, gy, gyaw, mode)| {
                    let between = Real::atan2_libm(gy - y, gx - x);
                    let d = wrap_angle(between - yaw).abs();
                    match mode {
                        0 => d,
                        1 => {
                            let b = if d < core::f64::consts::FRAC_PI_2 {
                                between
                            } else {
                                wrap_angle(between + core::f64::consts::PI)
                            };
                            wrap_angle(b - yaw).abs()
                        }
                        _ => {
                            let b = if wrap_angle(between - gyaw).abs() < core::f64::consts::FRAC_PI_2 {
                                between
                            } else {
                                wrap_angle(between + core::f64::consts::PI)
                            };
                            wrap_angle(b - yaw).abs()
                        }
                    }
                }),
                reached: t.plan.reached(lane(self.length), x, y),
            }
        })
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;
    use crate::reference::{Circle, Line};
    use crate::sensor::gaussian::mix64;

    fn uniform(h: &mut u64) -> f64 {
        *h = mix64(*h);
        (*h >> 11) as f64 / 9_007_199_254_740_992.0
    }

    #[test]
    fn a_plan_on_a_line_is_evenly_spaced_from_the_closest_point_and_pruned() {
        let line = Line::new(Pose2 { x: 1.0, y: 2.0, theta: 0.5 }, 0.3).unwrap();
        // s = arc length on a line: from s = 0.4, 0.05 m apart, at most 2.02 m of plan.
        let plan = LocalPlan::along::<f64>(&line, 0, 0.4, 0.05, 2.02, &Obstacles::default());
        assert_eq!(plan.len(), 41, "2 m / 0.05 m steps, both ends");
        assert!((plan.length() - 2.0).abs() < 1e-6, "{}", plan.length());
        for k in 0..plan.len() {
            let s = 0.4 + 0.05 * k as f64;
            assert!((plan.x[k] - (1.0 + s * 0.5f64.cos())).abs() < 1e-6);
            assert!((plan.y[k] - (2.0 + s * 0.5f64.sin())).abs() < 1e-6);
            assert!((plan.dist[k] - 0.05 * k as f64).abs() < 1e-6);
            assert!((plan.yaw[k] - 0.5).abs() < 1e-12);
        }
        assert_eq!(plan.index_at(0.4 + 0.05 * 7.5), 7);
        assert_eq!(plan.index_at(0.0), 0);
    }

    #[test]
    fn a_plan_is_capped_and_marks_the_points_an_obstacle_blocks() {
        let circle = Circle::new(0.0, 0.0, 1.0, 0.3, 0.0).unwrap();
        let obstacles =
            Obstacles::new(&[crate::obstacle::Obstacle::Circle { center: (1.0, 0.0), radius: 0.1 }], 0.05).unwrap();
        let plan = LocalPlan::along::<f64>(&circle, 0, 0.0, 0.01, 5.0, &obstacles);
        assert_eq!(plan.len(), MAX_PLAN_POINTS);
        let blocked: Vec<usize> = (0..plan.len()).filter(|&k| !plan.valid[k]).collect();
        // The circle starts at (1, 0) heading +y: the points within 0.15 m of the post's centre.
        for k in 0..plan.len() {
            let d = (plan.x[k] - 1.0).hypot(plan.y[k]);
            assert_eq!(!plan.valid[k], d <= 0.15, "point {k} at {d} m");
        }
        assert!(!blocked.is_empty());
    }

    /// nav2's batch critics, ported literally from `path_align_critic.cpp`,
    /// `path_follow_critic.cpp`, `path_angle_critic.cpp` and `utils.hpp`
    /// (`findPathFurthestReachedPoint`, `findClosestPathPt`) over stored trajectories.
    struct Nav2 {
        x: Vec<f64>,
        y: Vec<f64>,
        yaw: Vec<f64>,
        valid: Vec<bool>,
    }

    impl Nav2 {
        fn furthest(&self, traj: &[Vec<Pose2<f64>>]) -> usize {
            let n = self.x.len();
            let mut dists = std::vec![0.0; n];
            for i in 1..n {
                dists[i] = dists[i - 1] + (self.x[i] - self.x[i - 1]).hypot(self.y[i] - self.y[i - 1]);
            }
            let mut max_idx = 0;
            for t in traj {
                let len: f64 = t.windows(2).map(|w| (w[1].x - w[0].x).hypot(w[1].y - w[0].y)).sum();
                let reach = dists.partition_point(|&d| d < len).min(n - 1);
                let end = t.last().unwrap();
                let mut best = (0, f64::INFINITY);
                for k in 0..=reach {
                    let d2 = (self.x[k] - end.x).powi(2) + (self.y[k] - end.y).powi(2);
                    if d2 < best.1 {
                        best = (k, d2);
                    }
                }
                max_idx = max_idx.max(best.0);
            }
            max_idx
        }

        fn closest_pt(vec: &[f64], dist: f64, init: usize) -> usize {
            let mut distim1 = if init != 0 { vec[init] } else { 0.0 };
            #[allow(clippy::needless_range_loop)] // nav2's loop, as written there
            for i in init + 1..vec.len() {
                let disti = vec[i];
                if disti > dist {
                    if i > 0 && dist - distim1 < disti - dist {
                        return i - 1;
                    }
                    return i;
                }
                distim1 = disti;
            }
            vec.len() - 1
        }

        fn align(&self, t: &[Vec<Pose2<f64>>], furthest: usize, step: usize) -> Vec<f64> {
            let count = furthest;
            let mut dists = std::vec![0.0; count];
            for i in 1..count {
                dists[i] = dists[i - 1] + (self.x[i] - self.x[i - 1]).hypot(self.y[i] - self.y[i - 1]);
            }
            t.iter()
                .map(|traj| {
                    let strided: Vec<&Pose2<f64>> = traj.iter().step_by(step).collect();
                    let (mut sum, mut n, mut along, mut pt) = (0.0, 0u32, 0.0, 0usize);
                    for p in 1..strided.len() {
                        along += (strided[p].x - strided[p - 1].x).hypot(strided[p].y - strided[p - 1].y);
                        pt = Self::closest_pt(&dists, along, pt);
                        if self.valid[pt] {
                            n += 1;
                            sum += (self.x[pt] - strided[p].x).hypot(self.y[pt] - strided[p].y);
                        }
                    }
                    if n > 0 { sum / f64::from(n) } else { 0.0 }
                })
                .collect()
        }
    }

    #[test]
    fn the_streaming_critics_equal_nav2s_batch_critics() {
        let circle = Circle::new(0.0, 0.0, 1.0, 0.3, 0.0).unwrap();
        let obstacles =
            Obstacles::new(&[crate::obstacle::Obstacle::Circle { center: (0.5403, 0.8415), radius: 0.06 }], 0.0)
                .unwrap();
        let plan = LocalPlan::along::<f64>(&circle, 0, 0.1, 0.05, 2.0, &obstacles);
        assert!(plan.valid[..plan.len()].iter().any(|v| !v), "an obstacle blocks some points");
        let nav2 = Nav2 {
            x: plan.x[..plan.len()].to_vec(),
            y: plan.y[..plan.len()].to_vec(),
            yaw: plan.yaw[..plan.len()].to_vec(),
            valid: plan.valid[..plan.len()].to_vec(),
        };
        let p = MppiParams::<f64> { path_align_offset_from_furthest: 5, ..MppiParams::default() };
        let pose = Pose2 { x: 1.0, y: 0.05, theta: 2.5 };
        // Random rollouts around the circle: 8 lanes x 3 groups, 56 steps.
        let mut h = 7u64;
        let rollouts: Vec<Vec<Pose2<f64>>> = (0..24)
            .map(|_| {
                let (v, w) = (0.1 + 0.5 * uniform(&mut h), 1.6 * uniform(&mut h) - 0.3);
                let mut q = Pose2 { x: 1.0, y: 0.05, theta: 1.5 };
                (0..56)
                    .map(|_| {
                        q.theta += w * 0.05;
                        q.x += v * q.theta.cos() * 0.05;
                        q.y += v * q.theta.sin() * 0.05;
                        q
                    })
                    .collect()
            })
            .collect();
        let furthest_prev = nav2.furthest(&rollouts[..8]);
        assert!(furthest_prev >= 5, "path_align is on: {furthest_prev}");
        let t = PathTargets::new(&p, &plan, furthest_prev, pose);
        assert!(t.align && t.follow.is_some(), "all on");
        let expected_align = nav2.align(&rollouts, furthest_prev, 4);
        let mut reached = 0;
        for (g, group) in rollouts.chunks(ROLLOUT_LANES).enumerate() {
            let mut sums = PathSums::new();
            #[allow(clippy::needless_range_loop)] // step i of every rollout of the group
            for i in 0..56 {
                let pick = |f: fn(&Pose2<f64>) -> f64| Lanes(core::array::from_fn(|j| f(&group[j % group.len()][i])));
                sums.add(&t, i, Pose2 { x: pick(|q| q.x), y: pick(|q| q.y), theta: pick(|q| q.theta) });
            }
            for (j, c) in sums.finish(&t).iter().enumerate().take(group.len()) {
                let k = g * ROLLOUT_LANES + j;
                let end = rollouts[k].last().unwrap();
                assert!((c.align.unwrap() - expected_align[k]).abs() < 1e-12, "align {k}");
                // nav2 path_follow: min(F + 6, K - 1), past invalid points.
                let mut m = (furthest_prev + 6).min(nav2.x.len() - 1);
                while !nav2.valid[m] && m < nav2.x.len() - 2 {
                    m += 1;
                }
                let follow = (end.x - nav2.x[m]).hypot(end.y - nav2.y[m]);
                assert!((c.follow.unwrap() - follow).abs() < 1e-12, "follow {k}");
                if let Some(angle) = c.angle {
                    let m = (furthest_prev + 4).min(nav2.x.len() - 1);
                    let between = (nav2.y[m] - end.y).atan2(nav2.x[m] - end.x);
                    let expected = wrap_angle(between - end.theta).abs();
                    assert!((angle - expected).abs() < 1e-12, "angle {k}");
                }
                reached = reached.max(c.reached);
            }
        }
        assert_eq!(reached, nav2.furthest(&rollouts), "F over the batch");
        let _ = &nav2.yaw;
    }
}
