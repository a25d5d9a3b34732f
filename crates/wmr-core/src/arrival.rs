//! Early arrival: a shorter stop test than [`crate::settle`]'s 1 s window, for runs
//! that ask for it (`[sim] early_arrival`, with `stop_when_settled`; the million-start
//! region maps).
//!
//! A run has arrived early at time t when, at every plant step of the last
//! [`EARLY_WINDOW_S`]:
//!
//! 1. the law holds ([`crate::Law::holding`]): its memories are still and its demand
//!    stays the same while the measured pose stays in the hold;
//! 2. the true distance from C to the goal is below the arrival radius
//!    ([`crate::ARRIVAL_RADIUS_M`], 1 cm);
//! 3. the robot is at rest by [`crate::settle`]'s thresholds: |v| <
//!    [`SETTLE_SPEED_M_S`] and |omega| < [`SETTLE_TURN_RAD_S`];
//! 4. and, what the settle rule's long window stands in for, the motion is dying out:
//!    neither |v| nor |omega| grew from one plant step to the next;
//!
//! and at t a creep at the present speed could not carry C out of the arrival disc
//! before t_end: dl + |v| (t_end - t) < 1 cm (the settle rule's last condition).
//!
//! Why it is safe: under a held law the demand is fixed, so nothing feeds the plant but
//! the wheel servos pulling each wheel to a fixed angle, a damped mechanism whose speeds
//! decay (with the default servo, overdamped: the slowest mode decays at about
//! 13.5 1/s, so [`EARLY_WINDOW_S`] is more than one of its time constants, and a speed
//! that has fallen at every step for that long is in that mode). Speeds that fall
//! cannot carry C further than the creep bound, which already holds at the present
//! speed for the whole rest of the run. So the run's status and time to 1 cm are those
//! of the full-length run; its final pose differs by what the robot would still have
//! crept, below 1 cm by the creep bound. `crates/wmr-scenario/tests/arrival.rs` checks
//! both against full-length runs.
//!
//! It is a predicate of its own, beside the settle rule (either ends a run as
//! [`crate::Termination::Settled`]): the two change independently.

use crate::lane::{Lane, Mask};
use crate::math::Pose2;
use crate::outcome::ARRIVAL_RADIUS_M;
use crate::settle::{SETTLE_SPEED_M_S, SETTLE_TURN_RAD_S};
use crate::state::State;

/// How long conditions 1 to 4 must hold before a run stops early, s.
pub const EARLY_WINDOW_S: f64 = 0.1;

/// Watches a run for early arrival (module docs), one plant step at a time; per lane for
/// several runs side by side ([`crate::lane`]).
#[derive(Clone, Copy, Debug)]
pub struct ArrivalWatch<T: Lane> {
    /// t_end, s.
    t_end: T::Scalar,
    /// Conditions 1 to 4 have held without a break since `since` (s), where `watching`.
    since: T,
    watching: T::Mask,
    /// |v| (m/s) and |omega| (rad/s) at the previous plant step; infinite before a run's
    /// first step.
    last_speed: T,
    last_turn: T,
}

impl<T: Lane> ArrivalWatch<T> {
    /// A watch for a run that ends at `t_end` (s).
    pub fn new(t_end: T::Scalar) -> Self {
        let inf = T::lit(f64::INFINITY);
        Self { t_end, since: T::default(), watching: T::Mask::splat(false), last_speed: inf, last_turn: inf }
    }

    /// Sees the true `state` at `t` (s) against `goal`, with the law `holding` or not;
    /// true when the run has arrived early and may stop here.
    #[inline(always)]
    pub fn arrived(&mut self, t: T, state: &State<T>, goal: Pose2<T>, holding: T::Mask) -> T::Mask {
        let r = T::lit(ARRIVAL_RADIUS_M);
        let (speed, turn) = (state.v.abs(), state.omega.abs());
        let dying = speed.le(self.last_speed) & turn.le(self.last_turn);
        self.last_speed = speed;
        self.last_turn = turn;
        let dx = goal.x - state.x;
        let dy = goal.y - state.y;
        let dl_sq = dx * dx + dy * dy;
        let at_rest = speed.lt(T::lit(SETTLE_SPEED_M_S)) & turn.lt(T::lit(SETTLE_TURN_RAD_S));
        let held = holding & at_rest & dying & dl_sq.lt(r * r);
        if !held.any() {
            self.watching = held;
            return held;
        }
        self.since = T::select(held & !self.watching, t, self.since);
        self.watching = held;
        let creep = dl_sq.sqrt() + speed * (T::splat(self.t_end) - t);
        held & T::lit(EARLY_WINDOW_S).le(t - self.since) & creep.lt(r)
    }

    /// Forgets the runs in `lanes`, as at the start of a run.
    pub fn reset_lanes(&mut self, lanes: T::Mask) {
        self.watching = self.watching & !lanes;
        let inf = T::lit(f64::INFINITY);
        self.last_speed = T::select(lanes, inf, self.last_speed);
        self.last_turn = T::select(lanes, inf, self.last_turn);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(x: f64, v: f64, omega: f64) -> State<f64> {
        State { x, v, omega, ..State::at_rest(Pose2::new(x, 0.0, 0.0)) }
    }

    /// Fires after 0.1 s of falling speeds, not before; a speed that grows restarts it.
    #[test]
    fn arrives_after_a_short_window_of_falling_speeds() {
        let goal = Pose2::default();
        let mut w = ArrivalWatch::new(100.0);
        let mut t = 10.0;
        let mut v = 5e-5;
        let mut fired = None;
        for _ in 0..200 {
            if w.arrived(t, &state(0.002, v, 0.0), goal, true) {
                fired = Some(t);
                break;
            }
            t += 0.001;
            v *= 0.99;
        }
        let fired = fired.expect("fires");
        assert!((fired - 10.1).abs() < 1.5e-3, "{fired}");
        // A growing speed, a law not holding, outside 1 cm or a creep that could leave
        // the disc: no arrival within the window.
        for (growth, holding, x, t_end) in [
            (1.01, true, 0.002, 100.0),
            (0.99, false, 0.002, 100.0),
            (0.99, true, 0.011, 100.0),
            (0.99, true, 0.008, 1e4),
        ] {
            let mut w = ArrivalWatch::new(t_end);
            let (mut t, mut v) = (10.0, 5e-5);
            for _ in 0..200 {
                assert!(!w.arrived(t, &state(x, v, 0.0), goal, holding), "{growth} {holding} {x} {t_end}");
                t += 0.001;
                v *= growth;
            }
        }
    }
}
