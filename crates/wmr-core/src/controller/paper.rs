//! The paper's point-stabilization law (section 3): a "moving false target" R, two PI
//! loops on (e_s, e_theta) and the inverse of (20) to wheel angle references, which the
//! wheel stage's position servos follow.
//!
//! ```text
//! dl = hypot(x_d - x, y_d - y)                      (16)
//! alpha = atan2(y_d - y, x_d - x)                   (17)
//! theta_R = 2 alpha - theta_d  (pose)  | alpha  (position)     (21)
//! e_theta = wrap(theta_R - theta),  e_s = dl cos(theta_R - theta)   (18), (23)
//! u_theta = Kp_t e_theta + Ki_t int e_theta,  u_s = Kp_s e_s + Ki_s int e_s   (22), (24)
//! phi_r_ref = (u_s + R u_theta) / r,  phi_l_ref = (u_s - R u_theta) / r       (20)^-1
//! ```
//!
//! The references are absolute wheel angles (the integration constant of (20) is
//! neglected, as the paper says, because the encoders start at zero).

use super::law::{ControlErrors, Law, LawOutput, WheelDemand};
use crate::error::{ParamError, check};
use crate::lane::{Lane, Mask};
use crate::math::{Pose2, Wheels, wrap_angle};
use crate::reference::ReferenceState;
use crate::sensor::Measurement;
use crate::{Real, RobotParams};
use num_traits::Zero;

/// Which of the paper's two problems to solve (section 2.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize), serde(rename_all = "snake_case"))]
#[repr(u32)]
pub enum PaperMode {
    /// Orientating control: reach (x_d, y_d, theta_d); theta_R = 2 alpha - theta_d.
    #[default]
    Pose = 0,
    /// Positioning control: reach (x_d, y_d), heading free; theta_R = alpha.
    Position = 1,
}

/// What the law does inside `hold_radius`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize), serde(rename_all = "snake_case"))]
#[repr(u32)]
pub enum HoldMode {
    /// The default: [`HoldMode::ZeroErrors`] in pose mode (the paper's hold, so the
    /// paper's runs are unchanged) and [`HoldMode::Freeze`] in position mode, where the
    /// zero-errors hold does not let the robot settle: each entry steps the path
    /// reference back by Kp_s e_s, which pushes C out of the radius again (from (0, 0, 0)
    /// to (1, 1) the distance was 0.25 m at 60 s and 0.42 m at 120 s). See
    /// [`HoldMode::resolve`].
    #[default]
    Auto = 2,
    /// The paper's hold: the outer errors are taken as zero and the integrators
    /// stop, so u = Ki int. The wheel references step on entry (the Kp e parts drop
    /// out); on Fig. 7 that kick is what brings the heading error from 28 to 5 deg.
    ZeroErrors = 0,
    /// Bumpless: the wheel references of the last tick outside the radius are kept and
    /// the integrators stop. The robot stays where it entered the radius (position mode
    /// then converges; pose mode keeps the heading error it had at entry).
    Freeze = 1,
}

crate::word_enum!(PaperMode { Pose, Position });
crate::word_enum!(HoldMode { ZeroErrors, Freeze, Auto });

impl HoldMode {
    /// The hold the law applies in `mode`: [`HoldMode::Auto`] resolved, the others as given.
    pub fn resolve(self, mode: PaperMode) -> HoldMode {
        match (self, mode) {
            (HoldMode::Auto, PaperMode::Pose) => HoldMode::ZeroErrors,
            (HoldMode::Auto, PaperMode::Position) => HoldMode::Freeze,
            (h, _) => h,
        }
    }
}

/// What the law's integrators do while the wheel stage saturates (`anti_windup`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize), serde(rename_all = "snake_case"))]
#[repr(u32)]
pub enum AntiWindup {
    /// They integrate on, as the paper prints the law (the default of `paper`): a
    /// saturated wheel lets them wind up.
    #[default]
    Off = 0,
    /// Conditional integration: the outer integrators and the wheel servos' integrators
    /// hold at every tick after one at which the wheel stage saturated (the repaired law
    /// and the others always do this).
    Conditional = 1,
}

crate::word_enum!(AntiWindup { Off, Conditional });

crate::params! {
    words;
    /// `[controller] kind = "paper"`: the law's own keys.
    #[derive(Clone, Copy, Debug, PartialEq)]
    #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
    #[repr(C)]
    pub struct PaperParams<T> {
        /// Pose mode (reach x, y, theta: theta_R = 2 alpha - theta_d) or position mode (heading free: theta_R = alpha).
        pub mode: PaperMode [unit = "", rule = "\"pose\" or \"position\""],
        /// Kp_theta, rad of heading command per rad of error (paper: 2).
        pub kp_theta: T [unit = "rad/rad", rule = ">= 0"],
        /// Ki_theta (paper: 0.1).
        pub ki_theta: T [unit = "1/s", rule = ">= 0"],
        /// Kp_s, m of path command per m of error (paper: 1).
        pub kp_s: T [unit = "m/m", rule = ">= 0"],
        /// Ki_s (paper: 0.25).
        pub ki_s: T [unit = "1/s", rule = ">= 0"],
        /// Within this distance of the goal alpha keeps its last value.
        pub goal_radius: T [unit = "m", rule = ">= 0"],
        /// Within this distance of the goal the outer errors are zero and the outer integrators stop (0: off).
        pub hold_radius: T [unit = "m", rule = ">= 0"],
        /// The hold: auto (zero_errors in pose mode, freeze in position mode), zero_errors (references step on entry) or freeze (bumpless).
        ///
        /// [`HoldMode::ZeroErrors`] takes the errors as zero, so the wheel references
        /// step on entry; [`HoldMode::Freeze`] keeps the last references (bumpless).
        pub hold: HoldMode [unit = "", rule = "\"auto\", \"zero_errors\" or \"freeze\""],
        /// Anti-windup of the integrators (outer loops and wheel servos): off (as printed in the paper) or conditional (they hold while the wheels saturate).
        pub anti_windup: AntiWindup [unit = "", rule = "\"off\" or \"conditional\""],
    }
}

impl<T: Real> PaperParams<T> {
    /// The paper's gains (section 4), the default radii and the default hold
    /// ([`HoldMode::Auto`]: the paper's zero-errors hold in pose mode), anti-windup off.
    pub fn paper() -> Self {
        Self {
            mode: PaperMode::Pose,
            kp_theta: T::lit(2.0),
            ki_theta: T::lit(0.1),
            kp_s: T::lit(1.0),
            ki_s: T::lit(0.25),
            goal_radius: T::lit(1e-3),
            hold_radius: T::lit(5e-3),
            hold: HoldMode::Auto,
            anti_windup: AntiWindup::Off,
        }
    }

    /// Checks every key; errors name it.
    pub fn validate(&self) -> Result<(), ParamError> {
        check::non_negative("kp_theta", self.kp_theta)?;
        check::non_negative("ki_theta", self.ki_theta)?;
        check::non_negative("kp_s", self.kp_s)?;
        check::non_negative("ki_s", self.ki_s)?;
        check::non_negative("goal_radius", self.goal_radius)?;
        check::non_negative("hold_radius", self.hold_radius)?;
        Ok(())
    }
}

impl<T: Real> Default for PaperParams<T> {
    fn default() -> Self {
        Self::paper()
    }
}

impl<T: Real> super::law::LawSpec<T> for PaperParams<T> {
    /// It demands wheel angles, not a twist.
    const TWIST_DEMAND: bool = false;

    type Law<L: Lane<Scalar = T>> = PaperLaw<L>;

    fn build<L: Lane<Scalar = T>>(&self, model: &RobotParams<T>, control_dt: T) -> Result<PaperLaw<L>, ParamError> {
        PaperLaw::for_lanes(*self, model, control_dt)
    }
}

/// Defines a law on [`OuterLoops`] (the paper's and its repair): the struct of its keys
/// and loops, `new` and `for_lanes` (the keys' `validate`, then the loops, with the
/// anti-windup `$aw` of the keys `$p`), `params` and the [`Law`] impl, whose update is the law's own
/// `references` (wheel angle references, [`WheelDemand::Angles`]).
macro_rules! outer_law {
    ($(#[$doc:meta])* pub struct $law:ident($params:ident), anti_windup($p:ident) => $aw:expr, reaches_heading $rh:expr;) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct $law<T: Lane> {
            params: $params<T::Scalar>,
            outer: OuterLoops<T>,
        }

        impl<T: Real> $law<T> {
            /// Validates `params` (errors name the key) for the controller's robot model
            /// (r and R) and the control period (s, `control_dt`).
            pub fn new(params: $params<T>, model: &RobotParams<T>, control_dt: T) -> Result<Self, ParamError> {
                Self::for_lanes(params, model, control_dt)
            }
        }

        impl<T: Lane> $law<T> {
            #[doc = concat!("[`", stringify!($law), "::new`] for several runs side by side ([`crate::lane`]).")]
            pub fn for_lanes(
                params: $params<T::Scalar>,
                model: &RobotParams<T::Scalar>,
                control_dt: T::Scalar,
            ) -> Result<Self, ParamError> {
                params.validate()?;
                let anti_windup = {
                    let $p = &params;
                    $aw
                };
                Ok(Self { params, outer: OuterLoops::new(model, control_dt, anti_windup)? })
            }

            /// The parameters.
            pub fn params(&self) -> &$params<T::Scalar> {
                &self.params
            }
        }

        impl<T: Lane> Law<T> for $law<T> {
            #[cfg_attr(target_os = "none", inline)]
            #[cfg_attr(not(target_os = "none"), inline(always))]
            fn update(&mut self, _t: T, m: &Measurement<T>, r: &ReferenceState<T>) -> LawOutput<T> {
                let (refs, errors) = self.references(m.pose, r.pose);
                LawOutput { demand: WheelDemand::Angles(refs), errors }
            }

            fn reset_lanes(&mut self, lanes: T::Mask) {
                self.outer.reset_lanes(lanes);
            }

            fn holding(&self) -> T::Mask {
                self.outer.held
            }

            #[inline(always)]
            fn wheels_saturated(&mut self, lanes: T::Mask) {
                self.outer.saturated = lanes;
            }

            fn anti_windup(&self) -> bool {
                self.outer.anti_windup
            }

            fn reaches_heading(&self) -> bool {
                $rh
            }
        }
    };
}
pub(crate) use outer_law;

outer_law! {
    /// The paper's outer law. Implements [`Law`] with [`WheelDemand::Angles`].
    pub struct PaperLaw(PaperParams), anti_windup(p) => p.anti_windup == AntiWindup::Conditional, reaches_heading false;
}

impl<T: Lane> PaperLaw<T> {
    /// The law itself: errors and wheel angle references (rad) for the measured `pose`
    /// and the `goal` (m, m, rad), advancing the PI integrators by one control period.
    #[cfg_attr(target_os = "none", inline)]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub fn references(&mut self, pose: Pose2<T>, goal: Pose2<T>) -> (Wheels<T>, ControlErrors<T>) {
        let p = &self.params;
        let gains = PiGains { kp_s: p.kp_s, ki_s: p.ki_s, kp_theta: p.kp_theta, ki_theta: p.ki_theta };
        // At the goal alpha is undefined: keep the last one, or start from the value that
        // makes theta_R the goal heading (pose) or the current one (position).
        let alpha_at_goal = match p.mode {
            PaperMode::Pose => goal.theta,
            PaperMode::Position => pose.theta,
        };
        let mode = p.mode;
        let hold = Hold { goal_radius: p.goal_radius, radius: p.hold_radius, mode: p.hold.resolve(mode) };
        self.outer.step(
            &gains,
            hold,
            pose,
            goal,
            alpha_at_goal,
            #[cfg_attr(not(target_os = "none"), inline(always))]
            |_, _, dl, alpha| {
                let theta_ref = match mode {
                    PaperMode::Pose => alpha + alpha - goal.theta,
                    PaperMode::Position => alpha,
                };
                let diff = theta_ref - pose.theta;
                // (18), (23) and (21).
                (dl * diff.cos(), wrap_angle(diff))
            },
        )
    }
}

/// The gains of the two PI loops (22), (24).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PiGains<T> {
    /// Kp_s, m/m, and Ki_s, 1/s.
    pub kp_s: T,
    pub ki_s: T,
    /// Kp_theta, rad/rad, and Ki_theta, 1/s.
    pub kp_theta: T,
    pub ki_theta: T,
}

/// The radii of the goal: alpha's memory and the hold, and the hold's (resolved) mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Hold<T> {
    /// Within this distance (m) alpha keeps its last value.
    pub goal_radius: T,
    /// Within this distance (m) the outer loops hold; 0 = off.
    pub radius: T,
    /// [`HoldMode::ZeroErrors`] or [`HoldMode::Freeze`] (already resolved).
    pub mode: HoldMode,
}

/// What the paper's law and its repair share: the errors generator's alpha (17) with its
/// memory at the goal, the hold, the two PI loops (22), (24) and the inverse of (20) to
/// absolute wheel angle references. Only the errors differ between the two laws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct OuterLoops<T: Lane> {
    /// r, m and R, m (the controller's model), for the inverse of (20); 1/r, 1/m, for
    /// the lanes ([`Lane::div_by`]).
    wheel_radius: T::Scalar,
    inv_wheel_radius: T::Scalar,
    half_track: T::Scalar,
    /// Control period, s: the PI integrators' step.
    control_dt: T::Scalar,
    /// int e_theta dt, rad s.
    int_e_theta: T,
    /// int e_s dt, m s.
    int_e_s: T,
    /// alpha of the last tick outside `goal_radius`, rad, where `has_alpha`.
    last_alpha: T,
    has_alpha: T::Mask,
    /// Wheel references of the last tick, rad, where `has_refs` ([`HoldMode::Freeze`]
    /// keeps them).
    last_refs: Wheels<T>,
    has_refs: T::Mask,
    /// The last tick was inside the hold radius ([`Law::holding`]).
    pub(crate) held: T::Mask,
    /// Anti-windup (conditional integration): the integrators hold where the wheel stage
    /// saturated at the last tick (`saturated`, [`Law::wheels_saturated`]).
    pub(crate) anti_windup: bool,
    pub(crate) saturated: T::Mask,
}

impl<T: Lane> OuterLoops<T> {
    /// For the controller's robot model (r and R) and the control period (s,
    /// `control_dt`), with the anti-windup on or off.
    pub(crate) fn new(
        model: &RobotParams<T::Scalar>,
        control_dt: T::Scalar,
        anti_windup: bool,
    ) -> Result<Self, ParamError> {
        check::positive("control_dt", control_dt)?;
        let no = T::Mask::splat(false);
        Ok(Self {
            wheel_radius: model.wheel_radius,
            inv_wheel_radius: <T::Scalar as num_traits::One>::one() / model.wheel_radius,
            half_track: model.half_track,
            control_dt,
            int_e_theta: T::default(),
            int_e_s: T::default(),
            last_alpha: T::default(),
            has_alpha: no,
            last_refs: Wheels::default(),
            has_refs: no,
            held: no,
            anti_windup,
            saturated: no,
        })
    }

    /// One control period: `errors(dx, dy, dl, alpha)` gives (e_s in m, e_theta in rad)
    /// from the goal offset (m, world frame), the distance (m) and alpha (rad); the
    /// result is the wheel angle references (rad) and the logged errors. Per lane, the
    /// branches of the scalar law are selects; where every lane takes the same branch
    /// (always, for one run) only that branch is computed.
    #[inline(always)]
    pub(crate) fn step(
        &mut self,
        g: &PiGains<T::Scalar>,
        hold: Hold<T::Scalar>,
        pose: Pose2<T>,
        goal: Pose2<T>,
        alpha_at_goal: T,
        errors: impl FnOnce(T, T, T, T) -> (T, T),
    ) -> (Wheels<T>, ControlErrors<T>) {
        let zero = T::default();
        let dx = goal.x - pose.x;
        let dy = goal.y - pose.y;
        let dl = dx.hypot(dy);
        // At the goal alpha is undefined: keep the last one (or the caller's start value).
        let far = T::splat(hold.goal_radius).lt(dl);
        let fresh = dy.atan2(dx);
        let alpha = T::select(far, fresh, T::select(self.has_alpha, self.last_alpha, alpha_at_goal));
        self.last_alpha.assign_where(far, fresh);
        self.has_alpha = self.has_alpha | far;
        // Hold: inside the radius the outer errors are taken as zero and the integrators
        // stop, so u = Ki * int and the references stay put (zero errors; note the step on
        // entry: the proportional parts Kp e drop out at once), or the references of the
        // last tick outside are kept (freeze).
        let in_hold =
            if hold.radius > T::Scalar::zero() { dl.lt(T::splat(hold.radius)) } else { T::Mask::splat(false) };
        self.held = in_hold;
        let freeze = if hold.mode == HoldMode::Freeze { in_hold & self.has_refs } else { T::Mask::splat(false) };
        if freeze.all() {
            return (self.last_refs, ControlErrors { e_s: zero, e_theta: zero, dl });
        }
        let (e_s, e_theta) = if in_hold.all() {
            (zero, zero)
        } else {
            let (e_s, e_theta) = errors(dx, dy, dl, alpha);
            (T::select(in_hold, zero, e_s), T::select(in_hold, zero, e_theta))
        };
        // Forward-Euler sums that include the current error; they stop in the hold and,
        // with the anti-windup, where the wheel stage saturated at the last tick
        // (conditional integration: the references then move no faster than the wheels
        // follow them, and keep the ratio of the two loops' steps, the curvature).
        let dt = T::splat(self.control_dt);
        let stop = if self.anti_windup { in_hold | self.saturated } else { in_hold };
        self.int_e_s = T::select(stop, self.int_e_s, self.int_e_s + e_s * dt);
        self.int_e_theta = T::select(stop, self.int_e_theta, self.int_e_theta + e_theta * dt);
        let u_s = T::splat(g.kp_s) * e_s + T::splat(g.ki_s) * self.int_e_s;
        let u_theta = T::splat(g.kp_theta) * e_theta + T::splat(g.ki_theta) * self.int_e_theta;
        let turn = T::splat(self.half_track) * u_theta;
        let (r, inv_r) = (self.wheel_radius, self.inv_wheel_radius);
        let refs = Wheels::new(
            T::select(freeze, self.last_refs.right, (u_s + turn).div_by(r, inv_r)),
            T::select(freeze, self.last_refs.left, (u_s - turn).div_by(r, inv_r)),
        );
        self.last_refs = refs;
        self.has_refs = T::Mask::splat(true);
        (refs, ControlErrors { e_s, e_theta, dl })
    }

    /// Clears the integrators and memories, as at t = 0.
    pub(crate) fn reset_lanes(&mut self, lanes: T::Mask) {
        let keep = !lanes;
        self.int_e_theta = T::select(lanes, T::default(), self.int_e_theta);
        self.int_e_s = T::select(lanes, T::default(), self.int_e_s);
        self.has_alpha = self.has_alpha & keep;
        self.has_refs = self.has_refs & keep;
        self.held = self.held & keep;
        self.saturated = self.saturated & keep;
    }
}
