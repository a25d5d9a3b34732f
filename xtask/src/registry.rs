//! The registry of laws as data: one [`LawRow`] per line of `wmr_core::for_each_law!`.

use core::mem::{align_of, size_of};
use wmr_core::describe::{Described, ParamField};
use wmr_core::{Controller, Follows};

/// How the C API stores a value: a tag word, then the value (`wmr-ffi`'s `Slot`).
#[repr(C)]
struct Slot<V> {
    tag: u64,
    value: V,
}

/// One law of the registry.
#[derive(Clone, Copy, Debug)]
pub struct LawRow {
    /// Its Rust variant name (`PaperBidirectional`).
    pub variant: &'static str,
    /// Its keys' type (`PaperBidirectionalParams`).
    pub params: &'static str,
    /// Its law type (`PaperBidirectionalLaw`).
    pub law: &'static str,
    /// Its `kind` (`paper_bidirectional`).
    pub kind: &'static str,
    /// Its trace code.
    pub code: u32,
    /// What it follows.
    pub follows: Follows,
    /// Its one-line description (the registry line's doc).
    pub about: &'static str,
    /// Its keys.
    pub fields: &'static [ParamField],
    /// Bytes of its C storage slot (tag and controller) in f32 and f64.
    pub slot_bytes: [usize; 2],
    /// Alignment of those slots.
    pub slot_align: [usize; 2],
}

macro_rules! rows {
    ($krate:tt; $( $(#[doc = $doc:literal])* $variant:ident($params:ident, $law:ident) = $kind:ident, code $code:literal, follows $follows:ident; )+) => {
        /// Every law, in the registry's order.
        pub fn laws() -> Vec<LawRow> {
            vec![$(
                LawRow {
                    variant: stringify!($variant),
                    params: stringify!($params),
                    law: stringify!($law),
                    kind: stringify!($kind),
                    code: $code,
                    follows: Follows::$follows,
                    about: [$($doc),*][0].trim_ascii(),
                    fields: <$krate::$params<f64> as Described>::FIELDS,
                    slot_bytes: [
                        size_of::<Slot<Controller<f32, $krate::$law<f32>>>>(),
                        size_of::<Slot<Controller<f64, $krate::$law<f64>>>>(),
                    ],
                    slot_align: [
                        align_of::<Slot<Controller<f32, $krate::$law<f32>>>>(),
                        align_of::<Slot<Controller<f64, $krate::$law<f64>>>>(),
                    ],
                },
            )+]
        }
    };
}
wmr_core::for_each_law!(rows);

/// `snake_case` to `SCREAMING_SNAKE_CASE`.
pub fn screaming(kind: &str) -> String {
    kind.to_ascii_uppercase()
}
