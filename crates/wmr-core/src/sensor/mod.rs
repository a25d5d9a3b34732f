//! What the controller sees of the plant: a [`Measurement`] made by a [`Sensor`].
//!
//! The paper assumes "a global positioning system that measures the Cartesian
//! coordinates and the orientating angle" and wheel encoders: [`PerfectSensor`] gives
//! exactly that, the true pose and wheel state at the instant of the control tick.
//! [`PoseSensor`] is the real one: a pose sampled at its own rate, late, noisy, and
//! quantized wheel encoders ([`pose_sensor`]), a chain of the [`stage`]s a real sensor
//! has (sampling, noise, latency, encoders); [`gaussian`] draws its noise.
//! [`OdometrySensor`] hands the controller the pose dead-reckoned from the encoders
//! ([`dead_reckoning`]) and fused with optional absolute fixes by the pose EKF ([`ekf`]),
//! as `[sensor] pose = "odometry"` asks ([`odometry`]); [`AnySensor`] is either ([`any`]).

pub mod any;
pub mod dead_reckoning;
pub mod ekf;
pub mod gaussian;
pub mod odometry;
pub mod pose_sensor;
pub mod stage;

pub use any::AnySensor;
pub use odometry::{OdometryParams, OdometrySensor, PoseSource};
pub use pose_sensor::{PoseSensor, SensorParams};

use crate::math::{Pose2, Wheels};
use crate::state::State;
use crate::{Real, RobotParams};

/// What a controller measures at one control tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measurement<T> {
    /// When the measurement was taken, s (simulation time).
    pub t: T,
    /// Pose of C in the world frame: x, y in m, theta in rad.
    pub pose: Pose2<T>,
    /// Wheel angles from the encoders, rad (zero at start).
    pub wheel_angles: Wheels<T>,
    /// Wheel speeds, rad/s: each wheel's own rotation rate, as an encoder sees it (for
    /// wheels that slip it differs from (v +- R omega) / r, the body's).
    pub wheel_speeds: Wheels<T>,
}

/// Turns the true state into what the controller sees.
pub trait Sensor<T: Real> {
    /// The measurement handed to the controller at time `t` (s), given the plant's true
    /// `state` and the true robot, for wheels that roll: each wheel turns at
    /// (v +- R omega) / r ([`State::wheel_speeds`]).
    fn measure(&mut self, t: T, state: &State<T>, robot: &RobotParams<T>) -> Measurement<T>;

    /// [`Sensor::measure`] of a plant whose wheels turn at `wheel_speeds` (rad/s, each
    /// wheel's own rotation rate, [`crate::Plant::wheel_speeds`]): what the closed loop
    /// calls. Wheels that slip turn at their own speed, not at the body's
    /// (v +- R omega) / r, and an encoder measures the wheel. The sensors of
    /// this crate measure `wheel_speeds`; a sensor that does not override this method
    /// measures as [`Sensor::measure`] does, the body's speeds.
    fn measure_wheels(
        &mut self,
        t: T,
        state: &State<T>,
        wheel_speeds: Wheels<T>,
        robot: &RobotParams<T>,
    ) -> Measurement<T> {
        let _ = wheel_speeds;
        self.measure(t, state, robot)
    }

    /// Forgets any memory (buffers, filters), as at t = 0.
    fn reset(&mut self) {}

    /// True when the measurement is a function of the true state alone (no noise): a
    /// loop that has come to rest stays at rest. A noisy sensor keeps the controller
    /// moving, and its runs are never stopped early ([`crate::settle`]).
    fn deterministic(&self) -> bool {
        true
    }

    /// The pose of C dead-reckoned from the encoders at the last measurement (world
    /// frame), for a sensor that keeps one (logged beside the pose it hands the controller).
    fn odometry(&self) -> Option<Pose2<T>> {
        None
    }

    /// The covariance of the pose handed to the controller at the last measurement
    /// (x, y, theta: m^2, m rad, rad^2), for a sensor that estimates one (the odometry's
    /// EKF, [`odometry::OdometrySensor::covariance`]).
    fn pose_covariance(&self) -> Option<ekf::Mat3<T>> {
        None
    }
}

/// The true pose and wheel state, instantly: the paper's assumption.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PerfectSensor;

impl<T: Real> Sensor<T> for PerfectSensor {
    #[inline(always)]
    fn measure(&mut self, t: T, state: &State<T>, robot: &RobotParams<T>) -> Measurement<T> {
        self.measure_wheels(t, state, state.wheel_speeds(robot), robot)
    }

    #[inline(always)]
    fn measure_wheels(
        &mut self,
        t: T,
        state: &State<T>,
        wheel_speeds: Wheels<T>,
        _: &RobotParams<T>,
    ) -> Measurement<T> {
        Measurement { t, pose: state.pose(), wheel_angles: state.wheel_angles(), wheel_speeds }
    }
}
