//! A pose sensor as a real robot has one: the pose of C sampled at its own rate, arriving
//! late, with Gaussian noise; wheel encoders read every tick, quantized to whole counts.
//!
//! With control period `dt_c`, sample period P = 1/`rate_hz` and latency L (both whole
//! multiples of `dt_c`), at control tick k (time k dt_c):
//!
//! ```text
//! every k with k dt_c = j P:   sample j = true pose at j P  + (n_x, n_y, n_theta)
//!                              n_x, n_y ~ N(0, position_noise^2), n_theta ~ N(0, heading_noise^2)
//! pose seen at tick k:         the newest sample j with j P + L <= k dt_c;
//!                              before the first one arrives, the start pose without noise
//! encoders at tick k:          phi = q round(phi_true / q),  q = 2 pi / encoder_counts
//!                              omega = (phi_k - phi_(k-1)) / dt_c    (0 at the first tick)
//! ```
//!
//! With every default (a sample each tick, no latency, no noise, ideal encoders) the
//! measurement is the true state itself, bit for bit: the same as [`super::PerfectSensor`].
//! The samples in flight wait in a fixed ring of `N` (no heap): L / P + 1 must fit.

use super::stage::{DelayLine, Encoders, PoseNoise, Sampling, ticks_in};
use super::{Measurement, Sensor};
use crate::error::{ParamError, check};
use crate::math::{Pose2, Wheels};
use crate::state::State;
use crate::{Real, RobotParams};

crate::params! {
    /// `[sensor]` keys: what the controller sees.
    // repr(C): the C API hands this very struct across (wmr-ffi, include/wmr.h).
    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    pub struct SensorParams<T> {
        /// Pose samples per second (inf, the default: a sample at every control tick).
        pub rate_hz: T [unit = "Hz", rule = "> 0; 1 / rate_hz a whole multiple of control_dt"],
        /// Latency: a sample taken at t reaches the controller at t + latency.
        pub latency: T [unit = "s", rule = ">= 0, a whole multiple of control_dt; latency * rate_hz < 250"],
        /// Standard deviation of the Gaussian noise on x and on y of each sample.
        pub position_noise: T [unit = "m", rule = ">= 0, at most 1000 (the divergence box)"],
        /// Standard deviation of the Gaussian noise on theta of each sample.
        pub heading_noise_deg: T [unit = "deg", rule = ">= 0, at most 3600"],
        /// Encoder counts per wheel revolution (0, the default: ideal encoders).
        pub encoder_counts: u32 [unit = "counts/rev", rule = "whole number"],
        /// Seed of the noise: the noise of a run is a function of (seed, run index).
        pub seed: u64 [unit = "", rule = "whole number"],
    }
}

impl<T: Real> Default for SensorParams<T> {
    /// Perfect: a sample every tick, no latency, no noise, ideal encoders, seed 0.
    fn default() -> Self {
        Self {
            rate_hz: T::infinity(),
            latency: T::zero(),
            position_noise: T::zero(),
            heading_noise_deg: T::zero(),
            encoder_counts: 0,
            seed: 0,
        }
    }
}

impl<T: Real> SensorParams<T> {
    /// True when the sensor is the paper's ideal one (every default but the seed).
    pub fn is_perfect(&self) -> bool {
        self.rate_hz.is_infinite()
            && self.latency == T::zero()
            && self.position_noise == T::zero()
            && self.heading_noise_deg == T::zero()
            && self.encoder_counts == 0
    }
}

/// A pose sample as delivered: its index j (taken at j P) and its noisy pose.
pub(crate) type Fix<T> = (u64, Pose2<T>);

/// The sensor of the module docs, with room for `N` samples in flight: the stages of
/// [`super::stage`], chained.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoseSensor<T, const N: usize = 256> {
    params: SensorParams<T>,
    perfect: bool,
    sampling: Sampling<T>,
    noise: PoseNoise<T>,
    /// Control ticks of latency, L / dt_c (at most u32::MAX, as `ticks_in` checks), and
    /// the samples in flight.
    latency_ticks: u32,
    in_flight: DelayLine<Pose2<T>, N>,
    encoders: Encoders<T>,
    /// The next control tick's index k.
    tick: u64,
    /// The pose the controller sees now and when it was taken (s); the start pose at first.
    seen: Option<(Pose2<T>, T)>,
}

/// `latency * rate_hz` must be below this: the samples in flight the default buffer (256)
/// holds, with room to spare.
const MAX_SAMPLES_IN_FLIGHT: u64 = 250;

impl<T: Real, const N: usize> PoseSensor<T, N> {
    /// Validates `params` for control period `control_dt` (s); `run` selects the noise
    /// stream. Errors name `rate_hz`, `latency`, `position_noise`, `heading_noise_deg`.
    pub fn new(params: SensorParams<T>, control_dt: T, run: u64) -> Result<Self, ParamError> {
        check::positive("control_dt", control_dt)?;
        let sampling = Sampling::new(params.rate_hz, control_dt)?;
        let ticks_per_sample = sampling.ticks_per_sample();
        check::non_negative("latency", params.latency)?;
        let latency_ticks: u64 = if params.latency == T::zero() {
            0
        } else {
            ticks_in::<T>("latency", params.latency.to_f64_lossless(), control_dt.to_f64_lossless())?
        };
        let noise = PoseNoise::new(params.position_noise, params.heading_noise_deg, params.seed, run)?;
        // The documented bound, latency * rate_hz < 250 (in whole ticks), and what the
        // buffer of N samples holds.
        if latency_ticks >= MAX_SAMPLES_IN_FLIGHT * ticks_per_sample || latency_ticks / ticks_per_sample + 2 > N as u64
        {
            return Err(check::out_of_range(
                "latency",
                "holds more pose samples in flight than the sensor's buffer (latency * rate_hz must be below 250)",
                params.latency,
            ));
        }
        Ok(Self {
            params,
            perfect: params.is_perfect(),
            sampling,
            noise,
            // ticks_in refuses more than u32::MAX ticks.
            latency_ticks: u32::try_from(latency_ticks).unwrap_or(u32::MAX),
            in_flight: DelayLine::default(),
            encoders: Encoders::new(params.encoder_counts, control_dt),
            tick: 0,
            seen: None,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &SensorParams<T> {
        &self.params
    }

    /// The pose the controller sees at this tick, when it was taken (s), and the index j
    /// of the newest sample delivered at this tick (none: the pose seen is an older one).
    fn pose_at_tick(&mut self, truth: Pose2<T>) -> (Pose2<T>, T, Option<u64>) {
        let k = self.tick;
        if let Some(j) = self.sampling.sample_at(k) {
            let sample = self.noise.apply(truth);
            self.in_flight.push(j, sample);
        }
        // Deliver every sample that has arrived: j P + L <= k dt_c.
        let (tps, latency) = (self.sampling.ticks_per_sample(), u64::from(self.latency_ticks));
        let delivered = self.in_flight.deliver(|j| j * tps + latency <= k);
        if let Some((j, pose)) = delivered {
            self.seen = Some((pose, self.sampling.time_of(j)));
        }
        // Before the first sample arrives: the start pose, without noise.
        let (pose, taken) = *self.seen.get_or_insert((truth, T::zero()));
        (pose, taken, delivered.map(|(j, _)| j))
    }

    /// The encoder quantum q = 2 pi / encoder_counts, rad (0: ideal encoders).
    pub(crate) fn quantum(&self) -> T {
        self.encoders.quantum()
    }

    /// The sample clock (for odometry: when its fixes are taken).
    pub(crate) fn sampling(&self) -> &Sampling<T> {
        &self.sampling
    }

    /// One control tick for a sensor built on this one ([`super::odometry`]): the
    /// encoder angles (rad) and speeds (rad/s), and, with `fixes`, the pose sample
    /// delivered at this tick if one is (its index j and its noisy pose). Without
    /// `fixes` no sample is taken and no noise is drawn.
    pub(crate) fn encoders_and_fix(
        &mut self,
        state: &State<T>,
        wheel_speeds: Wheels<T>,
        fixes: bool,
    ) -> (Wheels<T>, Wheels<T>, Option<Fix<T>>) {
        let fix = if fixes {
            let (pose, _, delivered) = self.pose_at_tick(state.pose());
            delivered.map(|j| (j, pose))
        } else {
            None
        };
        let (angles, speeds) = self.encoders.read(state.wheel_angles(), wheel_speeds);
        self.tick += 1;
        (angles, speeds, fix)
    }
}

impl<T: Real, const N: usize> Sensor<T> for PoseSensor<T, N> {
    #[inline]
    fn measure(&mut self, t: T, state: &State<T>, robot: &RobotParams<T>) -> Measurement<T> {
        self.measure_wheels(t, state, state.wheel_speeds(robot), robot)
    }

    #[inline]
    fn measure_wheels(
        &mut self,
        t: T,
        state: &State<T>,
        wheel_speeds: Wheels<T>,
        robot: &RobotParams<T>,
    ) -> Measurement<T> {
        if self.perfect {
            return super::PerfectSensor.measure_wheels(t, state, wheel_speeds, robot);
        }
        let (pose, taken, _) = self.pose_at_tick(state.pose());
        let (wheel_angles, wheel_speeds) = self.encoders.read(state.wheel_angles(), wheel_speeds);
        self.tick += 1;
        Measurement { t: taken, pose, wheel_angles, wheel_speeds }
    }

    fn reset(&mut self) {
        self.noise.reset();
        self.in_flight.clear();
        self.encoders.reset();
        self.tick = 0;
        self.seen = None;
    }

    fn deterministic(&self) -> bool {
        self.params.position_noise == T::zero() && self.params.heading_noise_deg == T::zero()
    }
}
