//! The C API's layout: the structs C reads are laid out as the core's `#[repr(C)]`
//! structs and the header declares them so. The header and the entry points are
//! generated (`cargo xtask gen`, from xtask/src/ffi_api.rs and ffi_header.rs) and checked
//! for staleness by `cargo test -p xtask`.

use std::path::PathBuf;

use wmr_core::describe::{Described, ParamField};
use wmr_core::{
    BacksteppingParams, KanayamaParams, LyapunovParams, PaperBidirectionalParams, PaperParams, PolarParams,
    PurePursuitParams, RobotParams, TractionParams, WheelStageParams, WorldParams,
};

/// The checked-in header.
fn header() -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("include/wmr.h");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
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
    // The odometry and traction structs: a u32 code, then floats.
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_odometry_params<f32>>(), 3 * 4);
    assert_eq!(std::mem::offset_of!(wmr_ffi::wmr_odometry_params<f64>, fix_rate_hz), 8);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_odometry_params<f64>>(), 3 * 8);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_traction_params<f32>>(), TractionParams::<f64>::FIELDS.len() * 4);
    assert_eq!(std::mem::offset_of!(wmr_ffi::wmr_traction_params<f64>, friction_coefficient), 8);
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
        std::mem::offset_of!(wmr_ffi::wmr_paper_params<f64>, anti_windup),
    ];
    assert_eq!(paper.len(), offsets.len());
    assert_eq!(offsets, [0, 8, 16, 24, 32, 40, 48, 56, 60]);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_paper_params<f32>>(), 9 * 4);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_paper_params<f64>>(), 64);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_paper_bidirectional_params<f32>>(), 7 * 4);
    assert_eq!(std::mem::offset_of!(wmr_ffi::wmr_paper_bidirectional_params<f64>, hold), 6 * 8);
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
    let header = header();
    let laws: [(&str, &[ParamField]); 7] = [
        ("wmr_paper_params_f64", PaperParams::<f64>::FIELDS),
        ("wmr_paper_bidirectional_params_f64", PaperBidirectionalParams::<f64>::FIELDS),
        ("wmr_polar_params_f64", PolarParams::<f64>::FIELDS),
        ("wmr_lyapunov_params_f64", LyapunovParams::<f64>::FIELDS),
        ("wmr_kanayama_params_f64", KanayamaParams::<f64>::FIELDS),
        ("wmr_backstepping_params_f64", BacksteppingParams::<f64>::FIELDS),
        ("wmr_pure_pursuit_params_f64", PurePursuitParams::<f64>::FIELDS),
    ];
    for (name, fields) in laws {
        let core: Vec<&str> = fields.iter().map(|f| f.name).collect();
        assert_eq!(c_members(&header, name), core, "{name}");
    }
}

/// Issue 42: the observer's C struct (written out in src/lib.rs: the core's
/// `DisturbanceObserverParams` is not `#[repr(C)]`) has the core's fields, in order, and
/// nothing else; a key the core gains fails here until C has it too.
#[test]
fn the_observer_struct_has_the_core_fields_in_order() {
    let header = header();
    let core: Vec<&str> = wmr_core::DisturbanceObserverParams::<f64>::FIELDS.iter().map(|f| f.name).collect();
    for name in ["wmr_disturbance_observer_params_f32", "wmr_disturbance_observer_params_f64"] {
        assert_eq!(c_members(&header, name), core, "{name}");
    }
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_disturbance_observer_params<f32>>(), core.len() * 4);
    assert_eq!(std::mem::size_of::<wmr_ffi::wmr_disturbance_observer_params<f64>>(), core.len() * 8);
}
