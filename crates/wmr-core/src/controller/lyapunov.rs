//! Aicardi, Casalino, Bicchi and Balestrino's Lyapunov law in polar coordinates: reaches
//! the goal position and the goal heading exactly.
//!
//! Source: M. Aicardi, G. Casalino, A. Bicchi, A. Balestrino, "Closed loop steering of
//! unicycle-like vehicles via Lyapunov techniques", IEEE Robotics & Automation Magazine
//! 2(1), 1995, pp. 27-35. Coordinates as in [`super::polar_frame`]: e = rho (m), alpha (rad),
//! and the goal-frame angle of the vector from C to the goal, theta_A = -beta (rad). In the
//! driving frame the kinematics are
//!
//! ```text
//! e'       = -u cos(alpha)
//! alpha'   = -omega + u sin(alpha) / e
//! theta_A' =  u sin(alpha) / e
//! ```
//!
//! With the Lyapunov function V = lambda e^2 / 2 + (alpha^2 + h theta_A^2) / 2 the law
//!
//! ```text
//! u     = gamma cos(alpha) e                                                m/s
//! omega = k alpha + gamma (cos(alpha) sin(alpha) / alpha) (alpha + h theta_A)   rad/s
//! ```
//!
//! gives V' = -lambda gamma cos^2(alpha) e^2 - k alpha^2 <= 0 for every lambda > 0, so
//! W = alpha^2 + h theta_A^2 never increases (the tests check this on the dynamic robot)
//! and e, alpha, theta_A -> 0: position and heading (theta_d - theta = alpha - theta_A)
//! both converge. Gain conditions, checked at construction: gamma > 0 (1/s), k > 0 (1/s),
//! h > 0 (dimensionless); errors name `controller.gamma`, `controller.k`, `controller.h`.
//!
//! Choosing the gains: linearized about the goal, e decays at rate gamma and the angular
//! subsystem (alpha' = -k alpha - gamma h theta_A, theta_A' = gamma alpha, which does not
//! depend on e) with the roots of s^2 + k s + gamma^2 h. When both roots are faster than
//! gamma the heading error shrinks faster than the distance, so it is essentially zero
//! by the time the robot stops at `goal_radius`. The defaults (gamma = 0.5, k = 3, h = 9)
//! put a double root at k/2 = 1.5 1/s, three times gamma. With gamma = 0.5, k = 3, h = 4.5
//! the slow root is 0.44 1/s, below gamma: the heading then lags the distance and a
//! robot stopped at 1 mm keeps a heading error of about 2 deg (measured).
//!
//! u changes sign with cos(alpha), so the law backs up by itself, but alpha is wrapped
//! into (-pi, pi] and omega jumps at alpha = +-pi. As for [`super::PolarController`] the
//! driving direction is therefore chosen at the first tick (backwards when the goal is
//! behind, with the coordinates redefined in the reversed frame) and later switched only
//! with hysteresis; starting with |alpha| <= pi/2 also keeps |alpha| <= sqrt(W(0)) small.
//! sin(alpha)/alpha is taken as 1 at alpha = 0. Within `goal_radius` of the goal the law
//! stops (v = omega = 0, wheels hold) until the robot is pushed out to twice that distance.
//!
//! Logged errors ([`ControlErrors`]): dl = e; e_theta = wrap(theta_d - theta), the heading
//! error the law drives to zero; e_s = (x_d - x) cos(theta) + (y_d - y) sin(theta), the
//! signed distance to the goal along the heading.

use super::polar::{check_goal, goal_hold, polar_errors};
use super::polar_frame::{Direction, DirectionSelector, PolarCoords};
use super::saturation::check_wheel_speed_max;
use super::{ControlErrors, ControlOutput, Controller, Measurement, ServoGains, TwistServo};
use crate::drive::Drive;
use crate::error::{ParamError, check};
use crate::math::{Pose2, Twist2};
use crate::{Real, Robot};

/// `[controller] kind = "lyapunov"` parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LyapunovParams<T> {
    /// gamma, 1/s (`gamma`): forward speed per metre of distance, times cos(alpha). > 0.
    pub gamma: T,
    /// k, 1/s (`k`): yaw rate per rad of alpha. > 0.
    pub k: T,
    /// h, dimensionless (`h`): weight of theta_A against alpha in V. > 0.
    pub h: T,
    /// Drive backwards when the goal is behind (`reverse`); false always starts forward.
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

impl<T: Real> Default for LyapunovParams<T> {
    /// gamma = 0.5, k = 3, h = 9 (module docs), reverse on with pi/6 hysteresis,
    /// goal_radius 1 mm, no wheel speed limit, torque-drive servo, 1 ms.
    fn default() -> Self {
        Self {
            gamma: T::lit(0.5),
            k: T::lit(3.0),
            h: T::lit(9.0),
            reverse: true,
            reverse_hysteresis: T::lit(core::f64::consts::FRAC_PI_6),
            goal_radius: T::lit(1e-3),
            wheel_speed_max: T::infinity(),
            servo: ServoGains::torque_default(),
            control_dt: T::lit(1e-3),
        }
    }
}

impl<T: Real> LyapunovParams<T> {
    /// Checks every field; errors name the key.
    pub fn validate(&self) -> Result<(), ParamError> {
        check::positive("controller.gamma", self.gamma)?;
        check::positive("controller.k", self.k)?;
        check::positive("controller.h", self.h)?;
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

/// Aicardi et al.'s law driving the wheel servos. Implements [`Controller`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LyapunovController<T> {
    params: LyapunovParams<T>,
    goal: Pose2<T>,
    direction: DirectionSelector<T>,
    held: bool,
    wheels: TwistServo<T>,
}

impl<T: Real> LyapunovController<T> {
    /// Validates `params` and the goal pose (m, m, rad) for this robot and drive.
    pub fn new(
        params: LyapunovParams<T>,
        robot: &Robot<T>,
        drive: &Drive<T>,
        goal: Pose2<T>,
    ) -> Result<Self, ParamError> {
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
    pub fn params(&self) -> &LyapunovParams<T> {
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

    /// W = alpha^2 + h theta_A^2 (rad^2) of `pose` in driving direction `dir`: the angular
    /// part of the law's Lyapunov function, non-increasing along the kinematic closed loop.
    pub fn angular_lyapunov(&self, pose: Pose2<T>, dir: Direction) -> T {
        let c = PolarCoords::new(pose, self.goal, dir);
        c.alpha * c.alpha + self.params.h * c.beta * c.beta
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
        let (e, alpha, theta_a) = (c.rho, c.alpha, -c.beta);
        let (sin_a, cos_a) = alpha.sin_cos_libm();
        let sinc = if alpha.abs() < T::epsilon() { T::one() } else { sin_a / alpha };
        let u = p.gamma * cos_a * e;
        let omega = p.k * alpha + p.gamma * cos_a * sinc * (alpha + p.h * theta_a);
        (Twist2 { v: dir.sign::<T>() * u, omega }, errors)
    }
}

impl<T: Real> Controller<T> for LyapunovController<T> {
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
