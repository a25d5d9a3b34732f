//! `wmr-cli identify`, `excite` and `replay` (docs/identify.md): fit a robot file to a
//! log, write the command profiles that excite a robot, and run a robot file open loop on
//! a log's commands.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;
use wmr_core::{Drive, Robot};
use wmr_identify::excite::{ExciteSettings, Test, TwistProfile};
use wmr_identify::sim::{LogNoise, log_table};
use wmr_identify::{ColumnNames, CommandKind, IdentifyError, Log, Table};

use crate::errors::{bad_input, say};
use crate::ros2;
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

/// The format of `excite`'s OUT.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ProfileFormat {
    /// CSV, one row per sample.
    Csv,
    /// A ROS 2 MCAP (the MCAP `ros2` profile): /cmd_vel, geometry_msgs/msg/Twist in CDR
    /// (needs --speed-max).
    Mcap,
}

/// `excite`'s OUT and how it is written.
pub struct ProfileOut<'a> {
    /// OUT.
    pub path: &'a Path,
    /// `--format` (else by OUT's extension).
    pub format: Option<ProfileFormat>,
    /// `--speed-max`, m/s: the profile as twists.
    pub speed_max: Option<f64>,
    /// `--start-ns`: the first message's log time, ns (MCAP).
    pub start_ns: Option<u64>,
    /// `--pause`, s: from one test's stop message to the next test's first (MCAP).
    pub pause: Option<f64>,
    /// `--rosbag2`: metadata.yaml beside OUT (MCAP).
    pub rosbag2: bool,
}

/// The time between tests in a /cmd_vel MCAP when `--pause` is not given, s.
const DEFAULT_PAUSE_S: f64 = 5.0;

/// The settled form of a [`ProfileOut`]: every flag checked against the others.
struct Plan {
    format: ProfileFormat,
    twist: Option<f64>,
    start_ns: u64,
    pause_s: f64,
    /// metadata.yaml's path, with `--rosbag2`.
    bag: Option<std::path::PathBuf>,
}

impl ProfileOut<'_> {
    /// Checks the flags (each refusal names its flag, exit 2), before anything is written.
    fn plan(&self, dt_s: f64) -> Result<Plan> {
        // By OUT's extension: .mcap, else a CSV (as `excite` has always written, whatever
        // the name).
        let format = self.format.unwrap_or_else(|| {
            let ext = self.path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
            if ext.as_deref() == Some("mcap") { ProfileFormat::Mcap } else { ProfileFormat::Csv }
        });
        if let Some(v) = self.speed_max
            && !(v > 0.0 && v.is_finite())
        {
            return Err(bad_input(format!("--speed-max must be > 0 and finite (m/s), got {v}")));
        }
        let mcap = format == ProfileFormat::Mcap;
        if mcap && self.speed_max.is_none() {
            return Err(bad_input(
                "--speed-max: a /cmd_vel profile (an MCAP OUT) is body twists; give the wheels' rim speed at the largest command, m/s",
            ));
        }
        for (flag, given) in
            [("--start-ns", self.start_ns.is_some()), ("--pause", self.pause.is_some()), ("--rosbag2", self.rosbag2)]
        {
            if given && !mcap {
                return Err(bad_input(format!("{flag} describes the /cmd_vel MCAP: write OUT as .mcap")));
            }
        }
        let pause_s = self.pause.unwrap_or(DEFAULT_PAUSE_S);
        // At most a day between tests: also keeps the nanoseconds well inside u64.
        if !(pause_s >= dt_s && pause_s <= 86_400.0) {
            return Err(bad_input(format!(
                "--pause must be from the profile's step ({dt_s} s) to 86400 s, got {pause_s}"
            )));
        }
        let bag = if self.rosbag2 {
            let meta = ros2::bag::metadata_path(self.path);
            if !matches!(crate::atomic::target_of(self.path)?, crate::atomic::Target::File(_)) {
                return Err(bad_input("--rosbag2 writes metadata.yaml beside OUT: give OUT as a file"));
            }
            crate::foxglove_cmd::check_side_output("--rosbag2", &meta, Some(self.path))?;
            Some(meta)
        } else {
            None
        };
        Ok(Plan { format, twist: self.speed_max, start_ns: self.start_ns.unwrap_or(0), pause_s, bag })
    }
}

/// Nanoseconds of `s` seconds (s >= 0, at most a day: [`ProfileOut::plan`]).
fn ns_of(s: f64) -> u64 {
    (s * 1e9).round() as u64
}

/// Refuses, naming `--start-ns`, a start whose profile's last message would be past the
/// largest u64 time.
fn check_span(tests: &[(Vec<f64>, [Vec<f64>; 2])], dt_ns: u64, pause_ns: u64, start_ns: u64) -> Result<()> {
    let span: u64 = tests.iter().map(|(t, _)| (t.len() as u64 - 1) * dt_ns).sum::<u64>()
        + pause_ns * (tests.len() as u64).saturating_sub(1);
    if start_ns.checked_add(span).is_none() {
        return Err(bad_input(format!(
            "--start-ns {start_ns}: the profile's last message would be {span} ns later, past the largest time (2^64 - 1 ns)"
        )));
    }
    Ok(())
}

/// The /cmd_vel MCAP of `tests` (each a run's stamps and twists): test k's message i at
/// `start_ns + base_k + i dt_ns`, base_0 = 0 and each next test `pause_ns` after the
/// last message of the one before; publish time = log time. Its schema and CDR are those
/// of `run --profile ros2` ([`ros2::Ros2Schema`], [`ros2::cdr::CdrWriter`]).
fn cmd_vel_mcap(tests: &[(Vec<f64>, [Vec<f64>; 2])], dt_ns: u64, pause_ns: u64, start_ns: u64) -> Result<Vec<u8>> {
    use mcap::records::MessageHeader;
    check_span(tests, dt_ns, pause_ns, start_ns)?;
    let err = |e: mcap::McapError| anyhow::anyhow!("cannot write the MCAP: {e}");
    let options = mcap::WriteOptions::new()
        .profile("ros2")
        .library(concat!("wmr-cli ", env!("CARGO_PKG_VERSION")))
        .compression(Some(mcap::Compression::Zstd));
    let mut w = options.create(std::io::Cursor::new(Vec::new())).map_err(err)?;
    let schema = ros2::Ros2Schema::of("geometry_msgs/Twist");
    let schema_id = w.add_schema(&schema.name, ros2::ROS2MSG, schema.data.as_bytes()).map_err(err)?;
    let metadata =
        std::collections::BTreeMap::from([("offered_qos_profiles".to_owned(), ros2::offered_qos_profiles(false))]);
    let channel = w.add_channel(schema_id, "/cmd_vel", ros2::CDR, &metadata).map_err(err)?;
    let mut buf = Vec::with_capacity(64);
    let mut base = start_ns;
    let mut sequence = 0u32;
    for (t, tw) in tests {
        for (i, (&v, &omega)) in tw[0].iter().zip(&tw[1]).enumerate() {
            let mut cdr = ros2::cdr::CdrWriter::new(&mut buf);
            // geometry_msgs/Twist: Vector3 linear, Vector3 angular (base_link, REP 103).
            cdr.f64_array(&[v, 0.0, 0.0]);
            cdr.f64_array(&[0.0, 0.0, omega]);
            let ns = base + i as u64 * dt_ns;
            sequence += 1;
            let header = MessageHeader { channel_id: channel, sequence, log_time: ns, publish_time: ns };
            w.write_to_known_channel(&header, &buf).map_err(err)?;
        }
        base += (t.len() as u64 - 1) * dt_ns + pause_ns;
    }
    w.finish().map_err(err)?;
    Ok(w.into_inner().into_inner())
}

/// `wmr-cli excite -o OUT`: the profile (wheel commands as a CSV, or with `--speed-max`
/// twists as a CSV or a /cmd_vel MCAP), a table of the tests with their safe distances,
/// and with `log` a simulated log of the robot playing the commands.
#[allow(clippy::too_many_arguments)]
pub fn excite(
    out: &ProfileOut<'_>,
    robot_path: Option<&Path>,
    command_max: Option<f64>,
    log: Option<&Path>,
    encoder_noise: f64,
    jitter_s: f64,
    seed: u64,
    access: &wmr_scenario::FileAccess,
) -> Result<()> {
    let output = out.path;
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
    let plan = out.plan(settings.dt_s)?;
    let twist = plan.twist.map(|speed_max_m_s| TwistProfile { speed_max_m_s, half_track_m: robot.params().half_track });
    if let Some(tp) = &twist {
        tp.check().map_err(bad)?;
        if log.is_some() {
            return Err(bad_input(
                "--log simulates ROBOT on the wheel commands, --speed-max makes the profile twists: give them in two runs of excite",
            ));
        }
    }
    // Neither output may be an input: refused before anything is printed.
    crate::atomic::target_of(output)?;
    if let Some(l) = log {
        crate::atomic::target_of(l)?;
    }
    let tests = Test::all();
    let unit = if voltage { "V" } else { "N m" };
    let mut csv = String::from(match (&twist, voltage) {
        (Some(_), _) => "run,t,v_cmd,omega_cmd\n",
        (None, true) => "run,t,u_r,u_l\n",
        (None, false) => "run,t,tau_r,tau_l\n",
    });
    let mut profiles = Vec::with_capacity(tests.len());
    let mut distances = Vec::with_capacity(tests.len());
    for test in &tests {
        let (profile, dist) = match &twist {
            None => (test.profile(&settings), test.safe_distance_m(&settings, robot, drive).map_err(bad)?),
            Some(tp) => (tp.profile(test, &settings), tp.safe_distance_m(test, &settings)),
        };
        profiles.push(profile);
        distances.push(dist);
    }
    // The MCAP's clock is checked before anything is printed.
    let (dt_ns, pause_ns) = (ns_of(settings.dt_s), ns_of(plan.pause_s));
    if plan.format == ProfileFormat::Mcap {
        check_span(&profiles, dt_ns, pause_ns, plan.start_ns)?;
    }
    match &twist {
        None => say(&format!(
            "excite: {} tests for {} ({} commands up to {command_max} {unit}):",
            tests.len(),
            base.source,
            drive.params().kind()
        ))?,
        Some(tp) => say(&format!(
            "excite: {} tests for {} as twists (wheel rim speeds up to {} m/s; safe distances if the base follows them):",
            tests.len(),
            base.source,
            tp.speed_max_m_s
        ))?,
    }
    say("run  test                          duration_s  safe_distance_m")?;
    for (k, (test, (t, c))) in tests.iter().zip(&profiles).enumerate() {
        for i in 0..t.len() {
            let _ = writeln!(csv, "{k},{},{},{}", t[i], c[0][i], c[1][i]);
        }
        say(&format!("{k:<4} {:<29} {:>10.1} {:>16.2}", test.name(), test.duration_s(&settings), distances[k]))?;
    }
    if plan.format == ProfileFormat::Csv {
        crate::atomic::write_text(output, &csv)?;
        say(&format!("wrote {}", wmr_scenario::shown(output)))?;
    } else {
        let bytes = cmd_vel_mcap(&profiles, dt_ns, pause_ns, plan.start_ns)?;
        write_bytes(output, &bytes)?;
        let messages: usize = profiles.iter().map(|(t, _)| t.len()).sum();
        say(&format!(
            "wrote {} (ROS 2 MCAP: {messages} /cmd_vel messages, geometry_msgs/msg/Twist every {} s, each test ending on a zero twist, {} s between tests, from {} ns)",
            wmr_scenario::shown(output),
            settings.dt_s,
            plan.pause_s,
            plan.start_ns
        ))?;
        if plan.bag.is_some() {
            let meta = ros2::bag::write_metadata(output)?;
            say(&format!(
                "wrote {} (a rosbag2 bag: ros2 bag play {})",
                wmr_scenario::shown(&meta),
                wmr_scenario::shown(&crate::atomic::parent_dir(output))
            ))?;
        }
    }
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

/// Writes `bytes` to `path` by the rules of [`crate::atomic::write_text`].
fn write_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write as _;
    let out = crate::atomic::Output::create(path)?;
    let mut w = out.writer()?;
    w.write_all(bytes).map_err(|e| anyhow::anyhow!("cannot write {}: {e}", out.shown()))?;
    drop(w);
    out.finish()
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
