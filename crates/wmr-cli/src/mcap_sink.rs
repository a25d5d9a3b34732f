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
use wmr_core::{RobotParams, Sample};
use wmr_scenario::{Columns, RunSpec, Scenario, SimSpec, Sink, SinkError};

use crate::atomic::OutWriter;
use crate::foxglove_topics::{Kind, MESSAGE_ENCODING, RunEncoder, Schemas, topic};

/// Decompressed bytes a seek should cost at most, when chunks need not be smaller than
/// [`MIN_CHUNK_BYTES`].
pub const SEEK_BUDGET_BYTES: u64 = 8 << 20;
/// Smallest chunk (uncompressed bytes): smaller ones compress worse and cost an index
/// entry each (about 0.4 KB of memory until the file is finished).
pub const MIN_CHUNK_BYTES: u64 = 64 << 10;
/// Largest chunk (uncompressed bytes).
pub const MAX_CHUNK_BYTES: u64 = 1 << 20;

/// Uncompressed bytes after which a chunk is closed, for `runs` runs carrying `columns`
/// (which decide the topics, [`Kind::present`]): [`SEEK_BUDGET_BYTES`] over the number of
/// topics, within [`MIN_CHUNK_BYTES`]..=[`MAX_CHUNK_BYTES`]. Fig. 7 (5 topics): 1 MiB; 30
/// runs: 64 KiB.
pub fn chunk_bytes(runs: usize, columns: &Columns) -> u64 {
    let topics = (runs.max(1) * Kind::present(columns).count()) as u64;
    (SEEK_BUDGET_BYTES / topics).clamp(MIN_CHUNK_BYTES, MAX_CHUNK_BYTES)
}

/// zstd level of the chunks: 1, the fastest (level 3, zstd's default, makes Fig. 7's file
/// 4 % smaller for 25 % more writing time).
const ZSTD_LEVEL: u32 = 1;

/// The channel ids of one run, indexed by [`Kind`] (0 where the file has no such topic).
pub type RunChannels = [u16; Kind::ALL.len()];

/// An MCAP file being written: its schemas, and channels added run by run.
pub struct McapFile<W: Target = File> {
    writer: Writer<BufWriter<W>>,
    /// Schema ids by [`Kind`].
    schema_ids: [u16; Kind::ALL.len()],
    columns: Columns,
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
    /// Starts the file on `file` for `runs` runs carrying `columns`.
    pub fn new(file: W, runs: usize, columns: Columns) -> Result<Self, SinkError> {
        let options = WriteOptions::new()
            .disable_seeking(!file.seekable())
            .profile("")
            .library(concat!("wmr-cli ", env!("CARGO_PKG_VERSION")))
            .compression(Some(Compression::Zstd))
            .compression_level(ZSTD_LEVEL)
            // One thread: zstd's worker threads cost more in locking than they save on
            // 64 KiB chunks, and this keeps the writer's cost plain CPU time on this thread.
            .compression_threads(0)
            .chunk_size(Some(chunk_bytes(runs, &columns)));
        let mut writer = options.create(BufWriter::with_capacity(1 << 16, file)).map_err(mcap_err)?;
        let schemas = Schemas::new(&columns);
        let mut schema_ids = [0u16; Kind::ALL.len()];
        for kind in Kind::present(&columns) {
            let s = kind.schema(&schemas);
            schema_ids[kind as usize] = writer.add_schema(&s.name, &s.encoding, &s.data).map_err(mcap_err)?;
        }
        Ok(Self { writer, schema_ids, columns, sequence: 0 })
    }

    /// Adds the channels of run `run`.
    pub fn add_run(&mut self, run: usize) -> Result<RunChannels, SinkError> {
        let mut channels = [0u16; Kind::ALL.len()];
        let none = BTreeMap::new();
        for kind in Kind::present(&self.columns) {
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

/// One run's encoder and channels.
struct RunState {
    encoder: RunEncoder,
    channels: RunChannels,
    last_t: f64,
}

/// Writes the runs of `wmr-cli run` to an MCAP file.
pub struct McapSink {
    file: Option<McapFile<OutWriter>>,
    robot: RobotParams<f64>,
    sim: SimSpec,
    columns: Columns,
    run: Option<RunState>,
    runs_begun: usize,
}

impl McapSink {
    /// Starts an MCAP file on `file` for the runs of `scenario`.
    pub fn new(file: OutWriter, scenario: &Scenario) -> Result<Self, SinkError> {
        let columns = Columns::of(scenario);
        Ok(Self {
            file: Some(McapFile::new(file, scenario.runs().len(), columns.clone())?),
            robot: *scenario.robot().params(),
            sim: *scenario.sim(),
            columns,
            run: None,
            runs_begun: 0,
        })
    }

    fn file(&mut self) -> Result<&mut McapFile<OutWriter>, SinkError> {
        self.file.as_mut().ok_or_else(|| "MCAP sink already finished".into())
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
        self.run = Some(RunState {
            encoder: RunEncoder::new(index, run, &self.robot, self.columns.clone(), &self.sim),
            channels,
            last_t: 0.0,
        });
        Ok(())
    }

    fn sample(&mut self, _index: usize, s: &Sample<f64>) -> Result<(), SinkError> {
        let (Some(file), Some(run)) = (self.file.as_mut(), self.run.as_mut()) else {
            return Err("MCAP sink: sample before begin_run".into());
        };
        run.last_t = s.t;
        let channels = &run.channels;
        run.encoder.sample(s, &mut |kind, ns, data| file.write(channels, kind, ns, data)).map_err(mcap_err)
    }

    fn end_run(&mut self, _result: &wmr_scenario::RunResult) -> Result<(), SinkError> {
        let (Some(file), Some(mut run)) = (self.file.as_mut(), self.run.take()) else {
            return Err("MCAP sink: end_run before begin_run".into());
        };
        let channels = &run.channels;
        run.encoder.finish(run.last_t, &mut |kind, ns, data| file.write(channels, kind, ns, data)).map_err(mcap_err)
    }

    fn finish(&mut self) -> Result<(), SinkError> {
        self.file.take().ok_or("MCAP sink finished twice")?.finish()
    }
}
