//! The sensor of a run, chosen by `[sensor] pose`: the absolute pose sensor or odometry.

use super::odometry::{OdometryParams, OdometrySensor, PoseSource};
use super::{Measurement, PoseSensor, Sensor, SensorParams};
use crate::error::{ParamError, check};
use crate::math::{Pose2, Wheels};
use crate::state::State;
use crate::{Real, RobotParams};

/// Either pose source behind one type, so one loop type runs both.
// The odometry sensor carries a second ring of fixes in flight; without alloc there is no
// box to even the variants out, and a run holds one sensor.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum AnySensor<T> {
    /// `pose = "absolute"`: [`PoseSensor`], today's sensor.
    Absolute(PoseSensor<T>),
    /// `pose = "odometry"`: [`OdometrySensor`].
    Odometry(OdometrySensor<T>),
}

impl<T: Real> AnySensor<T> {
    /// The sensor `pose.pose` names, for the controller's `model` (validated; odometry
    /// uses its r and R), control period `control_dt` (s) and run `run` (the noise
    /// stream). Errors name the fields of [`SensorParams`] and [`OdometryParams`];
    /// `fix_rate_hz` > 0 with the absolute source is refused.
    pub fn new(
        sensor: SensorParams<T>,
        pose: OdometryParams<T>,
        model: &RobotParams<T>,
        control_dt: T,
        run: u64,
    ) -> Result<Self, ParamError> {
        match pose.pose {
            PoseSource::Absolute => {
                if pose.fix_rate_hz.is_nan() || pose.fix_rate_hz != T::zero() {
                    return Err(check::out_of_range(
                        "fix_rate_hz",
                        "absolute fixes are fused with odometry only: set pose = \"odometry\" (or use rate_hz)",
                        pose.fix_rate_hz,
                    ));
                }
                check::non_negative("odometry_noise", pose.odometry_noise)?;
                PoseSensor::new(sensor, control_dt, run).map(AnySensor::Absolute)
            }
            PoseSource::Odometry => OdometrySensor::new(sensor, pose, model, control_dt, run).map(AnySensor::Odometry),
        }
    }
}

impl<T: Real> Sensor<T> for AnySensor<T> {
    #[inline]
    fn measure(&mut self, t: T, state: &State<T>, robot: &RobotParams<T>) -> Measurement<T> {
        match self {
            AnySensor::Absolute(s) => s.measure(t, state, robot),
            AnySensor::Odometry(s) => s.measure(t, state, robot),
        }
    }

    #[inline]
    fn measure_wheels(
        &mut self,
        t: T,
        state: &State<T>,
        wheel_speeds: Wheels<T>,
        robot: &RobotParams<T>,
    ) -> Measurement<T> {
        match self {
            AnySensor::Absolute(s) => s.measure_wheels(t, state, wheel_speeds, robot),
            AnySensor::Odometry(s) => s.measure_wheels(t, state, wheel_speeds, robot),
        }
    }

    fn reset(&mut self) {
        match self {
            AnySensor::Absolute(s) => s.reset(),
            AnySensor::Odometry(s) => s.reset(),
        }
    }

    fn deterministic(&self) -> bool {
        match self {
            AnySensor::Absolute(s) => s.deterministic(),
            AnySensor::Odometry(s) => s.deterministic(),
        }
    }

    #[inline]
    fn odometry(&self) -> Option<Pose2<T>> {
        match self {
            AnySensor::Absolute(_) => None,
            AnySensor::Odometry(s) => s.odometry(),
        }
    }

    #[inline]
    fn pose_covariance(&self) -> Option<super::ekf::Mat3<T>> {
        match self {
            AnySensor::Absolute(_) => None,
            AnySensor::Odometry(s) => s.pose_covariance(),
        }
    }
}
