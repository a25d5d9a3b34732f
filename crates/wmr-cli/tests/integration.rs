//! wmr-cli's integration tests as one binary: each file of tests/ is a module of it.
// A new file of tests/ runs only with its `mod` line here (Cargo.toml: `autotests = false`).

mod identify_common;
mod skip;
mod wait;

mod cli;
mod compare_paths;
mod docking;
mod docs_commands;
mod docs_console_tables;
mod docs_tables;
mod excite_mcap;
mod foxglove;
mod foxglove_mppi;
mod fuzz;
mod golden;
mod hardening;
mod hardening39;
mod help_topics;
mod identify;
mod identify_c_header;
mod identify_mcap;
mod keys_documented;
mod live;
mod live_hardening;
mod long_path;
mod memory;
mod newcomer;
mod odometry;
mod ros2_odom;
mod ros2_viewer;
mod signals;
mod stream_order;
mod sweep_plot;
mod trace;
