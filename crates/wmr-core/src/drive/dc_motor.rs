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
    /// Defaults: Pololu 37D metal gearmotor, 12 V, 50:1 (items 4743/4753; datasheet
    /// "Pololu 37D Metal Gearmotors", rev 1.2): 200 rpm and 0.2 A free-running, 210 kg mm
    /// (2.06 N m) and 5.5 A stalled at the output, driven by a TI DRV8874 H-bridge (6 A
    /// peak output current). Its 50:1 is the robot's gear k_t = 0.1 (10:1) after a first
    /// 5:1 stage folded into the constants below, which are referred to the shaft 10:1
    /// before the wheel (the motor shaft of this model):
    ///
    /// ```text
    /// R_a   = u / i_stall                     = 12 / 5.5           = 2.18 Ohm
    /// k_e   = u / omega_free (2,000 rpm here) = 12 / 209.44        = 0.0573 V s/rad
    /// k_tau = tau_stall k_t / i_stall         = 2.059 * 0.1 / 5.5  = 0.0374 N m/A
    /// ```
    ///
    /// So the model runs free at 20.9 rad/s at the wheel (200 rpm; 2.09 m/s with the
    /// paper's r = 0.1 m) and stalls at 2.06 N m and 5.5 A. k_tau < k_e: the stall torque
    /// at the output includes the gearbox's losses. The free-running current (friction) is
    /// not modelled here: the robot's `viscous_friction` and `coulomb_friction` are the
    /// plant's. docs/model.md ("The default DC motor") has the derivation and the figures.
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
        /// Driver deadband: a voltage below this fraction of voltage_max gives none (plant only).
        pub deadband: T [unit = "", rule = "in [0, 1)"],
    }
}

impl<T: Real> Default for DcMotorParams<T> {
    fn default() -> Self {
        Self {
            voltage_max: T::lit(12.0),
            torque_constant: T::lit(0.03744),
            back_emf_constant: T::lit(0.0573),
            armature_resistance: T::lit(2.18),
            current_max: T::lit(6.0),
            deadband: T::zero(),
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
        super::check_deadband(self.deadband)?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Real, RobotParams};

    /// Issue 24: the default motor on the paper's robot (k_t = 0.1, r = 0.1 m, 5 kg)
    /// against its datasheet (Pololu 37D 50:1 12 V, rev 1.2: 200 rpm free, 210 kg mm and
    /// 5.5 A stalled), computed from the model's own wheel torque, in f32 and f64.
    fn figures_against_the_datasheet<T: Real>(tol: f64) {
        let robot = RobotParams::<T>::paper();
        let motor = DcMotorParams::<T>::default().validate(robot.gear_ratio).unwrap();
        let u = motor.params().voltage_max;
        let torque_at = |omega: f64| motor.wheel_torque(u, T::lit(omega)).to_f64_lossless();
        // No-load speed: where the full-voltage torque is zero (bisection on the model).
        let (mut lo, mut hi) = (0.0, 100.0);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if torque_at(mid) > 0.0 { lo = mid } else { hi = mid }
        }
        let free_rpm = lo * 60.0 / (2.0 * core::f64::consts::PI);
        assert!((free_rpm - 200.0).abs() < 200.0 * tol, "free {free_rpm} rpm");
        let stall = torque_at(0.0);
        let stall_datasheet = 0.210 * 9.80665; // 210 kg mm, N m
        assert!((stall - stall_datasheet).abs() < stall_datasheet * tol, "stall {stall} N m");
        // The current at stall: tau_wheel k_t / k_tau.
        let p = motor.params();
        let current = stall * robot.gear_ratio.to_f64_lossless() / p.torque_constant.to_f64_lossless();
        assert!((current - 5.5).abs() < 5.5 * tol, "stall current {current} A");
        // Top speed at most about 2 m/s; stall force at both wheels about the traction
        // limit mu m g (mu = 0.8): 41.2 N against 39.2 N.
        let r = robot.wheel_radius.to_f64_lossless();
        assert!(lo * r < 2.1, "top speed {} m/s", lo * r);
        let force = 2.0 * stall / r;
        let traction = 0.8 * robot.mass.to_f64_lossless() * 9.80665;
        assert!((force / traction - 1.0).abs() < 0.06, "{force} N against {traction} N");
        // The driver's 6 A bounds the current when braking against the back-EMF.
        let braking = motor.wheel_torque(-u, T::lit(lo)).to_f64_lossless();
        let i_brake = braking * robot.gear_ratio.to_f64_lossless() / p.torque_constant.to_f64_lossless();
        assert!((i_brake + 6.0).abs() < 6.0 * tol, "braking current {i_brake} A");
    }

    #[test]
    fn issue_24_default_motor_matches_its_datasheet_f64() {
        figures_against_the_datasheet::<f64>(0.002);
    }

    #[test]
    fn issue_24_default_motor_matches_its_datasheet_f32() {
        figures_against_the_datasheet::<f32>(0.002);
    }
}
