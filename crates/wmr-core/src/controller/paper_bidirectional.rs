//! The paper's law, repaired (`kind = "paper_bidirectional"`): the same errors generator,
//! two PI loops, inverse of (20) and wheel position servos as [`super::PaperLaw`], with a
//! position error that never feeds back positively, and gains for which the heading
//! settles before the position. The derivation is in `docs/model.md` ("The repaired
//! law"); in short:
//!
//! ```text
//! dl      = hypot(x_d - x, y_d - y)                                   (16)
//! alpha   = atan2(y_d - y, x_d - x)                                   (17)
//! theta_R = 2 alpha - theta_d,  e_theta = wrap(theta_R - theta)       (21), as the paper
//! e_s     = (x_d - x) cos(theta) + (y_d - y) sin(theta) = dl cos(alpha - theta)
//! u_theta = Kp_t e_theta + Ki_t int e_theta,  u_s = Kp_s e_s + Ki_s int e_s   (22), (24)
//! phi_r_ref = (u_s + R u_theta) / r,  phi_l_ref = (u_s - R u_theta) / r       (20)^-1
//! ```
//!
//! **The position error.** The paper's (18) measures the distance dl along the heading
//! towards the moving false target R, dl cos(theta_R - theta). With the heading on
//! theta_R, driving forward by ds changes it by -cos(alpha - theta_d) ds: positive
//! feedback whenever the goal lies behind the robot's goal-heading line (cos(alpha -
//! theta_d) < 0), and those runs drive away. Here e_s is the goal's own coordinate along
//! the heading axis; driving by ds along the heading changes it by exactly -ds, whatever
//! the pose: the position loop always sees negative feedback of gain one. The sign of e_s
//! chooses the direction, so the robot backs up when the goal lies behind its axis (the
//! paper's Fig. 6), and with the heading on theta_R it follows, forwards or backwards,
//! the circle through C that is tangent to theta_d at the goal, which arrives with the
//! goal heading.
//!
//! **The gains.** With ideal wheel servos (s = u_s, theta = u_theta up to constants) the
//! position loop is v = k_s e_s with k_s = Ki_s / (1 + Kp_s). Linearized about the goal
//! (robot behind it on its circle, small angles), the lateral angle q = alpha - theta_d and
//! the heading theta - theta_d obey
//!
//! ```text
//! q'     = k_s (q - theta)
//! theta' = (2 Kp_t k_s (q - theta) + Ki_t (2 q - theta)) / (1 + Kp_t)
//! ```
//!
//! whose decay rates mu solve mu^2 - T mu + D = 0 with
//! T = (2 Kp_t k_s + Ki_t) / (1 + Kp_t) - k_s and D = k_s Ki_t / (1 + Kp_t). The approach
//! is stable when Ki_t > 0 and T > 0 (checked at construction); the heading settles no
//! later than the distance when both rates exceed k_s ([`PaperBidirectionalParams::near_goal_rates`]).
//! The paper's gains (Kp_t 2, Ki_t 0.1, Kp_s 1, Ki_s 0.25) give k_s = 0.125 1/s and a
//! heading rate of 0.0375 1/s, 3.3 times slower than the distance: the robot arrives
//! before it has turned, which is the paper's residual heading error. The defaults here,
//! Ki_t = 1 1/s and Ki_s = 0.25 1/s (the paper's), give k_s = 0.25 1/s and a heading rate
//! of 0.375 1/s (1.5 k_s).
//!
//! **Why no proportional terms by default.** The servos make the plant of each outer
//! loop static (s follows u_s, theta follows u_theta), so the integral term alone is the
//! velocity command (v = Ki_s e_s, omega = Ki_t e_theta); a proportional term adds a
//! step of the wheel references by Kp times every jump of its error. e_s is a projection
//! on the heading axis, so it swings by up to 2 dl while the robot turns in place, and
//! Kp_s e_s then makes the robot lunge back and forth as it turns; the paper's Kp's also
//! step the references at the first tick, which saturates the drives (Fig. 8). Both
//! gains remain keys (`kp_theta`, `kp_s`); `docs/model.md` gives the measured effect.
//!
//! Inside `hold_radius` the law holds as [`super::PaperLaw`] does; the default is
//! [`HoldMode::Freeze`] (bumpless), and [`HoldMode::Auto`] means freeze here.
//!
//! Logged errors ([`super::ControlErrors`]): e_s the position error above, e_theta =
//! wrap(theta_R - theta) as the paper's, dl the distance.

use super::law::{ControlErrors, Law, LawOutput, WheelDemand};
use super::paper::{Hold, HoldMode, OuterLoops, PiGains, outer_law};
use crate::error::{ParamError, check};
use crate::lane::Lane;
use crate::math::{Pose2, Wheels, wrap_angle};
use crate::reference::ReferenceState;
use crate::sensor::Measurement;
use crate::{Real, RobotParams};

crate::params! {
    words;
    /// `[controller] kind = "paper_bidirectional"`: the law's own keys.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    #[repr(C)]
    pub struct PaperBidirectionalParams<T> {
        /// Kp_theta, rad of heading command per rad of error (0: no step when e_theta jumps).
        pub kp_theta: T [unit = "rad/rad", rule = ">= 0"],
        /// Ki_theta; below the bound the approach to the goal is unstable.
        pub ki_theta: T [unit = "1/s", rule = "> 0 and > ki_s (1 - kp_theta) / (1 + kp_s)"],
        /// Kp_s, m of path command per m of error (0: no lunge when e_s swings as the robot turns).
        pub kp_s: T [unit = "m/m", rule = ">= 0"],
        /// Ki_s.
        pub ki_s: T [unit = "1/s", rule = "> 0"],
        /// Within this distance of the goal alpha keeps its last value.
        pub goal_radius: T [unit = "m", rule = ">= 0"],
        /// Within this distance of the goal the outer loops hold (0: off).
        pub hold_radius: T [unit = "m", rule = ">= 0"],
        /// The hold: freeze (bumpless; auto is the same) or zero_errors.
        pub hold: HoldMode [unit = "", rule = "\"freeze\", \"auto\" or \"zero_errors\""],
    }
}

impl<T: Real> Default for PaperBidirectionalParams<T> {
    /// Kp_theta 0, Ki_theta 1 1/s, Kp_s 0, Ki_s 0.25 1/s (module docs), goal_radius
    /// 1 mm, hold_radius 5 mm, freeze.
    fn default() -> Self {
        Self {
            kp_theta: T::zero(),
            ki_theta: T::lit(1.0),
            kp_s: T::zero(),
            ki_s: T::lit(0.25),
            goal_radius: T::lit(1e-3),
            hold_radius: T::lit(5e-3),
            hold: HoldMode::Freeze,
        }
    }
}

impl<T: Real> super::law::LawSpec<T> for PaperBidirectionalParams<T> {
    /// It demands wheel angles, not a twist.
    const TWIST_DEMAND: bool = false;

    type Law<L: Lane<Scalar = T>> = PaperBidirectionalLaw<L>;

    fn build<L: Lane<Scalar = T>>(
        &self,
        model: &RobotParams<T>,
        control_dt: T,
    ) -> Result<PaperBidirectionalLaw<L>, ParamError> {
        PaperBidirectionalLaw::for_lanes(*self, model, control_dt)
    }
}

impl<T: Real> PaperBidirectionalParams<T> {
    /// The position loop's rate k_s = Ki_s / (1 + Kp_s) (1/s) and the decay rates (1/s)
    /// of the heading and lateral modes near the goal, linearized with ideal servos
    /// (module docs): `(k_s, slow, fast)`. Complex rates are given by their real part
    /// (both equal); a rate <= 0 is an unstable approach.
    pub fn near_goal_rates(&self) -> (T, T, T) {
        let one = T::one();
        let two = T::lit(2.0);
        let k_s = self.ki_s / (one + self.kp_s);
        let trace = (two * self.kp_theta * k_s + self.ki_theta) / (one + self.kp_theta) - k_s;
        let det = k_s * self.ki_theta / (one + self.kp_theta);
        let disc = trace * trace - T::lit(4.0) * det;
        let half = trace / two;
        if disc < T::zero() {
            (k_s, half, half)
        } else {
            let root = disc.sqrt() / two;
            (k_s, half - root, half + root)
        }
    }

    /// Checks every key; errors name it.
    pub fn validate(&self) -> Result<(), ParamError> {
        let kp_theta = check::non_negative("kp_theta", self.kp_theta)?;
        let kp_s = check::non_negative("kp_s", self.kp_s)?;
        let ki_s = check::positive("ki_s", self.ki_s)?;
        let ki_theta = check::positive("ki_theta", self.ki_theta)?;
        check::non_negative("goal_radius", self.goal_radius)?;
        check::non_negative("hold_radius", self.hold_radius)?;
        let k_s = ki_s / (T::one() + kp_s);
        if ki_theta <= k_s * (T::one() - kp_theta) {
            return Err(check::out_of_range(
                "ki_theta",
                "must exceed ki_s (1 - kp_theta) / (1 + kp_s): otherwise the heading loop cannot keep up with \
                 the position loop near the goal and the approach is unstable",
                ki_theta,
            ));
        }
        Ok(())
    }
}

outer_law! {
    /// The repaired paper law. Implements [`Law`] with [`WheelDemand::Angles`].
    pub struct PaperBidirectionalLaw(PaperBidirectionalParams), anti_windup(_p) => true, reaches_heading true;
}

impl<T: Lane> PaperBidirectionalLaw<T> {
    /// The law itself: errors and wheel angle references (rad) for the measured `pose`
    /// and the `goal` (m, m, rad, world frame), advancing the PI integrators by one
    /// control period.
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub fn references(&mut self, pose: Pose2<T>, goal: Pose2<T>) -> (Wheels<T>, ControlErrors<T>) {
        let p = &self.params;
        let gains = PiGains { kp_s: p.kp_s, ki_s: p.ki_s, kp_theta: p.kp_theta, ki_theta: p.ki_theta };
        let mode = if p.hold == HoldMode::ZeroErrors { HoldMode::ZeroErrors } else { HoldMode::Freeze };
        let hold = Hold { goal_radius: p.goal_radius, radius: p.hold_radius, mode };
        // At the goal from the start, alpha = theta_d makes theta_R the goal heading.
        self.outer.step(
            &gains,
            hold,
            pose,
            goal,
            goal.theta,
            #[cfg_attr(not(target_os = "none"), inline(always))]
            |dx, dy, _, alpha| {
                let (sin, cos) = pose.theta.sin_cos();
                let e_s = dx * cos + dy * sin;
                let e_theta = wrap_angle(alpha + alpha - goal.theta - pose.theta);
                (e_s, e_theta)
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default gains: stable, and the heading settles faster than the distance; the
    /// paper's gains: stable, but the heading is 3.3 times slower than the distance.
    #[test]
    fn near_goal_rates_of_the_defaults_and_of_the_papers_gains() {
        let (k_s, slow, fast) = PaperBidirectionalParams::<f64>::default().near_goal_rates();
        assert_eq!(k_s, 0.25);
        // mu^2 - 0.75 mu + 0.25 = 0: complex, real part 0.375 = 1.5 k_s.
        assert!((slow - 0.375).abs() < 1e-15 && slow == fast, "{k_s} {slow} {fast}");
        let paper = PaperBidirectionalParams::<f64> {
            kp_theta: 2.0,
            ki_theta: 0.1,
            kp_s: 1.0,
            ki_s: 0.25,
            ..Default::default()
        };
        let (k_s, slow, _) = paper.near_goal_rates();
        assert!((k_s - 0.125).abs() < 1e-15 && (slow - 0.0375).abs() < 1e-12, "{k_s} {slow}");
        assert!(paper.validate().is_ok());
    }

    #[test]
    fn gains_that_make_the_approach_unstable_are_refused() {
        let p = PaperBidirectionalParams::<f64> {
            kp_theta: 0.0,
            ki_theta: 0.2,
            kp_s: 0.0,
            ki_s: 0.25,
            ..Default::default()
        };
        assert!(p.near_goal_rates().1 < 0.0);
        assert_eq!(p.validate().unwrap_err().field, "ki_theta");
        let p = PaperBidirectionalParams { ki_s: 0.0, ..PaperBidirectionalParams::<f64>::default() };
        assert_eq!(p.validate().unwrap_err().field, "ki_s");
    }
}
