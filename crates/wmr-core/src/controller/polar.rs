//! Astolfi's polar-coordinates point-stabilization law (rho, alpha, beta) -> (v, omega),
//! with backward driving when the goal lies behind.
//!
//! Source: A. Astolfi, "Exponential stabilization of a wheeled mobile robot via
//! discontinuous control", J. Dyn. Sys. Meas. Control 121 (1999); in the form of
//! Siegwart, Nourbakhsh, Scaramuzza, "Introduction to Autonomous Mobile Robots", 2nd ed.,
//! section 3.6.2.4 (also P. Corke, "Robotics, Vision and Control", drive to a pose, and
//! PythonRobotics `move_to_pose`). Coordinates (rho in m, alpha and beta in rad) as in
//! [`super::polar_frame`]; in the driving frame the kinematics are
//!
//! ```text
//! rho'   = -v cos(alpha)
//! alpha' =  v sin(alpha) / rho - omega
//! beta'  = -v sin(alpha) / rho
//! ```
//!
//! and the law is
//!
//! ```text
//! v     = s k_rho rho                         m/s   (s = +1 forward, -1 backward)
//! omega = k_alpha alpha + k_beta beta         rad/s
//! ```
//!
//! with gains in 1/s. Linearized about the goal the loop is
//! (s + k_rho)(s^2 + (k_alpha - k_rho) s - k_rho k_beta), stable for
//!
//! ```text
//! k_rho > 0,  k_beta < 0,  k_alpha - k_rho > 0,
//! ```
//!
//! and Siegwart's strong-stability condition
//!
//! ```text
//! k_alpha + 5/3 k_beta - 2/pi k_rho > 0
//! ```
//!
//! guarantees that alpha never leaves I1 = (-pi/2, pi/2] once in it, so the robot never
//! reverses its direction of motion on the way. All four are checked at construction
//! (errors name `controller.k_rho`, `controller.k_beta` or `controller.k_alpha`).
//! PythonRobotics' `move_to_pose` negates v when the goal is behind but keeps alpha and
//! beta of the forward frame, so alpha stays near +-pi, outside the region the stability
//! argument covers. Here the backward case redefines the polar coordinates in the
//! reversed frame ([`super::polar_frame`]); the direction is decided at the first tick
//! and later switched only with hysteresis (`reverse_hysteresis`).
//!
//! Near the goal: alpha + beta = theta_d - theta, so the heading converges with alpha and
//! beta, at the rate of the slower angular mode (the smaller root of
//! s^2 + (k_alpha - k_rho) s - k_rho k_beta). Gains that satisfy the strong condition
//! tend to make it slower than k_rho (with the defaults it is 0.27 1/s = 0.54 k_rho), so
//! the heading settles more slowly than the distance and a robot stopped at 1 mm keeps a
//! heading error of up to a few degrees (measured 0.4 to 5 deg); use
//! [`super::LyapunovController`] when the heading matters. Within `goal_radius` of the
//! goal the law stops (v = omega = 0, the wheels hold their angles) until the robot is
//! pushed out to twice that distance.
//!
//! The twist goes to the wheels through [`super::TwistServo`]: wheel speed references
//! by the inverse of (1), the curvature-keeping `wheel_speed_max` limit, and the wheel
//! position servos tracking the integrated references.
//!
//! Logged errors ([`ControlErrors`]): dl = rho; e_theta = wrap(theta_d - theta), the
//! heading error the law drives to zero (= alpha + beta); e_s = (x_d - x) cos(theta) +
//! (y_d - y) sin(theta), the signed distance to the goal along the heading.

use super::polar_frame::{Direction, DirectionSelector};
use super::saturation::check_wheel_speed_max;
use super::{ControlErrors, ControlOutput, Controller, Measurement, ServoGains, TwistServo};
use crate::drive::Drive;
use crate::error::{ParamError, check};
use crate::math::{Pose2, Twist2, wrap_angle};
use crate::{Real, Robot};

/// `[controller] kind = "polar"` parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolarParams<T> {
    /// k_rho, 1/s (`k_rho`): forward speed per metre of distance. Must be > 0.
    pub k_rho: T,
    /// k_alpha, 1/s (`k_alpha`): yaw rate per rad of alpha. Must exceed k_rho and satisfy
    /// k_alpha + 5/3 k_beta - 2/pi k_rho > 0.
    pub k_alpha: T,
    /// k_beta, 1/s (`k_beta`): yaw rate per rad of beta. Must be < 0.
    pub k_beta: T,
    /// Drive backwards when the goal is behind (`reverse`); false always drives forward.
    pub reverse: bool,
    /// Overshoot of |alpha| past pi/2, rad, before a later direction switch (`reverse_hysteresis`).
    pub reverse_hysteresis: T,
    /// Within this distance of the goal, m, the law stops (`goal_radius`).
    pub goal_radius: T,
    /// Per-wheel speed limit, rad/s, curvature kept; infinity = off (`wheel_speed_max`).
    pub wheel_speed_max: T,
    /// Wheel servo gains (units follow the drive).
    pub servo: ServoGains<T>,
    /// Control period, s (`control_dt`).
    pub control_dt: T,
}

impl<T: Real> Default for PolarParams<T> {
    /// k_rho = 0.5, k_alpha = 3, k_beta = -1.2 (strong-stability margin 0.68 1/s; slow
    /// angular mode 0.27 1/s), reverse on with pi/6 hysteresis, goal_radius 1 mm, no
    /// wheel speed limit, torque-drive servo, 1 ms.
    fn default() -> Self {
        Self {
            k_rho: T::lit(0.5),
            k_alpha: T::lit(3.0),
            k_beta: T::lit(-1.2),
            reverse: true,
            reverse_hysteresis: T::lit(core::f64::consts::FRAC_PI_6),
            goal_radius: T::lit(1e-3),
            wheel_speed_max: T::infinity(),
            servo: ServoGains::torque_default(),
            control_dt: T::lit(1e-3),
        }
    }
}

impl<T: Real> PolarParams<T> {
    /// Checks every field; gain errors name the key and the violated condition.
    pub fn validate(&self) -> Result<(), ParamError> {
        let k_rho = check::positive("controller.k_rho", self.k_rho)?;
        let k_alpha = check::finite("controller.k_alpha", self.k_alpha)?;
        let k_beta = check::finite("controller.k_beta", self.k_beta)?;
        if k_beta >= T::zero() {
            return Err(check::out_of_range("controller.k_beta", "must be < 0", k_beta));
        }
        if k_alpha - k_rho <= T::zero() {
            return Err(check::out_of_range("controller.k_alpha", "must be > k_rho", k_alpha));
        }
        let strong = k_alpha + T::lit(5.0 / 3.0) * k_beta - T::FRAC_2_PI() * k_rho;
        if strong <= T::zero() {
            return Err(check::out_of_range(
                "controller.k_alpha",
                "must satisfy k_alpha + 5/3 k_beta - 2/pi k_rho > 0 (strong stability)",
                k_alpha,
            ));
        }
        check::non_negative("controller.reverse_hysteresis", self.reverse_hysteresis)?;
        if self.reverse_hysteresis >= T::FRAC_PI_2() {
            return Err(check::out_of_range(
                "controller.reverse_hysteresis",
                "must be < pi/2",
                self.reverse_hysteresis,
            ));
        }
        check::non_negative("controller.goal_radius", self.goal_radius)?;
        check_wheel_speed_max(self.wheel_speed_max)?;
        check::positive("controller.control_dt", self.control_dt)?;
        Ok(())
    }
}

/// Validates the goal pose (m, m, rad).
pub(crate) fn check_goal<T: Real>(goal: Pose2<T>) -> Result<(), ParamError> {
    check::finite("run.goal.x", goal.x)?;
    check::finite("run.goal.y", goal.y)?;
    check::finite("run.goal.theta", goal.theta)?;
    Ok(())
}

/// The errors every polar-coordinate law logs (module docs).
#[inline]
pub(crate) fn polar_errors<T: Real>(pose: Pose2<T>, goal: Pose2<T>) -> ControlErrors<T> {
    let dx = goal.x - pose.x;
    let dy = goal.y - pose.y;
    let (s, c) = pose.theta.sin_cos_libm();
    ControlErrors { e_s: dx * c + dy * s, e_theta: wrap_angle(goal.theta - pose.theta), dl: dx.hypot_libm(dy) }
}

/// Stop inside `radius`, resume beyond twice that: returns the new "held" flag.
#[inline]
pub(crate) fn goal_hold<T: Real>(held: bool, dl: T, radius: T) -> bool {
    if held { dl <= radius + radius } else { dl <= radius }
}

/// Astolfi's polar law driving the wheel servos. Implements [`Controller`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolarController<T> {
    params: PolarParams<T>,
    goal: Pose2<T>,
    direction: DirectionSelector<T>,
    held: bool,
    wheels: TwistServo<T>,
}

impl<T: Real> PolarController<T> {
    /// Validates `params` and the goal pose (m, m, rad) for this robot and drive.
    pub fn new(params: PolarParams<T>, robot: &Robot<T>, drive: &Drive<T>, goal: Pose2<T>) -> Result<Self, ParamError> {
        params.validate()?;
        check_goal(goal)?;
        let wheels = TwistServo::new(
            robot.params(),
            params.wheel_speed_max,
            params.servo,
            drive.command_limit(),
            params.control_dt,
        )?;
        Ok(Self {
            params,
            goal,
            direction: DirectionSelector::new(params.reverse, params.reverse_hysteresis),
            held: false,
            wheels,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &PolarParams<T> {
        &self.params
    }

    /// The driving direction in use (None before the first tick).
    pub fn direction(&self) -> Option<Direction> {
        self.direction.current()
    }

    /// The wheel-speed path: last twist of the law (before the limit) and wheel speed references.
    pub fn wheels(&self) -> &TwistServo<T> {
        &self.wheels
    }

    /// The law alone: the twist (v in m/s, omega in rad/s) for `pose`, and the errors.
    #[inline]
    pub fn twist(&mut self, pose: Pose2<T>) -> (Twist2<T>, ControlErrors<T>) {
        let errors = polar_errors(pose, self.goal);
        self.held = goal_hold(self.held, errors.dl, self.params.goal_radius);
        if self.held {
            return (Twist2::default(), errors);
        }
        let p = &self.params;
        let (dir, c) = self.direction.select(pose, self.goal);
        let v = dir.sign::<T>() * p.k_rho * c.rho;
        let omega = p.k_alpha * c.alpha + p.k_beta * c.beta;
        (Twist2 { v, omega }, errors)
    }
}

impl<T: Real> Controller<T> for PolarController<T> {
    #[inline]
    fn update(&mut self, m: &Measurement<T>) -> ControlOutput<T> {
        let (twist, errors) = self.twist(m.pose);
        ControlOutput { command: self.wheels.command(twist, m), errors }
    }

    fn reset(&mut self) {
        self.direction.reset();
        self.held = false;
        self.wheels.reset();
    }

    fn control_dt(&self) -> T {
        self.params.control_dt
    }

    fn goal(&self) -> Pose2<T> {
        self.goal
    }
}
