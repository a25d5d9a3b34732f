//! Where the robot's parts are, in `base_link` (C on the ground, x forward, y left, z up,
//! m): shared by the transforms of the ROS 2 topics and the URDF, so both draw one robot.

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
