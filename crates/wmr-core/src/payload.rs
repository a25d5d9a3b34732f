//! An unknown payload (`[world.payload]`): a point mass carried on the platform, in the
//! plant only (the controller's model does not know it), and the coupled equations of
//! motion it brings when it sits off the centreline.
//!
//! # The composite body
//!
//! The robot: mass m, centre of mass G at (d, 0) in the body frame of C (x forward,
//! y left, REP 103), yaw inertia I_p about G. The payload: a point mass M at (x_p, y_p).
//! The composite (parallel-axis theorem, each part's inertia moved to the new centre):
//!
//! ```text
//! m' = m + M
//! a  = (m d + M x_p) / m'                 G' forward of C
//! b  = M y_p / m'                         G' left of C
//! I' = I_p + m ((d - a)^2 + b^2) + M ((x_p - a)^2 + (y_p - b)^2)     about G'
//! I' + m' (a^2 + b^2) = I_p + m d^2 + M (x_p^2 + y_p^2)              about C
//! ```
//!
//! With b = 0 the composite is a robot of (15) with mass m', com_offset a and
//! platform_inertia I'; a payload at C (x_p = y_p = 0) leaves m d and the inertia about C
//! as they were and adds M to the mass only.
//!
//! # Equations of motion with G' off the centreline (b != 0)
//!
//! Newton-Euler at C. The no-slip constraints leave C the body-frame velocity (v, 0) and
//! the yaw rate omega; G' = C + (a, b) moves at (v - omega b, omega a) and, in the
//! rotating body frame (a' = d/dt + omega x), accelerates at
//!
//! ```text
//! A_x = v' - omega' b - omega^2 a,     A_y = omega' a + omega v - omega^2 b
//! ```
//!
//! The wheels push with F = ((tau_r - f_r) + (tau_l - f_l)) / r forward and a lateral
//! constraint force at C (no moment about C); their torques give the moment
//! M = (R / r)((tau_r - f_r) - (tau_l - f_l)) about C. Forward: m' A_x = F. Moments about
//! C: M = I' omega' + (a, b) x m' (A_x, A_y) = I' omega' + m' (a A_y - b A_x). Written out,
//! the omega^2 a b terms cancel:
//!
//! ```text
//!  m' v'     - m' b omega'         = F + m' a omega^2
//! -m' b v'   + I_C omega'          = M - m' a v omega        (I_C = I' + m' (a^2 + b^2))
//! ```
//!
//! With each wheel and rotor's I_m adding 2 I_m / r^2 to both diagonal terms (as in (15)):
//!
//! ```text
//! [ M_11   -m'b ] [ v'     ]   [ F + m' a omega^2 ]     M_11 = m' + 2 I_m / r^2
//! [ -m'b   M_22 ] [ omega' ] = [ M - m' a v omega ]     M_22 = I_C + 2 R^2 I_m / r^2
//! ```
//!
//! The mass matrix is symmetric and constant (the kinetic energy is
//! 1/2 M_11 v^2 - m' b v omega + 1/2 M_22 omega^2); its determinant
//! M_11 M_22 - (m' b)^2 >= m' (I' + m' a^2) > 0 whenever the composite has any yaw inertia
//! about C beyond the lateral offset's (checked). The Coriolis terms still do no work
//! (v m' a omega^2 - omega m' a v omega = 0). The off-diagonal term is what couples the
//! equations: equal wheel torques (M = 0) from rest give omega' = m' b F / det, a turn
//! towards the side the payload sits on.
//!
//! On a slope, the pull (f_x, f_y) along the plane (body frame) acts at G': it adds f_x to
//! F and a f_y - b f_x to M.
//!
//! The slip plant ([`crate::traction`]) takes the composite's mass, com_offset and
//! inertia; it keeps G on the centreline, so a payload with y != 0 is refused there.

use crate::error::{ParamError, check};
use crate::{Real, Robot};

crate::params! {
    /// `[world.payload]` keys: a point mass on the platform the controller does not know.
    // repr(C): laid out as the other parameter structs, for the C API.
    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    pub struct PayloadParams<T> {
        /// M, the payload's mass (0: no payload); the plant's mass becomes mass + M, the controller's stays.
        pub mass: T [unit = "kg", rule = ">= 0"],
        /// x_p, the payload's position forward of C (body frame).
        pub x: T [unit = "m", rule = "finite"],
        /// y_p, the payload's position left of C (body frame); != 0 couples the forward and yaw equations.
        pub y: T [unit = "m", rule = "finite"],
        /// When the payload is put on the robot (0: from the start); the plant's mass, centre of mass and inertia switch at the first step from t on.
        pub t: T [unit = "s", rule = ">= 0, finite"],
    }
}

impl<T: Real> Default for PayloadParams<T> {
    /// No payload.
    fn default() -> Self {
        Self { mass: T::zero(), x: T::zero(), y: T::zero(), t: T::zero() }
    }
}

impl<T: Real> PayloadParams<T> {
    /// Checks the keys; errors name `payload.mass`, `payload.x`, `payload.y` or `payload.t`.
    pub fn validate(self) -> Result<Payload<T>, ParamError> {
        check::non_negative("payload.mass", self.mass)?;
        check::finite("payload.x", self.x)?;
        check::finite("payload.y", self.y)?;
        check::non_negative("payload.t", self.t)?;
        check::finite("payload.t", self.t)?;
        Ok(Payload { params: self })
    }
}

/// A validated payload.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Payload<T> {
    params: PayloadParams<T>,
}

impl<T: Real> Payload<T> {
    /// No payload.
    pub fn none() -> Self {
        Self { params: PayloadParams::default() }
    }

    /// The parameters.
    pub fn params(&self) -> &PayloadParams<T> {
        &self.params
    }

    /// True when the payload has mass.
    pub fn is_some(&self) -> bool {
        self.params.mass > T::zero()
    }

    /// When the payload is put on the robot, s (0: from the start; the plant swaps the
    /// robot for [`Payload::carried_by`] then, [`crate::Plant::with_payload_at`]).
    pub fn t(&self) -> T {
        self.params.t
    }

    /// True when the payload has mass and appears after the start (`t` > 0).
    pub fn appears_later(&self) -> bool {
        self.is_some() && self.params.t > T::zero()
    }

    /// The composite robot: `robot` carrying this payload (the module's derivation). With
    /// no payload, `robot` itself (the same bits). The result's `mass`, `com_offset` and
    /// `platform_inertia` are m', a and I'; its lateral offset b is
    /// [`Robot::com_lateral`]. Error (naming `payload.y`): a composite whose mass matrix
    /// is singular (no yaw inertia about C beyond the lateral offset's).
    pub fn carried_by(&self, robot: &Robot<T>) -> Result<Robot<T>, ParamError> {
        if !self.is_some() {
            return Ok(*robot);
        }
        let p = robot.params();
        let (m, d, i_p) = (p.mass, p.com_offset, p.platform_inertia);
        let PayloadParams { mass: big_m, x, y, .. } = self.params;
        let total = m + big_m;
        let a = (m * d + big_m * x) / total;
        let b = big_m * y / total;
        let sq = |u: T| u * u;
        let inertia = i_p + m * (sq(d - a) + sq(b)) + big_m * (sq(x - a) + sq(y - b));
        let params = crate::RobotParams { mass: total, com_offset: a, platform_inertia: inertia, ..*p };
        let composite = params
            .validate()
            .map_err(|_| check::out_of_range("payload.mass", "gives a composite robot without yaw inertia", big_m))?;
        composite.with_lateral_offset(b)
    }
}
