//! wmr-ffi's integration tests as one binary: each file of tests/ is a module of it.
// A new file of tests/ runs only with its `mod` line here (Cargo.toml: `autotests = false`).

mod api;
mod c_programs;
mod fuzz;
mod header;
mod issue25;
mod odometry_slip;
mod readme;
mod tracking;
