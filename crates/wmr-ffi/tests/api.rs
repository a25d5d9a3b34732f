//! The C API called from Rust: its verdict on any parameters equals the core's own
//! validation (same code, same field), it never panics, and a loop composed of its calls
//! equals the core's `ClosedLoop` bit for bit for every law.
#![allow(unsafe_code)]

use std::ffi::CStr;
use std::mem::MaybeUninit;

use proptest::prelude::*;
use wmr_core::{
    ClosedLoop, Controller, DriveParams, FixedGoal, LyapunovLaw, LyapunovParams, ParamError, Plant, PolarLaw,
    PolarParams, Pose2, PoseSensor, Reason, Robot, RobotParams, SensorParams, TorqueDriveParams, WheelStage,
    WheelStageParams, WorldParams,
};
use wmr_ffi::*;

fn code_of(e: &ParamError) -> wmr_status {
    match e.reason {
        Reason::NotFinite => wmr_status::WMR_NOT_FINITE,
        Reason::NotPositive => wmr_status::WMR_NOT_POSITIVE,
        Reason::Negative => wmr_status::WMR_NEGATIVE,
        Reason::NotMultipleOfDt => wmr_status::WMR_NOT_MULTIPLE_OF_DT,
        Reason::NaN => wmr_status::WMR_NAN,
        Reason::OutOfRange(_) => wmr_status::WMR_OUT_OF_RANGE,
        other => panic!("a reason this test does not know: {other:?}"),
    }
}

fn field(e: &wmr_error) -> String {
    // SAFETY: the library NUL-terminates `field`.
    unsafe { CStr::from_ptr(e.field.as_ptr()) }.to_str().expect("ASCII").to_owned()
}

fn new_err() -> wmr_error {
    wmr_error { code: wmr_status::WMR_OK, value: 0.0, field: [0; WMR_FIELD_LEN], reason: [0; WMR_REASON_LEN] }
}

/// A value that is often invalid: NaN, infinities, zero, negative, or a plausible one.
fn any_value() -> impl Strategy<Value = f64> {
    prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY), Just(0.0), -10.0..10.0f64, 0.001..10.0f64,]
}

fn robot_params() -> impl Strategy<Value = RobotParams<f64>> {
    (prop::array::uniform11(any_value()), prop::array::uniform11(any::<bool>())).prop_map(|(v, keep)| {
        let p = RobotParams::<f64>::paper();
        let pick = |i: usize, d: f64| if keep[i] { d } else { v[i] };
        RobotParams {
            mass: pick(0, p.mass),
            wheel_radius: pick(1, p.wheel_radius),
            half_track: pick(2, p.half_track),
            com_offset: pick(3, p.com_offset),
            wheel_inertia: pick(4, p.wheel_inertia),
            platform_inertia: pick(5, p.platform_inertia),
            gear_ratio: pick(6, p.gear_ratio),
            viscous_friction: pick(7, p.viscous_friction),
            coulomb_friction: pick(8, p.coulomb_friction),
            coulomb_speed: pick(9, p.coulomb_speed),
            static_friction: pick(10, p.static_friction),
        }
    })
}

fn c_robot(p: &RobotParams<f64>) -> wmr_robot_params<f64> {
    wmr_robot_params {
        mass: p.mass,
        wheel_radius: p.wheel_radius,
        half_track: p.half_track,
        com_offset: p.com_offset,
        wheel_inertia: p.wheel_inertia,
        platform_inertia: p.platform_inertia,
        gear_ratio: p.gear_ratio,
        viscous_friction: p.viscous_friction,
        coulomb_friction: p.coulomb_friction,
        coulomb_speed: p.coulomb_speed,
        static_friction: p.static_friction,
    }
}

fn valid_robot() -> wmr_robot_f64 {
    let mut rp = MaybeUninit::uninit();
    let mut robot = MaybeUninit::uninit();
    // SAFETY: valid out-pointers; the calls fill them on WMR_OK.
    unsafe {
        assert_eq!(wmr_robot_params_f64_paper(rp.as_mut_ptr()), wmr_status::WMR_OK);
        assert_eq!(wmr_robot_f64_init(robot.as_mut_ptr(), rp.as_ptr(), std::ptr::null_mut()), wmr_status::WMR_OK);
        robot.assume_init()
    }
}

fn valid_drive(robot: &wmr_robot_f64, kind: u32) -> (wmr_drive_params<f64>, wmr_drive_f64) {
    let mut dp = MaybeUninit::uninit();
    let mut drive = MaybeUninit::uninit();
    // SAFETY: as above.
    unsafe {
        assert_eq!(wmr_drive_params_f64_default(kind, dp.as_mut_ptr()), wmr_status::WMR_OK);
        assert_eq!(
            wmr_drive_f64_init(drive.as_mut_ptr(), dp.as_ptr(), robot, std::ptr::null_mut()),
            wmr_status::WMR_OK
        );
        (dp.assume_init(), drive.assume_init())
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn robot_init_agrees_with_the_core(p in robot_params()) {
        let mut err = new_err();
        let mut robot = MaybeUninit::<wmr_robot_f64>::uninit();
        // SAFETY: valid pointers.
        let code = unsafe { wmr_robot_f64_init(robot.as_mut_ptr(), &c_robot(&p), &mut err) };
        prop_assert_ne!(code, wmr_status::WMR_PANIC);
        match p.validate() {
            Ok(_) => prop_assert_eq!(code, wmr_status::WMR_OK),
            Err(e) => {
                prop_assert_eq!(code, code_of(&e));
                prop_assert_eq!(err.code, code);
                prop_assert_eq!(field(&err), e.field);
                prop_assert!(err.value.to_bits() == e.value.to_bits());
            }
        }
    }

    #[test]
    fn torque_drive_and_wheel_stage_agree_with_the_core(
        limit in any_value(), kp in any_value(), kd in any_value(), ki in any_value(), vmax in any_value(), dt in any_value()
    ) {
        let robot_c = valid_robot();
        let robot = Robot::<f64>::paper();
        let (mut dp, _) = valid_drive(&robot_c, WMR_DRIVE_TORQUE);
        dp.motor_torque_max = limit;
        let mut err = new_err();
        let mut drive_c = MaybeUninit::<wmr_drive_f64>::uninit();
        // SAFETY: valid pointers.
        let code = unsafe { wmr_drive_f64_init(drive_c.as_mut_ptr(), &dp, &robot_c, &mut err) };
        let core = DriveParams::Torque(TorqueDriveParams { motor_torque_max: limit, ..TorqueDriveParams::default() }).validate(&robot);
        let drive = match core {
            Err(e) => {
                prop_assert_eq!(code, code_of(&e));
                prop_assert_eq!(field(&err), e.field);
                return Ok(());
            }
            Ok(d) => { prop_assert_eq!(code, wmr_status::WMR_OK); d }
        };
        let wp = wmr_wheel_stage_params { servo_kp: kp, servo_kd: kd, servo_ki: ki, wheel_speed_max: vmax };
        let pp = PolarParams::<f64>::default();
        let mut ppc = MaybeUninit::uninit();
        let mut ctrl = MaybeUninit::<wmr_polar_controller_f64>::uninit();
        // SAFETY: valid pointers; drive_c was filled (code was WMR_OK).
        let code = unsafe {
            wmr_polar_params_f64_default(ppc.as_mut_ptr());
            wmr_polar_controller_f64_init(ctrl.as_mut_ptr(), ppc.as_ptr(), &wp, &robot_c, drive_c.as_ptr(), dt, &mut err)
        };
        prop_assert_ne!(code, wmr_status::WMR_PANIC);
        let wheels = WheelStageParams { servo_kp: kp, servo_kd: kd, servo_ki: ki, wheel_speed_max: vmax };
        let core = PolarLaw::new(pp).and_then(|_| WheelStage::new(&wheels, robot.params(), &drive, dt));
        match core {
            Ok(_) => prop_assert_eq!(code, wmr_status::WMR_OK),
            Err(e) => {
                prop_assert_eq!(code, code_of(&e));
                prop_assert_eq!(field(&err), e.field);
            }
        }
    }

    #[test]
    fn lyapunov_gains_agree_with_the_core(gamma in any_value(), k in any_value(), h in any_value(), hyst in any_value(), radius in any_value(), reverse in 0u32..3) {
        let robot_c = valid_robot();
        let (dp, drive_c) = valid_drive(&robot_c, WMR_DRIVE_DC_MOTOR);
        let mut wp = MaybeUninit::uninit();
        let lp = wmr_lyapunov_params { gamma, k, h, reverse, reverse_hysteresis: hyst, goal_radius: radius };
        let mut err = new_err();
        let mut ctrl = MaybeUninit::<wmr_lyapunov_controller_f64>::uninit();
        // SAFETY: valid pointers.
        let code = unsafe {
            wmr_wheel_stage_params_f64_default(&dp, &robot_c, wp.as_mut_ptr());
            wmr_lyapunov_controller_f64_init(ctrl.as_mut_ptr(), &lp, wp.as_ptr(), &robot_c, &drive_c, 1e-3, &mut err)
        };
        prop_assert_ne!(code, wmr_status::WMR_PANIC);
        if reverse > 1 {
            prop_assert_eq!(code, wmr_status::WMR_OUT_OF_RANGE);
            prop_assert_eq!(field(&err), "reverse");
            return Ok(());
        }
        let core = LyapunovLaw::new(LyapunovParams { gamma, k, h, reverse: reverse == 1, reverse_hysteresis: hyst, goal_radius: radius });
        match core {
            Ok(_) => prop_assert_eq!(code, wmr_status::WMR_OK),
            Err(e) => {
                prop_assert_eq!(code, code_of(&e));
                prop_assert_eq!(field(&err), e.field);
            }
        }
    }
}

#[test]
fn null_pointers_are_refused_by_name() {
    let mut err = new_err();
    let robot = valid_robot();
    // SAFETY: NULL is allowed and must be refused; the rest are valid.
    unsafe {
        assert_eq!(wmr_robot_params_f32_paper(std::ptr::null_mut()), wmr_status::WMR_NULL_POINTER);
        let code = wmr_plant_f64_init(
            std::ptr::null_mut(),
            &robot,
            std::ptr::null(),
            std::ptr::null(),
            wmr_pose::default(),
            &mut err,
        );
        assert_eq!(code, wmr_status::WMR_NULL_POINTER);
        assert_eq!(field(&err), "drive");
        assert_eq!(wmr_plant_f64_step(std::ptr::null_mut(), 0.0, 1e-3), wmr_status::WMR_NULL_POINTER);
        assert_eq!(wmr_sensor_f32_init_perfect(std::ptr::null_mut()), wmr_status::WMR_NULL_POINTER);
    }
}

#[test]
fn a_diverging_plant_step_is_refused_and_keeps_the_state() {
    let robot = valid_robot();
    let (_, drive) = valid_drive(&robot, WMR_DRIVE_TORQUE);
    let mut plant = MaybeUninit::<wmr_plant_f64>::uninit();
    let mut before = wmr_state::default();
    let mut after = wmr_state::default();
    // SAFETY: valid pointers.
    unsafe {
        let start = wmr_pose { x: 999.9999, y: 0.0, theta: 0.0 };
        assert_eq!(
            wmr_plant_f64_init(plant.as_mut_ptr(), &robot, &drive, std::ptr::null(), start, std::ptr::null_mut()),
            wmr_status::WMR_OK
        );
        let plant = plant.as_mut_ptr();
        assert_eq!(wmr_plant_f64_apply(plant, wmr_wheels { right: 1e9, left: 1e9 }), wmr_status::WMR_OK);
        assert_eq!(wmr_plant_f64_step(plant, 0.0, 1e-3), wmr_status::WMR_OK);
        wmr_plant_f64_state(plant, &mut before);
        let mut code = wmr_status::WMR_OK;
        for k in 1..100_000 {
            code = wmr_plant_f64_step(plant, k as f64 * 1e-3, 1e-3);
            if code != wmr_status::WMR_OK {
                break;
            }
            wmr_plant_f64_state(plant, &mut before);
        }
        assert_eq!(code, wmr_status::WMR_DIVERGED_LEFT_BOX);
        wmr_plant_f64_state(plant, &mut after);
        assert_eq!(before, after);
        assert!(after.x <= 1000.0);
        // A step of NaN seconds is bad input, refused before the model runs (issue 25).
        assert_eq!(wmr_plant_f64_step(plant, 0.0, f64::NAN), wmr_status::WMR_NOT_FINITE);
        wmr_plant_f64_state(plant, &mut after);
        assert_eq!(before, after);
    }
}

const SLOPE_DEG: f64 = 3.0;
const SLOPE_DIR_DEG: f64 = 30.0;
const RUN: u64 = 3;

/// A sensor with every effect: 100 Hz, 20 ms late, noisy, 2048-count encoders.
fn sensor_params() -> SensorParams<f64> {
    SensorParams {
        rate_hz: 100.0,
        latency: 0.02,
        position_noise: 0.002,
        heading_noise_deg: 0.5,
        encoder_counts: 2048,
        seed: 7,
    }
}

/// A loop made of C API calls, as `examples/c/fig7.c` makes it, on a slope with the pose
/// sensor, against `ClosedLoop`; and
/// `reset` mid-way against a controller initialized afresh at that moment.
macro_rules! compare_loop {
    ($name:ident, $default:ident, $init:ident, $update:ident, $reset:ident, $storage:ty, $law:expr) => {
        #[test]
        fn $name() {
            let robot_c = valid_robot();
            let (dp, drive_c) = valid_drive(&robot_c, WMR_DRIVE_DC_MOTOR);
            let start = Pose2::new(0.3, -0.2, 2.5);
            let goal = Pose2::new(-1.0, 0.5, -1.0);
            let dt = 1e-3;
            let n = 8_000;
            let null = std::ptr::null_mut();
            // SAFETY: valid pointers, every init checked.
            let c_path = unsafe {
                let mut wp = MaybeUninit::uninit();
                let mut lp = MaybeUninit::uninit();
                let mut ctrl = MaybeUninit::<$storage>::uninit();
                let mut fresh = MaybeUninit::<$storage>::uninit();
                let mut plant = MaybeUninit::<wmr_plant_f64>::uninit();
                let mut sensor = MaybeUninit::<wmr_sensor_f64>::uninit();
                wmr_wheel_stage_params_f64_default(&dp, &robot_c, wp.as_mut_ptr());
                $default(lp.as_mut_ptr());
                assert_eq!(
                    $init(ctrl.as_mut_ptr(), lp.as_ptr(), wp.as_ptr(), &robot_c, &drive_c, dt, null),
                    wmr_status::WMR_OK
                );
                let s = wmr_pose { x: start.x, y: start.y, theta: start.theta };
                let world = wmr_world_params { slope_deg: SLOPE_DEG, slope_direction_deg: SLOPE_DIR_DEG };
                assert_eq!(
                    wmr_plant_f64_init(plant.as_mut_ptr(), &robot_c, &drive_c, &world, s, null),
                    wmr_status::WMR_OK
                );
                let sp = sensor_params();
                let csp = wmr_sensor_params {
                    rate_hz: sp.rate_hz,
                    latency: sp.latency,
                    position_noise: sp.position_noise,
                    heading_noise_deg: sp.heading_noise_deg,
                    encoder_counts: sp.encoder_counts,
                    seed: sp.seed,
                };
                assert_eq!(wmr_sensor_f64_init_pose(sensor.as_mut_ptr(), &csp, dt, RUN, null), wmr_status::WMR_OK);
                let g = wmr_pose { x: goal.x, y: goal.y, theta: goal.theta };
                let mut m = wmr_measurement::default();
                let mut out = wmr_control_output::default();
                let mut out_fresh = wmr_control_output::default();
                let mut path = Vec::new();
                for k in 0..n {
                    let t = k as f64 * dt;
                    if k == n / 2 {
                        assert_eq!($reset(ctrl.as_mut_ptr()), wmr_status::WMR_OK);
                        assert_eq!(
                            $init(fresh.as_mut_ptr(), lp.as_ptr(), wp.as_ptr(), &robot_c, &drive_c, dt, null),
                            wmr_status::WMR_OK
                        );
                    }
                    assert_eq!(
                        wmr_sensor_f64_measure(sensor.as_mut_ptr(), t, plant.as_ptr(), &mut m),
                        wmr_status::WMR_OK
                    );
                    assert_eq!($update(ctrl.as_mut_ptr(), t, &m, g, &mut out), wmr_status::WMR_OK);
                    if k >= n / 2 {
                        assert_eq!($update(fresh.as_mut_ptr(), t, &m, g, &mut out_fresh), wmr_status::WMR_OK);
                        assert_eq!(out, out_fresh, "tick {k}: reset differs from a fresh init");
                    }
                    assert_eq!(wmr_plant_f64_apply(plant.as_mut_ptr(), out.command), wmr_status::WMR_OK);
                    assert_eq!(wmr_plant_f64_step(plant.as_mut_ptr(), t, dt), wmr_status::WMR_OK);
                    let mut st = wmr_state::default();
                    wmr_plant_f64_state(plant.as_ptr(), &mut st);
                    path.push([st.x, st.y, st.theta, st.v, st.omega, st.phi_r, st.phi_l]);
                }
                path
            };
            let robot = Robot::<f64>::paper();
            let drive_params = DriveParams::DcMotor(Default::default());
            let drive = drive_params.validate(&robot).unwrap();
            let wheels = WheelStage::new(
                &WheelStageParams::for_drive(&drive_params, robot.params()),
                robot.params(),
                &drive,
                dt,
            )
            .unwrap();
            let world = WorldParams { slope_deg: SLOPE_DEG, slope_direction_deg: SLOPE_DIR_DEG }.validate().unwrap();
            let plant = Plant::on(robot, drive, world, start).unwrap();
            let sensor = PoseSensor::<f64>::new(sensor_params(), dt, RUN).unwrap();
            let goal = FixedGoal::new(goal).unwrap();
            let mut sim = ClosedLoop::with_sensor(plant, sensor, Controller::new($law, wheels), goal, dt).unwrap();
            // Until the reset (ClosedLoop has none) every state is the same, bit for bit.
            for (k, c) in c_path.iter().enumerate().take(n / 2) {
                sim.step().unwrap();
                let s = sim.state();
                let r = [s.x, s.y, s.theta, s.v, s.omega, s.phi_r, s.phi_l];
                assert_eq!(c.map(f64::to_bits), r.map(f64::to_bits), "step {k}");
            }
        }
    };
}

compare_loop!(
    polar_loop_equals_closed_loop,
    wmr_polar_params_f64_default,
    wmr_polar_controller_f64_init,
    wmr_polar_controller_f64_update,
    wmr_polar_controller_f64_reset,
    wmr_polar_controller_f64,
    PolarLaw::new(PolarParams::default()).unwrap()
);
compare_loop!(
    lyapunov_loop_equals_closed_loop,
    wmr_lyapunov_params_f64_default,
    wmr_lyapunov_controller_f64_init,
    wmr_lyapunov_controller_f64_update,
    wmr_lyapunov_controller_f64_reset,
    wmr_lyapunov_controller_f64,
    LyapunovLaw::new(LyapunovParams::default()).unwrap()
);
compare_loop!(
    paper_loop_equals_closed_loop,
    wmr_paper_params_f64_default,
    wmr_paper_controller_f64_init,
    wmr_paper_controller_f64_update,
    wmr_paper_controller_f64_reset,
    wmr_paper_controller_f64,
    wmr_core::PaperLaw::new(wmr_core::PaperParams::paper(), Robot::<f64>::paper().params(), 1e-3).unwrap()
);
compare_loop!(
    paper_bidirectional_loop_equals_closed_loop,
    wmr_paper_bidirectional_params_f64_default,
    wmr_paper_bidirectional_controller_f64_init,
    wmr_paper_bidirectional_controller_f64_update,
    wmr_paper_bidirectional_controller_f64_reset,
    wmr_paper_bidirectional_controller_f64,
    wmr_core::PaperBidirectionalLaw::new(
        wmr_core::PaperBidirectionalParams::default(),
        Robot::<f64>::paper().params(),
        1e-3
    )
    .unwrap()
);

/// The law structs that are the core's own types hold the core's enums as `uint32_t`
/// codes: a code that is no constant is refused by its field name before the struct is
/// read as the core's type (which would be undefined behaviour).
#[test]
fn enum_codes_outside_the_constants_are_refused_by_name() {
    let robot_c = valid_robot();
    let (dp, drive_c) = valid_drive(&robot_c, WMR_DRIVE_TORQUE);
    let mut wp = MaybeUninit::uninit();
    let mut err = new_err();
    // SAFETY: valid pointers; the bad codes are written through raw u32 pointers into
    // C-layout structs, as C would write them.
    unsafe {
        wmr_wheel_stage_params_f64_default(&dp, &robot_c, wp.as_mut_ptr());
        let mut pp = MaybeUninit::<wmr_paper_params<f64>>::uninit();
        let mut ctrl = MaybeUninit::<wmr_paper_controller_f64>::uninit();
        for (offset, code, name) in [
            (std::mem::offset_of!(wmr_paper_params<f64>, mode), 2u32, "mode"),
            (std::mem::offset_of!(wmr_paper_params<f64>, hold), 3u32, "hold"),
        ] {
            wmr_paper_params_f64_default(pp.as_mut_ptr());
            pp.as_mut_ptr().cast::<u8>().add(offset).cast::<u32>().write(code);
            let c = wmr_paper_controller_f64_init(
                ctrl.as_mut_ptr(),
                pp.as_ptr(),
                wp.as_ptr(),
                &robot_c,
                &drive_c,
                1e-3,
                &mut err,
            );
            assert_eq!(c, wmr_status::WMR_OUT_OF_RANGE, "{name}");
            assert_eq!(field(&err), name);
            assert_eq!(err.value, f64::from(code));
        }
        let mut bp = MaybeUninit::<wmr_paper_bidirectional_params<f64>>::uninit();
        let mut bctrl = MaybeUninit::<wmr_paper_bidirectional_controller_f64>::uninit();
        wmr_paper_bidirectional_params_f64_default(bp.as_mut_ptr());
        let hold = std::mem::offset_of!(wmr_paper_bidirectional_params<f64>, hold);
        bp.as_mut_ptr().cast::<u8>().add(hold).cast::<u32>().write(0xdead_beef);
        let c = wmr_paper_bidirectional_controller_f64_init(
            bctrl.as_mut_ptr(),
            bp.as_ptr(),
            wp.as_ptr(),
            &robot_c,
            &drive_c,
            1e-3,
            &mut err,
        );
        assert_eq!(c, wmr_status::WMR_OUT_OF_RANGE);
        assert_eq!(field(&err), "hold");
        // Every constant is accepted, and the defaults are the core's.
        for h in [WMR_HOLD_ZERO_ERRORS, WMR_HOLD_FREEZE, WMR_HOLD_AUTO] {
            bp.as_mut_ptr().cast::<u8>().add(hold).cast::<u32>().write(h);
            let c = wmr_paper_bidirectional_controller_f64_init(
                bctrl.as_mut_ptr(),
                bp.as_ptr(),
                wp.as_ptr(),
                &robot_c,
                &drive_c,
                1e-3,
                &mut err,
            );
            assert_eq!(c, wmr_status::WMR_OK, "hold {h}");
        }
        wmr_paper_bidirectional_params_f64_default(bp.as_mut_ptr());
        assert_eq!(bp.assume_init(), wmr_core::PaperBidirectionalParams::<f64>::default());
        let mut f32p = MaybeUninit::<wmr_paper_bidirectional_params<f32>>::uninit();
        assert_eq!(wmr_paper_bidirectional_params_f32_default(f32p.as_mut_ptr()), wmr_status::WMR_OK);
        assert_eq!(f32p.assume_init(), wmr_core::PaperBidirectionalParams::<f32>::default());
    }
}

/// A gain the core refuses is refused with the core's field name (ki_theta below its bound).
#[test]
fn paper_bidirectional_gains_are_checked_by_the_core() {
    let robot_c = valid_robot();
    let (dp, drive_c) = valid_drive(&robot_c, WMR_DRIVE_TORQUE);
    let mut wp = MaybeUninit::uninit();
    let mut err = new_err();
    let p = wmr_paper_bidirectional_params::<f64> { ki_theta: 0.1, ..Default::default() };
    let core = wmr_core::PaperBidirectionalLaw::new(p, Robot::<f64>::paper().params(), 1e-3).unwrap_err();
    let mut ctrl = MaybeUninit::<wmr_paper_bidirectional_controller_f64>::uninit();
    // SAFETY: valid pointers.
    let c = unsafe {
        wmr_wheel_stage_params_f64_default(&dp, &robot_c, wp.as_mut_ptr());
        wmr_paper_bidirectional_controller_f64_init(
            ctrl.as_mut_ptr(),
            &p,
            wp.as_ptr(),
            &robot_c,
            &drive_c,
            1e-3,
            &mut err,
        )
    };
    assert_eq!(c, code_of(&core));
    assert_eq!(field(&err), core.field);
}

/// `_update_reference` with the reference at rest at the goal equals `_update` with that
/// goal, bit for bit, tick after tick of a closed loop (in f64 and f32); a NaN in the
/// reference is refused by its field name and leaves the controller unchanged.
macro_rules! reference_at_rest {
    ($name:ident, $prec:ty, $default:ident, $init:ident, $update:ident, $update_ref:ident, $storage:ty, $params:ty,
     $robot:ident, $robot_init:ident, $drive_default:ident, $drive_init:ident, $wheels_default:ident,
     $plant:ty, $plant_init:ident, $apply:ident, $step:ident, $sensor:ty, $sensor_init:ident, $measure:ident) => {
        #[test]
        fn $name() {
            let null = std::ptr::null_mut();
            let dt: $prec = 1e-3;
            // SAFETY: valid pointers, every init checked.
            unsafe {
                let (mut rp, mut robot) = (MaybeUninit::uninit(), MaybeUninit::uninit());
                $robot(rp.as_mut_ptr());
                assert_eq!($robot_init(robot.as_mut_ptr(), rp.as_ptr(), null), wmr_status::WMR_OK);
                let (mut dp, mut drive) = (MaybeUninit::uninit(), MaybeUninit::uninit());
                $drive_default(WMR_DRIVE_DC_MOTOR, dp.as_mut_ptr());
                assert_eq!($drive_init(drive.as_mut_ptr(), dp.as_ptr(), robot.as_ptr(), null), wmr_status::WMR_OK);
                let (mut wp, mut lp) = (MaybeUninit::uninit(), MaybeUninit::<$params>::uninit());
                $wheels_default(dp.as_ptr(), robot.as_ptr(), wp.as_mut_ptr());
                $default(lp.as_mut_ptr());
                let mut a = MaybeUninit::<$storage>::uninit();
                let mut b = MaybeUninit::<$storage>::uninit();
                for c in [a.as_mut_ptr(), b.as_mut_ptr()] {
                    assert_eq!(
                        $init(c, lp.as_ptr(), wp.as_ptr(), robot.as_ptr(), drive.as_ptr(), dt, null),
                        wmr_status::WMR_OK
                    );
                }
                let mut plant = MaybeUninit::<$plant>::uninit();
                let start = wmr_pose { x: 0.3, y: -0.2, theta: 2.5 };
                assert_eq!(
                    $plant_init(plant.as_mut_ptr(), robot.as_ptr(), drive.as_ptr(), std::ptr::null(), start, null),
                    wmr_status::WMR_OK
                );
                let mut sensor = MaybeUninit::<$sensor>::uninit();
                $sensor_init(sensor.as_mut_ptr());
                // Distinct coordinates, so a swapped or dropped one shows.
                let goal = wmr_pose { x: -1.0, y: 0.5, theta: -0.7 };
                let at_rest = wmr_reference_state { pose: goal, ..Default::default() };
                let mut m = wmr_measurement::default();
                let (mut out_a, mut out_b) = (wmr_control_output::default(), wmr_control_output::default());
                for k in 0..3_000 {
                    let t = k as $prec * dt;
                    assert_eq!($measure(sensor.as_mut_ptr(), t, plant.as_ptr(), &mut m), wmr_status::WMR_OK);
                    assert_eq!($update(a.as_mut_ptr(), t, &m, goal, &mut out_a), wmr_status::WMR_OK);
                    assert_eq!($update_ref(b.as_mut_ptr(), t, &m, &at_rest, &mut out_b, null), wmr_status::WMR_OK);
                    let bits = |o: &wmr_control_output<$prec>| {
                        [o.command.right, o.command.left, o.e_s, o.e_theta, o.dl].map(<$prec>::to_bits)
                    };
                    assert_eq!(bits(&out_a), bits(&out_b), "tick {k}");
                    assert_eq!($apply(plant.as_mut_ptr(), out_a.command), wmr_status::WMR_OK);
                    assert_eq!($step(plant.as_mut_ptr(), t, dt), wmr_status::WMR_OK);
                }
                // Refused by name, the controller unchanged: the next tick still agrees.
                let t = 3_000 as $prec * dt;
                let mut e = new_err();
                for (field_name, bad) in [
                    (
                        "reference.accel.omega",
                        wmr_reference_state { accel: wmr_accel { v: 0.0, omega: <$prec>::NAN }, ..at_rest },
                    ),
                    (
                        "reference.twist.v",
                        wmr_reference_state { twist: wmr_twist { v: <$prec>::INFINITY, omega: 0.0 }, ..at_rest },
                    ),
                    (
                        "reference.pose.theta",
                        wmr_reference_state { pose: wmr_pose { theta: <$prec>::NAN, ..goal }, ..at_rest },
                    ),
                ] {
                    let mut kept = out_b;
                    assert_eq!($update_ref(b.as_mut_ptr(), t, &m, &bad, &mut kept, &mut e), wmr_status::WMR_NOT_FINITE);
                    assert_eq!(field(&e), field_name);
                    assert_eq!(kept, out_b, "a refused tick writes nothing");
                }
                let mut kept = out_b;
                assert_eq!(
                    $update_ref(b.as_mut_ptr(), t, &m, std::ptr::null(), &mut kept, &mut e),
                    wmr_status::WMR_NULL_POINTER
                );
                assert_eq!(field(&e), "reference");
                assert_eq!($update(a.as_mut_ptr(), t, &m, goal, &mut out_a), wmr_status::WMR_OK);
                assert_eq!($update_ref(b.as_mut_ptr(), t, &m, &at_rest, &mut out_b, &mut e), wmr_status::WMR_OK);
                assert_eq!(out_a, out_b);
            }
        }
    };
}

reference_at_rest!(
    paper_f64_update_reference_at_rest_is_update,
    f64,
    wmr_paper_params_f64_default,
    wmr_paper_controller_f64_init,
    wmr_paper_controller_f64_update,
    wmr_paper_controller_f64_update_reference,
    wmr_paper_controller_f64,
    wmr_paper_params<f64>,
    wmr_robot_params_f64_paper,
    wmr_robot_f64_init,
    wmr_drive_params_f64_default,
    wmr_drive_f64_init,
    wmr_wheel_stage_params_f64_default,
    wmr_plant_f64,
    wmr_plant_f64_init,
    wmr_plant_f64_apply,
    wmr_plant_f64_step,
    wmr_sensor_f64,
    wmr_sensor_f64_init_perfect,
    wmr_sensor_f64_measure
);
reference_at_rest!(
    paper_f32_update_reference_at_rest_is_update,
    f32,
    wmr_paper_params_f32_default,
    wmr_paper_controller_f32_init,
    wmr_paper_controller_f32_update,
    wmr_paper_controller_f32_update_reference,
    wmr_paper_controller_f32,
    wmr_paper_params<f32>,
    wmr_robot_params_f32_paper,
    wmr_robot_f32_init,
    wmr_drive_params_f32_default,
    wmr_drive_f32_init,
    wmr_wheel_stage_params_f32_default,
    wmr_plant_f32,
    wmr_plant_f32_init,
    wmr_plant_f32_apply,
    wmr_plant_f32_step,
    wmr_sensor_f32,
    wmr_sensor_f32_init_perfect,
    wmr_sensor_f32_measure
);
reference_at_rest!(
    paper_bidirectional_f64_update_reference_at_rest_is_update,
    f64,
    wmr_paper_bidirectional_params_f64_default,
    wmr_paper_bidirectional_controller_f64_init,
    wmr_paper_bidirectional_controller_f64_update,
    wmr_paper_bidirectional_controller_f64_update_reference,
    wmr_paper_bidirectional_controller_f64,
    wmr_paper_bidirectional_params<f64>,
    wmr_robot_params_f64_paper,
    wmr_robot_f64_init,
    wmr_drive_params_f64_default,
    wmr_drive_f64_init,
    wmr_wheel_stage_params_f64_default,
    wmr_plant_f64,
    wmr_plant_f64_init,
    wmr_plant_f64_apply,
    wmr_plant_f64_step,
    wmr_sensor_f64,
    wmr_sensor_f64_init_perfect,
    wmr_sensor_f64_measure
);
reference_at_rest!(
    paper_bidirectional_f32_update_reference_at_rest_is_update,
    f32,
    wmr_paper_bidirectional_params_f32_default,
    wmr_paper_bidirectional_controller_f32_init,
    wmr_paper_bidirectional_controller_f32_update,
    wmr_paper_bidirectional_controller_f32_update_reference,
    wmr_paper_bidirectional_controller_f32,
    wmr_paper_bidirectional_params<f32>,
    wmr_robot_params_f32_paper,
    wmr_robot_f32_init,
    wmr_drive_params_f32_default,
    wmr_drive_f32_init,
    wmr_wheel_stage_params_f32_default,
    wmr_plant_f32,
    wmr_plant_f32_init,
    wmr_plant_f32_apply,
    wmr_plant_f32_step,
    wmr_sensor_f32,
    wmr_sensor_f32_init_perfect,
    wmr_sensor_f32_measure
);
reference_at_rest!(
    polar_f64_update_reference_at_rest_is_update,
    f64,
    wmr_polar_params_f64_default,
    wmr_polar_controller_f64_init,
    wmr_polar_controller_f64_update,
    wmr_polar_controller_f64_update_reference,
    wmr_polar_controller_f64,
    wmr_polar_params<f64>,
    wmr_robot_params_f64_paper,
    wmr_robot_f64_init,
    wmr_drive_params_f64_default,
    wmr_drive_f64_init,
    wmr_wheel_stage_params_f64_default,
    wmr_plant_f64,
    wmr_plant_f64_init,
    wmr_plant_f64_apply,
    wmr_plant_f64_step,
    wmr_sensor_f64,
    wmr_sensor_f64_init_perfect,
    wmr_sensor_f64_measure
);
reference_at_rest!(
    polar_f32_update_reference_at_rest_is_update,
    f32,
    wmr_polar_params_f32_default,
    wmr_polar_controller_f32_init,
    wmr_polar_controller_f32_update,
    wmr_polar_controller_f32_update_reference,
    wmr_polar_controller_f32,
    wmr_polar_params<f32>,
    wmr_robot_params_f32_paper,
    wmr_robot_f32_init,
    wmr_drive_params_f32_default,
    wmr_drive_f32_init,
    wmr_wheel_stage_params_f32_default,
    wmr_plant_f32,
    wmr_plant_f32_init,
    wmr_plant_f32_apply,
    wmr_plant_f32_step,
    wmr_sensor_f32,
    wmr_sensor_f32_init_perfect,
    wmr_sensor_f32_measure
);
reference_at_rest!(
    lyapunov_f64_update_reference_at_rest_is_update,
    f64,
    wmr_lyapunov_params_f64_default,
    wmr_lyapunov_controller_f64_init,
    wmr_lyapunov_controller_f64_update,
    wmr_lyapunov_controller_f64_update_reference,
    wmr_lyapunov_controller_f64,
    wmr_lyapunov_params<f64>,
    wmr_robot_params_f64_paper,
    wmr_robot_f64_init,
    wmr_drive_params_f64_default,
    wmr_drive_f64_init,
    wmr_wheel_stage_params_f64_default,
    wmr_plant_f64,
    wmr_plant_f64_init,
    wmr_plant_f64_apply,
    wmr_plant_f64_step,
    wmr_sensor_f64,
    wmr_sensor_f64_init_perfect,
    wmr_sensor_f64_measure
);
reference_at_rest!(
    lyapunov_f32_update_reference_at_rest_is_update,
    f32,
    wmr_lyapunov_params_f32_default,
    wmr_lyapunov_controller_f32_init,
    wmr_lyapunov_controller_f32_update,
    wmr_lyapunov_controller_f32_update_reference,
    wmr_lyapunov_controller_f32,
    wmr_lyapunov_params<f32>,
    wmr_robot_params_f32_paper,
    wmr_robot_f32_init,
    wmr_drive_params_f32_default,
    wmr_drive_f32_init,
    wmr_wheel_stage_params_f32_default,
    wmr_plant_f32,
    wmr_plant_f32_init,
    wmr_plant_f32_apply,
    wmr_plant_f32_step,
    wmr_sensor_f32,
    wmr_sensor_f32_init_perfect,
    wmr_sensor_f32_measure
);

/// Issue 42: the observer's C defaults are the core's, and `_init_observer`'s verdict on
/// any bandwidth is the core's validation's (same code), named `observer.bandwidth` as the
/// scenario names it; a valid one gives a controller whose estimate is readable (0 before
/// a tick), a controller without one refuses `_disturbance`.
#[test]
fn issue_42_the_observer_bandwidth_is_checked_by_the_core() {
    let robot_c = valid_robot();
    let (dp, drive_c) = valid_drive(&robot_c, WMR_DRIVE_TORQUE);
    let mut op = MaybeUninit::<wmr_disturbance_observer_params<f64>>::uninit();
    // SAFETY: a valid out-pointer.
    assert_eq!(unsafe { wmr_disturbance_observer_params_f64_default(op.as_mut_ptr()) }, wmr_status::WMR_OK);
    // SAFETY: filled on WMR_OK.
    let op = unsafe { op.assume_init() };
    let dflt = wmr_core::DisturbanceObserverParams::<f64>::default();
    assert_eq!(
        (op.bandwidth, op.deadband, op.static_friction, op.precompensation_band),
        (dflt.bandwidth, dflt.deadband, dflt.static_friction, dflt.precompensation_band)
    );
    let model = Robot::<f64>::paper();
    let drive = wmr_core::DriveParams::default().validate(&model).unwrap();
    let bad = [0.0, -1.0, f64::NAN, f64::INFINITY];
    let cases =
        [op.bandwidth, 1e-3, 1e6].into_iter().chain(bad).map(|b| ("observer.bandwidth", Some(b), None, None, None));
    let cases = cases
        .chain([0.05, 0.5, -0.1, 1.0, f64::NAN].map(|x| ("observer.deadband", None, Some(x), None, None)))
        .chain(
            [0.04, 3.0, -0.1, f64::NAN, f64::INFINITY].map(|x| ("observer.static_friction", None, None, Some(x), None)),
        )
        .chain([0.0, 1.0, -0.1, 1.5, f64::NAN].map(|x| ("observer.precompensation_band", None, None, None, Some(x))));
    for (name, b, dead, stat, band) in cases {
        let p = wmr_disturbance_observer_params {
            bandwidth: b.unwrap_or(op.bandwidth),
            deadband: dead.unwrap_or(op.deadband),
            static_friction: stat.unwrap_or(op.static_friction),
            precompensation_band: band.unwrap_or(op.precompensation_band),
        };
        let bandwidth = (b, dead, stat, band);
        let core = wmr_core::DisturbanceObserverParams {
            bandwidth: p.bandwidth,
            deadband: p.deadband,
            static_friction: p.static_friction,
            precompensation_band: p.precompensation_band,
        }
        .validate::<f64>(model.params(), &drive, 1e-3)
        .map(|_| ());
        let (mut wp, mut lp) = (MaybeUninit::uninit(), MaybeUninit::uninit());
        let mut ctrl = MaybeUninit::<wmr_paper_controller_f64>::uninit();
        let mut err = new_err();
        let mut d = wmr_wheels { right: 7.0, left: 7.0 };
        // SAFETY: valid pointers; `ctrl` is read only after WMR_OK.
        let (c, got) = unsafe {
            wmr_wheel_stage_params_f64_default(&dp, &robot_c, wp.as_mut_ptr());
            wmr_paper_params_f64_default(lp.as_mut_ptr());
            let c = wmr_paper_controller_f64_init_observer(
                ctrl.as_mut_ptr(),
                lp.as_ptr(),
                wp.as_ptr(),
                &p,
                &robot_c,
                &drive_c,
                1e-3,
                &mut err,
            );
            let got =
                if c == wmr_status::WMR_OK { wmr_paper_controller_f64_disturbance(ctrl.as_ptr(), &mut d) } else { c };
            (c, got)
        };
        match core {
            Ok(()) => {
                assert_eq!((c, got), (wmr_status::WMR_OK, wmr_status::WMR_OK), "{bandwidth:?}");
                assert_eq!((d.right, d.left), (0.0, 0.0));
            }
            Err(e) => {
                assert_eq!(c, code_of(&e), "{bandwidth:?}");
                assert_eq!(field(&err), name, "{bandwidth:?}");
            }
        }
    }
    let (mut wp, mut lp) = (MaybeUninit::uninit(), MaybeUninit::uninit());
    let mut ctrl = MaybeUninit::<wmr_paper_controller_f64>::uninit();
    let mut d = wmr_wheels { right: 7.0, left: 7.0 };
    // SAFETY: valid pointers.
    unsafe {
        wmr_wheel_stage_params_f64_default(&dp, &robot_c, wp.as_mut_ptr());
        wmr_paper_params_f64_default(lp.as_mut_ptr());
        let null = std::ptr::null_mut();
        assert_eq!(
            wmr_paper_controller_f64_init(ctrl.as_mut_ptr(), lp.as_ptr(), wp.as_ptr(), &robot_c, &drive_c, 1e-3, null),
            wmr_status::WMR_OK
        );
        assert_eq!(wmr_paper_controller_f64_disturbance(ctrl.as_ptr(), &mut d), wmr_status::WMR_OUT_OF_RANGE);
    }
    assert_eq!((d.right, d.left), (7.0, 7.0), "out untouched");
}
