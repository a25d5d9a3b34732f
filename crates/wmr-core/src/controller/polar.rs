//! Astolfi's polar-coordinates point-stabilization law (rho, alpha, beta) -> (v, omega),
//! with backward driving when the goal lies behind.
//!
//! Source: A. Astolfi, "Exponential stabilization of a wheeled mobile robot via
//! discontinuous control", J. Dyn. Sys. Meas. Control 121 (1999); in the form of
//! Siegwart, Nourbakhsh, Scaramuzza, "Introduction to Autonomous Mobile Robots", 2nd ed.,
//! section 3.6.2.4 (also P. Corke, "Robotics, Vision and Control", drive to a pose, and
//! PythonRobotics `move_to_pose`). Coordinates (rho in m, alpha and beta in rad) as in
//! [`super::polar_frame`]; in the driving frame the kinematics are
//!
//! ```text
//! rho'   = -v cos(alpha)
//! alpha' =  v sin(alpha) / rho - omega
//! beta'  = -v sin(alpha) / rho
//! ```
//!
//! and the law is
//!
//! ```text
//! v     = s k_rho rho                         m/s   (s = +1 forward, -1 backward)
//! omega = k_alpha alpha + k_beta beta         rad/s
//! ```
//!
//! with gains in 1/s. Linearized about the goal the loop is
//! (s + k_rho)(s^2 + (k_alpha - k_rho) s - k_rho k_beta), stable for
//!
//! ```text
//! k_rho > 0,  k_beta < 0,  k_alpha - k_rho > 0,
//! ```
//!
//! and Siegwart's strong-stability condition
//!
//! ```text
//! k_alpha + 5/3 k_beta - 2/pi k_rho > 0
//! ```
//!
//! guarantees that alpha never leaves I1 = (-pi/2, pi/2] once in it, so the robot never
//! reverses its direction of motion on the way. All four are checked at construction
//! (errors name `k_rho`, `k_beta` or `k_alpha`).
//! PythonRobotics' `move_to_pose` negates v when the goal is behind but keeps alpha and
//! beta of the forward frame, so alpha stays near +-pi, outside the region the stability
//! argument covers. Here the backward case redefines the polar coordinates in the
//! reversed frame ([`super::polar_frame`]); the direction is decided at the first tick
//! and later switched only with hysteresis (`reverse_hysteresis`).
//!
//! Near the goal: alpha + beta = theta_d - theta, so the heading converges with alpha and
//! beta, at the rate of the slower angular mode (the smaller root of
//! s^2 + (k_alpha - k_rho) s - k_rho k_beta). Gains that satisfy the strong condition
//! tend to make it slower than k_rho (with the defaults it is 0.27 1/s = 0.54 k_rho), so
//! the heading settles more slowly than the distance and a robot stopped at 1 mm keeps a
//! heading error of a few degrees: over the 1,000 starts of `examples/compare.toml`
//! (`wmr-cli sweep examples/compare.toml`), median 2.97 deg, 10.8 % of the runs above
//! 5 deg, worst 18.07 deg. Use [`super::LyapunovLaw`] when the heading matters. Within `goal_radius` of the
//! goal the law stops (v = omega = 0, the wheels hold their angles) until the robot is
//! pushed out to twice that distance.
//!
//! The twist goes to the wheels through the wheel stage ([`super::WheelStage`]): wheel
//! speed references by the inverse of (1), the curvature-keeping `wheel_speed_max`
//! limit, and the wheel position servos tracking the integrated references.
//!
//! Logged errors ([`super::ControlErrors`]): dl = rho; e_theta = wrap(theta_d - theta), the
//! heading error the law drives to zero (= alpha + beta); e_s = (x_d - x) cos(theta) +
//! (y_d - y) sin(theta), the signed distance to the goal along the heading.

use super::polar_frame::{PolarCoordinateLaw, PolarCoords, PolarGains, Steering};
use crate::error::{ParamError, check};
use crate::lane::Lane;
use crate::math::Twist2;
use crate::{Real, RobotParams};

crate::params! {
    words;
    /// `[controller] kind = "polar"` parameters.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    #[repr(C)]
    pub struct PolarParams<T> {
        /// k_rho: forward speed per metre of distance.
        pub k_rho: T [unit = "1/s", rule = "> 0"],
        /// k_alpha: yaw rate per rad of alpha.
        pub k_alpha: T [unit = "1/s", rule = "> k_rho, and k_alpha + 5/3 k_beta - 2/pi k_rho > 0"],
        /// k_beta: yaw rate per rad of beta.
        pub k_beta: T [unit = "1/s", rule = "< 0"],
        /// Drive backwards when the goal is behind (false: always forward).
        pub reverse: bool [unit = "", rule = "true or false"],
        /// Overshoot of |alpha| past pi/2 before a later direction switch.
        pub reverse_hysteresis: T [unit = "rad", rule = "in [0, pi/2)"],
        /// Within this distance of the goal the law stops; it resumes beyond twice that.
        pub goal_radius: T [unit = "m", rule = ">= 0"],
    }
}

impl<T: Real> Default for PolarParams<T> {
    /// k_rho = 0.5, k_alpha = 3, k_beta = -1.2 (strong-stability margin 0.68 1/s; slow
    /// angular mode 0.27 1/s), reverse on with pi/6 hysteresis, goal_radius 1 mm.
    fn default() -> Self {
        Self {
            k_rho: T::lit(0.5),
            k_alpha: T::lit(3.0),
            k_beta: T::lit(-1.2),
            reverse: true,
            reverse_hysteresis: T::lit(core::f64::consts::FRAC_PI_6),
            goal_radius: T::lit(1e-3),
        }
    }
}

impl<T: Real> super::law::LawSpec<T> for PolarParams<T> {
    type Law<L: Lane<Scalar = T>> = PolarLaw<L>;

    fn build<L: Lane<Scalar = T>>(&self, _model: &RobotParams<T>, _control_dt: T) -> Result<PolarLaw<L>, ParamError> {
        PolarLaw::for_lanes(*self)
    }
}

impl<T: Real> PolarGains<T> for PolarParams<T> {
    const REACHES_HEADING: bool = false;

    fn check_gains(&self) -> Result<(), ParamError> {
        let k_rho = check::positive("k_rho", self.k_rho)?;
        let k_alpha = check::finite("k_alpha", self.k_alpha)?;
        let k_beta = check::finite("k_beta", self.k_beta)?;
        if k_beta >= T::zero() {
            return Err(check::out_of_range("k_beta", "must be < 0", k_beta));
        }
        if k_alpha - k_rho <= T::zero() {
            return Err(check::out_of_range("k_alpha", "must be > k_rho", k_alpha));
        }
        let strong = k_alpha + T::lit(5.0 / 3.0) * k_beta - T::FRAC_2_PI() * k_rho;
        if strong <= T::zero() {
            return Err(check::out_of_range(
                "k_alpha",
                "must satisfy k_alpha + 5/3 k_beta - 2/pi k_rho > 0 (strong stability)",
                k_alpha,
            ));
        }
        Ok(())
    }

    fn steering(&self) -> Steering<T> {
        Steering { reverse: self.reverse, reverse_hysteresis: self.reverse_hysteresis, goal_radius: self.goal_radius }
    }

    /// v = s k_rho rho, omega = k_alpha alpha + k_beta beta (module docs).
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    fn twist<L: Lane<Scalar = T>>(&self, sign: L, c: &PolarCoords<L>) -> Twist2<L> {
        let v = sign * L::splat(self.k_rho) * c.rho;
        let omega = L::splat(self.k_alpha) * c.alpha + L::splat(self.k_beta) * c.beta;
        Twist2 { v, omega }
    }
}

/// Astolfi's polar law. Implements [`super::Law`] with [`super::WheelDemand::Twist`].
pub type PolarLaw<T> = PolarCoordinateLaw<T, PolarParams<<T as Lane>::Scalar>>;
