//! Every kind of reference behind one enum, chosen by name at run time
//! (`[reference] kind = ...`): dispatched by `match`, no `dyn` in the loop, no alloc.
//!
//! The list is written once, in the `references!` invocation below: a new kind is its
//! own file plus one line there (the reference, what builds it, its name). What builds
//! any reference, [`ReferenceConfig`] (the trace's and the firmware's form, its kind code
//! the line's place in the list), follows from the same list.

use super::circle::Circle;
use super::config::{Configured, KindConfig};
use super::figure_eight::{FigureEight, FigureEightParams};
use super::fixed::FixedGoal;
use super::line::{Line, LineParams};
use super::path::Path;
use super::state::{Reference, ReferenceState};
use super::waypoints::{FIXED_WORDS, Waypoints, WaypointsConfig};
use crate::Real;
use crate::error::ParamError;
use crate::math::Pose2;

/// Defines [`AnyReference`] with one variant per kind and every `match` over it.
macro_rules! references {
    ($( $(#[$doc:meta])* $variant:ident($ty:ty) from $config:ty = $name:literal; )+) => {
        /// Any reference, dispatched by `match`. Implements [`Reference`]. `S` is the
        /// storage of a waypoints path ([`Waypoints`]): its own fixed array by default.
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[non_exhaustive]
        pub enum AnyReference<T, S = [T; FIXED_WORDS]> {
            $( $(#[$doc])* $variant($ty), )+
        }

        impl<T: Real, S: AsRef<[T]>> AnyReference<T, S> {
            /// Every kind's name, in documentation order.
            pub const KINDS: &'static [&'static str] = &[$($name),+];

            /// The kind's name (`[reference] kind`).
            pub fn kind(&self) -> &'static str {
                match self { $( AnyReference::$variant(_) => $name, )+ }
            }
        }

        impl<T: Real, S: AsRef<[T]>> Reference<T> for AnyReference<T, S> {
            #[inline]
            fn state_at(&self, t: T) -> ReferenceState<T> {
                match self { $( AnyReference::$variant(r) => r.state_at(t), )+ }
            }

            fn fixed(&self) -> bool {
                match self { $( AnyReference::$variant(r) => r.fixed(), )+ }
            }

            fn path(&self) -> Option<&dyn Path<T>> {
                match self { $( AnyReference::$variant(r) => r.path(), )+ }
            }
        }

        /// What builds a reference, as the trace ([`crate::trace`]) and the firmware
        /// carry it: its kind and the arguments of its constructor (a waypoints path's
        /// points and limits, not its spline, which is rebuilt from them).
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[non_exhaustive]
        pub enum ReferenceConfig<T> {
            $( $(#[$doc])* $variant($config), )+
        }

        /// The kind codes: each line's place in the list.
        #[repr(u32)]
        enum Code {
            $( $variant, )+
        }

        impl<T: Real> ReferenceConfig<T> {
            /// The most argument words a kind takes.
            pub const ARG_WORDS: usize = {
                let mut most = 0;
                $( if <$config as KindConfig<T>>::WORDS > most { most = <$config as KindConfig<T>>::WORDS; } )+
                most
            };

            /// What builds `r`. Errors name the key a trace cannot carry (`points` for a
            /// waypoints path longer than the fixed storage).
            pub fn of<S: AsRef<[T]>>(r: &AnyReference<T, S>) -> Result<Self, ParamError> {
                Ok(match r { $( AnyReference::$variant(k) => ReferenceConfig::$variant(k.config()?), )+ })
            }

            /// Builds the reference (its constructor checks the values; errors name the key).
            pub fn build(&self) -> Result<AnyReference<T>, ParamError> {
                Ok(match self { $( ReferenceConfig::$variant(c) => AnyReference::$variant(c.build()?), )+ })
            }

            /// The kind's code: its place in the list.
            pub fn code(&self) -> u32 {
                match self { $( ReferenceConfig::$variant(_) => Code::$variant as u32, )+ }
            }

            /// Writes the arguments into `args` ([`ReferenceConfig::ARG_WORDS`] words),
            /// each value through `real`.
            pub fn encode_args(&self, args: &mut [u32], real: &mut dyn FnMut(T) -> u32) {
                match self { $( ReferenceConfig::$variant(c) => c.encode(args, real), )+ }
            }

            /// Reads a reference of kind `code` from its arguments, each value through
            /// `real`. Err: an unknown code, or words that are no such arguments.
            pub fn decode(code: u32, args: &[u32], real: &mut dyn FnMut(u32) -> T) -> Result<Self, &'static str> {
                $( if code == Code::$variant as u32 {
                    return Ok(ReferenceConfig::$variant(<$config as KindConfig<T>>::decode(args, real)?));
                } )+
                Err("unknown reference kind")
            }
        }
    };
}

references! {
    /// A goal at rest (no `[reference]` table): point stabilization.
    Goal(FixedGoal<T>) from Pose2<T> = "goal";
    /// A circle at constant speed, [`Circle`].
    Circle(Circle<T>) from Circle<T> = "circle";
    /// A figure-eight, [`FigureEight`].
    FigureEight(FigureEight<T>) from FigureEightParams<T> = "figure_eight";
    /// A straight line, [`Line`].
    Line(Line<T>) from LineParams<T> = "line";
    /// A spline through points with a speed profile (`waypoints` and `file`), [`Waypoints`].
    Waypoints(Waypoints<T, S>) from WaypointsConfig<T> = "waypoints";
}

impl<T: Real, S: AsRef<[T]>> AnyReference<T, S> {
    /// The pose of C_ref at t = 0: what a sweep's start offsets are added to.
    pub fn start_pose(&self) -> Pose2<T> {
        self.state_at(T::zero()).pose
    }
}
