//! Facade over the wmr crates: the workspace root holds the cross-crate tests and benches.

pub use wmr_core as core;
