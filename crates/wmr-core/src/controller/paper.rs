//! The paper's point-stabilization law (section 3, SPEC section 4): a "moving false
//! target" R, two PI loops on (e_s, e_theta), the inverse of (20) to wheel angle
//! references, and two wheel position servos.
//!
//! ```text
//! dl = hypot(x_d - x, y_d - y)                      (16)
//! alpha = atan2(y_d - y, x_d - x)                   (17)
//! theta_R = 2 alpha - theta_d  (pose)  | alpha  (position)     (21)
//! e_theta = wrap(theta_R - theta),  e_s = dl cos(theta_R - theta)   (18), (23)
//! u_theta = Kp_t e_theta + Ki_t int e_theta,  u_s = Kp_s e_s + Ki_s int e_s   (22), (24)
//! phi_r_ref = (u_s + R u_theta) / r,  phi_l_ref = (u_s - R u_theta) / r       (20)^-1
//! ```
//!
//! The references are absolute wheel angles (the integration constant of (20) is
//! neglected, as the paper says, because the encoders start at zero).

use super::{ControlErrors, ControlOutput, Controller, Measurement, ServoGains, WheelServo};
use crate::drive::Drive;
use crate::error::{ParamError, check};
use crate::math::{Pose2, Wheels, wrap_angle};
use crate::{Real, Robot};

/// Which of the paper's two problems to solve (section 2.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PaperMode {
    /// Orientating control: reach (x_d, y_d, theta_d); theta_R = 2 alpha - theta_d.
    #[default]
    Pose,
    /// Positioning control: reach (x_d, y_d), heading free; theta_R = alpha.
    Position,
}

/// What the law does inside `hold_radius`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HoldMode {
    /// SPEC section 4, step 7: the outer errors are taken as zero and the integrators
    /// stop, so u = Ki int. The wheel references step on entry (the Kp e parts drop
    /// out); on Fig. 7 that kick is what brings the heading error from 28 to 5 deg.
    #[default]
    ZeroErrors,
    /// Bumpless: the wheel references of the last tick outside the radius are kept and
    /// the integrators stop. The robot stays where it entered the radius (position mode
    /// then converges; pose mode keeps the heading error it had at entry).
    Freeze,
}

/// `[controller] kind = "paper"` parameters (SPEC section 4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperParams<T> {
    /// Pose or position mode.
    pub mode: PaperMode,
    /// Kp_theta, rad of heading command per rad of error (paper: 2).
    pub kp_theta: T,
    /// Ki_theta, 1/s (paper: 0.1).
    pub ki_theta: T,
    /// Kp_s, m of path command per m of error (paper: 1).
    pub kp_s: T,
    /// Ki_s, 1/s (paper: 0.25).
    pub ki_s: T,
    /// Wheel servo gains (units follow the drive).
    pub servo: ServoGains<T>,
    /// Within this distance of the goal (m) alpha keeps its last value.
    pub goal_radius: T,
    /// Within this distance of the goal (m) the outer errors are zero and the outer
    /// integrators stop; 0 turns the hold off.
    pub hold_radius: T,
    /// How the hold behaves (`hold`): [`HoldMode::ZeroErrors`] (SPEC) or [`HoldMode::Freeze`].
    pub hold: HoldMode,
    /// Control period, s.
    pub control_dt: T,
}

impl<T: Real> PaperParams<T> {
    /// The paper's gains with the SPEC's servo, radii and period, for the torque drive.
    pub fn paper() -> Self {
        Self {
            mode: PaperMode::Pose,
            kp_theta: T::lit(2.0),
            ki_theta: T::lit(0.1),
            kp_s: T::lit(1.0),
            ki_s: T::lit(0.25),
            servo: ServoGains::torque_default(),
            goal_radius: T::lit(1e-3),
            hold_radius: T::lit(5e-3),
            hold: HoldMode::ZeroErrors,
            control_dt: T::lit(1e-3),
        }
    }
}

impl<T: Real> Default for PaperParams<T> {
    fn default() -> Self {
        Self::paper()
    }
}

/// The paper's controller with its two wheel servos. Implements [`Controller`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperController<T> {
    params: PaperParams<T>,
    goal: Pose2<T>,
    /// r, m and R, m, for the inverse of (20).
    wheel_radius: T,
    half_track: T,
    servo_r: WheelServo<T>,
    servo_l: WheelServo<T>,
    /// int e_theta dt, rad s.
    int_e_theta: T,
    /// int e_s dt, m s.
    int_e_s: T,
    /// alpha of the last tick outside `goal_radius`, rad.
    last_alpha: Option<T>,
    /// Wheel references of the last tick, rad ([`HoldMode::Freeze`] keeps them).
    last_refs: Option<Wheels<T>>,
}

impl<T: Real> PaperController<T> {
    /// Validates `params` and the goal pose (m, m, rad) for this robot and drive.
    pub fn new(params: PaperParams<T>, robot: &Robot<T>, drive: &Drive<T>, goal: Pose2<T>) -> Result<Self, ParamError> {
        check::non_negative("controller.kp_theta", params.kp_theta)?;
        check::non_negative("controller.ki_theta", params.ki_theta)?;
        check::non_negative("controller.kp_s", params.kp_s)?;
        check::non_negative("controller.ki_s", params.ki_s)?;
        check::non_negative("controller.goal_radius", params.goal_radius)?;
        check::non_negative("controller.hold_radius", params.hold_radius)?;
        check::positive("controller.control_dt", params.control_dt)?;
        check::finite("run.goal.x", goal.x)?;
        check::finite("run.goal.y", goal.y)?;
        check::finite("run.goal.theta", goal.theta)?;
        let limit = drive.command_limit();
        let servo = WheelServo::new(params.servo, limit)?;
        let p = robot.params();
        Ok(Self {
            params,
            goal,
            wheel_radius: p.wheel_radius,
            half_track: p.half_track,
            servo_r: servo,
            servo_l: servo,
            int_e_theta: T::zero(),
            int_e_s: T::zero(),
            last_alpha: None,
            last_refs: None,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &PaperParams<T> {
        &self.params
    }

    /// The outer loop alone: errors and wheel angle references (rad), advancing the PI
    /// integrators by one control period.
    #[inline]
    pub fn references(&mut self, pose: Pose2<T>) -> (Wheels<T>, ControlErrors<T>) {
        let p = &self.params;
        let dx = self.goal.x - pose.x;
        let dy = self.goal.y - pose.y;
        let dl = dx.hypot_libm(dy);
        let alpha = if dl > p.goal_radius {
            let a = dy.atan2_libm(dx);
            self.last_alpha = Some(a);
            a
        } else {
            // At the goal alpha is undefined: keep the last one, or start from the
            // value that makes theta_R the goal heading (pose) or the current one.
            self.last_alpha.unwrap_or(match p.mode {
                PaperMode::Pose => self.goal.theta,
                PaperMode::Position => pose.theta,
            })
        };
        let theta_ref = match p.mode {
            PaperMode::Pose => alpha + alpha - self.goal.theta,
            PaperMode::Position => alpha,
        };
        // Hold (SPEC section 4, step 7): inside hold_radius the outer errors are taken
        // as zero and the integrators stop, so u = Ki * int and the references stay put.
        // Note the step on entry: the proportional parts Kp e drop out at once.
        let in_hold = p.hold_radius > T::zero() && dl < p.hold_radius;
        if in_hold
            && p.hold == HoldMode::Freeze
            && let Some(refs) = self.last_refs
        {
            return (refs, ControlErrors { e_s: T::zero(), e_theta: T::zero(), dl });
        }
        let (e_s, e_theta) = if in_hold {
            (T::zero(), T::zero())
        } else {
            let diff = theta_ref - pose.theta;
            let e_s = dl * diff.cos_libm();
            let e_theta = wrap_angle(diff);
            // Forward-Euler sums that include the current error.
            self.int_e_s = self.int_e_s + e_s * p.control_dt;
            self.int_e_theta = self.int_e_theta + e_theta * p.control_dt;
            (e_s, e_theta)
        };
        let u_s = p.kp_s * e_s + p.ki_s * self.int_e_s;
        let u_theta = p.kp_theta * e_theta + p.ki_theta * self.int_e_theta;
        let turn = self.half_track * u_theta;
        let refs = Wheels::new((u_s + turn) / self.wheel_radius, (u_s - turn) / self.wheel_radius);
        self.last_refs = Some(refs);
        (refs, ControlErrors { e_s, e_theta, dl })
    }
}

impl<T: Real> Controller<T> for PaperController<T> {
    #[inline]
    fn update(&mut self, m: &Measurement<T>) -> ControlOutput<T> {
        let (refs, errors) = self.references(m.pose);
        let dt = self.params.control_dt;
        let command = Wheels::new(
            self.servo_r.update(refs.right, m.wheel_angles.right, m.wheel_speeds.right, dt),
            self.servo_l.update(refs.left, m.wheel_angles.left, m.wheel_speeds.left, dt),
        );
        ControlOutput { command, errors }
    }

    fn reset(&mut self) {
        self.servo_r.reset();
        self.servo_l.reset();
        self.int_e_theta = T::zero();
        self.int_e_s = T::zero();
        self.last_alpha = None;
        self.last_refs = None;
    }

    fn control_dt(&self) -> T {
        self.params.control_dt
    }

    fn goal(&self) -> Pose2<T> {
        self.goal
    }
}
