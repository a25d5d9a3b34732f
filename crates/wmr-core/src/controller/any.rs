//! Every law behind one enum, chosen by name at run time (`[controller] kind = ...`):
//! dispatched by `match`, no `dyn`, no alloc.
//!
//! The list of laws is written once, in the `laws!` invocation at the bottom: a new law
//! is its own file plus one line there.

use super::backstepping::{BacksteppingLaw, BacksteppingParams};
use super::kanayama::{KanayamaLaw, KanayamaParams};
use super::law::{Law, LawOutput};
use super::lyapunov::{LyapunovLaw, LyapunovParams};
use super::paper::{PaperLaw, PaperParams};
use super::paper_bidirectional::{PaperBidirectionalLaw, PaperBidirectionalParams};
use super::polar::{PolarLaw, PolarParams};
use super::pure_pursuit::{PurePursuitLaw, PurePursuitParams};
use crate::describe::{Described, ParamField};
use crate::error::ParamError;
use crate::lane::Lane;
use crate::reference::{Path, ReferenceState};
use crate::sensor::Measurement;
use crate::{Real, RobotParams};

/// Defines [`LawParams`] (a law's keys, tagged by `kind`) and [`AnyLaw`] (the running
/// law) with one variant per law, and every `match` over them.
macro_rules! laws {
    ($( $(#[$doc:meta])* $variant:ident($params:ident, $law:ident) = $name:literal, new($p:ident, $model:ident, $dt:ident) => $new:expr; )+) => {
        /// The keys of one law, tagged by its `kind` name (serialized with a `kind` key;
        /// read with `LawParams::deserialize_variant` (feature `serde`), since serde's tagged-enum reader
        /// needs an allocator).
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        #[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "snake_case"))]
        #[non_exhaustive]
        pub enum LawParams<T> {
            $( $(#[$doc])* $variant($params<T>), )+
        }

        impl<T: Real> LawParams<T> {
            /// Every law with its default keys, in documentation order.
            pub fn defaults() -> [Self; [$($name),+].len()] {
                [$( LawParams::$variant($params::default()), )+]
            }

            /// The law's `kind` name.
            pub fn kind(&self) -> &'static str {
                match self { $( LawParams::$variant(_) => $name, )+ }
            }

            /// The declared keys of the law ([`crate::describe`]): what `--help`, the
            /// docs tables and the C header are made from.
            pub fn fields(&self) -> &'static [ParamField] {
                match self { $( LawParams::$variant(_) => <$params<T> as Described>::FIELDS, )+ }
            }

            /// Reads the keys of the same law as `self` (without `kind`) from `d`.
            #[cfg(feature = "serde")]
            pub fn deserialize_variant<'de, D: serde::Deserializer<'de>>(&self, d: D) -> Result<Self, D::Error>
            where
                T: serde::Deserialize<'de>,
            {
                use serde::Deserialize as _;
                Ok(match self { $( LawParams::$variant(_) => LawParams::$variant($params::deserialize(d)?), )+ })
            }

            /// Validates the keys and builds the law for the controller's robot model and
            /// control period (s).
            pub fn build(&self, model: &RobotParams<T>, control_dt: T) -> Result<AnyLaw<T>, ParamError> {
                self.build_lanes(model, control_dt)
            }

            /// [`LawParams::build`] for several runs side by side ([`crate::lane`]).
            pub fn build_lanes<L: Lane<Scalar = T>>(&self, model: &RobotParams<T>, control_dt: T) -> Result<AnyLaw<L>, ParamError> {
                Ok(match *self { $( LawParams::$variant($p) => { let ($model, $dt) = (model, control_dt); let _ = ($model, $dt); AnyLaw::$variant($new?) } )+ })
            }
        }

        /// Any law, dispatched by `match`. Implements [`Law`].
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[non_exhaustive]
        pub enum AnyLaw<T: Lane> {
            $( $(#[$doc])* $variant($law<T>), )+
        }

        impl<T: Lane> AnyLaw<T> {
            /// The law's `kind` name.
            pub fn kind(&self) -> &'static str {
                match self { $( AnyLaw::$variant(_) => $name, )+ }
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

            fn holding(&self) -> T::Mask {
                match self { $( AnyLaw::$variant(l) => l.holding(), )+ }
            }
        }
    };
}

laws! {
    /// The paper's law (`"paper"`), [`PaperLaw`].
    Paper(PaperParams, PaperLaw) = "paper", new(p, model, dt) => PaperLaw::for_lanes(p, model, dt);
    /// The paper's law repaired (`"paper_bidirectional"`), [`PaperBidirectionalLaw`].
    PaperBidirectional(PaperBidirectionalParams, PaperBidirectionalLaw) = "paper_bidirectional", new(p, model, dt) => PaperBidirectionalLaw::for_lanes(p, model, dt);
    /// Astolfi's polar law (`"polar"`), [`PolarLaw`].
    Polar(PolarParams, PolarLaw) = "polar", new(p, model, dt) => PolarLaw::for_lanes(p);
    /// Aicardi et al.'s Lyapunov law (`"lyapunov"`), [`LyapunovLaw`].
    Lyapunov(LyapunovParams, LyapunovLaw) = "lyapunov", new(p, model, dt) => LyapunovLaw::for_lanes(p);
    /// Kanayama et al.'s trajectory tracking (`"kanayama"`), [`KanayamaLaw`].
    Kanayama(KanayamaParams, KanayamaLaw) = "kanayama", new(p, model, dt) => KanayamaLaw::for_lanes(p);
    /// Kanayama back-stepped into the dynamics (`"backstepping"`), [`BacksteppingLaw`].
    Backstepping(BacksteppingParams, BacksteppingLaw) = "backstepping", new(p, model, dt) => BacksteppingLaw::for_lanes(p, model, dt);
    /// Regulated pure pursuit, path following (`"pure_pursuit"`), [`PurePursuitLaw`].
    PurePursuit(PurePursuitParams, PurePursuitLaw) = "pure_pursuit", new(p, model, dt) => PurePursuitLaw::for_lanes(p, model);
}

impl<T: Real> Default for LawParams<T> {
    /// The paper's law with its default keys.
    fn default() -> Self {
        LawParams::Paper(PaperParams::paper())
    }
}
