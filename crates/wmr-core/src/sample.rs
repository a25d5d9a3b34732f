//! What the loop logs at one instant: the true state, the wheel torques and the
//! controller's diagnostic errors.

use crate::controller::ControlErrors;
use crate::math::{Pose2, Twist2, Wheels};
use crate::state::State;
use crate::traction::Contact;

/// Everything logged at one instant (the CSV columns of `docs/scenario.md`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample<T> {
    /// Time, s.
    pub t: T,
    /// The true state of the plant at `t`.
    pub state: State<T>,
    /// True wheel speeds at `t`, rad/s.
    pub wheel_speeds: Wheels<T>,
    /// Wheel torques applied from `t` on, N m.
    pub torque: Wheels<T>,
    /// The controller's errors of the last control tick at or before `t` (what each law
    /// logs is in [`crate::controller::ControlErrors`]).
    pub errors: ControlErrors<T>,
    /// The pose of C the controller used at the last control tick at or before `t`
    /// (what its sensor delivered: late, noisy; the true pose for a perfect sensor).
    pub measured: Pose2<T>,
    /// The wheels' contact with the ground at `t`: slip velocities, forces and loads
    /// (zero for a rolling plant, [`crate::traction`]).
    pub contact: Contact<T>,
    /// The pose of C dead-reckoned from the encoders at that tick, for an odometry sensor
    /// (`measured` is then the fused pose, [`crate::sensor::odometry`]); `None` otherwise.
    pub odometry: Option<Pose2<T>>,
    /// The body twist the law demanded at the last control tick at or before `t` (v m/s,
    /// omega rad/s, before the wheel stage's limits: ROS 2's `/cmd_vel`); `None` for a
    /// law that demands wheel angles or torques ([`crate::LawSpec::TWIST_DEMAND`]).
    pub twist_demand: Option<Twist2<T>>,
    /// The covariance of `measured` (x, y, theta: m^2, m rad, rad^2) at that tick, for a
    /// sensor that estimates one (the odometry's EKF: ROS 2's `/odom` pose covariance);
    /// `None` otherwise.
    pub pose_covariance: Option<[[T; 3]; 3]>,
    /// The disturbance observer's estimate of the disturbance torque at each wheel at
    /// the last control tick at or before `t` (N m, [`crate::controller::observer`]);
    /// `None` without an observer.
    pub disturbance: Option<Wheels<T>>,
}
