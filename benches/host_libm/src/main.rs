//! The firmware's run (firmware/src/main.rs) on the host: Fig. 7 in f32, printed as f32 bit
//! patterns in the firmware's format so `benches/compare` can compare them exactly.

use wmr_core::{
    ClosedLoop, Controller, DriveParams, FixedGoal, PaperLaw, PaperParams, Plant, Pose2, Robot, WheelStage,
    WheelStageParams,
};

fn main() {
    let robot = Robot::<f32>::paper();
    let dt = 1e-3;
    let drive_params = DriveParams::default();
    let drive = drive_params.validate(&robot).expect("default drive is valid");
    let goal = FixedGoal::new(Pose2::new(1.0, 1.0, 120f64.to_radians() as f32)).expect("finite goal");
    // As the firmware: the paper's law and its wheel servos, composed directly.
    let law = PaperLaw::new(PaperParams::paper(), robot.params(), dt).expect("paper gains are valid");
    let wheel_params = WheelStageParams::for_drive(&drive_params, robot.params());
    let wheels = WheelStage::new(&wheel_params, robot.params(), &drive, dt).expect("valid servos");
    let ctrl = Controller::new(law, wheels);
    let plant = Plant::new(robot, drive, Pose2::default()).expect("finite start");
    let mut sim = ClosedLoop::new(plant, ctrl, goal, dt).expect("dt divides control_dt");
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
