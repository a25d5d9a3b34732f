//! Traction: how the wheels hold the ground. Rolling (the paper's no-slip constraints,
//! `dynamics.rs`) or slip: each driven wheel pushes on the ground through a
//! regularised Coulomb law limited by mu times its normal load (docs/model.md, "Traction").
//!
//! The slip plant drops the two constraints of (15) and gains three speeds: each wheel's
//! own speed omega_r, omega_l (rad/s) and the lateral velocity v_y of C (m/s, body frame,
//! positive to the left); and the contact's elastic deflection e = (e_x, e_y) at each
//! wheel (m, body frame), which holds a force without slip. With u = v the forward speed
//! of C, omega the yaw rate, G a distance d ahead of C, I_G = platform_inertia,
//! I_m = wheel_inertia, and the contact of the right (sigma = +1) and left (sigma = -1)
//! wheel at (0, -sigma R) in the body frame:
//!
//! ```text
//! slip velocity of the contact, body frame:  s_x = u + sigma R omega - r omega_w,  s_y = v_y
//! the contact (a spring-damper anchor capped by Coulomb's friction circle):
//!     q  = e / L + s / v_eps                                  (L = stiction_length, v_eps = slip_speed)
//!     F  = -mu N q             while |q| <= 1                 (sticks: holds any force below mu N)
//!     F  = -mu N q / |q|       beyond                         (slides at exactly mu N)
//!     e' = s - v_eps (|q| - 1)+ q / |q|                       (the anchor slides with the contact)
//! wheel:    I_m omega_w'  = tau - tau_f(omega_w) - r F_x
//! forward:  m (u'   - omega v_y - omega^2 d) = F_xr + F_xl (+ gravity along the body x)
//! lateral:  m (v_y' + omega u   + omega' d)  = F_yr + F_yl (+ gravity along the body y)
//! yaw at G: I_G omega' = R (F_xr - F_xl) - d (F_yr + F_yl)
//! ```
//!
//! Normal loads: the caster at c = `caster_offset` ahead of C carries no horizontal force,
//! G sits at height h = `com_height`; moments about the axle line at the ground give
//! N_caster c = W d - h (F_xr + F_xl) with W = m g cos(slope), so pulling forward unloads
//! the caster. The wheels share the rest equally (no lateral load transfer):
//!
//! ```text
//! N_r = N_l = W (c - d) / (2 (c - h (f_xr + f_xl) / 2)),   f_x = F_x / N (the normalised force)
//! ```
//!
//! which solves the loop "force needs the load, the load needs the force" exactly: F_x is
//! f_x N with f_x given by the slip alone. The caster never lifts and the wheels never
//! lift while mu h <= |d| and 0 <= d / c < 1 ([`TractionParams::validate`]).
//!
//! The contact law is the elasto-plastic ("spring-damper anchor") friction of
//! multibody and game engines, a Kelvin-Voigt element (stiffness mu N / L, damping
//! mu N / v_eps) in series with a Coulomb slider: below mu N it holds the force with the
//! spring alone and zero slip (a robot parked on a slope stays parked); once the force
//! would exceed mu N the slider slides and the force is mu N exactly, against the slip.
//! The anchor's slide w = v_eps (|q| - 1)+ q / |q| is what dissipates: the power lost is
//! mu N (|e'|^2 / v_eps + |w|) >= 0, the rest of the contact's power being the spring's
//! energy 1/2 mu N |e|^2 / L ([`Contact::slip_power`], [`Contact::elastic_energy`]).
//! (Before 2026-12-06 the law was F = -mu N tanh(|s| / v_eps) s / |s|, which needs a
//! permanent slip v_eps atanh(|F| / mu N) to hold any force: parked robots crept.)
//!
//! With mu -> infinity the slip velocities vanish and the equations reduce to (15)
//! (docs/model.md derives it); the slip plant's state on top of [`State`] is a
//! [`SlipExtra`].

use crate::drive::Drive;
use crate::dynamics::Model;
use crate::error::{ParamError, check};
use crate::integrator::{RK4_HALF_DISK_RADIUS, RK4_REAL_STABILITY_LIMIT, Rhs, rk4_step_of};
use crate::math::Wheels;
use crate::state::State;
use crate::world::{STANDARD_GRAVITY, World};
use crate::{Real, Robot};

/// Which traction model the plant uses (`[robot] traction`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize), serde(rename_all = "snake_case"))]
// repr(u32): the C API holds it as a `uint32_t` code (wmr-ffi, `WMR_TRACTION_*`).
#[repr(u32)]
#[non_exhaustive]
pub enum TractionKind {
    /// The paper's pure rolling: no slip, any torque becomes acceleration (the default).
    #[default]
    Rolling = 0,
    /// Wheels that slip: forces limited by mu times the normal loads ([`crate::traction`]).
    Slip = 1,
}

crate::params! {
    /// `[robot]` keys of the traction model (read beside [`crate::RobotParams`]'s).
    ///
    /// Only `traction = "slip"` reads the others; with `"rolling"` they are ignored.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    // repr(C): the C API hands this very struct across (wmr-ffi, include/wmr.h).
    #[repr(C)]
    pub struct TractionParams<T> {
        /// Traction model: "rolling" (the paper's, no slip) or "slip" (forces within mu N).
        pub traction: TractionKind [unit = "", rule = "\"rolling\" or \"slip\""],
        /// mu, friction coefficient between tyre and ground (0.8 asphalt, 0.3 wet tiles, 0.1 ice).
        pub friction_coefficient: T [unit = "", rule = "> 0, and friction_coefficient * com_height <= abs(com_offset)"],
        /// c, distance from C forward to the caster's contact (negative: caster behind C).
        pub caster_offset: T [unit = "m", rule = "finite, 0 <= com_offset / caster_offset < 1"],
        /// h, height of the centre of mass G above the ground.
        pub com_height: T [unit = "m", rule = ">= 0"],
        /// v_eps, the contact's damping: below mu N, F = mu N (deflection / stiction_length + slip / v_eps); the plant takes sub-steps of dt while dt * stiffness >= 2.785.
        pub slip_speed: T [unit = "m/s", rule = "> 0, and at most 1000 sub-steps: dt * stiffness <= 2506.8"],
        /// L, the contact's deflection at which the tyre holds mu N without slipping (its stiffness is mu N / L).
        pub stiction_length: T [unit = "m", rule = "> 0, finite, and at most 1000 sub-steps: dt * stiffness <= 2506.8"],
    }
}

impl<T: Real> Default for TractionParams<T> {
    /// Rolling; for slip: mu = 0.8, the caster 0.35 m ahead of C, G 0.1 m high,
    /// v_eps = [`DEFAULT_SLIP_SPEED_M_S`], L = 1 mm (the paper's robot then takes 6 RK4
    /// sub-steps per dt = 1 ms, [`crate::Plant::substeps`]).
    fn default() -> Self {
        Self {
            traction: TractionKind::Rolling,
            friction_coefficient: T::lit(0.8),
            caster_offset: T::lit(0.35),
            com_height: T::lit(0.1),
            slip_speed: T::lit(DEFAULT_SLIP_SPEED_M_S),
            stiction_length: T::lit(DEFAULT_STICTION_LENGTH_M),
        }
    }
}

/// Default `slip_speed` v_eps, m/s: a slip of v_eps alone brings a contact's force to
/// mu N, and a rubber tyre's force peaks near a 10 % slip ratio, 0.03 m/s at the 0.3 m/s
/// these robots drive (before 2026-12-06: 0.2 m/s, a 67 % slip ratio there, chosen
/// for one RK4 step per dt = 1 ms; the plant now takes the sub-steps the contact needs).
pub const DEFAULT_SLIP_SPEED_M_S: f64 = 0.03;

/// Default `stiction_length`, m: a rubber tyre's contact deflects about a millimetre
/// before it lets go.
pub const DEFAULT_STICTION_LENGTH_M: f64 = 1e-3;

impl<T: Real> TractionParams<T> {
    /// Checks the keys against the robot and builds the traction model on `world`'s
    /// ground. Errors name
    /// `friction_coefficient`, `caster_offset`, `com_height`, `slip_speed`,
    /// `stiction_length` (`"rolling"` only refuses NaN and infinity there), and, since the
    /// slip plant integrates each wheel and the yaw on their own, `wheel_inertia` and
    /// `platform_inertia` (both must be > 0).
    pub fn validate(self, robot: &Robot<T>, world: &World<T>) -> Result<Traction<T>, ParamError> {
        if self.traction == TractionKind::Rolling {
            // Unused, but a NaN is never let through silently.
            check::finite("friction_coefficient", self.friction_coefficient)?;
            check::finite("caster_offset", self.caster_offset)?;
            check::finite("com_height", self.com_height)?;
            check::finite("slip_speed", self.slip_speed)?;
            check::finite("stiction_length", self.stiction_length)?;
            return Ok(Traction::Rolling);
        }
        let mu = check::positive("friction_coefficient", self.friction_coefficient)?;
        let c = check::finite("caster_offset", self.caster_offset)?;
        let h = check::non_negative("com_height", self.com_height)?;
        check::positive("slip_speed", self.slip_speed)?;
        check::positive("stiction_length", self.stiction_length)?;
        check::finite("stiction_length", self.stiction_length)?;
        let p = robot.params();
        if robot.com_lateral() != T::zero() {
            // The slip equations keep G on the centreline (crate::payload).
            return Err(check::out_of_range(
                "payload.y",
                "must be 0 with traction = \"slip\" (the slip plant keeps G on the centreline)",
                robot.com_lateral(),
            ));
        }
        check::positive("wheel_inertia", p.wheel_inertia)?;
        check::positive("platform_inertia", p.platform_inertia)?;
        let d = p.com_offset;
        let share = d / c;
        if c == T::zero() || !(share >= T::zero() && share < T::one()) {
            return Err(check::out_of_range(
                "caster_offset",
                "G must lie between the axle and the caster: 0 <= com_offset / caster_offset < 1",
                c,
            ));
        }
        if mu * h > d.abs() {
            return Err(check::out_of_range(
                "com_height",
                "the caster would lift at full traction: friction_coefficient * com_height must be <= |com_offset|",
                h,
            ));
        }
        Ok(Traction::Slip(Slip::new(self, robot, world)))
    }
}

/// A validated traction model.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Traction<T> {
    /// The paper's rolling wheels (`dynamics.rs`).
    Rolling,
    /// Wheels that slip ([`Slip`]).
    Slip(Slip<T>),
}

/// What the slip plant adds to [`State`] (zero for a rolling plant).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SlipExtra<T> {
    /// Lateral velocity of C, body frame (positive to the left), m/s.
    pub v_lat: T,
    /// Each wheel's own speed, rad/s.
    pub wheel_speeds: Wheels<T>,
    /// Longitudinal deflection e_x of each wheel's contact, body frame, m: how far the
    /// contact has moved forward over the ground since it last slid.
    pub deflection_x: Wheels<T>,
    /// Lateral deflection e_y of each wheel's contact, body frame (left +), m.
    pub deflection_y: Wheels<T>,
}

/// The contact of each wheel with the ground at one instant (zero for a rolling plant).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Contact<T> {
    /// Longitudinal slip velocity, m/s: r omega_w minus the ground speed under the wheel
    /// (positive when the wheel spins faster than the ground moves).
    pub slip: Wheels<T>,
    /// Lateral velocity of C (and of both contacts), body frame, m/s.
    pub v_lat: T,
    /// Longitudinal force of the ground on the robot at each wheel, body frame, N.
    pub force_x: Wheels<T>,
    /// Lateral force of the ground on the robot at each wheel, body frame (left +), N.
    pub force_y: Wheels<T>,
    /// Normal load on each wheel, N.
    pub normal: Wheels<T>,
    /// Power each wheel's contact dissipates, W: mu N (|e'|^2 / v_eps + |w|), never
    /// negative (module docs).
    pub dissipation: Wheels<T>,
    /// Energy each wheel's contact holds in its deflection, J: 1/2 mu N |e|^2 / L.
    pub elastic: Wheels<T>,
}

impl<T: Real> Contact<T> {
    /// Power lost in slip, W, over both wheels: what the contacts dissipate (never
    /// negative). The power the contact forces take from the robot, minus F . s, is this
    /// plus the rate of change of [`Contact::elastic_energy`] at a constant load (module
    /// docs).
    pub fn slip_power(&self) -> T {
        self.dissipation.right + self.dissipation.left
    }

    /// Power the contact forces take from the robot, W: minus their power on the contact
    /// points' velocities relative to the ground, -F . s, over both wheels. Negative
    /// while the deflected contacts give back the energy they hold.
    pub fn contact_power(&self) -> T {
        // The contact slides at (-slip, v_lat) relative to the ground; F opposes it.
        self.force_x.right * self.slip.right + self.force_x.left * self.slip.left
            - (self.force_y.right + self.force_y.left) * self.v_lat
    }

    /// Energy held in the contacts' deflection, J, over both wheels.
    pub fn elastic_energy(&self) -> T {
        self.elastic.right + self.elastic.left
    }
}

/// The slip plant's constants, computed once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slip<T> {
    params: TractionParams<T>,
    /// Rolling model, for the wheel friction tau_f and the robot's constants.
    model: Model<T>,
    r: T,
    big_r: T,
    d: T,
    mass: T,
    inv_mass: T,
    /// 1 / I_G, 1/(kg m^2).
    inv_i_g: T,
    /// 1 / I_m, 1/(kg m^2).
    inv_i_m: T,
    /// 1 / L, 1/m, and 1 / v_eps, s/m.
    inv_stiction_length: T,
    inv_slip_speed: T,
    /// W (c - d) / 2: each wheel's load times (c - h f_mean), N m.
    load_numerator: T,
    /// Gravity along the ground in world x and y, N.
    downhill: (T, T),
    /// Normal weight W = m g cos(slope), N.
    weight: T,
}

/// The slip plant's state as one array for RK4: [`State`]'s seven, then v_lat,
/// omega_r, omega_l, e_x right and left, e_y right and left.
pub(crate) const SLIP_STATE_LEN: usize = 14;

/// One wheel's contact, per newton of load: the force (f_x, f_y) = F / N of the ground
/// on the robot, the deflection's rate e' (m/s) and the anchor's slide speed |w| (m/s).
struct PerNewton<T> {
    f: (T, T),
    deflection_rate: (T, T),
    slide: T,
}

impl<T: Real> Slip<T> {
    /// Holds the pushes' `load` over the next step ([`crate::push`]).
    pub(crate) fn set_load(&mut self, load: crate::push::Load<T>) {
        self.model.set_load(load);
    }

    fn new(params: TractionParams<T>, robot: &Robot<T>, world: &World<T>) -> Self {
        let p = robot.params();
        let per_degree = T::PI() / T::lit(180.0);
        let cos_slope = (world.params().slope_deg * per_degree).cos_libm();
        let weight = p.mass * T::lit(STANDARD_GRAVITY) * cos_slope;
        let two = T::lit(2.0);
        Self {
            params,
            model: Model::on(robot, world),
            r: p.wheel_radius,
            big_r: p.half_track,
            d: p.com_offset,
            mass: p.mass,
            inv_mass: p.mass.recip(),
            inv_i_g: p.platform_inertia.recip(),
            inv_i_m: p.wheel_inertia.recip(),
            inv_stiction_length: params.stiction_length.recip(),
            inv_slip_speed: params.slip_speed.recip(),
            load_numerator: weight * (params.caster_offset - p.com_offset) / two,
            downhill: world.downhill_force(p.mass),
            weight,
        }
    }

    /// The parameters.
    pub fn params(&self) -> &TractionParams<T> {
        &self.params
    }

    /// Normal weight on the ground, W = m g cos(slope), N.
    pub fn weight(&self) -> T {
        self.weight
    }

    /// The largest normal load a wheel can see, N: W |c - d| / (2 (|c| - mu h)), at full
    /// traction forward (caster ahead) or backward (caster behind).
    pub fn max_wheel_load(&self) -> T {
        let p = &self.params;
        let c = p.caster_offset;
        self.weight * (c - self.d).abs() / (T::lit(2.0) * (c.abs() - p.friction_coefficient * p.com_height))
    }

    /// One wheel's contact with slip velocity `s` (m/s) and deflection `e` (m), body
    /// frame (module docs).
    #[inline(always)]
    fn per_newton(&self, s: (T, T), e: (T, T)) -> PerNewton<T> {
        let mu = self.params.friction_coefficient;
        let q = (
            e.0 * self.inv_stiction_length + s.0 * self.inv_slip_speed,
            e.1 * self.inv_stiction_length + s.1 * self.inv_slip_speed,
        );
        let size = q.0.hypot_libm(q.1);
        if size <= T::one() {
            // Sticks: the spring and the damper carry the force, the anchor stays.
            return PerNewton { f: (-mu * q.0, -mu * q.1), deflection_rate: s, slide: T::zero() };
        }
        // Slides: the force is mu N against q, the anchor follows at v_eps (|q| - 1).
        let unit = (q.0 / size, q.1 / size);
        let slide = self.params.slip_speed * (size - T::one());
        PerNewton {
            f: (-mu * unit.0, -mu * unit.1),
            deflection_rate: (s.0 - slide * unit.0, s.1 - slide * unit.1),
            slide,
        }
    }

    /// The contact at body speeds (u, omega, v_lat), wheel speeds `w` (rad/s) and contact
    /// deflections `e_x`, `e_y` (m), with each wheel's deflection rate (m/s, x and y).
    #[inline(always)]
    fn contact_and_rates(
        &self,
        u: T,
        omega: T,
        v_lat: T,
        w: Wheels<T>,
        e_x: Wheels<T>,
        e_y: Wheels<T>,
    ) -> (Contact<T>, [T; 4]) {
        let p = &self.params;
        // Velocity of each contact point relative to the ground, body frame.
        let sx_r = u + self.big_r * omega - self.r * w.right;
        let sx_l = u - self.big_r * omega - self.r * w.left;
        let right = self.per_newton((sx_r, v_lat), (e_x.right, e_y.right));
        let left = self.per_newton((sx_l, v_lat), (e_x.left, e_y.left));
        let half = T::lit(0.5);
        let n = self.load_numerator / (p.caster_offset - p.com_height * half * (right.f.0 + left.f.0));
        let mu_n = p.friction_coefficient * n;
        let dissipation = |c: &PerNewton<T>| {
            let (dx, dy) = c.deflection_rate;
            mu_n * ((dx * dx + dy * dy) * self.inv_slip_speed + c.slide)
        };
        let elastic = |ex: T, ey: T| half * mu_n * (ex * ex + ey * ey) * self.inv_stiction_length;
        let contact = Contact {
            slip: Wheels::new(-sx_r, -sx_l),
            v_lat,
            force_x: Wheels::new(right.f.0 * n, left.f.0 * n),
            force_y: Wheels::new(right.f.1 * n, left.f.1 * n),
            normal: Wheels::new(n, n),
            dissipation: Wheels::new(dissipation(&right), dissipation(&left)),
            elastic: Wheels::new(elastic(e_x.right, e_y.right), elastic(e_x.left, e_y.left)),
        };
        let rates = [right.deflection_rate.0, left.deflection_rate.0, right.deflection_rate.1, left.deflection_rate.1];
        (contact, rates)
    }

    /// The contact at body speeds (u, omega, v_lat) (m/s, rad/s, m/s), wheel speeds `w`
    /// (rad/s) and contact deflections `e_x`, `e_y` (m, body frame).
    #[inline]
    pub fn contact(&self, u: T, omega: T, v_lat: T, w: Wheels<T>, e_x: Wheels<T>, e_y: Wheels<T>) -> Contact<T> {
        self.contact_and_rates(u, omega, v_lat, w, e_x, e_y).0
    }

    /// The contact of state (`s`, `extra`).
    pub fn contact_of(&self, s: &State<T>, extra: &SlipExtra<T>) -> Contact<T> {
        self.contact(s.v, s.omega, extra.v_lat, extra.wheel_speeds, extra.deflection_x, extra.deflection_y)
    }

    /// The time derivative of the slip state under wheel torques from `torque(omega_w)`
    /// (N m, the drive at each wheel's own speed).
    #[inline]
    /// The wheels in `stuck` are held at rest by static friction (their speeds'
    /// derivatives zero: docs/model.md, "Stiction").
    fn derivative(
        &self,
        y: &[T; SLIP_STATE_LEN],
        torque: impl Fn(Wheels<T>) -> Wheels<T>,
        stuck: Wheels<bool>,
    ) -> [T; SLIP_STATE_LEN] {
        let [_, _, theta, u, omega, _, _, v_lat, w_r, w_l, ex_r, ex_l, ey_r, ey_l] = *y;
        let w = Wheels::new(w_r, w_l);
        let tau = torque(w);
        let (c, [dex_r, dex_l, dey_r, dey_l]) =
            self.contact_and_rates(u, omega, v_lat, w, Wheels::new(ex_r, ex_l), Wheels::new(ey_r, ey_l));
        let (sin, cos) = theta.sin_cos_libm();
        let mut f_x = c.force_x.right + c.force_x.left;
        let mut f_y = c.force_y.right + c.force_y.left;
        if self.model.is_sloped() {
            // World pull (F_X, F_Y) in the body frame; at G, so no moment about G.
            let (gx, gy) = self.downhill;
            f_x = f_x + gx * cos + gy * sin;
            f_y = f_y - gx * sin + gy * cos;
        }
        let mut moment_g =
            self.big_r * (c.force_x.right - c.force_x.left) - self.d * (c.force_y.right + c.force_y.left);
        if let Some(load) = self.model.load() {
            // A push at C (crate::push): its force on the body, its moment about G.
            f_x = f_x + load.force_x;
            f_y = f_y + load.force_y;
            moment_g = moment_g + (load.torque - self.d * load.force_y);
        }
        let omega_dot = moment_g * self.inv_i_g;
        let u_dot = f_x * self.inv_mass + omega * v_lat + omega * omega * self.d;
        let v_lat_dot = f_y * self.inv_mass - omega_dot * self.d - omega * u;
        let wheel_dot = |held: bool, tau: T, w: T, fx: T| {
            if held { T::zero() } else { (tau - self.model.friction_torque(w) - self.r * fx) * self.inv_i_m }
        };
        [
            u * cos - v_lat * sin,
            u * sin + v_lat * cos,
            omega,
            u_dot,
            omega_dot,
            w_r,
            w_l,
            v_lat_dot,
            wheel_dot(stuck.right, tau.right, w_r, c.force_x.right),
            wheel_dot(stuck.left, tau.left, w_l, c.force_x.left),
            dex_r,
            dex_l,
            dey_r,
            dey_l,
        ]
    }

    /// One RK4 step of `dt` (s) from (`s`, `extra`) with the drive's torque for the held
    /// `command` at each wheel's own speed.
    pub(crate) fn step(
        &self,
        s: &State<T>,
        extra: &SlipExtra<T>,
        drive: &Drive<T>,
        command: Wheels<T>,
        t: T,
        dt: T,
    ) -> (State<T>, SlipExtra<T>) {
        // Stiction: a wheel within omega_eps of rest whose friction can hold it against
        // its drive and its contact's force is held at rest over the step.
        let mut stuck = Wheels::new(false, false);
        let mut w = extra.wheel_speeds;
        if self.model.has_stiction() {
            let c = self.contact_of(s, extra);
            let tau = Wheels::new(drive.wheel_torque(command.right, w.right), drive.wheel_torque(command.left, w.left));
            stuck = Wheels::new(
                self.model.holds(w.right, tau.right, self.r * c.force_x.right),
                self.model.holds(w.left, tau.left, self.r * c.force_x.left),
            );
            w = Wheels::new(if stuck.right { T::zero() } else { w.right }, if stuck.left { T::zero() } else { w.left });
        }
        let y = [
            s.x,
            s.y,
            s.theta,
            s.v,
            s.omega,
            s.phi_r,
            s.phi_l,
            extra.v_lat,
            w.right,
            w.left,
            extra.deflection_x.right,
            extra.deflection_x.left,
            extra.deflection_y.right,
            extra.deflection_y.left,
        ];
        let mut f = SlipRhs { slip: self, drive, command, stuck };
        let [x, y, theta, v, omega, phi_r, phi_l, v_lat, w_r, w_l, ex_r, ex_l, ey_r, ey_l] =
            rk4_step_of(&mut f, t, &y, dt);
        let extra = SlipExtra {
            v_lat,
            wheel_speeds: Wheels::new(w_r, w_l),
            deflection_x: Wheels::new(ex_r, ex_l),
            deflection_y: Wheels::new(ey_r, ey_l),
        };
        (State { x, y, theta, v, omega, phi_r, phi_l }, extra)
    }

    /// Kinetic energy, J: 1/2 m |v_G|^2 + 1/2 I_G omega^2 + 1/2 I_m (omega_r^2 + omega_l^2),
    /// with v_G = (u, v_lat + omega d) in the body frame.
    pub fn kinetic_energy(&self, s: &State<T>, extra: &SlipExtra<T>) -> T {
        let half = T::lit(0.5);
        let vg_y = extra.v_lat + s.omega * self.d;
        let w = extra.wheel_speeds;
        half * self.mass * (s.v * s.v + vg_y * vg_y)
            + half * self.inv_i_g.recip() * s.omega * s.omega
            + half * self.inv_i_m.recip() * (w.right * w.right + w.left * w.left)
    }

    /// The stiffness of the slip (1/s): a bound of the fastest rate of the contacts'
    /// motion, over every state, such that RK4 at step dt is stable while
    /// dt * stiffness < [`RK4_REAL_STABILITY_LIMIT`]. While a contact sticks its force is
    /// linear, F = -(C s + K e), with damping at most c = mu N_max / v_eps and stiffness
    /// at most k = mu N_max / L (N_max the largest wheel load), both times
    /// 1 + mu h / (|c| - mu h) for the load that the force itself moves; the slip
    /// velocities answer the forces through the contacts' mobility matrix A (the inverse
    /// mass matrix seen at the contacts). C and K being multiples of one matrix, each
    /// eigenvalue lambda of A is a mode mu^2 + c lambda mu + k lambda = 0: real roots,
    /// the fastest (beta + sqrt(beta^2 - 4 omega^2)) / 2 with beta = c lambda,
    /// omega^2 = k lambda, where RK4 holds to 2.785; complex ones, of modulus omega, where
    /// it holds inside the half-disk of radius [`RK4_HALF_DISK_RADIUS`], so they count as
    /// omega 2.785 / 2.6156. By the robot's left-right symmetry A splits into a common
    /// mode, 2/m + r^2/I_m, and a 2 x 2 block [[2R^2/I_G + r^2/I_m, -2Rd/I_G],
    /// [-2Rd/I_G, 2(1/m + d^2/I_G)]] (differential slip and lateral slip, coupled by the
    /// yaw). The wheel's friction and the drive's damping b (N m s/rad) add b / I_m to
    /// beta. A sliding contact's anchor relaxes at v_eps / L.
    pub fn stiffness(&self, wheel_damping: T) -> T {
        let p = &self.params;
        let (mu, h, c) = (p.friction_coefficient, p.com_height, p.caster_offset.abs());
        let two = T::lit(2.0);
        let load = mu * self.max_wheel_load() * (T::one() + mu * h / (c - mu * h));
        let (damping, spring) = (load * self.inv_slip_speed, load * self.inv_stiction_length);
        let r2_over_i_m = self.r * self.r * self.inv_i_m;
        let common = two * self.inv_mass + r2_over_i_m;
        let a = two * self.big_r * self.big_r * self.inv_i_g + r2_over_i_m;
        let b = two * self.big_r * self.d * self.inv_i_g;
        let cc = two * (self.inv_mass + self.d * self.d * self.inv_i_g);
        let half_diff = (a - cc) / two;
        let lateral = (a + cc) / two + (half_diff * half_diff + b * b).sqrt();
        let mode = |lambda: T| {
            let beta = damping * lambda + wheel_damping * self.inv_i_m;
            let omega2 = spring * lambda;
            let disc = beta * beta - T::lit(4.0) * omega2;
            if disc >= T::zero() {
                (beta + disc.sqrt()) / two
            } else {
                omega2.sqrt() * T::lit(RK4_REAL_STABILITY_LIMIT / RK4_HALF_DISK_RADIUS)
            }
        };
        mode(common).max(mode(lateral)).max(p.slip_speed * self.inv_stiction_length)
    }

    /// The largest plant step (s) RK4 integrates stably: limit / stiffness.
    pub fn max_stable_dt(&self, wheel_damping: T) -> T {
        T::lit(RK4_REAL_STABILITY_LIMIT) / self.stiffness(wheel_damping)
    }
}

/// The slip plant's right-hand side under a held command.
struct SlipRhs<'a, T> {
    slip: &'a Slip<T>,
    drive: &'a Drive<T>,
    command: Wheels<T>,
    /// The wheels stiction holds at rest over this step.
    stuck: Wheels<bool>,
}

impl<T: Real> Rhs<T, SLIP_STATE_LEN> for SlipRhs<'_, T> {
    #[inline]
    fn eval(&mut self, _t: T, y: &[T; SLIP_STATE_LEN]) -> [T; SLIP_STATE_LEN] {
        let (drive, command) = (self.drive, self.command);
        self.slip.derivative(
            y,
            |w| Wheels::new(drive.wheel_torque(command.right, w.right), drive.wheel_torque(command.left, w.left)),
            self.stuck,
        )
    }
}
