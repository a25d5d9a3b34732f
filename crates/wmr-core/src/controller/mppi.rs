//! Model Predictive Path Integral control (MPPI) as nav2's `nav2_mppi_controller` runs
//! it: sample `batch_size` control sequences around the previous optimal one, roll each
//! out over `time_steps` steps of `model_dt` on a motion model, score the rollouts with
//! critics, and average the samples with softmax weights of their costs.
//!
//! Source: G. Williams, P. Drews, B. Goldfain, J. M. Rehg, E. A. Theodorou, "Information
//! theoretic MPC for model-based reinforcement learning", Proc. IEEE ICRA 2017; in the
//! form of nav2's `nav2_mppi_controller` (`optimizer.cpp`, `motion_models.hpp`,
//! `critics/*.cpp`, `tools/utils.hpp`), read at ros-navigation/navigation2 a3a97043e
//! (2026). The keys are nav2's (snake_case, flat: `goal_cost_weight` is nav2's
//! `GoalCritic.cost_weight`, since wmr's parameter structs are flat), with nav2's defaults.
//!
//! # One cycle (nav2 `Optimizer::evalControl`), every `model_dt`
//!
//! With the sequence u_t = (vx_t, wz_t), t = 0 .. T-1 (T = `time_steps`), the last
//! command c and the speed (v, w) measured from the wheel encoders
//! (v = r (w_R + w_L) / 2, w = r (w_R - w_L) / (2 R)):
//!
//! ```text
//! speed   s = (clamp(c.vx, v + dt ax_min, v + dt ax_max), clamp(c.wz, w - dt az_max, w + dt az_max))
//! repeat iteration_count times:
//!   u_0 = s
//!   sample k:  cvx_k,t = vx_t + vx_std n,  cwz_k,t = wz_t + wz_std n'      (n, n' ~ N(0, 1))
//!   rollout:   vx_0 = s.vx, wz_0 = s.wz,
//!              vx_i = clamp(cvx_(i-1), vx_(i-1) + dt ax_min, vx_(i-1) + dt ax_max)   (vx_(i-1) > 0; mirrored below)
//!              wz_i = clamp(cwz_(i-1), wz_(i-1) - dt az_max, wz_(i-1) + dt az_max)
//!              yaw_i = yaw_(i-1) + wz_i dt,  x_i = x_(i-1) + vx_i cos(yaw_(i-1)) dt,  y likewise
//!   cost:      S_k = critics (below) + gamma / vx_std^2 sum_t (cvx_k,t - vx_t) vx_t
//!                                    + gamma / wz_std^2 sum_t (cwz_k,t - wz_t) wz_t
//!   weights:   w_k = exp(-(S_k - min S) / temperature) / sum_j exp(-(S_j - min S) / temperature)
//!   update:    u_t = sum_k w_k (cvx_k,t, cwz_k,t), then clamped to the bounds and to the
//!              accelerations from u_0 = s on (nav2 `applyControlSequenceConstraints`)
//! command u_1 (nav2's `shift_control_sequence`: u_0 is the speed the robot has now);
//! shift the sequence by one, the last element repeated.
//! ```
//!
//! (dt = `model_dt`, which is also the planning period, as nav2 needs it to shift.) The
//! command goes to the wheel stage as a twist demand and holds until the next cycle; the
//! wheel stage keeps ticking at `control_dt`.
//!
//! # Critics (nav2 `critics/*.cpp`), over the rollout's steps i = 1 .. T
//!
//! With L the distance from the measured position to the goal (nav2's
//! `local_path_length`: at a goal, the plan is the straight line to it) and P the
//! critic's `cost_power` ((weight x)^P when P > 1, weight x otherwise):
//!
//! | critic | x | on when |
//! |---|---|---|
//! | `constraint` | sum_i (max(vx_i - vx_max, 0) + max(vx_min - vx_i, 0)) dt | always |
//! | `goal` | mean_i |(x_i, y_i) - goal| | L <= `goal_threshold_to_consider` |
//! | `goal_angle` | mean_i |wrap(theta_goal - yaw_i)| | L <= `goal_angle_threshold_to_consider` |
//! | `prefer_forward` | sum_i max(-vx_i, 0) dt | L >= `prefer_forward_threshold_to_consider` |
//! | `twirling` | mean_i |wz_i| | always (nav2: beyond the goal checker's tolerance) |
//!
//! A weight of 0 turns a critic off (nav2: leave it out of `critics`); twirling is off by
//! default, as in nav2's example configuration. On a path (the law called with
//! [`Law::update_on_path`]) L is the local plan's length, the goal is the path's end, and
//! the path critics (`path_align`, `path_follow`, `path_angle`) follow goal_angle
//! ([`super::mppi_path`]: the local plan, the critics, where wmr differs).
//!
//! # Where wmr differs from nav2
//!
//! - No workspace: the law is `Copy` and allocates nothing. The noise is not stored but
//!   regenerated from a counter-based generator keyed by (seed, draw, sample, step)
//!   ([`noise_pair`]), and the samples are combined as they are rolled out with an online
//!   softmax: a running minimum cost, a running sum of weights and a running weighted sum
//!   of the sampled sequences, all rescaled by exp(-(old min - new min) / temperature)
//!   when the minimum falls. The law holds O(T) numbers (the sequence; T at most
//!   [`MAX_TIME_STEPS`]); one sample's sequence lives on the stack while it is rolled out.
//!   The result equals the two-pass softmax up to rounding (`tests/mppi.rs`, 1e-12).
//! - The rollouts' model: by default the controller's robot and drive
//!   ([`super::rollout`], `motion_model = "dynamic"`), 8 samples at a time in SIMD lanes;
//!   nav2's DiffDrive with acceleration clamps is `motion_model = "kinematic"`
//!   ([`kinematic_rollout`]).
//! - No Savitzky-Golay smoothing of the sequence, no trajectory validator, no fallback.
//! - The noise: Box-Muller from SplitMix64 hashes, not Eigen's normal distribution.
//!
//! Logged errors ([`super::ControlErrors`]), as the polar laws': dl the distance from C to
//! the goal, e_theta = wrap(theta_d - theta), e_s = (x_d - x) cos(theta) + (y_d - y) sin(theta).

use super::law::{Law, LawContext, LawOutput, LawSpec, WheelDemand};
use super::mppi_path::{LocalPlan, MAX_PLAN_POINTS, PathCosts, PathSums, PathTargets};
use super::polar_frame::polar_errors;
use super::rollout::{DynamicModel, ROLLOUT_LANES, Wide};
use crate::drive::DriveParams;
use crate::error::{ParamError, check};
use crate::lane::{Lane, Lanes, Mask};
use crate::math::{Pose2, Twist2, wrap_angle};
use crate::obstacle::Obstacles;
use crate::reference::{Path, PathCursor, ReferenceState};
use crate::sensor::Measurement;
use crate::sensor::gaussian::mix64;
use crate::{Real, RobotParams};

/// The largest `time_steps`: the law holds its sequence in arrays of this length (no
/// allocation); nav2's default is 56.
pub const MAX_TIME_STEPS: usize = 64;

/// Most rollout steps one planning cycle may take (batch_size x time_steps x
/// iteration_count): 1e7, 180 times nav2's defaults (1000 x 56 x 1), about 0.4 s of one
/// core (a cycle at nav2's defaults took 2.1 ms: `wmr-cli run examples/mppi/goal.toml`,
/// release, 600 cycles in 1.27 s of CPU, AMD EPYC Zen 4, idle, 2026-12-07). One `update` is one cycle and cannot be interrupted: from C or
/// Python a larger one would hang the caller, so it is refused by name instead.
pub const MAX_ROLLOUT_STEPS_PER_CYCLE: u64 = 10_000_000;

/// The model the rollouts predict with (`motion_model`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize), serde(rename_all = "snake_case"))]
#[repr(u32)]
pub enum MotionModel {
    /// nav2's `DiffDrive`: the velocities are the sampled commands, clamped by the
    /// acceleration limits (`ax_max`, `ax_min`, `az_max`).
    Kinematic = 0,
    /// The controller's robot, drive and wheel speed limit ([`super::rollout`]): the
    /// accelerations are what the drive can give, the acceleration keys unused in the
    /// rollouts.
    #[default]
    Dynamic = 1,
}
crate::word_enum!(MotionModel { Kinematic, Dynamic });

crate::params! {
    words;
    /// `[controller] kind = "mppi"` parameters (nav2 `nav2_mppi_controller`, its critics'
    /// keys flat: `goal_cost_weight` is nav2's `GoalCritic.cost_weight`).
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    #[repr(C)]
    pub struct MppiParams<T> {
        /// The model the rollouts predict with: "dynamic" (the controller's robot and drive) or "kinematic" (nav2's DiffDrive).
        pub motion_model: MotionModel [unit = "", rule = "\"dynamic\" or \"kinematic\""],
        /// Samples (rollouts) per iteration.
        pub batch_size: u32 [unit = "", rule = ">= 1; batch_size x time_steps x iteration_count <= 1e7"],
        /// Steps of a rollout (the horizon is time_steps * model_dt).
        pub time_steps: u32 [unit = "", rule = ">= 2, <= 64"],
        /// Step of the rollouts and period of the planning (nav2: the controller period).
        pub model_dt: T [unit = "s", rule = "a whole multiple of control_dt"],
        /// Sample-and-update iterations per cycle.
        pub iteration_count: u32 [unit = "", rule = ">= 1"],
        /// Softmax temperature: lower follows the best samples more closely.
        pub temperature: T [unit = "", rule = "> 0"],
        /// Weight of the control cost gamma / std^2 sum (u_sampled - u) u.
        pub gamma: T [unit = "", rule = ">= 0"],
        /// Standard deviation of the sampled forward speed.
        pub vx_std: T [unit = "m/s", rule = ">= 0"],
        /// Standard deviation of the sampled yaw rate.
        pub wz_std: T [unit = "rad/s", rule = ">= 0"],
        /// Highest forward speed.
        pub vx_max: T [unit = "m/s", rule = ">= vx_min"],
        /// Lowest forward speed (negative: reversing allowed).
        pub vx_min: T [unit = "m/s", rule = "finite"],
        /// Highest yaw rate magnitude.
        pub wz_max: T [unit = "rad/s", rule = ">= 0"],
        /// Highest acceleration away from rest.
        pub ax_max: T [unit = "m/s^2", rule = "> 0"],
        /// Highest deceleration towards rest, negative.
        pub ax_min: T [unit = "m/s^2", rule = "< 0"],
        /// Highest yaw acceleration magnitude.
        pub az_max: T [unit = "rad/s^2", rule = "> 0"],
        /// Sub-steps of a dynamic rollout per model_dt (h = model_dt / rollout_substeps).
        pub rollout_substeps: u32 [unit = "", rule = ">= 1, <= 100"],
        /// Seed of the sampling noise: the noise is a function of (seed, cycle, sample, step).
        pub seed: u32 [unit = "", rule = "whole number"],
        /// goal critic: weight of the mean distance of a rollout to the goal.
        pub goal_cost_weight: T [unit = "1/m", rule = ">= 0"],
        /// goal critic: power of its cost.
        pub goal_cost_power: u32 [unit = "", rule = ">= 1"],
        /// goal critic: on only within this distance of the goal.
        pub goal_threshold_to_consider: T [unit = "m", rule = ">= 0"],
        /// goal_angle critic: weight of the mean heading error of a rollout to the goal's heading.
        pub goal_angle_cost_weight: T [unit = "1/rad", rule = ">= 0"],
        /// goal_angle critic: power of its cost.
        pub goal_angle_cost_power: u32 [unit = "", rule = ">= 1"],
        /// goal_angle critic: on only within this distance of the goal.
        pub goal_angle_threshold_to_consider: T [unit = "m", rule = ">= 0"],
        /// constraint critic: weight of the distance driven beyond vx_max or vx_min.
        pub constraint_cost_weight: T [unit = "1/m", rule = ">= 0"],
        /// constraint critic: power of its cost.
        pub constraint_cost_power: u32 [unit = "", rule = ">= 1"],
        /// prefer_forward critic: weight of the distance driven backwards.
        pub prefer_forward_cost_weight: T [unit = "1/m", rule = ">= 0"],
        /// prefer_forward critic: power of its cost.
        pub prefer_forward_cost_power: u32 [unit = "", rule = ">= 1"],
        /// prefer_forward critic: on only beyond this distance of the goal.
        pub prefer_forward_threshold_to_consider: T [unit = "m", rule = ">= 0"],
        /// twirling critic: weight of the mean yaw rate magnitude (0: off).
        pub twirling_cost_weight: T [unit = "s/rad", rule = ">= 0"],
        /// twirling critic: power of its cost.
        pub twirling_cost_power: u32 [unit = "", rule = ">= 1"],
        /// obstacles critic: weight of the collision cost and of the clearance inside the margin.
        pub obstacles_critical_weight: T [unit = "1/m", rule = ">= 0"],
        /// obstacles critic: weight of the repulsion from obstacles within the inflation radius.
        pub obstacles_repulsion_weight: T [unit = "1/m", rule = ">= 0"],
        /// obstacles critic: the cost of a rollout whose footprint touches an obstacle.
        pub obstacles_collision_cost: T [unit = "m", rule = ">= 0"],
        /// obstacles critic: clearance under which a step costs (margin - clearance).
        pub obstacles_collision_margin_distance: T [unit = "m", rule = ">= 0"],
        /// obstacles critic: no repulsion while the robot is this close to the goal.
        pub obstacles_near_goal_distance: T [unit = "m", rule = ">= 0"],
        /// obstacles critic: distance from C to an obstacle beyond which it costs nothing (nav2: the inflation layer's inflation_radius).
        pub obstacles_inflation_radius: T [unit = "m", rule = ">= 0"],
        /// On a path: the local plan covers this much path from the point closest to C (nav2's path handler).
        pub prune_distance: T [unit = "m", rule = "> 0; prune_distance / path_resolution <= 63"],
        /// On a path: the spacing of the local plan's points (nav2: the global plan's, the costmap resolution).
        pub path_resolution: T [unit = "m", rule = "> 0"],
        /// On a path: each search for the closest point covers this much path forward of the last one.
        pub max_robot_pose_search_dist: T [unit = "m", rule = "> 0"],
        /// path_align critic: weight of the mean distance of a rollout to the plan point as far along.
        pub path_align_cost_weight: T [unit = "1/m", rule = ">= 0"],
        /// path_align critic: power of its cost.
        pub path_align_cost_power: u32 [unit = "", rule = ">= 1"],
        /// path_align critic: on only while the local plan is at least this long.
        pub path_align_threshold_to_consider: T [unit = "m", rule = ">= 0"],
        /// path_align critic: on only once the furthest reached plan point is this many points in.
        pub path_align_offset_from_furthest: u32 [unit = "", rule = "whole number"],
        /// path_align critic: scores every this many steps of a rollout.
        pub path_align_trajectory_point_step: u32 [unit = "", rule = ">= 1"],
        /// path_align critic: off while more than this share of the plan up to the furthest point is blocked.
        pub path_align_max_path_occupancy_ratio: T [unit = "", rule = "in [0, 1]"],
        /// path_follow critic: weight of the distance of a rollout's end to the plan point offset_from_furthest beyond the furthest reached.
        pub path_follow_cost_weight: T [unit = "1/m", rule = ">= 0"],
        /// path_follow critic: power of its cost.
        pub path_follow_cost_power: u32 [unit = "", rule = ">= 1"],
        /// path_follow critic: on only while the local plan is at least this long.
        pub path_follow_threshold_to_consider: T [unit = "m", rule = ">= 0"],
        /// path_follow critic: plan points beyond the furthest reached it aims at.
        pub path_follow_offset_from_furthest: u32 [unit = "", rule = "whole number"],
        /// path_angle critic: weight of the angle between a rollout's end heading and the plan point offset_from_furthest beyond the furthest reached.
        pub path_angle_cost_weight: T [unit = "1/rad", rule = ">= 0"],
        /// path_angle critic: power of its cost.
        pub path_angle_cost_power: u32 [unit = "", rule = ">= 1"],
        /// path_angle critic: on only while the local plan is at least this long.
        pub path_angle_threshold_to_consider: T [unit = "m", rule = ">= 0"],
        /// path_angle critic: plan points beyond the furthest reached it aims at.
        pub path_angle_offset_from_furthest: u32 [unit = "", rule = "whole number"],
        /// path_angle critic: on only while C's bearing to that point is more than this off its heading.
        pub path_angle_max_angle_to_furthest: T [unit = "rad", rule = ">= 0"],
        /// path_angle critic: 0 forward preference, 1 no directional preference (needs vx_min < 0), 2 the direction the path's heading allows (nav2's mode).
        pub path_angle_mode: u32 [unit = "", rule = "0, 1 or 2"],
    }
}

impl<T: Real> Default for MppiParams<T> {
    /// nav2's defaults, rolled out on the dynamic model with 2 sub-steps per model_dt
    /// (`motion_model = "kinematic"` for nav2's own): 1000 x 56 samples of 0.05 s, one iteration, temperature 0.3,
    /// gamma 0.015, vx_std 0.2 m/s, wz_std 0.4 rad/s, vx in [-0.35, 0.5] m/s,
    /// |wz| <= 1.9 rad/s, ax in [-3, 3] m/s^2, |az| <= 3.5 rad/s^2; the critics' weights
    /// goal 5 (within 1.4 m), goal_angle 3 (within 0.5 m), constraint 4,
    /// prefer_forward 5 (beyond 0.5 m), powers 1; twirling off (nav2's weight when on: 10);
    /// obstacles (on when the world has some): critical weight 20, repulsion weight 1.5,
    /// collision cost 100000, margin 0.1 m, near the goal 0.5 m, inflation radius 0.55 m
    /// (nav2's inflation layer's default); on a path ([`super::mppi_path`]): a local plan of
    /// 2 m (nav2's prune_distance) at 0.05 m, searched within 1.5 m, path_align 10 (from
    /// 20 points in, every 4 steps, within 0.5 m, occupancy 0.07), path_follow 5 (6 points
    /// on, within 1.4 m), path_angle 2.2 (4 points on, within 0.5 m, beyond pi/4 rad,
    /// forward preference): nav2's critics' own defaults.
    fn default() -> Self {
        Self {
            motion_model: MotionModel::Dynamic,
            batch_size: 1000,
            time_steps: 56,
            model_dt: T::lit(0.05),
            iteration_count: 1,
            temperature: T::lit(0.3),
            gamma: T::lit(0.015),
            vx_std: T::lit(0.2),
            wz_std: T::lit(0.4),
            vx_max: T::lit(0.5),
            vx_min: T::lit(-0.35),
            wz_max: T::lit(1.9),
            ax_max: T::lit(3.0),
            ax_min: T::lit(-3.0),
            az_max: T::lit(3.5),
            rollout_substeps: 2,
            seed: 0,
            goal_cost_weight: T::lit(5.0),
            goal_cost_power: 1,
            goal_threshold_to_consider: T::lit(1.4),
            goal_angle_cost_weight: T::lit(3.0),
            goal_angle_cost_power: 1,
            goal_angle_threshold_to_consider: T::lit(0.5),
            constraint_cost_weight: T::lit(4.0),
            constraint_cost_power: 1,
            prefer_forward_cost_weight: T::lit(5.0),
            prefer_forward_cost_power: 1,
            prefer_forward_threshold_to_consider: T::lit(0.5),
            twirling_cost_weight: T::zero(),
            twirling_cost_power: 1,
            obstacles_critical_weight: T::lit(20.0),
            obstacles_repulsion_weight: T::lit(1.5),
            obstacles_collision_cost: T::lit(100_000.0),
            obstacles_collision_margin_distance: T::lit(0.1),
            obstacles_near_goal_distance: T::lit(0.5),
            obstacles_inflation_radius: T::lit(0.55),
            prune_distance: T::lit(2.0),
            path_resolution: T::lit(0.05),
            max_robot_pose_search_dist: T::lit(1.5),
            path_align_cost_weight: T::lit(10.0),
            path_align_cost_power: 1,
            path_align_threshold_to_consider: T::lit(0.5),
            path_align_offset_from_furthest: 20,
            path_align_trajectory_point_step: 4,
            path_align_max_path_occupancy_ratio: T::lit(0.07),
            path_follow_cost_weight: T::lit(5.0),
            path_follow_cost_power: 1,
            path_follow_threshold_to_consider: T::lit(1.4),
            path_follow_offset_from_furthest: 6,
            path_angle_cost_weight: T::lit(2.2),
            path_angle_cost_power: 1,
            path_angle_threshold_to_consider: T::lit(0.5),
            path_angle_offset_from_furthest: 4,
            path_angle_max_angle_to_furthest: T::lit(core::f64::consts::FRAC_PI_4),
            path_angle_mode: 0,
        }
    }
}

impl<T: Real> LawSpec<T> for MppiParams<T> {
    type Law<L: Lane<Scalar = T>> = MppiLaw<L>;

    /// One cycle at nav2's defaults is 56,000 rollout steps every 0.05 s: a plant step
    /// under it cost 430 times one under the paper's law (42.5 us against 0.098 us per
    /// step: examples/mppi/goal.toml and the same runs under paper_bidirectional for
    /// 1000 s, log_dt 1 s, release, AMD EPYC Zen 4, idle, 2026-12-07).
    /// It grows with the rollout steps per cycle (batch_size x time_steps x
    /// iteration_count) and the cycles per second (1 / model_dt), so that a scenario
    /// asking for a billion samples is refused by the step budget, not run for days.
    fn update_cost(&self) -> f64 {
        let rollout_steps = f64::from(self.batch_size) * f64::from(self.time_steps) * f64::from(self.iteration_count);
        let model_dt = self.model_dt.to_f64_lossless();
        // A model_dt the law refuses (<= 0, NaN) costs what the defaults do: the law's
        // own check names the key.
        let per_second = if model_dt > 0.0 { 0.05 / model_dt } else { 1.0 };
        430.0 * rollout_steps / 56_000.0 * per_second
    }

    /// 30 keys: more than the trace's 16 law words.
    const TRACED: bool = false;

    /// Without the drive: the dynamic rollouts assume the default torque drive and no
    /// wheel speed limit, and no obstacles ([`LawSpec::build_in`] is what a controller calls).
    fn build<L: Lane<Scalar = T>>(&self, model: &RobotParams<T>, control_dt: T) -> Result<MppiLaw<L>, ParamError> {
        MppiLaw::for_lanes(*self, model, &DriveParams::default(), T::infinity(), control_dt)
    }

    /// The noise of run `ctx.run` ([`LawContext::run`]): run 0 draws under the `seed` key,
    /// run k > 0 under seed_k = the high 32 bits of mix64(mix64(seed ^ 0x52554E << 40) ^ k)
    /// (SplitMix64's output function, [`mix64`]), which the law's [`MppiLaw::params`]
    /// then shows as its `seed`. Like the sensor's noise (`[sensor] seed` and the run
    /// index), so that every run of a sweep draws its own samples and the same run draws
    /// the same ones in the CLI, Python (`run=`) and C (`run`). Two runs share a stream
    /// only when their seed_k collide (32 bits: one pair expected among 93,000 runs).
    fn build_in<L: Lane<Scalar = T>>(&self, ctx: &LawContext<'_, T>) -> Result<MppiLaw<L>, ParamError> {
        let seed = match ctx.run {
            0 => self.seed,
            k => (mix64(mix64(u64::from(self.seed) ^ (0x52_554E << 40)) ^ k) >> 32) as u32,
        };
        let p = MppiParams { seed, ..*self };
        MppiLaw::for_lanes(p, ctx.model, ctx.drive, ctx.wheel_speed_max, ctx.control_dt)
            .map(|law| law.with_obstacles(ctx.obstacles))
    }
}

fn count_at_least<T: Real>(field: &'static str, v: u32, min: u32) -> Result<u32, ParamError> {
    if v < min {
        let why = if min == 1 { "must be >= 1" } else { "must be >= 2" };
        return Err(check::out_of_range(field, why, T::lit(f64::from(v))));
    }
    Ok(v)
}

impl<T: Real> MppiParams<T> {
    /// Checks every key against the control period `control_dt` (s); errors name the key.
    /// Returns the control ticks per planning cycle (model_dt / control_dt).
    pub fn validate(&self, control_dt: T) -> Result<u32, ParamError> {
        count_at_least::<T>("batch_size", self.batch_size, 1)?;
        count_at_least::<T>("time_steps", self.time_steps, 2)?;
        if self.time_steps as usize > MAX_TIME_STEPS {
            return Err(check::out_of_range(
                "time_steps",
                "must be <= 64 (the law's sequence has a fixed capacity, MAX_TIME_STEPS)",
                T::lit(f64::from(self.time_steps)),
            ));
        }
        count_at_least::<T>("iteration_count", self.iteration_count, 1)?;
        count_at_least::<T>("rollout_substeps", self.rollout_substeps, 1)?;
        if self.rollout_substeps > 100 {
            return Err(check::out_of_range(
                "rollout_substeps",
                "must be <= 100",
                T::lit(f64::from(self.rollout_substeps)),
            ));
        }
        let per_cycle = u64::from(self.batch_size) * u64::from(self.time_steps) * u64::from(self.iteration_count);
        if per_cycle > MAX_ROLLOUT_STEPS_PER_CYCLE {
            return Err(check::out_of_range(
                "batch_size",
                "batch_size x time_steps x iteration_count must be <= 1e7 rollout steps per cycle \
                 (MAX_ROLLOUT_STEPS_PER_CYCLE, about 0.4 s of one core)",
                T::lit(f64::from(self.batch_size)),
            ));
        }
        let model_dt = check::positive("model_dt", self.model_dt)?;
        let ticks = (model_dt / control_dt).round();
        let tol = T::lit(1e-9) * model_dt;
        if ticks < T::one() || (ticks * control_dt - model_dt).abs() > tol || ticks > T::lit(1e6) {
            return Err(check::out_of_range(
                "model_dt",
                "must be a whole multiple of control_dt (at least control_dt)",
                model_dt,
            ));
        }
        check::positive("temperature", self.temperature)?;
        check::non_negative("gamma", self.gamma)?;
        check::non_negative("vx_std", self.vx_std)?;
        check::non_negative("wz_std", self.wz_std)?;
        let vx_min = check::finite("vx_min", self.vx_min)?;
        let vx_max = check::finite("vx_max", self.vx_max)?;
        if vx_max < vx_min {
            return Err(check::out_of_range("vx_max", "must be >= vx_min", vx_max));
        }
        check::non_negative("wz_max", self.wz_max)?;
        check::positive("ax_max", self.ax_max)?;
        let ax_min = check::finite("ax_min", self.ax_min)?;
        if ax_min >= T::zero() {
            return Err(check::out_of_range("ax_min", "must be < 0 (a deceleration)", ax_min));
        }
        check::positive("az_max", self.az_max)?;
        check::non_negative("goal_cost_weight", self.goal_cost_weight)?;
        count_at_least::<T>("goal_cost_power", self.goal_cost_power, 1)?;
        check::non_negative("goal_threshold_to_consider", self.goal_threshold_to_consider)?;
        check::non_negative("goal_angle_cost_weight", self.goal_angle_cost_weight)?;
        count_at_least::<T>("goal_angle_cost_power", self.goal_angle_cost_power, 1)?;
        check::non_negative("goal_angle_threshold_to_consider", self.goal_angle_threshold_to_consider)?;
        check::non_negative("constraint_cost_weight", self.constraint_cost_weight)?;
        count_at_least::<T>("constraint_cost_power", self.constraint_cost_power, 1)?;
        check::non_negative("prefer_forward_cost_weight", self.prefer_forward_cost_weight)?;
        count_at_least::<T>("prefer_forward_cost_power", self.prefer_forward_cost_power, 1)?;
        check::non_negative("prefer_forward_threshold_to_consider", self.prefer_forward_threshold_to_consider)?;
        check::non_negative("twirling_cost_weight", self.twirling_cost_weight)?;
        count_at_least::<T>("twirling_cost_power", self.twirling_cost_power, 1)?;
        check::non_negative("obstacles_critical_weight", self.obstacles_critical_weight)?;
        check::non_negative("obstacles_repulsion_weight", self.obstacles_repulsion_weight)?;
        check::non_negative("obstacles_collision_cost", self.obstacles_collision_cost)?;
        check::non_negative("obstacles_collision_margin_distance", self.obstacles_collision_margin_distance)?;
        check::non_negative("obstacles_near_goal_distance", self.obstacles_near_goal_distance)?;
        check::non_negative("obstacles_inflation_radius", self.obstacles_inflation_radius)?;
        let prune = check::positive("prune_distance", self.prune_distance)?;
        let resolution = check::positive("path_resolution", self.path_resolution)?;
        if prune / resolution > T::lit((MAX_PLAN_POINTS - 1) as f64) {
            return Err(check::out_of_range(
                "prune_distance",
                "prune_distance / path_resolution must be <= 63 (the local plan has a fixed capacity, MAX_PLAN_POINTS)",
                prune,
            ));
        }
        check::positive("max_robot_pose_search_dist", self.max_robot_pose_search_dist)?;
        check::non_negative("path_align_cost_weight", self.path_align_cost_weight)?;
        count_at_least::<T>("path_align_cost_power", self.path_align_cost_power, 1)?;
        check::non_negative("path_align_threshold_to_consider", self.path_align_threshold_to_consider)?;
        count_at_least::<T>("path_align_trajectory_point_step", self.path_align_trajectory_point_step, 1)?;
        let occupancy =
            check::non_negative("path_align_max_path_occupancy_ratio", self.path_align_max_path_occupancy_ratio)?;
        if occupancy > T::one() {
            return Err(check::out_of_range("path_align_max_path_occupancy_ratio", "must be in [0, 1]", occupancy));
        }
        check::non_negative("path_follow_cost_weight", self.path_follow_cost_weight)?;
        count_at_least::<T>("path_follow_cost_power", self.path_follow_cost_power, 1)?;
        check::non_negative("path_follow_threshold_to_consider", self.path_follow_threshold_to_consider)?;
        check::non_negative("path_angle_cost_weight", self.path_angle_cost_weight)?;
        count_at_least::<T>("path_angle_cost_power", self.path_angle_cost_power, 1)?;
        check::non_negative("path_angle_threshold_to_consider", self.path_angle_threshold_to_consider)?;
        check::non_negative("path_angle_max_angle_to_furthest", self.path_angle_max_angle_to_furthest)?;
        if self.path_angle_mode > 2 {
            return Err(check::out_of_range(
                "path_angle_mode",
                "must be 0 (forward preference), 1 (no directional preference) or 2 (consider feasible path orientations)",
                T::lit(f64::from(self.path_angle_mode)),
            ));
        }
        // A whole number in [1, 1e6] (checked above).
        Ok(ticks.to_u32().unwrap_or(1))
    }
}

/// Two standard normal numbers (Box-Muller in f64, with the lanes' logarithm, sine and
/// cosine: [`Lanes::ln`], [`Lane::sin_cos`]) for sample `sample`, step `step` of draw
/// `draw` (cycle * iteration_count + iteration) under `seed`: a pure function of its
/// arguments, so the noise is regenerated rather than stored. The first perturbs vx,
/// the second wz. The law draws 8 samples' at once ([`ROLLOUT_LANES`]), the same numbers.
#[inline]
pub fn noise_pair(seed: u32, draw: u64, sample: u32, step: u32) -> (f64, f64) {
    let (a, b) = noise_lanes(draw_key(seed, draw), sample, step);
    (a.lane(0), b.lane(0))
}

/// The key of one draw: [`noise_pair`] = `noise_pair_keyed(draw_key(seed, draw), ..)`.
#[inline]
fn draw_key(seed: u32, draw: u64) -> u64 {
    mix64(mix64(u64::from(seed) ^ 0x4D50_5049_0000_0000) ^ draw)
}

/// The noise pairs of samples `first` .. `first` + 8 at step `step` under the draw's
/// `key`, one sample per lane: Box-Muller on two SplitMix64 hashes of (sample, step).
// One copy on the firmware (soft doubles: eight lanes of calls), inlined on hosts.
#[cfg_attr(target_os = "none", inline(never))]
#[cfg_attr(not(target_os = "none"), inline(always))]
fn noise_lanes(key: u64, first: u32, step: u32) -> (Wide, Wide) {
    let (mut u1, mut u2) = ([0.0; ROLLOUT_LANES], [0.0; ROLLOUT_LANES]);
    for (j, (a, b)) in u1.iter_mut().zip(u2.iter_mut()).enumerate() {
        let sample = first.wrapping_add(j as u32);
        let h1 = mix64(key ^ ((u64::from(sample) << 32) | u64::from(step)));
        let h2 = mix64(h1);
        // (0, 1]: 53 random bits, never 0, so the log is finite.
        *a = ((h1 >> 11) + 1) as f64 * (1.0 / 9_007_199_254_740_992.0);
        *b = ((h2 >> 11) + 1) as f64 * (1.0 / 9_007_199_254_740_992.0);
    }
    let radius = (Lanes(u1).ln() * Lanes::splat(-2.0)).sqrt();
    let (s, c) = (Lanes(u2) * Lanes::splat(core::f64::consts::TAU)).sin_cos();
    (radius * c, radius * s)
}

/// nav2 `utils::clampVelocityByAccel`: `max_delta` speeds up, `min_delta` (< 0) slows down.
#[inline(always)]
fn clamp_by_accel<T: Real>(last: T, curr: T, min_delta: T, max_delta: T) -> T {
    if last >= T::zero() {
        (last + max_delta).min(curr.max(last + min_delta))
    } else {
        (last - min_delta).min(curr.max(last - max_delta))
    }
}

/// (weight x)^power for power > 1, weight x otherwise (nav2's critics).
#[inline(always)]
fn critic_cost<T: Real>(x: T, weight: T, power: u32) -> T {
    let c = x * weight;
    if power > 1 { c.powi(power as i32) } else { c }
}

/// nav2's DiffDrive rollout (`MotionModel::predict`, `integrateStateVelocities`) of the
/// sampled sequence `cvx`, `cwz` (m/s, rad/s; `time_steps` long) from `pose` (world
/// frame) at `speed`: calls `visit(i, pose_i, twist_i)` for i = 0 .. T-1 with the pose
/// after step i + 1 and the twist the step was driven at:
///
/// ```text
/// vx_0 = speed.v, wz_0 = speed.omega
/// vx_i = clamp(cvx_(i-1), vx_(i-1) + dt ax_min, vx_(i-1) + dt ax_max)   (vx_(i-1) > 0; else mirrored)
/// wz_i = clamp(cwz_(i-1), wz_(i-1) - dt az_max, wz_(i-1) + dt az_max)
/// yaw_i = yaw_(i-1) + wz_i dt
/// x_i = x_(i-1) + vx_i cos(yaw_(i-1)) dt,   y_i = y_(i-1) + vx_i sin(yaw_(i-1)) dt
/// ```
///
/// (dt = `model_dt`; yaw_(-1), x_(-1), y_(-1) the start pose): the heading first, the
/// position on the heading of the step before, as nav2 integrates.
///
/// For one sample (`L` = `T`, `libm`'s sine and cosine) or several side by side
/// ([`Lanes`], the lanes' own): the same operations in the same order.
// One copy on the firmware (soft doubles: eight lanes of calls), inlined on hosts.
#[cfg_attr(target_os = "none", inline(never))]
#[cfg_attr(not(target_os = "none"), inline(always))]
pub fn kinematic_rollout<L: Lane>(
    p: &MppiParams<L::Scalar>,
    pose: Pose2<L>,
    speed: Twist2<L>,
    cvx: &[L],
    cwz: &[L],
    mut visit: impl FnMut(usize, Pose2<L>, Twist2<L>),
) {
    let dt = L::splat(p.model_dt);
    let (max_dvx, min_dvx, max_dwz) = (dt * L::splat(p.ax_max), dt * L::splat(p.ax_min), dt * L::splat(p.az_max));
    let (mut vx, mut wz) = (speed.v, speed.omega);
    let (mut x, mut y, mut yaw) = (pose.x, pose.y, pose.theta);
    let (mut sin_prev, mut cos_prev) = yaw.sin_cos();
    // The sampled controls of the step before (iterators, no index: nothing to panic).
    let (mut cvx_prev, mut cwz_prev) = (L::default(), L::default());
    let zero = L::default();
    for (i, (&cv, &cw)) in cvx.iter().zip(cwz).enumerate() {
        if i > 0 {
            let forward = zero.lt(vx);
            let lo = L::select(forward, vx + min_dvx, vx - max_dvx);
            let hi = L::select(forward, vx + max_dvx, vx - min_dvx);
            vx = cvx_prev.max(lo).min(hi);
            wz = cwz_prev.max(wz - max_dwz).min(wz + max_dwz);
        }
        (cvx_prev, cwz_prev) = (cv, cw);
        yaw = yaw + wz * dt;
        x = x + vx * cos_prev * dt;
        y = y + vx * sin_prev * dt;
        (sin_prev, cos_prev) = yaw.sin_cos();
        visit(i, Pose2 { x, y, theta: yaw }, Twist2 { v: vx, omega: wz });
    }
}

/// One run's planning state and its inputs at a cycle, in scalars.
struct Cycle<'a, T> {
    pose: Pose2<T>,
    /// The goal of the goal critics: the reference's pose at rest, or the path's end (the
    /// local plan's last point).
    goal: Pose2<T>,
    /// L, m: the local plan's length on a path, the distance to the goal at rest.
    path_length: T,
    /// On a path: the path critics' targets.
    path: Option<PathTargets<'a>>,
    /// The speed the rollouts start from (nav2 `state_.speed`): the last command within
    /// what the accelerations allow from the measured speed.
    speed: Twist2<T>,
    /// The speed measured by the wheel encoders: where a dynamic rollout starts.
    measured: Twist2<T>,
    /// The first draw of this cycle (cycle * iteration_count).
    draw: u64,
}

/// The streaming softmax over the samples of one iteration: a running minimum cost, the
/// running sum of exp(-(S - min) / temperature) and the running weighted sum of the
/// sampled sequences, rescaled when the minimum falls.
struct Softmax<T> {
    min: T,
    sum: T,
    vx: [T; MAX_TIME_STEPS],
    wz: [T; MAX_TIME_STEPS],
}

impl<T: Real> Softmax<T> {
    fn new() -> Self {
        Self { min: T::infinity(), sum: T::zero(), vx: [T::zero(); MAX_TIME_STEPS], wz: [T::zero(); MAX_TIME_STEPS] }
    }

    #[inline(always)]
    fn add(&mut self, cost: T, inv_temp: T, cvx: &[T], cwz: &[T]) {
        let n = cvx.len();
        if cost < self.min {
            if self.sum > T::zero() {
                let scale = (-(self.min - cost) * inv_temp).exp_libm();
                self.sum = self.sum * scale;
                for (v, w) in self.vx.iter_mut().zip(self.wz.iter_mut()).take(n) {
                    *v = *v * scale;
                    *w = *w * scale;
                }
            }
            self.min = cost;
        }
        let weight = (-(cost - self.min) * inv_temp).exp_libm();
        self.sum = self.sum + weight;
        for ((v, w), (&cv, &cw)) in self.vx.iter_mut().zip(self.wz.iter_mut()).zip(cvx.iter().zip(cwz)) {
            *v = *v + weight * cv;
            *w = *w + weight * cw;
        }
    }
}

/// The sums over a rollout's steps the critics read (module docs' table).
#[derive(Clone, Copy, Debug, Default)]
struct CriticSums<T> {
    /// sum_i |(x_i, y_i) - goal|, m.
    goal: T,
    /// sum_i |wrap(theta_goal - yaw_i)|, rad.
    angle: T,
    /// sum_i (max(vx_i - vx_max, 0) + max(vx_min - vx_i, 0)) dt, m.
    beyond: T,
    /// sum_i max(-vx_i, 0) dt, m.
    backwards: T,
    /// sum_i |wz_i|, rad/s.
    twirl: T,
    /// The obstacles critic's raw cost: the collision cost if a step touched an obstacle,
    /// else sum_i max(margin - clearance_i, 0) over the steps within the inflation radius, m.
    obstacle: T,
    /// sum_i (inflation_radius - clearance_i) over the steps within the inflation radius
    /// before any contact, m.
    repulsion: T,
    /// On a path: the path critics' raw costs and the plan point reached.
    path: PathCosts,
}

/// The obstacles critic's sums over a rollout's steps (nav2 `ObstaclesCritic::score`),
/// for one sample or several side by side: per step, with c the footprint's clearance
/// ([`Obstacles::clearance`]) and C's distance to the obstacle c + footprint_radius:
///
/// ```text
/// c <= 0:                        contact: the raw cost is collision_cost, the steps after it do not count
/// c + footprint >= inflation:    free: nothing
/// else:                          raw += max(margin - c, 0),  repulsion += inflation - c
/// ```
#[derive(Clone, Copy, Debug)]
struct ObstacleSums<L: Lane> {
    raw: L,
    repulsion: L,
    collided: L::Mask,
}

impl<L: Lane> ObstacleSums<L> {
    fn new<T: Real>(_p: &MppiParams<T>) -> Self {
        Self { raw: L::default(), repulsion: L::default(), collided: <L::Mask as Mask>::splat(false) }
    }

    #[inline(always)]
    fn add(&mut self, p: &MppiParams<L::Scalar>, obstacles: &Obstacles<L::Scalar>, x: L, y: L) {
        let zero = L::default();
        let clearance = obstacles.clearance(x, y);
        let contact = clearance.le(zero);
        let near = (clearance + L::splat(obstacles.footprint_radius())).lt(L::splat(p.obstacles_inflation_radius));
        let counts = near & !contact & !self.collided;
        let margin = (L::splat(p.obstacles_collision_margin_distance) - clearance).max(zero);
        self.raw = L::select(counts, self.raw + margin, self.raw);
        self.repulsion =
            L::select(counts, self.repulsion + (L::splat(p.obstacles_inflation_radius) - clearance), self.repulsion);
        self.collided = self.collided | contact;
    }

    /// (raw cost, repulsion sum).
    #[inline(always)]
    fn finish(self, p: &MppiParams<L::Scalar>) -> (L, L) {
        (L::select(self.collided, L::splat(p.obstacles_collision_cost), self.raw), self.repulsion)
    }
}

/// The sampled costs of MPPI: what [`MppiLaw`] runs each cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Planner<T> {
    p: MppiParams<T>,
    /// The dynamic rollouts' model (`motion_model = "dynamic"`), `None` for the kinematic.
    dynamic: Option<DynamicModel>,
    /// The obstacles the critic sees (none: the critic is off), and in `f64` for the
    /// dynamic rollouts.
    obstacles: Obstacles<T>,
    obstacles_f64: Obstacles<f64>,
}

impl<T: Real> Planner<T> {
    /// The critics' cost of a rollout of `n` steps from its sums.
    #[inline(always)]
    fn critics(&self, sums: &CriticSums<T>, n: usize, path_length: T) -> T {
        let p = &self.p;
        let CriticSums { goal: goal_sum, angle: angle_sum, beyond, backwards, twirl, obstacle, repulsion, path } =
            *sums;
        let nt = T::lit(n as f64);
        // nav2's critic order: constraint, goal, goal_angle, path_align, path_follow,
        // path_angle, prefer_forward, twirling (the path critics only on a path).
        let mut cost = T::zero();
        if p.constraint_cost_weight > T::zero() {
            cost = cost + critic_cost(beyond, p.constraint_cost_weight, p.constraint_cost_power);
        }
        if p.goal_cost_weight > T::zero() && path_length <= p.goal_threshold_to_consider {
            cost = cost + critic_cost(goal_sum / nt, p.goal_cost_weight, p.goal_cost_power);
        }
        if p.goal_angle_cost_weight > T::zero() && path_length <= p.goal_angle_threshold_to_consider {
            cost = cost + critic_cost(angle_sum / nt, p.goal_angle_cost_weight, p.goal_angle_cost_power);
        }
        if let Some(x) = path.align {
            cost = cost + critic_cost(T::lit(x), p.path_align_cost_weight, p.path_align_cost_power);
        }
        if let Some(x) = path.follow {
            cost = cost + critic_cost(T::lit(x), p.path_follow_cost_weight, p.path_follow_cost_power);
        }
        if let Some(x) = path.angle {
            cost = cost + critic_cost(T::lit(x), p.path_angle_cost_weight, p.path_angle_cost_power);
        }
        if p.prefer_forward_cost_weight > T::zero() && path_length >= p.prefer_forward_threshold_to_consider {
            cost = cost + critic_cost(backwards, p.prefer_forward_cost_weight, p.prefer_forward_cost_power);
        }
        if p.twirling_cost_weight > T::zero() {
            cost = cost + critic_cost(twirl / nt, p.twirling_cost_weight, p.twirling_cost_power);
        }
        if !self.obstacles.is_empty() {
            // nav2's repulsion is normalized by the batch's lowest, a shift of every
            // sample's cost by one number: the softmax weights do not see it, so it is left out.
            let repulsion = if path_length < p.obstacles_near_goal_distance { T::zero() } else { repulsion / nt };
            cost = cost + p.obstacles_critical_weight * obstacle + p.obstacles_repulsion_weight * repulsion;
        }
        cost
    }

    /// The critics' sums of [`ROLLOUT_LANES`] samples rolled out together in lanes: on the
    /// dynamic model from the measured speed, step 0 driven by the held command's speed (as
    /// nav2's step 0), step i by sample i - 1 (nav2's indexing); or on the kinematic model
    /// from that speed ([`kinematic_rollout`]).
    #[inline(always)]
    fn lane_sums(
        &self,
        c: &Cycle<'_, T>,
        cvx: &[[T; MAX_TIME_STEPS]; ROLLOUT_LANES],
        cwz: &[[T; MAX_TIME_STEPS]; ROLLOUT_LANES],
        n: usize,
    ) -> [CriticSums<T>; ROLLOUT_LANES] {
        let p = &self.p;
        let f = |x: T| x.to_f64_lossless();
        let (dt, vx_max, vx_min) = (Wide::splat(f(p.model_dt)), Wide::splat(f(p.vx_max)), Wide::splat(f(p.vx_min)));
        let goal =
            Pose2 { x: Wide::splat(f(c.goal.x)), y: Wide::splat(f(c.goal.y)), theta: Wide::splat(f(c.goal.theta)) };
        let zero = Wide::default();
        let mut sums = CriticSums {
            goal: zero,
            angle: zero,
            beyond: zero,
            backwards: zero,
            twirl: zero,
            obstacle: zero,
            repulsion: zero,
            path: PathCosts::default(),
        };
        let pf = self.p_f64();
        let mut obstacle = ObstacleSums::<Wide>::new(&pf);
        let seeing = !self.obstacles_f64.is_empty();
        let mut on_path = c.path.as_ref().map(|t| (t, PathSums::new()));
        let held = Twist2 { v: Wide::splat(f(c.speed.v)), omega: Wide::splat(f(c.speed.omega)) };
        let demand = |i: usize| match i.checked_sub(1) {
            None => held,
            Some(k) => Twist2 {
                v: Lanes(core::array::from_fn(|j| cvx.get(j).and_then(|s| s.get(k)).map_or(0.0, |&x| f(x)))),
                omega: Lanes(core::array::from_fn(|j| cwz.get(j).and_then(|s| s.get(k)).map_or(0.0, |&x| f(x)))),
            },
        };
        let start = Pose2 { x: f(c.pose.x), y: f(c.pose.y), theta: f(c.pose.theta) };
        let mut visit = |i: usize, pose: Pose2<Wide>, vel: Twist2<Wide>| {
            sums.goal = sums.goal + (pose.x - goal.x).hypot(pose.y - goal.y);
            sums.angle = sums.angle + wrap_angle(goal.theta - pose.theta).abs();
            sums.beyond = sums.beyond + ((vel.v - vx_max).max(zero) + (vx_min - vel.v).max(zero)) * dt;
            sums.backwards = sums.backwards + (-vel.v).max(zero) * dt;
            sums.twirl = sums.twirl + vel.omega.abs();
            if seeing {
                obstacle.add(&pf, &self.obstacles_f64, pose.x, pose.y);
            }
            if let Some((t, sums)) = on_path.as_mut() {
                sums.add(t, i, pose);
            }
        };
        match &self.dynamic {
            Some(model) => {
                let measured = Twist2 { v: f(c.measured.v), omega: f(c.measured.omega) };
                model.rollout(start, measured, n, demand, &mut visit);
            }
            None => {
                let step = |s: &[[T; MAX_TIME_STEPS]; ROLLOUT_LANES], t: usize| {
                    Lanes(core::array::from_fn(|j| s.get(j).and_then(|s| s.get(t)).map_or(0.0, |&x| f(x))))
                };
                let cv: [Wide; MAX_TIME_STEPS] = core::array::from_fn(|t| step(cvx, t));
                let cw: [Wide; MAX_TIME_STEPS] = core::array::from_fn(|t| step(cwz, t));
                let m = n.min(MAX_TIME_STEPS);
                let pose = Pose2 { x: Wide::splat(start.x), y: Wide::splat(start.y), theta: Wide::splat(start.theta) };
                kinematic_rollout(&pf, pose, held, &cv[..m], &cw[..m], &mut visit);
            }
        }
        (sums.obstacle, sums.repulsion) = obstacle.finish(&pf);
        let path = on_path.map(|(t, sums)| sums.finish(t));
        let at = |x: Wide, j: usize| T::lit(x.lane(j));
        core::array::from_fn(|j| CriticSums {
            goal: at(sums.goal, j),
            angle: at(sums.angle, j),
            beyond: at(sums.beyond, j),
            backwards: at(sums.backwards, j),
            twirl: at(sums.twirl, j),
            obstacle: at(sums.obstacle, j),
            repulsion: at(sums.repulsion, j),
            path: path.and_then(|p| p.get(j).copied()).unwrap_or_default(),
        })
    }

    /// The keys in `f64` (the dynamic rollouts' critics).
    fn p_f64(&self) -> MppiParams<f64> {
        self.p.cast()
    }

    /// One cycle: updates `vx`, `wz` (the optimal sequence, `time_steps` long) and returns
    /// the command (u_1), before the shift, and on a path the furthest plan point the last
    /// iteration's rollouts reached (F, for the next cycle).
    fn plan(&self, c: &Cycle<'_, T>, vx: &mut [T], wz: &mut [T]) -> (Twist2<T>, usize) {
        #[cfg(all(target_arch = "x86_64", not(target_os = "none")))]
        if super::vector_unit::has_avx2() {
            #[allow(unsafe_code)]
            // SAFETY: the processor has AVX2 (checked just above).
            return unsafe { self.plan_avx2(c, vx, wz) };
        }
        self.plan_baseline(c, vx, wz)
    }

    /// [`Planner::plan`] compiled for AVX2: the same code, the same bits
    /// ([`super::vector_unit`]).
    #[cfg(all(target_arch = "x86_64", not(target_os = "none")))]
    #[allow(unsafe_code)]
    #[target_feature(enable = "avx2")]
    unsafe fn plan_avx2(&self, c: &Cycle<'_, T>, vx: &mut [T], wz: &mut [T]) -> (Twist2<T>, usize) {
        self.plan_baseline(c, vx, wz)
    }

    /// [`Planner::plan`] for whichever build inlines it.
    #[inline(always)]
    fn plan_baseline(&self, c: &Cycle<'_, T>, vx: &mut [T], wz: &mut [T]) -> (Twist2<T>, usize) {
        let p = &self.p;
        // Bounded by the arrays below, so that no index can panic (the firmware's C
        // library is checked for panic paths): `time_steps` is validated within it.
        let n = vx.len().min(wz.len()).min(MAX_TIME_STEPS);
        let (vx, wz) = (&mut vx[..n], &mut wz[..n]);
        let path_length = c.path_length;
        let mut furthest = 0;
        let inv_temp = p.temperature.recip();
        let (vx_std, wz_std) = (p.vx_std, p.wz_std);
        let gamma_vx = if vx_std > T::zero() { p.gamma / (vx_std * vx_std) } else { T::zero() };
        let gamma_wz = if wz_std > T::zero() { p.gamma / (wz_std * wz_std) } else { T::zero() };
        for iter in 0..p.iteration_count {
            // nav2 `applyControlSequenceInterIterationConstraints` (shifting): u_0 = speed.
            if let (Some(v0), Some(w0)) = (vx.first_mut(), wz.first_mut()) {
                (*v0, *w0) = (c.speed.v, c.speed.omega);
            }
            let key = draw_key(p.seed, c.draw.wrapping_add(u64::from(iter)));
            let mut soft = Softmax::new();
            furthest = 0;
            // nav2 `updateControlSequence`: the control cost, vx then wz.
            let control_cost = |cvx: &[T], cwz: &[T]| {
                let (mut ctrl_vx, mut ctrl_wz) = (T::zero(), T::zero());
                for ((&cv, &cw), (&v, &w)) in cvx.iter().zip(cwz).zip(vx.iter().zip(wz.iter())) {
                    ctrl_vx = ctrl_vx + (cv - v) * v;
                    ctrl_wz = ctrl_wz + (cw - w) * w;
                }
                let mut cost = gamma_vx * ctrl_vx;
                if wz_std > T::zero() {
                    cost = cost + gamma_wz * ctrl_wz;
                }
                cost
            };
            // The samples, ROLLOUT_LANES at a time: their noise drawn in lanes, then rolled
            // out in lanes (dynamic) or one by one (kinematic), added in sample order.
            let mut cvx_w = [[T::zero(); MAX_TIME_STEPS]; ROLLOUT_LANES];
            let mut cwz_w = [[T::zero(); MAX_TIME_STEPS]; ROLLOUT_LANES];
            for k0 in (0..p.batch_size).step_by(ROLLOUT_LANES) {
                let lanes = ((p.batch_size - k0) as usize).min(ROLLOUT_LANES);
                for (t, (&v, &w)) in vx.iter().zip(wz.iter()).enumerate() {
                    let (a, b) = noise_lanes(key, k0, t as u32);
                    for (j, (cv, cw)) in cvx_w.iter_mut().zip(cwz_w.iter_mut()).enumerate() {
                        if let (Some(cv), Some(cw)) = (cv.get_mut(t), cw.get_mut(t)) {
                            *cv = v + vx_std * T::lit(a.lane(j));
                            *cw = w + wz_std * T::lit(b.lane(j));
                        }
                    }
                }
                let sums = self.lane_sums(c, &cvx_w, &cwz_w, n);
                for ((cv, cw), sums) in cvx_w.iter().zip(&cwz_w).zip(&sums).take(lanes) {
                    let cost = self.critics(sums, n, path_length) + control_cost(&cv[..n], &cw[..n]);
                    soft.add(cost, inv_temp, &cv[..n], &cw[..n]);
                    furthest = furthest.max(sums.path.reached);
                }
            }
            let inv_sum = soft.sum.recip();
            for ((v, w), (&sv, &sw)) in vx.iter_mut().zip(wz.iter_mut()).zip(soft.vx.iter().zip(&soft.wz)) {
                *v = sv * inv_sum;
                *w = sw * inv_sum;
            }
            self.constrain(c, vx, wz);
        }
        // u_1 (`time_steps` >= 2 is validated; the speed itself otherwise).
        let command =
            Twist2 { v: vx.get(1).copied().unwrap_or(c.speed.v), omega: wz.get(1).copied().unwrap_or(c.speed.omega) };
        (command, furthest)
    }

    /// nav2 `applyControlSequenceConstraints` (shifting, DiffDrive): u_0 = speed, every
    /// element within the bounds and the accelerations from the one before.
    fn constrain(&self, c: &Cycle<'_, T>, vx: &mut [T], wz: &mut [T]) {
        let p = &self.p;
        let dt = p.model_dt;
        let (max_dvx, min_dvx, max_dwz) = (dt * p.ax_max, dt * p.ax_min, dt * p.az_max);
        if let (Some(v0), Some(w0)) = (vx.first_mut(), wz.first_mut()) {
            (*v0, *w0) = (c.speed.v, c.speed.omega);
        }
        let (mut vx_last, mut wz_last) = (c.speed.v, c.speed.omega);
        for (vt, wt) in vx.iter_mut().zip(wz.iter_mut()) {
            let v = p.vx_max.min(vt.max(p.vx_min));
            *vt = clamp_by_accel(vx_last, v, min_dvx, max_dvx);
            vx_last = *vt;
            let w = p.wz_max.min(wt.max(-p.wz_max));
            *wt = clamp_by_accel(wz_last, w, -max_dwz, max_dwz);
            wz_last = *wt;
        }
    }
}

/// MPPI (module docs). Implements [`Law`] with [`WheelDemand::Twist`]. Several runs side
/// by side ([`crate::lane`]) are planned one lane at a time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MppiLaw<L: Lane> {
    planner: Planner<L::Scalar>,
    /// Control ticks per planning cycle: model_dt / control_dt.
    ticks_per_plan: u32,
    /// r, m and R, m: the speed from the wheel encoders.
    wheel_radius: L::Scalar,
    half_track: L::Scalar,
    /// The optimal sequence (nav2 `control_sequence_`), `time_steps` long: vx m/s, wz rad/s.
    vx: [L; MAX_TIME_STEPS],
    wz: [L; MAX_TIME_STEPS],
    /// The last command (nav2 `last_command_vel_`).
    command: Twist2<L>,
    /// Control ticks since the last plan (0: plan at this tick).
    tick: L,
    /// Planning cycles since the start: the noise's draw counter.
    cycle: L,
    /// On a path: the point closest to C, followed from tick to tick.
    cursor: PathCursor<L>,
    /// On a path: the path parameter of the furthest plan point the last cycle's rollouts
    /// reached (F, [`super::mppi_path`]); 0 before the first.
    furthest: L,
}

impl<L: Lane> MppiLaw<L> {
    /// Checks the keys (errors name the key) and builds the law for the controller's robot
    /// model (the speed from the encoders; the dynamic rollouts' robot), the drive it
    /// commands and the wheel stage's `wheel_speed_max` (rad/s; the dynamic rollouts'),
    /// and `control_dt` (s).
    pub fn for_lanes(
        p: MppiParams<L::Scalar>,
        model: &RobotParams<L::Scalar>,
        drive: &DriveParams<L::Scalar>,
        wheel_speed_max: L::Scalar,
        control_dt: L::Scalar,
    ) -> Result<Self, ParamError> {
        let ticks_per_plan = p.validate(control_dt)?;
        let dynamic = match p.motion_model {
            MotionModel::Kinematic => None,
            MotionModel::Dynamic => {
                Some(DynamicModel::new(model, drive, wheel_speed_max, p.model_dt, p.rollout_substeps)?)
            }
        };
        Ok(Self {
            planner: Planner { p, dynamic, obstacles: Obstacles::default(), obstacles_f64: Obstacles::default() },
            ticks_per_plan,
            wheel_radius: model.wheel_radius,
            half_track: model.half_track,
            vx: [L::default(); MAX_TIME_STEPS],
            wz: [L::default(); MAX_TIME_STEPS],
            command: Twist2::default(),
            tick: L::default(),
            cycle: L::default(),
            cursor: PathCursor::default(),
            furthest: L::default(),
        })
    }

    /// The law with the obstacles its `obstacles` critic scores the rollouts against (none
    /// by default: the critic is off).
    pub fn with_obstacles(mut self, obstacles: &Obstacles<L::Scalar>) -> Self {
        self.planner.obstacles = *obstacles;
        self.planner.obstacles_f64 = obstacles.cast();
        self
    }

    /// The keys.
    pub fn params(&self) -> &MppiParams<L::Scalar> {
        &self.planner.p
    }

    /// The optimal sequence of lane `lane` after the last plan and its shift: (vx m/s,
    /// wz rad/s) per step of `model_dt`, `time_steps` long.
    pub fn sequence(&self, lane: usize, vx: &mut [L::Scalar], wz: &mut [L::Scalar]) {
        let n = self.planner.p.time_steps as usize;
        for ((v, w), (sv, sw)) in vx.iter_mut().zip(wz.iter_mut()).zip(self.vx.iter().zip(&self.wz)).take(n) {
            *v = sv.lane(lane);
            *w = sw.lane(lane);
        }
    }

    /// Plans lane `i` from measurement `m` to the reference `r` (at rest: its pose is the
    /// goal) or, given, along `path` from the cursor's closest point.
    fn plan_lane(&mut self, i: usize, m: &Measurement<L>, r: &ReferenceState<L>, path: Option<&dyn Path<L>>) {
        let p = self.planner.p;
        // Within the arrays (validated so), so that no index can panic.
        let n = (p.time_steps as usize).min(MAX_TIME_STEPS);
        let dt = p.model_dt;
        let rr = self.wheel_radius;
        let (w_r, w_l) = (m.wheel_speeds.right.lane(i), m.wheel_speeds.left.lane(i));
        let half = <L::Scalar as Real>::lit(0.5);
        let v_meas = rr * (w_r + w_l) * half;
        let w_meas = rr * (w_r - w_l) * half / self.half_track;
        // nav2 `prepare` (closed loop): the last command within what the accelerations
        // allow from the measured speed over one period.
        let (c_v, c_w) = (self.command.v.lane(i), self.command.omega.lane(i));
        let speed = Twist2 {
            v: c_v.max(v_meas + dt * p.ax_min).min(v_meas + dt * p.ax_max),
            omega: c_w.max(w_meas - dt * p.az_max).min(w_meas + dt * p.az_max),
        };
        let cycle = self.cycle.lane(i).to_f64_lossless() as u64;
        let pose = Pose2 { x: m.pose.x.lane(i), y: m.pose.y.lane(i), theta: m.pose.theta.lane(i) };
        let plan = path.map(|path| {
            let prune = p.prune_distance.to_f64_lossless();
            LocalPlan::along(path, i, self.cursor.s.lane(i), p.path_resolution, prune, &self.planner.obstacles_f64)
        });
        let lit = <L::Scalar as Real>::lit;
        let (goal, path_length, targets) = match &plan {
            Some(plan) => {
                let end = plan.last();
                let goal = Pose2 { x: lit(end.x), y: lit(end.y), theta: lit(end.theta) };
                let furthest = plan.index_at(self.furthest.lane(i).to_f64_lossless());
                let at = Pose2 {
                    x: pose.x.to_f64_lossless(),
                    y: pose.y.to_f64_lossless(),
                    theta: pose.theta.to_f64_lossless(),
                };
                (goal, lit(plan.length()), Some(PathTargets::new(&p, plan, furthest, at)))
            }
            None => {
                let goal = Pose2 { x: r.pose.x.lane(i), y: r.pose.y.lane(i), theta: r.pose.theta.lane(i) };
                (goal, (goal.x - pose.x).hypot_libm(goal.y - pose.y), None)
            }
        };
        let c = Cycle {
            pose,
            goal,
            path_length,
            path: targets,
            speed,
            measured: Twist2 { v: v_meas, omega: w_meas },
            draw: cycle.wrapping_mul(u64::from(p.iteration_count)),
        };
        let mut vx = [<L::Scalar as num_traits::Zero>::zero(); MAX_TIME_STEPS];
        let mut wz = [<L::Scalar as num_traits::Zero>::zero(); MAX_TIME_STEPS];
        for ((v, w), (sv, sw)) in vx.iter_mut().zip(wz.iter_mut()).zip(self.vx.iter().zip(&self.wz)).take(n) {
            *v = sv.lane(i);
            *w = sw.lane(i);
        }
        let (cmd, reached) = self.planner.plan(&c, &mut vx[..n], &mut wz[..n]);
        if let Some(plan) = &plan {
            self.furthest.set_lane(i, lit(plan.s(reached)));
        }
        // nav2 `shiftControlSequence`: one step on, the last element repeated.
        let on = vx.iter().zip(&wz).take(n).skip(1);
        for ((sv, sw), (&v, &w)) in self.vx.iter_mut().zip(self.wz.iter_mut()).zip(on) {
            sv.set_lane(i, v);
            sw.set_lane(i, w);
        }
        if let Some(last) = n.checked_sub(1) {
            let (v, w) = (vx.get(last).copied(), wz.get(last).copied());
            if let (Some(sv), Some(sw), Some(v), Some(w)) = (self.vx.get_mut(last), self.wz.get_mut(last), v, w) {
                sv.set_lane(i, v);
                sw.set_lane(i, w);
            }
        }
        self.command.v.set_lane(i, cmd.v);
        self.command.omega.set_lane(i, cmd.omega);
        self.cycle.set_lane(i, <L::Scalar as Real>::lit((cycle + 1) as f64));
    }
}

impl<L: Lane> MppiLaw<L> {
    /// One control tick: plans the lanes whose cycle starts now, holds the command.
    fn control_tick(&mut self, m: &Measurement<L>, r: &ReferenceState<L>, path: Option<&dyn Path<L>>) -> LawOutput<L> {
        for i in 0..L::WIDTH {
            let tick = self.tick.lane(i);
            if tick == <L::Scalar as num_traits::Zero>::zero() {
                self.plan_lane(i, m, r, path);
            }
            let next = tick + <L::Scalar as num_traits::One>::one();
            let next = if next >= <L::Scalar as Real>::lit(f64::from(self.ticks_per_plan)) {
                <L::Scalar as num_traits::Zero>::zero()
            } else {
                next
            };
            self.tick.set_lane(i, next);
        }
        LawOutput { demand: WheelDemand::Twist(self.command), errors: polar_errors(m.pose, r.pose) }
    }
}

impl<L: Lane> Law<L> for MppiLaw<L> {
    /// To the reference's pose as a goal (at rest: nav2's goal critics).
    fn update(&mut self, _t: L, m: &Measurement<L>, r: &ReferenceState<L>) -> LawOutput<L> {
        self.control_tick(m, r, None)
    }

    fn reads_path(&self) -> bool {
        true
    }

    /// Along the reference's path, its timing ignored (nav2's path critics,
    /// [`super::mppi_path`]): the cursor follows the point closest to C every tick.
    fn update_on_path(&mut self, _t: L, m: &Measurement<L>, r: &ReferenceState<L>, path: &dyn Path<L>) -> LawOutput<L> {
        let p = &self.planner.p;
        let ds = p.path_resolution * <L::Scalar as Real>::lit(0.25);
        self.cursor.advance(path, m.pose.x, m.pose.y, p.max_robot_pose_search_dist, ds);
        self.control_tick(m, r, Some(path))
    }

    fn reset_lanes(&mut self, lanes: L::Mask) {
        let zero = L::default();
        for t in 0..MAX_TIME_STEPS {
            self.vx[t] = L::select(lanes, zero, self.vx[t]);
            self.wz[t] = L::select(lanes, zero, self.wz[t]);
        }
        self.command.v = L::select(lanes, zero, self.command.v);
        self.command.omega = L::select(lanes, zero, self.command.omega);
        self.tick = L::select(lanes, zero, self.tick);
        self.cycle = L::select(lanes, zero, self.cycle);
        self.cursor.reset_lanes(lanes);
        self.furthest = L::select(lanes, zero, self.furthest);
    }
}

// What the MCAP shows of a plan (wmr-cli's `/runN/mppi/optimal` and `/runN/mppi/rollouts`,
// issue 41): read-only views of the law, for one lane, into the caller's buffers. Nothing
// here runs in `update`.
impl<L: Lane> MppiLaw<L> {
    /// Planning cycles lane `lane` has run (one per `model_dt`, the first at t = 0).
    pub fn cycles(&self, lane: usize) -> u64 {
        self.cycle.lane(lane).to_f64_lossless() as u64
    }

    /// The speed (m/s, rad/s) the encoders of measurement `m` give for lane `lane`.
    fn measured_speed(&self, lane: usize, m: &Measurement<L>) -> Twist2<f64> {
        let f = |x: L::Scalar| x.to_f64_lossless();
        let (r, big_r) = (f(self.wheel_radius), f(self.half_track));
        let (w_r, w_l) = (f(m.wheel_speeds.right.lane(lane)), f(m.wheel_speeds.left.lane(lane)));
        Twist2 { v: r * (w_r + w_l) * 0.5, omega: r * (w_r - w_l) * 0.5 / big_r }
    }

    /// Rolls the twist demands `cvx`, `cwz` (m/s, rad/s, `n` steps of `model_dt`) out on
    /// the law's own model from the pose of `m` (lane `lane`): step i driven by `held`
    /// for i = 0 and by demand i - 1 after it (as the plan's rollouts are). Writes the
    /// pose after each step (world frame) into `out`; returns how many.
    fn roll(
        &self,
        lane: usize,
        m: &Measurement<L>,
        held: Twist2<f64>,
        cvx: &[f64; MAX_TIME_STEPS],
        cwz: &[f64; MAX_TIME_STEPS],
        out: &mut [Pose2<f64>],
    ) -> usize {
        let f = |x: L::Scalar| x.to_f64_lossless();
        let n = (self.planner.p.time_steps as usize).min(MAX_TIME_STEPS).min(out.len());
        let start = Pose2 { x: f(m.pose.x.lane(lane)), y: f(m.pose.y.lane(lane)), theta: f(m.pose.theta.lane(lane)) };
        let mut visit = |i: usize, pose: Pose2<Wide>, _: Twist2<Wide>| {
            if let Some(o) = out.get_mut(i) {
                *o = Pose2 { x: pose.x.lane(0), y: pose.y.lane(0), theta: pose.theta.lane(0) };
            }
        };
        match &self.planner.dynamic {
            Some(model) => {
                let demand = |i: usize| match i.checked_sub(1) {
                    None => Twist2 { v: Wide::splat(held.v), omega: Wide::splat(held.omega) },
                    Some(k) => Twist2 {
                        v: Wide::splat(cvx.get(k).copied().unwrap_or(0.0)),
                        omega: Wide::splat(cwz.get(k).copied().unwrap_or(0.0)),
                    },
                };
                model.rollout(start, self.measured_speed(lane, m), n, demand, &mut visit);
            }
            None => {
                let p = self.planner.p.cast::<f64>();
                let cv: [Wide; MAX_TIME_STEPS] = core::array::from_fn(|t| Wide::splat(cvx[t]));
                let cw: [Wide; MAX_TIME_STEPS] = core::array::from_fn(|t| Wide::splat(cwz[t]));
                let pose = Pose2 { x: Wide::splat(start.x), y: Wide::splat(start.y), theta: Wide::splat(start.theta) };
                let speed = Twist2 { v: Wide::splat(held.v), omega: Wide::splat(held.omega) };
                kinematic_rollout(&p, pose, speed, &cv[..n], &cw[..n], &mut visit);
            }
        }
        n
    }

    /// The optimal trajectory of lane `lane` after a plan: the sequence the law holds
    /// after its shift (the command u_1 first, then u_2, ...), rolled out on the law's own
    /// model (the dynamic model from the measured speed, or nav2's DiffDrive) from the
    /// pose of the measurement `m` the plan read, over `time_steps` steps of `model_dt`.
    /// Writes the pose after each step (world frame) into `out`; returns how many.
    pub fn predict(&self, lane: usize, m: &Measurement<L>, out: &mut [Pose2<f64>]) -> usize {
        let last = (self.planner.p.time_steps as usize).clamp(1, MAX_TIME_STEPS) - 1;
        let at = |t: usize| {
            let (v, w) = (self.vx.get(t.min(last)), self.wz.get(t.min(last)));
            v.zip(w).map_or((0.0, 0.0), |(v, w)| (v.lane(lane).to_f64_lossless(), w.lane(lane).to_f64_lossless()))
        };
        // Step 0 is driven by element 0 (u_1), step i by demand i - 1 = element i.
        let (mut cvx, mut cwz) = ([0.0; MAX_TIME_STEPS], [0.0; MAX_TIME_STEPS]);
        for (t, (v, w)) in cvx.iter_mut().zip(cwz.iter_mut()).enumerate() {
            (*v, *w) = at(t + 1);
        }
        let (v0, w0) = at(0);
        self.roll(lane, m, Twist2 { v: v0, omega: w0 }, &cvx, &cwz, out)
    }

    /// Sample `k` of the first iteration of the plan this law (lane `lane`) is about to
    /// run on measurement `m`, rolled out as the plan rolls it out: call it on a copy of
    /// the law taken before the `update` that plans. Writes the pose after each step
    /// (world frame) into `out`; returns how many.
    pub fn sampled_rollout(&self, lane: usize, k: u32, m: &Measurement<L>, out: &mut [Pose2<f64>]) -> usize {
        let p = &self.planner.p;
        let f = |x: L::Scalar| x.to_f64_lossless();
        let dt = f(p.model_dt);
        // The speed the rollouts start from (as the plan computes it).
        let meas = self.measured_speed(lane, m);
        let (c_v, c_w) = (f(self.command.v.lane(lane)), f(self.command.omega.lane(lane)));
        let held = Twist2 {
            v: c_v.max(meas.v + dt * f(p.ax_min)).min(meas.v + dt * f(p.ax_max)),
            omega: c_w.max(meas.omega - dt * f(p.az_max)).min(meas.omega + dt * f(p.az_max)),
        };
        let key = draw_key(p.seed, self.cycles(lane).wrapping_mul(u64::from(p.iteration_count)));
        let (mut cvx, mut cwz) = ([0.0; MAX_TIME_STEPS], [0.0; MAX_TIME_STEPS]);
        for (t, (v, w)) in cvx.iter_mut().zip(cwz.iter_mut()).enumerate() {
            let (a, b) = noise_lanes(key, k, t as u32);
            let (mean_v, mean_w) =
                if t == 0 { (held.v, held.omega) } else { (f(self.vx[t].lane(lane)), f(self.wz[t].lane(lane))) };
            *v = mean_v + f(p.vx_std) * a.lane(0);
            *w = mean_w + f(p.wz_std) * b.lane(0);
        }
        self.roll(lane, m, held, &cvx, &cwz, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drive::DcMotorParams;
    use crate::obstacle::Obstacle;
    use crate::reference::Circle;

    /// The planner's AVX2 build gives the baseline build's bits, on both models, with
    /// obstacles and on a path (skipped, and said so, on a processor without AVX2).
    #[test]
    fn the_avx2_build_plans_the_same_bits() {
        extern crate std;
        if !super::super::vector_unit::has_avx2() {
            std::eprintln!("SKIP: no AVX2 on this processor");
            return;
        }
        let robot = RobotParams::<f64>::paper();
        let drive = DriveParams::DcMotor(DcMotorParams::default());
        let obstacles = Obstacles::new(&[Obstacle::Circle { center: (0.6, 0.3), radius: 0.1 }], 0.1).unwrap();
        let circle = Circle::new(0.0, 0.0, 1.0, 0.3, 0.0).unwrap();
        for model in [MotionModel::Dynamic, MotionModel::Kinematic] {
            for on_path in [false, true] {
                let p = MppiParams::<f64> { motion_model: model, batch_size: 203, ..MppiParams::default() };
                let law = MppiLaw::<f64>::for_lanes(p, &robot, &drive, 40.0, 1e-3).unwrap().with_obstacles(&obstacles);
                let plan =
                    on_path.then(|| LocalPlan::along::<f64>(&circle, 0, 0.2, 0.05, 2.0, &law.planner.obstacles_f64));
                let pose = Pose2 { x: 0.9, y: 0.1, theta: 1.4 };
                let c = Cycle {
                    pose,
                    goal: Pose2 { x: 1.0, y: 0.2, theta: 0.2 },
                    path_length: plan.as_ref().map_or(0.8, |p| p.length()),
                    path: plan.as_ref().map(|plan| PathTargets::new(&p, plan, 6, pose)),
                    speed: Twist2 { v: 0.2, omega: 0.3 },
                    measured: Twist2 { v: 0.19, omega: 0.31 },
                    draw: 5,
                };
                let seq = |k: usize| (0.1 + 0.003 * k as f64, 0.2 - 0.004 * k as f64);
                let (mut vx, mut wz): ([f64; 56], [f64; 56]) =
                    (core::array::from_fn(|k| seq(k).0), core::array::from_fn(|k| seq(k).1));
                let (mut vx2, mut wz2) = (vx, wz);
                let a = law.planner.plan_baseline(&c, &mut vx, &mut wz);
                #[allow(unsafe_code)]
                // SAFETY: the processor has AVX2 (checked above).
                let b = unsafe { law.planner.plan_avx2(&c, &mut vx2, &mut wz2) };
                let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<std::vec::Vec<_>>();
                assert_eq!((a.0.v.to_bits(), a.0.omega.to_bits(), a.1), (b.0.v.to_bits(), b.0.omega.to_bits(), b.1));
                assert_eq!((bits(&vx), bits(&wz)), (bits(&vx2), bits(&wz2)), "{model:?}, on a path: {on_path}");
            }
        }
    }
}
