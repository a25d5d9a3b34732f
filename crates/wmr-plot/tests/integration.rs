//! wmr-plot's integration tests as one binary: each file of tests/ is a module of it.
// A new file of tests/ runs only with its `mod` line here (Cargo.toml: `autotests = false`).

mod common;

mod readable;
mod svg;
