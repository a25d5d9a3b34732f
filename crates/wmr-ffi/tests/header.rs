//! The checked-in C header and the f64 entry points are generated: these tests fail when
//! either is stale. `WMR_BLESS=1 cargo test -p wmr-ffi --test header` rewrites both.

use std::path::{Path, PathBuf};

use wmr_core::describe::{Described, ParamField};
use wmr_core::{
    LyapunovParams, PaperBidirectionalParams, PaperParams, PolarParams, RobotParams, SensorParams, WheelStageParams,
    WorldParams,
};

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn bless() -> bool {
    std::env::var_os("WMR_BLESS").is_some_and(|v| v == "1")
}

/// Compares `fresh` with the file at `path`, or rewrites the file under `WMR_BLESS=1`.
fn check_or_bless(path: &Path, fresh: &str, how: &str) {
    if bless() {
        std::fs::write(path, fresh).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
        return;
    }
    let current = std::fs::read_to_string(path).unwrap_or_default();
    if current != fresh {
        let line = current.lines().zip(fresh.lines()).position(|(a, b)| a != b).map_or(0, |i| i + 1);
        panic!("{} is stale (first difference near line {line}): {how}", path.display());
    }
}

/// `api_f64.rs` as it must be: `api_f32.rs` with f32 -> f64, under its own module docs.
fn mirror_f64(api_f32: &str) -> String {
    let body: Vec<&str> = api_f32.split('\n').skip_while(|l| l.starts_with("//!")).collect();
    let head = "//! The f64 entry points: `api_f32.rs` with every `f32` replaced by `f64`. Generated;\n\
                //! edit `api_f32.rs` and run `WMR_BLESS=1 cargo test -p wmr-ffi --test header`.\n";
    format!("{head}{}", body.join("\n").replace("f32", "f64"))
}

#[test]
fn f64_api_is_the_f32_api() {
    let dir = crate_dir().join("src");
    let f32_src = std::fs::read_to_string(dir.join("api_f32.rs")).expect("api_f32.rs");
    check_or_bless(
        &dir.join("api_f64.rs"),
        &mirror_f64(&f32_src),
        "run WMR_BLESS=1 cargo test -p wmr-ffi --test header",
    );
}

/// The core parameter structs the C API takes as they are (`pub type` aliases in
/// `src/lib.rs`): C name, doc, fields.
fn shared_structs() -> [(&'static str, &'static str, &'static [ParamField]); 6] {
    [
        (
            "wmr_robot_params",
            "Physical robot parameters, SI units (the `[robot]` keys of a scenario).",
            RobotParams::<f64>::FIELDS,
        ),
        (
            "wmr_world_params",
            "The ground (the `[world]` keys): a plane tilted by `slope_deg`, descending towards `slope_direction_deg`.",
            WorldParams::<f64>::FIELDS,
        ),
        (
            "wmr_sensor_params",
            "The pose sensor (the `[sensor]` keys); every default: the perfect sensor, bit for bit. Here latency * rate_hz must be below `WMR_SENSOR_SAMPLES_IN_FLIGHT` - 1.",
            SensorParams::<f64>::FIELDS,
        ),
        (
            "wmr_wheel_stage_params",
            "The wheel stage: two wheel position servos and the curvature-keeping speed limit.",
            WheelStageParams::<f64>::FIELDS,
        ),
        (
            "wmr_paper_params",
            "The paper's law (`[controller] kind = \"paper\"`): PI loops on (e_s, e_theta) towards a moving false target.",
            PaperParams::<f64>::FIELDS,
        ),
        (
            "wmr_paper_bidirectional_params",
            "The paper's law repaired (`[controller] kind = \"paper_bidirectional\"`).",
            PaperBidirectionalParams::<f64>::FIELDS,
        ),
    ]
}

/// The C type and the C constants of a core field type that is not `T`: the core's
/// `#[repr(u32)]` enums are `uint32_t` codes in C.
fn c_type(ty: &'static str) -> (&'static str, &'static str) {
    match ty {
        "PaperMode" => ("u32", "`WMR_PAPER_MODE_POSE` or `WMR_PAPER_MODE_POSITION`"),
        "HoldMode" => ("u32", "`WMR_HOLD_AUTO`, `WMR_HOLD_ZERO_ERRORS` or `WMR_HOLD_FREEZE`"),
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

#[test]
fn shared_structs_have_the_core_layout() {
    // The C declarations list the fields in declaration order; repr(C) lays them out so.
    // All-float structs: one float per declared field, nothing else.
    let floats = |fields: &[ParamField]| fields.len() * 4;
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_robot_params<f32>>(), floats(RobotParams::<f64>::FIELDS));
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_world_params<f32>>(), floats(WorldParams::<f64>::FIELDS));
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_wheel_stage_params<f32>>(), floats(WheelStageParams::<f64>::FIELDS));
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_sensor_params<f32>>(), 4 * 4 + 4 + 4 + 8);
    assert_eq!(std::mem::offset_of!(wmr_ffi::wmr_sensor_params<f64>, seed), 4 * 8 + 8);
    // The law structs: u32 codes and floats, in declaration order.
    let paper = PaperParams::<f64>::FIELDS;
    let offsets = [
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, mode),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, kp_theta),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, ki_theta),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, kp_s),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, ki_s),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, goal_radius),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, hold_radius),
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, hold),
    ];
    assert_eq!(paper.len(), offsets.len());
    assert_eq!(offsets, [0, 8, 16, 24, 32, 40, 48, 56]);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_paper_params<f32>>(), 8 * 4);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_paper_params<f64>>(), 64);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_paper_bidirectional_params<f32>>(), 7 * 4);
    assert_eq!(std::mem::offset_of!(wmr_ffi::wmr_paper_bidirectional_params<f64>, hold), 6 * 8);
    for (_, _, fields) in shared_structs() {
        assert!(fields.iter().all(|f| matches!(c_type(f.ty).0, "T" | "u32" | "u64")), "{fields:?}");
    }
}

/// The C struct `name`'s members as the generated header declares them, in order.
fn c_members(header: &str, name: &str) -> Vec<String> {
    let end = header.find(&format!("}} {name};")).unwrap_or_else(|| panic!("{name} is not in the header"));
    let start = header[..end].rfind("typedef struct {").expect("a typedef struct");
    header[start..end]
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with("//") && l.ends_with(';'))
        .map(|l| l.trim_end_matches(';').rsplit(' ').next().expect("a member").to_owned())
        .collect()
}

#[test]
fn every_law_struct_has_the_core_fields_in_order() {
    // The polar and Lyapunov structs are written out in src/lib.rs (their `bool`s are
    // `uint32_t` in C); the paper structs come from the core's tables. Either way the C
    // members must be the core's fields, in the core's order.
    let header = generate();
    let laws: [(&str, &[ParamField]); 4] = [
        ("wmr_paper_params_f64", PaperParams::<f64>::FIELDS),
        ("wmr_paper_bidirectional_params_f64", PaperBidirectionalParams::<f64>::FIELDS),
        ("wmr_polar_params_f64", PolarParams::<f64>::FIELDS),
        ("wmr_lyapunov_params_f64", LyapunovParams::<f64>::FIELDS),
    ];
    for (name, fields) in laws {
        let core: Vec<&str> = fields.iter().map(|f| f.name).collect();
        assert_eq!(c_members(&header, name), core, "{name}");
    }
}

fn generate() -> String {
    let dir = crate_dir();
    // One file per call: tests run generate() on several threads at once.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let shared = std::env::temp_dir().join(format!("wmr-ffi-shared-{}-{call}.rs", std::process::id()));
    std::fs::write(&shared, shared_structs_source()).expect("temporary source");
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

#[test]
fn header_is_current() {
    // The f64 file must be current first, or the header would be generated from a stale one.
    let dir = crate_dir().join("src");
    let f32_src = std::fs::read_to_string(dir.join("api_f32.rs")).expect("api_f32.rs");
    let f64_now = std::fs::read_to_string(dir.join("api_f64.rs")).expect("api_f64.rs");
    if !bless() {
        assert_eq!(
            f64_now,
            mirror_f64(&f32_src),
            "api_f64.rs is stale: run WMR_BLESS=1 cargo test -p wmr-ffi --test header"
        );
    }
    let header = generate();
    for name in [
        "wmr_plant_f32_step",
        "wmr_plant_f64_step",
        "wmr_lyapunov_controller_f64_update",
        "wmr_paper_bidirectional_controller_f32_update",
        "WMR_PLANT_F32_WORDS",
    ] {
        assert!(header.contains(name), "the generated header lacks {name}");
    }
    check_or_bless(&crate_dir().join("include/wmr.h"), &header, "run WMR_BLESS=1 cargo test -p wmr-ffi --test header");
}
