//! Wheel drives (SPEC section 3): what turns a servo command into a wheel torque.

mod dc_motor;
mod torque;

pub use dc_motor::{DcMotor, DcMotorParams};
pub use torque::{TorqueDrive, TorqueDriveParams};

use crate::error::ParamError;
use crate::{Real, Robot};

/// Drive parameters as written in a scenario (`[drive]`), before validation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DriveParams<T> {
    /// Ideal torque source with a motor torque limit (SPEC default).
    Torque(TorqueDriveParams<T>),
    /// Voltage-driven permanent-magnet DC motor with quasi-static armature.
    DcMotor(DcMotorParams<T>),
}

impl<T: Real> Default for DriveParams<T> {
    fn default() -> Self {
        DriveParams::Torque(TorqueDriveParams::default())
    }
}

impl<T: Real> DriveParams<T> {
    /// Validates against the robot (the gear ratio lives in [`crate::RobotParams`]).
    pub fn validate(self, robot: &Robot<T>) -> Result<Drive<T>, ParamError> {
        let k_t = robot.params().gear_ratio;
        Ok(match self {
            DriveParams::Torque(p) => Drive::Torque(p.validate(k_t)?),
            DriveParams::DcMotor(p) => Drive::DcMotor(p.validate(k_t)?),
        })
    }
}

/// A validated drive, one per wheel (both wheels use the same model).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Drive<T> {
    /// See [`TorqueDrive`].
    Torque(TorqueDrive<T>),
    /// See [`DcMotor`].
    DcMotor(DcMotor<T>),
}

impl<T: Real> Drive<T> {
    /// Torque on the wheel (N m) for a held servo `command` at wheel speed `omega_wheel` (rad/s).
    ///
    /// The command is a wheel-torque demand (N m) for [`Drive::Torque`] and a voltage (V)
    /// for [`Drive::DcMotor`].
    #[inline(always)]
    pub fn wheel_torque(&self, command: T, omega_wheel: T) -> T {
        match self {
            Drive::Torque(d) => d.wheel_torque(command),
            Drive::DcMotor(d) => d.wheel_torque(command, omega_wheel),
        }
    }

    /// Largest useful command magnitude (N m or V): the servo's anti-windup bound.
    pub fn command_limit(&self) -> T {
        match self {
            Drive::Torque(d) => d.wheel_torque_max(),
            Drive::DcMotor(d) => d.params().voltage_max,
        }
    }

    /// True when the wheel torque does not depend on the wheel speed, so it can be
    /// evaluated once per control period instead of once per RK4 stage.
    #[inline(always)]
    pub fn is_speed_independent(&self) -> bool {
        matches!(self, Drive::Torque(_))
    }
}
