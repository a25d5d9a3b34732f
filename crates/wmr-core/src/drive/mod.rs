//! Wheel drives (docs/model.md, "Drives"): what turns a servo command into a wheel torque.

mod dc_motor;
mod torque;

pub use dc_motor::{DcMotor, DcMotorParams};
pub use torque::{TorqueDrive, TorqueDriveParams};

use crate::describe::{Described, ParamField};
use crate::error::ParamError;
use crate::lane::Lane;
use crate::{Real, Robot};

/// `x` clamped to [-limit, limit], and NaN kept NaN: `x.max(-limit).min(limit)` alone
/// turns NaN into -limit (`max` keeps the number), a full command in reverse that would
/// drive the plant on as if commanded; kept NaN, the next plant step
/// is non-finite and refused. Every other x gives the same bits as that expression.
#[inline(always)]
pub(crate) fn clamp_keep_nan<L: Lane>(x: L, limit: L) -> L {
    L::select(x.eq(x), x.max(-limit).min(limit), x)
}

/// `deadband` is a fraction in [0, 1); the error names it.
pub(crate) fn check_deadband<T: Real>(deadband: T) -> Result<T, ParamError> {
    let d = crate::error::check::non_negative("deadband", deadband)?;
    if d >= T::one() {
        return Err(crate::error::check::out_of_range("deadband", "must be < 1", d));
    }
    Ok(d)
}

/// Drive parameters as written in a scenario (`[drive]`), before validation.
#[derive(Clone, Copy, Debug, PartialEq)]
/// Serialized with a `kind` key; read with `DriveParams::deserialize_variant` (feature `serde`) (serde's
/// tagged-enum reader needs an allocator).
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "snake_case"))]
#[non_exhaustive]
pub enum DriveParams<T> {
    /// Ideal torque source with a motor torque limit (the default).
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
    /// Every kind with its default parameters, in documentation order: what the
    /// scenario file's `[drive] kind = ...` can name and what its missing keys take.
    pub fn defaults() -> [Self; 2] {
        [DriveParams::Torque(TorqueDriveParams::default()), DriveParams::DcMotor(DcMotorParams::default())]
    }

    /// The kind's name in a scenario file: `"torque"` or `"dc_motor"`.
    pub fn kind(&self) -> &'static str {
        match self {
            DriveParams::Torque(_) => "torque",
            DriveParams::DcMotor(_) => "dc_motor",
        }
    }

    /// The declared fields of this kind's parameters ([`crate::params!`]).
    pub fn fields(&self) -> &'static [ParamField] {
        match self {
            DriveParams::Torque(_) => TorqueDriveParams::<T>::FIELDS,
            DriveParams::DcMotor(_) => DcMotorParams::<T>::FIELDS,
        }
    }

    /// Reads the keys of the same kind as `self` (without `kind`) from `d`.
    #[cfg(feature = "serde")]
    pub fn deserialize_variant<'de, D: serde::Deserializer<'de>>(&self, d: D) -> Result<Self, D::Error>
    where
        T: serde::Deserialize<'de>,
    {
        use serde::Deserialize as _;
        Ok(match self {
            DriveParams::Torque(_) => DriveParams::Torque(TorqueDriveParams::deserialize(d)?),
            DriveParams::DcMotor(_) => DriveParams::DcMotor(DcMotorParams::deserialize(d)?),
        })
    }

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
#[non_exhaustive]
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
    pub fn wheel_torque<L: Lane<Scalar = T>>(&self, command: L, omega_wheel: L) -> L {
        match self {
            Drive::Torque(d) => d.wheel_torque(command),
            Drive::DcMotor(d) => d.wheel_torque(command, omega_wheel),
        }
    }

    /// The commands the motor driver passes on (plant only; the controller never sees
    /// it): a command whose magnitude is below `deadband` times the largest command
    /// (the torque drive: motor_torque_max / k_t, N m at the wheel; the DC motor:
    /// voltage_max, V) becomes 0, any other passes unchanged. Without a deadband the
    /// commands themselves (the same bits).
    #[inline(always)]
    pub fn deadband<L: Lane<Scalar = T>>(&self, command: crate::math::Wheels<L>) -> crate::math::Wheels<L> {
        let dead = match self {
            Drive::Torque(d) => d.dead_demand(),
            Drive::DcMotor(d) => d.params().deadband * d.params().voltage_max,
        };
        if dead == T::zero() {
            return command;
        }
        let dead = L::splat(dead);
        command.map(|c| L::select(c.abs().lt(dead), L::default(), c))
    }

    /// Where the drive cannot give what `command` asks at wheel speed `omega_wheel`
    /// (rad/s): the torque or voltage limit, or a DC motor's current limit, clips it.
    #[inline(always)]
    pub fn saturates<L: Lane<Scalar = T>>(&self, command: L, omega_wheel: L) -> L::Mask {
        match self {
            Drive::Torque(d) => d.saturates(command),
            Drive::DcMotor(d) => d.saturates(command, omega_wheel),
        }
    }

    /// The parameters it was built from.
    pub fn params(&self) -> DriveParams<T> {
        match self {
            Drive::Torque(d) => DriveParams::Torque(*d.params()),
            Drive::DcMotor(d) => DriveParams::DcMotor(*d.params()),
        }
    }

    /// How much the wheel torque falls per rad/s of wheel speed at a fixed command,
    /// N m s/rad: the back-EMF damping k_tau k_e / (R_a k_t^2) of a DC motor, 0 for the
    /// torque drive. It adds to the friction's stiffness ([`crate::Plant::stiffness`]).
    pub fn speed_damping(&self) -> T {
        match self {
            Drive::Torque(_) => T::zero(),
            Drive::DcMotor(d) => d.speed_damping(),
        }
    }

    /// The command (N m or V) that makes the wheel torque `tau` (N m) at wheel speed
    /// `omega_wheel` (rad/s), the drive's limits aside: the inverse of
    /// [`Drive::wheel_torque`] where that is not saturated. The wheel stage's speed limit
    /// turns its torque bound into a command bound with it.
    #[inline(always)]
    pub fn command_for_wheel_torque<L: Lane<Scalar = T>>(&self, tau: L, omega_wheel: L) -> L {
        match self {
            Drive::Torque(_) => tau,
            Drive::DcMotor(d) => d.voltage_for_wheel_torque(tau, omega_wheel),
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
