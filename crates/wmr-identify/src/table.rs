//! A log as a table of named, time-stamped columns: the seam every log format feeds.
//!
//! A CSV (a wmr run's, or any with a header of named columns) is read here; another
//! reader (a ROS 2 MCAP, issue 43) only has to build a [`Table`] with the same names
//! ([`crate::log::ColumnNames`]) and the fit takes it unchanged.

use std::io::Read;

use crate::error::IdentifyError;

/// Columns of f64 values of equal length, by name; row `i` of every column is one sample.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    names: Vec<String>,
    columns: Vec<Vec<f64>>,
}

impl Table {
    /// An empty table.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds (or replaces) column `name`. Every column must have the same number of rows
    /// as the first one added.
    pub fn push(&mut self, name: &str, values: Vec<f64>) -> Result<(), IdentifyError> {
        if let Some(first) = self.columns.first()
            && first.len() != values.len()
        {
            return Err(IdentifyError::Read {
                detail: format!("column `{name}` has {} rows, the others {}", values.len(), first.len()),
            });
        }
        match self.names.iter().position(|n| n == name) {
            Some(i) => self.columns[i] = values,
            None => {
                self.names.push(name.to_owned());
                self.columns.push(values);
            }
        }
        Ok(())
    }

    /// The column called `name`, if any.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.names.iter().position(|n| n == name).map(|i| self.columns[i].as_slice())
    }

    /// The column names, in order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }

    /// Reads a CSV with a header line of column names. A field that is not a number is
    /// refused naming its column and row; an empty field reads as NaN (refused later, with
    /// its time, if the fit needs that column).
    pub fn read_csv(reader: impl Read) -> Result<Self, IdentifyError> {
        let mut r = csv::ReaderBuilder::new().has_headers(true).trim(csv::Trim::All).from_reader(reader);
        let headers = r.headers().map_err(|e| IdentifyError::Read { detail: e.to_string() })?.clone();
        let mut columns: Vec<Vec<f64>> = vec![Vec::new(); headers.len()];
        for (i, record) in r.records().enumerate() {
            let record = record.map_err(|e| IdentifyError::Read { detail: e.to_string() })?;
            for (j, field) in record.iter().enumerate() {
                let v = if field.is_empty() {
                    f64::NAN
                } else {
                    field.parse::<f64>().map_err(|_| IdentifyError::Read {
                        detail: format!("column `{}` row {}: `{field}` is not a number", &headers[j], i + 1),
                    })?
                };
                columns[j].push(v);
            }
        }
        let mut t = Table::new();
        for (name, col) in headers.iter().zip(columns) {
            t.push(name, col)?;
        }
        Ok(t)
    }
}

/// The shortest text that reads back to `v` (a CSV field): plain decimals in the usual
/// range, exponent form (`3.4e-17`) for the very small and very large. wmr's CSV files
/// (`wmr-cli run`, `log2csv`, `excite`) all write their numbers so.
pub fn format_f64(v: f64, out: &mut String) {
    use std::fmt::Write as _;
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
