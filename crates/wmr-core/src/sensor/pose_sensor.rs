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

use super::gaussian::Gaussian;
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

/// One pose sample in flight: its index j and the (noisy) pose.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct InFlight<T> {
    index: u64,
    pose: Pose2<T>,
}

/// The sensor of the module docs, with room for `N` samples in flight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoseSensor<T, const N: usize = 256> {
    params: SensorParams<T>,
    perfect: bool,
    /// Control ticks per sample (P / dt_c) and of latency (L / dt_c).
    ticks_per_sample: u64,
    latency_ticks: u64,
    /// heading noise, rad; encoder quantum q = 2 pi / counts, rad; control period, s.
    heading_noise: T,
    quantum: T,
    control_dt: T,
    /// The sample period P, s (for the measurement's time stamp).
    sample_period: T,
    noise: Gaussian,
    /// The run index, which selects the noise stream.
    run: u64,
    /// The next control tick's index k.
    tick: u64,
    ring: [InFlight<T>; N],
    /// Index in `ring` of the oldest sample in flight, and how many are in flight.
    head: usize,
    len: usize,
    /// The pose the controller sees now and when it was taken (s); the start pose at first.
    seen: Option<(Pose2<T>, T)>,
    /// Encoder angles of the previous tick, rad.
    last_angles: Option<Wheels<T>>,
}

/// `latency * rate_hz` must be below this: the samples in flight the default buffer (256)
/// holds, with room to spare.
const MAX_SAMPLES_IN_FLIGHT: u64 = 250;

/// Largest `heading_noise_deg` accepted, deg (ten turns: beyond it the heading measured is
/// uniform anyway).
const MAX_HEADING_NOISE_DEG: f64 = 3600.0;

impl<T: Real, const N: usize> PoseSensor<T, N> {
    /// Validates `params` for control period `control_dt` (s); `run` selects the noise
    /// stream. Errors name `rate_hz`, `latency`, `position_noise`, `heading_noise_deg`.
    pub fn new(params: SensorParams<T>, control_dt: T, run: u64) -> Result<Self, ParamError> {
        check::positive("control_dt", control_dt)?;
        if params.rate_hz.is_nan() || params.rate_hz <= T::zero() {
            return Err(check::out_of_range("rate_hz", "must be > 0 (inf: every control tick)", params.rate_hz));
        }
        let dt = control_dt.to_f64_lossless();
        let ticks_per_sample = if params.rate_hz.is_infinite() {
            1
        } else {
            ticks_in::<T>("rate_hz", 1.0 / params.rate_hz.to_f64_lossless(), dt).map_err(|e| ParamError {
                reason: crate::Reason::OutOfRange("1 / rate_hz must be a whole multiple of control_dt"),
                ..e
            })?
        };
        check::non_negative("latency", params.latency)?;
        let latency_ticks = if params.latency == T::zero() {
            0
        } else {
            ticks_in::<T>("latency", params.latency.to_f64_lossless(), dt)?
        };
        check::non_negative("position_noise", params.position_noise)?;
        check::non_negative("heading_noise_deg", params.heading_noise_deg)?;
        // Noise beyond the box a run may not leave only measures the noise, and a sample
        // of 1e308 m overflows to inf (issue 25 item 11).
        if params.position_noise > T::lit(crate::plant::DIVERGENCE_BOX_M) {
            return Err(check::out_of_range(
                "position_noise",
                "must be at most 1000 m (the box a run may not leave)",
                params.position_noise,
            ));
        }
        if params.heading_noise_deg > T::lit(MAX_HEADING_NOISE_DEG) {
            return Err(check::out_of_range("heading_noise_deg", "must be at most 3600 deg", params.heading_noise_deg));
        }
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
        let sample_period = T::lit(ticks_per_sample as f64) * control_dt;
        let quantum = if params.encoder_counts == 0 {
            T::zero()
        } else {
            T::lit(core::f64::consts::TAU / f64::from(params.encoder_counts))
        };
        Ok(Self {
            params,
            perfect: params.is_perfect(),
            ticks_per_sample,
            latency_ticks,
            heading_noise: params.heading_noise_deg.to_radians(),
            quantum,
            control_dt,
            sample_period,
            noise: Gaussian::new(params.seed, run),
            run,
            tick: 0,
            ring: [InFlight::default(); N],
            head: 0,
            len: 0,
            seen: None,
            last_angles: None,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &SensorParams<T> {
        &self.params
    }

    /// `value` plus Gaussian noise of standard deviation `sigma` (unchanged when 0).
    fn noisy(&mut self, value: T, sigma: T) -> T {
        if sigma > T::zero() { value + sigma * T::lit(self.noise.next_normal()) } else { value }
    }

    /// The pose the controller sees at this tick, when it was taken (s), and the index j
    /// of the newest sample delivered at this tick (none: the pose seen is an older one).
    fn pose_at_tick(&mut self, truth: Pose2<T>) -> (Pose2<T>, T, Option<u64>) {
        let k = self.tick;
        if k.is_multiple_of(self.ticks_per_sample) {
            let j = k / self.ticks_per_sample;
            let x = self.noisy(truth.x, self.params.position_noise);
            let y = self.noisy(truth.y, self.params.position_noise);
            let theta = self.noisy(truth.theta, self.heading_noise);
            let slot = (self.head + self.len) % N;
            self.ring[slot] = InFlight { index: j, pose: Pose2::new(x, y, theta) };
            self.len += 1;
        }
        // Deliver every sample that has arrived: j P + L <= k dt_c.
        let mut delivered = None;
        while self.len > 0 {
            let s = self.ring[self.head];
            if s.index * self.ticks_per_sample + self.latency_ticks > k {
                break;
            }
            self.seen = Some((s.pose, T::lit(s.index as f64) * self.sample_period));
            delivered = Some(s.index);
            self.head = (self.head + 1) % N;
            self.len -= 1;
        }
        // Before the first sample arrives: the start pose, without noise.
        let (pose, taken) = *self.seen.get_or_insert((truth, T::zero()));
        (pose, taken, delivered)
    }

    /// The encoder quantum q = 2 pi / encoder_counts, rad (0: ideal encoders).
    pub(crate) fn quantum(&self) -> T {
        self.quantum
    }

    /// Control ticks per pose sample (P / dt_c): sample j is taken at tick j times this.
    pub(crate) fn ticks_per_sample(&self) -> u64 {
        self.ticks_per_sample
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
        let (angles, speeds) = self.encoders(state, wheel_speeds);
        self.tick += 1;
        (angles, speeds, fix)
    }

    /// Encoder angles (rad) and speeds (rad/s) at this tick, of wheels turning at
    /// `wheel_speeds` (rad/s, each wheel's own).
    fn encoders(&mut self, state: &State<T>, wheel_speeds: Wheels<T>) -> (Wheels<T>, Wheels<T>) {
        if self.params.encoder_counts == 0 {
            return (state.wheel_angles(), wheel_speeds);
        }
        let q = self.quantum;
        let angles = state.wheel_angles().map(|phi| (phi / q).round() * q);
        let prev = self.last_angles.unwrap_or(angles);
        self.last_angles = Some(angles);
        let dt = self.control_dt;
        (angles, Wheels::new((angles.right - prev.right) / dt, (angles.left - prev.left) / dt))
    }
}

/// Control ticks in `period` (s) at control period `dt` (s), both as written in `T` and
/// widened to f64: the whole number n >= 1 with |n dt - period| <= tol period, where tol
/// is 1e-9 or, in a precision coarser than that, 4 epsilons of `T`. In f32, 1 / 50 Hz
/// (0.0199999995...) is 20 ticks of 1 ms (0.00100000005...) although the two differ by
/// 2 parts in 1e8: each was rounded once to f32 where it was written, and the f64 check's
/// 1e-9 would refuse what f64 accepts (issue 25, item 8). In f64 the tolerance is 1e-9,
/// the same as `ClosedLoop`'s check of control_dt against dt.
fn ticks_in<T: Real>(field: &'static str, period: f64, dt: f64) -> Result<u64, ParamError> {
    use num_traits::{Float, ToPrimitive as _};
    // Float's methods by name: no_std has no inherent f64::round.
    let ratio = Float::round(period / dt);
    let tol = 1e-9f64.max(4.0 * T::epsilon().to_f64_lossless()) * Float::abs(period).max(f64::MIN_POSITIVE);
    let refused = ParamError { field, reason: crate::Reason::NotMultipleOfDt, value: period };
    if ratio.is_nan() || ratio < 1.0 || Float::abs(ratio * dt - period) > tol || ratio > f64::from(u32::MAX) {
        return Err(refused);
    }
    ratio.to_u64().ok_or(refused)
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
        let (wheel_angles, wheel_speeds) = self.encoders(state, wheel_speeds);
        self.tick += 1;
        Measurement { t: taken, pose, wheel_angles, wheel_speeds }
    }

    fn reset(&mut self) {
        self.noise = Gaussian::new(self.params.seed, self.run);
        self.tick = 0;
        self.head = 0;
        self.len = 0;
        self.seen = None;
        self.last_angles = None;
    }

    fn deterministic(&self) -> bool {
        self.params.position_noise == T::zero() && self.params.heading_noise_deg == T::zero()
    }
}
