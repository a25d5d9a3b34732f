//! What builds a reference of each kind, as the trace ([`crate::trace`]) and the firmware
//! carry it: the kind's arguments as 32-bit words, rebuilt by the same constructor on the
//! host and on the target, so a replay checks the construction too. Each kind's file
//! implements [`KindConfig`] for what builds it and [`Configured`] for the reference;
//! [`super::any`]'s list makes [`super::ReferenceConfig`] of them.

use crate::Real;
use crate::error::ParamError;

/// The arguments that build a reference of one kind.
pub trait KindConfig<T: Real>: Copy + core::fmt::Debug + PartialEq {
    /// The reference they build (a waypoints path in its own fixed storage).
    type Built;
    /// The words [`KindConfig::encode`] writes, at most.
    const WORDS: usize;

    /// Builds the reference; its constructor checks the values (errors name the key).
    fn build(&self) -> Result<Self::Built, ParamError>;

    /// Writes the arguments into `args` (at least [`KindConfig::WORDS`] words; the
    /// words past what this kind writes are left as they are), each value through `real`.
    fn encode(&self, args: &mut [u32], real: &mut dyn FnMut(T) -> u32);

    /// Reads the arguments from `args` ([`KindConfig::WORDS`] words), each value through
    /// `real`. Err: why the words are no such arguments.
    fn decode(args: &[u32], real: &mut dyn FnMut(u32) -> T) -> Result<Self, &'static str>;
}

/// A reference that can say what built it.
pub trait Configured<T: Real> {
    /// What built it.
    type Config: KindConfig<T>;

    /// What built it. Errors name the key a trace cannot carry (a waypoints path longer
    /// than the fixed storage).
    fn config(&self) -> Result<Self::Config, ParamError>;
}

/// [`KindConfig`] for a [`params!`](crate::params) struct declared with `words;`: its
/// fields are the arguments, in declaration order; `|c| build` builds `$built` of them.
macro_rules! config_by_words {
    ($ty:ident => $built:ident, |$c:ident| $build:expr) => {
        impl<T: $crate::Real> $crate::reference::config::KindConfig<T> for $ty<T> {
            type Built = $built<T>;
            const WORDS: usize = <$ty<T> as $crate::describe::Described>::FIELDS.len();

            fn build(&self) -> Result<Self::Built, $crate::error::ParamError> {
                let $c = self;
                $build
            }

            fn encode(&self, args: &mut [u32], real: &mut dyn FnMut(T) -> u32) {
                self.to_words(args, real)
            }

            fn decode(args: &[u32], real: &mut dyn FnMut(u32) -> T) -> Result<Self, &'static str> {
                Self::from_words(args, real)
            }
        }
    };
}
pub(crate) use config_by_words;
