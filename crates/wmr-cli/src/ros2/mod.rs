//! The MCAP `ros2` profile (`wmr-cli run --profile ros2`): a run's samples as ROS 2
//! messages in CDR, with the `.msg` definitions ROS 2 tools read them by.
//!
//! [`cdr`] writes and reads CDR, [`msgs`] holds the message definitions, [`topics`] names
//! the topics, their types and QoS, [`geometry`] places the robot's parts, [`urdf`] writes
//! the robot's description, and [`encoder`] turns a run's samples into messages.

pub mod encoder;
pub mod geometry;
pub mod msgs;
pub mod topics;
pub mod urdf;

// CDR and the log reader live in wmr-identify (the identification reads ROS 2 logs with
// them, from the CLI and from Python); here under their old paths.
pub use wmr_identify::ros2::{cdr, log};

pub use encoder::Ros2RunEncoder;
pub use topics::{CDR, ROS2MSG, Ros2Schema, Topic, offered_qos_profiles, topic_name};
