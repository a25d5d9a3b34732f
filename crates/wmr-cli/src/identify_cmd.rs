//! `wmr-cli identify`, `excite` and `replay` (docs/identify.md): fit a robot file to a
//! log, write the command profiles that excite a robot, and run a robot file open loop on
//! a log's commands.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;
use wmr_core::{Drive, Robot};
use wmr_identify::excite::{ExciteSettings, Test};
use wmr_identify::sim::{LogNoise, log_table};
use wmr_identify::{ColumnNames, CommandKind, IdentifyError, Log, Table};

use crate::errors::{bad_input, say};
use wmr_identify::file::{
    Base, FileError, c_guard, c_header as c_header_text, command_kind, identify_table, residual_unit,
};

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
        command_kind(self == DriveKind::DcMotor)
    }
}

/// An identification error as bad input (exit 2), its message unchanged.
fn bad(e: IdentifyError) -> anyhow::Error {
    bad_input(e.to_string())
}

/// A shared identification error as bad input (exit 2), its message unchanged.
fn bad_file(e: FileError) -> anyhow::Error {
    bad_input(e.to_string())
}

/// The robot file `path` (registered as an input), or the paper's robot.
pub fn base(path: Option<&Path>, access: &wmr_scenario::FileAccess) -> Result<Base> {
    if let Some(p) = path {
        crate::atomic::register_input(p);
    }
    wmr_identify::file::base(path, access).map_err(bad_file)
}

/// Reads the log at `path` into a table (registered as an input): a CSV or a ROS 2 MCAP
/// ([`wmr_identify::file::read_table`]).
pub fn read_table(path: &Path, namespace: Option<&str>, kind: CommandKind) -> Result<Table> {
    let table = wmr_identify::file::read_table(path, namespace, kind).map_err(bad_file)?;
    crate::atomic::register_input(path);
    Ok(table)
}

/// `wmr-cli identify LOG -o OUT`.
#[allow(clippy::too_many_arguments)]
pub fn identify(
    log_path: &Path,
    output: &Path,
    drive: DriveKind,
    robot_path: Option<&Path>,
    hold: Option<&[String]>,
    namespace: Option<&str>,
    c_header: Option<&Path>,
    access: &wmr_scenario::FileAccess,
) -> Result<()> {
    let base = base(robot_path, access)?;
    let table = read_table(log_path, namespace, drive.command())?;
    // OUT (and the header) must not be an input (checked before the fit, so a refusal
    // costs nothing).
    crate::atomic::target_of(output)?;
    if let Some(h) = c_header {
        crate::atomic::target_of(h)?;
        if h == output {
            return Err(bad_input("--c-header: the same file as -o; give the header its own name (robot.h)"));
        }
    }
    let shown = wmr_scenario::shown(log_path);
    let id = identify_table(&table, &shown, &base, drive.command(), hold).map_err(bad_file)?;
    let fit = &id.fit;
    crate::atomic::write_text(output, &id.text)?;
    if let Some(h) = c_header {
        crate::atomic::write_text(h, &c_header_text(&id, &shown, &c_guard(h)))?;
    }
    let mut summary = String::new();
    let _ = writeln!(
        summary,
        "identify: {} of {} rows used ({} equations), condition number {:.3}, RMS residual {:.4e} {}",
        fit.rows_used,
        fit.rows_total,
        fit.equations,
        fit.condition,
        fit.rms_residual,
        residual_unit(id.kind)
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
    if let Some(h) = c_header {
        let _ = write!(summary, "\nwrote {} (C header)", wmr_scenario::shown(h));
    }
    for line in summary.lines() {
        say(line)?;
    }
    Ok(())
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

/// Seconds of the replay's per-second error table on one line.
const PER_LINE: usize = 10;

/// `wmr-cli replay LOG --robot ROBOT`: each run of the log from its first sample, open
/// loop on its commands; the errors against the logged wheel speeds and poses.
pub fn replay(
    log_path: &Path,
    robot_path: &Path,
    horizon_s: f64,
    namespace: Option<&str>,
    plot: Option<(&Path, usize)>,
    access: &wmr_scenario::FileAccess,
) -> Result<()> {
    let base = base(Some(robot_path), access)?;
    let robot: Robot<f64> = base.robot.validate().map_err(|e| bad_input(format!("{}: {e}", base.source)))?;
    let drive = base.drive.validate(&robot).map_err(|e| bad_input(format!("{}: {e}", base.source)))?;
    let kind = if matches!(drive, Drive::DcMotor(_)) { CommandKind::Voltage } else { CommandKind::Torque };
    let table = read_table(log_path, namespace, kind)?;
    let shown = wmr_scenario::shown(log_path);
    let log = Log::from_table(&table, &ColumnNames::default(), kind).map_err(|e| bad_input(format!("{shown}: {e}")))?;
    // The plot's run must be in the log, and the SVG not an input (both before the replay).
    let plot = match plot {
        Some((svg, run)) => {
            let Some(k) = log.runs.iter().position(|r| r.index == run) else {
                let have: Vec<String> = log.runs.iter().map(|r| r.index.to_string()).collect();
                return Err(bad_input(format!(
                    "--plot-run {run}: {shown} has no such run (its runs: {})",
                    have.join(", ")
                )));
            };
            crate::atomic::target_of(svg)?;
            Some((svg, k))
        }
        None => None,
    };
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
    // Ten seconds a line, each line led by its first second, so a long run stays readable.
    say(&format!(
        "wheel-speed error RMS in each second of log, rad/s (second 0: each run's first compared sample; {PER_LINE} a line)"
    ))?;
    say("run  from_s")?;
    for tr in &report.traces {
        for (k, chunk) in tr.speed_rms_per_second_rad_s.chunks(PER_LINE).enumerate() {
            let values: Vec<String> = chunk.iter().map(|v| format!("{v:.2e}")).collect();
            let run = if k == 0 { tr.index.to_string() } else { String::new() };
            say(&format!("{run:<4} {:>6}  {}", k * PER_LINE, values.join(" ")))?;
        }
    }
    if let Some((svg, k)) = plot {
        let tr = &report.traces[k];
        let run = wmr_plot::ReplayRun {
            t_s: &tr.t_s,
            logged_speed: [&tr.logged_speed[0], &tr.logged_speed[1]],
            replayed_speed: [&tr.replayed_speed[0], &tr.replayed_speed[1]],
            speed_rms_per_second: &tr.speed_rms_per_second_rad_s,
            logged_pose: tr.logged_pose.as_ref().map(|p| [&p[0][..], &p[1][..], &p[2][..]]),
            replayed_pose: [&tr.replayed_pose[0], &tr.replayed_pose[1], &tr.replayed_pose[2]],
        };
        let title = format!("replay of {} on run {} of {shown}", base.source, tr.index);
        let text = wmr_plot::replay_svg(&title, &run).map_err(|e| bad_input(format!("--plot: {e}")))?;
        crate::atomic::write_text(svg, &text)?;
        say(&format!("wrote {} (run {})", wmr_scenario::shown(svg), tr.index))?;
    }
    Ok(())
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "-".to_owned(), |v| format!("{v:.4e}"))
}
