//! Wheel position servo: PD on the wheel angle, derivative on the measured speed, optional I.

use crate::Real;
use crate::error::{ParamError, check};

/// Wheel position servo gains. Units follow the drive's command:
/// N m/rad, N m s/rad and N m/(rad s) for the torque drive; V/rad, V s/rad and V/(rad s)
/// for the DC motor drive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ServoGains<T> {
    /// Kp, command per rad of angle error (`servo_kp`).
    pub kp: T,
    /// Kd, command per rad/s of wheel speed (`servo_kd`).
    pub kd: T,
    /// Ki, command per rad s of integrated angle error (`servo_ki`).
    pub ki: T,
}

impl<T: Real> ServoGains<T> {
    /// Torque-drive defaults: Kp = 14 N m/rad, Kd = 1.4 N m s/rad, Ki = 0, about
    /// 20 rad/s of bandwidth on the wheel's share of the robot (M_r11 r^2 / 2 = 0.027 kg m^2).
    pub fn torque_default() -> Self {
        Self { kp: T::lit(14.0), kd: T::lit(1.4), ki: T::zero() }
    }

    /// DC-motor defaults: Kp = 14 V/rad, Kd = 1.1 V s/rad, Ki = 0. With the default
    /// motor (about 1.01 N m/V at the wheel, back-EMF damping 0.31 N m s/rad) this gives
    /// the same stiffness and damping at the wheel as the torque-drive defaults.
    pub fn dc_motor_default() -> Self {
        Self { kp: T::lit(14.0), kd: T::lit(1.1), ki: T::zero() }
    }

    pub(crate) fn validate(self) -> Result<Self, ParamError> {
        check::positive("servo_kp", self.kp)?;
        check::non_negative("servo_kd", self.kd)?;
        check::non_negative("servo_ki", self.ki)?;
        Ok(self)
    }
}

/// One wheel's servo: command = Kp (phi_ref - phi) + Ki int(phi_ref - phi) - Kd omega.
///
/// Anti-windup: the integral term is clamped to the drive's command limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelServo<T> {
    gains: ServoGains<T>,
    /// Largest useful |command| (N m or V).
    limit: T,
    /// Integral of the angle error, rad s.
    integral: T,
}

impl<T: Real> WheelServo<T> {
    /// A servo with validated gains and the drive's command limit (may be infinite).
    pub fn new(gains: ServoGains<T>, limit: T) -> Result<Self, ParamError> {
        Ok(Self { gains: gains.validate()?, limit, integral: T::zero() })
    }

    /// The gains.
    pub fn gains(&self) -> &ServoGains<T> {
        &self.gains
    }

    /// Kp e + Ki int(e), advancing the clamped integral of the angle error `e` (rad) by `dt` (s).
    #[inline(always)]
    fn proportional_integral(&mut self, e: T, dt: T) -> T {
        let mut i_term = T::zero();
        if self.gains.ki > T::zero() {
            let bound = self.limit / self.gains.ki;
            self.integral = (self.integral + e * dt).max(-bound).min(bound);
            i_term = self.gains.ki * self.integral;
        }
        self.gains.kp * e + i_term
    }

    /// Command for angle reference `phi_ref` (rad), measured angle `phi` (rad) and speed
    /// `omega` (rad/s), advancing the integral by `dt` (s).
    #[inline(always)]
    pub fn update(&mut self, phi_ref: T, phi: T, omega: T, dt: T) -> T {
        self.proportional_integral(phi_ref - phi, dt) - self.gains.kd * omega
    }

    /// Speed-tracking form (for laws that command wheel speeds): command for angle
    /// reference `phi_ref` (rad) moving at `omega_ref` (rad/s), measured angle `phi` (rad)
    /// and speed `omega` (rad/s), advancing the integral by `dt` (s):
    ///
    /// ```text
    /// command = Kp (phi_ref - phi) + Ki int(phi_ref - phi) + Kd (omega_ref - omega)
    /// ```
    ///
    /// The derivative acts on the speed error, so a reference ramp is followed without the
    /// steady lag Kd omega / Kp that [`WheelServo::update`] (derivative on the measured
    /// speed) would leave. With `omega_ref = 0` it equals [`WheelServo::update`].
    #[inline(always)]
    pub fn update_tracking(&mut self, phi_ref: T, omega_ref: T, phi: T, omega: T, dt: T) -> T {
        self.proportional_integral(phi_ref - phi, dt) + self.gains.kd * (omega_ref - omega)
    }

    /// Largest useful |command| (N m or V), the drive's limit given at construction.
    pub fn limit(&self) -> T {
        self.limit
    }

    /// Clears the integral.
    pub fn reset(&mut self) {
        self.integral = T::zero();
    }
}
