//! The tracking laws and references of the C API (wmr issue 23): a C-call loop of
//! Kanayama's law on the circle gives the scenario runner's samples (what the CLI's CSV
//! and Python carry) bit for bit; each new law's C loop equals the core's `ClosedLoop`
//! on its reference, in f64 and f32; `_update_reference` with `_state_at` equals
//! `_update_on` for the trajectory laws; bad references are refused by field.
#![allow(unsafe_code)]

use std::ffi::CStr;
use std::mem::MaybeUninit;

use wmr_core::reference::{FigureEight, Waypoints};
use wmr_core::{
    AnyReference, BacksteppingLaw, BacksteppingParams, ClosedLoop, Controller, DriveParams, KanayamaLaw,
    KanayamaParams, PerfectSensor, Plant, Pose2, PurePursuitLaw, PurePursuitParams, Robot, TorqueDriveParams,
    WheelStage, WheelStageParams, WorldParams,
};
use wmr_ffi::*;

fn field(e: &wmr_error) -> String {
    // SAFETY: `field` is NUL-terminated by the library.
    unsafe { CStr::from_ptr(e.field.as_ptr()) }.to_string_lossy().into_owned()
}

fn new_err() -> wmr_error {
    wmr_error { code: wmr_status::WMR_OK, value: 0.0, field: [0; WMR_FIELD_LEN], reason: [0; WMR_REASON_LEN] }
}

/// The robot, torque drive, wheel stage, plant at `start` and perfect sensor of the C API.
struct Rig {
    robot: wmr_robot_f64,
    drive: wmr_drive_f64,
    wheels: wmr_wheel_stage_params<f64>,
    plant: wmr_plant_f64,
    sensor: wmr_sensor_f64,
}

fn rig(start: Pose2<f64>) -> Rig {
    let null = std::ptr::null_mut();
    // SAFETY: valid pointers; every init checked.
    unsafe {
        let (mut rp, mut robot) = (MaybeUninit::uninit(), MaybeUninit::uninit());
        wmr_robot_params_f64_paper(rp.as_mut_ptr());
        assert_eq!(wmr_robot_f64_init(robot.as_mut_ptr(), rp.as_ptr(), null), wmr_status::WMR_OK);
        let (mut dp, mut drive) = (MaybeUninit::uninit(), MaybeUninit::uninit());
        wmr_drive_params_f64_default(WMR_DRIVE_TORQUE, dp.as_mut_ptr());
        assert_eq!(wmr_drive_f64_init(drive.as_mut_ptr(), dp.as_ptr(), robot.as_ptr(), null), wmr_status::WMR_OK);
        let mut wheels = MaybeUninit::uninit();
        wmr_wheel_stage_params_f64_default(dp.as_ptr(), robot.as_ptr(), wheels.as_mut_ptr());
        let (mut plant, mut sensor) = (MaybeUninit::uninit(), MaybeUninit::uninit());
        let s = wmr_pose { x: start.x, y: start.y, theta: start.theta };
        assert_eq!(
            wmr_plant_f64_init(plant.as_mut_ptr(), robot.as_ptr(), drive.as_ptr(), std::ptr::null(), s, null),
            wmr_status::WMR_OK
        );
        wmr_sensor_f64_init_perfect(sensor.as_mut_ptr());
        Rig {
            robot: robot.assume_init(),
            drive: drive.assume_init(),
            wheels: wheels.assume_init(),
            plant: plant.assume_init(),
            sensor: sensor.assume_init(),
        }
    }
}

/// One C-call step: measure, update on `reference` (the C object), apply, step. Returns
/// the control output.
macro_rules! c_tick {
    ($rig:expr, $update_on:ident, $ctrl:expr, $reference:expr, $t:expr, $dt:expr) => {{
        let mut m = wmr_measurement::default();
        let mut out = wmr_control_output::default();
        // SAFETY: valid, initialized storage.
        unsafe {
            assert_eq!(wmr_sensor_f64_measure(&mut $rig.sensor, $t, &$rig.plant, &mut m), wmr_status::WMR_OK);
            assert_eq!($update_on($ctrl, $t, &m, $reference, &mut out, std::ptr::null_mut()), wmr_status::WMR_OK);
            assert_eq!(wmr_plant_f64_apply(&mut $rig.plant, out.command), wmr_status::WMR_OK);
            assert_eq!(wmr_plant_f64_step(&mut $rig.plant, $t, $dt), wmr_status::WMR_OK);
        }
        out
    }};
}

fn state_bits(plant: &wmr_plant_f64) -> [u64; 7] {
    let mut st = wmr_state::default();
    // SAFETY: initialized plant.
    unsafe { wmr_plant_f64_state(plant, &mut st) };
    [st.x, st.y, st.theta, st.v, st.omega, st.phi_r, st.phi_l].map(f64::to_bits)
}

#[test]
fn circle_kanayama_c_loop_is_the_scenario_run_bit_for_bit() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/tracking/circle.toml");
    let text = wmr_scenario::read_text(std::path::Path::new(path)).unwrap();
    let sc = wmr_scenario::Scenario::from_toml_str(&text, "circle").unwrap();
    let mut samples = Vec::new();
    let result = sc.run(0, |s| samples.push(*s)).unwrap();
    assert!(result.converged());
    let run = sc.runs()[0].start;
    let sim = sc.sim();
    let (dt, every) = (sim.dt(), sim.log_every() as usize);
    let mut rig = rig(run);
    let null = std::ptr::null_mut();
    // SAFETY: valid pointers; every init checked.
    let (mut ctrl, reference) = unsafe {
        let mut lp = MaybeUninit::uninit();
        wmr_kanayama_params_f64_default(lp.as_mut_ptr());
        let mut ctrl = MaybeUninit::<wmr_kanayama_controller_f64>::uninit();
        assert_eq!(
            wmr_kanayama_controller_f64_init(
                ctrl.as_mut_ptr(),
                lp.as_ptr(),
                &rig.wheels,
                &rig.robot,
                &rig.drive,
                dt,
                null
            ),
            wmr_status::WMR_OK
        );
        // The file's keys: center (0, 0), radius 1 m, speed 0.3 m/s, phase -90 deg.
        let mut r = MaybeUninit::<wmr_reference_f64>::uninit();
        let center = wmr_pose { x: 0.0, y: 0.0, theta: 0.0 };
        assert_eq!(
            wmr_reference_f64_init_circle(r.as_mut_ptr(), center, 1.0, 0.3, (-90.0f64).to_radians(), null),
            wmr_status::WMR_OK
        );
        (ctrl.assume_init(), r.assume_init())
    };
    let clock = wmr_core::StepClock::new(dt);
    let mut outputs = Vec::new();
    for k in 0..sim.n_steps() as usize {
        let t = clock.time(k as u64);
        let out = c_tick!(rig, wmr_kanayama_controller_f64_update_on, &mut ctrl, &reference, t, dt);
        outputs.push(out);
        if (k + 1) % every == 0 {
            let s = &samples[(k + 1) / every];
            let want = [s.state.x, s.state.y, s.state.theta, s.state.v, s.state.omega, s.state.phi_r, s.state.phi_l];
            assert_eq!(state_bits(&rig.plant), want.map(f64::to_bits), "step {k}");
            // The reference columns (x_ref ... omega_ref) are the C reference's state.
            let mut r = wmr_reference_state::default();
            // SAFETY: initialized reference.
            unsafe { assert_eq!(wmr_reference_f64_state_at(&reference, s.t, &mut r), wmr_status::WMR_OK) };
            let want = wmr_scenario::reference_values(&sc.tracking().unwrap().reference.built.state_at_t(s.t));
            assert_eq!([r.pose.x, r.pose.y, r.pose.theta, r.twist.v, r.twist.omega], want, "reference at {}", s.t);
        }
    }
    assert_eq!(samples.len(), sim.n_steps() as usize / every + 1);
    // A sample's errors are the law's at the tick at the sample's time (the loop ticks
    // right after the step that reaches it): tick j * every.
    for (j, s) in samples.iter().enumerate() {
        let Some(o) = outputs.get(j * every) else { continue };
        let got = [o.e_s, o.e_theta, o.dl].map(f64::to_bits);
        assert_eq!(got, [s.errors.e_s, s.errors.e_theta, s.errors.dl].map(f64::to_bits), "errors of sample {j}");
    }
}

/// `state_at` spelled for the test (the trait method, by name).
trait StateAt {
    fn state_at_t(&self, t: f64) -> wmr_core::ReferenceState<f64>;
}
impl<S: AsRef<[f64]>> StateAt for AnyReference<f64, S> {
    fn state_at_t(&self, t: f64) -> wmr_core::ReferenceState<f64> {
        wmr_core::Reference::state_at(self, t)
    }
}

/// The C loop of a trajectory law on a C reference against `ClosedLoop` on the core's.
macro_rules! law_on_reference {
    ($name:ident, $default:ident, $init:ident, $update_on:ident, $update_ref:ident, $storage:ty, $law:expr, $steps:expr,
     c_ref = |$r:ident| $c_ref:expr, core_ref = $core_ref:expr, start = $start:expr) => {
        #[test]
        fn $name() {
            let dt = 1e-3;
            let start: Pose2<f64> = $start;
            let mut rig = rig(start);
            let null = std::ptr::null_mut();
            // SAFETY: valid pointers; every init checked.
            let (mut ctrl, mut twin, reference) = unsafe {
                let mut lp = MaybeUninit::uninit();
                $default(lp.as_mut_ptr());
                let (mut a, mut b) = (MaybeUninit::<$storage>::uninit(), MaybeUninit::<$storage>::uninit());
                for c in [a.as_mut_ptr(), b.as_mut_ptr()] {
                    assert_eq!(
                        $init(c, lp.as_ptr(), &rig.wheels, &rig.robot, &rig.drive, dt, null),
                        wmr_status::WMR_OK
                    );
                }
                let mut $r = MaybeUninit::<wmr_reference_f64>::uninit();
                assert_eq!($c_ref, wmr_status::WMR_OK);
                (a.assume_init(), b.assume_init(), $r.assume_init())
            };
            let robot = Robot::<f64>::paper();
            let drive_params = DriveParams::Torque(TorqueDriveParams::default());
            let drive = drive_params.validate(&robot).unwrap();
            let wheels = WheelStage::new(
                &WheelStageParams::for_drive(&drive_params, robot.params()),
                robot.params(),
                &drive,
                dt,
            )
            .unwrap();
            let plant = Plant::on(robot, drive, WorldParams::default().validate().unwrap(), start).unwrap();
            let core_ref: AnyReference<f64> = $core_ref;
            let mut sim =
                ClosedLoop::with_sensor(plant, PerfectSensor, Controller::new($law, wheels), core_ref, dt).unwrap();
            let clock = wmr_core::StepClock::new(dt);
            let mut moved = 0.0f64;
            for k in 0..$steps {
                let t = clock.time(k);
                // The trajectory laws read only the reference's state: `_update_reference`
                // given `_state_at` is `_update_on`, bit for bit.
                let mut m = wmr_measurement::default();
                let mut r = wmr_reference_state::default();
                let mut o = wmr_control_output::default();
                // SAFETY: initialized storage.
                unsafe {
                    assert_eq!(wmr_sensor_f64_measure(&mut rig.sensor, t, &rig.plant, &mut m), wmr_status::WMR_OK);
                    assert_eq!(wmr_reference_f64_state_at(&reference, t, &mut r), wmr_status::WMR_OK);
                    assert_eq!($update_ref(&mut twin, t, &m, &r, &mut o, null), wmr_status::WMR_OK);
                }
                let out = c_tick!(rig, $update_on, &mut ctrl, &reference, t, dt);
                assert_eq!(out, o, "tick {k}: _update_reference(_state_at) differs from _update_on");
                sim.step().unwrap();
                let s = sim.state();
                let want = [s.x, s.y, s.theta, s.v, s.omega, s.phi_r, s.phi_l];
                assert_eq!(state_bits(&rig.plant), want.map(f64::to_bits), "step {k}");
                moved = moved.max((s.x - start.x).hypot(s.y - start.y));
            }
            assert!(moved > 0.05, "the robot moved {moved} m");
        }
    };
}

const EIGHT: [f64; 5] = [0.1, -0.2, 2.0, 1.0, 30.0];

law_on_reference!(
    kanayama_on_figure_eight_is_closed_loop,
    wmr_kanayama_params_f64_default,
    wmr_kanayama_controller_f64_init,
    wmr_kanayama_controller_f64_update_on,
    wmr_kanayama_controller_f64_update_reference,
    wmr_kanayama_controller_f64,
    KanayamaLaw::for_lanes(KanayamaParams::default()).unwrap(),
    6_000,
    c_ref = |r| wmr_reference_f64_init_figure_eight(
        r.as_mut_ptr(),
        wmr_pose { x: EIGHT[0], y: EIGHT[1], theta: 0.0 },
        EIGHT[2],
        EIGHT[3],
        EIGHT[4],
        std::ptr::null_mut()
    ),
    core_ref = AnyReference::FigureEight(FigureEight::new(EIGHT[0], EIGHT[1], EIGHT[2], EIGHT[3], EIGHT[4]).unwrap()),
    start = Pose2::new(0.15, -0.3, 0.4)
);

law_on_reference!(
    backstepping_on_figure_eight_is_closed_loop,
    wmr_backstepping_params_f64_default,
    wmr_backstepping_controller_f64_init,
    wmr_backstepping_controller_f64_update_on,
    wmr_backstepping_controller_f64_update_reference,
    wmr_backstepping_controller_f64,
    BacksteppingLaw::for_lanes(BacksteppingParams::default(), Robot::<f64>::paper().params(), 1e-3).unwrap(),
    6_000,
    c_ref = |r| wmr_reference_f64_init_figure_eight(
        r.as_mut_ptr(),
        wmr_pose { x: EIGHT[0], y: EIGHT[1], theta: 0.0 },
        EIGHT[2],
        EIGHT[3],
        EIGHT[4],
        std::ptr::null_mut()
    ),
    core_ref = AnyReference::FigureEight(FigureEight::new(EIGHT[0], EIGHT[1], EIGHT[2], EIGHT[3], EIGHT[4]).unwrap()),
    start = Pose2::new(0.15, -0.3, 0.4)
);

const POINTS: [[f64; 2]; 4] = [[0.0, 0.0], [1.0, 0.2], [1.5, 1.0], [0.5, 1.5]];

#[test]
fn pure_pursuit_on_waypoints_is_closed_loop() {
    // `_update` and `_update_reference` give no path: the path follower refuses them
    // (naming `reference`) instead of answering a zero command; `_update_on` is compared
    // with the core.
    let dt = 1e-3;
    let start = Pose2::new(0.0, 0.05, 0.1);
    let mut rig = rig(start);
    let null = std::ptr::null_mut();
    // SAFETY: valid pointers; every init checked.
    let (mut ctrl, reference) = unsafe {
        let mut lp = MaybeUninit::uninit();
        wmr_pure_pursuit_params_f64_default(lp.as_mut_ptr());
        let mut a = MaybeUninit::<wmr_pure_pursuit_controller_f64>::uninit();
        assert_eq!(
            wmr_pure_pursuit_controller_f64_init(
                a.as_mut_ptr(),
                lp.as_ptr(),
                &rig.wheels,
                &rig.robot,
                &rig.drive,
                dt,
                null
            ),
            wmr_status::WMR_OK
        );
        let mut r = MaybeUninit::<wmr_reference_f64>::uninit();
        assert_eq!(
            wmr_reference_f64_init_waypoints(r.as_mut_ptr(), POINTS.as_ptr(), POINTS.len(), 0.3, 0.5, null),
            wmr_status::WMR_OK
        );
        (a.assume_init(), r.assume_init())
    };
    // SAFETY: valid, initialized storage.
    unsafe {
        let mut m = wmr_measurement::default();
        assert_eq!(wmr_sensor_f64_measure(&mut rig.sensor, 0.0, &rig.plant, &mut m), wmr_status::WMR_OK);
        let (mut out, mut err) = (wmr_control_output::default(), new_err());
        let before = std::mem::transmute_copy::<_, [u8; std::mem::size_of::<wmr_pure_pursuit_controller_f64>()]>(&ctrl);
        let goal = wmr_pose { x: 1.0, y: 0.0, theta: 0.0 };
        assert_eq!(
            wmr_pure_pursuit_controller_f64_update(&mut ctrl, 0.0, &m, goal, &mut out),
            wmr_status::WMR_OUT_OF_RANGE
        );
        let state = wmr_reference_state::default();
        assert_eq!(
            wmr_pure_pursuit_controller_f64_update_reference(&mut ctrl, 0.0, &m, &state, &mut out, &mut err),
            wmr_status::WMR_OUT_OF_RANGE
        );
        assert_eq!(field(&err), "reference");
        let after = std::mem::transmute_copy::<_, [u8; std::mem::size_of::<wmr_pure_pursuit_controller_f64>()]>(&ctrl);
        assert_eq!(before, after, "a refused update leaves the controller as it was");
    }
    let robot = Robot::<f64>::paper();
    let drive_params = DriveParams::Torque(TorqueDriveParams::default());
    let drive = drive_params.validate(&robot).unwrap();
    let wheels =
        WheelStage::new(&WheelStageParams::for_drive(&drive_params, robot.params()), robot.params(), &drive, dt)
            .unwrap();
    let plant = Plant::on(robot, drive, WorldParams::default().validate().unwrap(), start).unwrap();
    let law = PurePursuitLaw::for_lanes(PurePursuitParams::default(), robot.params(), dt).unwrap();
    let core_ref = AnyReference::Waypoints(Waypoints::new(&POINTS, 0.3, 0.5).unwrap());
    let mut sim = ClosedLoop::with_sensor(plant, PerfectSensor, Controller::new(law, wheels), core_ref, dt).unwrap();
    let clock = wmr_core::StepClock::new(dt);
    for k in 0..8_000 {
        let t = clock.time(k);
        c_tick!(rig, wmr_pure_pursuit_controller_f64_update_on, &mut ctrl, &reference, t, dt);
        sim.step().unwrap();
        let s = sim.state();
        let want = [s.x, s.y, s.theta, s.v, s.omega, s.phi_r, s.phi_l];
        assert_eq!(state_bits(&rig.plant), want.map(f64::to_bits), "step {k}");
    }
    let s = sim.state();
    assert!((s.x - start.x).hypot(s.y - start.y) > 0.5, "the robot followed the path");
}

#[test]
fn f32_kanayama_on_a_line_follows_it() {
    // The f32 flavour: the reference's state in f32 is the core's f32 state, bit for bit,
    // and the law converges onto the line.
    let null = std::ptr::null_mut();
    // SAFETY: valid pointers; every init checked.
    unsafe {
        let mut r = MaybeUninit::<wmr_reference_f32>::uninit();
        let start = wmr_pose { x: 0.1f32, y: -0.2, theta: 0.3 };
        assert_eq!(wmr_reference_f32_init_line(r.as_mut_ptr(), start, 0.25, null), wmr_status::WMR_OK);
        let core = wmr_core::reference::Line::new(Pose2::new(0.1f32, -0.2, 0.3), 0.25).unwrap();
        for t in [0.0f32, 0.37, 5.0, 123.25] {
            let mut s = wmr_reference_state::default();
            assert_eq!(wmr_reference_f32_state_at(r.as_ptr(), t, &mut s), wmr_status::WMR_OK);
            let c = wmr_core::Reference::state_at(&core, t);
            assert_eq!(
                [s.pose.x, s.pose.y, s.pose.theta, s.twist.v, s.twist.omega].map(f32::to_bits),
                [c.pose.x, c.pose.y, c.pose.theta, c.twist.v, c.twist.omega].map(f32::to_bits)
            );
        }
        let (mut rp, mut robot) = (MaybeUninit::uninit(), MaybeUninit::uninit());
        wmr_robot_params_f32_paper(rp.as_mut_ptr());
        assert_eq!(wmr_robot_f32_init(robot.as_mut_ptr(), rp.as_ptr(), null), wmr_status::WMR_OK);
        let (mut dp, mut drive) = (MaybeUninit::uninit(), MaybeUninit::uninit());
        wmr_drive_params_f32_default(WMR_DRIVE_TORQUE, dp.as_mut_ptr());
        assert_eq!(wmr_drive_f32_init(drive.as_mut_ptr(), dp.as_ptr(), robot.as_ptr(), null), wmr_status::WMR_OK);
        let (mut wp, mut lp) = (MaybeUninit::uninit(), MaybeUninit::uninit());
        wmr_wheel_stage_params_f32_default(dp.as_ptr(), robot.as_ptr(), wp.as_mut_ptr());
        wmr_kanayama_params_f32_default(lp.as_mut_ptr());
        let mut ctrl = MaybeUninit::<wmr_kanayama_controller_f32>::uninit();
        assert_eq!(
            wmr_kanayama_controller_f32_init(
                ctrl.as_mut_ptr(),
                lp.as_ptr(),
                wp.as_ptr(),
                robot.as_ptr(),
                drive.as_ptr(),
                1e-3,
                null
            ),
            wmr_status::WMR_OK
        );
        let (mut plant, mut sensor) = (MaybeUninit::uninit(), MaybeUninit::uninit());
        let p0 = wmr_pose { x: 0.0f32, y: 0.0, theta: 0.0 };
        assert_eq!(
            wmr_plant_f32_init(plant.as_mut_ptr(), robot.as_ptr(), drive.as_ptr(), std::ptr::null(), p0, null),
            wmr_status::WMR_OK
        );
        wmr_sensor_f32_init_perfect(sensor.as_mut_ptr());
        let mut m = wmr_measurement::default();
        let mut out = wmr_control_output::default();
        let n = 10_000u64;
        for k in 0..n {
            let t = wmr_core::StepClock::new(1e-3f32).time(k);
            assert_eq!(wmr_sensor_f32_measure(sensor.as_mut_ptr(), t, plant.as_ptr(), &mut m), wmr_status::WMR_OK);
            assert_eq!(
                wmr_kanayama_controller_f32_update_on(ctrl.as_mut_ptr(), t, &m, r.as_ptr(), &mut out, null),
                wmr_status::WMR_OK
            );
            assert_eq!(wmr_plant_f32_apply(plant.as_mut_ptr(), out.command), wmr_status::WMR_OK);
            assert_eq!(wmr_plant_f32_step(plant.as_mut_ptr(), t, 1e-3), wmr_status::WMR_OK);
        }
        let mut st = wmr_state::default();
        wmr_plant_f32_state(plant.as_ptr(), &mut st);
        let c = wmr_core::Reference::state_at(&core, 10.0f32);
        assert!((st.x - c.pose.x).hypot(st.y - c.pose.y) < 0.01, "{st:?} vs {c:?}");
    }
}

#[test]
fn bad_references_are_refused_by_field() {
    let mut e = new_err();
    let c = wmr_pose { x: 0.0, y: 0.0, theta: 0.0 };
    // SAFETY: valid or deliberately NULL pointers, as the contract allows.
    unsafe {
        let mut r = MaybeUninit::<wmr_reference_f64>::uninit();
        assert_eq!(
            wmr_reference_f64_init_circle(r.as_mut_ptr(), c, -1.0, 0.3, 0.0, &mut e),
            wmr_status::WMR_NOT_POSITIVE
        );
        assert_eq!(field(&e), "radius");
        assert_eq!(
            wmr_reference_f64_init_figure_eight(r.as_mut_ptr(), c, 1.0, f64::NAN, 1.0, &mut e),
            wmr_status::WMR_NOT_FINITE
        );
        assert_eq!(field(&e), "height");
        let far = wmr_pose { x: 2000.0, ..c };
        assert_eq!(wmr_reference_f64_init_line(r.as_mut_ptr(), far, 0.3, &mut e), wmr_status::WMR_OUT_OF_RANGE);
        assert_eq!(field(&e), "start.x");
        let one = [[0.0, 0.0]];
        assert_ne!(
            wmr_reference_f64_init_waypoints(r.as_mut_ptr(), one.as_ptr(), 1, 0.3, 0.5, &mut e),
            wmr_status::WMR_OK
        );
        assert_eq!(field(&e), "points");
        let many = [[0.0f64, 0.0]; 65];
        assert_eq!(
            wmr_reference_f64_init_waypoints(r.as_mut_ptr(), many.as_ptr(), 65, 0.3, 0.5, &mut e),
            wmr_status::WMR_OUT_OF_RANGE
        );
        assert_eq!(field(&e), "n");
        assert_eq!(
            wmr_reference_f64_init_waypoints(r.as_mut_ptr(), std::ptr::null(), 2, 0.3, 0.5, &mut e),
            wmr_status::WMR_NULL_POINTER
        );
        assert_eq!(field(&e), "points");
        // Storage no init filled, and NULL, are refused by the argument's name.
        let blank = std::mem::zeroed::<wmr_reference_f64>();
        let mut s = wmr_reference_state::default();
        assert_eq!(wmr_reference_f64_state_at(&blank, 0.0, &mut s), wmr_status::WMR_NOT_INITIALIZED);
        assert_eq!(wmr_reference_f64_state_at(std::ptr::null(), 0.0, &mut s), wmr_status::WMR_NULL_POINTER);
        assert_eq!(wmr_reference_f64_init_circle(r.as_mut_ptr(), c, 1.0, 0.3, 0.0, &mut e), wmr_status::WMR_OK);
        assert_eq!(wmr_reference_f64_state_at(r.as_ptr(), f64::NAN, &mut s), wmr_status::WMR_NOT_FINITE);
        let mut rig = rig(Pose2::new(0.0, -1.0, 0.0));
        let mut lp = MaybeUninit::uninit();
        wmr_kanayama_params_f64_default(lp.as_mut_ptr());
        let mut ctrl = MaybeUninit::<wmr_kanayama_controller_f64>::uninit();
        assert_eq!(
            wmr_kanayama_controller_f64_init(
                ctrl.as_mut_ptr(),
                lp.as_ptr(),
                &rig.wheels,
                &rig.robot,
                &rig.drive,
                1e-3,
                &mut e
            ),
            wmr_status::WMR_OK
        );
        let mut m = wmr_measurement::default();
        wmr_sensor_f64_measure(&mut rig.sensor, 0.0, &rig.plant, &mut m);
        let mut out = wmr_control_output::default();
        assert_eq!(
            wmr_kanayama_controller_f64_update_on(ctrl.as_mut_ptr(), 0.0, &m, &blank, &mut out, &mut e),
            wmr_status::WMR_NOT_INITIALIZED
        );
        assert_eq!(field(&e), "reference");
        // Gains are the core's checks.
        let mut bad = lp.assume_init();
        bad.ky = -1.0;
        assert_eq!(
            wmr_kanayama_controller_f64_init(
                ctrl.as_mut_ptr(),
                &bad,
                &rig.wheels,
                &rig.robot,
                &rig.drive,
                1e-3,
                &mut e
            ),
            wmr_status::WMR_NOT_POSITIVE
        );
        assert_eq!(field(&e), "ky");
    }
}

/// Issue 39 item 5: a figure-eight whose keys are each valid but whose state is not finite
/// (omega_ref = 0/0 from a squared speed that underflows, or inf from one that overflows)
/// is refused at init by the key to blame, in f64 and f32 as on the scenario path; before,
/// init returned WMR_OK and every state_at failed.
#[test]
fn regression_39_5_a_figure_eight_whose_state_is_not_finite_is_refused_at_init() {
    let mut e = new_err();
    let c = wmr_pose { x: 0.0, y: 0.0, theta: 0.0 };
    let cases: [(f64, f64, f64, &str); 4] = [
        (2.0, 1.0, 1e300, "period"),
        (2.0, 1.0, 1e-300, "period"),
        (1e-300, 1e-300, 30.0, "width"),
        (1e-300, 1e-301, 30.0, "height"),
    ];
    // SAFETY: valid pointers.
    unsafe {
        for (w, h, p, key) in cases {
            let mut r = MaybeUninit::<wmr_reference_f64>::uninit();
            let status = wmr_reference_f64_init_figure_eight(r.as_mut_ptr(), c, w, h, p, &mut e);
            assert_eq!(status, wmr_status::WMR_OUT_OF_RANGE, "{w} {h} {p}");
            assert_eq!(field(&e), key, "{w} {h} {p}");
        }
        // Fine in f64, not in f32: (2 pi / 1e25)^2 underflows f32.
        let mut r = MaybeUninit::<wmr_reference_f64>::uninit();
        assert_eq!(wmr_reference_f64_init_figure_eight(r.as_mut_ptr(), c, 2.0, 1.0, 1e25, &mut e), wmr_status::WMR_OK);
        let c32 = wmr_pose { x: 0.0f32, y: 0.0, theta: 0.0 };
        let mut r = MaybeUninit::<wmr_reference_f32>::uninit();
        let status = wmr_reference_f32_init_figure_eight(r.as_mut_ptr(), c32, 2.0, 1.0, 1e25, &mut e);
        assert_eq!(status, wmr_status::WMR_OUT_OF_RANGE);
        assert_eq!(field(&e), "period");
    }
}

/// Issue 38 item 9: a recorded path of 2,000 points in storage the C caller owns gives
/// the bits of the core's path in a Rust `Vec` (the scenario's storage), and drives the
/// pure pursuit law through `_update_on` as the core's loop does.
#[test]
fn regression_38_9_a_recorded_path_of_2000_points_in_caller_storage() {
    let points: Vec<[f64; 2]> = (0..2000)
        .map(|i| {
            let a = i as f64 * 1.5 * std::f64::consts::PI / 1999.0;
            [2.0 * a.cos(), 2.0 * a.sin()]
        })
        .collect();
    let null = std::ptr::null_mut();
    // SAFETY: valid pointers; `storage` outlives the reference.
    let words = wmr_reference_f64_waypoints_words(points.len());
    let mut storage = vec![0.0f64; words];
    let reference = unsafe {
        let mut r = MaybeUninit::<wmr_reference_f64>::uninit();
        assert_eq!(
            wmr_reference_f64_init_waypoints_in(
                r.as_mut_ptr(),
                points.as_ptr(),
                points.len(),
                0.3,
                0.5,
                storage.as_mut_ptr(),
                words,
                null
            ),
            wmr_status::WMR_OK
        );
        r.assume_init()
    };
    let core = Waypoints::new_in(&points, 0.3, 0.5, vec![0.0; words]).unwrap();
    for k in 0..400 {
        let t = k as f64 * 0.1;
        let mut r = wmr_reference_state::default();
        // SAFETY: initialized reference, its storage alive.
        unsafe { assert_eq!(wmr_reference_f64_state_at(&reference, t, &mut r), wmr_status::WMR_OK) };
        let c = wmr_core::Reference::state_at(&core, t);
        assert_eq!(
            [r.pose.x, r.pose.y, r.pose.theta, r.twist.v, r.twist.omega, r.accel.v, r.accel.omega].map(f64::to_bits),
            [c.pose.x, c.pose.y, c.pose.theta, c.twist.v, c.twist.omega, c.accel.v, c.accel.omega].map(f64::to_bits),
            "t = {t}"
        );
    }
    // The reference's own storage holds 64 (the firmware's capacity) and says what to do.
    let mut e = MaybeUninit::<wmr_error>::uninit();
    let mut r = MaybeUninit::<wmr_reference_f64>::uninit();
    // SAFETY: valid pointers.
    let code = unsafe {
        wmr_reference_f64_init_waypoints(r.as_mut_ptr(), points.as_ptr(), points.len(), 0.3, 0.5, e.as_mut_ptr())
    };
    assert_eq!(code, wmr_status::WMR_OUT_OF_RANGE);
    // SAFETY: the call wrote the error.
    let e = unsafe { e.assume_init() };
    let reason = unsafe { std::ffi::CStr::from_ptr(e.reason.as_ptr()) }.to_string_lossy().into_owned();
    assert!(reason.contains("64") && reason.contains("_init_waypoints_in"), "{reason}");
}

/// Issue 39 item 14: a circle of radius 1e300 and a line at 1e300 m/s around a centre
/// inside the box returned `WMR_OK`, then poses of 1e300 m. The circle and the
/// figure-eight are refused at init by the key that takes them out of the 1 km box; a
/// state outside it is refused by `_state_at`, `out` untouched (a line's reach depends
/// on the time asked).
#[test]
fn regression_39_14_references_stay_inside_the_box_in_c() {
    let mut e = new_err();
    let c = wmr_pose { x: 0.0, y: 0.0, theta: 0.0 };
    // SAFETY: valid pointers throughout.
    unsafe {
        let mut r = MaybeUninit::<wmr_reference_f64>::uninit();
        let status = wmr_reference_f64_init_circle(r.as_mut_ptr(), c, 1e300, 0.3, 0.0, &mut e);
        assert_eq!(status, wmr_status::WMR_OUT_OF_RANGE);
        assert_eq!(field(&e), "radius");
        let near = wmr_pose { x: 999.0, y: 0.0, theta: 0.0 };
        let status = wmr_reference_f64_init_circle(r.as_mut_ptr(), near, 2.0, 0.3, 0.0, &mut e);
        assert_eq!(status, wmr_status::WMR_OUT_OF_RANGE);
        assert_eq!(field(&e), "radius");
        for (w, h, key) in [(1e300, 1.0, "width"), (2.0, 1e300, "height")] {
            let status = wmr_reference_f64_init_figure_eight(r.as_mut_ptr(), c, w, h, 30.0, &mut e);
            assert_eq!(status, wmr_status::WMR_OUT_OF_RANGE, "{key}");
            assert_eq!(field(&e), key);
        }
        // Inside the box: accepted, as before.
        assert_eq!(wmr_reference_f64_init_circle(r.as_mut_ptr(), c, 1.0, 0.3, 0.0, &mut e), wmr_status::WMR_OK);
        let mut f = MaybeUninit::<wmr_reference_f32>::uninit();
        let c32 = wmr_pose { x: 0.0f32, y: 0.0, theta: 0.0 };
        let status = wmr_reference_f32_init_circle(f.as_mut_ptr(), c32, 1e30, 0.3, 0.0, &mut e);
        assert_eq!(status, wmr_status::WMR_OUT_OF_RANGE);
        assert_eq!(field(&e), "radius");
        // A line at 1e300 m/s: its start is in the box, its state at t = 1 s is not.
        assert_eq!(wmr_reference_f64_init_line(r.as_mut_ptr(), c, 1e300, &mut e), wmr_status::WMR_OK);
        let r = r.assume_init();
        let mut s = wmr_reference_state::default();
        assert_eq!(wmr_reference_f64_state_at(&r, 0.0, &mut s), wmr_status::WMR_OK);
        let before = s;
        assert_eq!(wmr_reference_f64_state_at(&r, 1.0, &mut s), wmr_status::WMR_OUT_OF_RANGE);
        assert_eq!(s.pose.x.to_bits(), before.pose.x.to_bits(), "out untouched");
    }
}
