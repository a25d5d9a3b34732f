//! `crates/wmr-ffi/include/wmr.h`, the C header, written by cbindgen from the C API's
//! sources and from declarations of the core's `#[repr(C)]` parameter structs and state
//! (cbindgen does not see through the core's `params!` macro, so their fields are spelled
//! out here from the same `FIELDS` tables, in the same order and types: the same layout).

use crate::{Generated, repo_root};
use wmr_core::describe::{Described, ParamField};
use wmr_core::{OdometryParams, RobotParams, SensorParams, TractionParams, WheelStageParams, WorldParams};

/// The C structs that are the core's `#[repr(C)]` parameter structs: the robot, world,
/// sensor and wheel stage, and each law's keys (from the registry) unless a flag makes
/// them a mirror struct (`laws.rs`, `cargo xtask gen`).
pub fn shared_structs() -> Vec<(String, String, &'static [ParamField])> {
    let mut out = vec![
        (
            "wmr_robot_params".to_owned(),
            "Physical robot parameters, SI units (the `[robot]` keys of a scenario).".to_owned(),
            RobotParams::<f64>::FIELDS,
        ),
        (
            "wmr_world_params".to_owned(),
            "The ground (the `[world]` keys): a plane tilted by `slope_deg`, descending towards `slope_direction_deg`.".to_owned(),
            WorldParams::<f64>::FIELDS,
        ),
        (
            "wmr_sensor_params".to_owned(),
            "The pose sensor (the `[sensor]` keys); every default: the perfect sensor, bit for bit. Here latency * rate_hz must be below `WMR_SENSOR_SAMPLES_IN_FLIGHT` - 1.".to_owned(),
            SensorParams::<f64>::FIELDS,
        ),
        (
            "wmr_wheel_stage_params".to_owned(),
            "The wheel stage: two wheel position servos and the curvature-keeping speed limit.".to_owned(),
            WheelStageParams::<f64>::FIELDS,
        ),
        (
            "wmr_odometry_params".to_owned(),
            "The odometry sensor's pose source (the `[sensor]` keys `pose`, `fix_rate_hz`, `odometry_noise`).".to_owned(),
            OdometryParams::<f64>::FIELDS,
        ),
        (
            "wmr_traction_params".to_owned(),
            "The traction model (the `[robot]` keys `traction` to `stiction_length`): rolling or slip.".to_owned(),
            TractionParams::<f64>::FIELDS,
        ),
    ];
    for law in wmr_core::LawParams::<f64>::defaults() {
        if law.fields().iter().all(|f| f.ty != "bool") {
            out.push((
                format!("wmr_{}_params", law.kind()),
                format!("{} (`[controller] kind = \"{}\"`).", law.about().trim_end_matches('.'), law.kind()),
                law.fields(),
            ));
        }
    }
    out
}

/// The C type and the C constants of a core field type that is not `T`: the core's
/// `#[repr(u32)]` enums are `uint32_t` codes in C.
pub fn c_type(ty: &'static str) -> (&'static str, &'static str) {
    match ty {
        "PaperMode" => ("u32", "`WMR_PAPER_MODE_POSE` or `WMR_PAPER_MODE_POSITION`"),
        "HoldMode" => ("u32", "`WMR_HOLD_AUTO`, `WMR_HOLD_ZERO_ERRORS` or `WMR_HOLD_FREEZE`"),
        "AntiWindup" => ("u32", "`WMR_ANTI_WINDUP_OFF` or `WMR_ANTI_WINDUP_CONDITIONAL`"),
        "PoseSource" => ("u32", "`WMR_POSE_ABSOLUTE` or `WMR_POSE_ODOMETRY`"),
        "TractionKind" => ("u32", "`WMR_TRACTION_ROLLING` or `WMR_TRACTION_SLIP`"),
        "MotionModel" => ("u32", "`WMR_MOTION_MODEL_KINEMATIC` or `WMR_MOTION_MODEL_DYNAMIC`"),
        other => (other, ""),
    }
}

/// Rust declarations of [`shared_structs`] for cbindgen (which cannot see through the
/// core's `params!` macro): the same fields, order and types, so the same C layout.
fn shared_structs_source() -> String {
    let mut out = String::new();
    for (name, doc, fields) in shared_structs() {
        out.push_str(&format!("/// {doc}\n#[repr(C)]\npub struct {name}<T> {{\n"));
        for f in fields {
            let unit = if f.unit.is_empty() { String::new() } else { format!(", {}", f.unit) };
            let (ty, constants) = c_type(f.ty);
            let rule = if constants.is_empty() { f.rule } else { constants };
            out.push_str(&format!(
                "    /// {}{unit} ({rule}).\n    pub {}: {ty},\n",
                f.doc.trim_end_matches('.'),
                f.name,
            ));
        }
        out.push_str("}\n\n");
    }
    out
}

/// The core's `#[repr(C)]` `State` (crates/wmr-core/src/state.rs), its declaration as
/// written there, named `wmr_state` for cbindgen (which does not follow the alias in
/// src/lib.rs).
fn core_state_source() -> String {
    let path = repo_root().join("crates/wmr-core/src/state.rs");
    let src = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let decl = src.find("pub struct State<T> {").expect("the core's State");
    let start = src[..decl].rfind("\n\n").expect("a blank line before State's doc") + 2;
    let end = decl + src[decl..].find("\n}\n").expect("the end of State") + 3;
    src[start..end].replace("pub struct State<T>", "pub struct wmr_state<T>")
}

/// The header's text, as cbindgen writes it from `crates/wmr-ffi/src` as it is on disk
/// (so `cargo xtask gen` writes the entry points first) and the shared structs above.
pub fn header_text() -> String {
    let dir = repo_root().join("crates/wmr-ffi");
    // One file per call: tests run generate() on several threads at once.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let shared = std::env::temp_dir().join(format!("wmr-ffi-shared-{}-{call}.rs", std::process::id()));
    std::fs::write(&shared, shared_structs_source() + &core_state_source()).expect("temporary source");
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(dir.join("src/lib.rs"))
        .with_src(&shared)
        .generate()
        .expect("cbindgen parses the crate");
    let _ = std::fs::remove_file(&shared);
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).expect("UTF-8 header")
}

/// The header.
pub fn generate() -> Generated {
    Generated { path: "crates/wmr-ffi/include/wmr.h".into(), text: header_text() }
}
