//! `wmr-cli trace FILE.toml -o OUT.bin|OUT.csv [--run I]`: one run of a scenario in f32,
//! as a microcontroller runs it, with every control tick's inputs (true state,
//! measurement, goal) and outputs (drive command, the law's errors).
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

use std::io::Write as _;
use std::path::Path;

use anyhow::{Context as _, Result, anyhow};
use wmr_core::trace::{self, Config, ConfigOf, Record};
use wmr_core::{ClosedLoop, Controller, FixedGoal, ParamError, Plant, PoseSensor, SensorParams, WheelStage, Wheels};
use wmr_scenario::{Scenario, ScenarioError};

use crate::atomic::AtomicOut;

/// The trace's file format, from OUT's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraceFormat {
    /// `wmr_core::trace` words.
    Bin,
    /// One row per tick.
    Csv,
}

impl TraceFormat {
    /// `.bin` or `.csv`; anything else is bad input (names `-o`).
    pub fn of(out: &Path) -> Result<Self, ScenarioError> {
        match out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("bin") => Ok(TraceFormat::Bin),
            Some("csv") => Ok(TraceFormat::Csv),
            _ => Err(ScenarioError::new(
                "-o",
                format!("cannot tell the trace format of {}: name it .bin or .csv", out.display()),
            )),
        }
    }
}

/// What `trace` did, for the summary line.
#[derive(Clone, Debug, PartialEq)]
pub struct Traced {
    /// Control ticks written.
    pub ticks: usize,
    /// The law's kind.
    pub law: &'static str,
    /// Time of the last tick, s.
    pub t_last: f32,
    /// True when a plant step diverged (the trace ends at the last good tick).
    pub diverged: bool,
}

/// A core error met while building the loop in f32 (a value valid in f64 may not be).
fn f32_error(e: ParamError) -> anyhow::Error {
    anyhow!("the scenario does not hold in f32: {e}")
}

/// The run's configuration as the trace records it (f64, rounded when encoded).
fn config_of(scenario: &Scenario, run: usize) -> Result<ConfigOf<f64>, ScenarioError> {
    let spec = scenario.runs().get(run).ok_or_else(|| {
        ScenarioError::new("--run", format!("no run {run}: the scenario has {} run(s)", scenario.runs().len()))
    })?;
    let setup = scenario.setup();
    let c = &setup.controller;
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
        goal: spec.goal,
    })
}

/// Runs the loop of `config` in f32 for `n_steps` plant steps and returns every tick: the
/// one loop ([`ClosedLoop`]), read at each control tick.
pub fn run_f32(
    config: &Config,
    sensor: SensorParams<f32>,
    run: u64,
    n_steps: u64,
) -> Result<(Vec<Record>, bool), ParamError> {
    let robot = config.robot.validate()?;
    let model = config.model.validate()?;
    let drive = config.drive.validate(&robot)?;
    let world = config.world.validate()?;
    let plant = Plant::on(robot, drive, world, config.start)?;
    let law = config.law.build(model.params(), config.control_dt)?;
    let wheels = WheelStage::new(&config.wheels, model.params(), &drive, config.control_dt)?;
    let controller = Controller::new(law, wheels);
    let sensor = PoseSensor::<f32>::new(sensor, config.control_dt, run)?;
    let goal = FixedGoal::new(config.goal)?;
    let mut lp = ClosedLoop::with_sensor(plant, sensor, controller, goal, config.dt)?;
    let per_tick = u64::from(config.steps_per_tick);
    let mut records = Vec::with_capacity(usize::try_from(n_steps / per_tick + 1).unwrap_or(0));
    loop {
        // Right after a tick the plant still holds the state the sensor measured.
        let tick = lp.last_tick();
        let (m, r, out) = (tick.measurement, tick.reference.pose, tick.output);
        let Wheels { right: wr, left: wl } = m.wheel_speeds;
        records.push(Record {
            t: tick.t,
            state: lp.state().to_array(),
            measurement: [m.t, m.pose.x, m.pose.y, m.pose.theta, m.wheel_angles.right, m.wheel_angles.left, wr, wl],
            goal: [r.x, r.y, r.theta],
            command: [out.command.right, out.command.left],
            errors: [out.errors.e_s, out.errors.e_theta, out.errors.dl],
        });
        if lp.steps() + per_tick > n_steps {
            return Ok((records, false));
        }
        for _ in 0..per_tick {
            if lp.step().is_err() {
                return Ok((records, true));
            }
        }
    }
}

/// Writes the trace of run `run` of `scenario` to `output`.
pub fn trace(scenario: &Scenario, run: usize, output: &Path) -> Result<Traced> {
    let format = TraceFormat::of(output)?;
    let config_words = config_of(scenario, run)?.encode();
    let config = Config::decode(&config_words).map_err(|e| anyhow!("trace config: {}", e.0))?;
    let sensor = scenario.setup().sensor.cast::<f32>();
    let (records, diverged) = run_f32(&config, sensor, run as u64, scenario.sim().n_steps()).map_err(f32_error)?;
    let ticks = u32::try_from(records.len()).context("too many ticks for a trace")?;

    let out = AtomicOut::create(output)?;
    let mut w = std::io::BufWriter::new(out.file()?);
    match format {
        TraceFormat::Bin => {
            let words = trace::header(ticks).into_iter().chain(config_words);
            for word in words.chain(records.iter().flat_map(Record::encode)) {
                w.write_all(&word.to_le_bytes())?;
            }
        }
        TraceFormat::Csv => {
            writeln!(w, "{}", Record::COLUMNS.join(","))?;
            for r in &records {
                let row: Vec<String> = r.values().iter().map(f32::to_string).collect();
                writeln!(w, "{}", row.join(","))?;
            }
        }
    }
    w.flush().with_context(|| format!("cannot write {}", output.display()))?;
    drop(w);
    out.persist()?;
    Ok(Traced { ticks: records.len(), law: config.law.kind(), t_last: records.last().map_or(0.0, |r| r.t), diverged })
}
