//! The Foxglove topics of a run and their encoding, shared by the MCAP file
//! ([`crate::mcap_sink`]) and the live WebSocket server ([`crate::live`]): the same bytes
//! go to both.
//!
//! Topics, per run `N` (0-based index of the `[[run]]`). Log time = simulation time in ns
//! from the Unix epoch (t = 0 is 1970-01-01T00:00:00Z), exactly `k * dt` for the `k`-th
//! plant step, so every sample lies on the log grid.
//!
//! The topics are [`Kind::ALL`], each `/runN/<`[`Kind::name`]`>` with the schema
//! [`Kind::schema`] and the messages [`Kind::messages`] says: that list is also what
//! `wmr-cli --help` prints (a test reads the topics back from an MCAP file).
//!
//! **Why the path is three topics.** On a seek, Foxglove clears the 3D scene and reads
//! back only the latest message of each topic. So the latest messages of `scene`, `path`
//! and `path_tip` together carry the whole path up to that time: `scene` from the start to
//! checkpoint A, `path` from A to checkpoint B, `path_tip` from B to C. The path is kept
//! as the vertices of a polyline within [`PATH_TOLERANCE_M`] of every sample, and C is
//! never more than [`PATH_PUBLISH_STEP_M`] from the drawn end, so what Foxglove shows after
//! a seek lies within 1 cm of the path travelled. `path_tip` holds at most
//! [`TIP_VERTICES`] vertices and `path` at most [`RECENT_VERTICES`], so the bytes written
//! grow linearly with the path (the `scene` message, which repeats the oldest piece, is
//! written once every [`RECENT_VERTICES`] vertices).

use foxglove::messages::{
    ArrowPrimitive, Color, CubePrimitive, FrameTransform, LinePrimitive, Point3, Pose, PoseInFrame, Quaternion,
    SceneEntity, SceneEntityDeletion, SceneUpdate, Timestamp, Vector3, line_primitive, scene_entity_deletion,
};
use foxglove::{Encode, Schema};
use prost::Message as _;
use prost_types::field_descriptor_proto::{Label, Type};
use prost_types::{DescriptorProto, FieldDescriptorProto, FileDescriptorProto, FileDescriptorSet};
use wmr_core::{Pose2, RobotParams, Sample};
use wmr_scenario::{MEASURED_COLUMNS, RunSpec, SAMPLE_COLUMNS, measured_values, sample_values};

/// Largest distance (m) of a logged position from the drawn path polyline, before C moves on.
pub const PATH_TOLERANCE_M: f64 = 0.003;
/// C moves at most this far (m) from the end of the drawn path before `path_tip` is sent again.
pub const PATH_PUBLISH_STEP_M: f64 = 0.007;
/// Vertices `path_tip` holds before they move to `path`.
pub const TIP_VERTICES: usize = 8;
/// Vertices `path` holds before they move to `scene`.
pub const RECENT_VERTICES: usize = 64 * TIP_VERTICES;

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
    /// `foxglove.PoseInFrame`: the measured pose (runs with a `[sensor]`).
    PoseMeas,
}

impl Kind {
    /// Every kind, in the order channels are created.
    pub const ALL: [Kind; 6] = [Kind::Tf, Kind::Sample, Kind::Scene, Kind::Path, Kind::PathTip, Kind::PoseMeas];

    /// The last part of the topic name.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Tf => "tf",
            Kind::Sample => "sample",
            Kind::Scene => "scene",
            Kind::Path => "path",
            Kind::PathTip => "path_tip",
            Kind::PoseMeas => "pose_meas",
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
            Kind::PoseMeas => "with a [sensor]: the pose the controller used, whenever it changes",
        }
    }

    /// The kinds a file has: [`Kind::PoseMeas`] only with a `[sensor]`.
    pub fn present(measured: bool) -> impl Iterator<Item = Kind> {
        Kind::ALL.into_iter().filter(move |k| measured || *k != Kind::PoseMeas)
    }

    /// The schema of this kind's messages.
    pub fn schema(self, schemas: &Schemas) -> &Schema {
        match self {
            Kind::Tf => &schemas.frame_transform,
            Kind::Sample => &schemas.sample,
            Kind::Scene | Kind::Path | Kind::PathTip => &schemas.scene_update,
            Kind::PoseMeas => &schemas.pose_in_frame,
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
    /// `wmr.Sample`.
    pub sample: Schema,
}

impl Schemas {
    /// The schemas; `measured`: `wmr.Sample` has the measured pose's fields too.
    pub fn new(measured: bool) -> Self {
        let fox = |s: Option<Schema>, name: &str| s.unwrap_or_else(|| Schema::new(name, "protobuf", Vec::new()));
        Self {
            frame_transform: fox(FrameTransform::get_schema(), "foxglove.FrameTransform"),
            scene_update: fox(SceneUpdate::get_schema(), "foxglove.SceneUpdate"),
            pose_in_frame: fox(PoseInFrame::get_schema(), "foxglove.PoseInFrame"),
            sample: sample_schema(measured),
        }
    }
}

/// Name of the sample schema.
pub const SAMPLE_SCHEMA: &str = "wmr.Sample";

/// The fields of `wmr.Sample`, in field-number order (1, 2, ...): the CSV columns after
/// `run`, then with a `[sensor]` the measured pose. Every field is a `double`.
pub fn sample_fields(measured: bool) -> Vec<&'static str> {
    let extra: &[&str] = if measured { &MEASURED_COLUMNS } else { &[] };
    SAMPLE_COLUMNS.iter().chain(extra).copied().collect()
}

/// `wmr.Sample` as a protobuf `FileDescriptorSet`: one `double` per field of
/// [`sample_fields`], numbered from 1. Units: s, m, rad, m/s, rad/s, N m (the CSV's).
fn sample_schema(measured: bool) -> Schema {
    let field = sample_fields(measured)
        .into_iter()
        .enumerate()
        .map(|(i, name)| FieldDescriptorProto {
            name: Some(name.to_owned()),
            number: Some(i as i32 + 1),
            label: Some(Label::Optional as i32),
            r#type: Some(Type::Double as i32),
            json_name: Some(name.to_owned()),
            ..Default::default()
        })
        .collect();
    let file = FileDescriptorProto {
        name: Some("wmr/Sample.proto".into()),
        package: Some("wmr".into()),
        message_type: vec![DescriptorProto { name: Some("Sample".into()), field, ..Default::default() }],
        syntax: Some("proto3".into()),
        ..Default::default()
    };
    Schema::new(SAMPLE_SCHEMA, "protobuf", FileDescriptorSet { file: vec![file] }.encode_to_vec())
}

/// Appends a `wmr.Sample` message: every field written (field number, wire type 1, the
/// f64's 8 little-endian bytes), so every message of a file has the same length.
fn encode_sample(s: &Sample<f64>, measured: bool, buf: &mut Vec<u8>) {
    let mut put = |number: u32, v: f64| {
        let mut key = (number << 3) | 1;
        while key >= 0x80 {
            buf.push((key as u8) | 0x80);
            key >>= 7;
        }
        buf.push(key as u8);
        buf.extend_from_slice(&v.to_le_bytes());
    };
    let mut n = 0;
    for v in sample_values(s) {
        n += 1;
        put(n, v);
    }
    if measured {
        for v in measured_values(s) {
            n += 1;
            put(n, v);
        }
    }
}

/// Log times: simulation time (s) to ns, exact on the plant-step grid.
#[derive(Clone, Copy, Debug)]
pub struct LogClock {
    /// Plant step, s.
    dt: f64,
    /// The plant step in whole ns, when it is one.
    dt_ns: Option<u64>,
}

impl LogClock {
    /// The clock of a scenario with plant step `dt` (s).
    pub fn new(dt: f64) -> Self {
        let ns = dt * 1e9;
        let whole = ns.round();
        let dt_ns = (whole >= 1.0 && (ns - whole).abs() <= 1e-6 * whole).then_some(whole as u64);
        Self { dt, dt_ns }
    }

    /// The log time of simulation time `t` (s): `k * dt_ns` for the `k`-th step when the
    /// step is a whole number of ns, else `t * 1e9` rounded.
    pub fn nanos(&self, t: f64) -> u64 {
        match self.dt_ns {
            Some(step) => ((t / self.dt).round().max(0.0) as u64).saturating_mul(step),
            None => (t * 1e9).round().max(0.0) as u64,
        }
    }
}

fn stamp(ns: u64) -> Timestamp {
    Timestamp::new((ns / 1_000_000_000) as u32, (ns % 1_000_000_000) as u32)
}

fn yaw(theta: f64) -> Quaternion {
    let h = 0.5 * theta;
    Quaternion { x: 0.0, y: 0.0, z: h.sin(), w: h.cos() }
}

fn pose(p: Pose2<f64>) -> Pose {
    Pose { position: Some(Vector3 { x: p.x, y: p.y, z: 0.0 }), orientation: Some(yaw(p.theta)) }
}

/// Run colours, `#rrggbb`: Tableau 10 for runs 0-9, then hues a golden angle apart.
/// The layout's plot series and the 3D panel's paths use the same colour per run.
pub fn run_rgb(run: usize) -> [u8; 3] {
    const TABLEAU: [[u8; 3]; 10] = [
        [0x4e, 0x79, 0xa7],
        [0xf2, 0x8e, 0x2b],
        [0xe1, 0x57, 0x59],
        [0x76, 0xb7, 0xb2],
        [0x59, 0xa1, 0x4f],
        [0xed, 0xc9, 0x48],
        [0xb0, 0x7a, 0xa1],
        [0xff, 0x9d, 0xa7],
        [0x9c, 0x75, 0x5f],
        [0xba, 0xb0, 0xac],
    ];
    if let Some(c) = TABLEAU.get(run) {
        return *c;
    }
    // HSL (hue, 0.65, 0.5) to RGB.
    let h = (run as f64 * 137.507_764_050_037_85).rem_euclid(360.0) / 60.0;
    let (s, l) = (0.65, 0.5);
    let c = (1.0 - (2.0 * l - 1.0_f64).abs()) * s;
    let x = c * (1.0 - (h.rem_euclid(2.0) - 1.0).abs());
    let (r, g, b) = match h as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = l - 0.5 * c;
    let byte = |v: f64| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8;
    [byte(r), byte(g), byte(b)]
}

/// The colour of run `run` as `#rrggbb`.
pub fn run_hex(run: usize) -> String {
    let [r, g, b] = run_rgb(run);
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// The colour of run `run` with opacity `a`.
pub fn run_color(run: usize, a: f64) -> Color {
    let [r, g, b] = run_rgb(run);
    Color { r: f64::from(r) / 255.0, g: f64::from(g) / 255.0, b: f64::from(b) / 255.0, a }
}

/// Line width of the drawn path, screen pixels.
const PATH_WIDTH_PX: f64 = 2.5;

#[derive(Clone, Copy, Debug, PartialEq)]
struct P2 {
    x: f64,
    y: f64,
}

impl P2 {
    fn dist(self, o: P2) -> f64 {
        (self.x - o.x).hypot(self.y - o.y)
    }
}

/// The path of C as a polyline in three pieces (see the module doc).
///
/// Vertices are logged positions. Between the last vertex (the anchor) and the newest
/// position (the end) every logged position lies within [`PATH_TOLERANCE_M`] of the
/// segment anchor-end: the end's direction from the anchor stays inside the cone of
/// directions that keeps every position since the anchor within the tolerance, and C
/// does not come back towards the anchor by more than the tolerance. When a new
/// position breaks this, the previous one becomes a vertex. O(1) per sample.
struct PathPieces {
    /// Oldest piece: the start, then vertices up to checkpoint A.
    old: Vec<P2>,
    /// Vertices after A up to checkpoint B.
    recent: Vec<P2>,
    /// Vertices after B.
    tip: Vec<P2>,
    anchor: P2,
    end: P2,
    /// Unit direction the cone's angles are measured from.
    reference: P2,
    /// The cone of directions (rad from `reference`), once a position is farther than the
    /// tolerance from the anchor.
    cone: Option<(f64, f64)>,
    /// Largest distance from the anchor of a position since the anchor, m.
    reach: f64,
    /// End of the path as last sent on `path_tip`.
    sent_end: Option<P2>,
    old_changed: bool,
    recent_changed: bool,
}

impl PathPieces {
    fn new(start: P2) -> Self {
        Self {
            old: vec![start],
            recent: Vec::with_capacity(RECENT_VERTICES),
            tip: Vec::with_capacity(TIP_VERTICES),
            anchor: start,
            end: start,
            reference: P2 { x: 1.0, y: 0.0 },
            cone: None,
            reach: 0.0,
            sent_end: None,
            old_changed: false,
            recent_changed: false,
        }
    }

    /// Angle of `p` seen from the anchor, rad from `reference`, and its distance, m.
    fn polar(&self, p: P2) -> (f64, f64) {
        let (dx, dy) = (p.x - self.anchor.x, p.y - self.anchor.y);
        let r = self.reference;
        ((r.x * dy - r.y * dx).atan2(r.x * dx + r.y * dy), dx.hypot(dy))
    }

    fn fits(&self, p: P2) -> bool {
        let (phi, d) = self.polar(p);
        if d + PATH_TOLERANCE_M < self.reach {
            return false;
        }
        match self.cone {
            None => true,
            Some((lo, hi)) => d <= PATH_TOLERANCE_M && self.reach <= PATH_TOLERANCE_M || (lo..=hi).contains(&phi),
        }
    }

    /// Takes `p` as the new end, narrowing the cone.
    fn extend(&mut self, p: P2) {
        let (_, d) = self.polar(p);
        if d > PATH_TOLERANCE_M {
            if self.cone.is_none() {
                self.reference = P2 { x: (p.x - self.anchor.x) / d, y: (p.y - self.anchor.y) / d };
            }
            let (phi, _) = self.polar(p);
            let w = (PATH_TOLERANCE_M / d).asin();
            let (lo, hi) = self.cone.unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
            self.cone = Some((lo.max(phi - w), hi.min(phi + w)));
        }
        self.reach = self.reach.max(d);
        self.end = p;
    }

    fn commit(&mut self, v: P2) {
        self.tip.push(v);
        self.anchor = v;
        self.cone = None;
        self.reach = 0.0;
        if self.tip.len() >= TIP_VERTICES {
            self.recent.append(&mut self.tip);
            self.recent_changed = true;
            if self.recent.len() >= RECENT_VERTICES {
                self.old.append(&mut self.recent);
                self.old_changed = true;
            }
        }
    }

    /// Adds the position `p` (m, world frame).
    fn push(&mut self, p: P2) {
        if !self.fits(p) {
            let v = self.end;
            self.commit(v);
        }
        self.extend(p);
    }

    /// `path_tip` must be sent: a piece changed, or C moved far enough.
    fn tip_due(&self) -> bool {
        self.old_changed
            || self.recent_changed
            || match self.sent_end {
                None => self.end.dist(self.old[0]) >= PATH_PUBLISH_STEP_M,
                Some(e) => self.end.dist(e) >= PATH_PUBLISH_STEP_M,
            }
    }

    fn last_old(&self) -> P2 {
        self.old[self.old.len() - 1]
    }

    fn last_recent(&self) -> P2 {
        self.recent.last().copied().unwrap_or_else(|| self.last_old())
    }
}

/// The entity id of a path piece on its topic.
pub const PATH_ENTITY: &str = "path";

/// Encodes one run's messages.
pub struct RunEncoder {
    clock: LogClock,
    measured: bool,
    tf: FrameTransform,
    meas: PoseInFrame,
    last_meas: Option<Pose2<f64>>,
    body: SceneEntity,
    goal: SceneEntity,
    line: LinePrimitive,
    path: Option<PathPieces>,
    points: Vec<Point3>,
    buf: Vec<u8>,
}

impl RunEncoder {
    /// The encoder of run `run` (`spec`) of robot `robot`; `measured`: the scenario has a
    /// `[sensor]`, so `pose_meas` and the measured fields are written.
    pub fn new(run: usize, spec: &RunSpec, robot: &RobotParams<f64>, measured: bool, clock: LogClock) -> Self {
        let r = robot;
        let colour = run_color(run, 1.0);
        // The body: a box of the track's width, locked to base_link (C at the axle).
        let body = CubePrimitive {
            pose: Some(Pose {
                position: Some(Vector3 { x: 0.5 * r.com_offset, y: 0.0, z: r.wheel_radius }),
                orientation: Some(yaw(0.0)),
            }),
            size: Some(Vector3 {
                x: (2.0 * r.com_offset.abs()).max(2.0 * r.wheel_radius) + 2.0 * r.wheel_radius,
                y: 2.0 * r.half_track,
                z: r.wheel_radius,
            }),
            color: Some(run_color(run, 0.6)),
        };
        let scale = r.half_track;
        let arrow = ArrowPrimitive {
            pose: Some(pose(spec.goal)),
            shaft_length: 1.5 * scale,
            shaft_diameter: 0.12 * scale,
            head_length: 0.5 * scale,
            head_diameter: 0.35 * scale,
            color: Some(colour),
        };
        Self {
            clock,
            measured,
            tf: FrameTransform {
                timestamp: None,
                parent_frame_id: WORLD_FRAME.into(),
                child_frame_id: base_link(run),
                translation: None,
                rotation: None,
            },
            meas: PoseInFrame { timestamp: None, frame_id: WORLD_FRAME.into(), pose: None },
            last_meas: None,
            body: SceneEntity {
                frame_id: base_link(run),
                id: "body".into(),
                frame_locked: true,
                cubes: vec![body],
                ..Default::default()
            },
            goal: SceneEntity {
                frame_id: WORLD_FRAME.into(),
                id: "goal".into(),
                arrows: vec![arrow],
                ..Default::default()
            },
            line: LinePrimitive {
                r#type: line_primitive::Type::LineStrip as i32,
                pose: Some(pose(Pose2::new(0.0, 0.0, 0.0))),
                thickness: PATH_WIDTH_PX,
                scale_invariant: true,
                points: Vec::new(),
                color: Some(colour),
                ..Default::default()
            },
            path: None,
            points: Vec::with_capacity(RECENT_VERTICES + 2),
            buf: Vec::with_capacity(1024),
        }
    }

    /// Encodes sample `s`, handing each message to `out(kind, log time ns, bytes)`.
    pub fn sample<E>(
        &mut self,
        s: &Sample<f64>,
        out: &mut impl FnMut(Kind, u64, &[u8]) -> Result<(), E>,
    ) -> Result<(), E> {
        let ns = self.clock.nanos(s.t);
        let ts = Some(stamp(ns));
        let p = s.state.pose();
        let here = P2 { x: p.x, y: p.y };
        let first = self.path.is_none();
        if first {
            self.path = Some(PathPieces::new(here));
            self.send_scene(ns, out)?;
        }

        self.tf.timestamp = ts;
        self.tf.translation = Some(Vector3 { x: p.x, y: p.y, z: 0.0 });
        self.tf.rotation = Some(yaw(p.theta));
        self.buf.clear();
        let _ = prost::Message::encode(&self.tf, &mut self.buf);
        out(Kind::Tf, ns, &self.buf)?;

        self.buf.clear();
        encode_sample(s, self.measured, &mut self.buf);
        out(Kind::Sample, ns, &self.buf)?;

        if self.measured && self.last_meas != Some(s.measured) {
            self.last_meas = Some(s.measured);
            self.meas.timestamp = ts;
            self.meas.pose = Some(pose(s.measured));
            self.buf.clear();
            let _ = prost::Message::encode(&self.meas, &mut self.buf);
            out(Kind::PoseMeas, ns, &self.buf)?;
        }

        if let Some(path) = self.path.as_mut()
            && !first
        {
            path.push(here);
            if path.tip_due() {
                self.send_path(ns, out)?;
            }
        }
        Ok(())
    }

    /// After the last sample: sends `path_tip` once more if C moved since it was sent.
    pub fn finish<E>(&mut self, last_t: f64, out: &mut impl FnMut(Kind, u64, &[u8]) -> Result<(), E>) -> Result<(), E> {
        match &self.path {
            Some(path) if path.sent_end != Some(path.end) && path.end != path.old[0] => {
                self.send_path(self.clock.nanos(last_t), out)
            }
            _ => Ok(()),
        }
    }

    /// Fills `self.points` with `pts`.
    fn set_points(&mut self, pts: impl IntoIterator<Item = P2>) {
        self.points.clear();
        self.points.extend(pts.into_iter().map(|p| Point3 { x: p.x, y: p.y, z: 0.0 }));
    }

    fn path_entity(&mut self, ns: u64) -> SceneEntity {
        let mut line = self.line.clone();
        line.points = std::mem::take(&mut self.points);
        SceneEntity {
            timestamp: Some(stamp(ns)),
            frame_id: WORLD_FRAME.into(),
            id: PATH_ENTITY.into(),
            lines: vec![line],
            ..Default::default()
        }
    }

    /// Sends one piece: the entity, or its deletion when it has no segment.
    fn send_piece<E>(
        &mut self,
        kind: Kind,
        ns: u64,
        out: &mut impl FnMut(Kind, u64, &[u8]) -> Result<(), E>,
    ) -> Result<(), E> {
        let update = if self.points.len() >= 2 {
            SceneUpdate { deletions: vec![], entities: vec![self.path_entity(ns)] }
        } else {
            SceneUpdate {
                deletions: vec![SceneEntityDeletion {
                    timestamp: Some(stamp(ns)),
                    r#type: scene_entity_deletion::Type::MatchingId as i32,
                    id: PATH_ENTITY.into(),
                }],
                entities: vec![],
            }
        };
        self.buf.clear();
        let _ = prost::Message::encode(&update, &mut self.buf);
        // Give the point buffer back for the next message.
        if let Some(mut e) = update.entities.into_iter().next()
            && let Some(line) = e.lines.pop()
        {
            self.points = line.points;
        }
        out(kind, ns, &self.buf)
    }

    /// `scene`: body, goal and the oldest piece of the path.
    fn send_scene<E>(&mut self, ns: u64, out: &mut impl FnMut(Kind, u64, &[u8]) -> Result<(), E>) -> Result<(), E> {
        let old = self.path.as_ref().map(|p| p.old.clone()).unwrap_or_default();
        self.set_points(old);
        let mut entities = Vec::with_capacity(3);
        let mut body = self.body.clone();
        body.timestamp = Some(stamp(ns));
        let mut goal = self.goal.clone();
        goal.timestamp = Some(stamp(ns));
        entities.push(body);
        entities.push(goal);
        if self.points.len() >= 2 {
            entities.push(self.path_entity(ns));
        }
        let update = SceneUpdate { deletions: vec![], entities };
        self.buf.clear();
        let _ = prost::Message::encode(&update, &mut self.buf);
        out(Kind::Scene, ns, &self.buf)
    }

    /// The pieces that changed, then `path_tip`.
    fn send_path<E>(&mut self, ns: u64, out: &mut impl FnMut(Kind, u64, &[u8]) -> Result<(), E>) -> Result<(), E> {
        let Some(path) = self.path.as_mut() else { return Ok(()) };
        let (old_changed, recent_changed) = (path.old_changed, path.recent_changed);
        path.old_changed = false;
        path.recent_changed = false;
        path.sent_end = Some(path.end);
        if old_changed {
            self.send_scene(ns, out)?;
        }
        let Some(path) = self.path.as_ref() else { return Ok(()) };
        if old_changed || recent_changed {
            let piece: Vec<P2> = std::iter::once(path.last_old()).chain(path.recent.iter().copied()).collect();
            self.set_points(piece);
            self.send_piece(Kind::Path, ns, out)?;
        }
        let Some(path) = self.path.as_ref() else { return Ok(()) };
        let piece: Vec<P2> = std::iter::once(path.last_recent())
            .chain(path.tip.iter().copied())
            .chain(std::iter::once(path.end))
            .collect();
        self.set_points(piece);
        self.send_piece(Kind::PathTip, ns, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance from `p` to segment a-b.
    fn seg_dist(p: P2, a: P2, b: P2) -> f64 {
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let l2 = dx * dx + dy * dy;
        let t = if l2 == 0.0 { 0.0 } else { (((p.x - a.x) * dx + (p.y - a.y) * dy) / l2).clamp(0.0, 1.0) };
        p.dist(P2 { x: a.x + t * dx, y: a.y + t * dy })
    }

    fn drawn(p: &PathPieces) -> Vec<P2> {
        let mut v = p.old.clone();
        v.extend(&p.recent);
        v.extend(&p.tip);
        v.push(p.end);
        v
    }

    fn max_gap(points: &[P2], line: &[P2]) -> f64 {
        points
            .iter()
            .map(|&q| line.windows(2).map(|w| seg_dist(q, w[0], w[1])).fold(f64::INFINITY, f64::min))
            .fold(0.0, f64::max)
    }

    #[test]
    fn a_straight_line_needs_no_vertex_and_a_circle_few() {
        let mut p = PathPieces::new(P2 { x: 0.0, y: 0.0 });
        for k in 1..=1000 {
            p.push(P2 { x: k as f64 * 1e-3, y: 0.0 });
        }
        assert_eq!(p.old.len() + p.recent.len() + p.tip.len(), 1);

        // Circle of radius 1 m: a chord 2 sqrt(2 r e) long stays within e of the arc.
        let mut p = PathPieces::new(P2 { x: 1.0, y: 0.0 });
        let mut all = vec![P2 { x: 1.0, y: 0.0 }];
        for k in 1..=6283 {
            let a = k as f64 * 1e-3;
            let q = P2 { x: a.cos(), y: a.sin() };
            all.push(q);
            p.push(q);
        }
        let vertices = p.old.len() + p.recent.len() + p.tip.len();
        let chord = 2.0 * (2.0 * PATH_TOLERANCE_M).sqrt();
        let least = (std::f64::consts::TAU / chord).floor() as usize;
        assert!((least..=2 * least).contains(&vertices), "{vertices} vertices, at least {least}");
        assert!(max_gap(&all, &drawn(&p)) <= PATH_TOLERANCE_M * 1.0001);
    }

    /// Bytes of the path topics (`scene`, `path`, `path_tip`) for `laps` laps of a circle
    /// of radius 1 m at 0.5 m/s, logged every 10 ms.
    fn path_bytes_for_laps(laps: usize) -> usize {
        let robot = RobotParams::<f64>::default();
        let spec = RunSpec::new(Pose2::new(1.0, 0.0, 0.0), Pose2::new(0.0, 0.0, 0.0));
        let mut enc = RunEncoder::new(0, &spec, &robot, false, LogClock::new(1e-3));
        let mut bytes = 0;
        let mut out = |kind: Kind, _ns: u64, data: &[u8]| -> Result<(), ()> {
            if matches!(kind, Kind::Scene | Kind::Path | Kind::PathTip) {
                bytes += data.len();
            }
            Ok(())
        };
        let per_lap = (std::f64::consts::TAU / 0.5 / 0.01).round() as usize;
        for k in 0..=laps * per_lap {
            let a = k as f64 * std::f64::consts::TAU / per_lap as f64;
            let mut s = Sample::<f64> { t: k as f64 * 0.01, ..Default::default() };
            s.state.x = a.cos();
            s.state.y = a.sin();
            let _ = enc.sample(&s, &mut out);
        }
        bytes
    }

    #[test]
    fn path_bytes_grow_linearly_with_the_path() {
        // 10 laps: about 400 vertices, 40 laps: 1,600 (the oldest piece is re-sent 3 times).
        let (short, long) = (path_bytes_for_laps(10), path_bytes_for_laps(40));
        let ratio = long as f64 / short as f64;
        assert!((3.9..4.4).contains(&ratio), "40 laps: {long} B, 10 laps: {short} B, ratio {ratio}");
    }

    #[test]
    fn back_and_forth_and_jitter_stay_within_tolerance() {
        let mut p = PathPieces::new(P2 { x: 0.0, y: 0.0 });
        let mut all = vec![P2 { x: 0.0, y: 0.0 }];
        // Forward 0.5 m, back 0.3 m, sideways, then jitter of 0.1 mm in place.
        let mut q = P2 { x: 0.0, y: 0.0 };
        let mut go = |dx: f64, dy: f64, n: usize, p: &mut PathPieces, all: &mut Vec<P2>| {
            for _ in 0..n {
                q = P2 { x: q.x + dx, y: q.y + dy };
                all.push(q);
                p.push(q);
            }
        };
        go(1e-3, 0.0, 500, &mut p, &mut all);
        go(-1e-3, 0.0, 300, &mut p, &mut all);
        go(0.0, 1e-3, 200, &mut p, &mut all);
        for k in 0..2000 {
            let s = if k % 2 == 0 { 1e-4 } else { -1e-4 };
            go(s, s, 1, &mut p, &mut all);
        }
        let line = drawn(&p);
        assert!(max_gap(&all, &line) <= PATH_TOLERANCE_M * 1.5, "{}", max_gap(&all, &line));
        assert!(line.len() <= 6, "{} vertices for three legs and jitter", line.len());
    }
}
