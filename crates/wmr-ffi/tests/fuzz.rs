//! Fuzz of the C API (issue 25): seeded random finite inputs to every entry point, f32
//! and f64, every law, plus NULL and a misaligned pointer in every pointer argument.
//! Asserted: nothing panics (no `WMR_PANIC`, no abort), every `WMR_OK` output is finite,
//! every refusal has a nonzero code, a name (`wmr_status_name`) and, where the function
//! takes a `wmr_error`, the same code, a field and a reason.
//!
//! `WMR_FUZZ_CASES` (default 1,500 per precision and law: 12,000 cases, about 2 s in a debug build) and `WMR_FUZZ_SEED` change the run.
#![allow(unsafe_code)]

use std::ffi::CStr;
use std::mem::MaybeUninit;

use wmr_core::sensor::gaussian::Gaussian;
use wmr_ffi::*;

/// The core's seeded SplitMix64 stream, so a failure replays from its seed.
struct Rng(Gaussian);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0.next_u64()
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
    /// [`Rng::value`] up to `usual`, or one time in ten up to `max`.
    fn value_or_huge(&mut self, keep: f64, usual: f64, max: f64) -> f64 {
        let max = if self.chance(0.1) { max } else { usual };
        self.value(keep, max)
    }
    /// A finite value: plausible, large, huge (up to `max`), tiny, zero or `keep`.
    fn value(&mut self, keep: f64, max: f64) -> f64 {
        let sign = if self.chance(0.5) { 1.0 } else { -1.0 };
        match self.below(10) {
            0..=3 => keep,
            4 => sign * self.unit() * 2.0,
            5 => sign * self.unit() * 1e3,
            6 => sign * self.unit() * max,
            7 => sign * 1e-30 * self.unit(),
            8 => 0.0,
            _ => keep * (0.5 + self.unit()),
        }
    }
}

fn reason(e: &wmr_error) -> String {
    // SAFETY: the library NUL-terminates `reason`.
    unsafe { CStr::from_ptr(e.reason.as_ptr()) }.to_string_lossy().into_owned()
}

fn field(e: &wmr_error) -> String {
    // SAFETY: the library NUL-terminates `field`.
    unsafe { CStr::from_ptr(e.field.as_ptr()) }.to_string_lossy().into_owned()
}

fn new_err() -> wmr_error {
    wmr_error { code: wmr_status::WMR_OK, value: 0.0, field: [0; WMR_FIELD_LEN], reason: [0; WMR_REASON_LEN] }
}

/// A refusal as the header promises it: a nonzero, named code; with `err`, the same code,
/// a field (but for WMR_PANIC) and a reason.
fn refused(code: wmr_status, err: Option<&wmr_error>, what: &str) {
    assert_ne!(code, wmr_status::WMR_OK, "{what}");
    assert_ne!(code, wmr_status::WMR_PANIC, "{what}: a panic was caught");
    // SAFETY: a static NUL-terminated string.
    let name = unsafe { CStr::from_ptr(wmr_status_name(code as i32)) }.to_str().unwrap();
    assert!(name.starts_with("WMR_") && name != "WMR_UNKNOWN", "{what}: {name}");
    if let Some(e) = err {
        assert_eq!(e.code, code, "{what}");
        assert!(!reason(e).is_empty(), "{what}: no reason");
        assert!(!field(e).is_empty(), "{what}: no field ({})", reason(e));
    }
}

/// `code` is WMR_OK, or a refusal as [`refused`] checks it; true for WMR_OK.
fn ok_or_refused(code: wmr_status, err: Option<&wmr_error>, what: &str) -> bool {
    if code == wmr_status::WMR_OK {
        return true;
    }
    refused(code, err, what);
    false
}

/// A buffer for misaligned pointers: `ptr::<X>()` is 4 bytes past an 8-byte boundary
/// (misaligned for every storage and f64 struct) or, for X of alignment 4, 2 bytes past.
struct Scratch(Vec<u64>);

impl Scratch {
    fn new() -> Self {
        Scratch(vec![0; 512])
    }
    fn ptr<X>(&mut self) -> *mut X {
        assert!(size_of::<X>() + 8 <= self.0.len() * 8);
        let off = if align_of::<X>() >= 8 { 4 } else { 2 };
        // SAFETY: inside the buffer (asserted).
        unsafe { self.0.as_mut_ptr().cast::<u8>().add(off).cast::<X>() }
    }
}

fn cases() -> usize {
    std::env::var("WMR_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(1500)
}

fn seed() -> u64 {
    std::env::var("WMR_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(25)
}

/// Writes random values of `T` into random `T`-sized slots of the C struct at `p` (a
/// `uint32_t` code among them gets random bits: init must refuse them, never read them
/// as an enum).
///
/// # Safety
/// `p` is valid for writes of `X`, a struct of `T`s and `uint32_t`s.
unsafe fn perturb<X, T: Copy>(rng: &mut Rng, p: *mut X, p_slot: f64, to_t: impl Fn(f64) -> T, max: f64) {
    let n = size_of::<X>() / size_of::<T>();
    for i in 0..n {
        if rng.chance(p_slot) {
            let v = to_t(rng.value(1.0, max));
            // SAFETY: slot i of n lies inside X (caller contract); T is plain data.
            unsafe { p.cast::<T>().add(i).write_unaligned(v) };
        }
    }
}

/// Each call refused (checked right after it, against the `wmr_error` it filled).
/// `none`: the functions take no `wmr_error`.
macro_rules! each_refused {
    (none, $name:expr, [$($call:expr),+ $(,)?]) => {$(
        refused($call, None, $name);
    )+};
    ($e:ident, $name:expr, [$($call:expr),+ $(,)?]) => {$(
        let c = $call;
        refused(c, Some(&$e), $name);
    )+};
}

/// Every component finite.
macro_rules! all_finite {
    ($($v:expr),+) => { [$($v),+].iter().all(|v| v.is_finite()) };
}

macro_rules! fuzz {
    ($name:ident, $t:ty, $robot_params:ident, $robot_init:ident, $robot:ty, $drive_default:ident, $drive_init:ident,
     $drive:ty, $wheels_default:ident, $plant_init:ident, $apply:ident, $step:ident, $state:ident, $plant:ty,
     $sensor_perfect:ident, $sensor_defaults:ident, $sensor_pose:ident, $measure:ident, $sensor_reset:ident,
     $sensor:ty, $law_default:ident, $law_params:ty, $init:ident, $update:ident, $update_ref:ident,
     $reset:ident, $init_observer:ident, $disturbance:ident, $ctrl:ty) => {
        #[test]
        fn $name() {
            let started = std::time::Instant::now();
            let name = stringify!($name);
            let mut rng = Rng(Gaussian::new(
                seed(),
                name.bytes().fold(0u64, |h, b| h.wrapping_mul(31).wrapping_add(u64::from(b))),
            ));
            let mut scratch = Scratch::new();
            let max = f64::from(<$t>::MAX) * 0.5;
            let to_t = |v: f64| v as $t;
            let (mut oks, mut refusals) = (0u64, 0u64);
            // SAFETY, for the whole test: every pointer is NULL, misaligned into a live
            // scratch buffer, or valid for its type; the library refuses the first two
            // without dereferencing them.
            unsafe {
                // --- NULL and misaligned pointers, with every other argument valid.
                let mut rp = MaybeUninit::<wmr_robot_params<$t>>::uninit();
                assert_eq!($robot_params(std::ptr::null_mut()), wmr_status::WMR_NULL_POINTER);
                assert_eq!($robot_params(scratch.ptr()), wmr_status::WMR_MISALIGNED);
                assert_eq!($robot_params(rp.as_mut_ptr()), wmr_status::WMR_OK);
                let mut robot = MaybeUninit::<$robot>::uninit();
                let mut e = new_err();
                for (c, f) in [("out", 0), ("params", 1), ("out", 2), ("params", 3)].map(|(f, i)| {
                    let c = match i {
                        0 => $robot_init(std::ptr::null_mut(), rp.as_ptr(), &mut e),
                        1 => $robot_init(robot.as_mut_ptr(), std::ptr::null(), &mut e),
                        2 => $robot_init(scratch.ptr(), rp.as_ptr(), &mut e),
                        _ => $robot_init(robot.as_mut_ptr(), scratch.ptr(), &mut e),
                    };
                    refused(c, Some(&e), name);
                    assert_eq!(field(&e), f);
                    (c, f)
                }) {
                    assert!(matches!(c, wmr_status::WMR_NULL_POINTER | wmr_status::WMR_MISALIGNED), "{f}");
                }
                assert_eq!($robot_init(robot.as_mut_ptr(), rp.as_ptr(), scratch.ptr()), wmr_status::WMR_MISALIGNED);
                assert_eq!($robot_init(robot.as_mut_ptr(), rp.as_ptr(), std::ptr::null_mut()), wmr_status::WMR_OK);
                let mut dp = MaybeUninit::<wmr_drive_params<$t>>::uninit();
                assert_eq!($drive_default(WMR_DRIVE_TORQUE, std::ptr::null_mut()), wmr_status::WMR_NULL_POINTER);
                assert_eq!($drive_default(WMR_DRIVE_TORQUE, scratch.ptr()), wmr_status::WMR_MISALIGNED);
                assert_eq!($drive_default(WMR_DRIVE_TORQUE, dp.as_mut_ptr()), wmr_status::WMR_OK);
                let mut drive = MaybeUninit::<$drive>::uninit();
                each_refused!(
                    e,
                    name,
                    [
                        $drive_init(std::ptr::null_mut(), dp.as_ptr(), robot.as_ptr(), &mut e),
                        $drive_init(drive.as_mut_ptr(), std::ptr::null(), robot.as_ptr(), &mut e),
                        $drive_init(drive.as_mut_ptr(), dp.as_ptr(), std::ptr::null(), &mut e),
                        $drive_init(scratch.ptr(), dp.as_ptr(), robot.as_ptr(), &mut e),
                        $drive_init(drive.as_mut_ptr(), scratch.ptr(), robot.as_ptr(), &mut e),
                        $drive_init(drive.as_mut_ptr(), dp.as_ptr(), scratch.ptr(), &mut e),
                    ]
                );
                assert_eq!(
                    $drive_init(drive.as_mut_ptr(), dp.as_ptr(), robot.as_ptr(), std::ptr::null_mut()),
                    wmr_status::WMR_OK
                );
                let mut wp = MaybeUninit::<wmr_wheel_stage_params<$t>>::uninit();
                let r = robot.as_ptr();
                assert_eq!($wheels_default(std::ptr::null(), r, wp.as_mut_ptr()), wmr_status::WMR_NULL_POINTER);
                assert_eq!(
                    $wheels_default(dp.as_ptr(), std::ptr::null(), wp.as_mut_ptr()),
                    wmr_status::WMR_NULL_POINTER
                );
                assert_eq!($wheels_default(dp.as_ptr(), r, std::ptr::null_mut()), wmr_status::WMR_NULL_POINTER);
                assert_eq!($wheels_default(scratch.ptr(), r, wp.as_mut_ptr()), wmr_status::WMR_MISALIGNED);
                assert_eq!($wheels_default(dp.as_ptr(), scratch.ptr(), wp.as_mut_ptr()), wmr_status::WMR_MISALIGNED);
                assert_eq!($wheels_default(dp.as_ptr(), r, scratch.ptr()), wmr_status::WMR_MISALIGNED);
                assert_eq!($wheels_default(dp.as_ptr(), r, wp.as_mut_ptr()), wmr_status::WMR_OK);
                let mut lp = MaybeUninit::<$law_params>::uninit();
                assert_eq!($law_default(std::ptr::null_mut()), wmr_status::WMR_NULL_POINTER);
                assert_eq!($law_default(scratch.ptr()), wmr_status::WMR_MISALIGNED);
                assert_eq!($law_default(lp.as_mut_ptr()), wmr_status::WMR_OK);
                let dt: $t = 1e-3;
                let mut ctrl = MaybeUninit::<$ctrl>::uninit();
                let (l, w, r, d) = (lp.as_ptr(), wp.as_ptr(), robot.as_ptr(), drive.as_ptr());
                each_refused!(
                    e,
                    name,
                    [
                        $init(std::ptr::null_mut(), l, w, r, d, dt, &mut e),
                        $init(ctrl.as_mut_ptr(), std::ptr::null(), w, r, d, dt, &mut e),
                        $init(ctrl.as_mut_ptr(), l, std::ptr::null(), r, d, dt, &mut e),
                        $init(ctrl.as_mut_ptr(), l, w, std::ptr::null(), d, dt, &mut e),
                        $init(ctrl.as_mut_ptr(), l, w, r, std::ptr::null(), dt, &mut e),
                        $init(scratch.ptr(), l, w, r, d, dt, &mut e),
                        $init(ctrl.as_mut_ptr(), scratch.ptr(), w, r, d, dt, &mut e),
                        $init(ctrl.as_mut_ptr(), l, scratch.ptr(), r, d, dt, &mut e),
                        $init(ctrl.as_mut_ptr(), l, w, scratch.ptr(), d, dt, &mut e),
                        $init(ctrl.as_mut_ptr(), l, w, r, scratch.ptr(), dt, &mut e),
                    ]
                );
                assert_eq!($init(ctrl.as_mut_ptr(), l, w, r, d, dt, std::ptr::null_mut()), wmr_status::WMR_OK);
                // The observer's init and estimate (issue 42): every pointer refused when
                // NULL or misaligned; a random bandwidth is taken or refused by its name.
                let op = wmr_disturbance_observer_params::<$t> {
                    bandwidth: 50.0,
                    deadband: 0.0,
                    static_friction: 0.0,
                    precompensation_band: 0.5,
                };
                let mut octrl = MaybeUninit::<$ctrl>::uninit();
                each_refused!(
                    e,
                    name,
                    [
                        $init_observer(std::ptr::null_mut(), l, w, &op, r, d, dt, &mut e),
                        $init_observer(octrl.as_mut_ptr(), l, w, std::ptr::null(), r, d, dt, &mut e),
                        $init_observer(scratch.ptr(), l, w, &op, r, d, dt, &mut e),
                        $init_observer(octrl.as_mut_ptr(), l, w, scratch.ptr(), r, d, dt, &mut e),
                        $init_observer(octrl.as_mut_ptr(), std::ptr::null(), w, &op, r, d, dt, &mut e),
                    ]
                );
                let random = wmr_disturbance_observer_params::<$t> {
                    bandwidth: to_t(rng.value(50.0, max)),
                    deadband: to_t(rng.value(0.05, 1.0)),
                    static_friction: to_t(rng.value(0.04, 1.0)),
                    precompensation_band: to_t(rng.value(0.5, 1.0)),
                };
                let mut e = new_err();
                let c = $init_observer(octrl.as_mut_ptr(), l, w, &random, r, d, dt, &mut e);
                if c != wmr_status::WMR_OK {
                    refused(c, Some(&e), name);
                }
                assert_eq!(
                    $init_observer(octrl.as_mut_ptr(), l, w, &op, r, d, dt, std::ptr::null_mut()),
                    wmr_status::WMR_OK
                );
                let mut dist = wmr_wheels::<$t>::default();
                each_refused!(
                    none,
                    name,
                    [
                        $disturbance(std::ptr::null(), &mut dist),
                        $disturbance(octrl.as_ptr(), std::ptr::null_mut()),
                        $disturbance(scratch.ptr(), &mut dist),
                        $disturbance(octrl.as_ptr(), scratch.ptr()),
                        $disturbance(ctrl.as_ptr(), &mut dist),
                    ]
                );
                assert_eq!($disturbance(octrl.as_ptr(), &mut dist), wmr_status::WMR_OK);
                assert!(all_finite!(dist.right, dist.left));
                let mut plant = MaybeUninit::<$plant>::uninit();
                let start = wmr_pose::<$t>::default();
                each_refused!(
                    e,
                    name,
                    [
                        $plant_init(std::ptr::null_mut(), r, d, std::ptr::null(), start, &mut e),
                        $plant_init(plant.as_mut_ptr(), std::ptr::null(), d, std::ptr::null(), start, &mut e),
                        $plant_init(plant.as_mut_ptr(), r, std::ptr::null(), std::ptr::null(), start, &mut e),
                        $plant_init(scratch.ptr(), r, d, std::ptr::null(), start, &mut e),
                        $plant_init(plant.as_mut_ptr(), scratch.ptr(), d, std::ptr::null(), start, &mut e),
                        $plant_init(plant.as_mut_ptr(), r, scratch.ptr(), std::ptr::null(), start, &mut e),
                        $plant_init(plant.as_mut_ptr(), r, d, scratch.ptr(), start, &mut e),
                    ]
                );
                assert_eq!(
                    $plant_init(plant.as_mut_ptr(), r, d, std::ptr::null(), start, std::ptr::null_mut()),
                    wmr_status::WMR_OK
                );
                let p = plant.as_mut_ptr();
                let cmd = wmr_wheels::<$t>::default();
                each_refused!(
                    none,
                    name,
                    [
                        $apply(std::ptr::null_mut(), cmd),
                        $apply(scratch.ptr(), cmd),
                        $step(std::ptr::null_mut(), 0.0, dt),
                        $step(scratch.ptr(), 0.0, dt),
                    ]
                );
                let mut st = wmr_state::<$t>::default();
                each_refused!(
                    none,
                    name,
                    [
                        $state(std::ptr::null(), &mut st),
                        $state(p, std::ptr::null_mut()),
                        $state(scratch.ptr(), &mut st),
                        $state(p, scratch.ptr()),
                    ]
                );
                let mut sensor = MaybeUninit::<$sensor>::uninit();
                let mut sp = MaybeUninit::<wmr_sensor_params<$t>>::uninit();
                each_refused!(
                    none,
                    name,
                    [
                        $sensor_perfect(std::ptr::null_mut()),
                        $sensor_perfect(scratch.ptr()),
                        $sensor_defaults(std::ptr::null_mut()),
                        $sensor_defaults(scratch.ptr()),
                    ]
                );
                assert_eq!($sensor_defaults(sp.as_mut_ptr()), wmr_status::WMR_OK);
                each_refused!(
                    e,
                    name,
                    [
                        $sensor_pose(std::ptr::null_mut(), sp.as_ptr(), dt, 0, &mut e),
                        $sensor_pose(sensor.as_mut_ptr(), std::ptr::null(), dt, 0, &mut e),
                        $sensor_pose(scratch.ptr(), sp.as_ptr(), dt, 0, &mut e),
                        $sensor_pose(sensor.as_mut_ptr(), scratch.ptr(), dt, 0, &mut e),
                    ]
                );
                assert_eq!(
                    $sensor_pose(sensor.as_mut_ptr(), sp.as_ptr(), dt, 0, std::ptr::null_mut()),
                    wmr_status::WMR_OK
                );
                let sn = sensor.as_mut_ptr();
                let mut m = wmr_measurement::<$t>::default();
                each_refused!(
                    none,
                    name,
                    [
                        $measure(std::ptr::null_mut(), 0.0, p, &mut m),
                        $measure(sn, 0.0, std::ptr::null(), &mut m),
                        $measure(sn, 0.0, p, std::ptr::null_mut()),
                        $measure(scratch.ptr(), 0.0, p, &mut m),
                        $measure(sn, 0.0, scratch.ptr(), &mut m),
                        $measure(sn, 0.0, p, scratch.ptr()),
                        $sensor_reset(std::ptr::null_mut()),
                        $sensor_reset(scratch.ptr()),
                    ]
                );
                let cp = ctrl.as_mut_ptr();
                let mut out = wmr_control_output::<$t>::default();
                let rs = wmr_reference_state::<$t>::default();
                each_refused!(
                    none,
                    name,
                    [
                        $update(std::ptr::null_mut(), 0.0, &m, start, &mut out),
                        $update(cp, 0.0, std::ptr::null(), start, &mut out),
                        $update(cp, 0.0, &m, start, std::ptr::null_mut()),
                        $update(scratch.ptr(), 0.0, &m, start, &mut out),
                        $update(cp, 0.0, scratch.ptr(), start, &mut out),
                        $update(cp, 0.0, &m, start, scratch.ptr()),
                        $reset(std::ptr::null_mut()),
                        $reset(scratch.ptr()),
                    ]
                );
                each_refused!(
                    e,
                    name,
                    [
                        $update_ref(std::ptr::null_mut(), 0.0, &m, &rs, &mut out, &mut e),
                        $update_ref(cp, 0.0, std::ptr::null(), &rs, &mut out, &mut e),
                        $update_ref(cp, 0.0, &m, std::ptr::null(), &mut out, &mut e),
                        $update_ref(cp, 0.0, &m, &rs, std::ptr::null_mut(), &mut e),
                        $update_ref(scratch.ptr(), 0.0, &m, &rs, &mut out, &mut e),
                        $update_ref(cp, 0.0, scratch.ptr(), &rs, &mut out, &mut e),
                        $update_ref(cp, 0.0, &m, scratch.ptr(), &mut out, &mut e),
                        $update_ref(cp, 0.0, &m, &rs, scratch.ptr(), &mut e),
                    ]
                );
                assert_eq!($update_ref(cp, 0.0, &m, &rs, &mut out, scratch.ptr()), wmr_status::WMR_MISALIGNED);

                // --- Random finite inputs: objects from perturbed parameters, then ticks.
                for case in 0..cases() {
                    let what = format!("{name} case {case} (WMR_FUZZ_SEED={})", seed());
                    let mut e = new_err();
                    let mut rp = MaybeUninit::<wmr_robot_params<$t>>::uninit();
                    $robot_params(rp.as_mut_ptr());
                    if rng.chance(0.3) {
                        perturb::<_, $t>(&mut rng, rp.as_mut_ptr(), 0.2, to_t, max);
                    }
                    let mut robot = MaybeUninit::<$robot>::uninit();
                    if !ok_or_refused($robot_init(robot.as_mut_ptr(), rp.as_ptr(), &mut e), Some(&e), &what) {
                        refusals += 1;
                        continue;
                    }
                    let kind = if rng.chance(0.1) { rng.below(4) as u32 } else { rng.below(2) as u32 };
                    let mut dp = MaybeUninit::<wmr_drive_params<$t>>::uninit();
                    if !ok_or_refused($drive_default(kind, dp.as_mut_ptr()), None, &what) {
                        refusals += 1;
                        continue;
                    }
                    let mut dp = dp.assume_init();
                    if rng.chance(0.3) {
                        perturb::<_, $t>(&mut rng, &mut dp, 0.2, to_t, max);
                        dp.kind = kind;
                    }
                    let mut drive = MaybeUninit::<$drive>::uninit();
                    if !ok_or_refused($drive_init(drive.as_mut_ptr(), &dp, robot.as_ptr(), &mut e), Some(&e), &what) {
                        refusals += 1;
                        continue;
                    }
                    let mut wp = MaybeUninit::<wmr_wheel_stage_params<$t>>::uninit();
                    assert_eq!($wheels_default(&dp, robot.as_ptr(), wp.as_mut_ptr()), wmr_status::WMR_OK, "{what}");
                    if rng.chance(0.3) {
                        perturb::<_, $t>(&mut rng, wp.as_mut_ptr(), 0.3, to_t, max);
                    }
                    let mut lp = MaybeUninit::<$law_params>::uninit();
                    assert_eq!($law_default(lp.as_mut_ptr()), wmr_status::WMR_OK, "{what}");
                    if rng.chance(0.3) {
                        perturb::<_, $t>(&mut rng, lp.as_mut_ptr(), 0.2, to_t, max);
                    }
                    let dt: $t = if rng.chance(0.1) { to_t(rng.value(1e-3, max)) } else { 1e-3 };
                    let mut ctrl = MaybeUninit::<$ctrl>::uninit();
                    let c =
                        $init(ctrl.as_mut_ptr(), lp.as_ptr(), wp.as_ptr(), robot.as_ptr(), drive.as_ptr(), dt, &mut e);
                    if !ok_or_refused(c, Some(&e), &what) {
                        refusals += 1;
                        continue;
                    }
                    let start = wmr_pose::<$t> {
                        x: to_t(rng.value_or_huge(0.0, 2.0, max)),
                        y: to_t(rng.value(0.0, 2.0)),
                        theta: to_t(rng.value_or_huge(0.5, 4.0, max)),
                    };
                    let mut world = wmr_world_params::<$t> { slope_deg: 0.0, slope_direction_deg: 0.0 };
                    let world_ptr = if rng.chance(0.3) {
                        world.slope_deg = to_t(rng.value(3.0, 100.0));
                        world.slope_direction_deg = to_t(rng.value(30.0, max));
                        &world as *const _
                    } else {
                        std::ptr::null()
                    };
                    let mut plant = MaybeUninit::<$plant>::uninit();
                    let c = $plant_init(plant.as_mut_ptr(), robot.as_ptr(), drive.as_ptr(), world_ptr, start, &mut e);
                    if !ok_or_refused(c, Some(&e), &what) {
                        refusals += 1;
                        continue;
                    }
                    let mut sensor = MaybeUninit::<$sensor>::uninit();
                    if rng.chance(0.5) {
                        assert_eq!($sensor_perfect(sensor.as_mut_ptr()), wmr_status::WMR_OK);
                    } else {
                        let mut sp = MaybeUninit::<wmr_sensor_params<$t>>::uninit();
                        $sensor_defaults(sp.as_mut_ptr());
                        let mut sp = sp.assume_init();
                        let rates: [$t; 6] = [<$t>::INFINITY, 1000.0, 100.0, 50.0, 20.0, 7.0];
                        sp.rate_hz = rates[rng.below(6) as usize];
                        sp.latency = [0.0, 0.001, 0.02, 0.05, 1.0][rng.below(5) as usize];
                        sp.position_noise = to_t(rng.value(0.002, max).abs());
                        sp.heading_noise_deg = to_t(rng.value(0.5, 1e3));
                        sp.encoder_counts = [0, 1, 1024, u32::MAX][rng.below(4) as usize];
                        sp.seed = rng.next();
                        let c = $sensor_pose(sensor.as_mut_ptr(), &sp, dt, rng.next(), &mut e);
                        if !ok_or_refused(c, Some(&e), &what) {
                            refusals += 1;
                            continue;
                        }
                    }
                    let (p, sn, cp) = (plant.as_mut_ptr(), sensor.as_mut_ptr(), ctrl.as_mut_ptr());
                    let goal = wmr_pose::<$t> {
                        x: to_t(rng.value_or_huge(1.0, 2.0, max)),
                        y: to_t(rng.value(1.0, 2.0)),
                        theta: to_t(rng.value(2.0, 10.0)),
                    };
                    for k in 0..40u32 {
                        let t = to_t(f64::from(k) * 1e-3);
                        let mut m = wmr_measurement::<$t>::default();
                        let c = $measure(sn, t, p, &mut m);
                        if ok_or_refused(c, None, &what) {
                            let (a, s) = (m.wheel_angles, m.wheel_speeds);
                            assert!(
                                all_finite!(m.t, m.pose.x, m.pose.y, m.pose.theta, a.right, a.left, s.right, s.left),
                                "{what}: {m:?}"
                            );
                        }
                        if rng.chance(0.1) {
                            perturb::<_, $t>(&mut rng, &mut m, 0.3, to_t, max);
                        }
                        let mut out = wmr_control_output::<$t>::default();
                        let c = if rng.chance(0.5) {
                            $update(cp, t, &m, goal, &mut out)
                        } else {
                            let rs = wmr_reference_state::<$t> {
                                pose: goal,
                                twist: wmr_twist { v: to_t(rng.value(0.0, 10.0)), omega: to_t(rng.value(0.0, 10.0)) },
                                accel: wmr_accel { v: to_t(rng.value(0.0, 10.0)), omega: to_t(rng.value(0.0, 10.0)) },
                            };
                            let c = $update_ref(cp, t, &m, &rs, &mut out, &mut e);
                            if c != wmr_status::WMR_OK {
                                refused(c, Some(&e), &what);
                            }
                            c
                        };
                        let command = if ok_or_refused(c, None, &what) {
                            oks += 1;
                            let o = out;
                            assert!(
                                all_finite!(o.command.right, o.command.left, o.e_s, o.e_theta, o.dl),
                                "{what}: WMR_OK with {o:?}"
                            );
                            o.command
                        } else {
                            refusals += 1;
                            wmr_wheels { right: to_t(rng.value(0.0, max)), left: to_t(rng.value(0.0, max)) }
                        };
                        let command =
                            if rng.chance(0.02) { wmr_wheels { right: <$t>::NAN, left: 0.0 } } else { command };
                        ok_or_refused($apply(p, command), None, &what);
                        let step_dt = if rng.chance(0.03) { to_t(rng.value(1e-3, max)) } else { 1e-3 };
                        if !ok_or_refused($step(p, t, step_dt), None, &what) {
                            refusals += 1;
                        }
                        let mut st = wmr_state::<$t>::default();
                        assert_eq!($state(p, &mut st), wmr_status::WMR_OK, "{what}");
                        assert!(
                            all_finite!(st.x, st.y, st.theta, st.v, st.omega, st.phi_r, st.phi_l),
                            "{what}: {st:?}"
                        );
                        if rng.chance(0.02) {
                            assert_eq!($reset(cp), wmr_status::WMR_OK, "{what}");
                            assert_eq!($sensor_reset(sn), wmr_status::WMR_OK, "{what}");
                        }
                    }
                }
            }
            eprintln!("{name}: {oks} ticks WMR_OK, {refusals} refusals, {:.1} s", started.elapsed().as_secs_f64());
            assert!(oks > 1000, "{name}: only {oks} good ticks: the fuzz barely reached the laws");
        }
    };
}

// Every law of the C API in both precisions (the list of `c_laws!`).
fuzz!(
    fuzz_paper_f32,
    f32,
    wmr_robot_params_f32_paper,
    wmr_robot_f32_init,
    wmr_robot_f32,
    wmr_drive_params_f32_default,
    wmr_drive_f32_init,
    wmr_drive_f32,
    wmr_wheel_stage_params_f32_default,
    wmr_plant_f32_init,
    wmr_plant_f32_apply,
    wmr_plant_f32_step,
    wmr_plant_f32_state,
    wmr_plant_f32,
    wmr_sensor_f32_init_perfect,
    wmr_sensor_params_f32_default,
    wmr_sensor_f32_init_pose,
    wmr_sensor_f32_measure,
    wmr_sensor_f32_reset,
    wmr_sensor_f32,
    wmr_paper_params_f32_default,
    wmr_paper_params<f32>,
    wmr_paper_controller_f32_init,
    wmr_paper_controller_f32_update,
    wmr_paper_controller_f32_update_reference,
    wmr_paper_controller_f32_reset,
    wmr_paper_controller_f32_init_observer,
    wmr_paper_controller_f32_disturbance,
    wmr_paper_controller_f32
);
fuzz!(
    fuzz_paper_f64,
    f64,
    wmr_robot_params_f64_paper,
    wmr_robot_f64_init,
    wmr_robot_f64,
    wmr_drive_params_f64_default,
    wmr_drive_f64_init,
    wmr_drive_f64,
    wmr_wheel_stage_params_f64_default,
    wmr_plant_f64_init,
    wmr_plant_f64_apply,
    wmr_plant_f64_step,
    wmr_plant_f64_state,
    wmr_plant_f64,
    wmr_sensor_f64_init_perfect,
    wmr_sensor_params_f64_default,
    wmr_sensor_f64_init_pose,
    wmr_sensor_f64_measure,
    wmr_sensor_f64_reset,
    wmr_sensor_f64,
    wmr_paper_params_f64_default,
    wmr_paper_params<f64>,
    wmr_paper_controller_f64_init,
    wmr_paper_controller_f64_update,
    wmr_paper_controller_f64_update_reference,
    wmr_paper_controller_f64_reset,
    wmr_paper_controller_f64_init_observer,
    wmr_paper_controller_f64_disturbance,
    wmr_paper_controller_f64
);
fuzz!(
    fuzz_paper_bidirectional_f32,
    f32,
    wmr_robot_params_f32_paper,
    wmr_robot_f32_init,
    wmr_robot_f32,
    wmr_drive_params_f32_default,
    wmr_drive_f32_init,
    wmr_drive_f32,
    wmr_wheel_stage_params_f32_default,
    wmr_plant_f32_init,
    wmr_plant_f32_apply,
    wmr_plant_f32_step,
    wmr_plant_f32_state,
    wmr_plant_f32,
    wmr_sensor_f32_init_perfect,
    wmr_sensor_params_f32_default,
    wmr_sensor_f32_init_pose,
    wmr_sensor_f32_measure,
    wmr_sensor_f32_reset,
    wmr_sensor_f32,
    wmr_paper_bidirectional_params_f32_default,
    wmr_paper_bidirectional_params<f32>,
    wmr_paper_bidirectional_controller_f32_init,
    wmr_paper_bidirectional_controller_f32_update,
    wmr_paper_bidirectional_controller_f32_update_reference,
    wmr_paper_bidirectional_controller_f32_reset,
    wmr_paper_bidirectional_controller_f32_init_observer,
    wmr_paper_bidirectional_controller_f32_disturbance,
    wmr_paper_bidirectional_controller_f32
);
fuzz!(
    fuzz_paper_bidirectional_f64,
    f64,
    wmr_robot_params_f64_paper,
    wmr_robot_f64_init,
    wmr_robot_f64,
    wmr_drive_params_f64_default,
    wmr_drive_f64_init,
    wmr_drive_f64,
    wmr_wheel_stage_params_f64_default,
    wmr_plant_f64_init,
    wmr_plant_f64_apply,
    wmr_plant_f64_step,
    wmr_plant_f64_state,
    wmr_plant_f64,
    wmr_sensor_f64_init_perfect,
    wmr_sensor_params_f64_default,
    wmr_sensor_f64_init_pose,
    wmr_sensor_f64_measure,
    wmr_sensor_f64_reset,
    wmr_sensor_f64,
    wmr_paper_bidirectional_params_f64_default,
    wmr_paper_bidirectional_params<f64>,
    wmr_paper_bidirectional_controller_f64_init,
    wmr_paper_bidirectional_controller_f64_update,
    wmr_paper_bidirectional_controller_f64_update_reference,
    wmr_paper_bidirectional_controller_f64_reset,
    wmr_paper_bidirectional_controller_f64_init_observer,
    wmr_paper_bidirectional_controller_f64_disturbance,
    wmr_paper_bidirectional_controller_f64
);
fuzz!(
    fuzz_polar_f32,
    f32,
    wmr_robot_params_f32_paper,
    wmr_robot_f32_init,
    wmr_robot_f32,
    wmr_drive_params_f32_default,
    wmr_drive_f32_init,
    wmr_drive_f32,
    wmr_wheel_stage_params_f32_default,
    wmr_plant_f32_init,
    wmr_plant_f32_apply,
    wmr_plant_f32_step,
    wmr_plant_f32_state,
    wmr_plant_f32,
    wmr_sensor_f32_init_perfect,
    wmr_sensor_params_f32_default,
    wmr_sensor_f32_init_pose,
    wmr_sensor_f32_measure,
    wmr_sensor_f32_reset,
    wmr_sensor_f32,
    wmr_polar_params_f32_default,
    wmr_polar_params<f32>,
    wmr_polar_controller_f32_init,
    wmr_polar_controller_f32_update,
    wmr_polar_controller_f32_update_reference,
    wmr_polar_controller_f32_reset,
    wmr_polar_controller_f32_init_observer,
    wmr_polar_controller_f32_disturbance,
    wmr_polar_controller_f32
);
fuzz!(
    fuzz_polar_f64,
    f64,
    wmr_robot_params_f64_paper,
    wmr_robot_f64_init,
    wmr_robot_f64,
    wmr_drive_params_f64_default,
    wmr_drive_f64_init,
    wmr_drive_f64,
    wmr_wheel_stage_params_f64_default,
    wmr_plant_f64_init,
    wmr_plant_f64_apply,
    wmr_plant_f64_step,
    wmr_plant_f64_state,
    wmr_plant_f64,
    wmr_sensor_f64_init_perfect,
    wmr_sensor_params_f64_default,
    wmr_sensor_f64_init_pose,
    wmr_sensor_f64_measure,
    wmr_sensor_f64_reset,
    wmr_sensor_f64,
    wmr_polar_params_f64_default,
    wmr_polar_params<f64>,
    wmr_polar_controller_f64_init,
    wmr_polar_controller_f64_update,
    wmr_polar_controller_f64_update_reference,
    wmr_polar_controller_f64_reset,
    wmr_polar_controller_f64_init_observer,
    wmr_polar_controller_f64_disturbance,
    wmr_polar_controller_f64
);
fuzz!(
    fuzz_lyapunov_f32,
    f32,
    wmr_robot_params_f32_paper,
    wmr_robot_f32_init,
    wmr_robot_f32,
    wmr_drive_params_f32_default,
    wmr_drive_f32_init,
    wmr_drive_f32,
    wmr_wheel_stage_params_f32_default,
    wmr_plant_f32_init,
    wmr_plant_f32_apply,
    wmr_plant_f32_step,
    wmr_plant_f32_state,
    wmr_plant_f32,
    wmr_sensor_f32_init_perfect,
    wmr_sensor_params_f32_default,
    wmr_sensor_f32_init_pose,
    wmr_sensor_f32_measure,
    wmr_sensor_f32_reset,
    wmr_sensor_f32,
    wmr_lyapunov_params_f32_default,
    wmr_lyapunov_params<f32>,
    wmr_lyapunov_controller_f32_init,
    wmr_lyapunov_controller_f32_update,
    wmr_lyapunov_controller_f32_update_reference,
    wmr_lyapunov_controller_f32_reset,
    wmr_lyapunov_controller_f32_init_observer,
    wmr_lyapunov_controller_f32_disturbance,
    wmr_lyapunov_controller_f32
);
fuzz!(
    fuzz_lyapunov_f64,
    f64,
    wmr_robot_params_f64_paper,
    wmr_robot_f64_init,
    wmr_robot_f64,
    wmr_drive_params_f64_default,
    wmr_drive_f64_init,
    wmr_drive_f64,
    wmr_wheel_stage_params_f64_default,
    wmr_plant_f64_init,
    wmr_plant_f64_apply,
    wmr_plant_f64_step,
    wmr_plant_f64_state,
    wmr_plant_f64,
    wmr_sensor_f64_init_perfect,
    wmr_sensor_params_f64_default,
    wmr_sensor_f64_init_pose,
    wmr_sensor_f64_measure,
    wmr_sensor_f64_reset,
    wmr_sensor_f64,
    wmr_lyapunov_params_f64_default,
    wmr_lyapunov_params<f64>,
    wmr_lyapunov_controller_f64_init,
    wmr_lyapunov_controller_f64_update,
    wmr_lyapunov_controller_f64_update_reference,
    wmr_lyapunov_controller_f64_reset,
    wmr_lyapunov_controller_f64_init_observer,
    wmr_lyapunov_controller_f64_disturbance,
    wmr_lyapunov_controller_f64
);
