//! wmr-core's integration tests as one binary: each file of tests/ is a module of it.
// A new file of tests/ runs only with its `mod` line here (Cargo.toml: `autotests = false`).

mod common;

mod closed_loop;
mod describe;
mod disturbances;
mod graceful;
mod issue25_drive_clamp;
mod kinematics_props;
mod long_path;
mod model;
mod mppi;
mod mppi_dynamic;
mod observer;
mod obstacle;
mod odometry;
mod path_search;
mod payload;
mod pure_pursuit;
mod push;
mod real_world;
mod reference;
mod repairs;
mod sensor_periods;
mod slip;
mod stiction;
mod tracking;
mod validation;
