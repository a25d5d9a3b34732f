//! Reading a ROS 2 MCAP back (`wmr-cli log2csv`, and the identification of a robot from its
//! logs): `/cmd_vel` (`geometry_msgs/msg/Twist` or `TwistStamped`), `/joint_states`
//! (`sensor_msgs/msg/JointState`) and `/odom` (`nav_msgs/msg/Odometry`) of any ROS 2 MCAP
//! (wmr's `--profile ros2`, `ros2 bag record -s mcap`, `rosbags`) into time-stamped tables.
//!
//! Times are the messages' `header.stamp` (ns), the log time for an unstamped `Twist`. The
//! wheels are the joints named `wheel_left_joint` / `wheel_right_joint` (TurtleBot3's and
//! wmr's names), else the one joint whose name holds `left` and the one holding `right`.

use std::collections::BTreeSet;

use super::cdr::{CdrError, CdrReader};

/// A `/cmd_vel` message: the commanded body twist.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CmdVel {
    /// Time, ns.
    pub t_ns: u64,
    /// linear.x, m/s.
    pub v: f64,
    /// angular.z, rad/s.
    pub omega: f64,
}

/// A `/joint_states` message: the two wheels (NaN where the message has no such array).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelStates {
    /// Time, ns.
    pub t_ns: u64,
    /// Wheel angles (right, left), rad.
    pub phi: [f64; 2],
    /// Wheel speeds (right, left), rad/s.
    pub omega: [f64; 2],
    /// Wheel torques (right, left), N m.
    pub tau: [f64; 2],
}

/// An `/odom` message: the pose in its frame and the body twist.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Odom {
    /// Time, ns.
    pub t_ns: u64,
    /// Position, m.
    pub x: f64,
    /// Position, m.
    pub y: f64,
    /// Yaw of the orientation, rad, in (-pi, pi].
    pub theta: f64,
    /// twist.linear.x, m/s (body frame).
    pub v: f64,
    /// twist.angular.z, rad/s.
    pub omega: f64,
}

/// The tables of one robot's log, each sorted by time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Ros2Log {
    /// `cmd_vel`.
    pub cmd_vel: Vec<CmdVel>,
    /// `joint_states`.
    pub joint_states: Vec<WheelStates>,
    /// `odom`.
    pub odom: Vec<Odom>,
}

/// The topics read, by their last name part.
const TOPICS: [&str; 3] = ["cmd_vel", "joint_states", "odom"];

/// Whether `topic` is `name` in `namespace` (`/odom`, `/run3/odom`), or in any namespace
/// when none is given.
fn matches(topic: &str, name: &str, namespace: Option<&str>) -> bool {
    let Some(ns) = topic.strip_suffix(name).and_then(|t| t.strip_suffix('/')) else { return false };
    match namespace {
        Some(want) => ns == want.trim_end_matches('/'),
        None => true,
    }
}

fn err(topic: &str, e: CdrError) -> String {
    format!("{topic}: cannot read a message: {e}")
}

fn header(r: &mut CdrReader) -> Result<u64, CdrError> {
    let t = r.time()?;
    r.string()?;
    Ok(t)
}

fn yaw(x: f64, y: f64, z: f64, w: f64) -> f64 {
    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
}

/// The wheels' indices (right, left) among joint `names`.
fn wheel_indices(names: &[String]) -> Option<[usize; 2]> {
    let exact = |n: &str| names.iter().position(|x| x == n);
    if let (Some(l), Some(r)) = (exact("wheel_left_joint"), exact("wheel_right_joint")) {
        return Some([r, l]);
    }
    let only = |side: &str| {
        let mut it = names.iter().enumerate().filter(|(_, n)| n.to_ascii_lowercase().contains(side));
        match (it.next(), it.next()) {
            (Some((i, _)), None) => Some(i),
            _ => None,
        }
    };
    Some([only("right")?, only("left")?])
}

/// Reads the tables of `mcap` (a whole MCAP file's bytes); `namespace` (`/run3`) picks
/// one robot of a file of several. Errors name the topic and what is wrong: a topic
/// present in several namespaces without `namespace`, a type other than those above, a
/// message that does not parse, a JointState without both wheels.
pub fn read_log(mcap: &[u8], namespace: Option<&str>) -> Result<Ros2Log, String> {
    let mut log = Ros2Log::default();
    let stream = mcap::MessageStream::new(mcap).map_err(|e| format!("not an MCAP file: {e}"))?;
    let mut seen: [BTreeSet<String>; 3] = Default::default();
    for message in stream {
        let message = message.map_err(|e| format!("cannot read the MCAP file: {e}"))?;
        let channel = &message.channel;
        let topic = channel.topic.as_str();
        let Some(which) = TOPICS.iter().position(|n| matches(topic, n, namespace)) else { continue };
        seen[which].insert(topic.to_owned());
        if seen[which].len() > 1 {
            let list: Vec<&str> = seen[which].iter().map(String::as_str).collect();
            return Err(format!(
                "{} topics named {}: pick one robot with --namespace (e.g. --namespace {})",
                list.len(),
                TOPICS[which],
                list[0].strip_suffix(TOPICS[which]).unwrap_or("/").trim_end_matches('/')
            ));
        }
        let schema = channel.schema.as_ref().map(|s| s.name.as_str()).unwrap_or("");
        if channel.message_encoding != "cdr" {
            return Err(format!("{topic}: message encoding {:?}, not cdr (a ROS 2 MCAP)", channel.message_encoding));
        }
        let mut r = CdrReader::new(&message.data).map_err(|e| err(topic, e))?;
        let parsed: Result<(), CdrError> = (|| {
            match (which, schema) {
                (0, "geometry_msgs/msg/TwistStamped" | "geometry_msgs/msg/Twist") => {
                    let t_ns = if schema.ends_with("Stamped") { header(&mut r)? } else { message.log_time };
                    let v = r.f64()?;
                    r.skip_f64(4)?;
                    let omega = r.f64()?;
                    log.cmd_vel.push(CmdVel { t_ns, v, omega });
                }
                (1, "sensor_msgs/msg/JointState") => {
                    let t_ns = header(&mut r)?;
                    let n = r.len()?;
                    let names = (0..n).map(|_| r.string()).collect::<Result<Vec<_>, _>>()?;
                    let [ir, il] = wheel_indices(&names)
                        .ok_or_else(|| CdrError(format!("no left and right wheel among the joints {names:?}")))?;
                    let mut pick = || -> Result<[f64; 2], CdrError> {
                        let v = r.f64_seq()?;
                        Ok(if v.len() == n { [v[ir], v[il]] } else { [f64::NAN; 2] })
                    };
                    let phi = pick()?;
                    let omega = pick()?;
                    let tau = pick()?;
                    log.joint_states.push(WheelStates { t_ns, phi, omega, tau });
                }
                (2, "nav_msgs/msg/Odometry") => {
                    let t_ns = header(&mut r)?;
                    r.string()?;
                    let (x, y) = (r.f64()?, r.f64()?);
                    r.f64()?;
                    let (qx, qy, qz, qw) = (r.f64()?, r.f64()?, r.f64()?, r.f64()?);
                    r.skip_f64(36)?;
                    let v = r.f64()?;
                    r.skip_f64(4)?;
                    let omega = r.f64()?;
                    log.odom.push(Odom { t_ns, x, y, theta: yaw(qx, qy, qz, qw), v, omega });
                }
                _ => {
                    return Err(CdrError(format!(
                        "type {schema:?} is not one this reader knows for {} (Twist, TwistStamped, JointState, Odometry)",
                        TOPICS[which]
                    )));
                }
            }
            Ok(())
        })();
        parsed.map_err(|e| err(topic, e))?;
    }
    log.cmd_vel.sort_by_key(|m| m.t_ns);
    log.joint_states.sort_by_key(|m| m.t_ns);
    log.odom.sort_by_key(|m| m.t_ns);
    Ok(log)
}

/// The CSV columns of [`Ros2Log::to_csv`], after `t`.
pub const LOG_COLUMNS: [&str; 13] =
    ["x", "y", "theta", "v", "omega", "phi_r", "phi_l", "omega_r", "omega_l", "tau_r", "tau_l", "v_cmd", "omega_cmd"];

impl Ros2Log {
    /// The log as one table in wmr's CSV columns: a row at every time any of the three
    /// topics has a message (t in s from the epoch: stamp ns / 1e9), each column the
    /// latest value at or before it (empty before its topic's first message). `x, y,
    /// theta, v, omega` from `/odom`, the wheels from `/joint_states`, `v_cmd, omega_cmd`
    /// from `/cmd_vel`.
    pub fn to_csv(&self) -> String {
        let times: BTreeSet<u64> = self
            .odom
            .iter()
            .map(|m| m.t_ns)
            .chain(self.joint_states.iter().map(|m| m.t_ns))
            .chain(self.cmd_vel.iter().map(|m| m.t_ns))
            .collect();
        let mut out = String::from("t");
        for c in LOG_COLUMNS {
            out.push(',');
            out.push_str(c);
        }
        out.push('\n');
        let (mut io, mut ij, mut ic) = (0usize, 0usize, 0usize);
        let mut field = String::new();
        for t in times {
            while io < self.odom.len() && self.odom[io].t_ns <= t {
                io += 1;
            }
            while ij < self.joint_states.len() && self.joint_states[ij].t_ns <= t {
                ij += 1;
            }
            while ic < self.cmd_vel.len() && self.cmd_vel[ic].t_ns <= t {
                ic += 1;
            }
            let mut values: [Option<f64>; 13] = [None; 13];
            if let Some(o) = io.checked_sub(1).map(|i| &self.odom[i]) {
                values[..5].copy_from_slice(&[Some(o.x), Some(o.y), Some(o.theta), Some(o.v), Some(o.omega)]);
            }
            if let Some(j) = ij.checked_sub(1).map(|i| &self.joint_states[i]) {
                let w = [j.phi[0], j.phi[1], j.omega[0], j.omega[1], j.tau[0], j.tau[1]];
                for (slot, v) in values[5..11].iter_mut().zip(w) {
                    *slot = Some(v);
                }
            }
            if let Some(c) = ic.checked_sub(1).map(|i| &self.cmd_vel[i]) {
                values[11] = Some(c.v);
                values[12] = Some(c.omega);
            }
            crate::table::format_f64(t as f64 / 1e9, &mut field);
            out.push_str(&field);
            for v in values {
                out.push(',');
                if let Some(v) = v.filter(|v| !v.is_nan()) {
                    crate::table::format_f64(v, &mut field);
                    out.push_str(&field);
                }
            }
            out.push('\n');
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn topics_match_by_namespace() {
        assert!(matches("/odom", "odom", None));
        assert!(matches("/run3/odom", "odom", None));
        assert!(matches("/run3/odom", "odom", Some("/run3")));
        assert!(!matches("/run3/odom", "odom", Some("/run1")));
        assert!(!matches("/wheel_odom", "odom", None));
        assert!(matches("/odom", "odom", Some("/")));
    }

    #[test]
    fn wheels_are_found_by_name() {
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(wheel_indices(&names(&["wheel_left_joint", "wheel_right_joint"])), Some([1, 0]));
        assert_eq!(wheel_indices(&names(&["right_wheel", "arm", "left_wheel"])), Some([0, 2]));
        assert_eq!(wheel_indices(&names(&["left_a", "left_b", "right"])), None);
    }

    #[test]
    fn yaw_of_a_rotation_about_z() {
        for theta in [0.0, 0.5, -2.0, 3.0] {
            let (s, c) = (0.5f64 * theta).sin_cos();
            assert!((yaw(0.0, 0.0, s, c) - theta).abs() < 1e-15);
        }
    }
}
