//! Closed-loop controllers: the common interface, the paper's law and the wheel servos.

mod paper;
mod servo;

pub use paper::{HoldMode, PaperController, PaperMode, PaperParams};
pub use servo::{ServoGains, WheelServo};

// More stabilization laws (issue 7), their wheel-speed path and run-time selection.
mod any;
mod lyapunov;
mod paper_saturated;
mod polar;
pub mod polar_frame;
pub mod saturation;
mod speed_servo;

pub use any::{AnyController, ControllerKind, ControllerParams};
pub use lyapunov::{LyapunovController, LyapunovParams};
pub use paper_saturated::PaperSaturated;
pub use polar::{PolarController, PolarParams};
pub use polar_frame::{Direction, DirectionSelector, PolarCoords};
pub use saturation::{WheelRateLimiter, limit_twist, limit_wheel_speeds, wheel_speed_scale};
pub use speed_servo::{SpeedServo, TwistServo};

use crate::Real;
use crate::math::{Pose2, Wheels};

/// What a controller measures at each control tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measurement<T> {
    /// Pose of C in the world frame (the paper's "global positioning system").
    pub pose: Pose2<T>,
    /// Wheel angles from the encoders, rad (zero at start).
    pub wheel_angles: Wheels<T>,
    /// Wheel speeds, rad/s.
    pub wheel_speeds: Wheels<T>,
}

/// The controller's errors, logged with every sample (SPEC section 6 columns).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ControlErrors<T> {
    /// e_s, the distance to the false target along the heading, m ((18), (23)).
    pub e_s: T,
    /// e_theta, the heading error, rad ((21)), wrapped into (-pi, pi].
    pub e_theta: T,
    /// dl, the distance from C to the goal position, m ((16)).
    pub dl: T,
}

/// One control tick's result: the drive commands, held until the next tick, and the errors.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ControlOutput<T> {
    /// Per-wheel drive command: wheel torque demand (N m) or voltage (V), by drive kind.
    pub command: Wheels<T>,
    /// Errors for logging.
    pub errors: ControlErrors<T>,
}

/// A discrete-time controller that runs every [`Controller::control_dt`] seconds.
pub trait Controller<T: Real> {
    /// Computes the commands from a measurement; called once per control period.
    fn update(&mut self, m: &Measurement<T>) -> ControlOutput<T>;
    /// Clears integrators and memories, as at t = 0.
    fn reset(&mut self);
    /// Control period, s.
    fn control_dt(&self) -> T;
    /// The goal pose of C.
    fn goal(&self) -> Pose2<T>;
}
