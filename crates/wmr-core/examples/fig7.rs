//! The paper's Fig. 7 run, (0, 0, 0) -> (1, 1, 120 deg), with every default; prints the summary.

use wmr_core::{ClosedLoop, ControllerParams, DriveParams, FixedGoal, Plant, Pose2, Robot};

fn main() {
    let robot = Robot::<f64>::paper();
    let drive = DriveParams::default().validate(&robot).expect("default drive is valid");
    let goal = FixedGoal::new(Pose2::new(1.0, 1.0, 120f64.to_radians())).expect("finite goal");
    let ctrl = ControllerParams::paper().build(robot.params(), &drive).expect("paper gains are valid");
    let plant = Plant::new(robot, drive, Pose2::default()).expect("finite start");
    let mut sim = ClosedLoop::new(plant, ctrl, goal, 1e-3).expect("dt divides control_dt");
    let mut peak = 0.0f64;
    let out = sim.run(60_000, 5000, |s| {
        peak = peak.max(s.wheel_speeds.right.abs()).max(s.wheel_speeds.left.abs());
        println!(
            "t={:5.1}s  x={:+.4} y={:+.4} theta={:+7.2}deg  dl={:.4} e_theta={:+7.2}deg  w_r={:+.3} w_l={:+.3} tau_r={:+.3} tau_l={:+.3}",
            s.t, s.state.x, s.state.y, s.state.theta.to_degrees(), s.errors.dl, s.errors.e_theta.to_degrees(),
            s.wheel_speeds.right, s.wheel_speeds.left, s.torque.right, s.torque.left
        );
    });
    println!("{out:#?}");
    println!("{}: final heading error {:.2} deg", out.status().name(), out.final_heading_error.to_degrees());
}
