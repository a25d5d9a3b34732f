//! The wheel stage: turns a law's [`WheelDemand`] into drive commands with two wheel
//! position servos, limiting the wheel speeds without changing the path's curvature.
//!
//! **Angle demands** (the paper's law: absolute wheel angle references, which jump at the
//! first tick and then move as the PI outputs do): a [`WheelRateLimiter`] lets the
//! references the servos see move by at most `wheel_speed_max * control_dt` per tick on
//! the faster wheel, both increments scaled by one factor (the ratio of the increments,
//! the curvature of the commanded motion, is kept). Each servo is the paper's PD with the
//! derivative on the measured speed ([`WheelServo::update`]). With an infinite limit the
//! references pass through bit for bit.
//!
//! **Twist demands** (v, omega): wheel speed references by the inverse of (1), scaled
//! together by [`limit_wheel_speeds`](super::saturation::limit_wheel_speeds), integrated into moving angle references that the
//! servos track with the derivative on the speed error ([`WheelServo::update_tracking`]):
//!
//! ```text
//! phi_ref  <- clamp(phi_ref, phi - e_max, phi + e_max)                 (anti-windup)
//! command   = Kp (phi_ref - phi) + Ki int(phi_ref - phi) + Kd (omega_ref - omega)
//! phi_ref  <- phi_ref + omega_ref * control_dt                          (forward Euler)
//! ```
//!
//! After construction or [`WheelStage::reset`] the first tick starts the references at
//! the measured wheel angles, so a restart never sees a stale angle gap. When the drive
//! saturates the wheel falls behind; the gap is clamped to e_max = command_limit / Kp (the
//! angle error that alone saturates the drive; no clamp when the limit is infinite), so
//! no lunge follows. Unlike a pure speed loop this keeps the position servo's stiffness.
//!
//! **Torque demands** (laws that compute wheel torques from the dynamic model): each
//! wheel torque becomes the drive command that gives it at the measured wheel speed
//! ([`Drive::command_for_wheel_torque`]); no servo runs.
//!
//! **The speed guard.** Limiting the references alone does not bound the wheels: a wheel
//! catching up with its reference, or pushed by the other wheel through the chassis
//! (the inertia coupling of (15)), overshoots it (the polar law on a 12 kg robot with DC
//! motors and `wheel_speed_max = 10` peaked at 11.2 rad/s). So each servo command is
//! finally clamped to the commands whose wheel torque keeps the measured wheel speed
//! omega inside the limit, as a fast speed loop that acts only near it:
//!
//! ```text
//! tau_up = K_g (omega_max - omega),  tau_lo = -K_g (omega_max + omega)      N m
//! K_g    = J_w / (2 control_dt),  J_w = r^2 / (1 / M_r11 + R^2 / M_r22)     N m s/rad
//! command <- clamp(command, drive command for tau_lo, drive command for tau_up)
//! ```
//!
//! J_w is the inertia one wheel sees when it alone is driven (the controller's robot
//! model), so without other torques the guard brings omega to the limit in about two
//! control periods and holds it there; far below the limit its bounds lie far outside
//! the drive's range and change nothing. The measured wheel speeds then stay within 2 %
//! of `wheel_speed_max` for every law (tested on every plant step), as long as the drive
//! can hold the wheel (not on a slope steeper than its torque allows). With an infinite
//! limit the guard is off and every command passes through bit for bit.
//!
//! A wheel that slips has let go of the robot: it answers a torque with its own inertia
//! I_m (`wheel_inertia`, 0.002 kg m^2 on the paper's robot, against J_w = 0.033), and a
//! gain sized for J_w, J_w / I_m = 16 times too strong, turns the clamp into an
//! oscillation about the limit (w_(k+1) - w_max = (1 - K_g dt / I_m) (w_k - w_max) per
//! tick, a factor of -7). On a plant whose wheels slip ([`WheelStage::with_slipping_wheels`],
//! set by [`crate::ClosedLoop`]) the guard uses J = I_m: a slipping wheel reaches the
//! limit in two periods as a rolling one does, and a gripping one, heavier, is brought
//! there more slowly, from below.

use super::law::WheelDemand;
use super::observer::DisturbanceObserver;
use super::saturation::{WheelRateLimiter, check_wheel_speed_max, limit_wheel_speeds_masked};
use super::servo::{ServoGains, WheelServo};
use crate::drive::{Drive, DriveParams};
use crate::error::{ParamError, check};
use crate::kinematics::wheel_speeds_lanes;
use crate::lane::{Lane, Mask};
use crate::math::Wheels;
use crate::sensor::Measurement;
use crate::{Real, RobotParams};
use num_traits::{Float, Zero};

crate::params! {
    /// The wheel stage's keys (flat in a scenario's `[controller]` table).
    // repr(C): the C API hands this very struct across (wmr-ffi, include/wmr.h).
    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    pub struct WheelStageParams<T> {
        /// Wheel servo Kp (the unit follows the drive: torque or dc_motor).
        pub servo_kp: T [unit = "N m/rad or V/rad", rule = "> 0"],
        /// Wheel servo Kd.
        pub servo_kd: T [unit = "N m s/rad or V s/rad", rule = ">= 0"],
        /// Wheel servo Ki.
        pub servo_ki: T [unit = "N m/(rad s) or V/(rad s)", rule = ">= 0"],
        /// Per-wheel speed limit (inf: off), on the references with the curvature kept.
        ///
        /// The speed guard keeps the measured wheel speeds within 2 % of it too.
        pub wheel_speed_max: T [unit = "rad/s", rule = "> 0, inf allowed"],
    }
}

impl<T: Real> WheelStageParams<T> {
    /// The defaults for a drive on the controller's robot model (its inertia at the wheel
    /// and its gear ratio k_t): with the torque drive the gains of
    /// [`ServoGains::for_wheel_inertia`] (the paper's robot's stiffness and damping scaled
    /// by the model's inertia at the wheel) and no speed limit; with a DC motor the same
    /// stiffness and damping through [`ServoGains::for_dc_motor`] for that motor and the
    /// speed limit at what it can deliver, its no-load speed at the wheel
    /// u_max k_t / k_e (rad/s; infinite without back-EMF). Faster references than that
    /// only wind the servos up: the wheels cannot follow them. A model that does not
    /// validate keeps the paper's gains (the controller refuses it later, naming the key).
    pub fn for_drive(drive: &DriveParams<T>, model: &RobotParams<T>) -> Self {
        let torque = match model.validate() {
            Ok(robot) => ServoGains::for_wheel_inertia(robot.driven_wheel_inertia()),
            Err(_) => ServoGains::torque_default(),
        };
        let (g, wheel_speed_max) = match drive {
            DriveParams::Torque(_) => (torque, T::infinity()),
            DriveParams::DcMotor(m) => {
                let k_t = model.gear_ratio;
                let torque_per_volt = m.torque_constant / (m.armature_resistance * k_t);
                let emf_per_wheel_speed = m.back_emf_constant / k_t;
                let no_load =
                    if emf_per_wheel_speed > T::zero() { m.voltage_max / emf_per_wheel_speed } else { T::infinity() };
                (ServoGains::for_dc_motor(torque, torque_per_volt, torque_per_volt * emf_per_wheel_speed), no_load)
            }
        };
        Self { servo_kp: g.kp, servo_kd: g.kd, servo_ki: g.ki, wheel_speed_max }
    }

    /// The servo gains.
    pub fn servo(&self) -> ServoGains<T> {
        ServoGains { kp: self.servo_kp, kd: self.servo_kd, ki: self.servo_ki }
    }
}

impl<T: Real> Default for WheelStageParams<T> {
    /// The torque drive's defaults (which do not depend on the robot).
    fn default() -> Self {
        Self::for_drive(&DriveParams::default(), &RobotParams::paper())
    }
}

/// Two wheel servos with the curvature-keeping speed limit (module docs), for one run or
/// several side by side ([`crate::lane`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelStage<T: Lane> {
    right: WheelServo<T>,
    left: WheelServo<T>,
    /// The controller's idea of the robot (r, R for twist to wheel speeds).
    model: RobotParams<T::Scalar>,
    wheel_speed_max: T::Scalar,
    /// Angle demands: the rate-limited references.
    limiter: WheelRateLimiter<T>,
    /// Twist demands: the integrated angle references, rad, where `phi_ref_set`
    /// (false until the first tick).
    phi_ref: Wheels<T>,
    phi_ref_set: T::Mask,
    /// Largest |phi_ref - phi|, rad (may be infinite).
    max_gap: T::Scalar,
    /// Control period, s.
    dt: T::Scalar,
    /// The wheel references of the last tick: angles (rad), speeds (rad/s) or torques
    /// (N m) by demand.
    last_refs: Wheels<T>,
    /// The drive, whose commands the speed guard bounds.
    drive: Drive<T::Scalar>,
    /// K_g of the speed guard, N m s/rad (zero when the limit is off): one of the two below.
    guard_gain: T::Scalar,
    /// K_g for wheels that roll, J_w / (2 control_dt), and for wheels that slip,
    /// I_m / (2 control_dt) (module docs), N m s/rad.
    guard_gains: (T::Scalar, T::Scalar),
    /// Anti-windup of the servos' integrators (conditional integration, module docs).
    anti_windup: bool,
    /// Where the stage saturated at the last tick, per wheel (module docs).
    saturated_right: T::Mask,
    saturated_left: T::Mask,
    /// The disturbance observer whose estimate is subtracted from the commands
    /// ([`super::observer`]); none by default.
    observer: Option<DisturbanceObserver<T>>,
}

impl<T: Real> WheelStage<T> {
    /// Validates `params` for the controller's robot model `model`, the drive (its
    /// command limit bounds the servos' integrals) and the control period (s).
    pub fn new(
        params: &WheelStageParams<T>,
        model: &RobotParams<T>,
        drive: &Drive<T>,
        control_dt: T,
    ) -> Result<Self, ParamError> {
        Self::for_lanes(params, model, drive, control_dt)
    }
}

impl<T: Lane> WheelStage<T> {
    /// [`WheelStage::new`] for several runs side by side ([`crate::lane`]).
    pub fn for_lanes(
        params: &WheelStageParams<T::Scalar>,
        model: &RobotParams<T::Scalar>,
        drive: &Drive<T::Scalar>,
        control_dt: T::Scalar,
    ) -> Result<Self, ParamError> {
        check::positive("control_dt", control_dt)?;
        let wheel_speed_max = check_wheel_speed_max(params.wheel_speed_max)?;
        let limit = drive.command_limit();
        let servo = WheelServo::for_lanes(params.servo(), limit)?;
        let guard_gains = if Float::is_finite(wheel_speed_max) {
            let wheel_inertia = model.validate()?.driven_wheel_inertia();
            let two_dt = <T::Scalar as Real>::lit(2.0) * control_dt;
            // A model without wheel inertia keeps the rolling gain when the wheels slip.
            let own =
                if model.wheel_inertia > <T::Scalar as Zero>::zero() { model.wheel_inertia } else { wheel_inertia };
            (wheel_inertia / two_dt, own / two_dt)
        } else {
            (<T::Scalar as Zero>::zero(), <T::Scalar as Zero>::zero())
        };
        let guard_gain = guard_gains.0;
        Ok(Self {
            right: servo,
            left: servo,
            model: *model,
            wheel_speed_max,
            limiter: WheelRateLimiter::new(wheel_speed_max, control_dt)?,
            phi_ref: Wheels::default(),
            phi_ref_set: T::Mask::splat(false),
            max_gap: limit / servo.gains().kp,
            dt: control_dt,
            last_refs: Wheels::default(),
            drive: *drive,
            guard_gain,
            guard_gains,
            anti_windup: true,
            saturated_right: T::Mask::splat(false),
            saturated_left: T::Mask::splat(false),
            observer: None,
        })
    }

    /// The stage with a disturbance observer ([`super::observer`]): each tick its estimate
    /// of the disturbance torque at each wheel is subtracted from the commands, before the
    /// speed guard.
    pub fn with_observer(mut self, observer: DisturbanceObserver<T>) -> Self {
        self.observer = Some(observer);
        self
    }

    /// The disturbance observer, if any.
    pub fn observer(&self) -> Option<&DisturbanceObserver<T>> {
        self.observer.as_ref()
    }

    /// The observer's estimate of the disturbance torque at each wheel at the last tick
    /// (N m); `None` without an observer.
    pub fn disturbance_estimate(&self) -> Option<Wheels<T>> {
        self.observer.as_ref().map(DisturbanceObserver::estimate)
    }

    /// The stage with the servos' anti-windup on or off (on after construction;
    /// [`super::Controller::new`] sets it from the law, [`super::Law::anti_windup`]).
    pub fn with_anti_windup(mut self, on: bool) -> Self {
        self.anti_windup = on;
        self
    }

    /// The stage for wheels that slip (`on`) or roll: the speed guard's gain K_g is then
    /// I_m / (2 control_dt) with I_m the model's `wheel_inertia` (the inertia of a wheel
    /// that has let go of the ground), or J_w / (2 control_dt) (module docs).
    /// [`crate::ClosedLoop`] sets it from its plant's traction.
    pub fn with_slipping_wheels(mut self, on: bool) -> Self {
        self.guard_gain = if on { self.guard_gains.1 } else { self.guard_gains.0 };
        self
    }

    /// Whether the servos' integrators hold while the stage saturates.
    pub fn anti_windup(&self) -> bool {
        self.anti_windup
    }

    /// Where the last tick saturated on either wheel: the speed limit held the
    /// references back, the speed guard clipped a command, or the drive cannot give the
    /// command (its torque, voltage or current limit). A law's anti-windup reads it
    /// ([`super::Law::wheels_saturated`]).
    pub fn saturated(&self) -> T::Mask {
        self.saturated_right | self.saturated_left
    }

    /// K_g of the speed guard, N m s/rad (zero when `wheel_speed_max` is infinite).
    pub fn guard_gain(&self) -> T::Scalar {
        self.guard_gain
    }

    /// `command` clamped so that the drive's wheel torque keeps the wheel speed `omega`
    /// (rad/s) within the limit (module docs).
    #[inline(always)]
    fn guard(&self, command: T, omega: T) -> T {
        let w = T::splat(self.wheel_speed_max);
        let k = T::splat(self.guard_gain);
        let up = self.drive.command_for_wheel_torque(k * (w - omega), omega);
        let lo = self.drive.command_for_wheel_torque(-k * (w + omega), omega);
        command.min(up).max(lo)
    }

    /// Control period, s.
    pub fn control_dt(&self) -> T::Scalar {
        self.dt
    }

    /// The wheel speed limit, rad/s (infinite: off).
    pub fn wheel_speed_max(&self) -> T::Scalar {
        self.wheel_speed_max
    }

    /// The wheel references of the last tick: angles (rad) for angle demands, speeds
    /// (rad/s) for twist demands, wheel torques (N m) for torque demands.
    pub fn last_refs(&self) -> Wheels<T> {
        self.last_refs
    }

    /// Drive commands (N m or V per wheel) for `demand` given the measured wheel angles
    /// (rad) and speeds (rad/s) in `m`.
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub fn command(&mut self, demand: WheelDemand<T>, m: &Measurement<T>) -> Wheels<T> {
        if self.anti_windup {
            self.right.hold = self.saturated_right;
            self.left.hold = self.saturated_left;
        }
        let (command, limited) = self.servo_command(demand, m);
        let w = m.wheel_speeds;
        let drive = self.drive;
        let command = match &mut self.observer {
            // The command moves by the command of -d_hat less the command of 0 (the
            // drive's command is affine in the wheel torque; the torque drive: -d_hat).
            Some(obs) => {
                // Written out, not a closure: the lanes' kernel must hold no out-of-line
                // call at every step (scripts/check-kernel), and a closure may not inline.
                let d = obs.update(w);
                let zero = T::default();
                let right = command.right
                    + (drive.command_for_wheel_torque(-d.right, w.right)
                        - drive.command_for_wheel_torque(zero, w.right));
                let left = command.left
                    + (drive.command_for_wheel_torque(-d.left, w.left) - drive.command_for_wheel_torque(zero, w.left));
                Wheels::new(right, left)
            }
            None => command,
        };
        // The deadband and stiction pre-compensation (observer's module docs; off: the
        // commands themselves).
        let command = match &self.observer {
            Some(obs) => obs.precompensate(command),
            None => command,
        };
        let (command, clipped) = if Float::is_finite(self.wheel_speed_max) {
            let guarded = Wheels::new(self.guard(command.right, w.right), self.guard(command.left, w.left));
            (guarded, Wheels::new(!guarded.right.eq(command.right), !guarded.left.eq(command.left)))
        } else {
            let no = T::Mask::splat(false);
            (command, Wheels::new(no, no))
        };
        self.saturated_right = limited | clipped.right | self.drive.saturates(command.right, w.right);
        self.saturated_left = limited | clipped.left | self.drive.saturates(command.left, w.left);
        if let Some(obs) = &mut self.observer {
            // The torques the drive gives as the controller believes it (its deadband).
            let passed = obs.believed_passed(command);
            obs.record(Wheels::new(drive.wheel_torque(passed.right, w.right), drive.wheel_torque(passed.left, w.left)));
        }
        command
    }

    #[inline(always)]
    fn servo_command(&mut self, demand: WheelDemand<T>, m: &Measurement<T>) -> (Wheels<T>, T::Mask) {
        let phi = m.wheel_angles;
        let w = m.wheel_speeds;
        let dt = T::splat(self.dt);
        match demand {
            WheelDemand::Angles(target) => {
                let (refs, limited) = if Float::is_finite(self.wheel_speed_max) {
                    (self.limiter.limit(target, phi), self.limiter.limited)
                } else {
                    (target, T::Mask::splat(false))
                };
                self.last_refs = refs;
                let command = Wheels::new(
                    self.right.update(refs.right, phi.right, w.right, dt),
                    self.left.update(refs.left, phi.left, w.left, dt),
                );
                (command, limited)
            }
            WheelDemand::Twist(twist) => {
                let speeds = wheel_speeds_lanes(&self.model, twist.v, twist.omega);
                let (omega_ref, limited) = limit_wheel_speeds_masked(speeds, T::splat(self.wheel_speed_max));
                self.last_refs = omega_ref;
                let set = self.phi_ref_set;
                let prev = Wheels::new(
                    T::select(set, self.phi_ref.right, phi.right),
                    T::select(set, self.phi_ref.left, phi.left),
                );
                let g = T::splat(self.max_gap);
                let clamp = |r: T, p: T| r.max(p - g).min(p + g);
                let r = Wheels::new(clamp(prev.right, phi.right), clamp(prev.left, phi.left));
                let command = Wheels::new(
                    self.right.update_tracking(r.right, omega_ref.right, phi.right, w.right, dt),
                    self.left.update_tracking(r.left, omega_ref.left, phi.left, w.left, dt),
                );
                self.phi_ref = Wheels::new(r.right + omega_ref.right * dt, r.left + omega_ref.left * dt);
                self.phi_ref_set = T::Mask::splat(true);
                // The references clamped to the gap are held back too.
                let gapped = !r.right.eq(prev.right) | !r.left.eq(prev.left);
                (command, limited | gapped)
            }
            WheelDemand::Torques(tau) => {
                self.last_refs = tau;
                let command = Wheels::new(
                    self.drive.command_for_wheel_torque(tau.right, w.right),
                    self.drive.command_for_wheel_torque(tau.left, w.left),
                );
                (command, T::Mask::splat(false))
            }
        }
    }

    /// What the servos' integrators have yet to move each wheel, rad
    /// ([`WheelServo::integrator_travel`]); the settle rule reads it ([`crate::settle`]).
    pub fn integrator_travel(&self) -> Wheels<T> {
        Wheels::new(self.right.integrator_travel(), self.left.integrator_travel())
    }

    /// Clears the servos' integrals and the references, as at t = 0.
    pub fn reset(&mut self) {
        self.reset_lanes(T::Mask::splat(true));
    }

    /// [`WheelStage::reset`] of the runs in `lanes` only (several runs side by side).
    pub fn reset_lanes(&mut self, lanes: T::Mask) {
        self.right.reset_lanes(lanes);
        self.left.reset_lanes(lanes);
        self.limiter.reset_lanes(lanes);
        self.phi_ref_set = self.phi_ref_set & !lanes;
        self.saturated_right = self.saturated_right & !lanes;
        self.saturated_left = self.saturated_left & !lanes;
        let zero = T::default();
        self.last_refs =
            Wheels::new(T::select(lanes, zero, self.last_refs.right), T::select(lanes, zero, self.last_refs.left));
        if let Some(obs) = &mut self.observer {
            obs.reset_lanes(lanes);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Robot;
    use crate::drive::DcMotorParams;
    use crate::math::Pose2;

    /// A torque demand becomes the command whose wheel torque, by the drive's own model at
    /// the measured wheel speed, is the torque asked for.
    #[test]
    fn torque_demands_give_the_asked_wheel_torques_through_either_drive() {
        let robot = Robot::<f64>::paper();
        for params in [DriveParams::default(), DriveParams::DcMotor(DcMotorParams::default())] {
            let drive = params.validate(&robot).unwrap();
            let wheels = WheelStageParams::for_drive(&params, robot.params());
            let mut stage = WheelStage::new(&wheels, robot.params(), &drive, 1e-3).unwrap();
            let speeds = Wheels::new(3.0, -1.5);
            let m = Measurement {
                t: 0.0,
                pose: Pose2::default(),
                wheel_angles: Wheels::new(0.4, 0.1),
                wheel_speeds: speeds,
            };
            let tau = Wheels::new(0.35, -0.2);
            let command = stage.command(WheelDemand::Torques(tau), &m);
            let got = Wheels::new(
                drive.wheel_torque(command.right, speeds.right),
                drive.wheel_torque(command.left, speeds.left),
            );
            assert!(
                (got.right - tau.right).abs() < 1e-12 && (got.left - tau.left).abs() < 1e-12,
                "{params:?}: {got:?}"
            );
            assert_eq!(stage.last_refs(), tau);
        }
    }
}
