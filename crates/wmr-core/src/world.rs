//! The ground the robot drives on: a plane tilted by `slope_deg`, descending towards
//! `slope_direction_deg`; x and y are coordinates in that plane.
//!
//! Gravity along the plane, F = m g sin(slope) with g = 9.80665 m/s^2, acts at the centre
//! of mass G. With psi the descent direction and theta the heading, its component along
//! the heading, F cos(psi - theta), adds to the forward force of (15), and its lateral
//! component F sin(psi - theta), applied at G a distance d ahead of C, adds the moment
//! d F sin(psi - theta) about C (the lateral part itself is carried by the wheels'
//! no-slip constraint).

use crate::Real;
use crate::error::{ParamError, check};

/// Standard gravity, m/s^2.
pub const STANDARD_GRAVITY: f64 = 9.80665;

crate::params! {
    /// `[world]` keys.
    // repr(C): the C API hands this very struct across (wmr-ffi, include/wmr.h).
    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    pub struct WorldParams<T> {
        /// Tilt of the ground plane (0: flat).
        pub slope_deg: T [unit = "deg", rule = "-90 < slope_deg < 90"],
        /// World direction (in the plane, from the x axis) in which the ground descends.
        pub slope_direction_deg: T [unit = "deg", rule = "finite"],
    }
}

impl<T: Real> Default for WorldParams<T> {
    fn default() -> Self {
        Self { slope_deg: T::zero(), slope_direction_deg: T::zero() }
    }
}

impl<T: Real> WorldParams<T> {
    /// Checks the keys; errors name `slope_deg` or `slope_direction_deg`.
    pub fn validate(self) -> Result<World<T>, ParamError> {
        let slope = check::finite("slope_deg", self.slope_deg)?;
        if slope.abs() >= T::lit(90.0) {
            return Err(check::out_of_range("slope_deg", "must be between -90 and 90 degrees", slope));
        }
        check::finite("slope_direction_deg", self.slope_direction_deg)?;
        Ok(World { params: self })
    }
}

/// Validated ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct World<T> {
    params: WorldParams<T>,
}

impl<T: Real> World<T> {
    /// Flat ground.
    pub fn flat() -> Self {
        Self { params: WorldParams::default() }
    }

    /// The parameters.
    pub fn params(&self) -> &WorldParams<T> {
        &self.params
    }

    /// True when the ground is tilted.
    pub fn is_sloped(&self) -> bool {
        self.params.slope_deg != T::zero()
    }

    /// Gravity's pull along the plane on a mass of `mass_kg`, in world x and y, N:
    /// F (cos psi, sin psi) with F = m g sin(slope). Computed in `T` with the core's
    /// `libm` calls (no double-precision trigonometry pulled into an f32 firmware).
    pub fn downhill_force(&self, mass_kg: T) -> (T, T) {
        let per_degree = T::PI() / T::lit(180.0);
        let (sin_slope, _) = (self.params.slope_deg * per_degree).sin_cos_libm();
        let f = mass_kg * T::lit(STANDARD_GRAVITY) * sin_slope;
        let (s, c) = (self.params.slope_direction_deg * per_degree).sin_cos_libm();
        (f * c, f * s)
    }
}
