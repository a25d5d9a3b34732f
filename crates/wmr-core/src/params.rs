//! Robot parameters (docs/model.md, "The robot"): the paper's defaults and their validation.

use crate::Real;
use crate::error::{ParamError, check};

crate::params! {
    /// Physical parameters of the differential-drive robot, SI units.
    ///
    /// Field names match the `[robot]` keys of a scenario file. Build a checked [`Robot`]
    /// with [`RobotParams::validate`]; the raw struct is never used by the models.
    // repr(C): the C API hands this very struct across (wmr-ffi, include/wmr.h).
    #[repr(C)]
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    pub struct RobotParams<T> {
        /// m, total mass.
        pub mass: T [unit = "kg", rule = "> 0"],
        /// r, wheel radius.
        pub wheel_radius: T [unit = "m", rule = "> 0"],
        /// R, half the distance between the wheels (axle midpoint C to each wheel).
        pub half_track: T [unit = "m", rule = "> 0"],
        /// d, distance from C forward to the centre of mass G (negative: G behind C).
        pub com_offset: T [unit = "m", rule = "finite, any sign"],
        /// I_m, inertia of one wheel plus its motor rotor about the wheel axis.
        pub wheel_inertia: T [unit = "kg m^2", rule = ">= 0"],
        /// I_p, platform inertia about G.
        pub platform_inertia: T [unit = "kg m^2", rule = ">= 0, and I_p + m d^2 > 0"],
        /// k_t, gear reduction: wheel speed = k_t * motor speed.
        pub gear_ratio: T [unit = "", rule = "> 0"],
        /// b_v, viscous friction at each wheel: tau_f = b_v * omega_wheel.
        pub viscous_friction: T [unit = "N m s", rule = ">= 0"],
        /// tau_c, Coulomb friction at each wheel, smoothed by coulomb_speed.
        pub coulomb_friction: T [unit = "N m", rule = ">= 0"],
        /// omega_eps: Coulomb friction is tau_c * tanh(omega_wheel / omega_eps).
        pub coulomb_speed: T [unit = "rad/s", rule = "> 0"],
        /// tau_s, stiction: the breakaway torque at each wheel; a wheel at rest stays so while the torque holding it is below (0: off, equal to coulomb_friction).
        pub static_friction: T [unit = "N m", rule = "0 (off) or >= coulomb_friction"],
    }
}

impl<T: Real> RobotParams<T> {
    /// The paper's robot (section 4): m = 5 kg, r = 0.1 m, R = 0.2 m, d = 0.25 m,
    /// J_m = 0.002 kg m^2, J_p = 0.005 kg m^2, k_t = 0.1, no friction.
    pub fn paper() -> Self {
        Self {
            mass: T::lit(5.0),
            wheel_radius: T::lit(0.1),
            half_track: T::lit(0.2),
            com_offset: T::lit(0.25),
            wheel_inertia: T::lit(0.002),
            platform_inertia: T::lit(0.005),
            gear_ratio: T::lit(0.1),
            viscous_friction: T::zero(),
            coulomb_friction: T::zero(),
            coulomb_speed: T::lit(1e-3),
            static_friction: T::zero(),
        }
    }

    /// Checks every field and precomputes the model's constant matrices.
    ///
    /// Rejects NaN and infinity everywhere; m, r, R, k_t, omega_eps and
    /// I_p + m d^2 must be > 0; I_m, I_p, b_v and tau_c must be >= 0; tau_s must be 0
    /// or >= tau_c.
    pub fn validate(self) -> Result<Robot<T>, ParamError> {
        let m = check::positive("mass", self.mass)?;
        check::positive("wheel_radius", self.wheel_radius)?;
        check::positive("half_track", self.half_track)?;
        let d = check::finite("com_offset", self.com_offset)?;
        check::non_negative("wheel_inertia", self.wheel_inertia)?;
        let i_p = check::non_negative("platform_inertia", self.platform_inertia)?;
        check::positive("gear_ratio", self.gear_ratio)?;
        check::non_negative("viscous_friction", self.viscous_friction)?;
        check::non_negative("coulomb_friction", self.coulomb_friction)?;
        check::positive("coulomb_speed", self.coulomb_speed)?;
        let tau_s = check::non_negative("static_friction", self.static_friction)?;
        if tau_s > T::zero() && tau_s < self.coulomb_friction {
            return Err(check::out_of_range(
                "static_friction",
                "must be >= coulomb_friction (the breakaway torque is at least the sliding one), or 0 (off)",
                tau_s,
            ));
        }
        let yaw_inertia_g = i_p + m * d * d;
        if yaw_inertia_g <= T::zero() {
            return Err(check::out_of_range(
                "platform_inertia",
                "platform_inertia + mass * com_offset^2 must be > 0",
                i_p,
            ));
        }
        Ok(self.derived())
    }

    /// The robot of these values with the inertias of (15) derived, unchecked: what
    /// [`RobotParams::validate`] returns once its checks pass. No panic path, so the
    /// paper's robot is built without one on a Cortex-M (firmware/check).
    fn derived(self) -> Robot<T> {
        let (m, r, big_r, d) = (self.mass, self.wheel_radius, self.half_track, self.com_offset);
        let (i_m, i_p) = (self.wheel_inertia, self.platform_inertia);
        let yaw_inertia_g = i_p + m * d * d;
        let two = T::lit(2.0);
        // Reduced inertia of (15): wheel/rotor inertia reflected to (v, omega).
        let m11 = m + two * i_m / (r * r);
        let m22 = yaw_inertia_g + two * big_r * big_r * i_m / (r * r);
        let zero = T::zero();
        Robot {
            params: self,
            m11,
            m22,
            inv_m11: m11.recip(),
            inv_m22: m22.recip(),
            md: m * d,
            com_lateral: zero,
            mb: zero,
            inv_m12: zero,
        }
    }
}

impl<T: Real> Default for RobotParams<T> {
    fn default() -> Self {
        Self::paper()
    }
}

/// Validated robot parameters with the reduced inertia matrix M_r of (15) precomputed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Robot<T> {
    params: RobotParams<T>,
    /// M_r11 = m + 2 I_m / r^2, kg.
    m11: T,
    /// M_r22 = I_p + 2 R^2 I_m / r^2 + m d^2, kg m^2.
    m22: T,
    inv_m11: T,
    inv_m22: T,
    /// m d, kg m: the Coriolis coefficient of C(v).
    md: T,
    /// b, m: G left of C, nonzero only for a robot carrying a payload off the centreline
    /// ([`crate::payload`]); then `m22` holds I_C with m b^2 and the mass matrix is
    /// [[m11, -m b], [-m b, m22]], whose inverse is [[inv_m11, inv_m12], [inv_m12, inv_m22]].
    com_lateral: T,
    /// m b, kg m.
    mb: T,
    /// The off-diagonal term of the inverse mass matrix, m b / det (0 when b = 0).
    inv_m12: T,
}

impl<T: Real> Robot<T> {
    /// The validated parameters.
    pub fn params(&self) -> &RobotParams<T> {
        &self.params
    }

    /// Diagonal of the reduced inertia matrix M_r of (15): (kg, kg m^2).
    pub fn reduced_inertia(&self) -> (T, T) {
        (self.m11, self.m22)
    }

    /// J_w = r^2 / (1 / M_r11 + R^2 / M_r22), kg m^2: the inertia one wheel sees when it
    /// alone is driven (the other wheel free), the robot's own inertia at the wheel. The
    /// wheel servo's default gains scale with it ([`crate::ServoGains::for_wheel_inertia`])
    /// and the speed guard's gain is J_w / (2 control_dt). 0.0328 kg m^2 on the paper's robot.
    pub fn driven_wheel_inertia(&self) -> T {
        let r = self.params.wheel_radius;
        let big_r = self.params.half_track;
        r * r / (self.m11.recip() + big_r * big_r / self.m22)
    }

    /// tau_s, the breakaway torque at each wheel (N m) when stiction is on
    /// ([`Robot::has_stiction`]: `static_friction` > `coulomb_friction`), else 0.
    pub fn breakaway_torque(&self) -> T {
        if self.has_stiction() { self.params.static_friction } else { T::zero() }
    }

    /// True when `static_friction` > `coulomb_friction`: the plant then holds a wheel at
    /// rest until the torque at it exceeds the breakaway torque (docs/model.md,
    /// "Stiction"). With `static_friction` 0 or equal to `coulomb_friction` the plant is
    /// the Coulomb model alone, bit for bit.
    pub fn has_stiction(&self) -> bool {
        self.params.static_friction > self.params.coulomb_friction
    }

    /// b, m: how far G lies left of C (body frame); 0 except for a robot carrying a
    /// payload off the centreline ([`crate::payload::Payload::carried_by`]).
    pub fn com_lateral(&self) -> T {
        self.com_lateral
    }

    /// The mass matrix's off-diagonal term -m b, kg m ([`crate::payload`]): 0 on the
    /// centreline, where M_r is the diagonal [`Robot::reduced_inertia`].
    pub fn mass_coupling(&self) -> T {
        -self.mb
    }

    /// The off-diagonal term of M_r's inverse, m b / det: 0 on the centreline.
    #[inline(always)]
    pub(crate) fn inv_coupling(&self) -> T {
        self.inv_m12
    }

    /// This robot with G moved `b` (m) left of C, the mass and the inertia about G kept
    /// ([`crate::payload`]): M_22 gains m b^2 and the mass matrix couples. `b` = 0: the
    /// robot itself. Error naming `payload.y`: b not finite, or a singular mass matrix.
    pub(crate) fn with_lateral_offset(mut self, b: T) -> Result<Self, ParamError> {
        check::finite("payload.y", b)?;
        if b == T::zero() {
            return Ok(self);
        }
        let mb = self.params.mass * b;
        self.m22 = self.m22 + mb * b;
        let det = self.m11 * self.m22 - mb * mb;
        if det.is_nan() || det <= T::zero() {
            return Err(check::out_of_range("payload.y", "gives a singular mass matrix", b));
        }
        self.com_lateral = b;
        self.mb = mb;
        self.inv_m11 = self.m22 / det;
        self.inv_m22 = self.m11 / det;
        self.inv_m12 = mb / det;
        Ok(self)
    }

    /// Inverse diagonal of M_r, precomputed: (1/kg, 1/(kg m^2)) (with a payload off the
    /// centreline, the diagonal of the coupled matrix's inverse).
    #[inline(always)]
    pub(crate) fn inv_reduced_inertia(&self) -> (T, T) {
        (self.inv_m11, self.inv_m22)
    }

    /// m d, kg m.
    #[inline(always)]
    pub(crate) fn mass_offset(&self) -> T {
        self.md
    }

    /// The paper's robot, already validated (its constants pass
    /// [`RobotParams::validate`]: a test checks it gives this very robot).
    pub fn paper() -> Self {
        RobotParams::paper().derived()
    }
}

#[cfg(test)]
mod tests {
    use super::{Robot, RobotParams};

    /// `Robot::paper` skips the checks (no panic path): they pass, and give the same robot.
    #[test]
    fn the_papers_robot_is_the_validated_one() {
        assert_eq!(RobotParams::<f64>::paper().validate(), Ok(Robot::<f64>::paper()));
        assert_eq!(RobotParams::<f32>::paper().validate(), Ok(Robot::<f32>::paper()));
    }
}
