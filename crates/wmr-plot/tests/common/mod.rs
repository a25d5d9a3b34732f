//! What the figure tests draw: runs of the paper's robot and law, built with the core.

use wmr_core::{ClosedLoop, ControllerParams, DriveParams, FixedGoal, Plant, Pose2, Robot, Sample};

/// The paper's law from `start` to `goal` for `secs` s (1 ms steps), a sample every 50 ms.
pub fn run(start: Pose2<f64>, goal: Pose2<f64>, secs: u64) -> Vec<Sample<f64>> {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).unwrap();
    let ctrl = ControllerParams::paper().build(robot.params(), &drive).unwrap();
    let plant = Plant::new(robot, drive, start).unwrap();
    let mut sim = ClosedLoop::new(plant, ctrl, FixedGoal::new(goal).unwrap(), 1e-3).unwrap();
    let mut out = Vec::new();
    sim.run(secs * 1000, 50, |s| out.push(*s));
    out
}

/// The numbers of every point of a polyline or polygon (its `points` attribute).
pub fn points(n: &roxmltree::Node<'_, '_>) -> Vec<(f64, f64)> {
    n.attribute("points")
        .unwrap()
        .split_whitespace()
        .map(|p| {
            let (x, y) = p.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}
