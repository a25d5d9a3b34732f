//! Issue 25 (the C API's boundary), one test per reproducer (`issue25_N_...`): what the
//! C API accepted that it must refuse, with the code the header documents.
//! Issue: wmr issue 25, items 1 (non-finite and out-of-range input and output) and 10
//! (misaligned and overwritten storage).
#![allow(unsafe_code)]

use std::ffi::CStr;
use std::mem::MaybeUninit;

use wmr_ffi::*;

fn new_err() -> wmr_error {
    wmr_error { code: wmr_status::WMR_OK, value: 0.0, field: [0; WMR_FIELD_LEN], reason: [0; WMR_REASON_LEN] }
}

fn field(e: &wmr_error) -> String {
    // SAFETY: the library NUL-terminates `field`.
    unsafe { CStr::from_ptr(e.field.as_ptr()) }.to_str().expect("ASCII").to_owned()
}

/// A robot, a torque drive and a plant at rest at `start`, in precision `$t`.
macro_rules! plant_setup {
    ($t:ty, $robot_params:ident, $robot_init:ident, $drive_default:ident, $drive_init:ident, $plant_init:ident,
     $robot:ty, $drive:ty, $plant:ty) => {{
        let null = std::ptr::null_mut();
        let mut rp = MaybeUninit::uninit();
        let mut robot = Box::new(MaybeUninit::<$robot>::uninit());
        let mut dp = MaybeUninit::uninit();
        let mut drive = Box::new(MaybeUninit::<$drive>::uninit());
        let mut plant = Box::new(MaybeUninit::<$plant>::uninit());
        // SAFETY: valid pointers; every init checked.
        unsafe {
            assert_eq!($robot_params(rp.as_mut_ptr()), wmr_status::WMR_OK);
            assert_eq!($robot_init(robot.as_mut_ptr(), rp.as_ptr(), null), wmr_status::WMR_OK);
            assert_eq!($drive_default(WMR_DRIVE_TORQUE, dp.as_mut_ptr()), wmr_status::WMR_OK);
            assert_eq!($drive_init(drive.as_mut_ptr(), dp.as_ptr(), robot.as_ptr(), null), wmr_status::WMR_OK);
            let start = wmr_pose::<$t> { x: 0.0, y: 0.0, theta: 0.0 };
            assert_eq!(
                $plant_init(plant.as_mut_ptr(), robot.as_ptr(), drive.as_ptr(), std::ptr::null(), start, null),
                wmr_status::WMR_OK
            );
            (*robot.assume_init(), *drive.assume_init(), plant.assume_init())
        }
    }};
}

/// Item 1: `apply({NaN, NaN})` returned WMR_OK and the drive's clamp
/// `x.max(-lim).min(lim)` made NaN full reverse torque: v = -7.407 m/s after 1 s. Now
/// refused, the held command (zero) kept: from rest on flat ground without a torque the
/// robot stays at rest, exactly (every derivative is 0).
macro_rules! nan_command_is_refused {
    ($name:ident, $t:ty, $robot_params:ident, $robot_init:ident, $drive_default:ident, $drive_init:ident,
     $plant_init:ident, $apply:ident, $step:ident, $state:ident, $robot:ty, $drive:ty, $plant:ty) => {
        #[test]
        fn $name() {
            let (_robot, _drive, mut plant) = plant_setup!(
                $t,
                $robot_params,
                $robot_init,
                $drive_default,
                $drive_init,
                $plant_init,
                $robot,
                $drive,
                $plant
            );
            let dt: $t = 1e-3;
            // SAFETY: valid pointers.
            unsafe {
                for bad in [
                    wmr_wheels { right: <$t>::NAN, left: <$t>::NAN },
                    wmr_wheels { right: 0.0, left: <$t>::NAN },
                    wmr_wheels { right: <$t>::INFINITY, left: 0.0 },
                ] {
                    assert_eq!($apply(&mut *plant, bad), wmr_status::WMR_NOT_FINITE);
                }
                for k in 0..1000 {
                    assert_eq!($step(&mut *plant, k as $t * dt, dt), wmr_status::WMR_OK);
                }
                let mut s = wmr_state::default();
                assert_eq!($state(&*plant, &mut s), wmr_status::WMR_OK);
                assert_eq!(s, wmr_state::default(), "the robot moved under a refused command");
                // A step of zero, of negative or of non-finite time is no step of the model.
                assert_eq!($step(&mut *plant, 1.0, 0.0), wmr_status::WMR_NOT_POSITIVE);
                assert_eq!($step(&mut *plant, 1.0, -dt), wmr_status::WMR_NOT_POSITIVE);
                assert_eq!($step(&mut *plant, 1.0, <$t>::INFINITY), wmr_status::WMR_NOT_FINITE);
                assert_eq!($step(&mut *plant, <$t>::NAN, dt), wmr_status::WMR_NOT_FINITE);
                // Torque held: the robot moves forward, and a refused step leaves it so.
                assert_eq!($apply(&mut *plant, wmr_wheels { right: 0.1, left: 0.1 }), wmr_status::WMR_OK);
                assert_eq!($step(&mut *plant, 1.0, dt), wmr_status::WMR_OK);
                let mut moved = wmr_state::default();
                $state(&*plant, &mut moved);
                assert!(moved.v > 0.0);
                assert_eq!($step(&mut *plant, 1.0, -dt), wmr_status::WMR_NOT_POSITIVE);
                let mut kept = wmr_state::default();
                $state(&*plant, &mut kept);
                assert_eq!(kept, moved);
            }
        }
    };
}

nan_command_is_refused!(
    issue25_1_nan_command_is_refused_f64,
    f64,
    wmr_robot_params_f64_paper,
    wmr_robot_f64_init,
    wmr_drive_params_f64_default,
    wmr_drive_f64_init,
    wmr_plant_f64_init,
    wmr_plant_f64_apply,
    wmr_plant_f64_step,
    wmr_plant_f64_state,
    wmr_robot_f64,
    wmr_drive_f64,
    wmr_plant_f64
);
nan_command_is_refused!(
    issue25_1_nan_command_is_refused_f32,
    f32,
    wmr_robot_params_f32_paper,
    wmr_robot_f32_init,
    wmr_drive_params_f32_default,
    wmr_drive_f32_init,
    wmr_plant_f32_init,
    wmr_plant_f32_apply,
    wmr_plant_f32_step,
    wmr_plant_f32_state,
    wmr_robot_f32,
    wmr_drive_f32,
    wmr_plant_f32
);

/// Item 1: a start outside the plant's 1 km box was accepted (and the first step then
/// "diverged"); refused by name.
#[test]
fn issue25_1_start_outside_the_box_is_refused() {
    let (robot, drive, _) = plant_setup!(
        f64,
        wmr_robot_params_f64_paper,
        wmr_robot_f64_init,
        wmr_drive_params_f64_default,
        wmr_drive_f64_init,
        wmr_plant_f64_init,
        wmr_robot_f64,
        wmr_drive_f64,
        wmr_plant_f64
    );
    let mut plant = Box::new(MaybeUninit::<wmr_plant_f64>::uninit());
    let mut err = new_err();
    for (start, name) in
        [(wmr_pose { x: 1000.5, y: 0.0, theta: 0.0 }, "start.x"), (wmr_pose { x: 0.0, y: -2e6, theta: 0.0 }, "start.y")]
    {
        // SAFETY: valid pointers.
        let code = unsafe { wmr_plant_f64_init(plant.as_mut_ptr(), &robot, &drive, std::ptr::null(), start, &mut err) };
        assert_eq!(code, wmr_status::WMR_OUT_OF_RANGE);
        assert_eq!(field(&err), name);
    }
}

/// The paper's controller (f64) with default gains but servo gains `kp`, `kd`.
fn paper_controller(
    robot: &wmr_robot_f64,
    drive: &wmr_drive_f64,
    kp: f64,
    kd: f64,
) -> Result<Box<wmr_paper_controller_f64>, wmr_status> {
    let mut dp = MaybeUninit::uninit();
    let mut wp = MaybeUninit::<wmr_wheel_stage_params<f64>>::uninit();
    let mut lp = MaybeUninit::uninit();
    let mut ctrl = Box::new(MaybeUninit::<wmr_paper_controller_f64>::uninit());
    // SAFETY: valid pointers.
    unsafe {
        wmr_drive_params_f64_default(WMR_DRIVE_TORQUE, dp.as_mut_ptr());
        wmr_wheel_stage_params_f64_default(dp.as_ptr(), robot, wp.as_mut_ptr());
        let mut wp = wp.assume_init();
        wp.servo_kp = kp;
        wp.servo_kd = kd;
        wmr_paper_params_f64_default(lp.as_mut_ptr());
        let code = wmr_paper_controller_f64_init(
            ctrl.as_mut_ptr(),
            lp.as_ptr(),
            &wp,
            robot,
            drive,
            1e-3,
            std::ptr::null_mut(),
        );
        if code != wmr_status::WMR_OK {
            return Err(code);
        }
        Ok(Box::from_raw(Box::into_raw(ctrl).cast()))
    }
}

/// Item 1: finite inputs whose command overflows (servo gains of 1e300, wheel angles of
/// +-1e308) returned WMR_OK with an infinite or NaN command. Now WMR_NOT_FINITE naming
/// the output, `out` untouched and the controller as before the tick: the next sane
/// tick gives what a controller that never saw the bad one gives.
#[test]
fn issue25_1_overflowing_command_is_refused_and_changes_nothing() {
    let (robot, drive, _) = plant_setup!(
        f64,
        wmr_robot_params_f64_paper,
        wmr_robot_f64_init,
        wmr_drive_params_f64_default,
        wmr_drive_f64_init,
        wmr_plant_f64_init,
        wmr_robot_f64,
        wmr_drive_f64,
        wmr_plant_f64
    );
    let goal = wmr_pose { x: 1.0, y: 1.0, theta: 2.0 };
    let sane = wmr_measurement { t: 0.0, pose: wmr_pose { x: 0.1, y: 0.0, theta: 0.3 }, ..Default::default() };
    let huge = wmr_measurement {
        wheel_angles: wmr_wheels { right: 1e308, left: -1e308 },
        wheel_speeds: wmr_wheels { right: 1e308, left: -1e308 },
        ..sane
    };
    let mut refused = 0;
    for (kp, kd, m) in [(1e300, 1e300, sane), (1e300, 1e300, huge), (30.0, 1.0, huge)] {
        let Ok(mut a) = paper_controller(&robot, &drive, kp, kd) else { continue };
        let mut b = paper_controller(&robot, &drive, kp, kd).unwrap();
        let marker = wmr_control_output { e_s: 42.0, ..Default::default() };
        let mut out = marker;
        // SAFETY: valid pointers.
        let code = unsafe { wmr_paper_controller_f64_update(&mut *a, 0.0, &m, goal, &mut out) };
        if code == wmr_status::WMR_OK {
            let o = [out.command.right, out.command.left, out.e_s, out.e_theta, out.dl];
            assert!(o.iter().all(|v| v.is_finite()), "WMR_OK with a non-finite output: {out:?}");
            continue;
        }
        refused += 1;
        assert_eq!(code, wmr_status::WMR_NOT_FINITE);
        assert_eq!(out, marker, "a refused tick wrote out");
        // The refused tick left `a` as `b`, which never saw it.
        let (mut oa, mut ob) = (wmr_control_output::default(), wmr_control_output::default());
        // SAFETY: valid pointers.
        unsafe {
            let ca = wmr_paper_controller_f64_update(&mut *a, 1e-3, &sane, goal, &mut oa);
            let cb = wmr_paper_controller_f64_update(&mut *b, 1e-3, &sane, goal, &mut ob);
            assert_eq!(ca, cb);
        }
        assert_eq!(oa, ob);
    }
    assert!(refused >= 2, "the overflowing ticks were not refused ({refused})");
    // The same tick through _update_reference names the output.
    let mut a = paper_controller(&robot, &drive, 30.0, 1.0).unwrap();
    let mut err = new_err();
    let r = wmr_reference_state { pose: goal, ..Default::default() };
    let mut out = wmr_control_output::default();
    // SAFETY: valid pointers.
    let code = unsafe { wmr_paper_controller_f64_update_reference(&mut *a, 0.0, &huge, &r, &mut out, &mut err) };
    assert_eq!(code, wmr_status::WMR_NOT_FINITE);
    assert!(field(&err).starts_with("out."), "{}", field(&err));
}

/// 16 bytes of storage per 8-byte word plus one, 8-aligned, for a storage type `S`; the
/// pointer 4 bytes in is misaligned for every storage and every f64 struct.
struct Misaligned<S> {
    words: Vec<u64>,
    _s: std::marker::PhantomData<S>,
}

impl<S> Misaligned<S> {
    fn new() -> Self {
        Misaligned { words: vec![0x5a5a_5a5a_5a5a_5a5a; size_of::<S>() / 8 + 2], _s: std::marker::PhantomData }
    }
    fn ptr(&mut self) -> *mut S {
        // SAFETY: 4 bytes into a buffer longer than S + 8 bytes.
        unsafe { self.words.as_mut_ptr().cast::<u8>().add(4).cast::<S>() }
    }
    fn untouched(&self) -> bool {
        self.words.iter().all(|&w| w == 0x5a5a_5a5a_5a5a_5a5a)
    }
}

/// Item 10: a misaligned pointer was used (undefined behaviour: WMR_OK in release, an
/// abort "misaligned pointer dereference" in a debug build). Now WMR_MISALIGNED naming
/// the argument, and nothing read or written through it.
#[test]
fn issue25_10_misaligned_pointers_are_refused_by_name() {
    let (robot, drive, mut plant) = plant_setup!(
        f64,
        wmr_robot_params_f64_paper,
        wmr_robot_f64_init,
        wmr_drive_params_f64_default,
        wmr_drive_f64_init,
        wmr_plant_f64_init,
        wmr_robot_f64,
        wmr_drive_f64,
        wmr_plant_f64
    );
    let mut err = new_err();
    let null = std::ptr::null();
    // SAFETY: the misaligned pointers point into live buffers large enough for their
    // types (the library must refuse them without dereferencing); the rest are valid.
    unsafe {
        let mut out = Misaligned::<wmr_plant_f64>::new();
        let start = wmr_pose::default();
        let code = wmr_plant_f64_init(out.ptr(), &robot, &drive, null, start, &mut err);
        assert_eq!((code, field(&err).as_str()), (wmr_status::WMR_MISALIGNED, "out"));
        assert!(out.untouched());
        let mut r = Misaligned::<wmr_robot_f64>::new();
        let code = wmr_plant_f64_init(&mut *plant, r.ptr(), &drive, null, start, &mut err);
        assert_eq!((code, field(&err).as_str()), (wmr_status::WMR_MISALIGNED, "robot"));
        let mut w = Misaligned::<wmr_world_params<f64>>::new();
        let code = wmr_plant_f64_init(&mut *plant, &robot, &drive, w.ptr(), start, &mut err);
        assert_eq!((code, field(&err).as_str()), (wmr_status::WMR_MISALIGNED, "world"));
        let mut p = Misaligned::<wmr_plant_f64>::new();
        assert_eq!(wmr_plant_f64_step(p.ptr(), 0.0, 1e-3), wmr_status::WMR_MISALIGNED);
        assert_eq!(wmr_plant_f64_apply(p.ptr(), wmr_wheels::default()), wmr_status::WMR_MISALIGNED);
        let mut s = Misaligned::<wmr_state<f64>>::new();
        assert_eq!(wmr_plant_f64_state(&*plant, s.ptr()), wmr_status::WMR_MISALIGNED);
        assert!(s.untouched());
        // The error struct itself: nowhere to write the details, the code says it.
        let mut e = Misaligned::<wmr_error>::new();
        let mut rp = MaybeUninit::uninit();
        wmr_robot_params_f64_paper(rp.as_mut_ptr());
        let mut robot2 = MaybeUninit::<wmr_robot_f64>::uninit();
        assert_eq!(wmr_robot_f64_init(robot2.as_mut_ptr(), rp.as_ptr(), e.ptr()), wmr_status::WMR_MISALIGNED);
        assert!(e.untouched());
        // Controller inputs and outputs (f64 structs are 8-aligned).
        let mut ctrl = paper_controller(&robot, &drive, 30.0, 1.0).unwrap();
        let mut m = Misaligned::<wmr_measurement<f64>>::new();
        let mut out = wmr_control_output::default();
        let goal = wmr_pose::default();
        assert_eq!(
            wmr_paper_controller_f64_update(&mut *ctrl, 0.0, m.ptr(), goal, &mut out),
            wmr_status::WMR_MISALIGNED
        );
        let mut o = Misaligned::<wmr_control_output<f64>>::new();
        let ok = wmr_measurement::default();
        assert_eq!(wmr_paper_controller_f64_update(&mut *ctrl, 0.0, &ok, goal, o.ptr()), wmr_status::WMR_MISALIGNED);
        assert!(o.untouched());
        let mut lp = Misaligned::<wmr_paper_params<f64>>::new();
        let mut wp = MaybeUninit::uninit();
        let mut dp = MaybeUninit::uninit();
        wmr_drive_params_f64_default(WMR_DRIVE_TORQUE, dp.as_mut_ptr());
        wmr_wheel_stage_params_f64_default(dp.as_ptr(), &robot, wp.as_mut_ptr());
        let mut c2 = MaybeUninit::<wmr_paper_controller_f64>::uninit();
        let code =
            wmr_paper_controller_f64_init(c2.as_mut_ptr(), lp.ptr(), wp.as_ptr(), &robot, &drive, 1e-3, &mut err);
        assert_eq!((code, field(&err).as_str()), (wmr_status::WMR_MISALIGNED, "params"));
        // f32: storage is 8-aligned even where its floats need 4.
        let mut p32 = Misaligned::<wmr_plant_f32>::new();
        assert_eq!(wmr_plant_f32_step(p32.ptr(), 0.0, 1e-3), wmr_status::WMR_MISALIGNED);
        let mut s32 = Misaligned::<wmr_sensor_f32>::new();
        assert_eq!(wmr_sensor_f32_init_perfect(s32.ptr()), wmr_status::WMR_MISALIGNED);
        assert!(s32.untouched());
    }
}

/// Item 10: storage whose body was overwritten but whose tag is intact was used
/// silently. Now a robot whose parameters no longer validate to it, and a plant whose
/// state was made NaN, are WMR_CORRUPTED, by the argument's name.
#[test]
fn issue25_10_overwritten_bodies_are_refused() {
    let (mut robot, drive, _) = plant_setup!(
        f64,
        wmr_robot_params_f64_paper,
        wmr_robot_f64_init,
        wmr_drive_params_f64_default,
        wmr_drive_f64_init,
        wmr_plant_f64_init,
        wmr_robot_f64,
        wmr_drive_f64,
        wmr_plant_f64
    );
    let mut err = new_err();
    let start = wmr_pose { x: 0.3, y: -0.2, theta: 2.5 };
    let mut plant = Box::new(MaybeUninit::<wmr_plant_f64>::uninit());
    // SAFETY: valid pointers.
    unsafe {
        assert_eq!(
            wmr_plant_f64_init(plant.as_mut_ptr(), &robot, &drive, std::ptr::null(), start, &mut err),
            wmr_status::WMR_OK
        );
    }
    // SAFETY: filled by init.
    let mut plant = unsafe { plant.assume_init() };
    // The plant's x, then y: find them by their bits (the layout is the library's). Every
    // such pair: the plant may keep the start pose beside its state.
    let pairs: Vec<usize> = (0..plant.opaque.len() - 1)
        .filter(|&i| plant.opaque[i..i + 2] == [0.3f64.to_bits(), (-0.2f64).to_bits()])
        .collect();
    assert!(!pairs.is_empty(), "the start pose in the plant's words");
    for at in pairs {
        plant.opaque[at] = f64::NAN.to_bits();
    }
    // SAFETY: valid pointers.
    unsafe {
        assert_eq!(wmr_plant_f64_step(&mut *plant, 0.0, 1e-3), wmr_status::WMR_CORRUPTED);
        let mut s = wmr_state::default();
        assert_eq!(wmr_plant_f64_state(&*plant, &mut s), wmr_status::WMR_CORRUPTED);
    }
    // The robot's mass (5 kg, the first parameter): overwritten with a negative one.
    let at = robot.opaque.iter().position(|&w| w == 5.0f64.to_bits()).expect("the mass in the robot's words");
    robot.opaque[at] = (-5.0f64).to_bits();
    let mut p2 = Box::new(MaybeUninit::<wmr_plant_f64>::uninit());
    // SAFETY: valid pointers.
    let code = unsafe { wmr_plant_f64_init(p2.as_mut_ptr(), &robot, &drive, std::ptr::null(), start, &mut err) };
    assert_eq!((code, field(&err).as_str()), (wmr_status::WMR_CORRUPTED, "robot"));
}
