//! Ideal torque drive: the motor makes the demanded torque up to a limit, through the gear.

use crate::Real;
use crate::error::{ParamError, check};
use crate::lane::Lane;

crate::params! {
    /// `[drive] kind = "torque"` parameters.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    pub struct TorqueDriveParams<T> {
        /// |tau_motor| limit at the motor shaft (the wheel gets it / k_t).
        pub motor_torque_max: T [unit = "N m", rule = "> 0, inf allowed"],
        /// Driver deadband: a demand below this fraction of the largest gives no torque (plant only).
        pub deadband: T [unit = "", rule = "in [0, 1); > 0 only with a finite motor_torque_max"],
    }
}

impl<T: Real> Default for TorqueDriveParams<T> {
    /// 0.2 N m at the motor, i.e. 2 N m at the wheel with k_t = 0.1 (docs/model.md, "Drives").
    fn default() -> Self {
        Self { motor_torque_max: T::lit(0.2), deadband: T::zero() }
    }
}

impl<T: Real> TorqueDriveParams<T> {
    pub(crate) fn validate(self, gear_ratio: T) -> Result<TorqueDrive<T>, ParamError> {
        check::positive_or_inf("motor_torque_max", self.motor_torque_max)?;
        let deadband = super::check_deadband(self.deadband)?;
        if deadband > T::zero() && self.motor_torque_max.is_infinite() {
            return Err(check::out_of_range("deadband", "must be 0 with an infinite motor_torque_max", deadband));
        }
        Ok(TorqueDrive {
            params: self,
            gear_ratio,
            inv_gear_ratio: T::one() / gear_ratio,
            wheel_torque_max: self.motor_torque_max / gear_ratio,
        })
    }
}

/// Validated torque drive.
///
/// A wheel-torque demand tau_d becomes the motor torque k_t tau_d, clamped to
/// +-motor_torque_max; the wheel receives the clamped motor torque / k_t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorqueDrive<T> {
    params: TorqueDriveParams<T>,
    gear_ratio: T,
    /// 1 / k_t, for the lanes ([`Lane::div_by`]).
    inv_gear_ratio: T,
    wheel_torque_max: T,
}

impl<T: Real> TorqueDrive<T> {
    /// The parameters.
    pub fn params(&self) -> &TorqueDriveParams<T> {
        &self.params
    }

    /// Largest wheel torque, N m: motor_torque_max / k_t.
    pub fn wheel_torque_max(&self) -> T {
        self.wheel_torque_max
    }

    /// The largest wheel-torque demand (N m) the deadband zeroes: deadband
    /// motor_torque_max / k_t (0: none).
    pub fn dead_demand(&self) -> T {
        if self.params.deadband > T::zero() { self.params.deadband * self.wheel_torque_max } else { T::zero() }
    }

    /// Where a wheel-torque demand (N m) exceeds what the motor gives: |demand| above
    /// motor_torque_max / k_t.
    #[inline(always)]
    pub fn saturates<L: Lane<Scalar = T>>(&self, demand: L) -> L::Mask {
        L::splat(self.wheel_torque_max).lt(demand.abs())
    }

    /// Wheel torque (N m) for a wheel-torque demand (N m).
    #[inline(always)]
    pub fn wheel_torque<L: Lane<Scalar = T>>(&self, demand: L) -> L {
        let k_t = L::splat(self.gear_ratio);
        let max = L::splat(self.params.motor_torque_max);
        let motor = super::clamp_keep_nan(demand * k_t, max);
        motor.div_by(self.gear_ratio, self.inv_gear_ratio)
    }
}
