//! How a run went, judged once, from the true state against the reference: arrival,
//! final errors, peaks and integrals, accumulated step by step without allocating.

use crate::Real;
use crate::lane::{Lane, Lanes, Mask};
use crate::math::{Pose2, Wheels, wrap_angle};
use crate::state::State;

/// Distance to the goal (m) below which a run counts as arrived: 1 cm.
pub const ARRIVAL_RADIUS_M: f64 = 0.01;

/// Largest |heading error| (rad) at the end of a converged run of a law built to reach
/// the goal heading ([`crate::controller::Law::reaches_heading`]): 5 deg. The Lyapunov
/// law and the repaired paper law end within hundredths of a degree when their wheels
/// hold them; a run that stops within 1 cm but 40 deg off has not done what the law is for.
pub const ARRIVAL_HEADING_RAD: f64 = 5.0 * core::f64::consts::PI / 180.0;

/// Default `[sim] xy_goal_tolerance`, m: a run is docked when it ends with C within this
/// distance of the goal position ([`Outcome::docked`]; nav2's `xy_goal_tolerance`).
pub const XY_GOAL_TOLERANCE_M: f64 = 0.01;

/// Default `[sim] yaw_goal_tolerance_deg`, deg: a run is docked when it ends with
/// |heading error| within this ([`Outcome::docked`]; nav2's `yaw_goal_tolerance`, in deg).
pub const YAW_GOAL_TOLERANCE_DEG: f64 = 1.0;

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Termination {
    /// Reached t_end with a finite state inside the box.
    Completed,
    /// Stopped before t_end by `stop_when_settled`: at rest within the arrival radius
    /// with the law holding ([`crate::settle`]).
    Settled,
    /// The next state was not finite; the run stopped at the last finite one.
    NonFinite,
    /// Point C left the 1 km box around the origin.
    LeftBox,
    /// The robot's footprint touched an obstacle ([`crate::obstacle`]): the run stopped
    /// at the contact.
    Collided,
}

impl Termination {
    /// Every termination, in the order of their codes ([`Termination::code`]).
    pub const ALL: [Termination; 5] = [
        Termination::Completed,
        Termination::Settled,
        Termination::NonFinite,
        Termination::LeftBox,
        Termination::Collided,
    ];

    /// A small number for the termination (its index in [`Termination::ALL`]), for
    /// number-only records (the Python sweep's outcome rows).
    pub fn code(self) -> u8 {
        match self {
            Termination::Completed => 0,
            Termination::Settled => 1,
            Termination::NonFinite => 2,
            Termination::LeftBox => 3,
            Termination::Collided => 4,
        }
    }

    /// The termination of `code`, if it is one.
    pub fn of_code(code: u8) -> Option<Self> {
        Self::ALL.get(usize::from(code)).copied()
    }

    /// True for the two divergence cases.
    pub fn diverged(self) -> bool {
        matches!(self, Termination::NonFinite | Termination::LeftBox)
    }
}

/// The verdict on a run, one of four (the fourth for tracking runs only): decided here
/// and in [`crate::tracking`], nowhere else.
///
/// A run that is neither converged nor diverged is [`Status::Unsettled`]: it may still
/// arrive later, wander for ever, or circle; only a longer run can tell. It is not
/// counted as a divergence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Status {
    /// Not diverged, and the final distance to the goal is below [`ARRIVAL_RADIUS_M`]; for a
    /// law built to reach the goal heading, the final heading error within
    /// [`ARRIVAL_HEADING_RAD`] too ([`Outcome::heading_tolerance`]). The paper's law,
    /// which leaves several degrees, is judged on the distance alone.
    Converged,
    /// The state stopped being finite or C left the 1 km box: the run was stopped there.
    Diverged,
    /// Finite and inside the box at t_end, but not within [`ARRIVAL_RADIUS_M`] of the goal
    /// (or, for a law built to reach the heading, not within [`ARRIVAL_HEADING_RAD`] of it).
    Unsettled,
    /// A tracking run only (never a run towards a goal): not within the tolerance at the
    /// end, and the reference asked more than the robot can give (wheel speeds above the
    /// limit, or an error that grew: [`crate::tracking::TrackingOutcome::cannot_follow`]).
    CannotFollow,
    /// The footprint touched an obstacle: the run stopped there ([`crate::obstacle`]).
    Collided,
}

impl Status {
    /// Every status, in report order.
    pub const ALL: [Status; 5] =
        [Status::Converged, Status::Diverged, Status::Unsettled, Status::CannotFollow, Status::Collided];

    /// `"converged"`, `"diverged"`, `"unsettled"`, `"cannot_follow"` or `"collided"`: the
    /// word every output uses.
    pub fn name(self) -> &'static str {
        match self {
            Status::Converged => "converged",
            Status::Diverged => "diverged",
            Status::Unsettled => "unsettled",
            Status::CannotFollow => "cannot_follow",
            Status::Collided => "collided",
        }
    }
}

/// Outcome of one run. Integrals are left Riemann sums over the plant steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome<T> {
    /// How the run ended.
    pub termination: Termination,
    /// Time of the last state, s (t_end unless diverged or settled).
    pub t_final: T,
    /// Final true pose of C (world frame).
    pub final_pose: Pose2<T>,
    /// The reference's goal at `t_final`.
    pub goal: Pose2<T>,
    /// Final distance from C to the goal position, m.
    pub final_dl: T,
    /// Final heading error wrap(theta_d - theta), rad.
    pub final_heading_error: T,
    /// Largest |final_heading_error| of a converged run, rad: [`ARRIVAL_HEADING_RAD`] for
    /// a law built to reach the goal heading, infinite for the others.
    pub heading_tolerance: T,
    /// First time from which the true distance to the goal stays below
    /// [`ARRIVAL_RADIUS_M`] to the end, s; `None` if never.
    pub time_to_arrival: Option<T>,
    /// Largest |wheel speed| seen, rad/s.
    pub peak_wheel_speed: T,
    /// Largest final distance to the goal position of a docked run, m (`[sim]
    /// xy_goal_tolerance`; [`XY_GOAL_TOLERANCE_M`] unless set with
    /// [`Outcome::with_goal_tolerance`]).
    pub xy_goal_tolerance: T,
    /// Largest |final heading error| of a docked run, rad (`[sim] yaw_goal_tolerance_deg`;
    /// [`YAW_GOAL_TOLERANCE_DEG`] unless set with [`Outcome::with_goal_tolerance`]).
    pub yaw_goal_tolerance: T,
    /// Path length of C, m: int |v| dt.
    pub path_length: T,
    /// Work of both drives on their wheels, J: int (|tau_r omega_r| + |tau_l omega_l|) dt.
    /// Braking counts as positive work: this is the effort spent, not the energy drawn.
    pub abs_work: T,
}

impl<T: Real> Outcome<T> {
    /// Converged, diverged or unsettled (see [`Status`]).
    pub fn status(&self) -> Status {
        if self.termination.diverged() {
            Status::Diverged
        } else if self.termination == Termination::Collided {
            Status::Collided
        } else if self.final_dl < T::lit(ARRIVAL_RADIUS_M) && self.final_heading_error.abs() <= self.heading_tolerance {
            Status::Converged
        } else {
            Status::Unsettled
        }
    }

    /// Whether the run ended docked: neither diverged nor collided, its final state (after settling, as
    /// `final_dl` and `final_heading_error`) within [`Outcome::xy_goal_tolerance`] of the
    /// goal position and [`Outcome::yaw_goal_tolerance`] of the goal heading, both bounds
    /// included (nav2's `SimpleGoalChecker`: `dx^2 + dy^2 <= xy^2`, `|dyaw| <= yaw`).
    /// Every law is judged on both, the paper's too: docking needs the heading.
    pub fn docked(&self) -> bool {
        !self.termination.diverged()
            && self.termination != Termination::Collided
            && self.final_dl <= self.xy_goal_tolerance
            && self.final_heading_error.abs() <= self.yaw_goal_tolerance
    }

    /// The outcome judged with the goal tolerances `xy` (m) and `yaw` (rad) of
    /// [`Outcome::docked`] (`[sim] xy_goal_tolerance`, `yaw_goal_tolerance_deg`).
    pub fn with_goal_tolerance(mut self, xy: T, yaw: T) -> Self {
        self.xy_goal_tolerance = xy;
        self.yaw_goal_tolerance = yaw;
        self
    }
}

/// Accumulates an [`Outcome`] from the true state at every plant step; per lane for
/// several runs side by side ([`crate::lane`]).
#[derive(Clone, Copy, Debug)]
pub struct Metrics<T: Lane> {
    /// ARRIVAL_RADIUS_M^2, m^2: arrival is decided on the squared distance (no root per step).
    arrival_radius_sq: T::Scalar,
    /// [`Outcome::heading_tolerance`], rad.
    heading_tolerance: T::Scalar,
    /// Within the arrival radius since `arrived_since` (s), where `arrived`.
    arrived: T::Mask,
    arrived_since: T,
    peak_wheel_speed: T,
    path_length: T,
    abs_work: T,
}

impl<T: Lane> Default for Metrics<T> {
    fn default() -> Self {
        let z = T::default();
        let r = <T::Scalar as Real>::lit(ARRIVAL_RADIUS_M);
        Self {
            arrival_radius_sq: r * r,
            heading_tolerance: <T::Scalar as num_traits::Float>::infinity(),
            arrived: T::Mask::splat(false),
            arrived_since: z,
            peak_wheel_speed: z,
            path_length: z,
            abs_work: z,
        }
    }
}

impl<T: Lane> Metrics<T> {
    /// The metrics for a law that is (`true`) or is not built to reach the goal heading
    /// ([`crate::controller::Law::reaches_heading`]): [`Outcome::heading_tolerance`].
    pub fn judging_heading(mut self, on: bool) -> Self {
        let r = <T::Scalar as Real>::lit(ARRIVAL_HEADING_RAD);
        self.heading_tolerance = if on { r } else { <T::Scalar as num_traits::Float>::infinity() };
        self
    }

    /// Adds the instant `t` (s) at the start of a plant step of length `dt` (s): the true
    /// state, the wheel speeds (rad/s) and torques (N m) held over the step, the goal.
    #[inline(always)]
    pub fn add_step(
        &mut self,
        t: T,
        state: &State<T>,
        wheel_speeds: Wheels<T>,
        torque: Wheels<T>,
        goal: Pose2<T>,
        dt: T,
    ) {
        self.observe(t, state, wheel_speeds, goal);
        self.path_length = self.path_length + state.v.abs() * dt;
        let power = (torque.right * wheel_speeds.right).abs() + (torque.left * wheel_speeds.left).abs();
        self.abs_work = self.abs_work + power * dt;
    }

    /// Sees the distance to the goal and the wheel speeds at `t` (also for the final state).
    #[inline(always)]
    pub fn observe(&mut self, t: T, state: &State<T>, wheel_speeds: Wheels<T>, goal: Pose2<T>) {
        let dx = goal.x - state.x;
        let dy = goal.y - state.y;
        let inside = (dx * dx + dy * dy).lt(T::splat(self.arrival_radius_sq));
        self.arrived_since = T::select(inside & !self.arrived, t, self.arrived_since);
        self.arrived = inside;
        let w = wheel_speeds.right.abs().max(wheel_speeds.left.abs());
        self.peak_wheel_speed = self.peak_wheel_speed.max(w);
    }

    /// Clears the runs in `lanes`, as at the start of a run.
    pub fn reset_lanes(&mut self, lanes: T::Mask) {
        let fresh = Self::default();
        self.arrived = self.arrived & !lanes;
        self.peak_wheel_speed = T::select(lanes, fresh.peak_wheel_speed, self.peak_wheel_speed);
        self.path_length = T::select(lanes, fresh.path_length, self.path_length);
        self.abs_work = T::select(lanes, fresh.abs_work, self.abs_work);
    }
}

impl<const N: usize> Metrics<Lanes<N>> {
    /// The metrics of lane `i`.
    pub fn lane(&self, i: usize) -> Metrics<f64> {
        Metrics {
            arrival_radius_sq: self.arrival_radius_sq,
            heading_tolerance: self.heading_tolerance,
            arrived: self.arrived.lane(i),
            arrived_since: self.arrived_since.0[i],
            peak_wheel_speed: self.peak_wheel_speed.0[i],
            path_length: self.path_length.0[i],
            abs_work: self.abs_work.0[i],
        }
    }
}

impl<T: Real> Metrics<T> {
    /// The outcome, given the last time (s), true state and goal, and how the run ended.
    pub fn finish(&self, t: T, state: &State<T>, goal: Pose2<T>, termination: Termination) -> Outcome<T> {
        let pose = state.pose();
        Outcome {
            termination,
            t_final: t,
            final_pose: pose,
            goal,
            final_dl: (goal.x - pose.x).hypot_libm(goal.y - pose.y),
            final_heading_error: wrap_angle(goal.theta - pose.theta),
            heading_tolerance: self.heading_tolerance,
            time_to_arrival: self.arrived.then_some(self.arrived_since),
            peak_wheel_speed: self.peak_wheel_speed,
            xy_goal_tolerance: T::lit(XY_GOAL_TOLERANCE_M),
            yaw_goal_tolerance: T::lit(YAW_GOAL_TOLERANCE_DEG * core::f64::consts::PI / 180.0),
            path_length: self.path_length,
            abs_work: self.abs_work,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn termination_codes_round_trip() {
        for (i, t) in Termination::ALL.into_iter().enumerate() {
            assert_eq!(usize::from(t.code()), i);
            assert_eq!(Termination::of_code(t.code()), Some(t));
        }
        assert_eq!(Termination::of_code(5), None);
    }

    fn outcome_at(x: f64, termination: Termination) -> Outcome<f64> {
        let state = State::at_rest(Pose2::new(x, 0.0, 0.0));
        Metrics::default().finish(60.0, &state, Pose2::default(), termination)
    }

    #[test]
    fn three_outcomes_from_the_true_state() {
        assert_eq!(outcome_at(0.009, Termination::Completed).status(), Status::Converged);
        assert_eq!(outcome_at(0.011, Termination::Completed).status(), Status::Unsettled);
        // Diverged wins over a final state near the goal: the run was stopped.
        assert_eq!(outcome_at(0.0, Termination::LeftBox).status(), Status::Diverged);
        assert_eq!(outcome_at(0.0, Termination::NonFinite).status(), Status::Diverged);
        // A law built to reach the goal heading: 137 deg off at 1 mm is not converged.
        let judged = |x: f64, heading: f64| {
            let state = State::at_rest(Pose2::new(x, 0.0, heading));
            Metrics::<f64>::default().judging_heading(true).finish(
                60.0,
                &state,
                Pose2::default(),
                Termination::Completed,
            )
        };
        assert_eq!(judged(0.001, 137f64.to_radians()).status(), Status::Unsettled);
        assert_eq!(judged(0.001, 4.9f64.to_radians()).status(), Status::Converged);
        assert_eq!(judged(0.001, -5.1f64.to_radians()).status(), Status::Unsettled);
        // The paper's law is judged on the distance alone.
        let paper = Metrics::<f64>::default().judging_heading(false);
        let off = State::at_rest(Pose2::new(0.001, 0.0, 137f64.to_radians()));
        assert_eq!(paper.finish(60.0, &off, Pose2::default(), Termination::Completed).status(), Status::Converged);
        let names: [&str; 5] = Status::ALL.map(Status::name);
        assert_eq!(names, ["converged", "diverged", "unsettled", "cannot_follow", "collided"]);
        // A collision is its own outcome, not a divergence.
        let hit = paper.finish(3.0, &off, Pose2::default(), Termination::Collided);
        assert_eq!(hit.status(), Status::Collided);
        assert!(!Termination::Collided.diverged());
    }

    /// Issue 42: a run is docked when its final state is within both goal tolerances
    /// (nav2's bounds included), whatever the law; a diverged run never is.
    #[test]
    fn docked_just_inside_and_just_outside_each_tolerance() {
        fn docked<T: Real>(x: f64, heading_deg: f64, tolerance: Option<(f64, f64)>, termination: Termination) -> bool {
            let state = State::at_rest(Pose2::new(T::lit(x), T::lit(0.0), T::lit(heading_deg.to_radians())));
            let o = Metrics::<T>::default().finish(T::lit(60.0), &state, Pose2::default(), termination);
            match tolerance {
                None => o.docked(),
                Some((xy, yaw_deg)) => o.with_goal_tolerance(T::lit(xy), T::lit(yaw_deg.to_radians())).docked(),
            }
        }
        fn check<T: Real>() {
            let done = Termination::Completed;
            // The defaults, 1 cm and 1 deg (a hand-made final state 1 % inside, 1 % outside).
            assert!(docked::<T>(0.0099, 0.0, None, done));
            assert!(!docked::<T>(0.0101, 0.0, None, done));
            assert!(docked::<T>(0.0, 0.99, None, done));
            assert!(!docked::<T>(0.0, 1.01, None, done));
            assert!(docked::<T>(0.0, -0.99, None, done), "|heading error|");
            assert!(!docked::<T>(0.0, -1.01, None, done));
            assert!(!docked::<T>(0.0101, 1.01, None, done));
            // Other tolerances: 5 cm and 0.2 deg.
            let t = Some((0.05, 0.2));
            assert!(docked::<T>(0.0499, 0.199, t, done));
            assert!(!docked::<T>(0.0501, 0.0, t, done));
            assert!(!docked::<T>(0.0, 0.201, t, done));
            // A run stopped once settled is judged alike; a diverged one never docks.
            assert!(docked::<T>(0.0099, 0.99, None, Termination::Settled));
            assert!(!docked::<T>(0.0, 0.0, None, Termination::NonFinite));
            assert!(!docked::<T>(0.0, 0.0, None, Termination::LeftBox));
        }
        check::<f32>();
        check::<f64>();
        // The paper's law, judged on the distance alone for `converged`, still needs the
        // heading to dock: 0.001 m and 3 deg is converged, not docked.
        let state = State::at_rest(Pose2::new(0.001, 0.0, 3f64.to_radians()));
        let o = Metrics::<f64>::default().judging_heading(false).finish(
            60.0,
            &state,
            Pose2::default(),
            Termination::Completed,
        );
        assert_eq!((o.status(), o.docked()), (Status::Converged, false));
    }
}
