//! Pushes (`[[world.push]]`): a force and a torque on the platform over a time window, as
//! a person's hand or a bump would give, in the plant only.
//!
//! A push acts at C: the force (F_x, F_y) in the body frame (x forward, y left), the
//! torque tau about the vertical. In the rolling plant (15) F_x adds to the forward force
//! and tau to the moment about C; F_y, along the axle, is taken by the wheels' no-slip
//! constraint (it changes nothing the rolling robot can do). In the slip plant
//! ([`crate::traction`]) all three act on the free body: F_x and F_y add to the forces,
//! tau - d F_y to the moment about G.
//!
//! Each plant step of dt from t holds the mean of the pushes over [t, t + dt]: a push
//! whose window covers a fraction q of the step acts with q of its force over the whole
//! step, so the impulse a step delivers is exactly force x overlap whatever the alignment
//! of the window with the steps (RK4 does not integrate a jump inside a step to its
//! order; a constant force over the step it does). Overlapping pushes add.

use crate::Real;
use crate::error::{ParamError, check};

/// The most pushes a plant holds (no allocation).
pub const MAX_PUSHES: usize = 16;

crate::params! {
    /// One `[[world.push]]`: a force and torque at C over [t, t + duration].
    #[repr(C)]
    #[derive(Clone, Copy, Debug, Default, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    pub struct PushParams<T> {
        /// Start of the push.
        pub t: T [unit = "s", rule = ">= 0"],
        /// How long it lasts.
        pub duration: T [unit = "s", rule = "> 0"],
        /// F_x, the force forward (body frame, at C).
        pub force_x: T [unit = "N", rule = "finite"],
        /// F_y, the force to the left (body frame, at C); the rolling plant's wheels take it.
        pub force_y: T [unit = "N", rule = "finite"],
        /// tau, the torque about the vertical (counter-clockwise +).
        pub torque: T [unit = "N m", rule = "finite"],
    }
}

impl<T: Real> PushParams<T> {
    /// Checks the keys; errors name `push.t`, `push.duration`, `push.force_x`,
    /// `push.force_y` or `push.torque`.
    pub fn validate(self) -> Result<Self, ParamError> {
        check::non_negative("push.t", self.t)?;
        check::finite("push.t", self.t)?;
        check::positive("push.duration", self.duration)?;
        check::finite("push.duration", self.duration)?;
        check::finite("push.force_x", self.force_x)?;
        check::finite("push.force_y", self.force_y)?;
        check::finite("push.torque", self.torque)?;
        Ok(self)
    }
}

/// The body-frame load a step holds: (F_x N, F_y N, tau N m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Load<T> {
    /// Forward force at C, N.
    pub force_x: T,
    /// Leftward force at C, N.
    pub force_y: T,
    /// Torque about the vertical, N m.
    pub torque: T,
}

/// Up to [`MAX_PUSHES`] validated pushes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pushes<T> {
    list: [PushParams<T>; MAX_PUSHES],
    len: usize,
}

impl<T: Real> Default for Pushes<T> {
    fn default() -> Self {
        let none =
            PushParams { t: T::zero(), duration: T::zero(), force_x: T::zero(), force_y: T::zero(), torque: T::zero() };
        Self { list: [none; MAX_PUSHES], len: 0 }
    }
}

impl<T: Real> Pushes<T> {
    /// The pushes of `list`, each checked; more than [`MAX_PUSHES`] is an error naming `push`.
    pub fn new(list: &[PushParams<T>]) -> Result<Self, ParamError> {
        if list.len() > MAX_PUSHES {
            return Err(check::out_of_range("push", "at most 16 pushes", T::lit(list.len() as f64)));
        }
        let mut out = Self::default();
        for (slot, p) in out.list.iter_mut().zip(list) {
            *slot = p.validate()?;
        }
        out.len = list.len();
        Ok(out)
    }

    /// The pushes.
    pub fn as_slice(&self) -> &[PushParams<T>] {
        &self.list[..self.len]
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The mean load over [t, t + dt] (s): each push's force and torque times the share of
    /// the step its window covers, summed.
    pub fn mean_over(&self, t: T, dt: T) -> Load<T> {
        let mut load = Load::default();
        let end = t + dt;
        // take(len), not a slice: no bounds check that could panic (firmware/check).
        for p in self.list.iter().take(self.len) {
            let overlap = (end.min(p.t + p.duration) - t.max(p.t)).max(T::zero());
            if overlap > T::zero() {
                let q = overlap / dt;
                load.force_x = load.force_x + q * p.force_x;
                load.force_y = load.force_y + q * p.force_y;
                load.torque = load.torque + q * p.torque;
            }
        }
        load
    }
}
