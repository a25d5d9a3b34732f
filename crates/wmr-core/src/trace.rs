//! The control trace: every control tick of an f32 closed loop, its inputs (the true
//! state, the measurement, the goal) and its outputs (the drive command and the law's
//! errors). `wmr-cli trace FILE.toml -o run.bin` writes it; the firmware's `replay`
//! program (`firmware/`) replays it on the Cortex-M4F under QEMU and checks every tick
//! bit for bit. Rust only (no C entry points), `no_std`, no allocation.
//!
//! The file is a sequence of little-endian 32-bit words: f32 values by their bit
//! patterns, enums and flags as integers.
//!
//! ```text
//! header   magic "WMRTRACE" (2 words), VERSION, CONFIG_WORDS, RECORD_WORDS, ticks
//! config   CONFIG_WORDS words (ConfigOf::encode): law, drive, robot (the plant's),
//!          model (the controller's robot), wheel stage, control_dt, dt, plant steps
//!          per tick, start pose, ground slope, reference (ReferenceConfig: its kind
//!          and what builds it)
//! records  `ticks` records of RECORD_WORDS words (Record::encode), tick k at
//!          t = k * control_dt:
//!          t, true state (x y theta v omega phi_r phi_l), measurement (t x y theta
//!          phi_r phi_l omega_r omega_l), reference state (x y theta v omega v'
//!          omega'), command (right left), errors (e_s e_theta dl)
//! ```
//!
//! Replaying: the reference, rebuilt from the config, must give the recorded reference
//! state at each tick; tick k's controller, fed the recorded measurement and that
//! reference (and its path, for a path-following law), must give the recorded command
//! and errors; the plant, started at `start` and driven by the recorded commands, must
//! reach each recorded state (the zero-order hold of `ClosedLoop`: control tick at
//! t = 0, then `plant steps per tick` RK4 steps of `dt` between ticks).

use crate::describe::Described;
pub use crate::reference::ReferenceConfig;
use crate::reference::ReferenceState;
use crate::{
    DcMotorParams, DriveParams, LawParams, Pose2, Real, RobotParams, TorqueDriveParams, WheelStageParams, WorldParams,
};

/// The first 8 bytes of a trace file.
pub const MAGIC: [u8; 8] = *b"WMRTRACE";
/// Format version (5: the drives' `deadband`; 6: the robot's `static_friction`).
pub const VERSION: u32 = 6;
/// Words of the header before the config: magic (2), version, config words, record words, ticks.
pub const HEADER_WORDS: usize = 6;
/// Words of [`Config`].
pub const CONFIG_WORDS: usize = REFERENCE_AT + REFERENCE;
/// Words of one [`Record`].
pub const RECORD_WORDS: usize = 28;

/// What was run: everything the replay needs to build the same loop, in f32.
pub type Config = ConfigOf<f32>;

/// Why a trace could not be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct FormatError(pub &'static str);

fn f<T: Real>(v: T) -> u32 {
    (v.to_f64_lossless() as f32).to_bits()
}

fn r(w: u32) -> f32 {
    f32::from_bits(w)
}

/// The word of each `T` field of `P` among its words, one per declared field in
/// declaration order ([`crate::params!`]); the others are copied from a template.
fn real_slots<P: Described>() -> impl Iterator<Item = usize> {
    P::FIELDS.iter().enumerate().filter(|(_, field)| field.ty == "T").map(|(i, _)| i)
}

/// For a parameter struct: its number of words (one per declared field), a writer of its
/// `T` fields into their words ([`real_slots`]), each rounded to f32, and a reader of the
/// struct from those words, the other fields copied from `$template` (the caller reads
/// them). A `T` key declared there is in the trace with no edit here.
macro_rules! real_words {
    ($len:ident, $put:ident, $read:ident, $ty:ident, $template:expr) => {
        const $len: usize = <$ty<f32> as Described>::FIELDS.len();

        fn $put<T: Real>(p: &$ty<T>, out: &mut [u32]) {
            let mut slots = real_slots::<$ty<f32>>();
            let _ = p.map(|v| {
                if let Some(i) = slots.next() {
                    out[i] = f(v);
                }
            });
        }

        fn $read(w: &[u32]) -> $ty<f32> {
            let mut slots = real_slots::<$ty<f32>>();
            let template: $ty<f32> = $template;
            template.map(|v| slots.next().map_or(v, |i| r(w[i])))
        }
    };
}

real_words!(ROBOT, put_robot, read_robot, RobotParams, RobotParams::paper());
real_words!(WHEELS, put_wheels, read_wheels, WheelStageParams, WheelStageParams::default());
real_words!(WORLD, put_world, read_world, WorldParams, WorldParams::default());
real_words!(TORQUE, put_torque, read_torque, TorqueDriveParams, TorqueDriveParams::default());
real_words!(DC_MOTOR, put_dc_motor, read_dc_motor, DcMotorParams, DcMotorParams::default());
/// Every law's keys fit the law's words after its kind word, from the registry.
macro_rules! law_keys_fit {
    ($krate:tt; $( $(#[doc = $doc:literal])* $variant:ident($params:ident, $law:ident) = $kind:ident, code $code:literal, follows $follows:ident; )+) => {
        const _: () = { $( assert!(!<$krate::$params<f32> as crate::LawSpec<f32>>::TRACED || <$krate::$params<f32> as Described>::FIELDS.len() < LAW); )+ };
    };
}
crate::for_each_law!(law_keys_fit);
/// Words of the law: its kind, then at most 16 keys (one word per declared key; pure
/// pursuit has 16).
const LAW: usize = 17;
/// Where each part of the config starts (word index).
const DRIVE_AT: usize = LAW;
const ROBOT_AT: usize = DRIVE_AT + 1 + TORQUE + DC_MOTOR;
const MODEL_AT: usize = ROBOT_AT + ROBOT;
const WHEELS_AT: usize = MODEL_AT + ROBOT;
const TIMING_AT: usize = WHEELS_AT + WHEELS;
const START_AT: usize = TIMING_AT + 3;
const WORLD_AT: usize = START_AT + 3;
const REFERENCE_AT: usize = WORLD_AT + WORLD;
/// Words of the reference: its kind, then its arguments (at most a waypoints
/// reference's: point count, speed, accel_max, then x and y of each point).
const REFERENCE: usize = 1 + ReferenceConfig::<f32>::ARG_WORDS;

/// What builds the reference ([`ReferenceConfig`]), as the config's words: its kind
/// code, then its arguments, every value rounded to f32.
fn put_reference<T: Real>(r: &ReferenceConfig<T>, w: &mut [u32]) {
    let (kind, args) = w.split_at_mut(1);
    kind[0] = r.code();
    r.encode_args(args, &mut f);
}

/// The reference of the config's words ([`put_reference`]).
fn read_reference(w: &[u32]) -> Result<ReferenceConfig<f32>, FormatError> {
    let (kind, args) = w.split_at(1);
    ReferenceConfig::decode(kind[0], &args[..ReferenceConfig::<f32>::ARG_WORDS], &mut r).map_err(FormatError)
}

/// The loop as the scenario gives it (f64) or as it ran ([`Config`], f32).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConfigOf<T> {
    /// The outer law and its keys.
    pub law: LawParams<T>,
    /// The drive.
    pub drive: DriveParams<T>,
    /// The robot.
    pub robot: RobotParams<T>,
    /// The controller's idea of the robot (`[controller.model]`).
    pub model: RobotParams<T>,
    /// The ground.
    pub world: WorldParams<T>,
    /// The wheel stage.
    pub wheels: WheelStageParams<T>,
    /// Control period, s.
    pub control_dt: T,
    /// Plant step, s.
    pub dt: T,
    /// Plant steps per control tick.
    pub steps_per_tick: u32,
    /// Start pose (m, m, rad).
    pub start: Pose2<T>,
    /// What the controller follows: a goal at rest or a moving reference.
    pub reference: ReferenceConfig<T>,
}

impl<T: Real> ConfigOf<T> {
    /// The config words, every value rounded to f32.
    pub fn encode(&self) -> [u32; CONFIG_WORDS] {
        let mut w = [0u32; CONFIG_WORDS];
        // The kind word, then one word per declared key ([`real_slots`]).
        let (kind, keys) = w[0..LAW].split_at_mut(1);
        kind[0] = self.law.to_words(keys, f);
        let d = &mut w[DRIVE_AT..ROBOT_AT];
        match self.drive {
            DriveParams::Torque(p) => put_torque(&p, &mut d[1..]),
            DriveParams::DcMotor(p) => {
                d[0] = 1;
                put_dc_motor(&p, &mut d[1 + TORQUE..]);
            }
        }
        put_robot(&self.robot, &mut w[ROBOT_AT..]);
        put_robot(&self.model, &mut w[MODEL_AT..]);
        put_wheels(&self.wheels, &mut w[WHEELS_AT..]);
        w[TIMING_AT] = f(self.control_dt);
        w[TIMING_AT + 1] = f(self.dt);
        w[TIMING_AT + 2] = self.steps_per_tick;
        for (d, v) in w[START_AT..WORLD_AT].iter_mut().zip([self.start.x, self.start.y, self.start.theta]) {
            *d = f(v);
        }
        put_world(&self.world, &mut w[WORLD_AT..]);
        put_reference(&self.reference, &mut w[REFERENCE_AT..]);
        w
    }
}

impl Config {
    /// Reads the config words.
    pub fn decode(w: &[u32; CONFIG_WORDS]) -> Result<Self, FormatError> {
        let keys = &w[1..LAW];
        let law = LawParams::from_words(w[0], keys, r).map_err(|what| {
            FormatError(if what == "kind" { "unknown law kind" } else { "a law's flag or mode word is no value of it" })
        })?;
        let d = &w[DRIVE_AT..ROBOT_AT];
        let drive = match d[0] {
            0 => DriveParams::Torque(read_torque(&d[1..])),
            1 => DriveParams::DcMotor(read_dc_motor(&d[1 + TORQUE..])),
            _ => return Err(FormatError("unknown drive kind")),
        };
        if w[TIMING_AT + 2] == 0 {
            return Err(FormatError("zero plant steps per tick"));
        }
        let pose = |at: usize| Pose2::new(r(w[at]), r(w[at + 1]), r(w[at + 2]));
        Ok(Config {
            law,
            drive,
            robot: read_robot(&w[ROBOT_AT..]),
            model: read_robot(&w[MODEL_AT..]),
            world: read_world(&w[WORLD_AT..]),
            wheels: read_wheels(&w[WHEELS_AT..]),
            control_dt: r(w[TIMING_AT]),
            dt: r(w[TIMING_AT + 1]),
            steps_per_tick: w[TIMING_AT + 2],
            start: pose(START_AT),
            reference: read_reference(&w[REFERENCE_AT..])?,
        })
    }
}

/// The header words for a trace of `ticks` records.
pub fn header(ticks: u32) -> [u32; HEADER_WORDS] {
    let m = |i: usize| u32::from_le_bytes([MAGIC[i], MAGIC[i + 1], MAGIC[i + 2], MAGIC[i + 3]]);
    [m(0), m(4), VERSION, CONFIG_WORDS as u32, RECORD_WORDS as u32, ticks]
}

/// Checks the header words and returns the number of ticks.
pub fn read_header(w: &[u32; HEADER_WORDS]) -> Result<u32, FormatError> {
    let expect = header(w[5]);
    if w[0..2] != expect[0..2] {
        return Err(FormatError("not a wmr trace (bad magic)"));
    }
    if w[2] != VERSION {
        return Err(FormatError("unsupported trace version"));
    }
    if w[3] as usize != CONFIG_WORDS || w[4] as usize != RECORD_WORDS {
        return Err(FormatError("unexpected config or record size"));
    }
    Ok(w[5])
}

/// A reference state as a [`Record`] holds it: pose x, y (m), theta (rad), twist v
/// (m/s), omega (rad/s), acceleration v' (m/s^2), omega' (rad/s^2).
pub fn reference_values<T: Copy>(r: &ReferenceState<T>) -> [T; 7] {
    [r.pose.x, r.pose.y, r.pose.theta, r.twist.v, r.twist.omega, r.accel.v, r.accel.omega]
}

/// One control tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Record {
    /// Time of the tick, s.
    pub t: f32,
    /// The plant's true state at the tick: x, y (m), theta (rad), v (m/s), omega (rad/s),
    /// phi_r, phi_l (rad).
    pub state: [f32; 7],
    /// The measurement the controller got: t (s), x, y (m), theta (rad), wheel angles
    /// right, left (rad), wheel speeds right, left (rad/s).
    pub measurement: [f32; 8],
    /// The reference state at the tick ([`reference_values`]).
    pub reference: [f32; 7],
    /// The drive command, right and left (N m or V).
    pub command: [f32; 2],
    /// The law's errors: e_s (m), e_theta (rad), dl (m).
    pub errors: [f32; 3],
}

impl Record {
    /// The record's words.
    pub fn encode(&self) -> [u32; RECORD_WORDS] {
        let mut w = [0u32; RECORD_WORDS];
        let values = core::iter::once(self.t)
            .chain(self.state)
            .chain(self.measurement)
            .chain(self.reference)
            .chain(self.command)
            .chain(self.errors);
        for (d, v) in w.iter_mut().zip(values) {
            *d = v.to_bits();
        }
        w
    }

    /// Reads a record's words.
    pub fn decode(w: &[u32; RECORD_WORDS]) -> Self {
        let v = |i: usize| f32::from_bits(w[i]);
        Record {
            t: v(0),
            state: core::array::from_fn(|i| v(1 + i)),
            measurement: core::array::from_fn(|i| v(8 + i)),
            reference: core::array::from_fn(|i| v(16 + i)),
            command: core::array::from_fn(|i| v(23 + i)),
            errors: core::array::from_fn(|i| v(25 + i)),
        }
    }

    /// Column names of the CSV form, in word order.
    pub const COLUMNS: [&'static str; RECORD_WORDS] = [
        "t",
        "x",
        "y",
        "theta",
        "v",
        "omega",
        "phi_r",
        "phi_l",
        "m_t",
        "m_x",
        "m_y",
        "m_theta",
        "m_phi_r",
        "m_phi_l",
        "m_omega_r",
        "m_omega_l",
        "x_ref",
        "y_ref",
        "theta_ref",
        "v_ref",
        "omega_ref",
        "dv_ref",
        "domega_ref",
        "command_r",
        "command_l",
        "e_s",
        "e_theta",
        "dl",
    ];

    /// The values in word order.
    pub fn values(&self) -> [f32; RECORD_WORDS] {
        self.encode().map(f32::from_bits)
    }
}

/// Words of `bytes` (little-endian); `bytes.len()` must be a multiple of 4.
pub fn words_le<const N: usize>(bytes: &[u8]) -> Option<[u32; N]> {
    if bytes.len() != 4 * N {
        return None;
    }
    Some(core::array::from_fn(|i| {
        u32::from_le_bytes([bytes[4 * i], bytes[4 * i + 1], bytes[4 * i + 2], bytes[4 * i + 3]])
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::Reference as _;
    use crate::reference::{AnyReference, Circle, FigureEight, FixedGoal, Line, Waypoints};
    use crate::{BacksteppingParams, KanayamaParams, PurePursuitParams};

    #[test]
    fn config_round_trips_for_every_law_and_drive() {
        // A law the trace does not carry (mppi: more keys than the trace's law words) is
        // refused by `wmr-cli trace` before any encoding.
        for law in LawParams::<f64>::defaults().into_iter().filter(|l| l.traced()) {
            for drive in DriveParams::<f64>::defaults() {
                let c = ConfigOf {
                    law,
                    drive,
                    robot: RobotParams::paper(),
                    model: RobotParams { mass: 6.0, ..RobotParams::paper() },
                    world: WorldParams { slope_deg: 2.0, slope_direction_deg: -45.0 },
                    wheels: WheelStageParams::for_drive(&drive, &RobotParams::paper()),
                    control_dt: 2e-3,
                    dt: 1e-3,
                    steps_per_tick: 2,
                    start: Pose2::new(0.1, -0.2, 0.3),
                    reference: ReferenceConfig::Goal(Pose2::new(1.0, 1.0, 120f64.to_radians())),
                };
                let d = Config::decode(&c.encode()).unwrap();
                assert_eq!(d.law.kind(), law.kind());
                assert_eq!(d.drive.kind(), drive.kind());
                assert_eq!(d.reference, ReferenceConfig::Goal(Pose2::new(1.0, 1.0, 120f64.to_radians() as f32)));
                // Infinite for the torque drive, the motor's no-load speed for a DC motor.
                assert_eq!(d.wheels.wheel_speed_max, c.wheels.wheel_speed_max as f32);
                assert_eq!(d.wheels.wheel_speed_max.is_finite(), matches!(drive, DriveParams::DcMotor(_)));
                assert_eq!(d.model.mass, 6.0);
                assert_eq!(d.world.slope_direction_deg, -45.0);
                // f32 -> words -> f32 is exact.
                let again = ConfigOf {
                    law: d.law,
                    drive: d.drive,
                    robot: d.robot,
                    model: d.model,
                    world: d.world,
                    wheels: d.wheels,
                    control_dt: d.control_dt,
                    dt: d.dt,
                    steps_per_tick: d.steps_per_tick,
                    start: d.start,
                    reference: d.reference,
                };
                assert_eq!(Config::decode(&again.encode()).unwrap(), d);
            }
        }
    }

    /// Every declared field of the robots, the wheel stage, the ground and both drives
    /// carries its own value through the words: a field dropped, swapped or laid over
    /// another breaks the equality. The old `Config` (a hand copy) was itself just such
    /// a place to forget one.
    #[test]
    fn every_declared_field_survives_the_words() {
        let mut n = 0.0_f32;
        let mut next = |_: f32| {
            n += 1.0;
            n
        };
        let dc = DcMotorParams::<f32>::default().map(&mut next);
        let torque = TorqueDriveParams::<f32>::default().map(&mut next);
        for drive in [DriveParams::DcMotor(dc), DriveParams::Torque(torque)] {
            let c: Config = ConfigOf {
                law: LawParams::default(),
                drive,
                robot: RobotParams::paper().map(&mut next),
                model: RobotParams::paper().map(&mut next),
                world: WorldParams::default().map(&mut next),
                wheels: WheelStageParams::default().map(&mut next),
                control_dt: next(0.0),
                dt: next(0.0),
                steps_per_tick: 3,
                start: Pose2::new(next(0.0), next(0.0), next(0.0)),
                reference: ReferenceConfig::Goal(Pose2::new(next(0.0), next(0.0), next(0.0))),
            };
            assert_eq!(Config::decode(&c.encode()).unwrap(), c);
        }
    }

    /// Every kind of reference and every tracking law survives the words with its own
    /// values, and the reference rebuilt from them is the one that was written: the same
    /// state at every time (a waypoints reference's spline and profile rebuilt from its
    /// points).
    #[test]
    fn every_reference_and_tracking_law_survives_the_words() {
        let mut n = 0.0_f32;
        let mut next = |_: f32| {
            n += 0.25;
            n
        };
        let laws = [
            LawParams::Kanayama(KanayamaParams::default().map(&mut next)),
            LawParams::Backstepping(BacksteppingParams::default().map(&mut next)),
            LawParams::PurePursuit(PurePursuitParams::default().map(&mut next)),
        ];
        let points = [[0.0, 0.0], [1.0, 0.5], [2.0, -0.25], [3.5, 1.0]];
        let references: [AnyReference<f32>; 5] = [
            AnyReference::Goal(FixedGoal::new(Pose2::new(1.0, -2.0, 0.5)).unwrap()),
            AnyReference::Circle(Circle::new(0.5, -0.5, 1.5, -0.3, -1.25).unwrap()),
            AnyReference::FigureEight(FigureEight::new(0.25, 0.5, 2.0, 1.0, 30.0).unwrap()),
            AnyReference::Line(Line::new(Pose2::new(-1.0, 2.0, 0.75), 0.4).unwrap()),
            AnyReference::Waypoints(Waypoints::new(&points, 0.3, 0.5).unwrap()),
        ];
        let mut last = None;
        for (law, reference) in laws.into_iter().zip(references.iter().cycle()).chain(
            // Every reference with a stabilization law too.
            references.iter().map(|r| (LawParams::default(), r)),
        ) {
            let c: Config = ConfigOf {
                law,
                drive: DriveParams::default(),
                robot: RobotParams::paper(),
                model: RobotParams::paper(),
                world: WorldParams::default(),
                wheels: WheelStageParams::default(),
                control_dt: 1e-3,
                dt: 1e-3,
                steps_per_tick: 1,
                start: Pose2::new(0.0, 0.0, 0.0),
                reference: ReferenceConfig::of(reference).unwrap(),
            };
            let d = Config::decode(&c.encode()).unwrap();
            assert_eq!(d, c, "{} on {}", law.kind(), reference.kind());
            last = Some(c);
            let rebuilt = d.reference.build().unwrap();
            assert_eq!(rebuilt.kind(), reference.kind());
            for k in 0..200 {
                let t = k as f32 * 0.137;
                assert_eq!(rebuilt.state_at(t), reference.state_at(t), "{} at t = {t}", reference.kind());
            }
        }
        // A waypoints reference with a point count outside 2..=64 is refused, not read.
        let mut w = last.unwrap().encode();
        assert_eq!(w[REFERENCE_AT], 4, "the last config follows the waypoints");
        w[REFERENCE_AT + 1] = 65;
        assert!(Config::decode(&w).unwrap_err().0.contains("point count"));
    }

    #[test]
    fn record_round_trips_and_header_checks() {
        let rec = Record {
            t: 0.5,
            state: [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0],
            measurement: [0.5, 1.0, 2.0, 3.0, 6.0, 7.0, -1.0, -2.0],
            reference: [1.0, 1.0, 2.0, 0.3, 0.1, 0.0, -0.5],
            command: [0.25, -0.25],
            errors: [0.1, 0.2, f32::NAN],
        };
        let back = Record::decode(&rec.encode());
        assert_eq!(back.encode(), rec.encode());
        assert_eq!(read_header(&header(7)), Ok(7));
        let mut bad = header(7);
        bad[2] = 99;
        assert!(read_header(&bad).is_err());
    }
}
