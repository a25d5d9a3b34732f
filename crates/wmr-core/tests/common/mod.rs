//! Test-only helpers: tolerance checks with explicit rtol/atol, and the paper's Fig. 7 loop.
#![allow(dead_code)]

use wmr_core::{
    ClosedLoop, Controller, ControllerParams, Drive, DriveParams, FixedGoal, PaperLaw, PaperParams, Plant, Pose2, Real,
    Robot, RobotParams, WheelStage, WheelStageParams,
};

/// |a - b| <= atol + rtol |b|.
pub fn isclose(a: f64, b: f64, rtol: f64, atol: f64) -> bool {
    (a - b).abs() <= atol + rtol * b.abs()
}

/// Asserts `isclose` with a readable message.
#[track_caller]
pub fn assert_close(what: &str, a: f64, b: f64, rtol: f64, atol: f64) {
    assert!(isclose(a, b, rtol, atol), "{what}: {a} vs {b} (|diff| {:e}, rtol {rtol:e}, atol {atol:e})", (a - b).abs());
}

/// The paper's closed loop: its law, the default wheel stage, a fixed goal, perfect sensing.
pub type PaperLoop<T> = ClosedLoop<T, PaperLaw<T>>;

/// The paper's law with the default wheel stage (torque-drive servo gains, no wheel speed
/// limit) for the controller's robot model `model`, the drive and the control period (s).
pub fn paper_controller<T: Real>(
    params: PaperParams<T>,
    model: &RobotParams<T>,
    drive: &Drive<T>,
    control_dt: T,
) -> Controller<T, PaperLaw<T>> {
    let law = PaperLaw::new(params, model, control_dt).expect("valid paper law");
    let wheels = WheelStage::new(&WheelStageParams::default(), model, drive, control_dt).expect("valid wheel stage");
    Controller::new(law, wheels)
}

/// The paper's closed loop from `start` to `goal` (m, m, rad) with every default.
pub fn paper_loop<T: Real>(start: Pose2<T>, goal: Pose2<T>) -> PaperLoop<T> {
    paper_loop_with(RobotParams::paper(), PaperParams::paper(), start, goal, T::lit(1e-3))
}

/// The paper's closed loop with given robot and law parameters and plant step (the
/// control period is the default 1 ms).
pub fn paper_loop_with<T: Real>(
    robot: RobotParams<T>,
    params: PaperParams<T>,
    start: Pose2<T>,
    goal: Pose2<T>,
    dt: T,
) -> PaperLoop<T> {
    let robot: Robot<T> = robot.validate().expect("valid robot");
    let drive = DriveParams::default().validate(&robot).expect("valid drive");
    let ctrl = paper_controller(params, robot.params(), &drive, ControllerParams::<T>::default_control_dt());
    let plant = Plant::new(robot, drive, start).expect("valid start");
    ClosedLoop::new(plant, ctrl, FixedGoal::new(goal).expect("valid goal"), dt).expect("valid loop")
}

/// Fig. 7: (0, 0, 0) -> (1, 1, 120 deg).
pub fn fig7<T: Real>() -> (Pose2<T>, Pose2<T>) {
    (Pose2::new(T::zero(), T::zero(), T::zero()), Pose2::new(T::one(), T::one(), T::lit(120f64.to_radians())))
}
