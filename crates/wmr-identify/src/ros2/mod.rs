//! The ROS 2 side of a log: CDR, the encoding of ROS 2 messages ([`cdr`], written by
//! `wmr-cli run --profile ros2` and read here), and the reader of a ROS 2 MCAP's
//! `/cmd_vel`, `/joint_states` and `/odom` ([`log`]: `wmr-cli log2csv`, and the
//! identification from a ROS 2 log).

pub mod cdr;
pub mod log;
