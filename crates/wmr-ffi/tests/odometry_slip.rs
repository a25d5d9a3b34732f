//! The slip plant and the odometry sensor through the C API: a loop of C calls equals the
//! core's `ClosedLoop` bit for bit (the speed guard fitted to slipping wheels by
//! `_for_plant`, the odometry pose and the EKF's covariance), and their parameter structs
//! are refused by field name as every other.
#![allow(unsafe_code)]

use std::ffi::CStr;
use std::mem::MaybeUninit;

use wmr_core::{
    AnySensor, ClosedLoop, Controller, DcMotorParams, DriveParams, FixedGoal, LawParams, LyapunovParams,
    OdometryParams, Plant, Pose2, PoseSource, Robot, SensorParams, TractionKind, TractionParams, WheelStage,
    WheelStageParams, WorldParams,
};
use wmr_ffi::*;

const DT: f64 = 1e-3;
const STEPS: usize = 4_000;
const START: Pose2<f64> = Pose2 { x: 0.0, y: 0.0, theta: 0.0 };
/// Far ahead, so both wheels are driven flat out on ice and spin past `wheel_speed_max`.
const GOAL: Pose2<f64> = Pose2 { x: 4.0, y: 0.5, theta: 0.0 };
const MU_ICE: f64 = 0.1;

fn new_err() -> wmr_error {
    wmr_error { code: wmr_status::WMR_OK, value: 0.0, field: [0; WMR_FIELD_LEN], reason: [0; WMR_REASON_LEN] }
}

fn field(e: &wmr_error) -> String {
    // SAFETY: the library NUL-terminates `field`.
    unsafe { CStr::from_ptr(e.field.as_ptr()) }.to_str().expect("ASCII").to_owned()
}

fn sensor_params() -> SensorParams<f64> {
    SensorParams {
        encoder_counts: 2048,
        position_noise: 0.01,
        heading_noise_deg: 0.5,
        latency: 0.1,
        seed: 9,
        ..Default::default()
    }
}

fn odometry_params() -> OdometryParams<f64> {
    OdometryParams { pose: PoseSource::Odometry, fix_rate_hz: 2.0, odometry_noise: 0.02 }
}

fn traction_params() -> TractionParams<f64> {
    TractionParams { traction: TractionKind::Slip, friction_coefficient: MU_ICE, ..Default::default() }
}

/// What a loop ends with: the true state's pose, the odometry pose, the EKF covariance.
#[derive(Debug, PartialEq)]
struct End {
    pose: [f64; 3],
    odometry: [f64; 3],
    covariance: [f64; 9],
}

/// The loop of C calls (as examples/c/odometry_slip.c makes it), the Lyapunov law on the
/// DC motor, on ice; `for_plant` says whether the controller is fitted to the plant.
fn c_loop(for_plant: bool) -> End {
    let null = std::ptr::null_mut();
    // SAFETY: valid pointers; every init is checked before its storage is used.
    unsafe {
        let mut rp = MaybeUninit::uninit();
        let mut robot = MaybeUninit::<wmr_robot_f64>::uninit();
        assert_eq!(wmr_robot_params_f64_paper(rp.as_mut_ptr()), wmr_status::WMR_OK);
        assert_eq!(wmr_robot_f64_init(robot.as_mut_ptr(), rp.as_ptr(), null), wmr_status::WMR_OK);
        let mut dp = MaybeUninit::uninit();
        let mut drive = MaybeUninit::<wmr_drive_f64>::uninit();
        assert_eq!(wmr_drive_params_f64_default(WMR_DRIVE_DC_MOTOR, dp.as_mut_ptr()), wmr_status::WMR_OK);
        assert_eq!(wmr_drive_f64_init(drive.as_mut_ptr(), dp.as_ptr(), robot.as_ptr(), null), wmr_status::WMR_OK);
        let mut tp = MaybeUninit::<wmr_traction_params<f64>>::uninit();
        assert_eq!(wmr_traction_params_f64_default(tp.as_mut_ptr()), wmr_status::WMR_OK);
        let mut tp = tp.assume_init();
        tp.traction = TractionKind::Slip;
        tp.friction_coefficient = MU_ICE;
        let mut plant = MaybeUninit::<wmr_plant_f64>::uninit();
        let start = wmr_pose { x: START.x, y: START.y, theta: START.theta };
        assert_eq!(
            wmr_plant_f64_init_traction(
                plant.as_mut_ptr(),
                robot.as_ptr(),
                drive.as_ptr(),
                std::ptr::null(),
                &tp,
                start,
                null
            ),
            wmr_status::WMR_OK
        );
        let mut op = MaybeUninit::<wmr_odometry_params<f64>>::uninit();
        assert_eq!(wmr_odometry_params_f64_default(op.as_mut_ptr()), wmr_status::WMR_OK);
        let mut op = op.assume_init();
        assert_eq!(op.pose, PoseSource::Odometry, "the default of the odometry init is odometry");
        op.fix_rate_hz = odometry_params().fix_rate_hz;
        op.odometry_noise = odometry_params().odometry_noise;
        let mut sensor = MaybeUninit::<wmr_sensor_f64>::uninit();
        assert_eq!(
            wmr_sensor_f64_init_odometry(sensor.as_mut_ptr(), &sensor_params(), &op, robot.as_ptr(), DT, 3, null),
            wmr_status::WMR_OK
        );
        let mut est = MaybeUninit::<wmr_odometry_estimate<f64>>::uninit();
        assert_eq!(
            wmr_sensor_f64_odometry(sensor.as_ptr(), est.as_mut_ptr()),
            wmr_status::WMR_OUT_OF_RANGE,
            "no estimate before the first tick"
        );
        let mut wp = MaybeUninit::uninit();
        let mut lp = MaybeUninit::uninit();
        let mut ctrl = MaybeUninit::<wmr_lyapunov_controller_f64>::uninit();
        wmr_wheel_stage_params_f64_default(dp.as_ptr(), robot.as_ptr(), wp.as_mut_ptr());
        wmr_lyapunov_params_f64_default(lp.as_mut_ptr());
        assert_eq!(
            wmr_lyapunov_controller_f64_init(
                ctrl.as_mut_ptr(),
                lp.as_ptr(),
                wp.as_ptr(),
                robot.as_ptr(),
                drive.as_ptr(),
                DT,
                null
            ),
            wmr_status::WMR_OK
        );
        if for_plant {
            assert_eq!(wmr_lyapunov_controller_f64_for_plant(ctrl.as_mut_ptr(), plant.as_ptr()), wmr_status::WMR_OK);
        }
        let goal = wmr_pose { x: GOAL.x, y: GOAL.y, theta: GOAL.theta };
        let mut m = wmr_measurement::default();
        let mut out = wmr_control_output::default();
        for k in 0..=STEPS {
            let t = k as f64 * DT;
            assert_eq!(wmr_sensor_f64_measure(sensor.as_mut_ptr(), t, plant.as_ptr(), &mut m), wmr_status::WMR_OK);
            assert_eq!(
                wmr_lyapunov_controller_f64_update(ctrl.as_mut_ptr(), t, &m, goal, &mut out),
                wmr_status::WMR_OK
            );
            assert_eq!(wmr_plant_f64_apply(plant.as_mut_ptr(), out.command), wmr_status::WMR_OK);
            if k == STEPS {
                break;
            }
            assert_eq!(wmr_plant_f64_step(plant.as_mut_ptr(), t, DT), wmr_status::WMR_OK);
        }
        let mut s = MaybeUninit::<wmr_state<f64>>::uninit();
        assert_eq!(wmr_plant_f64_state(plant.as_ptr(), s.as_mut_ptr()), wmr_status::WMR_OK);
        let s = s.assume_init();
        assert_eq!(wmr_sensor_f64_odometry(sensor.as_ptr(), est.as_mut_ptr()), wmr_status::WMR_OK);
        let e = est.assume_init();
        let d = e.dead_reckoning;
        End { pose: [s.x, s.y, s.theta], odometry: [d.x, d.y, d.theta], covariance: e.covariance }
    }
}

/// The same run through the core's `ClosedLoop` (which fits the controller to its plant).
fn core_loop() -> End {
    let robot = Robot::<f64>::paper();
    let drive_params = DriveParams::DcMotor(DcMotorParams::default());
    let drive = drive_params.validate(&robot).unwrap();
    let world = WorldParams::default().validate().unwrap();
    let traction = traction_params().validate(&robot, &world).unwrap();
    let plant = Plant::on(robot, drive, world, START).unwrap().with_traction(traction);
    let sensor = AnySensor::new(sensor_params(), odometry_params(), robot.params(), DT, 3).unwrap();
    let law = LawParams::Lyapunov(LyapunovParams::default()).build(robot.params(), DT).unwrap();
    let wheels =
        WheelStage::new(&WheelStageParams::for_drive(&drive_params, robot.params()), robot.params(), &drive, DT)
            .unwrap();
    let goal = FixedGoal::new(GOAL).unwrap();
    let mut sim = ClosedLoop::with_sensor(plant, sensor, Controller::new(law, wheels), goal, DT).unwrap();
    for _ in 0..STEPS {
        sim.step().unwrap();
    }
    let p = sim.state().pose();
    let AnySensor::Odometry(odo) = sim.sensor() else { panic!("an odometry sensor") };
    let d = odo.dead_reckoning().unwrap();
    let c = odo.covariance().unwrap();
    End {
        pose: [p.x, p.y, p.theta],
        odometry: [d.x, d.y, d.theta],
        covariance: [c[0], c[1], c[2]].concat().try_into().unwrap(),
    }
}

#[test]
fn a_c_loop_on_a_slip_plant_with_odometry_equals_closed_loop() {
    let core = core_loop();
    assert_eq!(c_loop(true), core);
    // The guard mattered here: without `_for_plant` the controller assumes rolling wheels
    // and the run differs (so the equality above checks the fitting, too).
    assert_ne!(c_loop(false).pose, core.pose);
    // And the wheels did slip: the dead reckoning is off the true pose.
    let drift = ((core.pose[0] - core.odometry[0]).powi(2) + (core.pose[1] - core.odometry[1]).powi(2)).sqrt();
    assert!(drift > 1e-3, "on ice the dead reckoning drifts from the true pose: {drift} m");
}

#[test]
fn traction_and_odometry_structs_are_refused_by_field_name() {
    let null = std::ptr::null_mut();
    // SAFETY: valid pointers; the struct fields are written as plain numbers (the u32 code
    // through a raw pointer, as C would write any uint32_t).
    unsafe {
        let mut rp = MaybeUninit::uninit();
        let mut robot = MaybeUninit::<wmr_robot_f64>::uninit();
        assert_eq!(wmr_robot_params_f64_paper(rp.as_mut_ptr()), wmr_status::WMR_OK);
        assert_eq!(wmr_robot_f64_init(robot.as_mut_ptr(), rp.as_ptr(), null), wmr_status::WMR_OK);
        let mut dp = MaybeUninit::uninit();
        let mut drive = MaybeUninit::<wmr_drive_f64>::uninit();
        assert_eq!(wmr_drive_params_f64_default(WMR_DRIVE_TORQUE, dp.as_mut_ptr()), wmr_status::WMR_OK);
        assert_eq!(wmr_drive_f64_init(drive.as_mut_ptr(), dp.as_ptr(), robot.as_ptr(), null), wmr_status::WMR_OK);
        let start = wmr_pose { x: 0.0, y: 0.0, theta: 0.0 };
        let mut plant = MaybeUninit::<wmr_plant_f64>::uninit();
        let plant_with = |tp: &wmr_traction_params<f64>, plant: *mut wmr_plant_f64| {
            let mut err = new_err();
            let code = wmr_plant_f64_init_traction(
                plant,
                robot.as_ptr(),
                drive.as_ptr(),
                std::ptr::null(),
                tp,
                start,
                &mut err,
            );
            (code, field(&err))
        };
        let mut tp = traction_params();
        std::ptr::addr_of_mut!(tp.traction).cast::<u32>().write(7);
        assert_eq!(plant_with(&tp, plant.as_mut_ptr()), (wmr_status::WMR_OUT_OF_RANGE, "traction".to_owned()));
        let tp = TractionParams { friction_coefficient: -0.1, ..traction_params() };
        assert_eq!(
            plant_with(&tp, plant.as_mut_ptr()),
            (wmr_status::WMR_NOT_POSITIVE, "friction_coefficient".to_owned())
        );
        let tp = TractionParams { com_height: 5.0, ..traction_params() }; // mu h = 0.5 m > |d|
        assert_eq!(plant_with(&tp, plant.as_mut_ptr()), (wmr_status::WMR_OUT_OF_RANGE, "com_height".to_owned()));
        // NULL traction is the rolling plant of `wmr_plant_f64_init`, bit for bit.
        let mut rolling = MaybeUninit::<wmr_plant_f64>::uninit();
        let code = wmr_plant_f64_init_traction(
            plant.as_mut_ptr(),
            robot.as_ptr(),
            drive.as_ptr(),
            std::ptr::null(),
            std::ptr::null(),
            start,
            null,
        );
        assert_eq!(code, wmr_status::WMR_OK);
        assert_eq!(
            wmr_plant_f64_init(rolling.as_mut_ptr(), robot.as_ptr(), drive.as_ptr(), std::ptr::null(), start, null),
            wmr_status::WMR_OK
        );
        // (Storage padding is not compared: the two step alike under the same command.)
        let command = wmr_wheels { right: 0.3, left: -0.1 };
        let mut states = [wmr_state::<f64>::default(); 2];
        for (p, s) in [plant.as_mut_ptr(), rolling.as_mut_ptr()].into_iter().zip(&mut states) {
            assert_eq!(wmr_plant_f64_apply(p, command), wmr_status::WMR_OK);
            for k in 0..500 {
                assert_eq!(wmr_plant_f64_step(p, k as f64 * DT, DT), wmr_status::WMR_OK);
            }
            assert_eq!(wmr_plant_f64_state(p, s), wmr_status::WMR_OK);
        }
        assert_eq!(states[0], states[1]);
        assert!(states[0].theta != 0.0, "the command turned the robot");

        let mut sensor = MaybeUninit::<wmr_sensor_f64>::uninit();
        let sensor_with = |op: &wmr_odometry_params<f64>, sp: &wmr_sensor_params<f64>, sensor: *mut wmr_sensor_f64| {
            let mut err = new_err();
            let code = wmr_sensor_f64_init_odometry(sensor, sp, op, robot.as_ptr(), DT, 0, &mut err);
            (code, field(&err))
        };
        let mut op = odometry_params();
        std::ptr::addr_of_mut!(op.pose).cast::<u32>().write(2);
        assert_eq!(
            sensor_with(&op, &sensor_params(), sensor.as_mut_ptr()),
            (wmr_status::WMR_OUT_OF_RANGE, "pose".to_owned())
        );
        let op = OdometryParams { odometry_noise: f64::NAN, ..odometry_params() };
        assert_eq!(sensor_with(&op, &sensor_params(), sensor.as_mut_ptr()).1, "odometry_noise");
        // A fix rate whose latency would overflow the C sensor's 16 samples in flight.
        let op = OdometryParams { fix_rate_hz: 500.0, ..odometry_params() };
        assert_eq!(
            sensor_with(&op, &sensor_params(), sensor.as_mut_ptr()),
            (wmr_status::WMR_OUT_OF_RANGE, "latency".to_owned())
        );
        // The perfect sensor has no odometry estimate.
        assert_eq!(wmr_sensor_f64_init_perfect(sensor.as_mut_ptr()), wmr_status::WMR_OK);
        let mut est = MaybeUninit::uninit();
        assert_eq!(wmr_sensor_f64_odometry(sensor.as_ptr(), est.as_mut_ptr()), wmr_status::WMR_OUT_OF_RANGE);
    }
}
