//! ROS 2 data for wmr, shared by the CLI (`run --profile ros2`, `log2csv`, `identify`) and
//! Python (`wmr_py.read_log`): [`cdr`] writes and reads CDR (XCDR1, little-endian), and
//! [`log`] reads a ROS 2 MCAP's `/cmd_vel`, `/joint_states` and `/odom` into wmr's tables.

pub mod cdr;
pub mod log;
