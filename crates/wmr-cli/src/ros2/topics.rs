//! The ROS 2 topics of a run (`wmr-cli run --profile ros2`): names, types, QoS.
//!
//! One run: `/tf`, `/odom`, ...; several runs: each under its own namespace
//! (`/run3/odom`), with frames `run3/odom`, `run3/base_link`, ... under one shared `map`.

use wmr_scenario::Columns;

use super::msgs::{flattened, schema_name};

/// One ROS 2 topic of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Topic {
    /// `tf2_msgs/TFMessage`, every sample: `map -> odom`, `odom -> base_link`, and
    /// `base_link -> wheel_left_link / wheel_right_link` (the wheels' joint angles).
    Tf,
    /// `tf2_msgs/TFMessage`, once (transient local): `base_link -> caster_link`.
    TfStatic,
    /// `nav_msgs/Odometry`, every sample: the pose the controller uses in `odom`.
    Odom,
    /// `sensor_msgs/JointState`, every sample: `wheel_left_joint`, `wheel_right_joint`.
    JointStates,
    /// `nav_msgs/Path`, once: the reference (tracking runs).
    Plan,
    /// `geometry_msgs/PoseStamped`, once: the goal.
    GoalPose,
    /// `wmr_msgs/Sample`, every sample: every CSV column.
    Sample,
    /// `std_msgs/String`, once (transient local): the robot's URDF.
    RobotDescription,
    /// `geometry_msgs/TwistStamped` in `base_link`, every sample: the twist the law
    /// demanded at its last tick (runs whose law demands a twist).
    CmdVel,
}

impl Topic {
    /// Every topic, in the order channels are created.
    pub const ALL: [Topic; 9] = [
        Topic::Tf,
        Topic::TfStatic,
        Topic::Odom,
        Topic::JointStates,
        Topic::Plan,
        Topic::GoalPose,
        Topic::Sample,
        Topic::RobotDescription,
        Topic::CmdVel,
    ];

    /// The topic's name without its namespace.
    pub fn name(self) -> &'static str {
        match self {
            Topic::Tf => "tf",
            Topic::TfStatic => "tf_static",
            Topic::Odom => "odom",
            Topic::JointStates => "joint_states",
            Topic::Plan => "plan",
            Topic::GoalPose => "goal_pose",
            Topic::Sample => "wmr/sample",
            Topic::RobotDescription => "robot_description",
            Topic::CmdVel => "cmd_vel",
        }
    }

    /// The message type, `pkg/Type`.
    pub fn msg_type(self) -> &'static str {
        match self {
            Topic::Tf | Topic::TfStatic => "tf2_msgs/TFMessage",
            Topic::Odom => "nav_msgs/Odometry",
            Topic::JointStates => "sensor_msgs/JointState",
            Topic::Plan => "nav_msgs/Path",
            Topic::GoalPose => "geometry_msgs/PoseStamped",
            Topic::Sample => "wmr_msgs/Sample",
            Topic::RobotDescription => "std_msgs/String",
            Topic::CmdVel => "geometry_msgs/TwistStamped",
        }
    }

    /// Whether its publisher is transient local (a late subscriber gets the last message).
    pub fn transient_local(self) -> bool {
        matches!(self, Topic::TfStatic | Topic::RobotDescription)
    }

    /// Whether runs with `columns` have this topic: [`Topic::Plan`] with a `[reference]`,
    /// [`Topic::CmdVel`] with a law that demands a twist.
    pub fn is_present(self, columns: &Columns) -> bool {
        match self {
            Topic::Plan => columns.reference.is_some(),
            Topic::CmdVel => columns.command,
            _ => true,
        }
    }

    /// The topics of runs with `columns`, in [`Topic::ALL`] order.
    pub fn present(columns: &Columns) -> impl Iterator<Item = Topic> + '_ {
        Topic::ALL.into_iter().filter(move |t| t.is_present(columns))
    }
}

/// The namespace of run `run` of `runs`: none for a file of one run, `/run3` otherwise.
pub fn namespace(run: usize, runs: usize) -> String {
    if runs > 1 { format!("/run{run}") } else { String::new() }
}

/// The topic `topic` of run `run` of `runs`: `/odom`, or `/run3/odom`.
pub fn topic_name(run: usize, runs: usize, topic: Topic) -> String {
    format!("{}/{}", namespace(run, runs), topic.name())
}

/// A run's frame `name` (`odom`, `base_link`, ...): `name`, or `run3/name` with several runs.
pub fn frame(run: usize, runs: usize, name: &str) -> String {
    if runs > 1 { format!("run{run}/{name}") } else { name.to_owned() }
}

/// The frame every run's `odom` hangs from.
pub const MAP_FRAME: &str = "map";

/// A schema of the file: name (`pkg/msg/Type`), encoding, the flattened definition.
pub struct Ros2Schema {
    /// `pkg/msg/Type`.
    pub name: String,
    /// The flattened `.msg` text ([`flattened`]).
    pub data: String,
}

impl Ros2Schema {
    /// The schema of `msg_type` (`pkg/Type`).
    pub fn of(msg_type: &str) -> Self {
        Self { name: schema_name(msg_type), data: flattened(msg_type) }
    }
}

/// Message encoding of the ROS 2 channels.
pub const CDR: &str = "cdr";
/// Schema encoding of the ROS 2 schemas.
pub const ROS2MSG: &str = "ros2msg";

/// The `offered_qos_profiles` of a channel (YAML, as rosbag2 writes it for Humble and
/// later, numeric policies): reliable, keep last (depth 1 for transient local, else 10),
/// volatile or transient local, no deadline, lifespan or lease limits.
pub fn offered_qos_profiles(transient_local: bool) -> String {
    let (depth, durability) = if transient_local { (1, 1) } else { (10, 2) };
    let infinite = "\n    sec: 9223372036\n    nsec: 854775807";
    format!(
        "- history: 1\n  depth: {depth}\n  reliability: 1\n  durability: {durability}\n  deadline:{infinite}\n  \
         lifespan:{infinite}\n  liveliness: 1\n  liveliness_lease_duration:{infinite}\n  \
         avoid_ros_namespace_conventions: false"
    )
}
