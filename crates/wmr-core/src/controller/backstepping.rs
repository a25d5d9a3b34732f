//! Kanayama's twist back-stepped into the dynamics: wheel torques from the controller's
//! model of the robot, in the manner of Fierro and Lewis.
//!
//! Source: R. Fierro, F. L. Lewis, "Control of a nonholonomic mobile robot:
//! backstepping kinematics into dynamics", J. Robotic Systems 14(3), 1997, pp. 149-163
//! (sections 3-4: the kinematic controller v_c is Kanayama's, and the torque is computed
//! from the model so the body twist v follows v_c). Here, with the body twist
//! v = (v, omega) measured from the wheel encoders (v = r (w_r + w_l) / 2,
//! omega = r (w_r - w_l) / (2 R), the model's r and R):
//!
//! ```text
//! v_c   = Kanayama's (v, omega)                                (super::kanayama)
//! u     = v_c' + k4 (v_c - v)                                  desired body acceleration
//! F     = M_r11 u_v - m d omega^2                              N, forward force at C
//! N     = M_r22 u_omega + m d v omega                          N m, moment about C
//! tau_r = (r F + (r / R) N) / 2 + f(w_r)                       N m at the wheel
//! tau_l = (r F - (r / R) N) / 2 + f(w_l)
//! ```
//!
//! that is tau = B^-1 (M_r u + C(v) + B tau_f) of (15) inverted (docs/model.md), with
//! f(w) = b_v w + tau_c tanh(w / omega_eps) the model's friction at the measured wheel
//! speed. wmr's choice for v_c': the difference of v_c over one control period
//! ((v_c(k) - v_c(k-1)) / control_dt, zero at the first tick): it needs no derivative
//! of the measurement, and a late or noisy sensor shows in it as it would on a robot.
//! The torques go through the drive's limits in the wheel stage; for the DC motor the
//! wheel stage turns them into voltages with the motor constants
//! ([`super::WheelDemand::Torques`]).
//!
//! Logged errors: Kanayama's (e_s = x_e, e_theta = theta_e, dl = |C_ref - C|).

use super::kanayama::KanayamaParams;
use super::law::{Law, LawOutput, WheelDemand};
use crate::error::{ParamError, check};
use crate::lane::{Lane, Mask};
use crate::math::{Twist2, Wheels};
use crate::reference::ReferenceState;
use crate::sensor::Measurement;
use crate::{Real, RobotParams};

crate::params! {
    words;
    /// `[controller] kind = "backstepping"` parameters.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    #[repr(C)]
    pub struct BacksteppingParams<T> {
        /// kx: Kanayama's forward speed per metre of along-track error.
        pub kx: T [unit = "1/s", rule = "> 0"],
        /// ky: Kanayama's yaw rate per metre of lateral error, per m/s of v_ref.
        pub ky: T [unit = "1/m^2", rule = "> 0"],
        /// ktheta: Kanayama's yaw rate per unit of sin(heading error), per m/s of |v_ref|.
        pub ktheta: T [unit = "1/m", rule = "> 0"],
        /// k4: rate at which the body twist is driven to Kanayama's.
        pub k4: T [unit = "1/s", rule = "> 0"],
    }
}

impl<T: Real> Default for BacksteppingParams<T> {
    /// Kanayama's defaults and k4 = 20 1/s (the velocity loop five times faster than
    /// Kanayama's heading loop at 0.3 m/s, ktheta v_ref / 2 = 2.4 1/s, twice kx).
    fn default() -> Self {
        let k = KanayamaParams::default();
        Self { kx: k.kx, ky: k.ky, ktheta: k.ktheta, k4: T::lit(20.0) }
    }
}

impl<T: Real> super::law::LawSpec<T> for BacksteppingParams<T> {
    /// It demands wheel torques, not a twist.
    const TWIST_DEMAND: bool = false;

    type Law<L: Lane<Scalar = T>> = BacksteppingLaw<L>;

    fn build<L: Lane<Scalar = T>>(
        &self,
        model: &RobotParams<T>,
        control_dt: T,
    ) -> Result<BacksteppingLaw<L>, ParamError> {
        BacksteppingLaw::for_lanes(*self, model, control_dt)
    }
}

/// The controller's model constants the torque computation uses.
#[derive(Clone, Copy, Debug, PartialEq)]
struct TorqueModel<T> {
    r: T,
    big_r: T,
    m11: T,
    m22: T,
    md: T,
    b_v: T,
    tau_c: T,
    omega_eps: T,
}

/// The back-stepping law. Implements [`Law`] with [`WheelDemand::Torques`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BacksteppingLaw<T: Lane> {
    kanayama: KanayamaParams<T::Scalar>,
    k4: T::Scalar,
    model: TorqueModel<T::Scalar>,
    control_dt: T::Scalar,
    /// Kanayama's twist at the last tick.
    prev: Twist2<T>,
    /// False until the first tick (then v_c' is taken as zero).
    started: T::Mask,
}

impl<T: Lane> BacksteppingLaw<T> {
    /// Checks the gains (errors name `kx`, `ky`, `ktheta`, `k4`) and the model, and builds
    /// the law for the controller's robot model and control period `control_dt` (s).
    pub fn for_lanes(
        p: BacksteppingParams<T::Scalar>,
        model: &RobotParams<T::Scalar>,
        control_dt: T::Scalar,
    ) -> Result<Self, ParamError> {
        let kanayama = KanayamaParams { kx: p.kx, ky: p.ky, ktheta: p.ktheta }.validate()?;
        let k4 = check::positive("k4", p.k4)?;
        let robot = model.validate()?;
        let (m11, m22) = robot.reduced_inertia();
        let model = TorqueModel {
            r: model.wheel_radius,
            big_r: model.half_track,
            m11,
            m22,
            md: robot.mass_offset(),
            b_v: model.viscous_friction,
            tau_c: model.coulomb_friction,
            omega_eps: model.coulomb_speed,
        };
        Ok(Self { kanayama, k4, model, control_dt, prev: Twist2::default(), started: T::Mask::splat(false) })
    }

    #[inline(always)]
    fn friction(&self, w: T) -> T {
        let m = &self.model;
        let viscous = T::splat(m.b_v) * w;
        if m.tau_c > <T::Scalar as num_traits::Zero>::zero() {
            viscous + T::splat(m.tau_c) * (w / T::splat(m.omega_eps)).tanh()
        } else {
            viscous
        }
    }
}

impl<T: Lane> Law<T> for BacksteppingLaw<T> {
    #[inline(always)]
    fn update(&mut self, _t: T, m: &Measurement<T>, r: &ReferenceState<T>) -> LawOutput<T> {
        let (vc, errors) = self.kanayama.twist(m, r);
        let md = &self.model;
        let half = T::lit(0.5);
        let (wr, wl) = (m.wheel_speeds.right, m.wheel_speeds.left);
        let v = T::splat(md.r) * (wr + wl) * half;
        let omega = T::splat(md.r) * (wr - wl) / (T::lit(2.0) * T::splat(md.big_r));
        let dt = T::splat(self.control_dt);
        let dv = T::select(self.started, (vc.v - self.prev.v) / dt, T::default());
        let domega = T::select(self.started, (vc.omega - self.prev.omega) / dt, T::default());
        let k4 = T::splat(self.k4);
        let u_v = dv + k4 * (vc.v - v);
        let u_omega = domega + k4 * (vc.omega - omega);
        let mdd = T::splat(md.md);
        let force = T::splat(md.m11) * u_v - mdd * omega * omega;
        let moment = T::splat(md.m22) * u_omega + mdd * v * omega;
        let rf = T::splat(md.r) * force;
        let rn = T::splat(md.r) / T::splat(md.big_r) * moment;
        let tau = Wheels::new((rf + rn) * half + self.friction(wr), (rf - rn) * half + self.friction(wl));
        self.prev = vc;
        self.started = T::Mask::splat(true);
        LawOutput { demand: WheelDemand::Torques(tau), errors }
    }

    fn reset_lanes(&mut self, lanes: T::Mask) {
        self.started = self.started & !lanes;
        self.prev = Twist2 {
            v: T::select(lanes, T::default(), self.prev.v),
            omega: T::select(lanes, T::default(), self.prev.omega),
        };
    }
}
