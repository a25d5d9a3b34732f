//! Parameter structs declared once: each field with its doc line, unit and rule, from
//! which come the struct itself, its field table ([`Described::FIELDS`], read by the
//! scenario schema, `--help` and the docs tables) and its elementwise map (f32 <-> f64).
//!
//! ```
//! use wmr_core::RobotParams;
//! use wmr_core::describe::Described;
//!
//! let mass = &RobotParams::<f64>::FIELDS[0];
//! assert_eq!((mass.name, mass.ty, mass.unit, mass.rule), ("mass", "T", "kg", "> 0"));
//! let f32_robot: RobotParams<f32> = RobotParams::<f64>::paper().cast();
//! assert_eq!(f32_robot.mass, 5.0);
//! ```

/// One field of a parameter struct, as [`params!`](crate::params) declared it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParamField {
    /// The field's name: the scenario key, the C struct member, the Python keyword.
    pub name: &'static str,
    /// Its type as declared: `T` (the float parameter) or a fixed type (`u32`, `bool`, an enum).
    pub ty: &'static str,
    /// Its unit (`""` for a name, a flag or a count).
    pub unit: &'static str,
    /// What it is, in one line (the first line of the field's doc).
    pub doc: &'static str,
    /// What values it accepts, as the validation checks them.
    pub rule: &'static str,
}

/// A parameter struct declared with [`params!`](crate::params): its fields, in declaration order.
pub trait Described {
    /// Every field, in declaration order (the serde and `repr` order).
    const FIELDS: &'static [ParamField];
}

/// A fixed-type parameter field (a flag or a mode) as one 32-bit word: how the trace
/// ([`crate::trace`]) and the C API carry it. A `T` field is an f32 bit pattern instead.
pub trait Word: Copy {
    /// The field's word: `0`/`1` for a flag, the `#[repr(u32)]` discriminant for a mode.
    fn to_word(self) -> u32;
    /// The field of a word; `None` for a word that is no value of the field.
    fn from_word(w: u32) -> Option<Self>;
}

impl Word for bool {
    fn to_word(self) -> u32 {
        u32::from(self)
    }
    fn from_word(w: u32) -> Option<Self> {
        match w {
            0 => Some(false),
            1 => Some(true),
            _ => None,
        }
    }
}

impl Word for u32 {
    fn to_word(self) -> u32 {
        self
    }
    fn from_word(w: u32) -> Option<Self> {
        Some(w)
    }
}

/// [`Word`] for a `#[repr(u32)]` enum without data: its discriminants are its words.
#[macro_export]
#[doc(hidden)]
macro_rules! word_enum {
    ($ty:ty { $($variant:ident),+ $(,)? }) => {
        impl $crate::describe::Word for $ty {
            fn to_word(self) -> u32 {
                self as u32
            }
            fn from_word(w: u32) -> Option<Self> {
                $( if w == <$ty>::$variant as u32 { return Some(<$ty>::$variant); } )+
                None
            }
        }
    };
}

/// The first line of a `///` doc without its leading space (what `#[doc = ..]` holds).
#[doc(hidden)]
pub const fn doc_line(doc: &'static str) -> &'static str {
    doc.trim_ascii()
}

/// Declares a parameter struct generic over `T` with, per field, its doc (the first
/// line is the field's doc line), type, unit and rule:
///
/// ```
/// wmr_core::params! {
///     /// The struct's doc.
///     #[derive(Clone, Copy, Debug, PartialEq)]
///     pub struct Example<T> {
///         /// m, a mass.
///         pub mass: T [unit = "kg", rule = "> 0"],
///         /// How many.
///         pub count: u32 [unit = "", rule = "whole number"],
///     }
/// }
/// use wmr_core::describe::Described;
///
/// assert_eq!(Example::<f64>::FIELDS[0].doc, "m, a mass.");
/// assert_eq!(Example::<f64>::FIELDS[1].name, "count");
/// let doubled = Example { mass: 2.0f64, count: 3 }.map(|m| m as f32 * 2.0);
/// assert_eq!(doubled, Example { mass: 4.0f32, count: 3 });
/// ```
///
/// Generates the struct (attributes and fields as written, the unit and rule appended to
/// each field's rustdoc), [`Described`] with the field table, `map` (every `T` field
/// through a function, the others copied) and `cast` (to another [`Real`](crate::Real),
/// through f64: exact when widening, rounded to nearest when narrowing, as `as` does).
/// A field's type is one token: `T` is mapped, anything else (`bool`, `u32`, an enum)
/// is copied. Opened with `words;`, it also generates `to_words` and `from_words`: every
/// field in one 32-bit word (the trace's and the firmware's form of a law's keys), each
/// non-`T` field through its [`Word`].
#[macro_export]
macro_rules! params {
    (@map T, $v:expr, $f:ident) => { $f($v) };
    (@map $other:tt, $v:expr, $f:ident) => { $v };
    (@put T, $v:expr, $real:ident) => { $real($v) };
    (@put $other:tt, $v:expr, $real:ident) => { <$other as $crate::describe::Word>::to_word($v) };
    (@get T, $w:expr, $field:ident, $real:ident) => { $real($w) };
    (@get $other:tt, $w:expr, $field:ident, $real:ident) => {
        match <$other as $crate::describe::Word>::from_word($w) {
            Some(v) => v,
            None => return Err(stringify!($field)),
        }
    };
    (@unit "") => { "none" };
    (@unit $unit:literal) => { $unit };
    (@words $name:ident { $($field:ident : $fty:tt),+ }) => {
        impl<T> $name<T> {
            /// Writes every field into one word each, in declaration order: a `T` field
            /// through `real` (e.g. its f32 bit pattern), the others as their
            /// [`Word`](crate::describe::Word). `out` holds at least `FIELDS.len()` words.
            pub fn to_words(&self, out: &mut [u32], mut real: impl FnMut(T) -> u32)
            where
                T: Copy,
            {
                let mut slots = out.iter_mut();
                $( if let Some(w) = slots.next() { *w = $crate::params!(@put $fty, self.$field, real); } )+
            }

            /// Reads the fields from their words ([`Self::to_words`]), a `T` field through
            /// `real`. Err: the name of a flag or mode whose word is no value of it.
            pub fn from_words(w: &[u32], mut real: impl FnMut(u32) -> T) -> Result<Self, &'static str> {
                let mut words = w.iter().copied();
                Ok($name { $( $field: $crate::params!(@get $fty, words.next().unwrap_or(u32::MAX), $field, real), )+ })
            }

        }
    };
    (words; $($rest:tt)*) => {
        $crate::params!($($rest)*);
        $crate::params!(@words_of $($rest)*);
    };
    (
        @words_of
        $(#[$smeta:meta])*
        $svis:vis struct $name:ident<T> {
            $(
                #[doc = $doc:literal]
                $(#[$fmeta:meta])*
                $fvis:vis $field:ident : $fty:tt [unit = $unit:literal, rule = $rule:literal]
            ),+ $(,)?
        }
    ) => {
        $crate::params!(@words $name { $($field : $fty),+ });
    };
    (
        $(#[$smeta:meta])*
        $svis:vis struct $name:ident<T> {
            $(
                #[doc = $doc:literal]
                $(#[$fmeta:meta])*
                $fvis:vis $field:ident : $fty:tt [unit = $unit:literal, rule = $rule:literal]
            ),+ $(,)?
        }
    ) => {
        $(#[$smeta])*
        $svis struct $name<T> {
            $(
                #[doc = $doc]
                $(#[$fmeta])*
                #[doc = ""]
                #[doc = concat!("Unit: ", $crate::params!(@unit $unit), "; valid: ", $rule, ".")]
                $fvis $field: $fty,
            )+
        }

        impl<T> $crate::describe::Described for $name<T> {
            const FIELDS: &'static [$crate::describe::ParamField] = &[$(
                $crate::describe::ParamField {
                    name: stringify!($field),
                    ty: stringify!($fty),
                    unit: $unit,
                    doc: $crate::describe::doc_line($doc),
                    rule: $rule,
                },
            )+];
        }

        impl<T> $name<T> {
            /// The same parameters with every `T` field passed through `f` (in
            /// declaration order); the other fields are copied.
            pub fn map<U>(self, mut f: impl FnMut(T) -> U) -> $name<U> {
                $name { $( $field: $crate::params!(@map $fty, self.$field, f), )+ }
            }

            /// The same parameters in another precision, through f64 (see [`params!`](crate::params)).
            pub fn cast<U: $crate::Real>(self) -> $name<U>
            where
                T: $crate::Real,
            {
                self.map(|v| U::lit(v.to_f64_lossless()))
            }
        }
    };
}
