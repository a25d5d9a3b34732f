//! wmr-scenario's integration tests as one binary: each file of tests/ is a module of it.
// A new file of tests/ runs only with its `mod` line here (Cargo.toml: `autotests = false`).

#[path = "../../wmr-cli/tests/skip/mod.rs"]
mod skip;

mod arrival;
mod chunk;
mod docking;
mod fast;
mod motor;
mod mppi_seed;
mod observer;
mod odometry;
mod payload_push;
mod preset;
mod real_world;
mod run_one;
mod saturation;
mod scenario;
mod self_contained;
mod settle;
mod slip;
mod sweep;
mod sweep_obstacles;
mod tracking;
mod tracking_sweep;
