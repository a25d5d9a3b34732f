//! wmr on a Cortex-M4F: the paper's law, the wheel servos, the torque drive and the
//! dynamic model, in f32, closed by RK4 for the Fig. 7 run (0, 0, 0) -> (1, 1, 120 deg),
//! 60 s at dt = control_dt = 1 ms, with every default. No allocator, no formatting:
//! the plain build only computes; `--features qemu` prints the final pose through
//! semihosting (as f32 bit patterns, so the host can compare exactly) and exits QEMU.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
// The panic handler (wmr-ffi's, through the firmware library).
use wmr_core::{
    ClosedLoop, Controller, DriveParams, FixedGoal, PaperLaw, PaperParams, Plant, Pose2, Robot, WheelStage,
    WheelStageParams,
};
use wmr_firmware as _;

/// 60 s at 1 ms.
const STEPS: u32 = 60_000;

#[entry]
fn main() -> ! {
    let robot = Robot::<f32>::paper();
    let dt = 1e-3;
    // `let else`, not `expect`: keeps the panic message formatting out of flash.
    let drive_params = DriveParams::default();
    let Ok(drive) = drive_params.validate(&robot) else { halt() };
    let Ok(goal) = FixedGoal::new(Pose2::new(1.0, 1.0, 120f64.to_radians() as f32)) else { halt() };
    // The paper's law and its wheel servos, composed directly: no `AnyLaw`, so the other
    // laws are not linked in.
    let Ok(law) = PaperLaw::new(PaperParams::paper(), robot.params(), dt) else { halt() };
    let wheel_params = WheelStageParams::for_drive(&drive_params, robot.params());
    let Ok(wheels) = WheelStage::new(&wheel_params, robot.params(), &drive, dt) else { halt() };
    let ctrl = Controller::new(law, wheels);
    let Ok(plant) = Plant::new(robot, drive, Pose2::default()) else { halt() };
    let Ok(mut sim) = ClosedLoop::new(plant, ctrl, goal, dt) else { halt() };
    for _ in 0..core::hint::black_box(STEPS) {
        if sim.step().is_err() {
            break;
        }
    }
    report(sim.state().pose(), sim.steps());
    halt()
}

#[cfg(not(feature = "qemu"))]
fn report(pose: Pose2<f32>, steps: u64) {
    // Keep the result observable so the run is not optimised away.
    core::hint::black_box((pose, steps));
}

#[cfg(feature = "qemu")]
fn report(pose: Pose2<f32>, steps: u64) {
    cortex_m_semihosting::hprintln!(
        // The bits (firmware/check compares them) and, for a reader, the decimals.
        "impl=firmware-f32 x_bits={:08x} y_bits={:08x} theta_bits={:08x} steps={} x={:.6}m y={:.6}m theta={:.6}rad",
        pose.x.to_bits(),
        pose.y.to_bits(),
        pose.theta.to_bits(),
        steps,
        pose.x,
        pose.y,
        pose.theta
    );
    cortex_m_semihosting::debug::exit(cortex_m_semihosting::debug::EXIT_SUCCESS);
}

fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}
