//! Wheel encoders: each wheel's own angle quantized to whole counts,
//! phi = q round(phi_true / q) with q = 2 pi / `encoder_counts`, and its speed
//! differenced from them, omega = (phi_k - phi_(k-1)) / dt_c (0 at the first tick).
//! With ideal encoders (0 counts) the true angles and speeds pass through, bit for bit.

use crate::Real;
use crate::math::Wheels;

/// The encoders of both wheels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Encoders<T> {
    /// The quantum q = 2 pi / counts, rad (0: ideal encoders).
    quantum: T,
    /// The control period dt_c, s.
    control_dt: T,
    /// Angles read at the previous tick, rad.
    last_angles: Option<Wheels<T>>,
}

impl<T: Real> Encoders<T> {
    /// Encoders of `counts` per revolution (0: ideal) read every `control_dt` (s).
    pub fn new(counts: u32, control_dt: T) -> Self {
        let quantum = if counts == 0 { T::zero() } else { T::lit(core::f64::consts::TAU / f64::from(counts)) };
        Self { quantum, control_dt, last_angles: None }
    }

    /// The quantum q = 2 pi / encoder_counts, rad (0: ideal encoders).
    pub fn quantum(&self) -> T {
        self.quantum
    }

    /// The angles (rad) and speeds (rad/s) read at this tick, of wheels at `angles`
    /// (rad) turning at `wheel_speeds` (rad/s, each wheel's own rotation rate).
    #[inline]
    pub fn read(&mut self, angles: Wheels<T>, wheel_speeds: Wheels<T>) -> (Wheels<T>, Wheels<T>) {
        let q = self.quantum;
        if q == T::zero() {
            return (angles, wheel_speeds);
        }
        let angles = angles.map(|phi| (phi / q).round() * q);
        let prev = self.last_angles.unwrap_or(angles);
        self.last_angles = Some(angles);
        let dt = self.control_dt;
        (angles, Wheels::new((angles.right - prev.right) / dt, (angles.left - prev.left) / dt))
    }

    /// Forgets the previous angles, as at t = 0.
    pub fn reset(&mut self) {
        self.last_angles = None;
    }
}
