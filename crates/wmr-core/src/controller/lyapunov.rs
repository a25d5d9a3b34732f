//! Aicardi, Casalino, Bicchi and Balestrino's Lyapunov law in polar coordinates: reaches
//! the goal position and the goal heading exactly.
//!
//! Source: M. Aicardi, G. Casalino, A. Bicchi, A. Balestrino, "Closed loop steering of
//! unicycle-like vehicles via Lyapunov techniques", IEEE Robotics & Automation Magazine
//! 2(1), 1995, pp. 27-35. Coordinates as in [`super::polar_frame`]: e = rho (m), alpha (rad),
//! and the goal-frame angle of the vector from C to the goal, theta_A = -beta (rad). In the
//! driving frame the kinematics are
//!
//! ```text
//! e'       = -u cos(alpha)
//! alpha'   = -omega + u sin(alpha) / e
//! theta_A' =  u sin(alpha) / e
//! ```
//!
//! With the Lyapunov function V = lambda e^2 / 2 + (alpha^2 + h theta_A^2) / 2 the law
//!
//! ```text
//! u     = gamma cos(alpha) e                                                m/s
//! omega = k alpha + gamma (cos(alpha) sin(alpha) / alpha) (alpha + h theta_A)   rad/s
//! ```
//!
//! gives V' = -lambda gamma cos^2(alpha) e^2 - k alpha^2 <= 0 for every lambda > 0, so
//! W = alpha^2 + h theta_A^2 never increases (the tests check this on the dynamic robot)
//! and e, alpha, theta_A -> 0: position and heading (theta_d - theta = alpha - theta_A)
//! both converge. Gain conditions, checked at construction: gamma > 0 (1/s), k > 0 (1/s),
//! h > 0 (dimensionless); errors name `gamma`, `k`, `h`.
//!
//! Choosing the gains: linearized about the goal, e decays at rate gamma and the angular
//! subsystem (alpha' = -k alpha - gamma h theta_A, theta_A' = gamma alpha, which does not
//! depend on e) with the roots of s^2 + k s + gamma^2 h. When both roots are faster than
//! gamma the heading error shrinks faster than the distance, so it is essentially zero
//! by the time the robot stops at `goal_radius`. The defaults (gamma = 0.5, k = 3, h = 9)
//! put a double root at k/2 = 1.5 1/s, three times gamma. With gamma = 0.5, k = 3, h = 4.5
//! the slow root is 0.44 1/s, below gamma: the heading then lags the distance and a
//! robot stopped at 1 mm keeps some heading error (over the 1,000 starts of
//! `examples/compare.toml` with `controllers = [{ kind = "lyapunov", h = 4.5 }]`: median
//! 0.48 deg, worst 8.27 deg; with the defaults, median 0.00 deg, worst 0.05 deg).
//!
//! u changes sign with cos(alpha), so the law backs up by itself, but alpha is wrapped
//! into (-pi, pi] and omega jumps at alpha = +-pi. As for [`super::PolarLaw`] the
//! driving direction is therefore chosen at the first tick (backwards when the goal is
//! behind, with the coordinates redefined in the reversed frame) and later switched only
//! with hysteresis; starting with |alpha| <= pi/2 also keeps |alpha| <= sqrt(W(0)) small.
//! sin(alpha)/alpha is taken as 1 at alpha = 0. Within `goal_radius` of the goal the law
//! stops (v = omega = 0, wheels hold) until the robot is pushed out to twice that distance.
//!
//! Logged errors ([`super::ControlErrors`]): dl = e; e_theta = wrap(theta_d - theta), the heading
//! error the law drives to zero; e_s = (x_d - x) cos(theta) + (y_d - y) sin(theta), the
//! signed distance to the goal along the heading.

use super::polar_frame::{Direction, PolarCoordinateLaw, PolarCoords, PolarGains, Steering};
use crate::error::{ParamError, check};
use crate::lane::Lane;
use crate::math::{Pose2, Twist2};
use crate::{Real, RobotParams};

crate::params! {
    words;
    /// `[controller] kind = "lyapunov"` parameters.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    #[repr(C)]
    pub struct LyapunovParams<T> {
        /// gamma: forward speed per metre of distance, times cos(alpha).
        pub gamma: T [unit = "1/s", rule = "> 0"],
        /// k: yaw rate per rad of alpha.
        pub k: T [unit = "1/s", rule = "> 0"],
        /// h: weight of theta_A against alpha in V.
        pub h: T [unit = "", rule = "> 0"],
        /// Drive backwards when the goal is behind (false: always start forward).
        pub reverse: bool [unit = "", rule = "true or false"],
        /// Overshoot of |alpha| past pi/2 before a later direction switch.
        pub reverse_hysteresis: T [unit = "rad", rule = "in [0, pi/2)"],
        /// Within this distance of the goal the law stops.
        pub goal_radius: T [unit = "m", rule = ">= 0"],
    }
}

impl<T: Real> Default for LyapunovParams<T> {
    /// gamma = 0.5, k = 3, h = 9 (module docs), reverse on with pi/6 hysteresis,
    /// goal_radius 1 mm.
    fn default() -> Self {
        Self {
            gamma: T::lit(0.5),
            k: T::lit(3.0),
            h: T::lit(9.0),
            reverse: true,
            reverse_hysteresis: T::lit(core::f64::consts::FRAC_PI_6),
            goal_radius: T::lit(1e-3),
        }
    }
}

impl<T: Real> super::law::LawSpec<T> for LyapunovParams<T> {
    type Law<L: Lane<Scalar = T>> = LyapunovLaw<L>;

    fn build<L: Lane<Scalar = T>>(
        &self,
        _model: &RobotParams<T>,
        _control_dt: T,
    ) -> Result<LyapunovLaw<L>, ParamError> {
        LyapunovLaw::for_lanes(*self)
    }
}

impl<T: Real> PolarGains<T> for LyapunovParams<T> {
    const REACHES_HEADING: bool = true;

    fn check_gains(&self) -> Result<(), ParamError> {
        check::positive("gamma", self.gamma)?;
        check::positive("k", self.k)?;
        check::positive("h", self.h)?;
        Ok(())
    }

    fn steering(&self) -> Steering<T> {
        Steering { reverse: self.reverse, reverse_hysteresis: self.reverse_hysteresis, goal_radius: self.goal_radius }
    }

    /// u = gamma cos(alpha) e, omega = k alpha + gamma (cos(alpha) sin(alpha) / alpha)
    /// (alpha + h theta_A) (module docs), v = s u.
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    fn twist<L: Lane<Scalar = T>>(&self, sign: L, c: &PolarCoords<L>) -> Twist2<L> {
        let (e, alpha, theta_a) = (c.rho, c.alpha, -c.beta);
        let (sin_a, cos_a) = alpha.sin_cos();
        let sinc = L::select(alpha.abs().lt(L::splat(T::epsilon())), L::lit(1.0), sin_a / alpha);
        let gamma = L::splat(self.gamma);
        let u = gamma * cos_a * e;
        let omega = L::splat(self.k) * alpha + gamma * cos_a * sinc * (alpha + L::splat(self.h) * theta_a);
        Twist2 { v: sign * u, omega }
    }
}

/// Aicardi et al.'s law. Implements [`super::Law`] with [`super::WheelDemand::Twist`].
pub type LyapunovLaw<T> = PolarCoordinateLaw<T, LyapunovParams<<T as Lane>::Scalar>>;

impl<T: Real> LyapunovLaw<T> {
    /// W = alpha^2 + h theta_A^2 (rad^2) of `pose` towards `goal` in driving direction
    /// `dir`: the angular part of the law's Lyapunov function, non-increasing along the
    /// kinematic closed loop.
    pub fn angular_lyapunov(&self, pose: Pose2<T>, goal: Pose2<T>, dir: Direction) -> T {
        let c = PolarCoords::new(pose, goal, dir);
        c.alpha * c.alpha + self.params().h * c.beta * c.beta
    }
}
