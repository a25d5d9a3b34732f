//! The simulation hot loop allocates nothing: a counting global allocator sees zero
//! allocations over 100 000 closed-loop steps (f64 and f32, torque and DC motor drives).

mod common;

use common::fig7;
use wmr_core::{
    ClosedLoop, Controller, DcMotorParams, DriveParams, FixedGoal, PaperLaw, PaperParams, Plant, Real, Robot,
    ServoGains, WheelStage, WheelStageParams,
};

fn steps_allocate<T: Real>(drive: DriveParams<T>, servo: ServoGains<T>) -> u64 {
    let robot = Robot::<T>::paper();
    let drive = drive.validate(&robot).unwrap();
    let (start, goal) = fig7::<T>();
    let dt = T::lit(1e-3);
    let wheels =
        WheelStageParams { servo_kp: servo.kp, servo_kd: servo.kd, servo_ki: servo.ki, ..WheelStageParams::default() };
    let law = PaperLaw::new(PaperParams::paper(), robot.params(), dt).unwrap();
    let ctrl = Controller::new(law, WheelStage::new(&wheels, robot.params(), &drive, dt).unwrap());
    let plant = Plant::new(robot, drive, start).unwrap();
    let mut sim = ClosedLoop::new(plant, ctrl, FixedGoal::new(goal).unwrap(), dt).unwrap();
    let mut checksum = T::zero();
    let info = allocation_counter::measure(|| {
        let out = sim.run(100_000, 10, |s| checksum = checksum + s.state.x);
        checksum = checksum + out.final_dl;
    });
    assert!(checksum.is_finite());
    info.count_total
}

#[test]
fn hundred_thousand_closed_loop_steps_allocate_nothing() {
    assert_eq!(steps_allocate::<f64>(DriveParams::default(), ServoGains::torque_default()), 0);
    assert_eq!(steps_allocate::<f32>(DriveParams::default(), ServoGains::torque_default()), 0);
    let dc = DriveParams::DcMotor(DcMotorParams::default());
    assert_eq!(steps_allocate::<f64>(dc, ServoGains::dc_motor_default()), 0);
}

/// The counter does count: a Vec push is seen (so the zero above is not vacuous).
#[test]
fn the_counter_sees_an_allocation() {
    let info = allocation_counter::measure(|| {
        let v: Vec<u8> = std::hint::black_box(Vec::with_capacity(16));
        drop(v);
    });
    assert!(info.count_total >= 1);
}
