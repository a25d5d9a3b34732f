//! `wmr-cli trace FILE.toml -o OUT.bin|OUT.csv [--run I]`: one run of a scenario in f32,
//! as a microcontroller runs it, with every control tick's inputs (true state,
//! measurement, the reference's state: a goal at rest or a moving reference) and outputs
//! (drive command, the law's errors).
//!
//! The binary form is the trace format of `wmr_core::trace` (little-endian 32-bit words:
//! header, the loop's configuration, one record per tick); the firmware's `replay`
//! program checks it on the Cortex-M4F under QEMU, tick by tick, bit for bit. The CSV
//! form has the same records, one row per tick, each f32 printed so it reads back to the
//! same bits.
//!
//! The scenario's values (f64) are rounded to f32 once, by writing the configuration
//! words; the loop here is then built from the words read back, so the file describes
//! exactly what ran. The loop is `ClosedLoop` itself: a control tick at t = 0 (measure,
//! update, hold the command), then `control_dt / dt` RK4 steps between ticks, time from
//! the loop's clock (in f32, step count times dt).
//!
//! Order and memory (issue 25, item 9): OUT is checked first (as `run` checks it: a
//! regular file is written atomically, a character device, a FIFO or `-` is streamed
//! to), then the loop is built in f32 (a value that does not hold in f32 is bad input,
//! exit 2, before anything is written), then each tick's record is written as it is
//! made: memory stays flat whatever `sim.t_end`. The binary header holds the tick count:
//! a file gets the count of a run to `t_end` and has it rewritten if the run diverges
//! earlier; a stream cannot be rewritten, so the run is simulated once to count the
//! ticks and once to write them.

use std::io::{Seek as _, SeekFrom, Write};
use std::path::Path;

use anyhow::{Result, anyhow};
use wmr_core::trace::{self, CONFIG_WORDS, Config, ConfigOf, HEADER_WORDS, RECORD_WORDS, Record, ReferenceConfig};
use wmr_core::{ClosedLoop, Controller, ParamError, Plant, PoseSensor, SensorParams, WheelStage, Wheels};
use wmr_scenario::{Scenario, ScenarioError};

use crate::atomic::{OutWriter, Output};
use crate::errors::{StdoutClosed, bad_input, is_broken_pipe};

/// The trace's file format: `--format`, or OUT's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum TraceFormat {
    /// `wmr_core::trace` words.
    Bin,
    /// One row per tick.
    Csv,
}

impl TraceFormat {
    /// `given`, else from OUT's extension, `.bin` or `.csv`; anything else is bad input
    /// (names `-o`).
    pub fn of(out: &Path, given: Option<Self>) -> Result<Self, ScenarioError> {
        if let Some(f) = given {
            return Ok(f);
        }
        match out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("bin") => Ok(TraceFormat::Bin),
            Some("csv") => Ok(TraceFormat::Csv),
            _ => Err(ScenarioError::new(
                "-o",
                format!("cannot tell the trace format of {}: name it .bin or .csv, or pass --format", out.display()),
            )),
        }
    }
}

/// What `trace` did, for the summary line.
#[derive(Clone, Debug, PartialEq)]
pub struct Traced {
    /// Control ticks written.
    pub ticks: u64,
    /// The law's kind.
    pub law: &'static str,
    /// Time of the last tick, s.
    pub t_last: f32,
    /// True when a plant step diverged (the trace ends at the last good tick).
    pub diverged: bool,
}

/// A core error met while building the loop in f32 (a value valid in f64 may not be):
/// bad input (exit 2).
fn f32_error(e: ParamError) -> anyhow::Error {
    bad_input(format!("the scenario does not hold in f32: {}: {} (got {})", e.field, e.reason, num_f32(e.value)))
}

/// An f32 value (widened in a core error) as the shortest text that reads back to it as
/// an f32 (`1e25`, not `9.999999562023526e24`), in exponent form when very large or small.
fn num_f32(v: f64) -> String {
    let v = v as f32;
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-5..1e16).contains(&a) { format!("{v}") } else { format!("{v:e}") }
}

/// The run's configuration as the trace records it (f64, rounded when encoded).
fn config_of(scenario: &Scenario, run: usize) -> Result<ConfigOf<f64>, ScenarioError> {
    let spec = scenario.runs().get(run).ok_or_else(|| {
        ScenarioError::new("--run", format!("no run {run}: the scenario has {} run(s)", scenario.runs().len()))
    })?;
    let setup = scenario.setup();
    let c = &setup.controller;
    if !c.law.traced() {
        return Err(ScenarioError::new(
            "controller.kind",
            format!(
                "{} is not traced: its {} keys do not fit the trace's 16 law words (the firmware does not replay it)",
                c.law.kind(),
                c.law.fields().len()
            ),
        ));
    }
    if !setup.obstacles.is_empty() {
        return Err(ScenarioError::new("world.obstacle", "is not traced: the firmware does not replay obstacles"));
    }
    if !setup.pushes.is_empty() {
        return Err(ScenarioError::new("world.push", "is not traced: the firmware does not replay pushes"));
    }
    if setup.payload.is_some() {
        // The trace's words hold [world]'s slope only (issue 42: the payload is not replayed).
        return Err(ScenarioError::new("world.payload", "is not traced: the firmware does not replay a payload"));
    }
    let dt = scenario.sim().dt();
    // The scenario checked that control_dt is a whole multiple of dt.
    let steps_per_tick = (c.control_dt / dt).round() as u32;
    Ok(ConfigOf {
        law: c.law,
        drive: setup.drive.params(),
        robot: *setup.robot.params(),
        model: *setup.model.params(),
        world: *setup.world.params(),
        wheels: c.wheels,
        control_dt: c.control_dt,
        dt,
        steps_per_tick,
        start: spec.start,
        reference: match scenario.tracking() {
            Some(t) => ReferenceConfig::of(&t.reference.built).map_err(|e| {
                // A `file` reference's points are its `path`.
                let file = t.reference.table.get("kind").and_then(|k| k.as_str()) == Some("file");
                ScenarioError::from_param(&e, if file { "reference.path" } else { "reference.points" })
            })?,
            None => ReferenceConfig::Goal(spec.goal),
        },
    })
}

/// How a run of [`run_f32`] ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunEnd {
    /// Control ticks handed to the sink.
    pub ticks: u64,
    /// True when a plant step diverged (the last tick is the last good one).
    pub diverged: bool,
}

/// Why [`run_f32`] stopped early.
#[derive(Debug)]
pub enum RunError<E> {
    /// The configuration does not hold in f32 (before any tick).
    Invalid(ParamError),
    /// The sink refused a record.
    Sink(E),
}

/// Runs the loop of `config` in f32 for `n_steps` plant steps and hands every tick, in
/// order, to `sink` as it is made: the one loop ([`ClosedLoop`]), read at each control
/// tick. Nothing is kept.
pub fn run_f32<E>(
    config: &Config,
    sensor: SensorParams<f32>,
    run: u64,
    n_steps: u64,
    mut sink: impl FnMut(&Record) -> Result<(), E>,
) -> Result<RunEnd, RunError<E>> {
    let built = || -> Result<_, ParamError> {
        let robot = config.robot.validate()?;
        let model = config.model.validate()?;
        let drive = config.drive.validate(&robot)?;
        let world = config.world.validate()?;
        let plant = Plant::on(robot, drive, world, config.start)?;
        let law = config.law.build(model.params(), config.control_dt)?;
        let wheels = WheelStage::new(&config.wheels, model.params(), &drive, config.control_dt)?;
        let controller = Controller::new(law, wheels);
        let sensor = PoseSensor::<f32>::new(sensor, config.control_dt, run)?;
        let reference = config.reference.build()?;
        ClosedLoop::with_sensor(plant, sensor, controller, reference, config.dt)
    };
    let mut lp = built().map_err(RunError::Invalid)?;
    let per_tick = u64::from(config.steps_per_tick);
    let mut ticks = 0;
    loop {
        // Right after a tick the plant still holds the state the sensor measured.
        let tick = lp.last_tick();
        let (m, r, out) = (tick.measurement, tick.reference, tick.output);
        let Wheels { right: wr, left: wl } = m.wheel_speeds;
        let record = Record {
            t: tick.t,
            state: lp.state().to_array(),
            measurement: [m.t, m.pose.x, m.pose.y, m.pose.theta, m.wheel_angles.right, m.wheel_angles.left, wr, wl],
            reference: trace::reference_values(&r),
            command: [out.command.right, out.command.left],
            errors: [out.errors.e_s, out.errors.e_theta, out.errors.dl],
        };
        sink(&record).map_err(RunError::Sink)?;
        ticks += 1;
        if lp.steps() + per_tick > n_steps {
            return Ok(RunEnd { ticks, diverged: false });
        }
        for _ in 0..per_tick {
            if lp.step().is_err() {
                return Ok(RunEnd { ticks, diverged: true });
            }
        }
    }
}

/// Ticks of a run of `n_steps` plant steps that does not diverge.
fn full_ticks(config: &Config, n_steps: u64) -> u64 {
    n_steps / u64::from(config.steps_per_tick.max(1)) + 1
}

/// Bytes of a binary trace of `ticks` ticks.
fn bin_bytes(ticks: u64) -> u128 {
    4 * (HEADER_WORDS as u128 + CONFIG_WORDS as u128 + u128::from(ticks) * RECORD_WORDS as u128)
}

/// Refuses a trace that cannot fit where it goes (a regular file's file system): the
/// binary form's exact size, or the CSV form's least (each value one digit and a comma).
fn check_space(out: &Output, format: TraceFormat, ticks: u64) -> Result<()> {
    let Some(free) = out.free_bytes() else { return Ok(()) };
    let least = match format {
        TraceFormat::Bin => bin_bytes(ticks),
        TraceFormat::Csv => u128::from(ticks) * 2 * RECORD_WORDS as u128,
    };
    if least <= u128::from(free) {
        return Ok(());
    }
    Err(bad_input(format!(
        "sim.t_end: a trace of {ticks} ticks to {} takes at least {least} bytes but only {free} are free there; \
         shorten sim.t_end or write elsewhere",
        out.shown()
    )))
}

/// The binary header of a trace of `ticks` ticks; more than its u32 count holds is bad
/// input (checked for every format, so the CSV and binary forms of a run agree).
fn header_of(ticks: u64) -> Result<[u32; HEADER_WORDS]> {
    let n = u32::try_from(ticks).map_err(|_| {
        bad_input(format!("sim.t_end: {ticks} ticks are more than a trace holds ({}); shorten it", u32::MAX))
    })?;
    Ok(trace::header(n))
}

/// A write error as the command reports it: quietly done when stdout's reader left.
fn write_error(out: &Output, e: impl Into<anyhow::Error>) -> anyhow::Error {
    let e = e.into();
    if out.is_stdout() && is_broken_pipe(&e) {
        anyhow::Error::new(StdoutClosed)
    } else {
        e.context(format!("cannot write {}", out.shown()))
    }
}

/// Writes the trace of run `run` of `scenario` to `output`.
pub fn trace(scenario: &Scenario, run: usize, output: &Path, format: Option<TraceFormat>) -> Result<Traced> {
    let format = TraceFormat::of(output, format)?;
    // Checked before OUT is created: nothing is written for a scenario the trace cannot hold.
    if scenario.setup().odometry() {
        return Err(bad_input(
            "sensor.pose: a trace carries the absolute pose sensor only (the firmware replays its records); \
             a scenario with pose = \"odometry\" cannot be traced: remove the key or set pose = \"absolute\""
                .to_owned(),
        ));
    }
    let config_words = config_of(scenario, run)?.encode();
    let config = Config::decode(&config_words).map_err(|e| anyhow!("trace config: {}", e.0))?;
    // A reference valid in f64 may not be in f32 (a figure-eight's period of 1e25 s
    // squares to 0): named by its scenario key, before OUT is created.
    if scenario.tracking().is_some() {
        config.reference.build().map_err(|e| {
            bad_input(format!(
                "reference.{}: does not hold in f32, the trace's number type: {} (got {})",
                e.field,
                e.reason,
                num_f32(e.value)
            ))
        })?;
    }
    let sensor = scenario.setup().sensor.cast::<f32>();
    let (run, n_steps) = (run as u64, scenario.sim().n_steps());
    // OUT first, then the loop in f32 (one tick, nothing written): both before the run.
    let out = Output::create(output)?;
    let first = |_: &Record| Ok::<(), std::convert::Infallible>(());
    run_f32(&config, sensor, run, 0, first).map_err(|e| match e {
        RunError::Invalid(e) => f32_error(e),
        RunError::Sink(never) => match never {},
    })?;
    let full = full_ticks(&config, n_steps);
    header_of(full)?;
    check_space(&out, format, full)?;
    crate::exec::announce_work(u128::from(n_steps), "trace");
    let mut w = std::io::BufWriter::new(out.writer()?);
    // The tick count of the header: a stream's is counted first (it cannot be rewritten).
    let seekable = w.get_ref().seekable();
    let expected = if format == TraceFormat::Bin && !seekable {
        let counted = run_f32(&config, sensor, run, n_steps, first);
        counted.map_err(|_| anyhow!("the counting run failed after the first one succeeded"))?.ticks
    } else {
        full
    };
    let header = header_of;
    let put_words = |w: &mut std::io::BufWriter<OutWriter>, words: &[u32]| -> std::io::Result<()> {
        words.iter().try_for_each(|word| w.write_all(&word.to_le_bytes()))
    };
    match format {
        TraceFormat::Bin => {
            put_words(&mut w, &header(expected)?).map_err(|e| write_error(&out, e))?;
            put_words(&mut w, &config_words).map_err(|e| write_error(&out, e))?;
        }
        TraceFormat::Csv => writeln!(w, "{}", Record::COLUMNS.join(",")).map_err(|e| write_error(&out, e))?,
    }
    let mut t_last = 0.0;
    let end = run_f32(&config, sensor, run, n_steps, |r: &Record| {
        t_last = r.t;
        match format {
            TraceFormat::Bin => put_words(&mut w, &r.encode()),
            TraceFormat::Csv => {
                let row: Vec<String> = r.values().iter().map(f32::to_string).collect();
                writeln!(w, "{}", row.join(","))
            }
        }
    })
    .map_err(|e| match e {
        RunError::Invalid(e) => f32_error(e),
        RunError::Sink(e) => write_error(&out, e),
    })?;
    if format == TraceFormat::Bin && end.ticks != expected {
        // A file whose run diverged before t_end: the header gets the true count.
        let stale = anyhow!("the trace of a stream has {} ticks, not the {expected} counted", end.ticks);
        let file = w.get_mut();
        if !file.seekable() {
            return Err(stale);
        }
        let words = header(end.ticks)?;
        w.flush().map_err(|e| write_error(&out, e))?;
        w.seek(SeekFrom::Start(0)).map_err(|e| write_error(&out, e))?;
        put_words(&mut w, &words).map_err(|e| write_error(&out, e))?;
    }
    w.flush().map_err(|e| write_error(&out, e))?;
    drop(w);
    let to_stdout = out.is_stdout();
    out.finish().map_err(|e| if to_stdout && is_broken_pipe(&e) { anyhow::Error::new(StdoutClosed) } else { e })?;
    Ok(Traced { ticks: end.ticks, law: config.law.kind(), t_last, diverged: end.diverged })
}
