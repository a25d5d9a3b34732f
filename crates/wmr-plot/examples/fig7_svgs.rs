//! Writes the Fig. 7-9 SVGs of the core's Fig. 7 run to the current folder.

use wmr_core::{ClosedLoop, ControllerParams, DriveParams, FixedGoal, Plant, Pose2, Robot};
use wmr_plot::{Trace, errors_svg, paths_svg, wheel_speeds_svg};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot)?;
    let goal = Pose2::new(1.0, 1.0, 120f64.to_radians());
    let ctrl = ControllerParams::paper().build(robot.params(), &drive)?;
    let plant = Plant::new(robot, drive, Pose2::default())?;
    let mut sim = ClosedLoop::new(plant, ctrl, FixedGoal::new(goal)?, 1e-3)?;
    let mut samples = Vec::new();
    sim.run(60_000, 10, |s| samples.push(*s));
    let trace = Trace { label: "(0,0,0) -> (1,1,120 deg)", goal, samples: &samples, reference: &[] };
    std::fs::write("fig7.svg", paths_svg("Fig. 7: path of C", &[trace])?)?;
    std::fs::write("fig8.svg", wheel_speeds_svg("Fig. 8: wheel speeds", &trace)?)?;
    std::fs::write("fig9.svg", errors_svg("Fig. 9: errors", &trace)?)?;
    Ok(())
}
