//! `wmr-cli`: run TOML scenarios of a differential-drive robot (docs/scenario.md) and write
//! MCAP for Foxglove or CSV; `check` validates and prints the resolved scenario.

mod atomic;
mod csv_sink;
mod errors;
mod exec;
mod foxglove_cmd;
mod foxglove_topics;
mod identify_cmd;
mod keys;
mod layout;
mod live;
mod mcap_sink;
mod plot_cmd;
mod ros2;
mod sinks;
mod sweep_cmd;
mod trace_cmd;

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};

use crate::errors::{bad_input, note};
use crate::sinks::Format;

/// Simulate and control two-wheeled differential-drive robots from scenario files.
#[derive(Parser, Debug)]
#[command(name = "wmr-cli", version, about, disable_help_subcommand = true, after_help = keys::keys_hint())]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run every [[run]] of a scenario and print one summary line per run; with -o OUT,
    /// also write OUT (MCAP or CSV).
    #[command(after_help = keys::keys_hint())]
    Run {
        /// The scenario file (TOML).
        file: PathBuf,
        #[command(flatten)]
        files: Files,
        /// Output file: MCAP when it ends in .mcap, CSV when it ends in .csv; without it, only
        /// the summary is printed. `-` is stdout (with --format). Replaced atomically when
        /// complete; a device or FIFO is written to directly. Its directory must exist.
        #[arg(short, long, value_name = "OUT")]
        output: Option<PathBuf>,
        /// Output format; overrides the extension of OUT.
        #[arg(long, value_enum)]
        format: Option<Format>,
        /// The MCAP's topics: `foxglove` (Foxglove's schemas, the default), `ros2` (ROS 2
        /// messages in CDR, as `ros2 bag record` writes them: /tf, /odom, /joint_states, ...),
        /// or `both`. Only for an MCAP OUT.
        #[arg(long, value_enum, value_name = "PROFILE")]
        profile: Option<mcap_sink::Profile>,
        /// Also write LAYOUT, a Foxglove layout made for these runs (as `wmr-cli layout`).
        #[arg(long, value_name = "LAYOUT")]
        layout: Option<PathBuf>,
        /// With --profile ros2: also write metadata.yaml beside OUT, so that OUT's folder is
        /// a rosbag2 bag (`ros2 bag play DIR`, `ros2 bag info DIR`; rosbag2's Humble format,
        /// which Jazzy reads too).
        #[arg(long)]
        rosbag2: bool,
        /// Serve the runs live on ADDR (default 127.0.0.1:8765, loopback only) over Foxglove's
        /// WebSocket protocol, paced at simulated time; in Foxglove: Open connection. Starts when
        /// a client subscribes; with -o OUT.mcap the file is written too. Give FILE first.
        #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = live::DEFAULT_ADDR,
              value_parser = foxglove_cmd::parse_addr)]
        live: Option<std::net::SocketAddr>,
        /// With --live: simulated seconds per second of wall time (2 = twice as fast) [default: 1].
        #[arg(long, value_name = "X", requires = "live", value_parser = foxglove_cmd::parse_speed)]
        speed: Option<f64>,
    },
    /// Write a Foxglove layout made for a scenario's runs: the 3D view of the plane (paths,
    /// robots, goals of every run) and plots of dl, e_theta and the wheel speeds, with units.
    Layout {
        /// The scenario file (TOML).
        file: PathBuf,
        #[command(flatten)]
        files: Files,
        /// The layout (JSON); import it in Foxglove with Layouts > Import from file.
        #[arg(short, long, value_name = "LAYOUT")]
        output: PathBuf,
        /// The profile of the MCAP it is for (`run --profile`): `ros2` names the ROS 2
        /// topics and frames and shows the robot from its URDF [default: foxglove].
        #[arg(long, value_enum, value_name = "PROFILE")]
        profile: Option<mcap_sink::Profile>,
    },
    /// Run the sweep table of a scenario: every law from every start, in parallel; write one CSV
    /// row per (law, start) and print a comparison table (median / worst per law).
    #[command(after_help = keys::keys_hint())]
    Sweep {
        /// The scenario file (TOML) with a sweep table.
        file: PathBuf,
        #[command(flatten)]
        files: Files,
        /// Outcome CSV (`-`: stdout); default: STEM-sweep.csv in the current folder (STEM:
        /// the scenario file's name without .toml).
        #[arg(short, long, value_name = "OUT")]
        output: Option<PathBuf>,
        /// Also write one region-of-attraction map per law (region-LAW.svg) into DIR
        /// (created if missing; its parent must exist).
        #[arg(long, value_name = "DIR")]
        plots: Option<PathBuf>,
        /// Step the runs in SIMD lanes, several at once: several times faster, outcomes
        /// not bit-identical to the default exact path (final poses within about 1e-9
        /// relative; docs/scenario.md, "The fast path").
        #[arg(long)]
        fast: bool,
    },
    /// Plot a scenario's runs as SVG into DIR: paths.svg (all runs, the paper's Figs. 4-7),
    /// and per run I runI-wheel-speeds.svg (Fig. 8) and runI-errors.svg (Fig. 9).
    Plot {
        /// The scenario file (TOML).
        file: PathBuf,
        #[command(flatten)]
        files: Files,
        /// Output folder (created if missing; its parent must exist).
        #[arg(short, long, value_name = "DIR")]
        output: PathBuf,
    },
    /// Write the scenario's robot as a URDF (ROS's robot description, for Foxglove, Rerun
    /// and robot_state_publisher): platform, wheels on wheel_left_joint / wheel_right_joint,
    /// caster, centre of mass and inertias from the `[robot]` parameters.
    Urdf {
        /// The scenario file (TOML).
        file: PathBuf,
        #[command(flatten)]
        files: Files,
        /// The URDF file; without it, stdout.
        #[arg(short, long, value_name = "URDF")]
        output: Option<PathBuf>,
    },
    /// Read a ROS 2 MCAP (a wmr `--profile ros2` file, or a robot's `ros2 bag record -s mcap`)
    /// and write its /cmd_vel, /joint_states and /odom as one CSV in wmr's columns: a row at
    /// each message time, each column its topic's latest value (docs/scenario.md).
    Log2csv {
        /// The MCAP file.
        log: PathBuf,
        /// The CSV file; without it, stdout.
        #[arg(short, long, value_name = "CSV")]
        output: Option<PathBuf>,
        /// The robot's namespace in a file of several (`/run1` reads /run1/odom, ...).
        #[arg(long, value_name = "NS")]
        namespace: Option<String>,
    },
    /// Validate a scenario and print it with every default filled in (TOML).
    #[command(after_help = keys::keys_hint())]
    Check {
        /// The scenario file (TOML).
        file: PathBuf,
        #[command(flatten)]
        files: Files,
    },
    /// Run one [[run]] in f32, as firmware does, and write every control tick's inputs
    /// (true state, measurement, goal) and outputs (command, errors): OUT.bin for the
    /// firmware's bit-for-bit replay under QEMU (firmware/README.md), or OUT.csv.
    Trace {
        /// The scenario file (TOML).
        file: PathBuf,
        #[command(flatten)]
        files: Files,
        /// Output file: .bin (the trace format of wmr_core::trace) or .csv.
        #[arg(short, long, value_name = "OUT")]
        output: PathBuf,
        /// Which [[run]] (0 = the first).
        #[arg(long, default_value_t = 0)]
        run: usize,
        /// Trace format; without it, from OUT's extension (.bin or .csv). Needed for `-`
        /// (stdout) and devices such as /dev/null, which are written to as ticks come.
        #[arg(long, value_enum)]
        format: Option<trace_cmd::TraceFormat>,
    },
    /// Fit a robot file to a log (docs/identify.md): mass, inertias and friction (and a DC
    /// motor's constants) by least squares on the model's equations, each value written with
    /// its standard error; refuses a parameter the log does not determine, naming it.
    Identify {
        /// The log: a wmr run's CSV, or a CSV with the columns t, tau_r, tau_l (or u_r, u_l
        /// with --drive dc_motor), phi_r, phi_l (or omega_r, omega_l), optionally run, x, y, theta;
        /// or a ROS 2 MCAP (.mcap): /joint_states effort, position or velocity, and /odom.
        log: PathBuf,
        #[command(flatten)]
        files: Files,
        /// The robot file to write (usable with `[robot] from`).
        #[arg(short, long, value_name = "OUT")]
        output: PathBuf,
        /// What the log's commands are: wheel torques (torque) or motor voltages (dc_motor).
        #[arg(long, value_enum, default_value = "torque")]
        drive: identify_cmd::DriveKind,
        /// A robot file with the geometry (wheel_radius, half_track, com_offset, gear_ratio,
        /// coulomb_speed) and the held values [default: the paper's robot].
        #[arg(long, value_name = "ROBOT")]
        robot: Option<PathBuf>,
        /// Parameters held rather than fitted, `key` (at ROBOT's value) or `key=value`,
        /// comma-separated; replaces the default (torque: none; dc_motor: mass,
        /// viscous_friction, armature_resistance).
        #[arg(long, value_name = "KEYS", num_args = 1)]
        hold: Option<Vec<String>>,
        /// With a ROS 2 MCAP log: the robot's namespace in a file of several (`/run1` reads
        /// /run1/joint_states, ...), as for `log2csv`.
        #[arg(long, value_name = "NS")]
        namespace: Option<String>,
        /// Also write the identified values as a C header of constants for the C API
        /// (crates/wmr-ffi/include/wmr.h): `WMR_IDENTIFIED_<KEY>`, bit for bit the robot
        /// file's, and the initializers WMR_IDENTIFIED_ROBOT_PARAMS, WMR_IDENTIFIED_DRIVE_PARAMS.
        #[arg(long, value_name = "H")]
        c_header: Option<PathBuf>,
    },
    /// Write the command profiles to play on a robot for `identify` (SysId's quasistatic
    /// ramps and dynamic steps; straight, turning and arcs) as CSV, or as body twists for a
    /// base driven by /cmd_vel (--speed-max; a ROS 2 MCAP to `ros2 bag play`), with the room
    /// each needs.
    Excite {
        /// The profile: a CSV of run, t, and tau_r, tau_l (N m) or u_r, u_l (V) by ROBOT's
        /// drive; with --speed-max the twists, run, t, v_cmd (m/s), omega_cmd (rad/s), as a
        /// CSV or (OUT.mcap) a ROS 2 MCAP of /cmd_vel (geometry_msgs/msg/Twist).
        #[arg(short, long, value_name = "OUT")]
        output: PathBuf,
        /// OUT's format [default: mcap for a .mcap OUT, else csv].
        #[arg(long, value_enum)]
        format: Option<identify_cmd::ProfileFormat>,
        /// The profile as body twists for a base driven by /cmd_vel: each wheel's rim speed
        /// at the largest command, m/s (the others in proportion to their command).
        #[arg(long, value_name = "M_PER_S")]
        speed_max: Option<f64>,
        /// With OUT.mcap: the log time of the first message, ns since the Unix epoch
        /// [default: 0].
        #[arg(long, value_name = "NS")]
        start_ns: Option<u64>,
        /// With OUT.mcap: the time between one test's stop message and the next test's
        /// first, s (room to bring the robot back; `ros2 bag play` pauses on space)
        /// [default: 5].
        #[arg(long, value_name = "S")]
        pause: Option<f64>,
        /// With OUT.mcap: also write metadata.yaml beside OUT, so that OUT's folder is a
        /// rosbag2 bag (`ros2 bag play DIR`), as `run --rosbag2` does.
        #[arg(long)]
        rosbag2: bool,
        #[command(flatten)]
        files: Files,
        /// The robot file (its drive and its limits; the safe distances are simulated on it)
        /// [default: the paper's robot].
        #[arg(long, value_name = "ROBOT")]
        robot: Option<PathBuf>,
        /// The largest command, N m at the wheel or V [default: the drive's limit].
        #[arg(long, value_name = "X")]
        command_max: Option<f64>,
        /// Also write LOG, the robot playing the profile as wmr simulates it (a log to try
        /// `identify` on), with --encoder-noise and --jitter.
        #[arg(long, value_name = "LOG")]
        log: Option<PathBuf>,
        /// With --log: encoder noise, a fraction of the wheels' mean travel per sample.
        #[arg(long, value_name = "F", default_value_t = 0.0)]
        encoder_noise: f64,
        /// With --log: each sample up to this late, s (uniform).
        #[arg(long, value_name = "S", default_value_t = 0.0)]
        jitter: f64,
        /// With --log: the noise's seed.
        #[arg(long, default_value_t = 0)]
        seed: u64,
    },
    /// Run a robot file open loop on a log's commands and print the error against the
    /// logged wheel speeds and poses (RMS and final, per run): how a fit is judged.
    Replay {
        /// The log (as for `identify`; the commands' columns by ROBOT's drive).
        log: PathBuf,
        #[command(flatten)]
        files: Files,
        /// The robot file to replay.
        #[arg(long, value_name = "ROBOT")]
        robot: PathBuf,
        /// Start again from the log's state every S seconds (0: once per run). An open-loop
        /// replay cannot follow an unstable motion (d > 0 driving backward spins on the
        /// smallest error): a short horizon measures the model instead (docs/identify.md).
        #[arg(long, value_name = "S", default_value_t = 0.0)]
        horizon: f64,
        /// With a ROS 2 MCAP log: the robot's namespace in a file of several (`/run1` reads
        /// /run1/joint_states, ...), as for `log2csv`.
        #[arg(long, value_name = "NS")]
        namespace: Option<String>,
        /// Also draw one run of the replay as an SVG: the logged and replayed wheel speeds,
        /// the error's RMS per second, and the logged and replayed paths of C.
        #[arg(long, value_name = "SVG")]
        plot: Option<PathBuf>,
        /// With --plot: the run to draw (its `run` index).
        #[arg(long, value_name = "N", default_value_t = 0)]
        plot_run: usize,
    },
    /// Print this help, a subcommand's (`help run`), or the scenario file's keys with their
    /// units, defaults and rules (`help keys`, or one table: `help keys robot`).
    Help {
        /// A subcommand, or `keys`.
        topic: Option<String>,
        /// With `keys`: one table or section (robot, run, sweep, outputs, ...; a table's name
        /// with or without its brackets).
        table: Option<String>,
    },
}

/// The files a scenario may name besides those in its folder (issue 39 item 14).
#[derive(clap::Args, Debug)]
struct Files {
    /// Also read the files the scenario names (`[robot] from`, `[reference] path`) from DIR
    /// and below; without it, only from the scenario's folder and below (links followed).
    /// Repeat for several folders.
    #[arg(long = "allow-files-under", value_name = "DIR")]
    allow_files_under: Vec<PathBuf>,
}

impl Files {
    fn access(&self) -> Result<wmr_scenario::FileAccess> {
        wmr_scenario::FileAccess::under(&self.allow_files_under, wmr_scenario::AllowedBy::CommandLine)
            .map_err(|e| bad_input(e.to_string()))
    }
}

fn main() -> ExitCode {
    let cli = Cli::try_parse().unwrap_or_else(|e| errors::clap_exit(&e));
    // In `run --live` the first signal stops the session (which cleans up and exits).
    let live = matches!(cli.command, Command::Run { live: Some(_), .. });
    let handlers = atomic::install_signal_handlers(live.then_some(&live::STOP_SIGNAL));
    errors::finish(handlers.and_then(|()| run(cli)))
}

fn format_of(out: &Path, format: Option<Format>) -> Result<Format> {
    if let Some(f) = format {
        return Ok(f);
    }
    out.extension().and_then(|e| e.to_str()).and_then(Format::of_extension).ok_or_else(|| {
        bad_input(format!(
            "cannot tell the format of {} from its extension: name it {}, or pass --format",
            wmr_scenario::shown(out),
            Format::extensions()
        ))
    })
}

/// Loads a scenario file ([`exec::load`], which remembers it as an input) and remembers
/// every other file it read (its robot preset, its reference CSVs) as an input too, so
/// that no output of the command (`-o`, `--layout`, `--plots`) replaces one of them.
fn load(file: &Path, files: &Files) -> Result<wmr_scenario::Scenario> {
    let scenario = exec::load(file, &files.access()?)?;
    for input in scenario.inputs() {
        let described =
            format!("{} ({} in {})", wmr_scenario::shown(&input.path), input.key, wmr_scenario::shown(file));
        atomic::register_input_as(&input.path, described);
    }
    Ok(scenario)
}

/// `wmr-cli help [SUBCOMMAND]` as clap's `--help` prints it; `wmr-cli help keys [TABLE]`:
/// the scenario file's keys ([`keys::keys_help_of`]).
fn help(topic: Option<&str>, table: Option<&str>) -> Result<()> {
    match topic {
        Some("keys") => errors::say_raw(&keys::keys_help_of(table).map_err(bad_input)?),
        _ if table.is_some() => Err(bad_input("help: only `help keys` takes a second word (a table)")),
        // Clap prints the help (or its error for an unknown subcommand) as for `SUB --help`.
        _ => {
            let args = ["wmr-cli"].into_iter().chain(topic).chain(["--help"]);
            match Cli::try_parse_from(args) {
                Err(e) => errors::clap_exit(&e),
                Ok(_) => Err(bad_input("help: nothing to show")),
            }
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Check { file, files } => exec::check_command(&file, &files.access()?),
        Command::Log2csv { log, output, namespace } => {
            let shown = wmr_scenario::shown(&log);
            let bytes = wmr_identify::file::read_log_bytes(&log).map_err(|e| bad_input(e.to_string()))?;
            let tables =
                ros2::log::read_log(&bytes, namespace.as_deref()).map_err(|e| bad_input(format!("{shown}: {e}")))?;
            if tables.is_empty() {
                return Err(bad_input(format!("{shown}: no /cmd_vel, /joint_states or /odom messages")));
            }
            let text = csv_sink::log_table_csv(&tables.table());
            match output {
                None => errors::say_raw(&text),
                Some(path) => {
                    atomic::register_input(&log);
                    foxglove_cmd::write_text(&path, &text)?;
                    note(&format!(
                        "wmr-cli: wrote {} ({} odom, {} joint_states, {} cmd_vel messages)",
                        wmr_scenario::shown(&path),
                        tables.odom.len(),
                        tables.joint_states.len(),
                        tables.cmd_vel.len()
                    ));
                    Ok(())
                }
            }
        }
        Command::Urdf { file, files, output } => {
            let scenario = load(&file, &files)?;
            let text = wmr_scenario::urdf::urdf(scenario.robot().params(), scenario.name(), "");
            match output {
                None => errors::say_raw(&text),
                Some(path) => {
                    foxglove_cmd::write_text(&path, &text)?;
                    note(&format!("wmr-cli: wrote {}", wmr_scenario::shown(&path)));
                    Ok(())
                }
            }
        }
        Command::Help { topic, table } => help(topic.as_deref(), table.as_deref()),
        Command::Identify { log, files, output, drive, robot, hold, namespace, c_header } => identify_cmd::identify(
            &log,
            &output,
            drive,
            robot.as_deref(),
            hold.as_deref(),
            namespace.as_deref(),
            c_header.as_deref(),
            &files.access()?,
        ),
        Command::Excite {
            output,
            format,
            speed_max,
            start_ns,
            pause,
            rosbag2,
            files,
            robot,
            command_max,
            log,
            encoder_noise,
            jitter,
            seed,
        } => {
            let out = identify_cmd::ProfileOut { path: &output, format, speed_max, start_ns, pause, rosbag2 };
            identify_cmd::excite(
                &out,
                robot.as_deref(),
                command_max,
                log.as_deref(),
                encoder_noise,
                jitter,
                seed,
                &files.access()?,
            )
        }
        Command::Replay { log, files, robot, horizon, namespace, plot, plot_run } => identify_cmd::replay(
            &log,
            &robot,
            horizon,
            namespace.as_deref(),
            plot.as_deref().map(|p| (p, plot_run)),
            &files.access()?,
        ),
        Command::Trace { file, files, output, run, format } => {
            let scenario = load(&file, &files)?;
            let t = trace_cmd::trace(&scenario, run, &output, format)?;
            let end = if t.diverged { "diverged" } else { "completed" };
            let shown = if output.as_os_str() == "-" { "stdout".to_owned() } else { wmr_scenario::shown(&output) };
            let line = format!("trace: {} ticks of {} (f32) to t = {} s, {end}: {shown}", t.ticks, t.law, t.t_last);
            // With the trace on stdout the summary goes to stderr, so the data stays clean.
            if output.as_os_str() == "-" {
                note(&line);
                Ok(())
            } else {
                errors::say(&line)
            }
        }
        Command::Sweep { file, files, output, plots, fast } => {
            let scenario = load(&file, &files)?;
            let output = output.unwrap_or_else(|| sweep_cmd::default_output(&file));
            sweep_cmd::sweep(&scenario, &file, &output, plots.as_deref(), fast, std::io::stderr().is_terminal())
        }
        Command::Plot { file, files, output } => {
            let scenario = load(&file, &files)?;
            let written = plot_cmd::plot(&scenario, &file, &output)?;
            note(&format!("wmr-cli: wrote {} SVG file(s) into {}", written.len(), wmr_scenario::shown(&output)));
            Ok(())
        }
        Command::Layout { file, files, output, profile } => {
            let scenario = load(&file, &files)?;
            exec::require_runs(&scenario, &file)?;
            foxglove_cmd::write_layout(&scenario, &output, profile.unwrap_or_default())?;
            note(&format!("wmr-cli: wrote {} ({} run(s))", wmr_scenario::shown(&output), scenario.runs().len()));
            Ok(())
        }
        Command::Run { file, files, output, format, profile, layout, rosbag2, live, speed } => {
            if rosbag2 && profile != Some(mcap_sink::Profile::Ros2) {
                foxglove_cmd::usage_error(
                    "--rosbag2: a rosbag2 bag holds ROS 2 channels only; give --profile ros2 (and -o OUT.mcap)",
                );
            }
            if profile.is_some() && live.is_some() {
                foxglove_cmd::usage_error("--profile: --live serves the Foxglove topics only; leave --profile out");
            }
            if let Some(addr) = live {
                let scenario = load(&file, &files)?;
                exec::require_runs(&scenario, &file)?;
                return foxglove_cmd::run_live(&scenario, output, format, layout, addr, speed.unwrap_or(1.0));
            }
            let Some(output) = output else {
                if layout.is_some() || format.is_some() || profile.is_some() {
                    foxglove_cmd::usage_error("--layout, --format and --profile describe OUT: give -o OUT");
                }
                let scenario = load(&file, &files)?;
                return exec::run_summary(&scenario, &file);
            };
            let format = format_of(&output, format)?;
            if layout.is_some() && format != Format::Mcap {
                foxglove_cmd::usage_error("--layout describes the MCAP topics: write OUT as .mcap");
            }
            if profile.is_some() && format != Format::Mcap {
                foxglove_cmd::usage_error("--profile chooses the MCAP's topics: write OUT as .mcap");
            }
            let scenario = load(&file, &files)?;
            // After the load, which names the inputs LAYOUT must not replace either (it is
            // written after OUT: refused now, before OUT is).
            if let Some(l) = &layout {
                foxglove_cmd::check_layout_path(l, Some(&output))?;
            }
            let bag = rosbag2.then(|| ros2::bag::metadata_path(&output));
            if let Some(meta) = &bag {
                if !matches!(atomic::target_of(&output)?, atomic::Target::File(_)) {
                    foxglove_cmd::usage_error("--rosbag2 writes metadata.yaml beside OUT: give OUT as a file");
                }
                foxglove_cmd::check_side_output("--rosbag2", meta, Some(&output))?;
            }
            exec::run_command(&scenario, &file, &output, format, profile.unwrap_or_default(), layout.as_deref())?;
            if bag.is_some() {
                let meta = ros2::bag::write_metadata(&output)?;
                note(&format!(
                    "wmr-cli: wrote {} (a rosbag2 bag: ros2 bag play {})",
                    wmr_scenario::shown(&meta),
                    wmr_scenario::shown(&atomic::parent_dir(&output))
                ));
            }
            Ok(())
        }
    }
}
