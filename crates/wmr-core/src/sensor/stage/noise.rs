//! Gaussian noise on a pose sample: n_x, n_y ~ N(0, position_noise^2),
//! n_theta ~ N(0, heading_noise^2), drawn in the order x, y, theta from the stream of
//! (seed, run), and not drawn at all for a standard deviation of 0.

use crate::Real;
use crate::error::{ParamError, check};
use crate::math::Pose2;
use crate::sensor::gaussian::Gaussian;

/// Largest `heading_noise_deg` accepted, deg (ten turns: beyond it the heading measured is
/// uniform anyway).
const MAX_HEADING_NOISE_DEG: f64 = 3600.0;

/// The noise of a sensor's pose samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoseNoise<T> {
    /// Standard deviations: of x and y, m; of theta, rad.
    position_sigma: T,
    heading_sigma: T,
    seed: u64,
    /// The run index, which selects the noise stream.
    run: u64,
    stream: Gaussian,
}

impl<T: Real> PoseNoise<T> {
    /// Noise of `position_noise` (m) and `heading_noise_deg` (deg) from the stream of
    /// (`seed`, `run`). Errors name `position_noise` and `heading_noise_deg`: negative,
    /// NaN, or beyond the box a run may not leave (1000 m) and ten turns (3600 deg).
    pub fn new(position_noise: T, heading_noise_deg: T, seed: u64, run: u64) -> Result<Self, ParamError> {
        check::non_negative("position_noise", position_noise)?;
        check::non_negative("heading_noise_deg", heading_noise_deg)?;
        // Noise beyond the box a run may not leave only measures the noise, and a sample
        // of 1e308 m overflows to inf (issue 25 item 11).
        if position_noise > T::lit(crate::plant::DIVERGENCE_BOX_M) {
            return Err(check::out_of_range(
                "position_noise",
                "must be at most 1000 m (the box a run may not leave)",
                position_noise,
            ));
        }
        if heading_noise_deg > T::lit(MAX_HEADING_NOISE_DEG) {
            return Err(check::out_of_range("heading_noise_deg", "must be at most 3600 deg", heading_noise_deg));
        }
        Ok(Self {
            position_sigma: position_noise,
            heading_sigma: heading_noise_deg.to_radians(),
            seed,
            run,
            stream: Gaussian::new(seed, run),
        })
    }

    /// `truth` with its noise added.
    #[inline]
    pub fn apply(&mut self, truth: Pose2<T>) -> Pose2<T> {
        let x = self.noisy(truth.x, self.position_sigma);
        let y = self.noisy(truth.y, self.position_sigma);
        let theta = self.noisy(truth.theta, self.heading_sigma);
        Pose2::new(x, y, theta)
    }

    /// `value` plus Gaussian noise of standard deviation `sigma` (unchanged when 0).
    fn noisy(&mut self, value: T, sigma: T) -> T {
        if sigma > T::zero() { value + sigma * T::lit(self.stream.next_normal()) } else { value }
    }

    /// Starts the stream again, as at t = 0.
    pub fn reset(&mut self) {
        self.stream = Gaussian::new(self.seed, self.run);
    }
}
