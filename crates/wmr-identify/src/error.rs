//! What identification refuses, each error naming the column, the time or the parameter.

use std::fmt;

/// Why a log cannot be read or a parameter cannot be fitted from it.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum IdentifyError {
    /// The table has no column of this name (nor any of its accepted aliases).
    MissingColumn {
        /// The column (with its aliases, e.g. `t or t_s`).
        column: String,
    },
    /// A value is not a finite number.
    NotFinite {
        /// The column.
        column: String,
        /// The time of the row, s (NaN when the time itself is the bad value).
        t_s: f64,
        /// 1-based data row (the header is row 0).
        row: usize,
    },
    /// Time does not increase from one row to the next (within one run).
    NonMonotonicTime {
        /// The column of the time (`t`).
        column: String,
        /// The time that is not after the one before it, s.
        t_s: f64,
        /// The time before it, s.
        t_prev_s: f64,
        /// 1-based data row.
        row: usize,
    },
    /// A run has too few rows for the derivative filter.
    TooShort {
        /// The run index (`run` column, or 0).
        run: usize,
        /// Rows it has.
        rows: usize,
        /// Rows the filter needs.
        needed: usize,
    },
    /// Nothing in the log moves the wheels: every command or every wheel speed is zero.
    NoExcitation {
        /// The column that carries nothing (a command or a wheel speed).
        column: String,
        /// What was found.
        detail: String,
    },
    /// A parameter the log does not determine (its regressor is zero, or a combination
    /// of the others); hold it at a known value instead.
    NotIdentifiable {
        /// The parameter's key (`platform_inertia`), or several joined by `, `.
        parameter: String,
        /// Why, with the figures (e.g. the condition number).
        detail: String,
    },
    /// The fit gives a parameter below zero by more than 3 standard errors: the model does
    /// not describe the log (a wrong geometry, a drive other than the one named, slip).
    Unphysical {
        /// The parameter's key.
        parameter: String,
        /// The value the fit gave.
        value: f64,
        /// Its standard error.
        std_err: f64,
    },
    /// A setting of the fit is out of range.
    BadSetting {
        /// The setting's name.
        key: String,
        /// Why.
        detail: String,
    },
    /// The file could not be read or parsed as CSV.
    Read {
        /// What went wrong.
        detail: String,
    },
}

impl fmt::Display for IdentifyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IdentifyError::MissingColumn { column } => write!(f, "log: missing column `{column}`"),
            IdentifyError::NotFinite { column, t_s, row } => {
                write!(f, "log: column `{column}` at t = {t_s} s (row {row}): not a finite number")
            }
            IdentifyError::NonMonotonicTime { column, t_s, t_prev_s, row } => write!(
                f,
                "log: column `{column}` at t = {t_s} s (row {row}): time does not increase (the row before is at {t_prev_s} s)"
            ),
            IdentifyError::TooShort { run, rows, needed } => {
                write!(f, "log: run {run} has {rows} rows; the derivative filter needs at least {needed}")
            }
            IdentifyError::NoExcitation { column, detail } => {
                write!(f, "log: no excitation in column `{column}`: {detail}")
            }
            IdentifyError::NotIdentifiable { parameter, detail } => write!(
                f,
                "{parameter}: not identifiable from this log ({detail}); hold it at a known value (--hold {})",
                parameter.split(", ").next().unwrap_or(parameter)
            ),
            IdentifyError::Unphysical { parameter, value, std_err } => write!(
                f,
                "{parameter}: the fit gives {value:.4e} +- {std_err:.2e}, below zero: the model does not describe this log (check the geometry, --drive, and that the wheels do not slip)"
            ),
            IdentifyError::BadSetting { key, detail } => write!(f, "{key}: {detail}"),
            IdentifyError::Read { detail } => write!(f, "log: {detail}"),
        }
    }
}

impl std::error::Error for IdentifyError {}
