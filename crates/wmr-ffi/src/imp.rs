//! The generic implementation behind the `_f32` and `_f64` entry points: pointer checks,
//! storage tags, conversions between the C structs and the core's types, error reports
//! and the panic guard. Every `unsafe` of the crate is here.

use core::ffi::{CStr, c_char};
use core::marker::PhantomData;
use core::mem::{align_of, size_of};

use wmr_core::controller::{Law, LawContext};
use wmr_core::obstacle::MAX_OBSTACLES;
use wmr_core::reference::waypoints::{FIXED_WORDS, SUBSTEPS};
use wmr_core::reference::{Circle, FigureEight, Line, Waypoints};
use wmr_core::{
    AntiWindup, AnyReference, Controller, DcMotorParams, DisturbanceObserverParams, Drive, DriveParams, HoldMode,
    Measurement, Obstacle, Obstacles, OdometryParams, OdometrySensor, PaperMode, ParamError, PerfectSensor, Plant,
    Pose2, PoseSensor, PoseSource, Real, Reason, Reference, ReferenceState, Robot, RobotParams, Sensor, SensorParams,
    State, Termination, TorqueDriveParams, TractionKind, TractionParams, Twist2, WheelStage, WheelStageParams, Wheels,
};

use crate::*;

/// The listed fields of `$v` with their names, `$prefix.field` (as `err` names them):
/// what the finiteness checks go through.
macro_rules! named {
    ($prefix:literal, $v:expr; $($($f:ident).+),+ $(,)?) => {
        [$( (concat!($prefix $(, ".", stringify!($f))+), $v$(.$f)+) ),+]
    };
}

/// The numbers of a reference state (`wmr_reference_state` or the core's
/// `ReferenceState`), named `$prefix.pose.x` and so on.
macro_rules! reference_fields {
    ($prefix:literal, $v:expr) => {
        named!($prefix, $v; pose.x, pose.y, pose.theta, twist.v, twist.omega, accel.v, accel.omega)
    };
}

/// The numbers of a `wmr_measurement`, named `$prefix.t`, `$prefix.pose.x` and so on.
macro_rules! measurement_fields {
    ($prefix:literal, $v:expr) => {
        named!($prefix, $v; t, pose.x, pose.y, pose.theta, wheel_angles.right, wheel_angles.left, wheel_speeds.right, wheel_speeds.left)
    };
}

/// Why a call failed, before it is written into a [`wmr_error`].
#[derive(Clone, Copy, Debug)]
pub struct Fail {
    code: wmr_status,
    field: &'static str,
    reason: &'static str,
    value: f64,
}

impl Fail {
    fn null(arg: &'static str) -> Self {
        Fail { code: wmr_status::WMR_NULL_POINTER, field: arg, reason: "must not be NULL", value: 0.0 }
    }

    fn not_initialized(arg: &'static str) -> Self {
        Fail {
            code: wmr_status::WMR_NOT_INITIALIZED,
            field: arg,
            reason: "was not filled by the matching *_init function",
            value: 0.0,
        }
    }

    fn out_of_range(field: &'static str, reason: &'static str, value: f64) -> Self {
        Fail { code: wmr_status::WMR_OUT_OF_RANGE, field, reason, value }
    }

    fn not_finite(field: &'static str, value: f64) -> Self {
        Fail { code: wmr_status::WMR_NOT_FINITE, field, reason: "must be a finite number", value }
    }

    fn misaligned(arg: &'static str) -> Self {
        Fail {
            code: wmr_status::WMR_MISALIGNED,
            field: arg,
            reason: "is not aligned for its type (storage: WMR_STORAGE_ALIGN bytes)",
            value: 0.0,
        }
    }

    fn corrupted(arg: &'static str, reason: &'static str) -> Self {
        Fail { code: wmr_status::WMR_CORRUPTED, field: arg, reason, value: 0.0 }
    }

    /// A non-finite value the library computed, refused instead of returned.
    fn not_finite_output(field: &'static str, value: f64) -> Self {
        Fail { code: wmr_status::WMR_NOT_FINITE, field, reason: "came out non-finite; nothing was changed", value }
    }

    #[cfg(feature = "std")]
    fn panic() -> Self {
        Fail { code: wmr_status::WMR_PANIC, field: "", reason: "internal error (a Rust panic was caught)", value: 0.0 }
    }
}

impl From<ParamError> for Fail {
    fn from(e: ParamError) -> Self {
        let (code, reason) = match e.reason {
            Reason::NotFinite => (wmr_status::WMR_NOT_FINITE, "must be a finite number"),
            Reason::NotPositive => (wmr_status::WMR_NOT_POSITIVE, "must be > 0"),
            Reason::Negative => (wmr_status::WMR_NEGATIVE, "must be >= 0"),
            Reason::NotMultipleOfDt => {
                (wmr_status::WMR_NOT_MULTIPLE_OF_DT, "must be a whole multiple of the plant step dt")
            }
            Reason::NaN => (wmr_status::WMR_NAN, "must not be NaN"),
            Reason::OutOfRange(why) => (wmr_status::WMR_OUT_OF_RANGE, why),
            // A reason added to the core later: still out of range, with a plain message.
            _ => (wmr_status::WMR_OUT_OF_RANGE, "is out of range"),
        };
        Fail { code, field: e.field, reason, value: e.value }
    }
}

/// Copies `s` into `dst` as a NUL-terminated string, cut to fit.
fn copy_c(dst: &mut [c_char], s: &str) {
    let n = s.len().min(dst.len().saturating_sub(1));
    for (d, b) in dst.iter_mut().zip(&s.as_bytes()[..n]) {
        *d = *b as c_char;
    }
    for d in dst.iter_mut().skip(n) {
        *d = 0;
    }
}

/// Writes the result of a call into `err` (when not NULL) and returns its code.
fn report(err: *mut wmr_error, r: Result<(), Fail>) -> wmr_status {
    let fail = match r {
        Ok(()) => Fail { code: wmr_status::WMR_OK, field: "", reason: "", value: 0.0 },
        Err(f) => f,
    };
    if !err.is_null() && !err.is_aligned() {
        // Nowhere to write the details: the code says why.
        return wmr_status::WMR_MISALIGNED;
    }
    // SAFETY: the caller passes NULL or a pointer valid for writes of a wmr_error
    // (aligned: checked above).
    if let Some(e) = unsafe { err.as_mut() } {
        e.code = fail.code;
        e.value = fail.value;
        copy_c(&mut e.field, fail.field);
        copy_c(&mut e.reason, fail.reason);
    }
    fail.code
}

/// Runs an entry point's body. With `std`, under `catch_unwind`: a panic becomes
/// `WMR_PANIC` and never unwinds into C.
pub fn guard(err: *mut wmr_error, f: impl FnOnce() -> Result<(), Fail>) -> wmr_status {
    #[cfg(feature = "std")]
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|_| Err(Fail::panic()));
    #[cfg(not(feature = "std"))]
    let r = f();
    report(err, r)
}

/// The no_std build's panic handler. `firmware/check` links every entry point for the
/// Cortex-M4F with `--gc-sections` and lists the functions left that can panic: only the
/// core pose sensor's two sites (a division by its ticks per sample and a ring index,
/// both in range by construction). Were one reached, the core stops with a permanently
/// undefined instruction, a HardFault the firmware handles as any other fault: nothing
/// unwinds into C.
#[cfg(all(feature = "panic-handler", not(feature = "std"), not(test)))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {
        #[cfg(target_arch = "arm")]
        // SAFETY: `udf` only raises the UsageFault/HardFault exception.
        unsafe {
            core::arch::asm!("udf #0");
        }
    }
}

/// The name of a status code as a C string.
pub fn status_name(code: i32) -> &'static CStr {
    use wmr_status::*;
    const ALL: [(wmr_status, &CStr); 14] = [
        (WMR_OK, c"WMR_OK"),
        (WMR_NOT_FINITE, c"WMR_NOT_FINITE"),
        (WMR_NOT_POSITIVE, c"WMR_NOT_POSITIVE"),
        (WMR_NEGATIVE, c"WMR_NEGATIVE"),
        (WMR_NOT_MULTIPLE_OF_DT, c"WMR_NOT_MULTIPLE_OF_DT"),
        (WMR_NAN, c"WMR_NAN"),
        (WMR_OUT_OF_RANGE, c"WMR_OUT_OF_RANGE"),
        (WMR_NULL_POINTER, c"WMR_NULL_POINTER"),
        (WMR_NOT_INITIALIZED, c"WMR_NOT_INITIALIZED"),
        (WMR_DIVERGED_NON_FINITE, c"WMR_DIVERGED_NON_FINITE"),
        (WMR_DIVERGED_LEFT_BOX, c"WMR_DIVERGED_LEFT_BOX"),
        (WMR_PANIC, c"WMR_PANIC"),
        (WMR_MISALIGNED, c"WMR_MISALIGNED"),
        (WMR_CORRUPTED, c"WMR_CORRUPTED"),
    ];
    ALL.iter().find(|(s, _)| *s as i32 == code).map_or(c"WMR_UNKNOWN", |(_, n)| n)
}

// ---------------------------------------------------------------------------------------
// Storage: a tag word, then the Rust value.

/// A storage struct of the header and the Rust value it holds.
pub trait Storage {
    /// The Rust object.
    type Value: Copy;
    /// Tag written by `init`; a different one per storage type, so uninitialized storage
    /// and storage of another type are refused.
    const TAG: u64;
    /// Compile-time proof that the value fits (evaluated where the storage is used).
    const FITS: ();
    /// What can be checked of a stored value whose tag is intact (a caller's stray write
    /// may have changed its body): `WMR_CORRUPTED` when it fails.
    fn check(_value: &Self::Value) -> Result<(), &'static str> {
        Ok(())
    }
}

#[repr(C)]
struct Slot<V> {
    tag: u64,
    value: V,
}

macro_rules! storage_of {
    ($($s:ty => $v:ty, $tag:expr $(, check $check:path)?;)+) => {$(
        impl Storage for $s {
            type Value = $v;
            const TAG: u64 = $tag;
            const FITS: () = assert!(
                size_of::<Slot<$v>>() <= size_of::<$s>() && align_of::<Slot<$v>>() <= WMR_STORAGE_ALIGN,
                "storage too small: raise its WORDS constant in lib.rs and WMR_ABI_VERSION"
            );
            $(
                fn check(value: &Self::Value) -> Result<(), &'static str> {
                    $check(value)
                }
            )?
        }
    )+};
}

/// A stored robot is its parameters validated: validating them again gives it back.
fn check_robot<T: Real>(robot: &Robot<T>) -> Result<(), &'static str> {
    match robot.params().validate() {
        Ok(again) if again == *robot => Ok(()),
        _ => Err("was overwritten: its parameters no longer validate to it"),
    }
}

/// A stored plant: its robot checks, its state is finite and inside the divergence box,
/// its held command is finite.
fn check_plant<T: Real>(plant: &Plant<T>) -> Result<(), &'static str> {
    check_robot(plant.robot())?;
    let s = plant.state();
    let bound = T::lit(wmr_core::plant::DIVERGENCE_BOX_M);
    let c = plant.command();
    if !s.is_finite() || s.x.abs() > bound || s.y.abs() > bound || !c.right.is_finite() || !c.left.is_finite() {
        return Err("was overwritten: its state or held command is not finite, or C is outside the 1 km box");
    }
    Ok(())
}

/// The sensor models behind `wmr_sensor_*`. A new model is a variant here, an init
/// function per precision, and (if larger) more words in the storage.
#[derive(Clone, Copy, Debug)]
pub enum AnySensor<T> {
    /// The true pose and wheel state, instantly.
    Perfect(PerfectSensor, PhantomData<T>),
    /// Rate, latency, noise and encoder counts.
    Pose(PoseSensor<T, WMR_SENSOR_SAMPLES_IN_FLIGHT>),
    /// Dead reckoning from the encoders, fused by the EKF with absolute fixes.
    Odometry(OdometrySensor<T, WMR_SENSOR_SAMPLES_IN_FLIGHT>),
}

impl<T: Real> AnySensor<T> {
    /// The measurement of the plant's state with its wheels' own speeds (under slip they
    /// differ from the body's).
    fn measure(&mut self, t: T, state: &State<T>, wheel_speeds: Wheels<T>, robot: &RobotParams<T>) -> Measurement<T> {
        match self {
            AnySensor::Perfect(s, _) => s.measure_wheels(t, state, wheel_speeds, robot),
            AnySensor::Pose(s) => s.measure_wheels(t, state, wheel_speeds, robot),
            AnySensor::Odometry(s) => s.measure_wheels(t, state, wheel_speeds, robot),
        }
    }

    fn reset(&mut self) {
        match self {
            AnySensor::Perfect(s, _) => Sensor::<T>::reset(s),
            AnySensor::Pose(s) => s.reset(),
            AnySensor::Odometry(s) => s.reset(),
        }
    }
}

/// The storage of a C reference's waypoints path: its own array of
/// `WMR_REFERENCE_MAX_POINTS` points (`_init_waypoints`), or numbers the caller owns
/// (`_init_waypoints_in`), which must outlive the reference and stay unchanged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RefWords<T> {
    /// The reference's own fixed storage.
    Own([T; FIXED_WORDS]),
    /// `len` numbers at `ptr`, the caller's.
    Caller {
        /// Start (not NULL, aligned: checked when built).
        ptr: *const T,
        /// Numbers.
        len: usize,
    },
}

impl<T> AsRef<[T]> for RefWords<T> {
    fn as_ref(&self) -> &[T] {
        match self {
            RefWords::Own(a) => a,
            // SAFETY: `ptr` was a valid, aligned `&mut [T]` of `len` numbers when the
            // reference was built, and the caller keeps it alive and unchanged while it
            // uses the reference (the contract of `_init_waypoints_in`).
            RefWords::Caller { ptr, len } => unsafe { core::slice::from_raw_parts(*ptr, *len) },
        }
    }
}

/// A C reference: any kind, a waypoints path in [`RefWords`].
pub type CReference<T> = AnyReference<T, RefWords<T>>;

storage_of! {
    wmr_robot_f32 => Robot<f32>, 0x574d_5201_0000_0f32, check check_robot;
    wmr_robot_f64 => Robot<f64>, 0x574d_5201_0000_0f64, check check_robot;
    wmr_drive_f32 => Drive<f32>, 0x574d_5202_0000_0f32;
    wmr_drive_f64 => Drive<f64>, 0x574d_5202_0000_0f64;
    wmr_plant_f32 => Plant<f32>, 0x574d_5203_0000_0f32, check check_plant;
    wmr_plant_f64 => Plant<f64>, 0x574d_5203_0000_0f64, check check_plant;
    wmr_sensor_f32 => AnySensor<f32>, 0x574d_5204_0000_0f32;
    wmr_sensor_f64 => AnySensor<f64>, 0x574d_5204_0000_0f64;
    wmr_reference_f32 => CReference<f32>, 0x574d_520c_0000_0f32;
    wmr_reference_f64 => CReference<f64>, 0x574d_520c_0000_0f64;
    wmr_obstacles_f32 => Obstacles<f32>, 0x574d_520d_0000_0f32;
    wmr_obstacles_f64 => Obstacles<f64>, 0x574d_520d_0000_0f64;
}

/// Fills `out` with `value` and its tag.
fn put<S: Storage>(out: *mut S, arg: &'static str, value: S::Value) -> Result<(), Fail> {
    let () = S::FITS;
    if out.is_null() {
        return Err(Fail::null(arg));
    }
    if !out.is_aligned() {
        return Err(Fail::misaligned(arg));
    }
    // SAFETY: `out` is valid for writes of S (caller contract), aligned (checked), S is at least as large
    // and as aligned as Slot<Value> (FITS), and Slot is plain data.
    unsafe { out.cast::<Slot<S::Value>>().write(Slot { tag: S::TAG, value }) };
    Ok(())
}

/// The value in initialized storage.
fn get<'a, S: Storage>(p: *const S, arg: &'static str) -> Result<&'a S::Value, Fail> {
    let () = S::FITS;
    if p.is_null() {
        return Err(Fail::null(arg));
    }
    if !p.is_aligned() {
        return Err(Fail::misaligned(arg));
    }
    let slot = p.cast::<Slot<S::Value>>();
    // SAFETY: `p` is valid for reads of S (caller contract) and aligned (checked); the
    // tag is a plain u64.
    let tag = unsafe { core::ptr::addr_of!((*slot).tag).read() };
    if tag != S::TAG {
        return Err(Fail::not_initialized(arg));
    }
    // SAFETY: the tag says `put` wrote a valid value of this type here.
    let value = unsafe { &(*slot).value };
    S::check(value).map_err(|why| Fail::corrupted(arg, why))?;
    Ok(value)
}

/// The value in initialized storage, mutably.
fn get_mut<'a, S: Storage>(p: *mut S, arg: &'static str) -> Result<&'a mut S::Value, Fail> {
    get::<S>(p, arg)?;
    // SAFETY: as in `get`; `p` is valid for writes and not aliased during the call.
    Ok(unsafe { &mut (*p.cast::<Slot<S::Value>>()).value })
}

/// Reads a C input struct.
fn read<'a, X>(p: *const X, arg: &'static str) -> Result<&'a X, Fail> {
    read_or_null(p, arg)?.ok_or(Fail::null(arg))
}

/// Reads a C input struct that may be NULL (`None`).
fn read_or_null<'a, X>(p: *const X, arg: &'static str) -> Result<Option<&'a X>, Fail> {
    if !p.is_aligned() {
        return Err(Fail::misaligned(arg));
    }
    // SAFETY: NULL or valid for reads of X (caller contract) and aligned (checked); the C
    // structs here are plain numbers, valid for any bit pattern.
    Ok(unsafe { p.as_ref() })
}

/// Writes a C output struct.
fn write<X>(p: *mut X, arg: &'static str, value: X) -> Result<(), Fail> {
    if p.is_null() {
        return Err(Fail::null(arg));
    }
    if !p.is_aligned() {
        return Err(Fail::misaligned(arg));
    }
    // SAFETY: valid for writes of X (caller contract) and aligned (checked).
    unsafe { p.write(value) };
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Conversions.

fn pose<T: Real>(p: wmr_pose<T>) -> Pose2<T> {
    Pose2::new(p.x, p.y, p.theta)
}

fn c_pose<T: Real>(p: Pose2<T>) -> wmr_pose<T> {
    wmr_pose { x: p.x, y: p.y, theta: p.theta }
}

fn c_wheels<T: Real>(w: Wheels<T>) -> wmr_wheels<T> {
    wmr_wheels { right: w.right, left: w.left }
}

fn drive_params<T: Real>(p: &wmr_drive_params<T>) -> Result<DriveParams<T>, Fail> {
    match p.kind {
        WMR_DRIVE_TORQUE => Ok(DriveParams::Torque(TorqueDriveParams {
            motor_torque_max: p.motor_torque_max,
            // The C struct has no deadband yet (issue 42): none.
            ..TorqueDriveParams::default()
        })),
        WMR_DRIVE_DC_MOTOR => Ok(DriveParams::DcMotor(DcMotorParams {
            voltage_max: p.voltage_max,
            torque_constant: p.torque_constant,
            back_emf_constant: p.back_emf_constant,
            armature_resistance: p.armature_resistance,
            current_max: p.current_max,
            // The C struct has no deadband yet (issue 42): none.
            ..DcMotorParams::default()
        })),
        k => Err(Fail::out_of_range("kind", "must be WMR_DRIVE_TORQUE (0) or WMR_DRIVE_DC_MOTOR (1)", f64::from(k))),
    }
}

/// Both kinds' defaults, with `kind` set: a C struct holds the keys of both.
fn c_drive_params<T: Real>(kind: u32) -> Result<wmr_drive_params<T>, Fail> {
    let t = TorqueDriveParams::<T>::default();
    let d = DcMotorParams::<T>::default();
    drive_params(&wmr_drive_params::<T> { kind, ..Default::default() })?;
    Ok(wmr_drive_params {
        kind,
        motor_torque_max: t.motor_torque_max,
        voltage_max: d.voltage_max,
        torque_constant: d.torque_constant,
        back_emf_constant: d.back_emf_constant,
        armature_resistance: d.armature_resistance,
        current_max: d.current_max,
    })
}

fn flag(field: &'static str, v: u32) -> Result<bool, Fail> {
    match v {
        0 => Ok(false),
        1 => Ok(true),
        v => Err(Fail::out_of_range(field, "must be 0 or 1", f64::from(v))),
    }
}

/// A core enum a C struct holds as a `uint32_t` (`#[repr(u32)]` in the core): the codes
/// C may write there.
pub(crate) trait CEnum: Copy + 'static {
    /// Every variant.
    const ALL: &'static [Self];
    /// Why another code is refused.
    const REASON: &'static str;
    /// The variant's C code (its discriminant).
    fn code(self) -> u32;
}

impl CEnum for PaperMode {
    const ALL: &'static [Self] = &[PaperMode::Pose, PaperMode::Position];
    const REASON: &'static str = "must be WMR_PAPER_MODE_POSE (0) or WMR_PAPER_MODE_POSITION (1)";
    fn code(self) -> u32 {
        self as u32
    }
}

impl CEnum for HoldMode {
    const ALL: &'static [Self] = &[HoldMode::ZeroErrors, HoldMode::Freeze, HoldMode::Auto];
    const REASON: &'static str = "must be WMR_HOLD_ZERO_ERRORS (0), WMR_HOLD_FREEZE (1) or WMR_HOLD_AUTO (2)";
    fn code(self) -> u32 {
        self as u32
    }
}

impl CEnum for PoseSource {
    const ALL: &'static [Self] = &[PoseSource::Absolute, PoseSource::Odometry];
    const REASON: &'static str = "must be WMR_POSE_ABSOLUTE (0) or WMR_POSE_ODOMETRY (1)";
    fn code(self) -> u32 {
        self as u32
    }
}

impl CEnum for TractionKind {
    const ALL: &'static [Self] = &[TractionKind::Rolling, TractionKind::Slip];
    const REASON: &'static str = "must be WMR_TRACTION_ROLLING (0) or WMR_TRACTION_SLIP (1)";
    fn code(self) -> u32 {
        self as u32
    }
}

impl CEnum for wmr_core::MotionModel {
    const ALL: &'static [Self] = &[wmr_core::MotionModel::Kinematic, wmr_core::MotionModel::Dynamic];
    const REASON: &'static str = "must be WMR_MOTION_MODEL_KINEMATIC (0) or WMR_MOTION_MODEL_DYNAMIC (1)";
    fn code(self) -> u32 {
        self as u32
    }
}

impl CEnum for AntiWindup {
    const ALL: &'static [Self] = &[AntiWindup::Off, AntiWindup::Conditional];
    const REASON: &'static str = "must be WMR_ANTI_WINDUP_OFF (0) or WMR_ANTI_WINDUP_CONDITIONAL (1)";
    fn code(self) -> u32 {
        self as u32
    }
}

/// Refuses a `uint32_t` that is not a code of `E`.
pub(crate) fn enum_code<E: CEnum>(field: &'static str, code: u32) -> Result<(), Fail> {
    if E::ALL.iter().any(|e| e.code() == code) {
        Ok(())
    } else {
        Err(Fail::out_of_range(field, E::REASON, f64::from(code)))
    }
}

/// A law's C parameter struct and the core's parameters it stands for.
pub trait CParams: Copy {
    /// The core's parameter struct.
    type Core: Copy;
    /// Reads the C struct at `p` as the core's parameters, refusing a code that is not
    /// one of the C constants by its field name.
    ///
    /// # Safety
    /// `p` is not NULL and valid for reads of `Self`.
    unsafe fn read_core(p: *const Self) -> Result<Self::Core, Fail>;
    /// The C struct of the core's parameters.
    fn from_core(core: Self::Core) -> Self;
}

/// [`CParams`] for the C structs. `alias Core { enum fields }`: the C struct is the
/// core's `#[repr(C)]` type, its enum fields checked as `uint32_t` before the struct is
/// read. `mirror C = Core { float fields; flags }`: a C struct of the core's fields, its
/// `bool`s as 0/1 `uint32_t`.
macro_rules! c_params {
    ($(alias $core:ident { $($enum_field:ident: $enum:ty),* $(,)? };)*
     $(mirror $c:ident = $mcore:ident { $($float:ident),* ; flags $($flag:ident),* $(,)? };)*) => {
        $(
            impl<T: wmr_core::Real> $crate::imp::CParams for wmr_core::$core<T> {
                type Core = Self;
                unsafe fn read_core(p: *const Self) -> Result<Self, $crate::imp::Fail> {
                    $(
                        // SAFETY: `p` is valid for reads (contract) and the field is a
                        // `#[repr(u32)]` enum, so 4 readable bytes; read as a plain u32.
                        let code = unsafe { core::ptr::addr_of!((*p).$enum_field).cast::<u32>().read() };
                        $crate::imp::enum_code::<$enum>(stringify!($enum_field), code)?;
                    )*
                    // SAFETY: every enum field holds a valid discriminant (checked above)
                    // and the other fields are floats, valid for any bits.
                    Ok(unsafe { p.read() })
                }
                fn from_core(core: Self) -> Self {
                    core
                }
            }
        )*
        $(
            impl<T: wmr_core::Real> $crate::imp::CParams for $c<T> {
                type Core = wmr_core::$mcore<T>;
                unsafe fn read_core(p: *const Self) -> Result<wmr_core::$mcore<T>, $crate::imp::Fail> {
                    // SAFETY: valid for reads (contract); plain numbers, any bits valid.
                    let c = unsafe { p.read() };
                    Ok(wmr_core::$mcore { $($float: c.$float,)* $($flag: $crate::imp::flag(stringify!($flag), c.$flag)?,)* })
                }
                fn from_core(core: wmr_core::$mcore<T>) -> Self {
                    $c { $($float: core.$float,)* $($flag: u32::from(core.$flag),)* }
                }
            }
        )*
    };
}

// Every law's C parameter struct (the list is generated: `laws.rs`).
crate::laws::for_each_c_params!(c_params);

// The odometry sensor's and the slip plant's C structs: the core's own.
c_params! {
    alias OdometryParams { pose: PoseSource };
    alias TractionParams { traction: TractionKind };
}

/// A law of the C API: its C parameter struct and how it becomes the core's law.
pub trait CLaw<T: Prec> {
    /// The C parameter struct.
    type Params: CParams;
    /// The core's law.
    type Law: Law<T> + Copy;
    /// The storage of the law with its wheel stage.
    type Storage: Storage<Value = Controller<T, Self::Law>>;
    /// What the law follows (the registry's `follows`): a path-following law is only
    /// updated on a reference's path.
    const FOLLOWS: wmr_core::Follows;
    /// The default parameters.
    fn defaults() -> Self::Params;
    /// Validates and builds the law for what the controller knows ([`LawContext`]: the
    /// robot model, the drive, the wheel speed limit, the obstacles, the period, the run),
    /// as the scenario builds it.
    fn build(p: <Self::Params as CParams>::Core, ctx: &LawContext<'_, T>) -> Result<Self::Law, Fail>;
}

/// Defines, from the registry (`wmr_core::for_each_law!`): a marker type per law with its
/// [`CLaw`], the storage of each law per precision ([`Storage`], [`Prec`]), and [`Prec`]
/// itself. The C entry points of a law are `law_params_default`, `controller_init`,
/// `controller_update`, `controller_update_reference` and `controller_reset` with its
/// marker (`api_f32.rs`, written by `cargo xtask gen` from the registry: xtask/src/ffi_api.rs);
/// its C declarations are in `laws.rs` (`cargo xtask gen`). A
/// storage tag is `0x574d52__00000f32` (f32) or `..0f64`, `__` = 5 + the law's code.
macro_rules! c_laws {
    ($krate:tt; $( $(#[doc = $doc:literal])* $marker:ident($params:ident, $law:ident) = $kind:ident, code $code:literal, follows $follows:ident; )+) => { paste::paste! {
        $( $(#[doc = $doc])* pub struct $marker; )+

        storage_of! {
            $(
                [<wmr_ $kind _controller_f32>] => Controller<f32, $krate::$law<f32>>, 0x574d_5205_0000_0f32 + (($code as u64) << 32);
                [<wmr_ $kind _controller_f64>] => Controller<f64, $krate::$law<f64>>, 0x574d_5205_0000_0f64 + (($code as u64) << 32);
            )+
        }

        /// f32 or f64 with the storage types of that precision.
        #[allow(non_camel_case_types)]
        pub trait Prec: Real {
            /// `wmr_robot_*`.
            type Robot: Storage<Value = Robot<Self>>;
            /// `wmr_drive_*`.
            type Drive: Storage<Value = Drive<Self>>;
            /// `wmr_plant_*`.
            type Plant: Storage<Value = Plant<Self>>;
            /// `wmr_sensor_*`.
            type Sensor: Storage<Value = AnySensor<Self>>;
            /// `wmr_reference_*`.
            type Reference: Storage<Value = CReference<Self>>;
            /// `wmr_obstacles_*`.
            type Obstacles: Storage<Value = Obstacles<Self>>;
            $(
                /// The controller storage of this law.
                type $marker: Storage<Value = Controller<Self, $krate::$law<Self>>>;
            )+
        }

        impl Prec for f32 {
            type Robot = wmr_robot_f32;
            type Drive = wmr_drive_f32;
            type Plant = wmr_plant_f32;
            type Sensor = wmr_sensor_f32;
            type Reference = wmr_reference_f32;
            type Obstacles = wmr_obstacles_f32;
            $( type $marker = [<wmr_ $kind _controller_f32>]; )+
        }

        impl Prec for f64 {
            type Robot = wmr_robot_f64;
            type Drive = wmr_drive_f64;
            type Plant = wmr_plant_f64;
            type Sensor = wmr_sensor_f64;
            type Reference = wmr_reference_f64;
            type Obstacles = wmr_obstacles_f64;
            $( type $marker = [<wmr_ $kind _controller_f64>]; )+
        }

        $(
            impl<T: Prec> CLaw<T> for $marker {
                type Params = [<wmr_ $kind _params>]<T>;
                type Law = $krate::$law<T>;
                type Storage = <T as Prec>::$marker;
                const FOLLOWS: wmr_core::Follows = wmr_core::Follows::$follows;

                fn defaults() -> Self::Params {
                    CParams::from_core(Default::default())
                }

                fn build(p: <Self::Params as CParams>::Core, ctx: &LawContext<'_, T>) -> Result<Self::Law, Fail> {
                    Ok(wmr_core::LawSpec::build_in::<T>(&p, ctx)?)
                }
            }
        )+
    } };
}

// The C API's laws: the registry's.
wmr_core::for_each_law!(c_laws);

// ---------------------------------------------------------------------------------------
// The entry points, generic; `api_f32.rs` and `api_f64.rs` export them.

pub fn robot_params_paper<T: Prec>(out: *mut wmr_robot_params<T>) -> wmr_status {
    guard(core::ptr::null_mut(), || write(out, "out", RobotParams::<T>::paper()))
}

pub fn robot_init<T: Prec>(out: *mut T::Robot, params: *const wmr_robot_params<T>, err: *mut wmr_error) -> wmr_status {
    guard(err, || {
        let robot = read(params, "params")?.validate()?;
        put(out, "out", robot)
    })
}

pub fn drive_params_default<T: Prec>(kind: u32, out: *mut wmr_drive_params<T>) -> wmr_status {
    guard(core::ptr::null_mut(), || write(out, "out", c_drive_params(kind)?))
}

pub fn drive_init<T: Prec>(
    out: *mut T::Drive,
    params: *const wmr_drive_params<T>,
    robot: *const T::Robot,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        let params = drive_params(read(params, "params")?)?;
        let robot = get(robot, "robot")?;
        put(out, "out", params.validate(robot)?)
    })
}

pub fn wheel_stage_params_default<T: Prec>(
    drive: *const wmr_drive_params<T>,
    model: *const T::Robot,
    out: *mut wmr_wheel_stage_params<T>,
) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        let drive = drive_params(read(drive, "drive")?)?;
        let model = get(model, "model")?;
        write(out, "out", WheelStageParams::for_drive(&drive, model.params()))
    })
}

pub fn law_params_default<T: Prec, L: CLaw<T>>(out: *mut L::Params) -> wmr_status {
    guard(core::ptr::null_mut(), || write(out, "out", L::defaults()))
}

pub fn plant_init<T: Prec>(
    out: *mut T::Plant,
    robot: *const T::Robot,
    drive: *const T::Drive,
    world: *const wmr_world_params<T>,
    start: wmr_pose<T>,
    err: *mut wmr_error,
) -> wmr_status {
    plant_init_traction(out, robot, drive, world, core::ptr::null(), start, err)
}

/// Both plants' init: the rolling plant, or the slip plant of `traction` (NULL: rolling).
pub fn plant_init_traction<T: Prec>(
    out: *mut T::Plant,
    robot: *const T::Robot,
    drive: *const T::Drive,
    world: *const wmr_world_params<T>,
    traction: *const wmr_traction_params<T>,
    start: wmr_pose<T>,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        // NULL: flat ground; rolling wheels.
        let world = read_or_null(world, "world")?.copied().unwrap_or_default().validate()?;
        let robot = *get(robot, "robot")?;
        let plant = Plant::on(robot, *get(drive, "drive")?, world, pose(start))?;
        let traction = match traction.is_null() {
            true => TractionParams::default(),
            false if !traction.is_aligned() => return Err(Fail::misaligned("traction")),
            // SAFETY: not NULL, aligned (checked), valid for reads (caller contract).
            false => unsafe { TractionParams::read_core(traction) }?,
        };
        let traction = traction.validate(&robot, &world)?;
        in_box(["start.x", "start.y"], start.x, start.y)?;
        put(out, "out", plant.with_traction(traction))
    })
}

pub fn traction_params_default<T: Prec>(out: *mut wmr_traction_params<T>) -> wmr_status {
    guard(core::ptr::null_mut(), || write(out, "out", TractionParams::<T>::default()))
}

pub fn plant_wheel_speeds<T: Prec>(plant: *const T::Plant, out: *mut wmr_wheels<T>) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        let speeds = get(plant, "plant")?.wheel_speeds();
        write(out, "out", c_wheels(speeds))
    })
}

pub fn plant_apply<T: Prec>(plant: *mut T::Plant, command: wmr_wheels<T>) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        // A NaN would reach the drive's clamp, which keeps the larger of NaN and -limit:
        // full reverse. Refused here, the held command unchanged.
        finite("command.right", command.right)?;
        finite("command.left", command.left)?;
        get_mut(plant, "plant")?.apply(Wheels::new(command.right, command.left));
        Ok(())
    })
}

pub fn plant_step<T: Prec>(plant: *mut T::Plant, t: T, dt: T) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        finite("t", t)?;
        let plant = get_mut(plant, "plant")?;
        // dt > 0 (a step of 0 or backwards in time is no step of the model) and below
        // the RK4 stability limit of the plant's friction, or for a slip plant within
        // 1000 sub-steps (Plant::substeps, as `ClosedLoop` checks it).
        finite("dt", dt)?;
        if dt <= T::zero() {
            return Err(Fail {
                code: wmr_status::WMR_NOT_POSITIVE,
                field: "dt",
                reason: "must be > 0",
                value: dt.to_f64_lossless(),
            });
        }
        if plant.substeps(dt).is_none() {
            let reason = if plant.slips() {
                "too large for the slip's contacts: more than 1000 RK4 sub-steps of dt * stiffness <= 0.9 x 2.785"
            } else {
                "too large for the plant's friction: RK4 is unstable unless dt * stiffness < 2.785"
            };
            return Err(Fail::out_of_range("dt", reason, dt.to_f64_lossless()));
        }
        plant.step(t, dt).map_err(|term| {
            let code = match term {
                Termination::LeftBox => wmr_status::WMR_DIVERGED_LEFT_BOX,
                _ => wmr_status::WMR_DIVERGED_NON_FINITE,
            };
            Fail { code, field: "state", reason: "the step diverged; the state is unchanged", value: 0.0 }
        })
    })
}

pub fn plant_state<T: Prec>(plant: *const T::Plant, out: *mut wmr_state<T>) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        let state = *get(plant, "plant")?.state();
        write(out, "out", state)
    })
}

pub fn sensor_init_perfect<T: Prec>(out: *mut T::Sensor) -> wmr_status {
    guard(core::ptr::null_mut(), || put(out, "out", AnySensor::Perfect(PerfectSensor, PhantomData)))
}

pub fn sensor_params_default<T: Prec>(out: *mut wmr_sensor_params<T>) -> wmr_status {
    guard(core::ptr::null_mut(), || write(out, "out", SensorParams::<T>::default()))
}

pub fn sensor_init_pose<T: Prec>(
    out: *mut T::Sensor,
    params: *const wmr_sensor_params<T>,
    control_dt: T,
    run: u64,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        let params = *read(params, "params")?;
        let sensor = PoseSensor::new(params, control_dt, run).map_err(|e| {
            let mut fail = Fail::from(e);
            if e.field == "latency" && matches!(e.reason, Reason::OutOfRange(_)) {
                // The core's text counts its own default buffer; this one holds fewer.
                fail.reason = "latency * rate_hz must be below WMR_SENSOR_SAMPLES_IN_FLIGHT - 1 (15)";
            }
            fail
        })?;
        put(out, "out", AnySensor::Pose(sensor))
    })
}

pub fn odometry_params_default<T: Prec>(out: *mut wmr_odometry_params<T>) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        write(out, "out", OdometryParams { pose: PoseSource::Odometry, ..OdometryParams::<T>::default() })
    })
}

pub fn sensor_init_odometry<T: Prec>(
    out: *mut T::Sensor,
    params: *const wmr_sensor_params<T>,
    odometry: *const wmr_odometry_params<T>,
    model: *const T::Robot,
    control_dt: T,
    run: u64,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        let params = *read(params, "params")?;
        if odometry.is_null() {
            return Err(Fail::null("odometry"));
        }
        if !odometry.is_aligned() {
            return Err(Fail::misaligned("odometry"));
        }
        // SAFETY: not NULL, aligned (checked), valid for reads (caller contract).
        let odometry = unsafe { OdometryParams::read_core(odometry) }?;
        let model = get(model, "model")?.params();
        let sensor = OdometrySensor::new(params, odometry, model, control_dt, run).map_err(|e| {
            let mut fail = Fail::from(e);
            if e.field == "latency" && matches!(e.reason, Reason::OutOfRange(_)) {
                // The core's text counts its own default buffer; this one holds fewer.
                fail.reason = "latency * fix_rate_hz must be below WMR_SENSOR_SAMPLES_IN_FLIGHT - 1 (15)";
            }
            fail
        })?;
        put(out, "out", AnySensor::Odometry(sensor))
    })
}

pub fn sensor_odometry<T: Prec>(sensor: *const T::Sensor, out: *mut wmr_odometry_estimate<T>) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        let AnySensor::Odometry(sensor) = get(sensor, "sensor")? else {
            return Err(Fail::out_of_range("sensor", "is not an odometry sensor (wmr_sensor_*_init_odometry)", 0.0));
        };
        let (Some(pose), Some(cov)) = (sensor.dead_reckoning(), sensor.covariance()) else {
            return Err(Fail::out_of_range("sensor", "has not measured yet: no estimate before the first tick", 0.0));
        };
        let c = [cov[0][0], cov[0][1], cov[0][2], cov[1][0], cov[1][1], cov[1][2], cov[2][0], cov[2][1], cov[2][2]];
        write(out, "out", wmr_odometry_estimate { dead_reckoning: c_pose(pose), covariance: c })
    })
}

pub fn sensor_measure<T: Prec>(
    sensor: *mut T::Sensor,
    t: T,
    plant: *const T::Plant,
    out: *mut wmr_measurement<T>,
) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        finite("t", t)?;
        let plant = get(plant, "plant")?;
        let sensor = get_mut(sensor, "sensor")?;
        if out.is_null() {
            return Err(Fail::null("out"));
        }
        // Refused outputs leave the sensor as it was (its ring, noise stream and tick).
        let before = *sensor;
        let m = sensor.measure(t, plant.state(), plant.wheel_speeds(), plant.robot().params());
        let m = wmr_measurement {
            t: m.t,
            pose: c_pose(m.pose),
            wheel_angles: c_wheels(m.wheel_angles),
            wheel_speeds: c_wheels(m.wheel_speeds),
        };
        finite_output(&measurement_fields!("out", m)).inspect_err(|_| *sensor = before)?;
        write(out, "out", m)
    })
}

pub fn sensor_reset<T: Prec>(sensor: *mut T::Sensor) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        get_mut(sensor, "sensor")?.reset();
        Ok(())
    })
}

pub fn controller_init<T: Prec, L: CLaw<T>>(
    out: *mut L::Storage,
    params: *const L::Params,
    wheels: *const wmr_wheel_stage_params<T>,
    model: *const T::Robot,
    drive: *const T::Drive,
    control_dt: T,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || init_controller::<T, L>(out, params, wheels, None, model, drive, control_dt, None))
}

/// [`controller_init`] knowing the obstacles on the controller's map (`obstacles`, NULL:
/// none) and the run whose noise a sampling law draws (`run`; [`LawContext::run`]), as a
/// scenario's run `run` builds its controller: MPPI's `_init_in`.
#[allow(clippy::too_many_arguments)]
pub fn controller_init_in<T: Prec, L: CLaw<T>>(
    out: *mut L::Storage,
    params: *const L::Params,
    wheels: *const wmr_wheel_stage_params<T>,
    model: *const T::Robot,
    drive: *const T::Drive,
    control_dt: T,
    obstacles: *const T::Obstacles,
    run: u64,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        let obstacles = if obstacles.is_null() { Obstacles::default() } else { *get(obstacles, "obstacles")? };
        init_controller::<T, L>(out, params, wheels, None, model, drive, control_dt, Some((&obstacles, run)))
    })
}

/// An empty set of obstacles with the robot's footprint radius (m, about C; nav2's
/// `robot_radius`): `err` names `footprint_radius` when it is negative or not finite.
pub fn obstacles_init<T: Prec>(out: *mut T::Obstacles, footprint_radius: T, err: *mut wmr_error) -> wmr_status {
    guard(err, || put(out, "out", Obstacles::new(&[], footprint_radius)?))
}

/// `obstacles` with `add` appended (circles stay before polygons: the scenario's order
/// and numbering). Refused, `obstacles` unchanged, naming `obstacle.center`,
/// `obstacle.radius`, `obstacle.points` (the obstacle's index as the value) or `obstacle`
/// (more than 16).
fn obstacles_add<T: Prec>(obstacles: *mut T::Obstacles, add: Obstacle<'_, T>) -> Result<(), Fail> {
    let had = get(obstacles.cast_const(), "obstacles")?;
    let mut list = [Obstacle::Circle { center: (T::zero(), T::zero()), radius: T::one() }; MAX_OBSTACLES + 1];
    let mut n = 0;
    for (slot, ob) in list.iter_mut().zip(had.iter()) {
        *slot = ob;
        n += 1;
    }
    if n >= MAX_OBSTACLES {
        return Err(Fail::out_of_range("obstacle", "at most 16 obstacles (MAX_OBSTACLES)", (n + 1) as f64));
    }
    if let Some(slot) = list.get_mut(n) {
        *slot = add;
    }
    let next = Obstacles::new(list.get(..=n).unwrap_or(&[]), had.footprint_radius())?;
    *get_mut(obstacles, "obstacles")? = next;
    Ok(())
}

/// Appends a circle: centre (`x`, `y`), m, world frame, and `radius`, m (> 0).
pub fn obstacles_add_circle<T: Prec>(
    obstacles: *mut T::Obstacles,
    x: T,
    y: T,
    radius: T,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || obstacles_add::<T>(obstacles, Obstacle::Circle { center: (x, y), radius }))
}

/// Appends a polygon of `n` vertices `points` ((x, y), m, world frame, in order, at least
/// 3; 32 in all).
pub fn obstacles_add_polygon<T: Prec>(
    obstacles: *mut T::Obstacles,
    points: *const [T; 2],
    n: usize,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        if points.is_null() {
            return Err(Fail::null("points"));
        }
        if !points.is_aligned() {
            return Err(Fail::misaligned("points"));
        }
        if n > wmr_core::obstacle::MAX_POLYGON_POINTS {
            return Err(Fail::out_of_range(
                "obstacle.points",
                "at most 32 polygon vertices in all (MAX_POLYGON_POINTS)",
                n as f64,
            ));
        }
        let mut xy = [(T::zero(), T::zero()); wmr_core::obstacle::MAX_POLYGON_POINTS];
        for (i, slot) in xy.iter_mut().enumerate().take(n) {
            // SAFETY: `points` is valid for reads of `n` pairs (caller contract), not NULL
            // and aligned (checked); i < n.
            let [x, y] = unsafe { points.add(i).read() };
            *slot = (x, y);
        }
        obstacles_add::<T>(obstacles, Obstacle::Polygon(xy.get(..n).unwrap_or(&[])))
    })
}

pub fn disturbance_observer_params_default<T: Prec>(out: *mut wmr_disturbance_observer_params<T>) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        let DisturbanceObserverParams { bandwidth, deadband, static_friction, precompensation_band } =
            DisturbanceObserverParams::<T>::default();
        write(
            out,
            "out",
            wmr_disturbance_observer_params { bandwidth, deadband, static_friction, precompensation_band },
        )
    })
}

/// [`controller_init`] with the disturbance observer `observer` on the wheel stage, as
/// `wmr_core::ControllerParams::build` puts it (its errors named `observer.bandwidth`, ...).
#[allow(clippy::too_many_arguments)]
pub fn controller_init_observer<T: Prec, L: CLaw<T>>(
    out: *mut L::Storage,
    params: *const L::Params,
    wheels: *const wmr_wheel_stage_params<T>,
    observer: *const wmr_disturbance_observer_params<T>,
    model: *const T::Robot,
    drive: *const T::Drive,
    control_dt: T,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        let observer = read(observer, "observer")?;
        init_controller::<T, L>(out, params, wheels, Some(observer), model, drive, control_dt, None)
    })
}

/// The observer's estimate of the disturbance torque at each wheel at the last tick
/// (N m); `WMR_OUT_OF_RANGE` naming `ctrl` for a controller without an observer.
pub fn controller_disturbance<T: Prec, L: CLaw<T>>(ctrl: *const L::Storage, out: *mut wmr_wheels<T>) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        let ctrl = get(ctrl, "ctrl")?;
        let Some(d) = ctrl.wheels().disturbance_estimate() else {
            return Err(Fail::out_of_range(
                "ctrl",
                "has no disturbance observer (init it with _init_observer)",
                f64::NAN,
            ));
        };
        write(out, "out", c_wheels(d))
    })
}

/// The body of the controller inits: the law, its wheel stage and, if given, the
/// disturbance observer on it.
/// `world`: the obstacles and the run ([`controller_init_in`]); `None`: none, run 0.
#[allow(clippy::too_many_arguments)]
fn init_controller<T: Prec, L: CLaw<T>>(
    out: *mut L::Storage,
    params: *const L::Params,
    wheels: *const wmr_wheel_stage_params<T>,
    observer: Option<&wmr_disturbance_observer_params<T>>,
    model: *const T::Robot,
    drive: *const T::Drive,
    control_dt: T,
    world: Option<(&Obstacles<T>, u64)>,
) -> Result<(), Fail> {
    if params.is_null() {
        return Err(Fail::null("params"));
    }
    if !params.is_aligned() {
        return Err(Fail::misaligned("params"));
    }
    let wheels = *read(wheels, "wheels")?;
    let model = get(model, "model")?.params();
    let drive = get(drive, "drive")?;
    // SAFETY: not NULL, aligned (checked), and valid for reads of the C struct (caller
    // contract).
    let params = unsafe { L::Params::read_core(params) }?;
    let none = Obstacles::default();
    let (obstacles, run) = world.unwrap_or((&none, 0));
    let ctx = LawContext {
        model,
        drive: &drive.params(),
        wheel_speed_max: wheels.wheel_speed_max,
        obstacles,
        control_dt,
        run,
    };
    let law = L::build(params, &ctx)?;
    let mut stage = WheelStage::new(&wheels, model, drive, control_dt)?;
    if let Some(o) = observer {
        // Its errors name the keys as the scenario does (`observer.bandwidth`, ...).
        let params = DisturbanceObserverParams {
            bandwidth: o.bandwidth,
            deadband: o.deadband,
            static_friction: o.static_friction,
            precompensation_band: o.precompensation_band,
        };
        stage = stage.with_observer(params.validate(model, drive, control_dt)?);
    }
    put(out, "out", Controller::new(law, stage))
}

fn finite<T: Real>(field: &'static str, v: T) -> Result<(), Fail> {
    if v.is_finite() { Ok(()) } else { Err(Fail::not_finite(field, v.to_f64_lossless())) }
}

/// Refuses the first non-finite value of an output by its field name
/// (`WMR_NOT_FINITE`, "came out non-finite"): the caller restores what the call changed.
fn finite_output<T: Real>(values: &[(&'static str, T)]) -> Result<(), Fail> {
    match values.iter().find(|(_, v)| !v.is_finite()) {
        Some(&(field, v)) => Err(Fail::not_finite_output(field, v.to_f64_lossless())),
        None => Ok(()),
    }
}

/// A position inside the plant's divergence box (|x|, |y| <= 1 km): where C can be (a
/// plant step past it is refused) and so where a start, a measured pose or a reference
/// can be. `fields` name x and y.
fn in_box<T: Real>(fields: [&'static str; 2], x: T, y: T) -> Result<(), Fail> {
    let bound = T::lit(wmr_core::plant::DIVERGENCE_BOX_M);
    for (field, v) in fields.into_iter().zip([x, y]) {
        // A non-finite value is the finiteness check's to name.
        if v.is_finite() && v.abs() > bound {
            return Err(Fail::out_of_range(
                field,
                "must be within the plant's 1 km box (|x|, |y| <= 1000 m)",
                v.to_f64_lossless(),
            ));
        }
    }
    Ok(())
}

pub fn controller_update<T: Prec, L: CLaw<T>>(
    ctrl: *mut L::Storage,
    t: T,
    m: *const wmr_measurement<T>,
    goal: wmr_pose<T>,
    out: *mut wmr_control_output<T>,
) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        let m = read(m, "measurement")?;
        let goal_fields = [("goal.x", goal.x), ("goal.y", goal.y), ("goal.theta", goal.theta)];
        in_box(["goal.x", "goal.y"], goal.x, goal.y)?;
        tick::<T, L>(ctrl, t, m, &goal_fields, &ReferenceState::at_rest(pose(goal)), out)
    })
}

pub fn controller_update_reference<T: Prec, L: CLaw<T>>(
    ctrl: *mut L::Storage,
    t: T,
    m: *const wmr_measurement<T>,
    reference: *const wmr_reference_state<T>,
    out: *mut wmr_control_output<T>,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        let m = read(m, "measurement")?;
        let r = read(reference, "reference")?;
        in_box(["reference.pose.x", "reference.pose.y"], r.pose.x, r.pose.y)?;
        let fields = reference_fields!("reference", r);
        let state = ReferenceState {
            pose: pose(r.pose),
            twist: Twist2 { v: r.twist.v, omega: r.twist.omega },
            accel: Twist2 { v: r.accel.v, omega: r.accel.omega },
        };
        tick::<T, L>(ctrl, t, m, &fields, &state, out)
    })
}

/// One control tick: refuses a non-finite input by its field name (the reference's
/// fields in `reference_fields`), then updates the controller and writes `out`.
fn tick<T: Prec, L: CLaw<T>>(
    ctrl: *mut L::Storage,
    t: T,
    m: &wmr_measurement<T>,
    reference_fields: &[(&'static str, T)],
    reference: &ReferenceState<T>,
    out: *mut wmr_control_output<T>,
) -> Result<(), Fail> {
    tick_on::<T, L>(ctrl, t, m, reference_fields, reference, None, out)
}

/// [`tick`] with the reference's path, when it has one: the law is updated as the
/// scenario loop updates it (`wmr_core::ClosedLoop`), on the path when there is one.
fn tick_on<T: Prec, L: CLaw<T>>(
    ctrl: *mut L::Storage,
    t: T,
    m: &wmr_measurement<T>,
    reference_fields: &[(&'static str, T)],
    reference: &ReferenceState<T>,
    path: Option<&dyn wmr_core::reference::Path<T>>,
    out: *mut wmr_control_output<T>,
) -> Result<(), Fail> {
    if out.is_null() {
        return Err(Fail::null("out"));
    }
    // A path-following law steers by the reference's path: without one it has nothing to
    // follow, and a zero command would pass for an answer.
    if L::FOLLOWS == wmr_core::Follows::Path && path.is_none() {
        return Err(Fail::out_of_range(
            "reference",
            "this law follows a path: call _update_on with a reference that has one",
            f64::NAN,
        ));
    }
    let values = measurement_fields!("measurement", m);
    [("t", t)].iter().chain(&values).chain(reference_fields).try_for_each(|&(f, v)| finite(f, v))?;
    in_box(["measurement.pose.x", "measurement.pose.y"], m.pose.x, m.pose.y)?;
    let ctrl = get_mut(ctrl, "ctrl")?;
    if !out.is_aligned() {
        return Err(Fail::misaligned("out"));
    }
    let m = Measurement {
        t: m.t,
        pose: pose(m.pose),
        wheel_angles: Wheels::new(m.wheel_angles.right, m.wheel_angles.left),
        wheel_speeds: Wheels::new(m.wheel_speeds.right, m.wheel_speeds.left),
    };
    // Finite inputs can still overflow (gains of 1e300, wheel angles of 1e308): such a
    // tick is refused, the controller restored and `out` untouched, as for a bad input.
    let before = *ctrl;
    let o = match path {
        Some(path) => ctrl.update_on_path(t, &m, reference, path),
        None => ctrl.update(t, &m, reference),
    };
    let out_value = wmr_control_output {
        command: c_wheels(o.command),
        e_s: o.errors.e_s,
        e_theta: o.errors.e_theta,
        dl: o.errors.dl,
    };
    finite_output(&named!("out", out_value; command.right, command.left, e_s, e_theta, dl))
        .inspect_err(|_| *ctrl = before)?;
    write(out, "out", out_value)
}

pub fn reference_init_circle<T: Prec>(
    out: *mut T::Reference,
    center: wmr_pose<T>,
    radius: T,
    speed: T,
    phase: T,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        in_box(["center.x", "center.y"], center.x, center.y)?;
        let c = Circle::new(center.x, center.y, radius, speed, phase)?;
        // The whole circle inside the box, as on the scenario path (issue 39 item 14).
        reaches_within("radius", center.x.abs().max(center.y.abs()) + radius, radius)?;
        put(out, "out", CReference::Circle(c))
    })
}

pub fn reference_init_figure_eight<T: Prec>(
    out: *mut T::Reference,
    center: wmr_pose<T>,
    width: T,
    height: T,
    period: T,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        in_box(["center.x", "center.y"], center.x, center.y)?;
        let f = FigureEight::new(center.x, center.y, width, height, period)?;
        reaches_within("width", center.x.abs() + width / T::lit(2.0), width)?;
        reaches_within("height", center.y.abs() + height / T::lit(2.0), height)?;
        put(out, "out", CReference::FigureEight(f))
    })
}

pub fn reference_init_line<T: Prec>(
    out: *mut T::Reference,
    start: wmr_pose<T>,
    speed: T,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        in_box(["start.x", "start.y"], start.x, start.y)?;
        put(out, "out", CReference::Line(Line::new(pose(start), speed)?))
    })
}

/// A figure that reaches `reach` m from the origin along an axis stays inside the box;
/// else refused at `field` (its value `value`).
fn reaches_within<T: Real>(field: &'static str, reach: T, value: T) -> Result<(), Fail> {
    if reach > T::lit(wmr_core::plant::DIVERGENCE_BOX_M) {
        return Err(Fail::out_of_range(
            field,
            "takes the reference outside the plant's 1 km box (|x|, |y| <= 1000 m)",
            value.to_f64_lossless(),
        ));
    }
    Ok(())
}

/// The `n` points at `points`, checked: not NULL, aligned, each inside the box.
fn waypoints_of<'a, T: Prec>(points: *const [T; 2], n: usize) -> Result<&'a [[T; 2]], Fail> {
    if points.is_null() {
        return Err(Fail::null("points"));
    }
    if !points.is_aligned() {
        return Err(Fail::misaligned("points"));
    }
    // SAFETY: not NULL, aligned (checked) and valid for reads of `n` pairs (caller
    // contract), plain numbers.
    let points = unsafe { core::slice::from_raw_parts(points, n) };
    for p in points {
        in_box(["points.x", "points.y"], p[0], p[1])?;
    }
    Ok(points)
}

pub fn reference_init_waypoints<T: Prec>(
    out: *mut T::Reference,
    points: *const [T; 2],
    n: usize,
    speed: T,
    accel_max: T,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        if n > WMR_REFERENCE_MAX_POINTS {
            return Err(Fail::out_of_range(
                "n",
                "must be at most WMR_REFERENCE_MAX_POINTS (64) here: more with _init_waypoints_in",
                n as f64,
            ));
        }
        let points = waypoints_of(points, n)?;
        let w = Waypoints::new(points, speed, accel_max)?.map_storage(RefWords::Own);
        put(out, "out", CReference::Waypoints(w))
    })
}

/// Numbers of storage a waypoints path of `n` points takes (0 when that overflows).
pub fn waypoints_words(n: usize) -> usize {
    // 5 n + 4 ((n - 1) SUBSTEPS + 1), as Waypoints::words, without overflow.
    match n.checked_mul(5 + 4 * SUBSTEPS) {
        Some(w) if n >= 1 => w + 4 - 4 * SUBSTEPS,
        _ => 0,
    }
}

#[allow(clippy::too_many_arguments)]
pub fn reference_init_waypoints_in<T: Prec>(
    out: *mut T::Reference,
    points: *const [T; 2],
    n: usize,
    speed: T,
    accel_max: T,
    storage: *mut T,
    words: usize,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        let points = waypoints_of(points, n)?;
        if storage.is_null() {
            return Err(Fail::null("storage"));
        }
        if !storage.is_aligned() {
            return Err(Fail::misaligned("storage"));
        }
        let need = waypoints_words(n);
        if n >= 2 && (need == 0 || words < need) {
            return Err(Fail::out_of_range(
                "words",
                "is less than the path needs: _waypoints_words(n) = 37 n - 28",
                words as f64,
            ));
        }
        // SAFETY: not NULL, aligned (checked), valid for reads and writes of `words`
        // numbers and not overlapping `points` (caller contract).
        let buf = unsafe { core::slice::from_raw_parts_mut(storage, words) };
        let w = Waypoints::new_in(points, speed, accel_max, buf)?;
        let w = w.map_storage(|b: &mut [T]| RefWords::Caller { ptr: b.as_ptr(), len: b.len() });
        put(out, "out", CReference::Waypoints(w))
    })
}

pub fn reference_state_at<T: Prec>(
    reference: *const T::Reference,
    t: T,
    out: *mut wmr_reference_state<T>,
) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        finite("t", t)?;
        let s = get(reference, "reference")?.state_at(t);
        let value = wmr_reference_state {
            pose: c_pose(s.pose),
            twist: wmr_twist { v: s.twist.v, omega: s.twist.omega },
            accel: wmr_accel { v: s.accel.v, omega: s.accel.omega },
        };
        finite_output(&reference_fields!("out", value))?;
        // A reference state where C cannot be (a line at 1e300 m/s) is refused, `out`
        // untouched (issue 39 item 14).
        in_box(["out.pose.x", "out.pose.y"], s.pose.x, s.pose.y)?;
        write(out, "out", value)
    })
}

pub fn controller_update_on<T: Prec, L: CLaw<T>>(
    ctrl: *mut L::Storage,
    t: T,
    m: *const wmr_measurement<T>,
    reference: *const T::Reference,
    out: *mut wmr_control_output<T>,
    err: *mut wmr_error,
) -> wmr_status {
    guard(err, || {
        let m = read(m, "measurement")?;
        finite("t", t)?;
        let r = get(reference, "reference")?;
        let state = r.state_at(t);
        let fields = reference_fields!("reference", state);
        tick_on::<T, L>(ctrl, t, m, &fields, &state, r.path(), out)
    })
}

pub fn controller_reset<T: Prec, L: CLaw<T>>(ctrl: *mut L::Storage) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        get_mut(ctrl, "ctrl")?.reset();
        Ok(())
    })
}

pub fn controller_for_plant<T: Prec, L: CLaw<T>>(ctrl: *mut L::Storage, plant: *const T::Plant) -> wmr_status {
    guard(core::ptr::null_mut(), || {
        let slips = get(plant, "plant")?.slips();
        let ctrl = get_mut(ctrl, "ctrl")?;
        *ctrl = (*ctrl).with_slipping_wheels(slips);
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guard_turns_a_panic_into_wmr_panic() {
        let mut e = core::mem::MaybeUninit::<wmr_error>::uninit();
        let code = guard(e.as_mut_ptr(), || panic!("a bug"));
        assert_eq!(code, wmr_status::WMR_PANIC);
        // SAFETY: `report` wrote every field.
        let e = unsafe { e.assume_init() };
        assert_eq!(e.code, wmr_status::WMR_PANIC);
    }

    #[test]
    fn copy_c_cuts_and_terminates() {
        let mut b = [1 as c_char; 5];
        copy_c(&mut b, "abcdefgh");
        assert_eq!(b, [b'a' as c_char, b'b' as c_char, b'c' as c_char, b'd' as c_char, 0]);
        copy_c(&mut b, "x");
        assert_eq!(b, [b'x' as c_char, 0, 0, 0, 0]);
    }
}
