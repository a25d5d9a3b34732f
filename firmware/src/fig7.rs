//! The Fig. 7 run in f32 with any law: start (0, 0, 0), goal (1, 1, 120 deg), torque
//! drive, the paper's robot, 60 s at dt = control_dt = 1 ms. The loop is `ClosedLoop`'s,
//! composed by hand so a meter can wrap the control update and the plant step.

use wmr_core::controller::Law;
use wmr_core::sensor::Sensor as _;
use wmr_core::{
    ControlOutput, Controller, DriveParams, LyapunovLaw, LyapunovParams, Measurement, PaperLaw, PaperParams,
    PerfectSensor, Plant, PolarLaw, PolarParams, Pose2, ReferenceState, Robot, Termination, WheelStage,
    WheelStageParams, Wheels,
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

/// The law of a cost program, built for the paper's robot at 1 ms.
pub trait FirmwareLaw: Law<f32> + Copy + Sized {
    /// Its `kind` name.
    const KIND: &'static str;
    /// The law with its default keys.
    fn build() -> Option<Self>;
}

impl FirmwareLaw for PaperLaw<f32> {
    const KIND: &'static str = "paper";
    fn build() -> Option<Self> {
        PaperLaw::new(PaperParams::paper(), Robot::<f32>::paper().params(), DT).ok()
    }
}

impl FirmwareLaw for PolarLaw<f32> {
    const KIND: &'static str = "polar";
    fn build() -> Option<Self> {
        PolarLaw::new(PolarParams::default()).ok()
    }
}

impl FirmwareLaw for LyapunovLaw<f32> {
    const KIND: &'static str = "lyapunov";
    fn build() -> Option<Self> {
        LyapunovLaw::new(LyapunovParams::default()).ok()
    }
}

/// The final pose and the plant steps taken.
pub struct Ran {
    /// Final true pose.
    pub pose: Pose2<f32>,
    /// Plant steps taken.
    pub steps: u32,
}

/// Fig. 7 with law `L` and its wheel stage, the plant and the perfect sensor. `None` when
/// a parameter is refused (they are the defaults, so never in practice).
pub fn run<L: FirmwareLaw>(meter: &mut impl Meter) -> Option<Ran> {
    let robot = Robot::<f32>::paper();
    let drive_params = DriveParams::default();
    let drive = drive_params.validate(&robot).ok()?;
    let wheels = WheelStage::new(&WheelStageParams::for_drive(&drive_params, robot.params()), robot.params(), &drive, DT).ok()?;
    let mut ctrl = Controller::new(L::build()?, wheels);
    let mut plant = Plant::new(robot, drive, Pose2::default()).ok()?;
    let goal = ReferenceState::at_rest(goal());
    let mut sensor = PerfectSensor;
    let mut k = 0;
    loop {
        let t = k as f32 * DT;
        let m: Measurement<f32> = sensor.measure(t, plant.state(), robot.params());
        let out = meter.update(&mut || ctrl.update(t, &m, &goal));
        plant.apply(out.command);
        if k == core::hint::black_box(STEPS) {
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
