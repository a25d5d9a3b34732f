//! MCAP output for Foxglove: the topics of [`crate::foxglove_topics`], written with the
//! `mcap` crate (zstd chunks, message indexes, chunk indexes, statistics).
//!
//! `wmr-cli run` hands the runs over one after the other; the chunk is closed at every
//! run boundary, so no chunk spans two runs' times. A seek in Foxglove decompresses one
//! chunk per subscribed topic (the one holding its latest message), so the chunk size is
//! chosen from the number of topics ([`chunk_bytes`]): a seek decompresses about
//! [`SEEK_BUDGET_BYTES`], or topics x [`MIN_CHUNK_BYTES`] when there are many.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufWriter, Seek, Write};

use mcap::records::MessageHeader;
use mcap::{Compression, WriteOptions, Writer};
use wmr_core::obstacle::Obstacles;
use wmr_core::{RobotParams, Sample};
use wmr_scenario::{Columns, RunSpec, Scenario, SimSpec, Sink, SinkError};

use crate::atomic::OutWriter;
use crate::foxglove_topics::{Kind, MESSAGE_ENCODING, MppiView, RunEncoder, Schemas, Views, topic};
use crate::ros2::{self, Ros2RunEncoder, Ros2Schema, Topic};
use crate::sinks::{FileSink, SinkOptions};

/// Which topics an MCAP file carries (`wmr-cli run --profile`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Profile {
    /// Foxglove's well-known schemas (protobuf): `/runN/tf`, `/runN/sample`, scenes.
    #[default]
    Foxglove,
    /// ROS 2 messages (CDR, `.msg` schemas; the MCAP `ros2` profile): `/tf`, `/odom`,
    /// `/joint_states`, ... (`/runN/...` with several runs).
    Ros2,
    /// Both sets of channels in one file.
    Both,
}

impl Profile {
    /// Whether the file has the Foxglove channels.
    pub fn foxglove(self) -> bool {
        self != Profile::Ros2
    }

    /// Whether the file has the ROS 2 channels.
    pub fn ros2(self) -> bool {
        self != Profile::Foxglove
    }

    /// The profile field of the MCAP header: `ros2` for a ROS 2 file, else empty.
    fn header(self) -> &'static str {
        if self == Profile::Ros2 { "ros2" } else { "" }
    }
}

/// Decompressed bytes a seek should cost at most, when chunks need not be smaller than
/// [`MIN_CHUNK_BYTES`].
pub const SEEK_BUDGET_BYTES: u64 = 8 << 20;
/// Smallest chunk (uncompressed bytes): smaller ones compress worse and cost an index
/// entry each (about 0.4 KB of memory until the file is finished).
pub const MIN_CHUNK_BYTES: u64 = 64 << 10;
/// Largest chunk (uncompressed bytes).
pub const MAX_CHUNK_BYTES: u64 = 1 << 20;

/// Uncompressed bytes after which a chunk is closed, for `runs` runs carrying `columns`
/// and `views` (which decide the topics, [`Kind::present`]): [`SEEK_BUDGET_BYTES`] over the number of
/// topics, within [`MIN_CHUNK_BYTES`]..=[`MAX_CHUNK_BYTES`]. Fig. 7 (5 topics): 1 MiB; 30
/// runs: 64 KiB.
pub fn chunk_bytes(runs: usize, columns: &Columns, views: Views) -> u64 {
    let topics = (runs.max(1) * Kind::present(columns, views).count()) as u64;
    (SEEK_BUDGET_BYTES / topics).clamp(MIN_CHUNK_BYTES, MAX_CHUNK_BYTES)
}

/// zstd level of the chunks: 1, the fastest (level 3, zstd's default, makes Fig. 7's file
/// 4 % smaller for 25 % more writing time).
const ZSTD_LEVEL: u32 = 1;

/// The channel ids of one run, indexed by [`Kind`] (0 where the file has no such topic).
pub type RunChannels = [u16; Kind::ALL.len()];

/// The ROS 2 channel ids of one run, indexed by [`Topic`] (0 where the file has no such topic).
pub type Ros2Channels = [u16; Topic::ALL.len()];

/// An MCAP file being written: its schemas, and channels added run by run.
pub struct McapFile<W: Target = File> {
    writer: Writer<BufWriter<W>>,
    /// Schema ids by [`Kind`].
    schema_ids: [u16; Kind::ALL.len()],
    /// ROS 2 schema ids by [`Topic`].
    ros2_schema_ids: [u16; Topic::ALL.len()],
    columns: Columns,
    views: Views,
    profile: Profile,
    runs: usize,
    sequence: u32,
}

/// Where an MCAP file goes: a file, or an [`OutWriter`] (a file, or a stream such as
/// stdout or a FIFO, which gets the MCAP written front to back, without seeking).
pub trait Target: Write + Seek {
    /// True when the writer may seek back.
    fn seekable(&self) -> bool {
        true
    }
}

impl Target for File {}

impl Target for OutWriter {
    fn seekable(&self) -> bool {
        OutWriter::seekable(self)
    }
}

/// An MCAP error as a sink error; an I/O error keeps its kind (a full disk, a closed pipe).
fn mcap_err(e: mcap::McapError) -> SinkError {
    match e {
        mcap::McapError::Io(io) => Box::new(io::Error::new(io.kind(), format!("cannot write the MCAP file: {io}"))),
        e => format!("cannot write the MCAP file: {e}").into(),
    }
}

impl<W: Target> McapFile<W> {
    /// Starts the file on `file` for `runs` runs carrying `columns` and `views` (the
    /// Foxglove profile).
    pub fn new(file: W, runs: usize, columns: Columns, views: Views) -> Result<Self, SinkError> {
        Self::with_profile(file, runs, columns, views, Profile::Foxglove)
    }

    /// Starts the file on `file` for `runs` runs carrying `columns` and `views`, with the
    /// channels of `profile`.
    pub fn with_profile(
        file: W,
        runs: usize,
        columns: Columns,
        views: Views,
        profile: Profile,
    ) -> Result<Self, SinkError> {
        let chunk = if profile == Profile::Foxglove {
            chunk_bytes(runs, &columns, views)
        } else {
            let fox = if profile.foxglove() { Kind::present(&columns, views).count() } else { 0 };
            let topics = (runs.max(1) * (fox + Topic::present(&columns).count())) as u64;
            (SEEK_BUDGET_BYTES / topics).clamp(MIN_CHUNK_BYTES, MAX_CHUNK_BYTES)
        };
        let options = WriteOptions::new()
            .disable_seeking(!file.seekable())
            .profile(profile.header())
            .library(concat!("wmr-cli ", env!("CARGO_PKG_VERSION")))
            .compression(Some(Compression::Zstd))
            .compression_level(ZSTD_LEVEL)
            // One thread: zstd's worker threads cost more in locking than they save on
            // 64 KiB chunks, and this keeps the writer's cost plain CPU time on this thread.
            .compression_threads(0)
            .chunk_size(Some(chunk));
        let mut writer = options.create(BufWriter::with_capacity(1 << 16, file)).map_err(mcap_err)?;
        let mut schema_ids = [0u16; Kind::ALL.len()];
        if profile.foxglove() {
            let schemas = Schemas::new(&columns);
            for kind in Kind::present(&columns, views) {
                let s = kind.schema(&schemas);
                schema_ids[kind as usize] = writer.add_schema(&s.name, &s.encoding, &s.data).map_err(mcap_err)?;
            }
        }
        let mut ros2_schema_ids = [0u16; Topic::ALL.len()];
        if profile.ros2() {
            for topic in Topic::present(&columns) {
                let s = Ros2Schema::of(topic.msg_type());
                ros2_schema_ids[topic as usize] =
                    writer.add_schema(&s.name, ros2::ROS2MSG, s.data.as_bytes()).map_err(mcap_err)?;
            }
        }
        Ok(Self { writer, schema_ids, ros2_schema_ids, columns, views, profile, runs, sequence: 0 })
    }

    /// Adds the ROS 2 channels of run `run` (none without the ROS 2 profile).
    pub fn add_ros2_run(&mut self, run: usize) -> Result<Ros2Channels, SinkError> {
        let mut channels = [0u16; Topic::ALL.len()];
        if !self.profile.ros2() {
            return Ok(channels);
        }
        for topic in Topic::present(&self.columns) {
            let metadata = BTreeMap::from([(
                "offered_qos_profiles".to_owned(),
                ros2::offered_qos_profiles(topic.transient_local()),
            )]);
            channels[topic as usize] = self
                .writer
                .add_channel(
                    self.ros2_schema_ids[topic as usize],
                    &ros2::topic_name(run, self.runs, topic),
                    ros2::CDR,
                    &metadata,
                )
                .map_err(|e| SinkError::from(format!("cannot add the channels of run {run} to the MCAP file: {e}")))?;
        }
        Ok(channels)
    }

    /// Attaches the robot's URDF (`robot.urdf`, for Foxglove's 3D panel), log time 0.
    pub fn attach_urdf(&mut self, urdf: &str) -> Result<(), SinkError> {
        let attachment = mcap::Attachment {
            log_time: 0,
            create_time: 0,
            name: "robot.urdf".into(),
            media_type: "application/xml".into(),
            data: std::borrow::Cow::Borrowed(urdf.as_bytes()),
        };
        self.writer.attach(&attachment).map_err(mcap_err)
    }

    /// Writes one ROS 2 message of `topic` on `channels`, log time `ns`.
    #[inline]
    pub fn write_ros2(
        &mut self,
        channels: &Ros2Channels,
        topic: Topic,
        ns: u64,
        data: &[u8],
    ) -> Result<(), mcap::McapError> {
        self.sequence = self.sequence.wrapping_add(1);
        let header = MessageHeader {
            channel_id: channels[topic as usize],
            sequence: self.sequence,
            log_time: ns,
            publish_time: ns,
        };
        self.writer.write_to_known_channel(&header, data)
    }

    /// Adds the channels of run `run`.
    pub fn add_run(&mut self, run: usize) -> Result<RunChannels, SinkError> {
        let mut channels = [0u16; Kind::ALL.len()];
        if !self.profile.foxglove() {
            return Ok(channels);
        }
        let none = BTreeMap::new();
        for kind in Kind::present(&self.columns, self.views) {
            let id = self.schema_ids[kind as usize];
            channels[kind as usize] = self
                .writer
                .add_channel(id, &topic(run, kind), MESSAGE_ENCODING, &none)
                .map_err(|e| SinkError::from(format!("cannot add the channels of run {run} to the MCAP file: {e}")))?;
        }
        Ok(channels)
    }

    /// Writes one message of `kind` on `channels`, log time `ns`.
    #[inline]
    pub fn write(&mut self, channels: &RunChannels, kind: Kind, ns: u64, data: &[u8]) -> Result<(), mcap::McapError> {
        self.sequence = self.sequence.wrapping_add(1);
        let header = MessageHeader {
            channel_id: channels[kind as usize],
            sequence: self.sequence,
            log_time: ns,
            publish_time: ns,
        };
        self.writer.write_to_known_channel(&header, data)
    }

    /// Closes the current chunk.
    pub fn end_chunk(&mut self) -> Result<(), SinkError> {
        self.writer.flush().map_err(mcap_err)
    }

    /// Writes the summary (indexes, statistics) and the footer, and flushes.
    pub fn finish(mut self) -> Result<(), SinkError> {
        self.writer.finish().map_err(mcap_err)?;
        self.writer.into_inner().flush().map_err(|e| SinkError::from(format!("cannot write the MCAP file: {e}")))
    }
}

/// One run's encoders and channels.
struct RunState {
    /// The Foxglove topics' encoder (Foxglove profile).
    encoder: Option<RunEncoder>,
    channels: RunChannels,
    /// The ROS 2 topics' encoder (ROS 2 profile).
    ros2: Option<Ros2RunEncoder>,
    ros2_channels: Ros2Channels,
    last_t: f64,
    /// MPPI's plans (an MPPI law, Foxglove profile).
    mppi: Option<MppiView>,
}

/// Writes the runs of `wmr-cli run` to an MCAP file.
pub struct McapSink {
    file: Option<McapFile<OutWriter>>,
    robot: RobotParams<f64>,
    sim: SimSpec,
    columns: Columns,
    /// The world's obstacles (none: no [`Kind::Obstacles`]).
    obstacles: Obstacles<f64>,
    /// The scenario, when its law is MPPI: [`MppiView`] steps a copy of each run's loop.
    mppi: Option<Box<Scenario>>,
    profile: Profile,
    runs: usize,
    /// The scenario's name: the URDF's robot name.
    name: String,
    run: Option<RunState>,
    runs_begun: usize,
}

impl McapSink {
    /// Starts an MCAP file on `file` for the runs of `scenario`, with the topics of `profile`.
    pub fn new(file: OutWriter, scenario: &Scenario, profile: Profile) -> Result<Self, SinkError> {
        let columns = Columns::of(scenario);
        let runs = scenario.runs().len();
        let mut mcap = McapFile::with_profile(file, runs, columns.clone(), Views::of(scenario), profile)?;
        if profile.ros2() {
            mcap.attach_urdf(&wmr_scenario::urdf::urdf(scenario.robot().params(), scenario.name(), ""))?;
        }
        Ok(Self {
            file: Some(mcap),
            robot: *scenario.robot().params(),
            sim: *scenario.sim(),
            columns,
            obstacles: scenario.setup().obstacles,
            mppi: (profile.foxglove() && Views::of(scenario).mppi).then(|| Box::new(scenario.clone())),
            profile,
            runs,
            name: scenario.name().to_owned(),
            run: None,
            runs_begun: 0,
        })
    }

    fn file(&mut self) -> Result<&mut McapFile<OutWriter>, SinkError> {
        self.file.as_mut().ok_or_else(|| "MCAP sink already finished".into())
    }
}

/// MCAP samples, zstd-compressed, take 130 to 180 bytes (Fig. 7: 180), fewer when the
/// robot stands still.
impl FileSink for McapSink {
    const NAME: &'static str = "mcap";
    const HELP: &'static str = "MCAP with Foxglove's well-known schemas (or ROS 2 messages: --profile)";
    const BYTES_PER_SAMPLE: (u64, u64) = (50, 180);

    fn open(out: OutWriter, scenario: &Scenario, options: &SinkOptions) -> Result<Self, SinkError> {
        Self::new(out, scenario, options.profile)
    }
}

impl Sink for McapSink {
    fn begin_run(&mut self, index: usize, run: &RunSpec) -> Result<(), SinkError> {
        let first = self.runs_begun == 0;
        self.runs_begun += 1;
        let file = self.file()?;
        if !first {
            // Each run starts again at t = 0: a chunk holding the end of one run and the
            // start of the next would span the whole time range.
            file.end_chunk()?;
        }
        let channels = file.add_run(index)?;
        let ros2_channels = file.add_ros2_run(index)?;
        let profile = self.profile;
        self.run = Some(RunState {
            encoder: profile.foxglove().then(|| {
                let encoder = RunEncoder::new(index, run, &self.robot, self.columns.clone(), &self.sim)
                    .with_obstacles(&self.obstacles);
                // Several runs' ROS 2 frames are named as the Foxglove ones (run3/base_link).
                if profile == Profile::Both && self.runs > 1 { encoder.joined_to_ros2_map() } else { encoder }
            }),
            channels,
            ros2: profile.ros2().then(|| {
                let prefix = ros2::topics::frame(index, self.runs, "");
                let description = wmr_scenario::urdf::urdf(&self.robot, &self.name, &prefix);
                Ros2RunEncoder::new(index, self.runs, run, &self.robot, self.columns.clone(), &self.sim, description)
            }),
            ros2_channels,
            last_t: 0.0,
            mppi: match &self.mppi {
                Some(scenario) => MppiView::new(scenario, index)?,
                None => None,
            },
        });
        Ok(())
    }

    fn sample(&mut self, _index: usize, s: &Sample<f64>) -> Result<(), SinkError> {
        let (Some(file), Some(run)) = (self.file.as_mut(), self.run.as_mut()) else {
            return Err("MCAP sink: sample before begin_run".into());
        };
        run.last_t = s.t;
        let channels = &run.channels;
        if let Some(view) = &mut run.mppi {
            view.advance_to(s.t, &mut |kind, ns, data| file.write(channels, kind, ns, data)).map_err(mcap_err)?;
        }
        if let Some(encoder) = &mut run.encoder {
            encoder.sample(s, &mut |kind, ns, data| file.write(channels, kind, ns, data)).map_err(mcap_err)?;
        }
        let channels = &run.ros2_channels;
        if let Some(encoder) = &mut run.ros2 {
            encoder.sample(s, &mut |topic, ns, data| file.write_ros2(channels, topic, ns, data)).map_err(mcap_err)?;
        }
        Ok(())
    }

    fn end_run(&mut self, _result: &wmr_scenario::RunResult) -> Result<(), SinkError> {
        let (Some(file), Some(mut run)) = (self.file.as_mut(), self.run.take()) else {
            return Err("MCAP sink: end_run before begin_run".into());
        };
        let channels = &run.channels;
        match &mut run.encoder {
            Some(encoder) => {
                encoder.finish(run.last_t, &mut |kind, ns, data| file.write(channels, kind, ns, data)).map_err(mcap_err)
            }
            None => Ok(()),
        }
    }

    fn finish(&mut self) -> Result<(), SinkError> {
        self.file.take().ok_or("MCAP sink finished twice")?.finish()
    }
}
