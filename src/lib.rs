//! Facade over the wmr crates; the workspace root also holds the benches. Its docs are
//! the README, so the README's Rust example runs as a doctest.
#![doc = include_str!("../README.md")]

pub use wmr_core as core;
