//! C programs against the host static library, compiled with the system's `cc`:
//! `examples/c/fig7.c` (the final pose of Fig. 7 equals the CLI's bit for bit in double
//! and the Rust core's f32 run in float), the README's example, and `tests/c/errors.c`
//! (error codes and field names as C sees them, through the header's struct layout).

use std::path::PathBuf;
use std::process::Command;
use std::sync::OnceLock;

use wmr_core::{
    ClosedLoop, Controller, DriveParams, FixedGoal, PaperLaw, PaperParams, Plant, Pose2, Robot, WheelStage,
    WheelStageParams,
};

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn repo_dir() -> PathBuf {
    crate_dir().join("../..")
}

/// The host static library, built once for these tests into their own target directory
/// (`cargo test` builds the crate as an rlib for the test binaries; whether it also leaves
/// `libwmr_ffi.a` beside them depends on what else the workspace builds).
fn static_lib() -> PathBuf {
    static LIB: OnceLock<PathBuf> = OnceLock::new();
    LIB.get_or_init(|| {
        let target = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("ffi-staticlib");
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let status = Command::new(cargo)
            .args(["build", "-q", "-p", "wmr-ffi", "--lib", "--locked", "--target-dir"])
            .arg(&target)
            .current_dir(crate_dir())
            .status()
            .expect("cargo runs");
        assert!(status.success(), "cargo build -p wmr-ffi failed");
        let lib = target.join("debug/libwmr_ffi.a");
        assert!(lib.is_file(), "{} is missing", lib.display());
        lib
    })
    .clone()
}

/// Compiles `sources` with `cc` (C99, every warning an error) against the header and
/// the static library, runs the program and returns its standard output.
fn build_and_run(name: &str, sources: &[PathBuf]) -> String {
    let out_dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("c_programs");
    std::fs::create_dir_all(&out_dir).expect("scratch dir");
    let exe = out_dir.join(name);
    let status = Command::new("cc")
        .args(["-std=c99", "-O1", "-Wall", "-Wextra", "-Werror", "-pedantic", "-I"])
        .arg(crate_dir().join("include"))
        .args(sources)
        .arg(static_lib())
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&exe)
        .status()
        .expect("cc runs (the C compiler is needed for these tests)");
    assert!(status.success(), "cc failed on {sources:?}");
    let run = Command::new(&exe).output().expect("the program runs");
    let stdout = String::from_utf8(run.stdout).expect("UTF-8 output");
    assert!(run.status.success(), "{name} failed:\n{stdout}{}", String::from_utf8_lossy(&run.stderr));
    stdout
}

/// `key=value` of the line starting with `impl=<tag>`.
fn field<'a>(out: &'a str, tag: &str, key: &str) -> &'a str {
    let line = out
        .lines()
        .find(|l| l.starts_with(&format!("impl={tag} ")))
        .unwrap_or_else(|| panic!("no {tag} line in:\n{out}"));
    line.split(' ').find_map(|kv| kv.strip_prefix(&format!("{key}="))).unwrap_or_else(|| panic!("no {key} in {line}"))
}

/// The final pose of `wmr-cli run examples/paper/fig7.toml`: the scenario runner the CLI
/// uses (the CLI's golden test pins its output to a checked-in CSV).
fn cli_final_pose() -> [f64; 3] {
    let scenario = wmr_scenario::Scenario::from_path(repo_dir().join("examples/paper/fig7.toml")).expect("fig7.toml");
    let mut last = None;
    scenario.run(0, |s| last = Some(s.state)).expect("the run");
    let s = last.expect("samples");
    [s.x, s.y, s.theta]
}

/// Fig. 7 in f32 through the Rust core's own closed loop (as the firmware runs it).
fn rust_f32_final_pose() -> Pose2<f32> {
    let robot = Robot::<f32>::paper();
    let dt = 1e-3;
    let drive_params = DriveParams::default();
    let drive = drive_params.validate(&robot).unwrap();
    let goal = FixedGoal::new(Pose2::new(1.0, 1.0, 120f64.to_radians() as f32)).unwrap();
    let law = PaperLaw::new(PaperParams::paper(), robot.params(), dt).unwrap();
    let wheels =
        WheelStage::new(&WheelStageParams::for_drive(&drive_params, robot.params()), robot.params(), &drive, dt)
            .unwrap();
    let plant = Plant::new(robot, drive, Pose2::default()).unwrap();
    let mut sim = ClosedLoop::new(plant, Controller::new(law, wheels), goal, dt).unwrap();
    for _ in 0..60_000 {
        sim.step().unwrap();
    }
    sim.state().pose()
}

#[test]
fn fig7_c_example_matches_the_cli_in_double_and_the_core_in_float() {
    let out = build_and_run("fig7", &[repo_dir().join("examples/c/fig7.c")]);
    let [x, y, theta] = cli_final_pose();
    assert_eq!(field(&out, "c-f64", "x_bits"), format!("{:016x}", x.to_bits()), "{out}");
    assert_eq!(field(&out, "c-f64", "y_bits"), format!("{:016x}", y.to_bits()), "{out}");
    assert_eq!(field(&out, "c-f64", "theta_bits"), format!("{:016x}", theta.to_bits()), "{out}");
    assert_eq!(field(&out, "c-f64", "steps"), "60000");
    let p = rust_f32_final_pose();
    assert_eq!(field(&out, "c-f32", "x_bits"), format!("{:08x}", p.x.to_bits()), "{out}");
    assert_eq!(field(&out, "c-f32", "y_bits"), format!("{:08x}", p.y.to_bits()), "{out}");
    assert_eq!(field(&out, "c-f32", "theta_bits"), format!("{:08x}", p.theta.to_bits()), "{out}");
    // Issue 27: the pose in decimal beside the bits (m, m, rad, 6 decimals).
    assert_eq!(field(&out, "c-f64", "x"), format!("{x:.6}m"), "{out}");
    assert_eq!(field(&out, "c-f64", "y"), format!("{y:.6}m"), "{out}");
    assert_eq!(field(&out, "c-f64", "theta"), format!("{theta:.6}rad"), "{out}");
    assert_eq!(field(&out, "c-f32", "theta"), format!("{:.6}rad", f64::from(p.theta)), "{out}");
}

#[test]
fn readme_example_compiles_and_runs_fig7() {
    let readme = std::fs::read_to_string(crate_dir().join("README.md")).expect("README.md");
    let start = readme.find("```c\n").expect("a C block in the README") + 5;
    let block = &readme[start..start + readme[start..].find("```").expect("closed block")];
    assert!(block.lines().count() <= 25, "the README example should stay short");
    let (includes, body): (Vec<&str>, Vec<&str>) = block.lines().partition(|l| l.starts_with("#include"));
    let program = format!(
        "#include <stdint.h>\n#include <stdio.h>\n#include <string.h>\n{}\nint main(void) {{\n{}\n\
         wmr_state_f32 s; uint32_t b[3];\n\
         if (wmr_plant_f32_state(&plant, &s) != WMR_OK) return 1;\n\
         memcpy(&b[0], &s.x, 4); memcpy(&b[1], &s.y, 4); memcpy(&b[2], &s.theta, 4);\n\
         printf(\"impl=readme x_bits=%08lx y_bits=%08lx theta_bits=%08lx\\n\", (unsigned long)b[0], (unsigned long)b[1], (unsigned long)b[2]);\n\
         return 0;\n}}\n",
        includes.join("\n"),
        body.join("\n")
    );
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("readme_example.c");
    std::fs::write(&path, program).expect("write the program");
    let out = build_and_run("readme_example", &[path]);
    // The README's goal heading is 120 deg rounded to float, as the firmware's.
    let p = rust_f32_final_pose();
    assert_eq!(field(&out, "readme", "x_bits"), format!("{:08x}", p.x.to_bits()), "{out}");
    assert_eq!(field(&out, "readme", "y_bits"), format!("{:08x}", p.y.to_bits()), "{out}");
    assert_eq!(field(&out, "readme", "theta_bits"), format!("{:08x}", p.theta.to_bits()), "{out}");
}

#[test]
fn errors_name_the_field_in_c() {
    let out = build_and_run("errors", &[crate_dir().join("tests/c/errors.c")]);
    assert!(out.ends_with("ok\n"), "{out}");
    assert!(!out.contains("FAIL"), "{out}");
}

/// Issue 38 item 9: a recorded path of 2,000 points in storage the C caller owns.
#[test]
fn regression_38_9_a_recorded_path_of_2000_points_in_c() {
    let out = build_and_run("long_path", &[crate_dir().join("tests/c/long_path.c")]);
    assert!(out.contains("pass f64:") && out.contains("pass f32:"), "{out}");
    assert!(out.ends_with("ok\n"), "{out}");
    assert!(!out.contains("FAIL"), "{out}");
}

#[test]
fn reference_at_rest_is_the_goal_in_c() {
    let out = build_and_run("reference", &[crate_dir().join("tests/c/reference.c")]);
    assert!(out.contains("pass f64:") && out.contains("pass f32:"), "{out}");
    assert!(out.ends_with("ok\n"), "{out}");
    assert!(!out.contains("FAIL"), "{out}");
}

/// The last sample of `wmr-cli run examples/c/odometry_slip.toml`: true pose and the
/// odometry pose, through the scenario runner the CLI uses.
fn cli_odometry_slip_final() -> ([f64; 3], [f64; 3]) {
    let path = repo_dir().join("examples/c/odometry_slip.toml");
    let scenario = wmr_scenario::Scenario::from_path(path).expect("odometry_slip.toml");
    let mut last = None;
    scenario.run(0, |s| last = Some(*s)).expect("the run");
    let s = last.expect("samples");
    let odo = s.odometry.expect("an odometry pose");
    ([s.state.x, s.state.y, s.state.theta], [odo.x, odo.y, odo.theta])
}

/// The same run in f32 through the Rust core's own closed loop: DC motors, slip plant on
/// the slope, odometry with EKF fixes, the repaired paper law.
fn rust_f32_odometry_slip_final() -> ([f32; 3], [f32; 3]) {
    use wmr_core::{
        AnySensor, LawParams, OdometryParams, PaperBidirectionalParams, PoseSource, SensorParams, TractionKind,
        TractionParams, WorldParams,
    };
    let robot = Robot::<f32>::paper();
    let dt = 1e-3;
    let drive_params = DriveParams::DcMotor(wmr_core::DcMotorParams::default());
    let drive = drive_params.validate(&robot).unwrap();
    let world = WorldParams { slope_deg: 2.0, slope_direction_deg: 30.0 }.validate().unwrap();
    let traction = TractionParams { traction: TractionKind::Slip, friction_coefficient: 0.3, ..Default::default() }
        .validate(&robot, &world)
        .unwrap();
    let plant = Plant::on(robot, drive, world, Pose2::default()).unwrap().with_traction(traction);
    let sensor_params = SensorParams {
        encoder_counts: 1024,
        position_noise: 0.01,
        heading_noise_deg: 0.5,
        latency: 0.1,
        seed: 24,
        ..Default::default()
    };
    let odometry = OdometryParams { pose: PoseSource::Odometry, fix_rate_hz: 1.0, ..Default::default() };
    let sensor = AnySensor::new(sensor_params, odometry, robot.params(), dt, 0).unwrap();
    let goal = FixedGoal::new(Pose2::new(1.0, 1.0, 120f64.to_radians() as f32)).unwrap();
    let law = LawParams::PaperBidirectional(PaperBidirectionalParams::default()).build(robot.params(), dt).unwrap();
    let wheels =
        WheelStage::new(&WheelStageParams::for_drive(&drive_params, robot.params()), robot.params(), &drive, dt)
            .unwrap();
    let mut sim = ClosedLoop::with_sensor(plant, sensor, Controller::new(law, wheels), goal, dt).unwrap();
    for _ in 0..45_000 {
        sim.step().unwrap();
    }
    let p = sim.state().pose();
    let odo = sim.sample().odometry.expect("an odometry pose");
    ([p.x, p.y, p.theta], [odo.x, odo.y, odo.theta])
}

#[test]
fn odometry_slip_c_example_matches_the_cli_in_double_and_the_core_in_float() {
    let out = build_and_run("odometry_slip", &[repo_dir().join("examples/c/odometry_slip.c")]);
    let (pose, odo) = cli_odometry_slip_final();
    for (key, v) in ["x", "y", "theta"].iter().zip(pose).chain(["odom_x", "odom_y", "odom_theta"].iter().zip(odo)) {
        assert_eq!(field(&out, "c-f64", &format!("{key}_bits")), format!("{:016x}", v.to_bits()), "{key}: {out}");
    }
    let (pose, odo) = rust_f32_odometry_slip_final();
    for (key, v) in ["x", "y", "theta"].iter().zip(pose).chain(["odom_x", "odom_y", "odom_theta"].iter().zip(odo)) {
        assert_eq!(field(&out, "c-f32", &format!("{key}_bits")), format!("{:08x}", v.to_bits()), "{key}: {out}");
    }
    // The EKF's x variance is a variance: positive, and the fixes keep it below (10 cm)^2.
    let var_x = f64::from_bits(u64::from_str_radix(field(&out, "c-f64", "var_x_bits"), 16).unwrap());
    assert!(var_x > 0.0 && var_x < 0.01, "{var_x}: {out}");
}

/// The last sample of tests/c/observer.toml through the scenario runner the CLI uses:
/// true pose and the observer's estimate (N m per wheel).
fn cli_observer_final() -> ([f64; 3], [f64; 2]) {
    let path = crate_dir().join("tests/c/observer.toml");
    let scenario = wmr_scenario::Scenario::from_path(path).expect("observer.toml");
    assert!(scenario.controller().observer.is_some(), "the scenario has the observer");
    let mut last = None;
    scenario.run(0, |s| last = Some(*s)).expect("the run");
    let s = last.expect("samples");
    let d = s.disturbance.expect("an estimate");
    ([s.state.x, s.state.y, s.state.theta], [d.right, d.left])
}

/// The same run in f32 through the Rust core's own closed loop: the paper's law, its
/// wheel stage carrying the observer, the plant on the slope with Coulomb friction.
fn rust_f32_observer_final() -> ([f32; 3], [f32; 2]) {
    use wmr_core::{DisturbanceObserverParams, RobotParams, WorldParams};
    let robot = RobotParams::<f32> { coulomb_friction: 0.05, ..RobotParams::paper() }.validate().unwrap();
    let dt = 1e-3;
    let drive_params = DriveParams::default();
    let drive = drive_params.validate(&robot).unwrap();
    let world = WorldParams { slope_deg: 3.0, slope_direction_deg: 30.0 }.validate().unwrap();
    let plant = Plant::on(robot, drive, world, Pose2::default()).unwrap();
    let goal = FixedGoal::new(Pose2::new(1.0, 1.0, 120f64.to_radians() as f32)).unwrap();
    let law = PaperLaw::new(PaperParams::paper(), robot.params(), dt).unwrap();
    let observer = DisturbanceObserverParams::default().validate(robot.params(), &drive, dt).unwrap();
    let wheels =
        WheelStage::new(&WheelStageParams::for_drive(&drive_params, robot.params()), robot.params(), &drive, dt)
            .unwrap()
            .with_observer(observer);
    let mut sim = ClosedLoop::new(plant, Controller::new(law, wheels), goal, dt).unwrap();
    for _ in 0..20_000 {
        sim.step().unwrap();
    }
    let p = sim.state().pose();
    let d = sim.sample().disturbance.expect("an estimate");
    ([p.x, p.y, p.theta], [d.right, d.left])
}

/// Issue 42: the disturbance observer from C (`_init_observer`, `_disturbance`) runs the
/// CLI's path bit for bit in double and the Rust core's in float: final pose and the
/// observer's last estimate.
#[test]
fn issue_42_the_observer_in_c_matches_the_cli_in_double_and_the_core_in_float() {
    let out = build_and_run("observer", &[crate_dir().join("tests/c/observer.c")]);
    assert!(out.contains("pass f64: refusals") && out.contains("pass f32: refusals"), "{out}");
    assert!(out.ends_with("ok\n") && !out.contains("FAIL"), "{out}");
    let keys = ["x", "y", "theta", "tau_dist_r", "tau_dist_l"];
    let (pose, d) = cli_observer_final();
    for (key, v) in keys.iter().zip(pose.into_iter().chain(d)) {
        assert_eq!(field(&out, "c-f64", &format!("{key}_bits")), format!("{:016x}", v.to_bits()), "{key}: {out}");
    }
    assert_eq!(field(&out, "c-f64", "steps"), "20000");
    // The estimate holds the slope and the friction: not zero.
    assert!(d[0].abs() > 1e-3 && d[1].abs() > 1e-3, "{d:?}");
    let (pose, d) = rust_f32_observer_final();
    for (key, v) in keys.iter().zip(pose.into_iter().chain(d)) {
        assert_eq!(field(&out, "c-f32", &format!("{key}_bits")), format!("{:08x}", v.to_bits()), "{key}: {out}");
    }
}

/// The last pose of run `run` of tests/c/mppi_obstacles.toml through the scenario runner
/// the CLI uses, with the plant steps it took.
fn cli_mppi_final(run: usize) -> ([f64; 3], usize) {
    let path = crate_dir().join("tests/c/mppi_obstacles.toml");
    let scenario = wmr_scenario::Scenario::from_path(path).expect("mppi_obstacles.toml");
    let mut last = None;
    let result = scenario.run(run, |s| last = Some(*s)).expect("the run");
    assert_eq!(result.outcome.termination, wmr_core::Termination::Completed, "run {run}: the whole run is compared");
    let s = last.expect("samples");
    assert_eq!(s.t, 3.0, "run {run} ended early");
    ([s.state.x, s.state.y, s.state.theta], 3000)
}

/// Issue 41: MPPI from C with its obstacles (`wmr_obstacles_*`, `_init_in`) and a run's
/// own noise (`run`) is the CLI's run of the same scenario bit for bit: run 1 and run 0,
/// which differ (their noise), and without the obstacles it goes elsewhere (the critic
/// reads them).
#[test]
fn issue_41_mppi_with_obstacles_in_c_matches_the_cli_run_for_run() {
    let out = build_and_run("mppi_obstacles", &[crate_dir().join("tests/c/mppi_obstacles.c")]);
    assert!(out.contains("pass f64: refusals") && out.contains("pass f32: refusals"), "{out}");
    assert!(out.ends_with("ok\n") && !out.contains("FAIL"), "{out}");
    let keys = ["x", "y", "theta"];
    for (tag, run) in [("run1", 1), ("run0", 0)] {
        let (pose, steps) = cli_mppi_final(run);
        for (key, v) in keys.iter().zip(pose) {
            let c = field(&out, &format!("{tag}-f64"), &format!("{key}_bits"));
            assert_eq!(c, format!("{:016x}", v.to_bits()), "{tag} {key}: {out}");
        }
        assert_eq!(field(&out, &format!("{tag}-f64"), "steps"), steps.to_string());
    }
    assert_ne!(field(&out, "run1-f64", "x_bits"), field(&out, "run0-f64", "x_bits"), "{out}");
    assert_ne!(field(&out, "run1-f64", "y_bits"), field(&out, "blind-f64", "y_bits"), "{out}");
}
