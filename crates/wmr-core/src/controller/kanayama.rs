//! Kanayama et al.'s trajectory-tracking law: the reference's twist as feedforward plus
//! feedback on the tracking error in the robot's frame.
//!
//! Source: Y. Kanayama, Y. Kimura, F. Miyazaki, T. Noguchi, "A stable tracking control
//! method for an autonomous mobile robot", Proc. IEEE ICRA 1990, pp. 384-389, eq. (6)
//! (the error (2) and the law; the gains of its simulations, Kx = 10 1/s, Ky = 64 1/m^2,
//! Ktheta = 16 1/m, are the defaults here). With the reference pose (x_ref, y_ref,
//! theta_ref) and twist (v_ref, omega_ref) at the tick and the measured pose (x, y, theta):
//!
//! ```text
//! x_e     =  cos(theta) (x_ref - x) + sin(theta) (y_ref - y)       m
//! y_e     = -sin(theta) (x_ref - x) + cos(theta) (y_ref - y)       m
//! theta_e = wrap(theta_ref - theta)                                rad
//! v       = v_ref cos(theta_e) + kx x_e                            m/s
//! omega   = omega_ref + v_ref (ky y_e + sgn(v_ref) ktheta sin(theta_e))   rad/s
//! ```
//!
//! with sgn(v_ref) = -1 for v_ref < 0 and +1 otherwise: the paper's law for v_ref >= 0
//! (the same numbers to the bit: the factor is exactly 1), and for a reference driven
//! backwards (a `line` with `speed < 0`) the heading term's sign turned, as follows.
//! The errors obey (Kanayama et al. 1990, eq. (3))
//!
//! ```text
//! x_e'     =  omega y_e - v + v_ref cos(theta_e)
//! y_e'     = -omega x_e + v_ref sin(theta_e)
//! theta_e' =  omega_ref - omega
//! ```
//!
//! Linearized about zero error at constant v_ref, x_e' = -kx x_e (the along-track loop
//! s + kx) and y_e' = v_ref theta_e, theta_e' = -v_ref ky y_e - |v_ref| ktheta theta_e,
//! so y_e'' = -ky v_ref^2 y_e - ktheta |v_ref| y_e': the lateral loop
//! s^2 + ktheta |v_ref| s + ky v_ref^2, poles -|v_ref| (ktheta +- sqrt(ktheta^2 - 4 ky)) / 2,
//! in the left half-plane whichever way the reference runs; critically damped when
//! ky = ktheta^2 / 4, which the defaults are (64 = 16^2 / 4): a double pole at
//! -ktheta |v_ref| / 2 = -2.4 1/s at 0.3 m/s. Without the sign (the paper's form) the
//! damping term is ktheta v_ref: at v_ref = -0.3 m/s a double pole at +2.4 1/s, and a
//! 2 cm offset grew to 2.2 m in 20 s. The sign keeps Kanayama's Lyapunov function
//! V = (x_e^2 + y_e^2) / 2 + (1 - cos theta_e) / ky decreasing along the full nonlinear
//! errors: V' = -kx x_e^2 - |v_ref| ktheta sin^2(theta_e) / ky <= 0 (the y_e terms
//! cancel as in the paper). The twist goes to the wheels through the wheel stage as the
//! polar law's does ([`super::WheelStage`]).
//!
//! Logged errors ([`super::ControlErrors`]): e_s = x_e, e_theta = theta_e, dl the
//! distance from C to C_ref, all from the measurement.

use super::law::{ControlErrors, Law, LawOutput, WheelDemand};
use crate::error::{ParamError, check};
use crate::lane::Lane;
use crate::math::{Twist2, wrap_angle};
use crate::reference::ReferenceState;
use crate::sensor::Measurement;
use crate::{Real, RobotParams};

crate::params! {
    words;
    /// `[controller] kind = "kanayama"` parameters.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    #[repr(C)]
    pub struct KanayamaParams<T> {
        /// kx: forward speed per metre of along-track error.
        pub kx: T [unit = "1/s", rule = "> 0"],
        /// ky: yaw rate per metre of lateral error, per m/s of v_ref.
        pub ky: T [unit = "1/m^2", rule = "> 0"],
        /// ktheta: yaw rate per unit of sin(heading error), per m/s of |v_ref|.
        pub ktheta: T [unit = "1/m", rule = "> 0"],
    }
}

impl<T: Real> Default for KanayamaParams<T> {
    /// Kanayama et al. 1990's gains: kx = 10 1/s, ky = 64 1/m^2, ktheta = 16 1/m
    /// (critically damped, ky = ktheta^2 / 4).
    fn default() -> Self {
        Self { kx: T::lit(10.0), ky: T::lit(64.0), ktheta: T::lit(16.0) }
    }
}

impl<T: Real> super::law::LawSpec<T> for KanayamaParams<T> {
    type Law<L: Lane<Scalar = T>> = KanayamaLaw<L>;

    fn build<L: Lane<Scalar = T>>(
        &self,
        _model: &RobotParams<T>,
        _control_dt: T,
    ) -> Result<KanayamaLaw<L>, ParamError> {
        KanayamaLaw::for_lanes(*self)
    }
}

impl<T: Real> KanayamaParams<T> {
    /// Checks the gains; errors name `kx`, `ky` or `ktheta`.
    pub fn validate(&self) -> Result<Self, ParamError> {
        check::positive("kx", self.kx)?;
        check::positive("ky", self.ky)?;
        check::positive("ktheta", self.ktheta)?;
        Ok(*self)
    }

    /// The law's twist (v m/s, omega rad/s) and errors for measured pose `m` and
    /// reference `r` (module docs): shared with [`super::BacksteppingLaw`].
    #[inline(always)]
    pub fn twist<L: Lane<Scalar = T>>(
        &self,
        m: &Measurement<L>,
        r: &ReferenceState<L>,
    ) -> (Twist2<L>, ControlErrors<L>) {
        let (dx, dy) = (r.pose.x - m.pose.x, r.pose.y - m.pose.y);
        let (x_e, y_e) = m.pose.body_offset(r.pose.x, r.pose.y);
        let theta_e = wrap_angle(r.pose.theta - m.pose.theta);
        let (s_e, c_e) = theta_e.sin_cos();
        let v = r.twist.v * c_e + L::splat(self.kx) * x_e;
        // sgn(v_ref) ktheta (module docs): the heading term damps in reverse too.
        let ktheta = L::splat(self.ktheta);
        let ktheta = L::select(r.twist.v.lt(L::default()), -ktheta, ktheta);
        let omega = r.twist.omega + r.twist.v * (L::splat(self.ky) * y_e + ktheta * s_e);
        (Twist2 { v, omega }, ControlErrors { e_s: x_e, e_theta: theta_e, dl: dx.hypot(dy) })
    }
}

/// Kanayama et al.'s tracking law. Implements [`Law`] with [`WheelDemand::Twist`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KanayamaLaw<T: Lane> {
    params: KanayamaParams<T::Scalar>,
}

impl<T: Lane> KanayamaLaw<T> {
    /// Checks the gains (errors name `kx`, `ky`, `ktheta`) and builds the law.
    pub fn for_lanes(p: KanayamaParams<T::Scalar>) -> Result<Self, ParamError> {
        Ok(Self { params: p.validate()? })
    }

    /// The gains.
    pub fn params(&self) -> &KanayamaParams<T::Scalar> {
        &self.params
    }
}

impl<T: Lane> Law<T> for KanayamaLaw<T> {
    #[inline(always)]
    fn update(&mut self, _t: T, m: &Measurement<T>, r: &ReferenceState<T>) -> LawOutput<T> {
        let (twist, errors) = self.params.twist(m, r);
        LawOutput { demand: WheelDemand::Twist(twist), errors }
    }

    fn reset_lanes(&mut self, _lanes: T::Mask) {}
}
