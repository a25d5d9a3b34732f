//! CSV output (docs/scenario.md): one header line, one row per run and logged sample.

use std::fmt::Write as _;
use std::io::BufWriter;

use wmr_core::Sample;
use wmr_scenario::{Columns, Sink, SinkError};

use crate::atomic::OutWriter;
use crate::sinks::{FileSink, SinkOptions};

/// Writes `run,t,x,...` rows, the columns of [`Columns`]; every number reads back to the
/// same f64.
pub struct CsvSink {
    writer: csv::Writer<BufWriter<OutWriter>>,
    field: String,
    columns: Columns,
}

/// The shortest text that reads back to `v` (shared with the ROS 2 log reader).
pub use wmr_identify::table::format_f64;

impl CsvSink {
    /// Writes the header (`run`, then `columns`' names) to `out` and flushes it, so an
    /// output that cannot be written at all (a full disk) fails before any run starts.
    pub fn new(out: OutWriter, columns: Columns) -> Result<Self, SinkError> {
        let mut writer =
            csv::WriterBuilder::new().buffer_capacity(1 << 16).from_writer(BufWriter::with_capacity(1 << 16, out));
        writer.write_record(std::iter::once("run").chain(columns.names()))?;
        writer.flush()?;
        Ok(Self { writer, field: String::with_capacity(32), columns })
    }
}

/// CSV rows take 150 to 290 bytes (Fig. 7: 280).
impl FileSink for CsvSink {
    const NAME: &'static str = "csv";
    const HELP: &'static str = "CSV, the columns of docs/scenario.md";
    const BYTES_PER_SAMPLE: (u64, u64) = (100, 280);

    fn open(out: OutWriter, scenario: &wmr_scenario::Scenario, _options: &SinkOptions) -> Result<Self, SinkError> {
        Self::new(out, Columns::of(scenario))
    }
}

impl CsvSink {
    /// Writes each of `values` as a field ([`format_f64`]).
    fn write_values(&mut self, values: impl IntoIterator<Item = f64>) -> Result<(), SinkError> {
        for v in values {
            format_f64(v, &mut self.field);
            self.writer.write_field(&self.field)?;
        }
        Ok(())
    }
}

impl Sink for CsvSink {
    fn sample(&mut self, index: usize, sample: &Sample<f64>) -> Result<(), SinkError> {
        self.field.clear();
        let _ = write!(self.field, "{index}");
        self.writer.write_field(&self.field)?;
        // Taken out for the call (its reference is shared storage, not Copy) and put back.
        let columns = std::mem::take(&mut self.columns);
        let written = self.write_values(columns.values(sample));
        self.columns = columns;
        written?;
        self.writer.write_record(None::<&[u8]>)?;
        Ok(())
    }

    fn finish(&mut self) -> Result<(), SinkError> {
        self.writer.flush()?;
        Ok(())
    }
}

/// A ROS 2 log's table ([`wmr_ros2::log::Ros2Log::table`]) as CSV: `t` and
/// [`wmr_ros2::log::LOG_COLUMNS`], a NaN written as an empty field (no message yet).
pub fn log_table_csv(table: &wmr_ros2::log::LogTable) -> String {
    let mut out = String::from("t");
    for c in wmr_ros2::log::LOG_COLUMNS {
        out.push(',');
        out.push_str(c);
    }
    out.push('\n');
    let mut field = String::new();
    for (row, t) in table.t.iter().enumerate() {
        format_f64(*t, &mut field);
        out.push_str(&field);
        for column in &table.columns {
            out.push(',');
            if !column[row].is_nan() {
                format_f64(column[row], &mut field);
                out.push_str(&field);
            }
        }
        out.push('\n');
    }
    out
}
