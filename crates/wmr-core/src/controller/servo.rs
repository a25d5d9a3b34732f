//! Wheel position servo: PD on the wheel angle, derivative on the measured speed, optional I.

use crate::Real;
use crate::error::{ParamError, check};
use crate::lane::{Lane, Mask};
use num_traits::Zero;

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
    /// The paper's robot's gains (torque drive): Kp = 14 N m/rad, Kd = 1.4 N m s/rad,
    /// Ki = 0, about 20 rad/s of bandwidth on the wheel's share of the robot
    /// (M_r11 r^2 / 2 = 0.027 kg m^2).
    pub fn torque_default() -> Self {
        Self { kp: T::lit(14.0), kd: T::lit(1.4), ki: T::zero() }
    }

    /// Torque-drive gains for a robot whose inertia at the wheel is `wheel_inertia`
    /// J_w kg m^2 ([`crate::Robot::driven_wheel_inertia`]): the paper's robot's stiffness
    /// and damping scaled by J_w / J_w,paper, Kp = 14 s N m/rad, Kd = 1.4 s N m s/rad,
    /// s = J_w / J_w,paper (J_w,paper = 0.0328 kg m^2), Ki = 0. The bandwidth
    /// sqrt(Kp / J_w) and the damping ratio stay the paper's on any robot; the paper's
    /// robot gets exactly (bit for bit) [`ServoGains::torque_default`]. Fixed gains gave
    /// a 120 kg robot the 5 kg robot's stiffness: its wheels could not hold the law's
    /// references, and the Lyapunov law stopped 137 deg off the goal heading.
    pub fn for_wheel_inertia(wheel_inertia: T) -> Self {
        let scale = wheel_inertia / crate::Robot::<T>::paper().driven_wheel_inertia();
        let paper = Self::torque_default();
        Self { kp: paper.kp * scale, kd: paper.kd * scale, ki: T::zero() }
    }

    /// DC-motor gains giving the wheel the stiffness and damping of `torque` (N m/rad,
    /// N m s/rad: [`ServoGains::for_wheel_inertia`]) through a motor of `torque_per_volt`
    /// b = k_tau / (R_a k_t) N m/V and back-EMF damping `emf_damping` b k_e / k_t
    /// N m s/rad at the wheel: Kp = Kp_tau / b V/rad and Kd = max(Kd_tau - b k_e / k_t, 0) / b
    /// V s/rad (the motor's own back-EMF damps the wheel already), Ki = 0. Where the
    /// back-EMF alone damps the wheel more than that (a small robot on a strong gear),
    /// the servo is overdamped and its slow pole sits near Kp_tau / (b k_e / k_t): the
    /// stiffness is then raised to at least (b k_e / k_t) w_b, w_b = sqrt(14 / J_w,paper)
    /// = 20.7 rad/s the paper's servo bandwidth, so the wheel still follows within
    /// 1 / w_b (the TurtleBot3 Burger's wheels, with 0.22 N m/rad against 0.23 N m s/rad
    /// of back-EMF, lagged by a second and the Lyapunov law stopped 30 deg off). For the
    /// default motor (Pololu 37D through k_t = 0.1: b = 0.1717 N m/V, 0.098 N m s/rad) on
    /// the paper's robot Kp = 81.5 and Kd = 7.58. Fixed gains for one motor left a
    /// stronger or weaker motor's wheels several times too stiff or too soft (with the
    /// maxon's 14 and 1.1 the Pololu's wheels were a fifth as stiff: the polar and
    /// Lyapunov laws circled the goal).
    pub fn for_dc_motor(torque: Self, torque_per_volt: T, emf_damping: T) -> Self {
        let kd = (torque.kd - emf_damping).max(T::zero()) / torque_per_volt;
        let kp = torque.kp.max(emf_damping * Self::paper_bandwidth());
        Self { kp: kp / torque_per_volt, kd, ki: T::zero() }
    }

    /// w_b = sqrt(Kp / J_w) of the paper's robot, rad/s (20.7): the bandwidth the derived
    /// gains keep on any robot.
    pub fn paper_bandwidth() -> T {
        (Self::torque_default().kp / crate::Robot::<T>::paper().driven_wheel_inertia()).sqrt()
    }

    pub(crate) fn validate(self) -> Result<Self, ParamError> {
        check::positive("servo_kp", self.kp)?;
        check::non_negative("servo_kd", self.kd)?;
        check::non_negative("servo_ki", self.ki)?;
        Ok(self)
    }
}

/// One wheel's position servo: its gains and integrator, for one run or several side by
/// side ([`crate::lane`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelServo<T: Lane> {
    gains: ServoGains<T::Scalar>,
    /// The drive's command limit (N m or V), which bounds the integral term.
    limit: T::Scalar,
    /// int (phi_ref - phi) dt, rad s.
    integral: T,
    /// Where the integral holds this tick (conditional integration: the wheel stage
    /// saturated at the last tick, [`super::WheelStage`]).
    pub(crate) hold: T::Mask,
    /// The angle error phi_ref - phi of the last update, rad.
    error: T,
}

impl<T: Real> WheelServo<T> {
    /// A servo with validated `gains` for a drive whose commands are limited to
    /// +-`limit` (errors name `servo_kp`, `servo_kd`, `servo_ki`).
    pub fn new(gains: ServoGains<T>, limit: T) -> Result<Self, ParamError> {
        Self::for_lanes(gains, limit)
    }
}

impl<T: Lane> WheelServo<T> {
    /// [`WheelServo::new`] for several runs side by side ([`crate::lane`]).
    pub fn for_lanes(gains: ServoGains<T::Scalar>, limit: T::Scalar) -> Result<Self, ParamError> {
        Ok(Self {
            gains: gains.validate()?,
            limit,
            integral: T::default(),
            hold: T::Mask::splat(false),
            error: T::default(),
        })
    }

    /// The gains.
    pub fn gains(&self) -> &ServoGains<T::Scalar> {
        &self.gains
    }

    /// Kp e + Ki int e, the integral advanced by e dt and kept within +-limit / Ki
    /// (where it does not hold).
    #[inline(always)]
    fn proportional_integral(&mut self, e: T, dt: T) -> T {
        let ki = self.gains.ki;
        self.error = e;
        let p = T::splat(self.gains.kp) * e;
        if ki > T::Scalar::zero() {
            let bound = T::splat(self.limit / ki);
            let next = (self.integral + e * dt).max(-bound).min(bound);
            self.integral = T::select(self.hold, self.integral, next);
            p + T::splat(ki) * self.integral
        } else {
            p + T::default()
        }
    }

    /// The paper's servo: Kp (phi_ref - phi) + Ki int(phi_ref - phi) - Kd omega, with the
    /// angles in rad, omega in rad/s and dt (the control period) in s.
    #[inline(always)]
    pub fn update(&mut self, phi_ref: T, phi: T, omega: T, dt: T) -> T {
        self.proportional_integral(phi_ref - phi, dt) - T::splat(self.gains.kd) * omega
    }

    /// Tracking a moving reference: Kp (phi_ref - phi) + Ki int(...) + Kd (omega_ref - omega).
    #[inline(always)]
    pub fn update_tracking(&mut self, phi_ref: T, omega_ref: T, phi: T, omega: T, dt: T) -> T {
        self.proportional_integral(phi_ref - phi, dt) + T::splat(self.gains.kd) * (omega_ref - omega)
    }

    /// The drive's command limit.
    pub fn limit(&self) -> T::Scalar {
        self.limit
    }

    /// Clears the integrator.
    pub fn reset(&mut self) {
        self.reset_lanes(T::Mask::splat(true));
    }

    /// Clears the integrator of the runs in `lanes` (several runs side by side).
    pub fn reset_lanes(&mut self, lanes: T::Mask) {
        self.integral = T::select(lanes, T::default(), self.integral);
        self.hold = self.hold & !lanes;
        self.error = T::select(lanes, T::default(), self.error);
    }

    /// What the integrator has yet to move the wheel, rad: an integrating servo (Ki > 0)
    /// brings its wheel onto the reference, so the angle error of the last update
    /// phi_ref - phi; zero without an integrator (the proportional error then stays).
    pub fn integrator_travel(&self) -> T {
        if self.gains.ki > T::Scalar::zero() { self.error } else { T::default() }
    }

    /// The integral term Ki int(phi_ref - phi), in command units (N m or V): what the
    /// integrator adds to the command now.
    pub fn integral_term(&self) -> T {
        T::splat(self.gains.ki) * self.integral
    }
}
