//! Issue 44, "Firmware": `wmr-cli identify --c-header robot.h` writes the identified
//! values as C constants for the C API. A C program (C99, every warning an error)
//! initialises the C API's `wmr_robot_params_f64` / `wmr_drive_params_f64` (and the f32
//! twins) with the header's initializers, validates them with the library, and prints
//! every field with 17 significant digits: each equals the robot file's value bit for bit.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::identify_common::{ok, refused, run};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The C API's static library, built into the workspace's target directory.
fn ffi_static_lib() -> PathBuf {
    let target = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("..");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = Command::new(cargo)
        .args(["build", "-q", "-p", "wmr-ffi", "--lib", "--target-dir"])
        .arg(&target)
        .current_dir(repo())
        .status()
        .expect("cargo runs");
    assert!(status.success(), "cargo build -p wmr-ffi failed");
    target.join("debug/libwmr_ffi.a")
}

const ROBOT_KEYS: [&str; 11] = [
    "mass",
    "wheel_radius",
    "half_track",
    "com_offset",
    "wheel_inertia",
    "platform_inertia",
    "gear_ratio",
    "viscous_friction",
    "coulomb_friction",
    "coulomb_speed",
    "static_friction",
];
const DRIVE_KEYS: [&str; 6] =
    ["motor_torque_max", "voltage_max", "torque_constant", "back_emf_constant", "armature_resistance", "current_max"];

/// The C program: the header's initializers into the C API's structs, validated, printed.
fn program() -> String {
    let mut c = String::from(
        "#include <stdio.h>\n#include \"robot.h\"\n\nint main(void) {\n\
         \x20 wmr_robot_params_f64 p = WMR_IDENTIFIED_ROBOT_PARAMS;\n\
         \x20 wmr_drive_params_f64 d = WMR_IDENTIFIED_DRIVE_PARAMS;\n\
         \x20 wmr_robot_params_f32 p32 = WMR_IDENTIFIED_ROBOT_PARAMS;\n\
         \x20 wmr_drive_params_f32 d32 = WMR_IDENTIFIED_DRIVE_PARAMS;\n\
         \x20 wmr_robot_f64 robot; wmr_drive_f64 drive; wmr_robot_f32 robot32; wmr_drive_f32 drive32;\n\
         \x20 wmr_error err;\n\
         \x20 if (wmr_robot_f64_init(&robot, &p, &err) != 0) { printf(\"robot refused: %s\\n\", err.field); return 1; }\n\
         \x20 if (wmr_drive_f64_init(&drive, &d, &robot, &err) != 0) { printf(\"drive refused: %s\\n\", err.field); return 1; }\n\
         \x20 if (wmr_robot_f32_init(&robot32, &p32, &err) != 0) { printf(\"robot32 refused: %s\\n\", err.field); return 1; }\n\
         \x20 if (wmr_drive_f32_init(&drive32, &d32, &robot32, &err) != 0) { printf(\"drive32 refused: %s\\n\", err.field); return 1; }\n",
    );
    for k in ROBOT_KEYS {
        c += &format!("  printf(\"{k}=%.17g f32=%.9g\\n\", p.{k}, (double)p32.{k});\n");
    }
    for k in DRIVE_KEYS {
        c += &format!("  printf(\"{k}=%.17g f32=%.9g\\n\", d.{k}, (double)d32.{k});\n");
    }
    c += "  printf(\"kind=%u\\n\", (unsigned)d.kind);\n";
    for k in ["wheel_inertia", "platform_inertia", "coulomb_friction", "torque_constant", "back_emf_constant"] {
        c += &format!("  printf(\"{k}_std_err=%.17g\\n\", WMR_IDENTIFIED_{}_STD_ERR);\n", k.to_ascii_uppercase());
    }
    c += "  return 0;\n}\n";
    c
}

/// The value of `key = value` in a robot file (its comment dropped).
fn file_value(toml: &str, key: &str) -> f64 {
    let line = toml.lines().find(|l| l.starts_with(&format!("{key} ="))).unwrap_or_else(|| panic!("{key} in {toml}"));
    line.split('=').nth(1).unwrap().split('#').next().unwrap().trim().parse().unwrap()
}

/// The standard error in `key`'s comment: `fitted: +- 1.234e-5 (standard error)`.
fn file_std_err(toml: &str, key: &str) -> f64 {
    let line = toml.lines().find(|l| l.starts_with(&format!("{key} ="))).unwrap();
    line.split("+- ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap()
}

/// The value C printed for `key` (the first field: `%.17g` of the double).
fn printed(out: &str, key: &str) -> (f64, Option<f32>) {
    let line = out.lines().find(|l| l.starts_with(&format!("{key}="))).unwrap_or_else(|| panic!("{key} in {out}"));
    let mut parts = line.split(' ');
    let v = parts.next().unwrap().split_once('=').unwrap().1.parse().unwrap();
    let f = parts.next().map(|p| p.strip_prefix("f32=").unwrap().parse().unwrap());
    (v, f)
}

#[test]
fn issue_44_c_header_initialises_the_c_api_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let robot = repo().join("examples/identify/robot.toml");
    let robot = robot.to_str().unwrap();
    ok(&run(
        d,
        &[
            "excite",
            "-o",
            "profile.csv",
            "--robot",
            robot,
            "--log",
            "log.csv",
            "--encoder-noise",
            "0.01",
            "--seed",
            "44",
        ],
    ));
    let out = ok(&run(
        d,
        &["identify", "log.csv", "--drive", "dc_motor", "--robot", robot, "-o", "robot.toml", "--c-header", "robot.h"],
    ));
    assert!(out.contains("wrote robot.h (C header)"), "{out}");
    let toml = fs::read_to_string(d.join("robot.toml")).unwrap();
    let header = fs::read_to_string(d.join("robot.h")).unwrap();
    assert!(
        header.starts_with("/* Identified by `wmr-cli identify`") && header.contains("#ifndef WMR_ROBOT_H"),
        "{header}"
    );
    fs::write(d.join("main.c"), program()).unwrap();
    let exe = d.join("main");
    let status = Command::new("cc")
        .args(["-std=c99", "-O1", "-Wall", "-Wextra", "-Werror", "-pedantic", "-I"])
        .arg(repo().join("crates/wmr-ffi/include"))
        .arg("-I")
        .arg(d)
        .arg(d.join("main.c"))
        .arg(ffi_static_lib())
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&exe)
        .status()
        .expect("cc runs (the C compiler is needed for this test)");
    assert!(status.success(), "cc failed on the header:\n{header}");
    let run_c = Command::new(&exe).output().unwrap();
    let out = String::from_utf8(run_c.stdout).unwrap();
    assert!(run_c.status.success(), "{out}");
    // The torque drive's limit is not a key of a DC-motor robot file: the C struct gets
    // the torque drive's default (unread for WMR_DRIVE_DC_MOTOR).
    assert!(!toml.contains("motor_torque_max"), "{toml}");
    let (limit, _) = printed(&out, "motor_torque_max");
    assert_eq!(limit.to_bits(), wmr_core::TorqueDriveParams::<f64>::default().motor_torque_max.to_bits());
    let line = header.lines().find(|l| l.starts_with("#define WMR_IDENTIFIED_MOTOR_TORQUE_MAX ")).unwrap();
    assert!(line.ends_with("/* N m at the motor, the default; not read for this drive kind */"), "{line}");
    for k in ROBOT_KEYS.iter().chain(DRIVE_KEYS.iter().filter(|k| **k != "motor_torque_max")) {
        let want = file_value(&toml, k);
        let (got, got32) = printed(&out, k);
        assert_eq!(got.to_bits(), want.to_bits(), "{k}: C {got:e}, robot file {want:e}\n{header}");
        // The f32 struct holds the value rounded to float.
        assert_eq!(got32.unwrap().to_bits(), (want as f32).to_bits(), "{k} (f32)");
    }
    assert_eq!(printed(&out, "kind").0, 1.0, "WMR_DRIVE_DC_MOTOR");
    for k in ["wheel_inertia", "platform_inertia", "coulomb_friction", "torque_constant", "back_emf_constant"] {
        let (se, _) = printed(&out, &format!("{k}_std_err"));
        let shown = file_std_err(&toml, k);
        // The file shows 4 digits; the header carries the f64.
        assert!(se > 0.0 && (se - shown).abs() <= 5e-4 * shown, "{k}: {se} against the file's {shown}");
    }
}

#[test]
fn issue_44_c_header_refuses_the_robot_file_itself() {
    let dir = tempfile::tempdir().unwrap();
    let d: &Path = dir.path();
    fs::write(d.join("log.csv"), "t,tau_r,tau_l,phi_r,phi_l\n0,0,0,0,0\n").unwrap();
    let err = refused(&run(d, &["identify", "log.csv", "-o", "r.toml", "--c-header", "r.toml"]));
    assert!(err.contains("--c-header"), "{err}");
    let err = refused(&run(d, &["identify", "log.csv", "-o", "r.toml", "--c-header", "log.csv"]));
    assert!(err.contains("log.csv is the input file"), "{err}");
}
