//! Every law behind one enum, chosen by name at run time (`[controller] kind = ...`):
//! dispatched by `match`, no `dyn`, no alloc. Expanded from the registry
//! ([`super::registry`]): this file names no law.

use super::law::{Follows, Law, LawContext, LawOutput, LawSpec};
use crate::describe::{Described, ParamField};
use crate::error::ParamError;
use crate::lane::Lane;
use crate::reference::{Path, ReferenceState};
use crate::sensor::Measurement;
use crate::{Real, RobotParams};

/// Defines [`LawParams`] (a law's keys, tagged by `kind`) and [`AnyLaw`] (the running
/// law) with one variant per line of [`crate::for_each_law!`], and every `match` over them.
macro_rules! laws {
    ($krate:tt; $( $(#[doc = $doc:literal])* $variant:ident($params:ident, $law:ident) = $kind:ident, code $code:literal, follows $follows:ident; )+) => {
        /// The keys of one law, tagged by its `kind` name (serialized with a `kind` key;
        /// read with `LawParams::deserialize_variant` (feature `serde`), since serde's tagged-enum reader
        /// needs an allocator).
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        #[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "snake_case"))]
        #[non_exhaustive]
        pub enum LawParams<T> {
            $( $(#[doc = $doc])* #[doc = concat!("\n\n`kind = \"", stringify!($kind), "\"`: [`", stringify!($law), "`](crate::", stringify!($law), ").")] $variant($krate::$params<T>), )+
        }

        impl<T: Real> LawParams<T> {
            /// Every law with its default keys, in documentation order.
            pub fn defaults() -> [Self; [$(stringify!($kind)),+].len()] {
                [$( LawParams::$variant($krate::$params::default()), )+]
            }

            /// The law's `kind` name.
            pub fn kind(&self) -> &'static str {
                match self { $( LawParams::$variant(_) => stringify!($kind), )+ }
            }

            /// The law's name in Rust enums and, with `Controller` appended, its Python
            /// class (`PaperBidirectional`).
            pub fn name(&self) -> &'static str {
                match self { $( LawParams::$variant(_) => stringify!($variant), )+ }
            }

            /// What the law is, in one line (the first line of its registry doc).
            pub fn about(&self) -> &'static str {
                match self { $( LawParams::$variant(_) => [$($doc),*][0].trim_ascii(), )+ }
            }

            /// What the law follows: a goal, a trajectory or a path.
            pub fn follows(&self) -> Follows {
                match self { $( LawParams::$variant(_) => Follows::$follows, )+ }
            }

            /// The law's code in a trace file and the C storage tags (never reused).
            pub fn code(&self) -> u32 {
                match self { $( LawParams::$variant(_) => $code, )+ }
            }

            /// CPU time of a plant step under the law against one under the paper's law
            /// ([`LawSpec::update_cost`]): announced durations and the step budget.
            pub fn update_cost(&self) -> f64 {
                match self { $( LawParams::$variant(p) => LawSpec::<T>::update_cost(p), )+ }
            }

            /// Whether the trace carries the law ([`LawSpec::TRACED`]).
            pub fn traced(&self) -> bool {
                match self { $( LawParams::$variant(_) => <$krate::$params<T> as LawSpec<T>>::TRACED, )+ }
            }

            /// Whether the law demands a body twist ([`LawSpec::TWIST_DEMAND`]).
            pub fn twist_demand(&self) -> bool {
                match self { $( LawParams::$variant(_) => <$krate::$params<T> as LawSpec<T>>::TWIST_DEMAND, )+ }
            }

            /// The declared keys of the law ([`crate::describe`]): what `--help`, the
            /// docs tables and the C header are made from.
            pub fn fields(&self) -> &'static [ParamField] {
                match self { $( LawParams::$variant(_) => <$krate::$params<T> as Described>::FIELDS, )+ }
            }

            /// Writes the law's keys into one word each ([`crate::describe::Word`], a `T`
            /// key through `real`); returns the law's code.
            pub fn to_words(&self, out: &mut [u32], real: impl FnMut(T) -> u32) -> u32 {
                match self { $( LawParams::$variant(p) => { p.to_words(out, real); $code } )+ }
            }

            /// The law of `code` read from its words ([`LawParams::to_words`]). Err: what is wrong.
            pub fn from_words(code: u32, w: &[u32], real: impl FnMut(u32) -> T) -> Result<Self, &'static str> {
                match code {
                    $( $code => Ok(LawParams::$variant($krate::$params::from_words(w, real)?)), )+
                    _ => Err("kind"),
                }
            }

            /// Reads the keys of the same law as `self` (without `kind`) from `d`.
            #[cfg(feature = "serde")]
            pub fn deserialize_variant<'de, D: serde::Deserializer<'de>>(&self, d: D) -> Result<Self, D::Error>
            where
                T: serde::Deserialize<'de>,
            {
                use serde::Deserialize as _;
                Ok(match self { $( LawParams::$variant(_) => LawParams::$variant($krate::$params::deserialize(d)?), )+ })
            }

            /// Validates the keys and builds the law for the controller's robot model and
            /// control period (s).
            pub fn build(&self, model: &RobotParams<T>, control_dt: T) -> Result<AnyLaw<T>, ParamError> {
                self.build_lanes(model, control_dt)
            }

            /// [`LawParams::build`] for several runs side by side ([`crate::lane`]).
            pub fn build_lanes<L: Lane<Scalar = T>>(&self, model: &RobotParams<T>, control_dt: T) -> Result<AnyLaw<L>, ParamError> {
                Ok(match self { $( LawParams::$variant(p) => AnyLaw::$variant(p.build::<L>(model, control_dt)?), )+ })
            }

            /// [`LawParams::build_lanes`] knowing all the controller knows: what a
            /// controller calls ([`LawSpec::build_in`]).
            pub fn build_lanes_in<L: Lane<Scalar = T>>(&self, ctx: &LawContext<'_, T>) -> Result<AnyLaw<L>, ParamError> {
                Ok(match self { $( LawParams::$variant(p) => AnyLaw::$variant(p.build_in::<L>(ctx)?), )+ })
            }
        }

        /// Any law, dispatched by `match`. Implements [`Law`].
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[non_exhaustive]
        // MPPI holds its sequence and its obstacles inline (no allocation in the core): the
        // enum is as large as it is, and every law a plain `Copy` value.
        #[allow(clippy::large_enum_variant)]
        pub enum AnyLaw<T: Lane> {
            $( $(#[doc = $doc])* $variant($krate::$law<T>), )+
        }

        impl<T: Lane> AnyLaw<T> {
            /// The law's `kind` name.
            pub fn kind(&self) -> &'static str {
                match self { $( AnyLaw::$variant(_) => stringify!($kind), )+ }
            }
        }

        impl<T: Lane> Law<T> for AnyLaw<T> {
            #[cfg_attr(target_os = "none", inline)]
            #[cfg_attr(not(target_os = "none"), inline(always))]
            fn update(&mut self, t: T, m: &Measurement<T>, r: &ReferenceState<T>) -> LawOutput<T> {
                match self { $( AnyLaw::$variant(l) => l.update(t, m, r), )+ }
            }

            #[cfg_attr(target_os = "none", inline)]
            #[cfg_attr(not(target_os = "none"), inline(always))]
            fn update_on_path(&mut self, t: T, m: &Measurement<T>, r: &ReferenceState<T>, path: &dyn Path<T>) -> LawOutput<T> {
                match self { $( AnyLaw::$variant(l) => l.update_on_path(t, m, r, path), )+ }
            }

            fn needs_path(&self) -> bool {
                match self { $( AnyLaw::$variant(l) => l.needs_path(), )+ }
            }

            fn reads_path(&self) -> bool {
                match self { $( AnyLaw::$variant(l) => l.reads_path(), )+ }
            }

            fn reset_lanes(&mut self, lanes: T::Mask) {
                match self { $( AnyLaw::$variant(l) => l.reset_lanes(lanes), )+ }
            }

            #[inline(always)]
            fn wheels_saturated(&mut self, lanes: T::Mask) {
                match self { $( AnyLaw::$variant(l) => l.wheels_saturated(lanes), )+ }
            }

            fn anti_windup(&self) -> bool {
                match self { $( AnyLaw::$variant(l) => l.anti_windup(), )+ }
            }

            fn reaches_heading(&self) -> bool {
                match self { $( AnyLaw::$variant(l) => l.reaches_heading(), )+ }
            }

            fn holding(&self) -> T::Mask {
                match self { $( AnyLaw::$variant(l) => l.holding(), )+ }
            }
        }
    };
}

crate::for_each_law!(laws);

impl<T: Real> Default for LawParams<T> {
    /// The paper's law with its default keys.
    fn default() -> Self {
        LawParams::Paper(crate::PaperParams::paper())
    }
}
