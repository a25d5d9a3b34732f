//! The Fig. 7 run in f32 with any stabilization law: start (0, 0, 0), goal (1, 1,
//! 120 deg); a tracking law follows the figure-eight of `examples/tracking` (2 m x 1 m in
//! 30 s) from its start. Torque drive, the paper's robot, 60 s at dt = control_dt = 1 ms.
//! The loop is `ClosedLoop`'s, composed by hand so a meter can wrap the control update
//! (the reference's state at the tick, then the law and the wheel stage) and the plant
//! step.

use wmr_core::controller::Law;
use wmr_core::reference::{FigureEight, Reference};
use wmr_core::sensor::Sensor as _;
use wmr_core::{
    ControlOutput, Controller, DisturbanceObserverParams, DriveParams, FixedGoal, LawSpec as _, Measurement,
    PerfectSensor, Plant, Pose2, Robot, Termination, WheelStage, WheelStageParams, Wheels,
};

/// Plant steps: 60 s at 1 ms.
pub const STEPS: u32 = 60_000;
/// Plant step = control period, s.
pub const DT: f32 = 1e-3;

/// The goal pose of Fig. 7 (m, m, rad).
pub fn goal() -> Pose2<f32> {
    Pose2::new(1.0, 1.0, 120f64.to_radians() as f32)
}

/// What a loop hands its meter: the control update and the plant step, each as a call.
pub trait Meter {
    /// Runs one control update.
    fn update(&mut self, f: &mut dyn FnMut() -> ControlOutput<f32>) -> ControlOutput<f32>;
    /// Runs one plant step.
    fn step(&mut self, f: &mut dyn FnMut() -> Result<(), Termination>) -> Result<(), Termination>;
}

/// No meter: the calls as they are.
pub struct Plain;

impl Meter for Plain {
    #[inline(always)]
    fn update(&mut self, f: &mut dyn FnMut() -> ControlOutput<f32>) -> ControlOutput<f32> {
        f()
    }
    #[inline(always)]
    fn step(&mut self, f: &mut dyn FnMut() -> Result<(), Termination>) -> Result<(), Termination> {
        f()
    }
}

/// The law of a cost program, built for the paper's robot at 1 ms, and what it follows.
pub trait FirmwareLaw: Law<f32> + Copy + Sized {
    /// Its `kind` name.
    const KIND: &'static str;
    /// What it follows: Fig. 7's goal, or the figure-eight.
    type Reference: Reference<f32>;
    /// The law with its default keys.
    fn build() -> Option<Self>;
    /// Its reference.
    fn reference() -> Option<Self::Reference>;
    /// Plant steps of its program: [`STEPS`] (60 s), MPPI's [`EMBEDDED_MPPI_RUN_STEPS`].
    const STEPS: u32 = STEPS;
}

/// Fig. 7's goal, for a stabilization law.
fn fig7_goal() -> Option<FixedGoal<f32>> {
    FixedGoal::new(goal()).ok()
}

/// The figure-eight of `examples/tracking/figure_eight.toml` (2 m x 1 m, 30 s), for a
/// tracking law.
fn figure_eight() -> Option<FigureEight<f32>> {
    FigureEight::new(0.0, 0.0, 2.0, 1.0, 30.0).ok()
}

/// MPPI sized for a microcontroller: 64 samples of 20 steps (a 1 s horizon at nav2's
/// `model_dt` of 0.05 s), the dynamic model at its default 2 sub-steps: 2,560 model
/// steps per plan, 1/44 of nav2's defaults (1,000 samples of 56 steps), which the
/// cost of one plan scales with. Every other key its default.
fn embedded_mppi() -> wmr_core::MppiParams<f32> {
    wmr_core::MppiParams { batch_size: EMBEDDED_MPPI_BATCH, time_steps: EMBEDDED_MPPI_STEPS, ..Default::default() }
}

/// MPPI's samples per plan on the firmware ([`embedded_mppi`]).
pub const EMBEDDED_MPPI_BATCH: u32 = 64;
/// MPPI's steps per sample on the firmware ([`embedded_mppi`]).
pub const EMBEDDED_MPPI_STEPS: u32 = 20;
/// Plant steps of MPPI's cost program: 5 s at 1 ms, 100 plans (one per model_dt), the
/// first 5 s of Fig. 7 (60 s under QEMU's instruction counting took 13 minutes).
pub const EMBEDDED_MPPI_RUN_STEPS: u32 = 5_000;

/// `impl FirmwareLaw` for each law of the registry (`wmr_core::for_each_law!`): a law
/// that follows a goal runs Fig. 7, one that follows a trajectory or a path the
/// figure-eight; each with its default keys for the paper's robot at [`DT`].
macro_rules! firmware_laws {
    (@reference Goal) => { FixedGoal<f32> };
    (@reference $other:ident) => { FigureEight<f32> };
    (@make Goal) => { fig7_goal() };
    (@make $other:ident) => { figure_eight() };
    (@params mppi, $krate:tt, $params:ident) => { embedded_mppi() };
    (@params $other:ident, $krate:tt, $params:ident) => { $krate::$params::<f32>::default() };
    (@steps mppi) => { EMBEDDED_MPPI_RUN_STEPS };
    (@steps $other:ident) => { STEPS };
    ($krate:tt; $( $(#[doc = $doc:literal])* $variant:ident($params:ident, $law:ident) = $kind:ident, code $code:literal, follows $follows:ident; )+) => {
        $(
            impl FirmwareLaw for $krate::$law<f32> {
                const KIND: &'static str = stringify!($kind);
                const STEPS: u32 = firmware_laws!(@steps $kind);
                type Reference = firmware_laws!(@reference $follows);
                fn build() -> Option<Self> {
                    firmware_laws!(@params $kind, $krate, $params).build(Robot::<f32>::paper().params(), DT).ok()
                }
                fn reference() -> Option<Self::Reference> {
                    firmware_laws!(@make $follows)
                }
            }
        )+
    };
}

wmr_core::for_each_law!(firmware_laws);

/// The final pose and the plant steps taken.
pub struct Ran {
    /// Final true pose.
    pub pose: Pose2<f32>,
    /// Plant steps taken.
    pub steps: u32,
}

/// Law `L` and its wheel stage on its reference, the plant and the perfect sensor, from
/// the reference's pose at t = 0 (Fig. 7's start for its goal). `None` when a parameter
/// is refused (they are the defaults, so never in practice).
pub fn run<L: FirmwareLaw>(meter: &mut impl Meter) -> Option<Ran> {
    run_with::<L, false>(meter)
}

/// [`run`], with the disturbance observer on the wheel stage (`[controller.observer]
/// kind = "disturbance"`, its default bandwidth) when `OBSERVER`: what the observer adds
/// to a control update (the `cost-observer` program). A constant, so the programs
/// without it link none of it.
pub fn run_with<L: FirmwareLaw, const OBSERVER: bool>(meter: &mut impl Meter) -> Option<Ran> {
    let robot = Robot::<f32>::paper();
    let drive_params = DriveParams::default();
    let drive = drive_params.validate(&robot).ok()?;
    let mut wheels =
        WheelStage::new(&WheelStageParams::for_drive(&drive_params, robot.params()), robot.params(), &drive, DT)
            .ok()?;
    if OBSERVER {
        wheels = wheels.with_observer(DisturbanceObserverParams::default().validate(robot.params(), &drive, DT).ok()?);
    }
    let mut ctrl = Controller::new(L::build()?, wheels);
    let reference = L::reference()?;
    let start = if reference.fixed() { Pose2::default() } else { reference.pose_at(0.0) };
    let mut plant = Plant::new(robot, drive, start).ok()?;
    let mut sensor = PerfectSensor;
    let mut k = 0;
    loop {
        let t = k as f32 * DT;
        let m: Measurement<f32> = sensor.measure(t, plant.state(), robot.params());
        let out = meter.update(&mut || {
            let r = reference.state_at(t);
            match reference.path() {
                Some(path) => ctrl.update_on_path(t, &m, &r, path),
                None => ctrl.update(t, &m, &r),
            }
        });
        plant.apply(out.command);
        if k == core::hint::black_box(L::STEPS) {
            break;
        }
        if meter.step(&mut || plant.step(t, DT)).is_err() {
            break;
        }
        k += 1;
    }
    Some(Ran { pose: plant.state().pose(), steps: k })
}

/// The plant alone under a held command (the `black_box` keeps it unknown to the
/// compiler): what the plant step costs without any controller.
pub fn run_plant(meter: &mut impl Meter) -> Option<Ran> {
    let robot = Robot::<f32>::paper();
    let drive = DriveParams::default().validate(&robot).ok()?;
    let mut plant = Plant::new(robot, drive, Pose2::default()).ok()?;
    // Small torques (N m): the robot circles slowly and stays inside the 1 km box.
    plant.apply(core::hint::black_box(Wheels::new(0.003, 0.002)));
    let mut k = 0;
    while k < core::hint::black_box(STEPS) {
        let t = k as f32 * DT;
        if meter.step(&mut || plant.step(t, DT)).is_err() {
            break;
        }
        k += 1;
    }
    Some(Ran { pose: plant.state().pose(), steps: k })
}
