//! xtask's integration tests as one binary: each file of tests/ is a module of it.
// A new file of tests/ runs only with its `mod` line here (Cargo.toml: `autotests = false`).

mod declared;
mod fresh;
mod stubs;
