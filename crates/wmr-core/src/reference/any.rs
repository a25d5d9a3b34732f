//! Every kind of reference behind one enum, chosen by name at run time
//! (`[reference] kind = ...`): dispatched by `match`, no `dyn` in the loop, no alloc.
//!
//! The list is written once, in the `references!` invocation below: a new kind is its
//! own file plus one line there.

use super::circle::Circle;
use super::figure_eight::FigureEight;
use super::fixed::FixedGoal;
use super::line::Line;
use super::path::Path;
use super::state::{Reference, ReferenceState};
use super::waypoints::{FIXED_WORDS, Waypoints};
use crate::Real;
use crate::math::Pose2;

/// Defines [`AnyReference`] with one variant per kind and every `match` over it.
macro_rules! references {
    ($( $(#[$doc:meta])* $variant:ident($ty:ty) = $name:literal; )+) => {
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
    };
}

references! {
    /// A goal at rest (no `[reference]` table): point stabilization.
    Goal(FixedGoal<T>) = "goal";
    /// A circle at constant speed, [`Circle`].
    Circle(Circle<T>) = "circle";
    /// A figure-eight, [`FigureEight`].
    FigureEight(FigureEight<T>) = "figure_eight";
    /// A straight line, [`Line`].
    Line(Line<T>) = "line";
    /// A spline through points with a speed profile (`waypoints` and `file`), [`Waypoints`].
    Waypoints(Waypoints<T, S>) = "waypoints";
}

impl<T: Real, S: AsRef<[T]>> AnyReference<T, S> {
    /// The pose of C_ref at t = 0: what a sweep's start offsets are added to.
    pub fn start_pose(&self) -> Pose2<T> {
        self.state_at(T::zero()).pose
    }
}
