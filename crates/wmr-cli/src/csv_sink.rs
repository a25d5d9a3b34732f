//! CSV output (docs/scenario.md): one header line, one row per run and logged sample.

use std::fmt::Write as _;
use std::io::BufWriter;

use wmr_core::{AnyReference, Reference, Sample};
use wmr_scenario::{
    CONTACT_COLUMNS, CSV_COLUMNS, MEASURED_COLUMNS, ODOMETRY_COLUMNS, REFERENCE_COLUMNS, Sink, SinkError,
    contact_values, measured_values, odometry_values, reference_values, sample_values,
};

use crate::atomic::OutWriter;

/// Writes `run,t,x,...,dl` rows; every number reads back to the same f64.
pub struct CsvSink {
    writer: csv::Writer<BufWriter<OutWriter>>,
    field: String,
    /// Also write the measured pose (`x_meas, y_meas, theta_meas`): the run has a `[sensor]`.
    measured: bool,
    /// Also write the dead-reckoned pose (`x_odom, y_odom, theta_odom`): the run is on odometry.
    odometry: bool,
    /// Also write the wheels' contact (`slip_r, ..., n_l`): the wheels slip.
    contact: bool,
    /// Also write the reference at each sample's t (`x_ref, ..., omega_ref`): a tracking run.
    reference: Option<AnyReference<f64>>,
}

/// The shortest text that reads back to `v`: plain decimals in the usual range,
/// exponent form (`3.4e-17`) for the very small and very large.
pub fn format_f64(v: f64, out: &mut String) {
    out.clear();
    let a = v.abs();
    if v == 0.0 {
        out.push('0');
    } else if (1e-5..1e16).contains(&a) {
        let _ = write!(out, "{v}");
    } else {
        let _ = write!(out, "{v:e}");
    }
}

impl CsvSink {
    /// Writes the header to `out` (with `measured`, the measured pose's columns too) and
    /// flushes it, so an output that cannot be written at all (a full disk) fails before
    /// any run starts.
    /// With `odometry` (the controller's pose is dead reckoning, so `measured` is too),
    /// the odometry pose's columns follow the measured (fused) pose's. With `contact` (wheels that slip),
    /// the contact columns follow. For the runs of a
    /// tracking scenario (`reference`), the reference's columns come last.
    pub fn new(
        out: OutWriter,
        measured: bool,
        odometry: bool,
        contact: bool,
        reference: Option<AnyReference<f64>>,
    ) -> Result<Self, SinkError> {
        let mut writer =
            csv::WriterBuilder::new().buffer_capacity(1 << 16).from_writer(BufWriter::with_capacity(1 << 16, out));
        let extra: &[&str] = if measured { &MEASURED_COLUMNS } else { &[] };
        let odometry_columns: &[&str] = if odometry { &ODOMETRY_COLUMNS } else { &[] };
        let slip: &[&str] = if contact { &CONTACT_COLUMNS } else { &[] };
        let tracking: &[&str] = if reference.is_some() { &REFERENCE_COLUMNS } else { &[] };
        writer.write_record(CSV_COLUMNS.iter().chain(extra).chain(odometry_columns).chain(slip).chain(tracking))?;
        writer.flush()?;
        Ok(Self { writer, field: String::with_capacity(32), measured, odometry, contact, reference })
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
        self.write_values(sample_values(sample))?;
        if self.measured {
            self.write_values(measured_values(sample))?;
        }
        if self.odometry {
            self.write_values(odometry_values(sample))?;
        }
        if self.contact {
            self.write_values(contact_values(sample))?;
        }
        if let Some(values) = self.reference.as_ref().map(|r| reference_values(&r.state_at(sample.t))) {
            self.write_values(values)?;
        }
        self.writer.write_record(None::<&[u8]>)?;
        Ok(())
    }

    fn finish(&mut self) -> Result<(), SinkError> {
        self.writer.flush()?;
        Ok(())
    }
}
