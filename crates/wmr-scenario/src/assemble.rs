//! One run's closed loop from a validated [`Setup`]: the plant at its start pose, the
//! run's sensor, a fresh copy of the built controller, a fixed goal and the plant step.

use crate::reference::RunReference;
use wmr_core::{AnyLaw, AnyReference, AnySensor, ClosedLoop, FixedGoal, ParamError, Pose2};

use crate::error::ScenarioError;
use crate::keys::join;
use crate::setup::Setup;
use crate::sim::SimSpec;

/// The closed loop of one run.
pub type RunLoop = ClosedLoop<f64, AnyLaw<f64>, AnySensor<f64>, RunReference>;

/// Where a run's values came from, to name them in errors: the table holding its start
/// and goal (`run[2]`, `sweep`) and its controller (`controller`, `sweep.controllers[1]`).
#[derive(Clone, Copy, Debug)]
pub struct Origin<'a> {
    /// Path of the table with `start` and `goal`.
    pub run: &'a str,
    /// Path of the controller table.
    pub controller: &'a str,
}

impl Origin<'_> {
    /// The scenario key of a core error raised while assembling the loop.
    pub fn key_of(&self, e: &ParamError) -> ScenarioError {
        let key = match e.field {
            "dt" => "sim.dt".to_owned(),
            "control_dt" => join(self.controller, "control_dt"),
            field @ ("rate_hz" | "latency" | "position_noise" | "heading_noise_deg" | "pose" | "fix_rate_hz"
            | "odometry_noise") => join("sensor", field),
            field => join(self.run, field),
        };
        ScenarioError::from_param(e, &key)
    }
}

/// The loop of run number `run` (it selects the sensor's noise stream) from `start` to
/// `goal` (m, m, rad) with the plant step and settle rule of `sim`.
pub fn closed_loop(
    setup: &Setup,
    run: u64,
    start: Pose2<f64>,
    goal: Pose2<f64>,
    sim: &SimSpec,
    origin: Origin<'_>,
) -> Result<RunLoop, ScenarioError> {
    assemble(setup, run, start, || FixedGoal::new(goal).map(AnyReference::Goal), sim, origin)
}

/// [`closed_loop`] following `reference` (a moving one, for a tracking run).
pub fn closed_loop_to(
    setup: &Setup,
    run: u64,
    start: Pose2<f64>,
    reference: RunReference,
    sim: &SimSpec,
    origin: Origin<'_>,
) -> Result<RunLoop, ScenarioError> {
    assemble(setup, run, start, || Ok(reference), sim, origin)
}

/// The loop with the reference `reference` makes. Checked in this order (plant, sensor,
/// reference, loop) so a run's first error stays the one it always was.
fn assemble(
    setup: &Setup,
    run: u64,
    start: Pose2<f64>,
    reference: impl FnOnce() -> Result<RunReference, ParamError>,
    sim: &SimSpec,
    origin: Origin<'_>,
) -> Result<RunLoop, ScenarioError> {
    let plant = setup.plant(start).map_err(|e| origin.key_of(&e))?;
    let sensor = setup.sensor_for(run).map_err(|e| origin.key_of(&e))?;
    let controller = setup.controller_for(run).map_err(|e| origin.key_of(&e))?;
    let reference = reference().map_err(|e| origin.key_of(&e))?;
    ClosedLoop::with_sensor(plant, sensor, controller, reference, sim.dt())
        .map(|lp| {
            lp.stop_when_settled(sim.stop_when_settled())
                .early_arrival(sim.early_arrival())
                .with_obstacles(setup.obstacles)
                .goal_tolerance(sim.xy_goal_tolerance(), sim.yaw_goal_tolerance_deg().to_radians())
        })
        .map_err(|e| origin.key_of(&e))
}
