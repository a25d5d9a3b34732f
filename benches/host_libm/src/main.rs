//! The firmware's run (firmware/src/main.rs) on the host: Fig. 7 in f32, printed as f32 bit
//! patterns in the firmware's format so `benches/compare` can compare them exactly.

use wmr_core::{ClosedLoop, DriveParams, PaperController, PaperParams, Pose2, Robot};

fn main() {
    let robot = Robot::<f32>::paper();
    let drive = DriveParams::default().validate(&robot).expect("default drive is valid");
    let goal = Pose2::new(1.0, 1.0, 120f64.to_radians() as f32);
    let ctrl = PaperController::new(PaperParams::paper(), &robot, &drive, goal).expect("paper gains are valid");
    let mut sim = ClosedLoop::new(robot, drive, ctrl, Pose2::default(), 1e-3).expect("dt divides control_dt");
    for _ in 0..60_000 {
        if sim.step().is_err() {
            break;
        }
    }
    let p = sim.state().pose();
    println!(
        "impl=host-libm-f32 x_bits={:08x} y_bits={:08x} theta_bits={:08x} steps={}",
        p.x.to_bits(),
        p.y.to_bits(),
        p.theta.to_bits(),
        sim.steps()
    );
}
