//! The topics of a run: their names, frames, encoding and schemas, in one list that the
//! MCAP file, the live server and `wmr-cli help keys` all read.
//!
//! Topics, per run `N` (0-based index of the `[[run]]`). Log time = simulation time in ns
//! from the Unix epoch (t = 0 is 1970-01-01T00:00:00Z), exactly `k * dt` for the `k`-th
//! plant step, so every sample lies on the log grid.
//!
//! The topics are [`Kind::ALL`], each `/runN/<`[`Kind::name`]`>` with the schema
//! [`Kind::schema`] and the messages [`Kind::messages`] says: that list is also what
//! `wmr-cli help keys` prints (a test reads the topics back from an MCAP file).

use foxglove::messages::{FrameTransform, PoseInFrame, PosesInFrame, SceneUpdate};
use foxglove::{Encode, Schema};
use wmr_scenario::{Columns, Scenario};

use super::sample::sample_schema;

/// The frame every run is drawn in.
pub const WORLD_FRAME: &str = "world";

/// One kind of topic of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    /// `foxglove.FrameTransform`, every sample.
    Tf,
    /// `wmr.Sample`, every sample.
    Sample,
    /// `foxglove.SceneUpdate`: body, goal, oldest piece of the path.
    Scene,
    /// `foxglove.SceneUpdate`: middle piece of the path.
    Path,
    /// `foxglove.SceneUpdate`: newest piece of the path, up to C.
    PathTip,
    /// `foxglove.PoseInFrame`: the measured pose (runs with a `[sensor]`; the fused pose
    /// on odometry).
    PoseMeas,
    /// `foxglove.PoseInFrame`: the dead-reckoned pose (runs on odometry).
    PoseOdom,
    /// `foxglove.FrameTransform`, every sample: the reference's frame (tracking runs).
    TfRef,
    /// `foxglove.SceneUpdate`, once: the reference path and the reference robot's ghost
    /// (tracking runs).
    Reference,
    /// `foxglove.SceneUpdate`: the world's obstacles at t = 0, and the obstacle the run
    /// collided with, red, at the collision (worlds with `[[world.obstacle]]`).
    Obstacles,
    /// `foxglove.PosesInFrame`, every planning cycle: MPPI's optimal trajectory (MCAP of
    /// an MPPI law).
    MppiOptimal,
    /// `foxglove.SceneUpdate`, every [`MPPI_ROLLOUTS_EVERY`] cycles: a sample of MPPI's
    /// rollouts as lines (MCAP of an MPPI law).
    MppiRollouts,
}

/// Planning cycles between two messages of [`Kind::MppiRollouts`].
pub const MPPI_ROLLOUTS_EVERY: u64 = 4;

/// Rollouts drawn per message of [`Kind::MppiRollouts`]: samples 0 .. this of the cycle.
pub const MPPI_ROLLOUTS_DRAWN: u32 = 16;

/// What a file shows beside the samples' columns, from the scenario: its obstacles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Views {
    /// The world has obstacles (`[[world.obstacle]]`): [`Kind::Obstacles`].
    pub obstacles: bool,
    /// The law is MPPI: [`Kind::MppiOptimal`], [`Kind::MppiRollouts`] (written to an
    /// MCAP file, not served live).
    pub mppi: bool,
}

impl Views {
    /// The views of `scenario`'s runs.
    pub fn of(scenario: &Scenario) -> Self {
        Self {
            obstacles: !scenario.setup().obstacles.is_empty(),
            mppi: matches!(scenario.controller().law, wmr_core::LawParams::Mppi(_)),
        }
    }
}

impl Kind {
    /// Every kind, in the order channels are created.
    pub const ALL: [Kind; 12] = [
        Kind::Tf,
        Kind::Sample,
        Kind::Scene,
        Kind::Path,
        Kind::PathTip,
        Kind::PoseMeas,
        Kind::PoseOdom,
        Kind::TfRef,
        Kind::Reference,
        Kind::Obstacles,
        Kind::MppiOptimal,
        Kind::MppiRollouts,
    ];

    /// The last part of the topic name.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Tf => "tf",
            Kind::Sample => "sample",
            Kind::Scene => "scene",
            Kind::Path => "path",
            Kind::PathTip => "path_tip",
            Kind::PoseMeas => "pose_meas",
            Kind::PoseOdom => "pose_odom",
            Kind::TfRef => "tf_ref",
            Kind::Reference => "reference",
            Kind::Obstacles => "obstacles",
            Kind::MppiOptimal => "mppi/optimal",
            Kind::MppiRollouts => "mppi/rollouts",
        }
    }

    /// When this topic gets a message, and what it holds.
    pub fn messages(self) -> &'static str {
        match self {
            Kind::Tf => "every sample: world -> runN/base_link (pose of C)",
            Kind::Sample => "every sample: every CSV column after run, same f64",
            Kind::Scene => {
                "at t = 0: the robot's body, the goal arrow; again whenever the oldest piece of the path grows"
            }
            Kind::Path => "the middle piece of the path, whenever it grows",
            Kind::PathTip => "the newest piece of the path, up to C, whenever C has moved on by a few mm",
            Kind::PoseMeas => {
                "with a [sensor]: the pose the controller used (on odometry the fused pose), whenever it changes"
            }
            Kind::PoseOdom => "on odometry: the pose dead-reckoned from the encoders, whenever it changes",
            Kind::TfRef => "with a [reference], every sample: world -> runN/reference (pose of C_ref)",
            Kind::Reference => {
                "with a [reference], at t = 0: the reference path (dashed), the reference robot's ghost on runN/reference"
            }
            Kind::Obstacles => {
                "with [[world.obstacle]], at t = 0: every obstacle (obstacleK, K in the summary's collided_with order: \
                 circles as grey discs, polygons as outlines); at a collision: that obstacle red and the footprint"
            }
            Kind::MppiOptimal => {
                "kind = \"mppi\", every planning cycle (model_dt): the measured pose, then the poses of the sequence \
                 just chosen (u_1, u_2, ...) rolled out on the law's model, one per model_dt"
            }
            Kind::MppiRollouts => {
                "kind = \"mppi\", every 4th planning cycle: samples 0-15 of the cycle rolled out as the plan rolls \
                 them (lines, entity rollouts)"
            }
        }
    }

    /// Whether runs with `columns` and `views` have this topic: [`Kind::PoseMeas`] with a
    /// `[sensor]`, [`Kind::PoseOdom`] on odometry, [`Kind::TfRef`] and [`Kind::Reference`]
    /// with a `[reference]`, [`Kind::Obstacles`] with obstacles, the others always.
    pub fn is_present(self, columns: &Columns, views: Views) -> bool {
        match self {
            Kind::Obstacles => views.obstacles,
            Kind::MppiOptimal | Kind::MppiRollouts => views.mppi,
            Kind::PoseMeas => columns.measured,
            Kind::PoseOdom => columns.odometry,
            Kind::TfRef | Kind::Reference => columns.reference.is_some(),
            Kind::Tf | Kind::Sample | Kind::Scene | Kind::Path | Kind::PathTip => true,
        }
    }

    /// The kinds a file of runs with `columns` and `views` has, in [`Kind::ALL`] order.
    pub fn present(columns: &Columns, views: Views) -> impl Iterator<Item = Kind> + '_ {
        Kind::ALL.into_iter().filter(move |k| k.is_present(columns, views))
    }

    /// The schema of this kind's messages.
    pub fn schema(self, schemas: &Schemas) -> &Schema {
        match self {
            Kind::Tf | Kind::TfRef => &schemas.frame_transform,
            Kind::Sample => &schemas.sample,
            Kind::Scene | Kind::Path | Kind::PathTip | Kind::Reference | Kind::Obstacles | Kind::MppiRollouts => {
                &schemas.scene_update
            }
            Kind::PoseMeas | Kind::PoseOdom => &schemas.pose_in_frame,
            Kind::MppiOptimal => &schemas.poses_in_frame,
        }
    }
}

/// The topic of `kind` for run `run`: `/run3/tf`.
pub fn topic(run: usize, kind: Kind) -> String {
    format!("/run{run}/{}", kind.name())
}

/// The child frame of run `run`'s transforms: `run3/base_link` (C, x forward).
pub fn base_link(run: usize) -> String {
    format!("run{run}/base_link")
}

/// The frame of run `run`'s reference: `run3/reference` (C_ref, x along the reference's heading).
pub fn reference_frame(run: usize) -> String {
    format!("run{run}/reference")
}

/// Message encoding of every topic.
pub const MESSAGE_ENCODING: &str = "protobuf";

/// The schemas of a file (protobuf `FileDescriptorSet`s).
pub struct Schemas {
    /// `foxglove.FrameTransform`.
    pub frame_transform: Schema,
    /// `foxglove.SceneUpdate`.
    pub scene_update: Schema,
    /// `foxglove.PoseInFrame`.
    pub pose_in_frame: Schema,
    /// `foxglove.PosesInFrame`.
    pub poses_in_frame: Schema,
    /// `wmr.Sample`.
    pub sample: Schema,
}

impl Schemas {
    /// The schemas; `wmr.Sample` has one field per column of `columns`.
    pub fn new(columns: &Columns) -> Self {
        let fox = |s: Option<Schema>, name: &str| s.unwrap_or_else(|| Schema::new(name, "protobuf", Vec::new()));
        Self {
            frame_transform: fox(FrameTransform::get_schema(), "foxglove.FrameTransform"),
            scene_update: fox(SceneUpdate::get_schema(), "foxglove.SceneUpdate"),
            pose_in_frame: fox(PoseInFrame::get_schema(), "foxglove.PoseInFrame"),
            poses_in_frame: fox(PosesInFrame::get_schema(), "foxglove.PosesInFrame"),
            sample: sample_schema(columns),
        }
    }
}
