//! Seeded, deterministic Gaussian noise without `std`: SplitMix64 for uniform bits and the
//! Box-Muller transform, computed in f64 with the `libm` crate so every build (CLI,
//! Python, firmware) draws the same numbers for the same seed.

/// SplitMix64's output function: a well-mixed 64-bit hash of `x`.
#[inline]
pub fn mix64(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// Standard normal numbers (mean 0, standard deviation 1) from a seeded SplitMix64 stream.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gaussian {
    state: u64,
    /// Box-Muller makes two numbers at a time; the second waits here.
    spare: Option<f64>,
}

impl Gaussian {
    /// The stream for `seed` and `stream` (e.g. the run index): different streams of the
    /// same seed are independent for practical purposes.
    pub fn new(seed: u64, stream: u64) -> Self {
        Self { state: mix64(seed ^ mix64(stream.wrapping_add(0x5EED))), spare: None }
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform number in (0, 1]: 53 random bits, never 0 (so its log is finite).
    #[inline]
    pub fn uniform_open0(&mut self) -> f64 {
        ((self.next_u64() >> 11) + 1) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }

    /// The next standard normal number.
    pub fn next_normal(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        let u1 = self.uniform_open0();
        let u2 = self.uniform_open0();
        let radius = libm::sqrt(-2.0 * libm::log(u1));
        let (s, c) = libm::sincos(core::f64::consts::TAU * u2);
        self.spare = Some(radius * s);
        radius * c
    }
}
