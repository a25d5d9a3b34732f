//! Wheel speed tracking through the wheel position servos: speed references are
//! integrated into angle references inside the controller.
//!
//! Laws that command a body twist (v, omega) turn it into wheel speed references by the
//! inverse of (1), `kinematics::wheel_speeds`, then limit them
//! ([`super::saturation`]). Each wheel's [`WheelServo`] then tracks a moving angle
//! reference, with the derivative acting on the speed error
//! ([`WheelServo::update_tracking`]), at every control tick k:
//!
//! ```text
//! phi_ref  <- clamp(phi_ref, phi - e_max, phi + e_max)                 (anti-windup)
//! command   = Kp (phi_ref - phi) + Ki int(phi_ref - phi) + Kd (omega_ref - omega)
//! phi_ref  <- phi_ref + omega_ref * control_dt                          (forward Euler)
//! ```
//!
//! - Reset-safe: after construction or [`SpeedServo::reset`] the first tick starts the
//!   reference at the measured wheel angles, so a restart never sees a stale angle gap.
//! - Anti-windup of the integrated reference: when the drive saturates, the wheel falls
//!   behind and phi_ref - phi would grow without bound, to be "caught up" later by a
//!   lunge. The gap is clamped to e_max = command_limit / Kp (the angle error that alone
//!   saturates the drive: 2 N m / 14 N m/rad = 0.14 rad with the defaults; no clamp when
//!   the drive limit is infinite).
//!
//! Compared with a pure speed (PI) loop this keeps the position servo's stiffness: the
//! wheel angle, not only its speed, follows the integrated reference, so a wheel that is
//! held still by a zero speed reference holds its angle.

use super::saturation::{check_wheel_speed_max, limit_wheel_speeds};
use super::{Measurement, ServoGains, WheelServo};
use crate::error::{ParamError, check};
use crate::kinematics::wheel_speeds;
use crate::math::{Twist2, Wheels};
use crate::{Real, RobotParams};

/// Two wheel servos tracking wheel speed references (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedServo<T> {
    right: WheelServo<T>,
    left: WheelServo<T>,
    /// Integrated angle references, rad; `None` until the first tick.
    phi_ref: Option<Wheels<T>>,
    /// Largest |phi_ref - phi|, rad (may be infinite).
    max_gap: T,
    /// Control period, s.
    dt: T,
}

impl<T: Real> SpeedServo<T> {
    /// Servos with validated `gains`, the drive's command limit `limit` (N m or V; may be
    /// infinite) and control period `control_dt` (s).
    pub fn new(gains: ServoGains<T>, limit: T, control_dt: T) -> Result<Self, ParamError> {
        check::positive("controller.control_dt", control_dt)?;
        let servo = WheelServo::new(gains, limit)?;
        let max_gap = limit / servo.gains().kp;
        Ok(Self { right: servo, left: servo, phi_ref: None, max_gap, dt: control_dt })
    }

    /// The current angle references, rad (None before the first tick).
    pub fn angle_refs(&self) -> Option<Wheels<T>> {
        self.phi_ref
    }

    /// Drive commands (N m or V) that make the wheels track `omega_ref` (rad/s), given
    /// the measurement; advances the angle references by one control period.
    #[inline]
    pub fn command(&mut self, omega_ref: Wheels<T>, m: &Measurement<T>) -> Wheels<T> {
        let phi = m.wheel_angles;
        let w = m.wheel_speeds;
        let prev = self.phi_ref.unwrap_or(phi);
        let g = self.max_gap;
        let clamp = |r: T, p: T| r.max(p - g).min(p + g);
        let r = Wheels::new(clamp(prev.right, phi.right), clamp(prev.left, phi.left));
        let dt = self.dt;
        let command = Wheels::new(
            self.right.update_tracking(r.right, omega_ref.right, phi.right, w.right, dt),
            self.left.update_tracking(r.left, omega_ref.left, phi.left, w.left, dt),
        );
        self.phi_ref = Some(Wheels::new(r.right + omega_ref.right * dt, r.left + omega_ref.left * dt));
        command
    }

    /// Clears the servo integrals and the angle references.
    pub fn reset(&mut self) {
        self.right.reset();
        self.left.reset();
        self.phi_ref = None;
    }
}

/// The whole wheel-speed path of a twist-commanding law: (v, omega) to wheel speed
/// references by the inverse of (1), the curvature-keeping limit, then [`SpeedServo`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwistServo<T> {
    robot: RobotParams<T>,
    wheel_speed_max: T,
    servo: SpeedServo<T>,
    last_twist: Twist2<T>,
    last_refs: Wheels<T>,
}

impl<T: Real> TwistServo<T> {
    /// For robot `robot`, wheel speed limit `wheel_speed_max` (rad/s, infinity = off),
    /// servo `gains`, drive command limit `limit` and control period `control_dt` (s).
    pub fn new(
        robot: &RobotParams<T>,
        wheel_speed_max: T,
        gains: ServoGains<T>,
        limit: T,
        control_dt: T,
    ) -> Result<Self, ParamError> {
        let wheel_speed_max = check_wheel_speed_max(wheel_speed_max)?;
        let servo = SpeedServo::new(gains, limit, control_dt)?;
        Ok(Self { robot: *robot, wheel_speed_max, servo, last_twist: Twist2::default(), last_refs: Wheels::default() })
    }

    /// Drive commands for the law's twist (v in m/s, omega in rad/s).
    #[inline]
    pub fn command(&mut self, twist: Twist2<T>, m: &Measurement<T>) -> Wheels<T> {
        let refs = limit_wheel_speeds(wheel_speeds(&self.robot, twist), self.wheel_speed_max);
        self.last_twist = twist;
        self.last_refs = refs;
        self.servo.command(refs, m)
    }

    /// The law's twist of the last tick, before the limit.
    pub fn last_twist(&self) -> Twist2<T> {
        self.last_twist
    }

    /// The wheel speed references of the last tick, after the limit, rad/s.
    pub fn last_wheel_speed_refs(&self) -> Wheels<T> {
        self.last_refs
    }

    /// The wheel speed limit, rad/s (infinite when off).
    pub fn wheel_speed_max(&self) -> T {
        self.wheel_speed_max
    }

    /// Clears the servos and the last values.
    pub fn reset(&mut self) {
        self.servo.reset();
        self.last_twist = Twist2::default();
        self.last_refs = Wheels::default();
    }
}
