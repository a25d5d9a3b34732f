//! Permanent-magnet DC motor with a quasi-static armature (inductance neglected), through the gear.
//!
//! i = (u - k_e omega_motor) / R_a with omega_motor = omega_wheel / k_t;
//! tau_wheel = k_tau i / k_t; u clamped to +-u_max.

use crate::Real;
use crate::error::{ParamError, check};
use crate::lane::Lane;

crate::params! {
    /// `[drive] kind = "dc_motor"` parameters, SI units.
    ///
    /// Defaults: maxon RE 40 (40 mm, graphite brushes, 150 W), catalogue part 148867,
    /// 24 V winding: torque constant 30.2 mN m/A, speed constant 317 rpm/V
    /// (k_e = 30.2 mV s/rad, the same number in SI), terminal resistance 0.299 Ohm.
    /// With the paper's gear k_t = 0.1 it stalls at about 24 N m at the wheel and runs
    /// free at about 79 rad/s at the wheel (7,600 rpm at the motor) on 24 V.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    pub struct DcMotorParams<T> {
        /// u_max, supply voltage limit.
        pub voltage_max: T [unit = "V", rule = "> 0"],
        /// k_tau, torque constant.
        pub torque_constant: T [unit = "N m/A", rule = "> 0"],
        /// k_e, back-EMF constant at the motor shaft.
        pub back_emf_constant: T [unit = "V s/rad", rule = ">= 0"],
        /// R_a, armature (terminal) resistance.
        pub armature_resistance: T [unit = "Ohm", rule = "> 0"],
        /// i_max, armature current limit of the motor driver (inf: none).
        ///
        /// The current is clamped to +-i_max, so the wheel torque to +-k_tau i_max / k_t.
        pub current_max: T [unit = "A", rule = "> 0, inf allowed"],
    }
}

impl<T: Real> Default for DcMotorParams<T> {
    fn default() -> Self {
        Self {
            voltage_max: T::lit(24.0),
            torque_constant: T::lit(0.0302),
            back_emf_constant: T::lit(0.0302),
            armature_resistance: T::lit(0.299),
            current_max: T::infinity(),
        }
    }
}

impl<T: Real> DcMotorParams<T> {
    pub(crate) fn validate(self, gear_ratio: T) -> Result<DcMotor<T>, ParamError> {
        check::positive("voltage_max", self.voltage_max)?;
        check::positive("torque_constant", self.torque_constant)?;
        check::non_negative("back_emf_constant", self.back_emf_constant)?;
        check::positive("armature_resistance", self.armature_resistance)?;
        check::positive_or_inf("current_max", self.current_max)?;
        let torque_per_volt = self.torque_constant / (self.armature_resistance * gear_ratio);
        let emf_per_wheel_speed = self.back_emf_constant / gear_ratio;
        let wheel_torque_max = self.torque_constant * self.current_max / gear_ratio;
        Ok(DcMotor { params: self, torque_per_volt, emf_per_wheel_speed, wheel_torque_max })
    }
}

/// Validated DC motor drive; the servo command is the voltage, V.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DcMotor<T> {
    params: DcMotorParams<T>,
    /// k_tau / (R_a k_t), N m/V at the wheel.
    torque_per_volt: T,
    /// k_e / k_t, V per rad/s of wheel speed.
    emf_per_wheel_speed: T,
    /// k_tau i_max / k_t, N m: the wheel torque at the current limit (infinite without one).
    wheel_torque_max: T,
}

impl<T: Real> DcMotor<T> {
    /// The parameters.
    pub fn params(&self) -> &DcMotorParams<T> {
        &self.params
    }

    /// Wheel torque (N m) for a voltage command (V, clamped) at wheel speed (rad/s):
    /// k_tau i / k_t with i = (u - k_e omega_motor) / R_a clamped to +-current_max.
    #[inline(always)]
    pub fn wheel_torque<L: Lane<Scalar = T>>(&self, voltage: L, omega_wheel: L) -> L {
        let u_max = L::splat(self.params.voltage_max);
        let u = super::clamp_keep_nan(voltage, u_max);
        let tau = (u - L::splat(self.emf_per_wheel_speed) * omega_wheel) * L::splat(self.torque_per_volt);
        // Torque is proportional to current: clamping it clamps the current.
        if self.wheel_torque_max.is_finite() {
            let tau_max = L::splat(self.wheel_torque_max);
            super::clamp_keep_nan(tau, tau_max)
        } else {
            tau
        }
    }

    /// Where the motor cannot give what `voltage` (V) asks at `omega_wheel` (rad/s): the
    /// voltage beyond +-u_max, or the current it drives beyond +-i_max. The wheel stage's
    /// anti-windup reads it ([`crate::controller::WheelStage::saturated`]).
    #[inline(always)]
    pub fn saturates<L: Lane<Scalar = T>>(&self, voltage: L, omega_wheel: L) -> L::Mask {
        let u_max = L::splat(self.params.voltage_max);
        let over_voltage = u_max.lt(voltage.abs());
        if self.wheel_torque_max.is_finite() {
            let u = super::clamp_keep_nan(voltage, u_max);
            let tau = (u - L::splat(self.emf_per_wheel_speed) * omega_wheel) * L::splat(self.torque_per_volt);
            over_voltage | L::splat(self.wheel_torque_max).lt(tau.abs())
        } else {
            over_voltage
        }
    }

    /// The voltage (V) that makes the wheel torque `tau` (N m) at wheel speed
    /// `omega_wheel` (rad/s), the voltage and current limits aside: tau R_a k_t / k_tau +
    /// k_e omega_wheel / k_t.
    #[inline(always)]
    pub fn voltage_for_wheel_torque<L: Lane<Scalar = T>>(&self, tau: L, omega_wheel: L) -> L {
        tau / L::splat(self.torque_per_volt) + L::splat(self.emf_per_wheel_speed) * omega_wheel
    }

    /// Back-EMF damping at the wheel, N m s/rad: k_tau k_e / (R_a k_t^2).
    pub fn speed_damping(&self) -> T {
        self.emf_per_wheel_speed * self.torque_per_volt
    }

    /// The largest wheel torque the current limit allows, N m (infinite without one).
    pub fn wheel_torque_max(&self) -> T {
        self.wheel_torque_max
    }
}
