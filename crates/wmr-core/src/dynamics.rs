//! Equations of motion (15) of the paper, written at C (SPEC section 2).
//!
//! With M_r = diag(m + 2 I_m/r^2, I_p + 2 R^2 I_m/r^2 + m d^2):
//!
//! ```text
//! v'     = ((tau_r - f_r + tau_l - f_l)/r + m d omega^2) / M_r11
//! omega' = ((R/r)((tau_r - f_r) - (tau_l - f_l)) - m d v omega) / M_r22
//! ```
//!
//! The Coriolis terms C(v) = [-m d omega^2, m d v omega] do no work
//! (v * m d omega^2 - omega * m d v omega = 0), which the energy test relies on.

use crate::math::Wheels;
use crate::state::State;
use crate::{Real, Robot};

impl<T: Real> Robot<T> {
    /// Friction torque at one wheel, N m: b_v omega + tau_c tanh(omega / omega_eps).
    #[inline(always)]
    pub fn friction_torque(&self, omega_wheel: T) -> T {
        let p = self.params();
        p.viscous_friction * omega_wheel + p.coulomb_friction * (omega_wheel / p.coulomb_speed).tanh()
    }

    /// Time derivative of the state under wheel torques `tau_wheel` (N m, drive on wheel).
    #[inline(always)]
    pub fn derivative(&self, s: &State<T>, tau_wheel: Wheels<T>) -> State<T> {
        let p = self.params();
        let (inv_m11, inv_m22) = self.inv_reduced_inertia();
        let md = self.mass_offset();
        let w = s.wheel_speeds(p);
        let net_r = tau_wheel.right - self.friction_torque(w.right);
        let net_l = tau_wheel.left - self.friction_torque(w.left);
        let (sin, cos) = s.theta.sin_cos();
        let r = p.wheel_radius;
        State {
            x: s.v * cos,
            y: s.v * sin,
            theta: s.omega,
            v: ((net_r + net_l) / r + md * s.omega * s.omega) * inv_m11,
            omega: (p.half_track / r * (net_r - net_l) - md * s.v * s.omega) * inv_m22,
            phi_r: w.right,
            phi_l: w.left,
        }
    }

    /// Kinetic energy, J: T = 1/2 M_r11 v^2 + 1/2 M_r22 omega^2 (platform, wheels, rotors).
    pub fn kinetic_energy(&self, s: &State<T>) -> T {
        let (m11, m22) = self.reduced_inertia();
        let half = T::lit(0.5);
        half * m11 * s.v * s.v + half * m22 * s.omega * s.omega
    }
}
