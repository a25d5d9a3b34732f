//! `wmr-cli identify`, `excite` and `replay` (docs/identify.md): fit a robot file to a
//! log, write the command profiles that excite a robot, and run a robot file open loop on
//! a log's commands.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;
use wmr_core::{DcMotorParams, Drive, DriveParams, Robot, RobotParams, TorqueDriveParams};
use wmr_identify::excite::{ExciteSettings, Test};
use wmr_identify::sim::{LogNoise, log_table};
use wmr_identify::{ColumnNames, CommandKind, FitSettings, IdentifyError, Log, Param, Table};

use crate::errors::{bad_input, say};

/// The drive a log's commands are for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DriveKind {
    /// Wheel torques, N m (columns tau_r, tau_l).
    Torque,
    /// Motor voltages, V (columns u_r, u_l).
    #[value(name = "dc_motor")]
    DcMotor,
}

impl DriveKind {
    fn command(self) -> CommandKind {
        match self {
            DriveKind::Torque => CommandKind::Torque,
            DriveKind::DcMotor => CommandKind::Voltage,
        }
    }
}

/// The robot and drive of a robot file (or scenario) `path`, or the paper's robot.
pub struct Base {
    /// Where it came from, for the comments of the output.
    pub source: String,
    /// The robot's parameters.
    pub robot: RobotParams<f64>,
    /// The drive's parameters.
    pub drive: DriveParams<f64>,
}

/// Reads the robot file `path` as `[robot] from = "path"` reads it (its `[robot]` and
/// `[drive]` keys, every one checked), or the paper's robot without one.
pub fn base(path: Option<&Path>, access: &wmr_scenario::FileAccess) -> Result<Base> {
    match path {
        Some(p) => {
            let shown = wmr_scenario::shown(p);
            let name = p
                .file_name()
                .and_then(|n| n.to_str())
                .ok_or_else(|| bad_input(format!("--robot {shown}: not a file name")))?;
            let dir = p.parent().unwrap_or(Path::new(""));
            crate::atomic::register_input(p);
            // A scenario of this robot alone (the run is never run: it only makes the
            // scenario complete), so the robot file is read exactly as `from` reads it. Its
            // step is short, so that a stiff Coulomb friction is not refused here: the fit
            // and the replay take their own steps (a scenario using the robot is checked
            // against its own sim.dt).
            let text = format!(
                "[robot]\nfrom = {}\n\n[sim]\ndt = 1e-5\nt_end = 0.01\nlog_dt = 0.01\n\n[[run]]\ngoal = {{ x = 1.0, y = 0.0, theta_deg = 0.0 }}\n",
                toml_string(name)
            );
            let s = wmr_scenario::Scenario::from_toml_str_with(&text, "robot", dir, access)
                .map_err(|e| bad_input(format!("--robot {shown}: {e}")))?;
            Ok(Base { source: shown, robot: *s.robot().params(), drive: s.drive().params() })
        }
        None => Ok(Base {
            source: "the paper's robot (no --robot given)".to_owned(),
            robot: RobotParams::paper(),
            drive: DriveParams::default(),
        }),
    }
}

/// `s` as a TOML basic string.
fn toml_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// An identification error as bad input (exit 2), its message unchanged.
fn bad(e: IdentifyError) -> anyhow::Error {
    bad_input(e.to_string())
}

/// The first bytes of every MCAP file.
const MCAP_MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// Whether `path` is an MCAP log: a `.mcap` name, or a file starting with the MCAP magic.
fn is_mcap(path: &Path) -> bool {
    if path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("mcap")) {
        return true;
    }
    let mut head = [0u8; 8];
    std::fs::File::open(path).and_then(|mut f| std::io::Read::read_exact(&mut f, &mut head)).is_ok()
        && &head == MCAP_MAGIC
}

/// Reads the log at `path` into a table: a CSV, or a ROS 2 MCAP (`.mcap`, or any file
/// starting with the MCAP magic) through [`crate::ros2::log::read_log`] ([`mcap_table`]);
/// `namespace` (`/run1`) picks one robot of an MCAP of several.
pub fn read_table(path: &Path, namespace: Option<&str>, kind: CommandKind) -> Result<Table> {
    let shown = wmr_scenario::shown(path);
    if is_mcap(path) {
        let bytes = std::fs::read(path).map_err(|e| bad_input(format!("{shown}: cannot read it: {e}")))?;
        crate::atomic::register_input(path);
        let log = crate::ros2::log::read_log(&bytes, namespace).map_err(|e| bad_input(format!("{shown}: {e}")))?;
        return mcap_table(&log, kind).map_err(|e| bad_input(format!("{shown}: {e}")));
    }
    if namespace.is_some() {
        return Err(bad_input(format!("--namespace: {shown} is a CSV; the flag picks a robot of a ROS 2 MCAP")));
    }
    let file = std::fs::File::open(path).map_err(|e| bad_input(format!("{shown}: {e}")))?;
    crate::atomic::register_input(path);
    Table::read_csv(std::io::BufReader::new(file)).map_err(|e| bad_input(format!("{shown}: {e}")))
}

/// A ROS 2 log as the table a wmr run's CSV gives: a row per `/joint_states` message, `t`
/// (s since its first stamp, so that an epoch's 1.7e9 s costs no precision), `tau_r,
/// tau_l` from `effort` (N m), `phi_r, phi_l` from `position` (rad) and `omega_r, omega_l`
/// from `velocity` (rad/s) where every message has them, and `x, y, theta` from the latest
/// `/odom` at or before each row when there is one before the first row (the robot's own
/// pose estimate: `--profile ros2` logs the measured pose there).
pub fn mcap_table(log: &crate::ros2::log::Ros2Log, kind: CommandKind) -> Result<Table, String> {
    if kind == CommandKind::Voltage {
        return Err("per-wheel voltage is not in a ROS 2 log (sensor_msgs/msg/JointState has position, velocity and effort): \
             a ROS 2 MCAP takes a torque drive (its effort, N m: identify --drive torque, a replay robot of [drive] kind = \"torque\"); give voltages as a CSV with u_r, u_l"
            .to_owned());
    }
    let js = &log.joint_states;
    let Some(first) = js.first() else {
        return Err("no /joint_states messages (sensor_msgs/msg/JointState): the wheels' efforts and positions or velocities are needed".to_owned());
    };
    let t0 = first.t_ns;
    let t: Vec<f64> = js.iter().map(|m| (m.t_ns - t0) as f64 / 1e9).collect();
    let at = |i: usize| t[i];
    if let Some(i) = js.iter().position(|m| !m.tau.iter().all(|v| v.is_finite())) {
        return Err(format!(
            "/joint_states: no effort (the wheel torques, N m) for both wheels in the message at t = {} s (stamp {} ns)",
            at(i),
            js[i].t_ns
        ));
    }
    let all = |f: fn(&crate::ros2::log::WheelStates) -> [f64; 2]| js.iter().all(|m| f(m).iter().all(|v| v.is_finite()));
    let has_phi = all(|m| m.phi);
    let has_omega = all(|m| m.omega);
    if !has_phi && !has_omega {
        return Err("/joint_states: neither position nor velocity for both wheels in every message".to_owned());
    }
    let col = |f: &dyn Fn(&crate::ros2::log::WheelStates) -> f64| js.iter().map(f).collect::<Vec<f64>>();
    let mut table = Table::new();
    let e = |e: IdentifyError| e.to_string();
    table.push("t", t.clone()).map_err(e)?;
    table.push("tau_r", col(&|m| m.tau[0])).map_err(e)?;
    table.push("tau_l", col(&|m| m.tau[1])).map_err(e)?;
    if has_phi {
        table.push("phi_r", col(&|m| m.phi[0])).map_err(e)?;
        table.push("phi_l", col(&|m| m.phi[1])).map_err(e)?;
    }
    if has_omega {
        table.push("omega_r", col(&|m| m.omega[0])).map_err(e)?;
        table.push("omega_l", col(&|m| m.omega[1])).map_err(e)?;
    }
    let odom = &log.odom;
    if odom.first().is_some_and(|o| o.t_ns <= t0) {
        let mut k = 0usize;
        let mut pose = [Vec::new(), Vec::new(), Vec::new()];
        for m in js {
            while k + 1 < odom.len() && odom[k + 1].t_ns <= m.t_ns {
                k += 1;
            }
            pose[0].push(odom[k].x);
            pose[1].push(odom[k].y);
            pose[2].push(odom[k].theta);
        }
        let [x, y, theta] = pose;
        table.push("x", x).map_err(e)?;
        table.push("y", y).map_err(e)?;
        table.push("theta", theta).map_err(e)?;
    }
    Ok(table)
}

/// `--hold key[=value],...`: the parameters held, with the values given.
fn parse_hold(list: &[String], robot: &mut RobotParams<f64>, motor: &mut DcMotorParams<f64>) -> Result<Vec<Param>> {
    let mut out = Vec::new();
    for item in list.iter().flat_map(|s| s.split(',')).map(str::trim).filter(|s| !s.is_empty()) {
        let (key, value) = match item.split_once('=') {
            Some((k, v)) => (k.trim(), Some(v.trim())),
            None => (item, None),
        };
        let Some(p) = Param::from_key(key) else {
            let known: Vec<&str> = Param::ALL.iter().map(|p| p.key()).collect();
            return Err(bad_input(format!("--hold: unknown parameter `{key}` (one of {})", known.join(", "))));
        };
        if let Some(v) = value {
            let x: f64 = v.parse().map_err(|_| bad_input(format!("--hold: {key} = `{v}` is not a number")))?;
            if !(x.is_finite() && x >= 0.0) {
                return Err(bad_input(format!("--hold: {key} must be finite and >= 0, got {v}")));
            }
            p.set(robot, motor, x);
        }
        out.push(p);
    }
    Ok(out)
}

/// `wmr-cli identify LOG -o OUT`.
pub fn identify(
    log_path: &Path,
    output: &Path,
    drive: DriveKind,
    robot_path: Option<&Path>,
    hold: Option<&[String]>,
    namespace: Option<&str>,
    access: &wmr_scenario::FileAccess,
) -> Result<()> {
    let base = base(robot_path, access)?;
    let table = read_table(log_path, namespace, drive.command())?;
    // OUT must not be an input (checked before the fit, so a refusal costs nothing).
    crate::atomic::target_of(output)?;
    let shown = wmr_scenario::shown(log_path);
    let log = Log::from_table(&table, &ColumnNames::default(), drive.command())
        .map_err(|e| bad_input(format!("{shown}: {e}")))?;
    let mut motor = match base.drive {
        DriveParams::DcMotor(m) => m,
        _ => DcMotorParams::default(),
    };
    let mut robot = base.robot;
    let mut settings = FitSettings::new(drive.command(), robot, motor);
    if let Some(h) = hold {
        settings.hold = parse_hold(h, &mut robot, &mut motor)?;
        settings.robot = robot;
        settings.motor = motor;
    }
    let fit = wmr_identify::fit(&log, &settings).map_err(|e| bad_input(format!("{shown}: {e}")))?;
    let text = robot_file(&fit, &base, drive, &shown, &log);
    crate::atomic::write_text(output, &text)?;
    let mut summary = String::new();
    let _ = writeln!(
        summary,
        "identify: {} of {} rows used ({} equations), condition number {:.3}, RMS residual {:.4e} {}",
        fit.rows_used,
        fit.rows_total,
        fit.equations,
        fit.condition,
        fit.rms_residual,
        if drive == DriveKind::Torque { "N m" } else { "V" }
    );
    for e in &fit.estimates {
        let how = if e.held {
            "held".to_owned()
        } else if e.zeroed {
            format!("+- {:.3e} (fitted below 0: set to 0)", e.std_err)
        } else {
            format!("+- {:.3e}", e.std_err)
        };
        let _ = writeln!(summary, "  {:<20} {:>12.6e} {:<7} {how}", e.param.key(), e.value, e.param.unit());
    }
    let _ = write!(summary, "wrote {}", wmr_scenario::shown(output));
    for line in summary.lines() {
        say(line)?;
    }
    Ok(())
}

/// A robot file of the fit: `[robot]` and `[drive]` with every key, each fitted value with
/// its standard error and the log in a comment.
fn robot_file(fit: &wmr_identify::Fit, base: &Base, drive: DriveKind, log: &str, l: &Log) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Identified by `wmr-cli identify` (docs/identify.md) from {log}:");
    let _ = writeln!(
        s,
        "# {} of its {} rows used (columns {}), condition number {:.3}, RMS residual {:.4e} {}.",
        fit.rows_used,
        fit.rows_total,
        l.columns_used.join(", "),
        fit.condition,
        fit.rms_residual,
        if drive == DriveKind::Torque { "N m" } else { "V" }
    );
    let _ = writeln!(s, "# Geometry and held values from {}.", base.source);
    let _ = writeln!(s, "# Use: [robot] from = \"THIS FILE\"; check it with `wmr-cli replay LOG --robot THIS FILE`.");
    let note_of = |p: Param| -> String {
        match fit.get(p) {
            Some(e) if e.zeroed => {
                format!(
                    "# {}, fitted: below 0 within 3 standard errors ({:.3e}), so 0, from {log}",
                    p.unit(),
                    e.std_err
                )
            }
            Some(e) if !e.held => format!("# {}, fitted: +- {:.3e} (standard error), from {log}", p.unit(), e.std_err),
            Some(_) => format!("# {}, held", p.unit()),
            None => String::new(),
        }
    };
    let r = &fit.robot;
    let _ = writeln!(s, "\n[robot]");
    let rows: [(&str, f64, String); 11] = [
        ("mass", r.mass, note_of(Param::Mass)),
        ("wheel_radius", r.wheel_radius, "# m, held".to_owned()),
        ("half_track", r.half_track, "# m, held".to_owned()),
        ("com_offset", r.com_offset, "# m, held".to_owned()),
        ("wheel_inertia", r.wheel_inertia, note_of(Param::WheelInertia)),
        ("platform_inertia", r.platform_inertia, note_of(Param::PlatformInertia)),
        ("gear_ratio", r.gear_ratio, "# held".to_owned()),
        ("viscous_friction", r.viscous_friction, note_of(Param::ViscousFriction)),
        ("coulomb_friction", r.coulomb_friction, note_of(Param::CoulombFriction)),
        ("coulomb_speed", r.coulomb_speed, "# rad/s, held".to_owned()),
        ("static_friction", r.static_friction, "# N m, held (0: no stiction beyond coulomb_friction)".to_owned()),
    ];
    for (k, v, c) in rows {
        let _ = writeln!(s, "{k} = {v:?}   {c}");
    }
    let _ = writeln!(s, "\n[drive]");
    match drive {
        DriveKind::Torque => {
            let p = match base.drive {
                DriveParams::Torque(p) => p,
                _ => TorqueDriveParams::default(),
            };
            let _ = writeln!(s, "kind = \"torque\"");
            let _ = writeln!(s, "motor_torque_max = {:?}   # N m at the motor, held", p.motor_torque_max);
            let _ = writeln!(s, "deadband = {:?}   # held", p.deadband);
        }
        DriveKind::DcMotor => {
            let m = &fit.motor;
            let _ = writeln!(s, "kind = \"dc_motor\"");
            let _ = writeln!(s, "voltage_max = {:?}   # V, held", m.voltage_max);
            let _ = writeln!(s, "torque_constant = {:?}   {}", m.torque_constant, note_of(Param::TorqueConstant));
            let _ = writeln!(s, "back_emf_constant = {:?}   {}", m.back_emf_constant, note_of(Param::BackEmfConstant));
            let _ = writeln!(
                s,
                "armature_resistance = {:?}   {}",
                m.armature_resistance,
                note_of(Param::ArmatureResistance)
            );
            let _ = writeln!(s, "current_max = {:?}   # A, held", m.current_max);
            let _ = writeln!(s, "deadband = {:?}   # held", m.deadband);
        }
    }
    s
}

/// `wmr-cli excite -o OUT`: the profile CSV, a table of the tests with their safe
/// distances, and with `log` a simulated log of the robot playing them.
#[allow(clippy::too_many_arguments)]
pub fn excite(
    output: &Path,
    robot_path: Option<&Path>,
    command_max: Option<f64>,
    log: Option<&Path>,
    encoder_noise: f64,
    jitter_s: f64,
    seed: u64,
    access: &wmr_scenario::FileAccess,
) -> Result<()> {
    let base = base(robot_path, access)?;
    let robot = base.robot.validate().map_err(|e| bad_input(format!("{}: {e}", base.source)))?;
    let drive = base.drive.validate(&robot).map_err(|e| bad_input(format!("{}: {e}", base.source)))?;
    let voltage = matches!(drive, Drive::DcMotor(_));
    let command_max = match command_max {
        Some(c) if c > 0.0 && c.is_finite() => c,
        Some(c) => return Err(bad_input(format!("--command-max must be > 0 and finite, got {c}"))),
        None => drive.command_limit(),
    };
    if !command_max.is_finite() {
        return Err(bad_input(
            "--command-max: the drive has no finite command limit (motor_torque_max = inf): give one",
        ));
    }
    for (flag, v) in [("--encoder-noise", encoder_noise), ("--jitter", jitter_s)] {
        if !(v >= 0.0 && v.is_finite()) {
            return Err(bad_input(format!("{flag} must be >= 0 and finite, got {v}")));
        }
    }
    let settings = ExciteSettings::new(command_max);
    settings.check().map_err(bad)?;
    // Neither output may be an input: refused before anything is printed.
    crate::atomic::target_of(output)?;
    if let Some(l) = log {
        crate::atomic::target_of(l)?;
    }
    let tests = Test::all();
    let unit = if voltage { "V" } else { "N m" };
    let mut csv = String::from(if voltage { "run,t,u_r,u_l\n" } else { "run,t,tau_r,tau_l\n" });
    say(&format!(
        "excite: {} tests for {} ({} commands up to {command_max} {unit}):",
        tests.len(),
        base.source,
        drive.params().kind()
    ))?;
    say("run  test                          duration_s  safe_distance_m")?;
    for (k, test) in tests.iter().enumerate() {
        let (t, c) = test.profile(&settings);
        for i in 0..t.len() {
            let _ = writeln!(csv, "{k},{},{},{}", t[i], c[0][i], c[1][i]);
        }
        let dist = test.safe_distance_m(&settings, robot, drive).map_err(bad)?;
        say(&format!("{k:<4} {:<29} {:>10.1} {:>16.2}", test.name(), test.duration_s(&settings), dist))?;
    }
    crate::atomic::write_text(output, &csv)?;
    say(&format!("wrote {}", wmr_scenario::shown(output)))?;
    if let Some(log_path) = log {
        let noise = LogNoise { encoder_fraction: encoder_noise, jitter_s, seed };
        let table = log_table(robot, drive, &tests, &settings, noise).map_err(bad)?;
        let mut text = table.names().join(",");
        text.push('\n');
        let cols: Vec<&[f64]> = table.names().iter().map(|n| table.column(n).expect("named")).collect();
        let mut field = String::new();
        for i in 0..table.rows() {
            for (j, c) in cols.iter().enumerate() {
                crate::csv_sink::format_f64(c[i], &mut field);
                text.push_str(if j == 0 { "" } else { "," });
                text.push_str(&field);
            }
            text.push('\n');
        }
        crate::atomic::write_text(log_path, &text)?;
        say(&format!(
            "wrote {} (the robot playing them: encoder noise {encoder_noise} of the travel per sample, jitter up to {jitter_s} s, seed {seed})",
            wmr_scenario::shown(log_path)
        ))?;
    }
    Ok(())
}

/// `wmr-cli replay LOG --robot ROBOT`: each run of the log from its first sample, open
/// loop on its commands; the errors against the logged wheel speeds and poses.
pub fn replay(
    log_path: &Path,
    robot_path: &Path,
    horizon_s: f64,
    namespace: Option<&str>,
    access: &wmr_scenario::FileAccess,
) -> Result<()> {
    let base = base(Some(robot_path), access)?;
    let robot: Robot<f64> = base.robot.validate().map_err(|e| bad_input(format!("{}: {e}", base.source)))?;
    let drive = base.drive.validate(&robot).map_err(|e| bad_input(format!("{}: {e}", base.source)))?;
    let kind = if matches!(drive, Drive::DcMotor(_)) { CommandKind::Voltage } else { CommandKind::Torque };
    let table = read_table(log_path, namespace, kind)?;
    let shown = wmr_scenario::shown(log_path);
    let log = Log::from_table(&table, &ColumnNames::default(), kind).map_err(|e| bad_input(format!("{shown}: {e}")))?;
    let report =
        wmr_identify::replay::replay(&log, robot, drive, horizon_s).map_err(|e| bad_input(format!("{shown}: {e}")))?;
    let from = if horizon_s > 0.0 {
        format!("from the log's state every {horizon_s} s")
    } else {
        "from each run's first sample".to_owned()
    };
    say(&format!("replay: {} on the commands of {shown} ({} runs, open loop {from})", base.source, report.runs.len()))?;
    say("run  samples  speed_rms_rad_s  speed_rms_pct  speed_final_rad_s  pos_rms_m  pos_final_m  heading_final_rad")?;
    for r in &report.runs {
        say(&format!(
            "{:<4} {:>7}  {:>15.4e}  {:>13.3}  {:>17.4e}  {:>9}  {:>11}  {:>17}",
            r.index,
            r.samples,
            r.speed_rms_rad_s,
            100.0 * r.speed_rms_relative,
            r.speed_final_rad_s,
            opt(r.position_rms_m),
            opt(r.position_final_m),
            opt(r.heading_final_rad),
        ))?;
    }
    let t = &report.total;
    say(format!(
        "all  {:>7}  {:>15.4e}  {:>13.3}  {:>17}  {:>9}",
        t.samples,
        t.speed_rms_rad_s,
        100.0 * t.speed_rms_relative,
        "",
        opt(t.position_rms_m),
    )
    .trim_end())?;
    Ok(())
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "-".to_owned(), |v| format!("{v:.4e}"))
}
