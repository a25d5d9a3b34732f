//! The MCAP `ros2` profile (`wmr-cli run --profile ros2`): a run's samples as ROS 2
//! messages in CDR, with the `.msg` definitions ROS 2 tools read them by.
//!
//! [`cdr`] writes and reads CDR (from `wmr-ros2`), [`msgs`] holds the message definitions, [`topics`] names
//! the topics, their types and QoS (the robot's parts and URDF: `wmr_scenario::urdf`),
//! [`encoder`] turns a run's samples into messages, [`log`] (`wmr-ros2`) reads a ROS 2
//! MCAP back, and [`bag`] writes the `metadata.yaml` of a rosbag2 bag around one.

pub mod bag;
pub mod encoder;
pub mod msgs;
pub mod topics;

/// CDR and the log reader live in `wmr-ros2` (Python reads logs with them too).
pub use wmr_ros2::{cdr, log};

pub use encoder::Ros2RunEncoder;
pub use topics::{CDR, ROS2MSG, Ros2Schema, Topic, offered_qos_profiles, topic_name};
