//! The ROS 2 message definitions wmr writes, as the MCAP `ros2` profile stores them
//! (`schema_encoding = "ros2msg"`): the type's `.msg` text, then every type it uses, each
//! after a line of 80 `=` and a `MSG: pkg/Type` line. The texts are those of ROS 2's
//! `common_interfaces` and `geometry2` (Humble to Rolling: unchanged), without their
//! comments; `wmr_msgs/Sample` is `crates/wmr-cli/msg/wmr_msgs/msg/Sample.msg`.

/// `wmr_msgs/msg/Sample`: the file in the repository, as written.
pub const WMR_SAMPLE_MSG: &str = include_str!("../../msg/wmr_msgs/msg/Sample.msg");

/// A message type: its name (`pkg/Type`), its `.msg` text and the types it names.
struct MsgType {
    name: &'static str,
    text: &'static str,
    uses: &'static [&'static str],
}

const TYPES: &[MsgType] = &[
    MsgType { name: "builtin_interfaces/Time", text: "int32 sec\nuint32 nanosec\n", uses: &[] },
    MsgType {
        name: "std_msgs/Header",
        text: "builtin_interfaces/Time stamp\nstring frame_id\n",
        uses: &["builtin_interfaces/Time"],
    },
    MsgType { name: "std_msgs/String", text: "string data\n", uses: &[] },
    MsgType { name: "geometry_msgs/Vector3", text: "float64 x\nfloat64 y\nfloat64 z\n", uses: &[] },
    MsgType { name: "geometry_msgs/Point", text: "float64 x\nfloat64 y\nfloat64 z\n", uses: &[] },
    MsgType {
        name: "geometry_msgs/Quaternion",
        text: "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n",
        uses: &[],
    },
    MsgType {
        name: "geometry_msgs/Transform",
        text: "Vector3 translation\nQuaternion rotation\n",
        uses: &["geometry_msgs/Vector3", "geometry_msgs/Quaternion"],
    },
    MsgType {
        name: "geometry_msgs/TransformStamped",
        text: "std_msgs/Header header\nstring child_frame_id\nTransform transform\n",
        uses: &["std_msgs/Header", "geometry_msgs/Transform"],
    },
    MsgType {
        name: "geometry_msgs/Pose",
        text: "Point position\nQuaternion orientation\n",
        uses: &["geometry_msgs/Point", "geometry_msgs/Quaternion"],
    },
    MsgType {
        name: "geometry_msgs/PoseStamped",
        text: "std_msgs/Header header\nPose pose\n",
        uses: &["std_msgs/Header", "geometry_msgs/Pose"],
    },
    MsgType {
        name: "geometry_msgs/PoseWithCovariance",
        text: "Pose pose\nfloat64[36] covariance\n",
        uses: &["geometry_msgs/Pose"],
    },
    MsgType {
        name: "geometry_msgs/Twist",
        text: "Vector3  linear\nVector3  angular\n",
        uses: &["geometry_msgs/Vector3"],
    },
    MsgType {
        name: "geometry_msgs/TwistWithCovariance",
        text: "Twist twist\nfloat64[36] covariance\n",
        uses: &["geometry_msgs/Twist"],
    },
    MsgType {
        name: "geometry_msgs/TwistStamped",
        text: "std_msgs/Header header\nTwist twist\n",
        uses: &["std_msgs/Header", "geometry_msgs/Twist"],
    },
    MsgType {
        name: "tf2_msgs/TFMessage",
        text: "geometry_msgs/TransformStamped[] transforms\n",
        uses: &["geometry_msgs/TransformStamped"],
    },
    MsgType {
        name: "nav_msgs/Odometry",
        text: "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n\
               geometry_msgs/TwistWithCovariance twist\n",
        uses: &["std_msgs/Header", "geometry_msgs/PoseWithCovariance", "geometry_msgs/TwistWithCovariance"],
    },
    MsgType {
        name: "nav_msgs/Path",
        text: "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n",
        uses: &["std_msgs/Header", "geometry_msgs/PoseStamped"],
    },
    MsgType {
        name: "sensor_msgs/JointState",
        text: "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\nfloat64[] effort\n",
        uses: &["std_msgs/Header"],
    },
    MsgType { name: "wmr_msgs/Sample", text: WMR_SAMPLE_MSG, uses: &["std_msgs/Header"] },
];

fn find(name: &str) -> &'static MsgType {
    TYPES.iter().find(|t| t.name == name).unwrap_or_else(|| panic!("no ROS 2 message definition for {name}"))
}

/// The schema name of `pkg/Type` as ROS 2 bags carry it: `pkg/msg/Type`.
pub fn schema_name(name: &str) -> String {
    match name.split_once('/') {
        Some((pkg, ty)) => format!("{pkg}/msg/{ty}"),
        None => name.to_owned(),
    }
}

/// The separator line before each dependency.
const SEPARATOR: &str = "================================================================================";

/// The flattened definition of `name` (`pkg/Type`, one of wmr's): its text, then each type
/// it uses, directly or not, once, in the order first met (depth first).
pub fn flattened(name: &str) -> String {
    fn visit(name: &str, order: &mut Vec<&'static str>) {
        for &dep in find(name).uses {
            if !order.contains(&dep) {
                order.push(dep);
                visit(dep, order);
            }
        }
    }
    let mut order = Vec::new();
    visit(name, &mut order);
    let mut out = find(name).text.trim_end().to_owned();
    for dep in order {
        out.push('\n');
        out.push_str(SEPARATOR);
        out.push_str("\nMSG: ");
        out.push_str(dep);
        out.push('\n');
        out.push_str(find(dep).text.trim_end());
    }
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nested_type_lists_each_dependency_once_after_a_separator() {
        let text = flattened("nav_msgs/Odometry");
        let deps: Vec<&str> = text.lines().filter_map(|l| l.strip_prefix("MSG: ")).collect();
        assert_eq!(
            deps,
            [
                "std_msgs/Header",
                "builtin_interfaces/Time",
                "geometry_msgs/PoseWithCovariance",
                "geometry_msgs/Pose",
                "geometry_msgs/Point",
                "geometry_msgs/Quaternion",
                "geometry_msgs/TwistWithCovariance",
                "geometry_msgs/Twist",
                "geometry_msgs/Vector3",
            ]
        );
        assert_eq!(text.lines().filter(|l| *l == SEPARATOR).count(), deps.len());
        assert!(text.starts_with("std_msgs/Header header\nstring child_frame_id\n"));
    }

    /// The Sample message has one float64 per CSV column of every group, in the CSV's order.
    #[test]
    fn the_sample_message_has_every_csv_column_in_order() {
        let fields: Vec<&str> = WMR_SAMPLE_MSG
            .lines()
            .map(|l| l.split('#').next().unwrap_or("").trim())
            .filter_map(|l| l.strip_prefix("float64 "))
            .collect();
        let columns: Vec<&str> =
            wmr_scenario::ColumnGroup::ALL.iter().flat_map(|g| g.names().iter().copied()).collect();
        assert_eq!(fields, columns);
        assert_eq!(schema_name("wmr_msgs/Sample"), "wmr_msgs/msg/Sample");
    }
}
