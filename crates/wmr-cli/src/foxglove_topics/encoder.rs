//! The per-run encoder: a run's samples to the messages of every topic, with the path's
//! pieces, the clock's stamps and the run's colour; its bytes go to the MCAP file and the
//! live server alike.

use foxglove::messages::{
    ArrowPrimitive, CubePrimitive, FrameTransform, LinePrimitive, Point3, Pose, PoseInFrame, Quaternion, SceneEntity,
    SceneEntityDeletion, SceneUpdate, Vector3, line_primitive, scene_entity_deletion,
};
use wmr_core::obstacle::Obstacles;
use wmr_core::{Pose2, Reference, RobotParams, Sample};
use wmr_scenario::{Columns, RunSpec, SimSpec};

use super::clock::{LogClock, stamp};
use super::colour::run_color;
use super::obstacles;
use super::path::{P2, PathPieces, RECENT_VERTICES};
use super::reference::dashes;
use super::sample::encode_sample;
use super::topics::{Kind, WORLD_FRAME, base_link, reference_frame};

fn yaw(theta: f64) -> Quaternion {
    let h = 0.5 * theta;
    Quaternion { x: 0.0, y: 0.0, z: h.sin(), w: h.cos() }
}

fn pose(p: Pose2<f64>) -> Pose {
    Pose { position: Some(Vector3 { x: p.x, y: p.y, z: 0.0 }), orientation: Some(yaw(p.theta)) }
}

/// Line width of the drawn path, screen pixels.
const PATH_WIDTH_PX: f64 = 2.5;

/// The entity id of a path piece on its topic.
pub const PATH_ENTITY: &str = "path";

/// Opacity of the reference robot's ghost (the robot's body is 0.6).
const GHOST_ALPHA: f64 = 0.25;

/// Dash length of the drawn reference path, in half-tracks (a 0.16 m half-track: 8 cm).
const DASH_HALF_TRACKS: f64 = 0.5;

/// Encodes one run's messages.
pub struct RunEncoder {
    clock: LogClock,
    columns: Columns,
    tf: FrameTransform,
    /// `tf` joins `world` to the ROS 2 channels' `map` instead of placing the body
    /// ([`RunEncoder::joined_to_ros2_map`]).
    tf_to_map: bool,
    meas: PoseInFrame,
    last_meas: Option<Pose2<f64>>,
    last_odom: Option<Pose2<f64>>,
    tf_ref: FrameTransform,
    /// A tracking run's `reference` message (path and ghost), until sent at the first sample.
    reference: Option<SceneUpdate>,
    body: SceneEntity,
    goal: SceneEntity,
    line: LinePrimitive,
    path: Option<PathPieces>,
    points: Vec<Point3>,
    buf: Vec<u8>,
    /// The world's obstacles ([`Kind::Obstacles`]), when it has some.
    obstacles: Option<Obstacles<f64>>,
}

impl RunEncoder {
    /// In a file that also has the ROS 2 channels of several runs (`--profile both`),
    /// where this run's body frame `runN/base_link` is also the ROS 2 one (parent
    /// `runN/odom`): the `tf` channel carries `world -> map` (identity) instead of
    /// `world -> runN/base_link`, so that every frame has one parent (Foxglove re-parents
    /// a frame at each transform that names another parent: the body would flicker
    /// between two trees) and the ROS 2 tree, which places `runN/base_link` at the same
    /// true pose, hangs from `world`.
    pub fn joined_to_ros2_map(mut self) -> Self {
        self.tf_to_map = true;
        self.tf.child_frame_id = crate::ros2::topics::MAP_FRAME.into();
        self
    }

    /// The encoder of run `run` (`spec`) of robot `robot`, simulated with `sim`, whose
    /// samples carry `columns`: `wmr.Sample` has their fields, and the topics
    /// [`Kind::present`] says (`pose_meas`, `pose_odom`, the reference's) are written.
    pub fn new(run: usize, spec: &RunSpec, robot: &RobotParams<f64>, columns: Columns, sim: &SimSpec) -> Self {
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
        // The reference robot's ghost: the same box, fainter, locked to the reference's frame.
        let ghost = CubePrimitive { color: Some(run_color(run, GHOST_ALPHA)), ..body };
        let reference = columns.reference.as_ref().map(|reference| SceneUpdate {
            deletions: vec![],
            entities: vec![
                SceneEntity {
                    frame_id: WORLD_FRAME.into(),
                    id: "reference_path".into(),
                    lines: vec![LinePrimitive {
                        r#type: line_primitive::Type::LineList as i32,
                        pose: Some(pose(Pose2::new(0.0, 0.0, 0.0))),
                        thickness: PATH_WIDTH_PX,
                        scale_invariant: true,
                        points: dashes(reference, sim, DASH_HALF_TRACKS * r.half_track),
                        color: Some(colour),
                        ..Default::default()
                    }],
                    ..Default::default()
                },
                SceneEntity {
                    frame_id: reference_frame(run),
                    id: "ghost".into(),
                    frame_locked: true,
                    cubes: vec![ghost],
                    ..Default::default()
                },
            ],
        });
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
            clock: LogClock::new(sim.dt()),
            columns,
            tf: FrameTransform {
                timestamp: None,
                parent_frame_id: WORLD_FRAME.into(),
                child_frame_id: base_link(run),
                translation: None,
                rotation: None,
            },
            tf_to_map: false,
            meas: PoseInFrame { timestamp: None, frame_id: WORLD_FRAME.into(), pose: None },
            last_meas: None,
            last_odom: None,
            tf_ref: FrameTransform {
                timestamp: None,
                parent_frame_id: WORLD_FRAME.into(),
                child_frame_id: reference_frame(run),
                translation: None,
                rotation: None,
            },
            reference,
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
            obstacles: None,
        }
    }

    /// The encoder drawing `obstacles` on [`Kind::Obstacles`] (nothing when there is none):
    /// at t = 0, and in red at the end of a run whose footprint touches one.
    pub fn with_obstacles(mut self, obstacles: &Obstacles<f64>) -> Self {
        self.obstacles = (!obstacles.is_empty()).then_some(*obstacles);
        self
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
            if let Some(o) = &self.obstacles {
                self.buf.clear();
                let _ = prost::Message::encode(&obstacles::scene(o, ts), &mut self.buf);
                out(Kind::Obstacles, ns, &self.buf)?;
            }
            if let Some(mut update) = self.reference.take() {
                for e in &mut update.entities {
                    e.timestamp = ts;
                }
                self.buf.clear();
                let _ = prost::Message::encode(&update, &mut self.buf);
                out(Kind::Reference, ns, &self.buf)?;
            }
        }

        self.tf.timestamp = ts;
        let placed = if self.tf_to_map { Pose2::new(0.0, 0.0, 0.0) } else { p };
        self.tf.translation = Some(Vector3 { x: placed.x, y: placed.y, z: 0.0 });
        self.tf.rotation = Some(yaw(placed.theta));
        self.buf.clear();
        let _ = prost::Message::encode(&self.tf, &mut self.buf);
        out(Kind::Tf, ns, &self.buf)?;

        if let Some(reference) = &self.columns.reference {
            let c_ref = reference.state_at(s.t).pose;
            self.tf_ref.timestamp = ts;
            self.tf_ref.translation = Some(Vector3 { x: c_ref.x, y: c_ref.y, z: 0.0 });
            self.tf_ref.rotation = Some(yaw(c_ref.theta));
            self.buf.clear();
            let _ = prost::Message::encode(&self.tf_ref, &mut self.buf);
            out(Kind::TfRef, ns, &self.buf)?;
        }

        self.buf.clear();
        encode_sample(s, &self.columns, &mut self.buf);
        out(Kind::Sample, ns, &self.buf)?;

        if self.columns.measured && self.last_meas != Some(s.measured) {
            self.last_meas = Some(s.measured);
            self.send_pose(Kind::PoseMeas, s.measured, ns, out)?;
        }
        if self.columns.odometry
            && let Some(odo) = s.odometry
            && self.last_odom != Some(odo)
        {
            self.last_odom = Some(odo);
            self.send_pose(Kind::PoseOdom, odo, ns, out)?;
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

    /// After the last sample: sends `path_tip` once more if C moved since it was sent; and
    /// when the footprint touches an obstacle there (the run collided), the collision on
    /// [`Kind::Obstacles`].
    pub fn finish<E>(&mut self, last_t: f64, out: &mut impl FnMut(Kind, u64, &[u8]) -> Result<(), E>) -> Result<(), E> {
        if let (Some(o), Some(path)) = (&self.obstacles, &self.path) {
            let ns = self.clock.nanos(last_t);
            if let Some(update) = obstacles::collision(o, path.end.x, path.end.y, Some(stamp(ns))) {
                self.buf.clear();
                let _ = prost::Message::encode(&update, &mut self.buf);
                out(Kind::Obstacles, ns, &self.buf)?;
            }
        }
        match &self.path {
            Some(path) if path.sent_end != Some(path.end) && path.end != path.old[0] => {
                self.send_path(self.clock.nanos(last_t), out)
            }
            _ => Ok(()),
        }
    }

    /// Sends pose `p` (frame world) on `kind`, stamped `ns`.
    fn send_pose<E>(
        &mut self,
        kind: Kind,
        p: Pose2<f64>,
        ns: u64,
        out: &mut impl FnMut(Kind, u64, &[u8]) -> Result<(), E>,
    ) -> Result<(), E> {
        self.meas.timestamp = Some(stamp(ns));
        self.meas.pose = Some(pose(p));
        self.buf.clear();
        let _ = prost::Message::encode(&self.meas, &mut self.buf);
        out(kind, ns, &self.buf)
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

    /// Bytes of the path topics (`scene`, `path`, `path_tip`) for `laps` laps of a circle
    /// of radius 1 m at 0.5 m/s, logged every 10 ms.
    fn path_bytes_for_laps(laps: usize) -> usize {
        let robot = RobotParams::<f64>::default();
        let spec = RunSpec::new(Pose2::new(1.0, 0.0, 0.0), Pose2::new(0.0, 0.0, 0.0));
        let columns = Columns::default();
        let sim = SimSpec::new(laps as f64 * 13.0, 1e-3, 0.01).unwrap();
        let mut enc = RunEncoder::new(0, &spec, &robot, columns, &sim);
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
}
