//! When a run may stop early: the settle rule of `[sim] stop_when_settled`.
//!
//! A run is settled at time t when, for the whole of the last [`SETTLE_WINDOW_S`]:
//!
//! 1. the law holds ([`crate::Law::holding`]): inside its hold its memories stop and its
//!    demand stays the same (paper laws: measured distance below `hold_radius`; polar
//!    laws: inside `goal_radius`). A law that is still integrating may yet move the robot;
//! 2. the true distance from C to the goal is below the arrival radius
//!    ([`crate::ARRIVAL_RADIUS_M`], 1 cm), so the run already counts as converged;
//! 3. the robot is at rest: |v| < [`SETTLE_SPEED_M_S`] and |omega| < [`SETTLE_TURN_RAD_S`];
//!
//! and at t, the robot cannot still move far before t_end, at its present speeds or by
//! what the wheel servos' integrators have yet to do (with `servo_ki` > 0 on a
//! slope a held robot still turned slowly while its integrators built up the holding
//! torque, and the stopped run's heading was off by up to 0.17 deg):
//!
//! ```text
//! e_r, e_l  = phi_ref - phi of each servo with Ki > 0 (0 without an integrator), rad
//! ds_I      = r |e_r + e_l| / 2,  dtheta_I = r |e_r - e_l| / (2 R)   (the plant's r, R)
//! position: dl + |v| (t_end - t) + ds_I           < 1 cm
//! heading:  |omega| (t_end - t) + dtheta_I        < SETTLE_HEADING_RAD (1e-4 rad)
//! ```
//!
//! An integrating servo brings its wheel onto its reference (the reference stands still in
//! the hold), so e is what the wheel still has to turn ([`crate::controller::WheelServo::integrator_travel`]);
//! the outer laws' integrators stop in the hold (condition 1). The sensor must be noise-free and the goal
//! fixed ([`crate::Sensor::deterministic`], [`crate::Reference::fixed`]), else the rule
//! never fires: noise keeps a held law's input moving.
//!
//! So an `unsettled` run (never within 1 cm, or not at rest there) is never stopped, and
//! one that is stopped would have stayed within 1 cm: its status and time to 1 cm are
//! those of the full-length run; its final pose differs by what the robot would still
//! have crept (tested on every start of `examples/compare.toml`).

use crate::RobotParams;
use crate::lane::{Lane, Mask};
use crate::math::{Pose2, Wheels};
use crate::outcome::ARRIVAL_RADIUS_M;
use crate::state::State;

/// Speed of C below which the robot counts as at rest, m/s.
pub const SETTLE_SPEED_M_S: f64 = 1e-4;
/// Turn rate below which the robot counts as at rest, rad/s.
pub const SETTLE_TURN_RAD_S: f64 = 1e-3;
/// How long the conditions must hold before the run stops, s.
pub const SETTLE_WINDOW_S: f64 = 1.0;
/// How far the heading may still turn before t_end, at the present turn rate and by the
/// servos' integrators, for the run to stop, rad (0.0057 deg).
pub const SETTLE_HEADING_RAD: f64 = 1e-4;

/// Watches a run for the settle rule (module docs), one plant step at a time; per lane
/// for several runs side by side ([`crate::lane`]).
#[derive(Clone, Copy, Debug)]
pub struct SettleWatch<T: Lane> {
    /// t_end, s.
    t_end: T::Scalar,
    /// The plant's wheel radius r and half track R, m: wheel travel to body travel.
    wheel_radius: T::Scalar,
    half_track: T::Scalar,
    /// Conditions 1 to 3 have held without a break since `since` (s), where `watching`.
    since: T,
    watching: T::Mask,
}

impl<T: Lane> SettleWatch<T> {
    /// A watch for a run that ends at `t_end` (s) on the plant `robot` (its r and R).
    pub fn new(t_end: T::Scalar, robot: &RobotParams<T::Scalar>) -> Self {
        Self {
            t_end,
            wheel_radius: robot.wheel_radius,
            half_track: robot.half_track,
            since: T::default(),
            watching: T::Mask::splat(false),
        }
    }

    /// Sees the true `state` at `t` (s) against `goal`, with the law `holding` or not and
    /// the wheel angles (rad) the servos' integrators have yet to turn
    /// ([`crate::Controller::integrator_travel`]); true when the run is settled and may
    /// stop here.
    #[inline(always)]
    pub fn settled(
        &mut self,
        t: T,
        state: &State<T>,
        goal: Pose2<T>,
        holding: T::Mask,
        integrator_travel: Wheels<T>,
    ) -> T::Mask {
        let r = T::lit(ARRIVAL_RADIUS_M);
        let dx = goal.x - state.x;
        let dy = goal.y - state.y;
        let dl_sq = dx * dx + dy * dy;
        let at_rest = state.v.abs().lt(T::lit(SETTLE_SPEED_M_S)) & state.omega.abs().lt(T::lit(SETTLE_TURN_RAD_S));
        let held = holding & at_rest & dl_sq.lt(r * r);
        if !held.any() {
            self.watching = held;
            return held;
        }
        self.since = T::select(held & !self.watching, t, self.since);
        self.watching = held;
        let left = T::splat(self.t_end) - t;
        let half_r = T::splat(self.wheel_radius) * T::lit(0.5);
        let e = integrator_travel;
        let ds = (half_r * (e.right + e.left)).abs();
        let dtheta = (half_r * (e.right - e.left) / T::splat(self.half_track)).abs();
        let creep = dl_sq.sqrt() + state.v.abs() * left + ds;
        let turn = state.omega.abs() * left + dtheta;
        held & T::lit(SETTLE_WINDOW_S).le(t - self.since) & creep.lt(r) & turn.lt(T::lit(SETTLE_HEADING_RAD))
    }

    /// Forgets the runs in `lanes`, as at the start of a run.
    pub fn reset_lanes(&mut self, lanes: T::Mask) {
        self.watching = self.watching & !lanes;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(x: f64, v: f64, omega: f64) -> State<f64> {
        State { x, v, omega, ..State::at_rest(Pose2::new(x, 0.0, 0.0)) }
    }

    /// Fires only after the window, with every condition held throughout.
    #[test]
    fn settles_after_a_window_at_rest_near_the_goal_while_holding() {
        let goal = Pose2::default();
        let mut w = SettleWatch::new(100.0, &RobotParams::paper());
        let s = state(0.002, 0.0, 0.0);
        assert!(!w.settled(10.0, &s, goal, true, Wheels::default()));
        assert!(!w.settled(10.5, &s, goal, true, Wheels::default()));
        assert!(w.settled(11.0, &s, goal, true, Wheels::default()));
        // Any break restarts the window: not holding, moving, turning, outside 1 cm.
        for (s, holding) in [
            (s, false),
            (state(0.002, 2e-4, 0.0), true),
            (state(0.002, 0.0, 2e-3), true),
            (state(0.011, 0.0, 0.0), true),
        ] {
            let mut w = SettleWatch::new(100.0, &RobotParams::paper());
            assert!(!w.settled(10.0, &state(0.002, 0.0, 0.0), goal, true, Wheels::default()));
            assert!(!w.settled(10.5, &s, goal, holding, Wheels::default()));
            assert!(!w.settled(11.0, &state(0.002, 0.0, 0.0), goal, true, Wheels::default()));
        }
    }

    /// A creep below the rest speed that would still leave the 1 cm disc before t_end
    /// (5 mm + 5e-5 m/s * 100 s = 1 cm) does not stop the run; a slower one does.
    #[test]
    fn a_creep_that_could_leave_the_arrival_disc_is_not_settled() {
        let goal = Pose2::default();
        let mut w = SettleWatch::new(111.0, &RobotParams::paper());
        let creep = state(0.005, 5e-5, 0.0);
        assert!(!w.settled(10.0, &creep, goal, true, Wheels::default()));
        assert!(!w.settled(11.0, &creep, goal, true, Wheels::default()));
        let slow = state(0.005, 4e-5, 0.0);
        assert!(w.settled(12.0, &slow, goal, true, Wheels::default()));
    }

    /// Issue 24: a turn the servos' integrators have yet to make, or a slow turn at the
    /// present rate, keeps the run going. Paper robot: r = 0.1 m, R = 0.2 m, so wheel
    /// errors (+e, -e) turn the heading by r e / R = 0.5 e rad.
    #[test]
    fn a_turn_still_to_come_is_not_settled() {
        let goal = Pose2::default();
        let at_rest = state(0.002, 0.0, 0.0);
        // 0.5 * 3e-4 = 1.5e-4 rad still to turn: not settled; 0.5 * 1.5e-4 = 0.75e-4: settled.
        for (e, settles) in [(3e-4, false), (1.5e-4, true)] {
            let mut w = SettleWatch::new(100.0, &RobotParams::paper());
            let travel = Wheels::new(e, -e);
            assert!(!w.settled(10.0, &at_rest, goal, true, travel));
            assert_eq!(w.settled(11.0, &at_rest, goal, true, travel), settles, "e = {e}");
        }
        // 5e-7 rad/s below the rest rate 1e-3, for the 89 s left: 4.45e-5 rad; 2e-6: 1.8e-4.
        for (omega, settles) in [(5e-7, true), (2e-6, false)] {
            let mut w = SettleWatch::new(100.0, &RobotParams::paper());
            let s = state(0.002, 0.0, omega);
            assert!(!w.settled(10.0, &s, goal, true, Wheels::default()));
            assert_eq!(w.settled(11.0, &s, goal, true, Wheels::default()), settles, "omega = {omega}");
        }
    }
}
