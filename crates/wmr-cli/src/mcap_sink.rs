//! MCAP output with Foxglove's well-known schemas, written by the `foxglove` crate.
//!
//! Topics, per run `N` (0-based index of the `[[run]]`); log time = simulation time (ns
//! from the Unix epoch, so t = 0 is 1970-01-01T00:00:00Z):
//!
//! | topic | schema | messages |
//! |---|---|---|
//! | `/runN/tf` | `foxglove.FrameTransform` | every sample: `world` -> `runN/base_link` (pose of C) |
//! | `/runN/pose` | `foxglove.PoseInFrame` | every sample: pose of C in `world` |
//! | `/runN/path` | `foxglove.SceneUpdate` | every sample: the path of C so far, as line strips of up to 32 points (entities `path/K`) |
//! | `/runN/sample` | `wmr.Sample` (JSON, JSON Schema) | every sample: `run` and every CSV column |
//! | `/runN/goal` | `foxglove.PoseInFrame` | once, at t = 0: the goal pose in `world` |
//! | `/runN/robot` | `foxglove.SceneUpdate` | once, at t = 0: a box locked to `runN/base_link` |
//! | `/runN/pose_meas` | `foxglove.PoseInFrame` | with a `[sensor]`: every sample, the pose the controller used |
//!
//! With a `[sensor]` the JSON samples also carry `x_meas`, `y_meas`, `theta_meas`.

use std::fmt::Write as _;
use std::fs::File;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::sync::{Arc, Mutex};

use foxglove::messages::{
    Color, CubePrimitive, FrameTransform, LinePrimitive, Point3, Pose, PoseInFrame, Quaternion, SceneEntity,
    SceneEntityDeletion, SceneUpdate, Timestamp, Vector3, line_primitive, scene_entity_deletion,
};
use foxglove::{Channel, Context, McapWriteOptions, McapWriterHandle, PartialMetadata, RawChannel, Schema};
use wmr_core::{Pose2, RobotParams, Sample};
use wmr_scenario::{MEASURED_COLUMNS, RunSpec, SAMPLE_COLUMNS, Sink, SinkError, measured_values, sample_values};

use crate::csv_sink::format_f64;

/// Points per path entity: the path of a run is a chain of line strips this long, so
/// each message stays small and the 3D panel holds few entities.
const PATH_CHUNK: usize = 32;

/// A writer that remembers its first I/O error: the foxglove sink only logs write
/// errors, and the output must not be renamed into place after one.
struct Checked<W> {
    inner: W,
    error: Arc<Mutex<Option<String>>>,
}

impl<W> Checked<W> {
    fn note<T>(&self, r: io::Result<T>) -> io::Result<T> {
        if let Err(e) = &r
            && let Ok(mut slot) = self.error.lock()
            && slot.is_none()
        {
            *slot = Some(e.to_string());
        }
        r
    }
}

impl<W: Write> Write for Checked<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let r = self.inner.write(buf);
        self.note(r)
    }
    fn flush(&mut self) -> io::Result<()> {
        let r = self.inner.flush();
        self.note(r)
    }
}

impl<W: Seek> Seek for Checked<W> {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        let r = self.inner.seek(pos);
        self.note(r)
    }
}

/// One run's channels.
struct RunChannels {
    tf: Channel<FrameTransform>,
    pose: Channel<PoseInFrame>,
    path: Channel<SceneUpdate>,
    sample: Arc<RawChannel>,
    /// The measured pose, with a `[sensor]`.
    pose_meas: Option<Channel<PoseInFrame>>,
    base_link: String,
    /// Points of the path chunk being drawn.
    chunk: Vec<Point3>,
    chunk_index: usize,
    /// JSON of the current sample.
    json: String,
    number: String,
}

/// Writes the runs to an MCAP file; see the module doc for the topics.
pub struct McapSink {
    context: Arc<Context>,
    handle: Option<McapWriterHandle<Checked<BufWriter<File>>>>,
    error: Arc<Mutex<Option<String>>>,
    robot: RobotParams<f64>,
    run: Option<RunChannels>,
    schema: Schema,
    /// Also log the measured pose (the scenario has a `[sensor]`).
    measured: bool,
}

/// Log time of a simulation time `t` (s): ns from the Unix epoch.
fn nanos(t: f64) -> u64 {
    // t is in [0, 1e6] s (the scenario checks it), so this fits a u64 exactly enough.
    (t * 1e9).round().max(0.0) as u64
}

fn stamp(t: f64) -> Timestamp {
    let ns = nanos(t);
    Timestamp::new((ns / 1_000_000_000) as u32, (ns % 1_000_000_000) as u32)
}

fn yaw(theta: f64) -> Quaternion {
    let h = 0.5 * theta;
    Quaternion { x: 0.0, y: 0.0, z: h.sin(), w: h.cos() }
}

fn pose(p: Pose2<f64>) -> Pose {
    Pose { position: Some(Vector3 { x: p.x, y: p.y, z: 0.0 }), orientation: Some(yaw(p.theta)) }
}

/// JSON Schema of the `/runN/sample` messages: `run` and every CSV column, all numbers.
fn sample_schema(measured: bool) -> Schema {
    let mut props = String::from(r#""run":{"type":"integer","description":"0-based index of the [[run]]"}"#);
    let extra: &[&str] = if measured { &MEASURED_COLUMNS } else { &[] };
    for c in SAMPLE_COLUMNS.iter().chain(extra) {
        let _ = write!(props, r#","{c}":{{"type":"number"}}"#);
    }
    let text = format!(
        r#"{{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"wmr.Sample","description":"One logged sample of a wmr run: SI units, radians (SPEC section 6 CSV columns)","type":"object","properties":{{{props}}}}}"#
    );
    Schema::new("wmr.Sample", "jsonschema", text.into_bytes())
}

impl McapSink {
    /// Starts an MCAP file on `file` for runs of `robot`; `measured`: log the measured pose too.
    pub fn new(file: File, robot: RobotParams<f64>, measured: bool) -> Result<Self, SinkError> {
        let context = Context::new();
        let error = Arc::new(Mutex::new(None));
        let writer = Checked { inner: BufWriter::with_capacity(1 << 16, file), error: error.clone() };
        let options = McapWriteOptions::new().profile("");
        let handle = context.mcap_writer_with_options(options).create(writer)?;
        Ok(Self { context, handle: Some(handle), error, robot, run: None, schema: sample_schema(measured), measured })
    }

    fn check(&self) -> Result<(), SinkError> {
        match self.error.lock().map(|e| e.clone()) {
            Ok(None) => Ok(()),
            Ok(Some(e)) => Err(format!("cannot write the MCAP file: {e}").into()),
            Err(_) => Err("cannot write the MCAP file".into()),
        }
    }
}

impl Sink for McapSink {
    fn begin_run(&mut self, index: usize, run: &RunSpec) -> Result<(), SinkError> {
        let ctx = &self.context;
        let topic = |name: &str| format!("/run{index}/{name}");
        let base_link = format!("run{index}/base_link");
        let at0 = stamp(0.0);

        let goal: Channel<PoseInFrame> = ctx.channel_builder(topic("goal")).build();
        goal.log_with_time(
            &PoseInFrame { timestamp: Some(at0), frame_id: "world".into(), pose: Some(pose(run.goal)) },
            nanos(0.0),
        );
        // The body: a box of the track's width, locked to base_link (C at the axle).
        let r = &self.robot;
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
            color: Some(Color { r: 0.2, g: 0.5, b: 0.9, a: 0.8 }),
        };
        let robot: Channel<SceneUpdate> = ctx.channel_builder(topic("robot")).build();
        robot.log_with_time(
            &SceneUpdate {
                deletions: vec![],
                entities: vec![SceneEntity {
                    timestamp: Some(at0),
                    frame_id: base_link.clone(),
                    id: "body".into(),
                    frame_locked: true,
                    cubes: vec![body],
                    ..Default::default()
                }],
            },
            nanos(0.0),
        );
        let sample =
            ctx.channel_builder(topic("sample")).message_encoding("json").schema(self.schema.clone()).build_raw()?;
        self.run = Some(RunChannels {
            tf: ctx.channel_builder(topic("tf")).build(),
            pose: ctx.channel_builder(topic("pose")).build(),
            path: ctx.channel_builder(topic("path")).build(),
            sample,
            pose_meas: self.measured.then(|| ctx.channel_builder(topic("pose_meas")).build()),
            base_link,
            chunk: Vec::with_capacity(PATH_CHUNK),
            chunk_index: 0,
            json: String::with_capacity(512),
            number: String::with_capacity(32),
        });
        self.check()
    }

    fn sample(&mut self, index: usize, s: &Sample<f64>) -> Result<(), SinkError> {
        let ch = self.run.as_mut().ok_or("MCAP sink: sample before begin_run")?;
        let ns = nanos(s.t);
        let ts = Some(stamp(s.t));
        let p = s.state.pose();
        ch.tf.log_with_time(
            &FrameTransform {
                timestamp: ts,
                parent_frame_id: "world".into(),
                child_frame_id: ch.base_link.clone(),
                translation: Some(Vector3 { x: p.x, y: p.y, z: 0.0 }),
                rotation: Some(yaw(p.theta)),
            },
            ns,
        );
        ch.pose.log_with_time(&PoseInFrame { timestamp: ts, frame_id: "world".into(), pose: Some(pose(p)) }, ns);
        if let Some(meas) = &ch.pose_meas {
            meas.log_with_time(
                &PoseInFrame { timestamp: ts, frame_id: "world".into(), pose: Some(pose(s.measured)) },
                ns,
            );
        }

        // Path: the current chunk grows until PATH_CHUNK points, then a new entity starts
        // at the last point so the line stays continuous.
        let point = Point3 { x: p.x, y: p.y, z: 0.0 };
        if ch.chunk.len() >= PATH_CHUNK {
            let last = ch.chunk[ch.chunk.len() - 1];
            ch.chunk.clear();
            ch.chunk.push(last);
            ch.chunk_index += 1;
        }
        ch.chunk.push(point);
        let first = ch.chunk.len() == 1 && ch.chunk_index == 0;
        let mut points = ch.chunk.clone();
        if points.len() == 1 {
            points.push(point);
        }
        let deletions = if first {
            vec![SceneEntityDeletion {
                timestamp: ts,
                r#type: scene_entity_deletion::Type::All as i32,
                id: String::new(),
            }]
        } else {
            vec![]
        };
        ch.path.log_with_time(
            &SceneUpdate {
                deletions,
                entities: vec![SceneEntity {
                    timestamp: ts,
                    frame_id: "world".into(),
                    id: format!("path/{}", ch.chunk_index),
                    lines: vec![LinePrimitive {
                        r#type: line_primitive::Type::LineStrip as i32,
                        pose: Some(pose(Pose2::new(0.0, 0.0, 0.0))),
                        thickness: 0.01,
                        scale_invariant: false,
                        points,
                        color: Some(Color { r: 1.0, g: 0.6, b: 0.1, a: 1.0 }),
                        ..Default::default()
                    }],
                    ..Default::default()
                }],
            },
            ns,
        );

        ch.json.clear();
        let _ = write!(ch.json, "{{\"run\":{index}");
        for (name, v) in SAMPLE_COLUMNS.iter().zip(sample_values(s)) {
            format_f64(v, &mut ch.number);
            let _ = write!(ch.json, ",\"{name}\":{}", ch.number);
        }
        if ch.pose_meas.is_some() {
            for (name, v) in MEASURED_COLUMNS.iter().zip(measured_values(s)) {
                format_f64(v, &mut ch.number);
                let _ = write!(ch.json, ",\"{name}\":{}", ch.number);
            }
        }
        ch.json.push('}');
        ch.sample.log_with_meta(ch.json.as_bytes(), PartialMetadata::with_log_time(ns));
        Ok(())
    }

    fn end_run(&mut self, _result: &wmr_scenario::RunResult) -> Result<(), SinkError> {
        self.run = None;
        self.check()
    }

    fn finish(&mut self) -> Result<(), SinkError> {
        let handle = self.handle.take().ok_or("MCAP sink finished twice")?;
        let mut writer = handle.close()?;
        writer.flush()?;
        self.check()
    }
}
