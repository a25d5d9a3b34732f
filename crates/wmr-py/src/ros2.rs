//! The ROS 2 MCAP reader of `wmr-cli` (its `ros2::cdr` and `ros2::log`), compiled here from
//! the CLI's own files so that `wmr_py.identify` reads a log exactly as `wmr-cli identify`
//! does.

#![allow(dead_code)]

#[path = "../../wmr-cli/src/ros2/cdr.rs"]
pub mod cdr;
#[path = "../../wmr-cli/src/ros2/log.rs"]
pub mod log;
