//! The robot as a URDF (`wmr-cli urdf`, `/robot_description` of a ROS 2 MCAP, and
//! `wmr_py.Robot.urdf()`): the
//! platform on `base_link`, the two wheels on continuous joints `wheel_left_joint` and
//! `wheel_right_joint` at `(0, +-half_track, wheel_radius)` turning about y, and a caster
//! ball on a fixed joint ([`Geometry`]).
//!
//! Inertial values (SI units) come from the robot's parameters: the whole mass `m` (the
//! model's total, wheels included) sits on `base_link` at the centre of mass G,
//! `com_offset` ahead of C, with yaw inertia `I_p = platform_inertia` about G; the
//! planar model has no roll or pitch inertia, so `base_link` gets `I_p / 2` about x and y
//! (a flat plate's). Each wheel link carries `I_m = wheel_inertia` about its axis (y) and
//! `I_m / 2` about x and z (a disc's), with mass 0 (its mass is in `m`). The caster is
//! massless.

//!
//! [`Geometry`] places the parts in `base_link` (C on the ground, x forward, y left, z up,
//! m): the transforms of the ROS 2 topics use it too, so both draw one robot.

use std::fmt::Write as _;

use wmr_core::RobotParams;

/// The wheels' joints, left then right (TurtleBot3's names).
pub const JOINT_NAMES: [&str; 2] = ["wheel_left_joint", "wheel_right_joint"];

/// The robot's parts in `base_link`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geometry {
    /// The wheels' axle: at `(0, +-half_track, wheel_z)`, m (`wheel_z` = the wheel radius).
    pub half_track: f64,
    /// Height of the wheels' axis, m: the wheel radius.
    pub wheel_z: f64,
    /// x of the caster's centre, m: on the centre of mass's side of the axle, twice as far
    /// (at least two wheel radii), so the centre of mass lies between axle and caster.
    pub caster_x: f64,
    /// z of the caster's centre, m: its radius (half the wheel radius), so it touches the ground.
    pub caster_z: f64,
    /// Radius of the caster ball, m.
    pub caster_radius: f64,
}

impl Geometry {
    /// The geometry of `robot`.
    pub fn of(robot: &RobotParams<f64>) -> Self {
        let r = robot.wheel_radius;
        let d = robot.com_offset;
        let caster_x = if d >= 0.0 { (2.0 * d).max(2.0 * r) } else { (2.0 * d).min(-2.0 * r) };
        Self { half_track: robot.half_track, wheel_z: r, caster_x, caster_z: 0.5 * r, caster_radius: 0.5 * r }
    }
}

/// Escapes `&`, `<`, `>` and `"` for an XML attribute.
fn xml_attr(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// The URDF of `robot`, named `name`, its links and joints prefixed with `prefix`
/// (`""`, or `run3/` for run 3 of a file of several runs, as its tf frames are).
pub fn urdf(robot: &RobotParams<f64>, name: &str, prefix: &str) -> String {
    let g = Geometry::of(robot);
    let r = robot.wheel_radius;
    let d = robot.com_offset;
    let i_p = robot.platform_inertia;
    let i_m = robot.wheel_inertia;
    // The body as Foxglove's 3D panel draws it: a box of the track's width over C and G.
    let length = (2.0 * d.abs()).max(2.0 * r) + 2.0 * r;
    let wheel_width = 0.4 * r;
    let p = xml_attr(prefix);
    let mut out = String::new();
    let _ = writeln!(out, r#"<?xml version="1.0"?>"#);
    let _ = writeln!(out, "<!-- Written by wmr {} from the robot's parameters. -->", env!("CARGO_PKG_VERSION"));
    let _ = writeln!(out, r#"<robot name="{}">"#, xml_attr(name));
    let _ = writeln!(out, r#"  <link name="{p}base_link">"#);
    let _ = writeln!(out, "    <inertial>");
    let _ = writeln!(out, r#"      <origin xyz="{d} 0 {r}" rpy="0 0 0"/>"#);
    let _ = writeln!(out, r#"      <mass value="{}"/>"#, robot.mass);
    let _ = writeln!(
        out,
        r#"      <inertia ixx="{}" ixy="0" ixz="0" iyy="{}" iyz="0" izz="{i_p}"/>"#,
        i_p / 2.0,
        i_p / 2.0
    );
    let _ = writeln!(out, "    </inertial>");
    let _ = writeln!(out, "    <visual>");
    let _ = writeln!(out, r#"      <origin xyz="{} 0 {r}" rpy="0 0 0"/>"#, 0.5 * d);
    let _ = writeln!(
        out,
        r#"      <geometry><box size="{length} {} {}"/></geometry>"#,
        2.0 * robot.half_track - wheel_width,
        r
    );
    let _ = writeln!(out, "    </visual>");
    let _ = writeln!(out, "  </link>");
    for (joint, side) in JOINT_NAMES.iter().zip([1.0, -1.0]) {
        let link = joint.replace("_joint", "_link");
        let _ = writeln!(out, r#"  <link name="{p}{link}">"#);
        let _ = writeln!(out, "    <inertial>");
        let _ = writeln!(out, r#"      <origin xyz="0 0 0" rpy="0 0 0"/>"#);
        let _ = writeln!(out, r#"      <mass value="0"/>"#);
        let _ = writeln!(
            out,
            r#"      <inertia ixx="{}" ixy="0" ixz="0" iyy="{i_m}" iyz="0" izz="{}"/>"#,
            i_m / 2.0,
            i_m / 2.0
        );
        let _ = writeln!(out, "    </inertial>");
        let _ = writeln!(out, "    <visual>");
        let _ = writeln!(out, r#"      <origin xyz="0 0 0" rpy="1.5707963267948966 0 0"/>"#);
        let _ = writeln!(out, r#"      <geometry><cylinder radius="{r}" length="{wheel_width}"/></geometry>"#);
        let _ = writeln!(out, "    </visual>");
        let _ = writeln!(out, "  </link>");
        let _ = writeln!(out, r#"  <joint name="{p}{joint}" type="continuous">"#);
        let _ = writeln!(out, r#"    <parent link="{p}base_link"/>"#);
        let _ = writeln!(out, r#"    <child link="{p}{link}"/>"#);
        let _ = writeln!(out, r#"    <origin xyz="0 {} {}" rpy="0 0 0"/>"#, side * g.half_track, g.wheel_z);
        let _ = writeln!(out, r#"    <axis xyz="0 1 0"/>"#);
        let _ = writeln!(out, "  </joint>");
    }
    let _ = writeln!(out, r#"  <link name="{p}caster_link">"#);
    let _ = writeln!(out, "    <visual>");
    let _ = writeln!(out, r#"      <geometry><sphere radius="{}"/></geometry>"#, g.caster_radius);
    let _ = writeln!(out, "    </visual>");
    let _ = writeln!(out, "  </link>");
    let _ = writeln!(out, r#"  <joint name="{p}caster_joint" type="fixed">"#);
    let _ = writeln!(out, r#"    <parent link="{p}base_link"/>"#);
    let _ = writeln!(out, r#"    <child link="{p}caster_link"/>"#);
    let _ = writeln!(out, r#"    <origin xyz="{} 0 {}" rpy="0 0 0"/>"#, g.caster_x, g.caster_z);
    let _ = writeln!(out, "  </joint>");
    let _ = writeln!(out, "</robot>");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_robot_has_its_mass_and_inertias() {
        let text = urdf(&RobotParams::paper(), "fig<7>", "");
        assert!(text.contains(r#"<robot name="fig&lt;7&gt;">"#));
        assert!(text.contains(r#"<mass value="5"/>"#));
        assert!(text.contains(r#"izz="0.005""#));
        assert!(text.contains(r#"iyy="0.002""#));
        assert!(text.contains(r#"<origin xyz="0 0.2 0.1" rpy="0 0 0"/>"#));
        assert!(text.contains(r#"<joint name="wheel_right_joint" type="continuous">"#));
        let prefixed = urdf(&RobotParams::paper(), "r", "run3/");
        assert!(prefixed.contains(r#"<parent link="run3/base_link"/>"#));
    }
}
