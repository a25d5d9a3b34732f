//! Odometry as the controller's pose: dead reckoning from the (quantized) wheel
//! encoders with the controller model's r and R ([`super::dead_reckoning`]), fused with
//! optional absolute pose fixes by the pose EKF ([`super::ekf`]).
//!
//! At control tick k the [`OdometrySensor`]:
//!
//! ```text
//! reads the encoders           phi_k (quantized as the pose sensor's, [`super::pose_sensor`])
//! dead-reckons                 odo_k = arc_step(odo_(k-1), r (phi_k - phi_(k-1)))   (odo_0: the start pose)
//! predicts the EKF             with the same wheel travel (process noise: quantum and odometry_noise)
//! takes a fix, if one arrives  sample j of the pose sensor at fix_rate_hz, with its noise and latency:
//!                              z taken at t_j = j P, carried to now by the odometry since then,
//!                              z_k = z (+) (odo_k (-) odo_(t_j)), then the EKF update with z_k
//! hands the controller         the EKF's mean (= odo_k bit for bit when no fix ever came)
//! ```
//!
//! The start pose is known (as the paper's controller knows it): the dead reckoning and the
//! EKF start there, the EKF with covariance diag(1 mm^2, 1 mm^2, (1 mrad)^2). A fix's noise
//! covariance is diag(sigma_p^2, sigma_p^2, sigma_th^2) from the sensor's
//! `position_noise` and `heading_noise_deg`, each at least 1 mm and 1 mrad so that a
//! noiseless fix keeps the covariance positive definite. Carrying a late fix forward by
//! the odometry ignores the odometry's own error over the latency (a few ticks' worth).

use super::dead_reckoning::DeadReckoning;
use super::ekf::{Mat3, PoseEkf, diag};
use super::stage::DelayLine;
use super::{Measurement, PoseSensor, Sensor, SensorParams};
use crate::error::{ParamError, check};
use crate::math::{Pose2, Wheels};
use crate::state::State;
use crate::{Real, RobotParams};

/// Where the controller's pose comes from (`[sensor] pose`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize), serde(rename_all = "snake_case"))]
#[repr(u32)]
#[non_exhaustive]
pub enum PoseSource {
    /// The pose sensor's samples (rate, latency, noise): today's sensor.
    #[default]
    Absolute = 0,
    /// Dead reckoning from the encoders, fused with fixes at `fix_rate_hz` if any.
    Odometry = 1,
}

crate::params! {
    /// `[sensor]` keys of the pose source: absolute or odometry with optional fixes.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    // repr(C): the C API hands this very struct across (wmr-ffi, include/wmr.h).
    #[repr(C)]
    pub struct OdometryParams<T> {
        /// Where the controller's pose comes from: the pose sensor, or the encoders' odometry.
        pub pose: PoseSource [unit = "", rule = "\"absolute\" or \"odometry\""],
        /// Absolute fixes per second fused with the odometry (0, the default: none).
        pub fix_rate_hz: T [unit = "Hz", rule = ">= 0; 1 / fix_rate_hz a whole multiple of control_dt; > 0 only with pose = \"odometry\""],
        /// The EKF's slip and radius term: a wheel's travel error grows as this times sqrt(distance).
        pub odometry_noise: T [unit = "m^(1/2)", rule = ">= 0, at most 1"],
    }
}

impl<T: Real> Default for OdometryParams<T> {
    /// Absolute (today's sensor), no fixes, odometry_noise 0.01 m^(1/2) (1 cm after 1 m).
    fn default() -> Self {
        Self { pose: PoseSource::Absolute, fix_rate_hz: T::zero(), odometry_noise: T::lit(DEFAULT_ODOMETRY_NOISE) }
    }
}

/// Default `odometry_noise`, m^(1/2): a wheel's travel is known to 1 cm after 1 m, 10 cm
/// after 100 m (a 1 % radius error is 1 cm per metre).
pub const DEFAULT_ODOMETRY_NOISE: f64 = 0.01;

/// The least standard deviation of a fix's position (m) and heading (rad) the EKF
/// assumes, and of its start pose: a noiseless fix keeps the covariance positive definite.
pub const FIX_SIGMA_FLOOR: f64 = 1e-3;

/// Dead reckoning and the EKF, from the first tick on.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Track<T> {
    odometry: DeadReckoning<T>,
    ekf: PoseEkf<T>,
}

/// The sensor of the module docs, with room for `N` fixes in flight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdometrySensor<T, const N: usize = 256> {
    /// The encoders, and the fixes (its pose samples at fix_rate_hz).
    inner: PoseSensor<T, N>,
    params: OdometryParams<T>,
    /// The controller's model of the robot (its r and R).
    model: RobotParams<T>,
    fixes: bool,
    /// The encoder quantum in wheel travel, r q, m (0: ideal encoders).
    quantum_m: T,
    /// odometry_noise^2, m.
    noise_per_m: T,
    fix_noise: Mat3<T>,
    track: Option<Track<T>>,
    /// The odometry pose at the instant each fix in flight was taken.
    taken: DelayLine<Pose2<T>, N>,
    tick: u64,
}

impl<T: Real, const N: usize> OdometrySensor<T, N> {
    /// Validates `sensor` and `odometry` (whose `pose` must be odometry) for the
    /// controller's `model` (validated) and control period `control_dt` (s); `run`
    /// selects the fixes' noise stream. Errors name the sensor's fields (`rate_hz` when
    /// given: the fixes' rate is `fix_rate_hz`), `fix_rate_hz`, `odometry_noise`.
    pub fn new(
        sensor: SensorParams<T>,
        odometry: OdometryParams<T>,
        model: &RobotParams<T>,
        control_dt: T,
        run: u64,
    ) -> Result<Self, ParamError> {
        if odometry.pose != PoseSource::Odometry {
            return Err(check::out_of_range("pose", "must be \"odometry\" for the odometry sensor", T::zero()));
        }
        if !sensor.rate_hz.is_infinite() {
            return Err(check::out_of_range(
                "rate_hz",
                "with pose = \"odometry\" the pose comes from the encoders: give absolute fixes as fix_rate_hz",
                sensor.rate_hz,
            ));
        }
        check::non_negative("fix_rate_hz", odometry.fix_rate_hz)?;
        check::non_negative("odometry_noise", odometry.odometry_noise)?;
        if odometry.odometry_noise > T::one() {
            return Err(check::out_of_range("odometry_noise", "must be at most 1 m^(1/2)", odometry.odometry_noise));
        }
        check::positive("wheel_radius", model.wheel_radius)?;
        check::positive("half_track", model.half_track)?;
        let fixes = odometry.fix_rate_hz > T::zero();
        let inner_params = if fixes { SensorParams { rate_hz: odometry.fix_rate_hz, ..sensor } } else { sensor };
        let inner = PoseSensor::new(inner_params, control_dt, run)
            .map_err(|e| if e.field == "rate_hz" { ParamError { field: "fix_rate_hz", ..e } } else { e })?;
        let rq = model.wheel_radius * inner.quantum();
        let floor = T::lit(FIX_SIGMA_FLOOR);
        let sigma_p = sensor.position_noise.max(floor);
        let sigma_th = sensor.heading_noise_deg.to_radians().max(floor);
        Ok(Self {
            inner,
            params: odometry,
            model: *model,
            fixes,
            quantum_m: rq,
            noise_per_m: odometry.odometry_noise * odometry.odometry_noise,
            fix_noise: diag(sigma_p * sigma_p, sigma_p * sigma_p, sigma_th * sigma_th),
            track: None,
            taken: DelayLine::default(),
            tick: 0,
        })
    }

    /// The pose-source parameters.
    pub fn params(&self) -> &OdometryParams<T> {
        &self.params
    }

    /// The dead-reckoned pose of C at the last tick (world frame), if a tick has run.
    pub fn dead_reckoning(&self) -> Option<Pose2<T>> {
        self.track.map(|t| t.odometry.pose())
    }

    /// The EKF's covariance of the pose at the last tick (m^2, m rad, rad^2), if a tick has run.
    pub fn covariance(&self) -> Option<Mat3<T>> {
        self.track.map(|t| *t.ekf.covariance())
    }
}

impl<T: Real, const N: usize> Sensor<T> for OdometrySensor<T, N> {
    fn measure(&mut self, t: T, state: &State<T>, robot: &RobotParams<T>) -> Measurement<T> {
        self.measure_wheels(t, state, state.wheel_speeds(robot), robot)
    }

    fn measure_wheels(
        &mut self,
        t: T,
        state: &State<T>,
        wheel_speeds: Wheels<T>,
        _: &RobotParams<T>,
    ) -> Measurement<T> {
        let (wheel_angles, wheel_speeds, fix) = self.inner.encoders_and_fix(state, wheel_speeds, self.fixes);
        let track = match &mut self.track {
            None => {
                let floor = T::lit(FIX_SIGMA_FLOOR);
                let p0 = diag(floor * floor, floor * floor, floor * floor);
                let start = state.pose();
                self.track.insert(Track {
                    odometry: DeadReckoning::new(&self.model, start, wheel_angles),
                    ekf: PoseEkf::new(start, p0),
                })
            }
            Some(track) => {
                let travel = track.odometry.update(wheel_angles);
                // The process noise (super::ekf): var_w = (r q)^2 / 12 min(1, |d_w| / (r q)) + k^2 |d_w|, m^2.
                let rq = self.quantum_m;
                let variance = travel.map(|d| {
                    let rounding =
                        if rq > T::zero() { rq * rq / T::lit(12.0) * (d.abs() / rq).min(T::one()) } else { T::zero() };
                    rounding + self.noise_per_m * d.abs()
                });
                track.ekf.predict(travel, variance, self.model.half_track);
                track
            }
        };
        let odometry_now = track.odometry.pose();
        if self.fixes {
            if let Some(j) = self.inner.sampling().sample_at(self.tick) {
                self.taken.push(j, odometry_now);
            }
            if let Some((j, z)) = fix {
                // The odometry when fix j was taken; older entries were never delivered.
                let then = self.taken.deliver(|i| i <= j).map(|(_, pose)| pose);
                let then = then.unwrap_or(odometry_now);
                let z_now = z.compose(&odometry_now.relative_to(&then));
                let z_now = Pose2::new(z_now.x, z_now.y, z.theta + (odometry_now.theta - then.theta));
                track.ekf.update(z_now, &self.fix_noise);
            }
        }
        self.tick += 1;
        Measurement { t, pose: track.ekf.mean(), wheel_angles, wheel_speeds }
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.track = None;
        self.taken.clear();
        self.tick = 0;
    }

    fn deterministic(&self) -> bool {
        !self.fixes || self.inner.deterministic()
    }

    fn odometry(&self) -> Option<Pose2<T>> {
        self.dead_reckoning()
    }

    fn pose_covariance(&self) -> Option<Mat3<T>> {
        self.covariance()
    }
}
