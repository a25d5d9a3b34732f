//! The paper's law with the per-wheel speed limit applied to its wheel angle references.
//!
//! The paper's controller ([`PaperController`]) commands absolute wheel *angles*
//! phi_ref = (u_s +- R u_theta) / r, which jump at the first tick (u_s = Kp_s e_s, tens of
//! rad for a goal metres away) and then move as the PI outputs do. Here the limit
//! `wheel_speed_max` (rad/s) bounds the speed at which the references the servos see
//! move: a [`WheelRateLimiter`] lets the limited references follow the law's by at most
//! `wheel_speed_max * control_dt` per tick on the faster wheel, both wheels' increments
//! scaled by one factor, so the ratio of the increments (the curvature of the commanded
//! motion, kappa = (dphi_r - dphi_l) / (R (dphi_r + dphi_l))) is kept.
//!
//! What it limits, precisely: the reference speed, not the wheel speed. The wheel
//! servos are the paper's (PD with the derivative on the measured speed), unchanged; a
//! wheel following a reference ramp at w_max lags it and can briefly overshoot w_max
//! when the ramp ends. The law's outer loop (its PI integrators, the hold) runs on the
//! true pose exactly as in [`PaperController`]; only the servos' references are limited.
//!
//! With an infinite limit use [`PaperController`] itself (as
//! [`super::ControllerParams::build`] does), which keeps its numbers bit for bit.

use super::saturation::WheelRateLimiter;
use super::{ControlOutput, Controller, Measurement, PaperController, PaperParams, WheelServo};
use crate::drive::Drive;
use crate::error::ParamError;
use crate::math::{Pose2, Wheels};
use crate::{Real, Robot};

/// [`PaperController`]'s outer loop, a [`WheelRateLimiter`] on its references, and the
/// paper's wheel servos. Implements [`Controller`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperSaturated<T> {
    law: PaperController<T>,
    limiter: WheelRateLimiter<T>,
    servo_r: WheelServo<T>,
    servo_l: WheelServo<T>,
    last_refs: Wheels<T>,
}

impl<T: Real> PaperSaturated<T> {
    /// Validates `params`, the goal and `wheel_speed_max` (rad/s, > 0, infinity allowed).
    pub fn new(
        params: PaperParams<T>,
        wheel_speed_max: T,
        robot: &Robot<T>,
        drive: &Drive<T>,
        goal: Pose2<T>,
    ) -> Result<Self, ParamError> {
        let law = PaperController::new(params, robot, drive, goal)?;
        let limiter = WheelRateLimiter::new(wheel_speed_max, params.control_dt)?;
        let servo = WheelServo::new(params.servo, drive.command_limit())?;
        Ok(Self { law, limiter, servo_r: servo, servo_l: servo, last_refs: Wheels::default() })
    }

    /// The paper's law (outer loop) inside.
    pub fn law(&self) -> &PaperController<T> {
        &self.law
    }

    /// The wheel speed limit, rad/s.
    pub fn wheel_speed_max(&self) -> T {
        self.limiter.w_max()
    }

    /// The limited wheel angle references of the last tick, rad.
    pub fn last_angle_refs(&self) -> Wheels<T> {
        self.last_refs
    }
}

impl<T: Real> Controller<T> for PaperSaturated<T> {
    #[inline]
    fn update(&mut self, m: &Measurement<T>) -> ControlOutput<T> {
        let (target, errors) = self.law.references(m.pose);
        let refs = self.limiter.limit(target, m.wheel_angles);
        self.last_refs = refs;
        let dt = self.law.control_dt();
        let command = Wheels::new(
            self.servo_r.update(refs.right, m.wheel_angles.right, m.wheel_speeds.right, dt),
            self.servo_l.update(refs.left, m.wheel_angles.left, m.wheel_speeds.left, dt),
        );
        ControlOutput { command, errors }
    }

    fn reset(&mut self) {
        self.law.reset();
        self.limiter.reset();
        self.servo_r.reset();
        self.servo_l.reset();
        self.last_refs = Wheels::default();
    }

    fn control_dt(&self) -> T {
        self.law.control_dt()
    }

    fn goal(&self) -> Pose2<T> {
        self.law.goal()
    }
}
