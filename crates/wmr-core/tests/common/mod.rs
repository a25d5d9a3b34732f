//! Test-only helpers: tolerance checks with explicit rtol/atol, and the paper's Fig. 7 loop.
#![allow(dead_code)]

use wmr_core::{ClosedLoop, DriveParams, PaperController, PaperParams, Pose2, Real, Robot, RobotParams};

/// |a - b| <= atol + rtol |b|.
pub fn isclose(a: f64, b: f64, rtol: f64, atol: f64) -> bool {
    (a - b).abs() <= atol + rtol * b.abs()
}

/// Asserts `isclose` with a readable message.
#[track_caller]
pub fn assert_close(what: &str, a: f64, b: f64, rtol: f64, atol: f64) {
    assert!(isclose(a, b, rtol, atol), "{what}: {a} vs {b} (|diff| {:e}, rtol {rtol:e}, atol {atol:e})", (a - b).abs());
}

/// The paper's closed loop from `start` to `goal` (m, m, rad) with every SPEC default.
pub fn paper_loop<T: Real>(start: Pose2<T>, goal: Pose2<T>) -> ClosedLoop<T, PaperController<T>> {
    paper_loop_with(RobotParams::paper(), PaperParams::paper(), start, goal, T::lit(1e-3))
}

/// The paper's closed loop with given robot and controller parameters and plant step.
pub fn paper_loop_with<T: Real>(
    robot: RobotParams<T>,
    params: PaperParams<T>,
    start: Pose2<T>,
    goal: Pose2<T>,
    dt: T,
) -> ClosedLoop<T, PaperController<T>> {
    let robot: Robot<T> = robot.validate().expect("valid robot");
    let drive = DriveParams::default().validate(&robot).expect("valid drive");
    let ctrl = PaperController::new(params, &robot, &drive, goal).expect("valid controller");
    ClosedLoop::new(robot, drive, ctrl, start, dt).expect("valid loop")
}

/// Fig. 7: (0, 0, 0) -> (1, 1, 120 deg).
pub fn fig7<T: Real>() -> (Pose2<T>, Pose2<T>) {
    (Pose2::new(T::zero(), T::zero(), T::zero()), Pose2::new(T::one(), T::one(), T::lit(120f64.to_radians())))
}
