//! # rsf-record — the one reader of measured lab records
//!
//! Every record rsf reads — `rsf fit`, `rsf segments`, `rsf diagnose`, the measured load-point
//! histories of `rsf simulate` protocols, the Python package and the tests — goes through
//! [`read_path`] / [`read_text`]. Delimited text with a header naming the columns, in the forms
//! lab software writes:
//!
//! * comma, tab, semicolon (with a decimal comma) or runs of spaces between fields; quoted
//!   cells; space-padded cells;
//! * an instrument preamble before the header (lines that do not name the key column), unit
//!   or count rows between the header and the first data row, `#` comment lines, blank lines;
//! * UTF-8 with or without a byte-order mark, UTF-16 (with or without one), a Windows-1252 /
//!   Latin-1 header (`Displ(µm)` written by older Windows software); `\n`, `\r\n` or the old
//!   Mac's lone `\r` at line ends;
//! * a leading row index that the header does not name (xlook exports), or a delimiter ending
//!   every line.
//!
//! What it refuses, naming file, line and column ([`ReadError`]): binary data, a line of more
//! than [`MAX_LINE_BYTES`] (memory stays bounded on a file without line breaks), a ragged row,
//! a cell that is not a number, NaN or infinity, a value at or beyond [`OVER_RANGE`] or a
//! column's own bound, an instrument's no-reading value ([`SENTINELS`]), a time that does not
//! increase. Over-range, sentinel and non-finite values may instead be dropped and counted
//! ([`InvalidRows::Drop`]). A last line without a line end that is shorter than the rows
//! before it (a file cut while it was copied or written) is dropped with a warning, never
//! used.
//!
//! Why the `csv` crate: it splits quoted fields exactly as spreadsheets write them and reuses
//! one buffer per row; the encoding is `encoding_rs`'s. What is this crate's own: finding the
//! header in a preamble, the lab conventions above, and the checks.
#![forbid(unsafe_code)]

mod error;
mod rows;
mod text;

pub use error::{MAX_CELL_CHARS, ReadError, ReadErrorKind, short_cell, short_num};
pub use text::TextEncoding;

use std::path::Path;

/// Longest line read, bytes. Lab records have lines of tens to hundreds of bytes; a longer
/// "line" is a file without line breaks (or `/dev/zero`), which is refused before it fills
/// memory.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// Lines searched for the header (instrument preambles run to a few dozen lines).
pub const HEADER_SCAN_LINES: usize = 200;

/// Fewest data rows a record may have: every consumer (fit, segmentation, Python) uses this one
/// number.
pub const MIN_ROWS: usize = 10;

/// Values this large are no measurement in any unit a lab records in (s, µm, MPa, friction),
/// but what an instrument writes when out of range (9.9e37) or what a broken export leaves.
pub const OVER_RANGE: f64 = 1e30;

/// Friction beyond this is not friction: a column mix-up or an over-range reading.
pub const MAX_ABS_FRICTION: f64 = 10.0;

/// Values loggers write for "no reading": IEEE-style over-range markers (9.9e37 and larger are
/// caught by [`OVER_RANGE`]) and the integer fill values of acquisition software.
pub const SENTINELS: [f64; 2] = [-999_999.0, -99_999.0];

/// One column to read.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    /// Its name in the header.
    pub name: String,
    /// Bound on |value| (a value at or beyond it is over range); [`OVER_RANGE`] by default.
    pub max_abs: f64,
    /// Whether the value must be positive (normal stress).
    pub positive: bool,
}

impl Column {
    /// A column with the default bound.
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), max_abs: OVER_RANGE, positive: false }
    }
    /// A friction column (|μ| < [`MAX_ABS_FRICTION`]).
    pub fn friction(name: impl Into<String>) -> Self {
        Self { max_abs: MAX_ABS_FRICTION, ..Self::new(name) }
    }
    /// A column whose values must be positive.
    pub fn positive(name: impl Into<String>) -> Self {
        Self { positive: true, ..Self::new(name) }
    }
}

/// Which columns to read.
#[derive(Clone, Debug, PartialEq)]
pub enum Columns {
    /// These, in this order (each must be in the header).
    Named(Vec<Column>),
    /// Every column of the header, in its order.
    All,
}

/// Rows with a value that is over range, a sentinel, not finite or not positive where it
/// must be.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InvalidRows {
    /// Refuse the record, naming line and column (the default).
    #[default]
    Error,
    /// Drop such rows and count them ([`Summary::dropped_invalid`]).
    Drop,
    /// Keep every value that reads as a number, NaN included: for tables of computed results
    /// (a reference solution that stopped), never for lab records.
    Keep,
}

/// Rows whose time equals the previous row's (loggers that write two rows per clock tick).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DuplicateTimes {
    /// Refuse the record, naming the line (the default: a repeated time may mean a broken clock).
    #[default]
    Error,
    /// Keep the first row of each run of equal times, drop the others and count them.
    Drop,
}

impl DuplicateTimes {
    /// The names, in options: `error`, `drop` (this crate stands below rsf-core's
    /// `vocabulary!`, so they are written out here).
    pub const NAMES: &'static [&'static str] = &["error", "drop"];
    /// The name.
    pub fn name(self) -> &'static str {
        match self {
            DuplicateTimes::Error => "error",
            DuplicateTimes::Drop => "drop",
        }
    }
}

impl std::str::FromStr for DuplicateTimes {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "error" => Ok(DuplicateTimes::Error),
            "drop" => Ok(DuplicateTimes::Drop),
            other => Err(format!("unknown duplicate-times handling `{other}`: use error or drop")),
        }
    }
}

/// What to read.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// A column name that identifies the header line (lines before it are a preamble).
    pub header_key: String,
    /// The columns.
    pub columns: Columns,
    /// Index (into the columns read) of the column that must strictly increase (time).
    pub increasing: Option<usize>,
    /// Equal consecutive values of the increasing column.
    pub duplicates: DuplicateTimes,
    /// Over-range, sentinel and non-finite values.
    pub invalid: InvalidRows,
    /// Fewest data rows accepted ([`MIN_ROWS`] for a record).
    pub min_rows: usize,
    /// Keep only rows whose increasing column, times `window_scale`, lies in this range
    /// (either end open); the other columns of rows outside it are not checked (a record's
    /// set-up before the part asked for may hold zeros or sentinels).
    pub window: (Option<f64>, Option<f64>),
    /// Factor from the increasing column's unit to the window's (e.g. 1e-3 for ms and a window
    /// in s).
    pub window_scale: f64,
}

impl Spec {
    /// The named columns, the first identifying the header and strictly increasing (time).
    pub fn timed(columns: Vec<Column>) -> Self {
        Self {
            header_key: columns[0].name.clone(),
            columns: Columns::Named(columns),
            increasing: Some(0),
            duplicates: DuplicateTimes::Error,
            invalid: InvalidRows::Error,
            min_rows: MIN_ROWS,
            window: (None, None),
            window_scale: 1.0,
        }
    }
    /// Every column of a table of computed results whose header names `key` (NaN kept).
    pub fn all(key: impl Into<String>) -> Self {
        Self {
            header_key: key.into(),
            columns: Columns::All,
            increasing: None,
            duplicates: DuplicateTimes::Error,
            invalid: InvalidRows::Keep,
            min_rows: 1,
            window: (None, None),
            window_scale: 1.0,
        }
    }
}

/// A caller's reason to refuse a row (from the row visitor).
#[derive(Clone, Debug, PartialEq)]
pub struct RowError {
    /// Index of the column at fault, into the columns read.
    pub column: Option<usize>,
    /// What is wrong.
    pub message: String,
}

/// What a read found besides the rows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    /// The names of the columns read, as the header spells them.
    pub names: Vec<String>,
    /// The header's line.
    pub header_line: u64,
    /// The text encoding.
    pub encoding: Option<TextEncoding>,
    /// Data rows passed to the visitor.
    pub rows: usize,
    /// Rows dropped for an invalid value ([`InvalidRows::Drop`]).
    pub dropped_invalid: usize,
    /// Rows dropped because their time repeated the previous row's ([`DuplicateTimes::Drop`]).
    pub dropped_duplicates: usize,
    /// Things the user should know (a dropped cut last line, a Windows-1252 header, the first
    /// lines of dropped rows).
    pub warnings: Vec<String>,
}

/// Reads the file at `path`, passing each data row (its line and the values of the columns
/// asked for, in that order) to `visit`.
pub fn read_path(
    path: &Path,
    spec: &Spec,
    visit: impl FnMut(u64, &[f64]) -> Result<(), RowError>,
) -> Result<Summary, ReadError> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|e| ReadError {
        file: name.clone(),
        line: None,
        column: None,
        kind: ReadErrorKind::Io(e.to_string()),
    })?;
    rows::read(file, &name, spec, visit)
}

/// Reads a record held in memory; `file` names it in errors.
pub fn read_text(
    text: &str,
    file: &str,
    spec: &Spec,
    visit: impl FnMut(u64, &[f64]) -> Result<(), RowError>,
) -> Result<Summary, ReadError> {
    rows::read(text.as_bytes(), file, spec, visit)
}

/// Reads bytes from any source (a pipe, a network stream, a decompressor).
pub fn read_from(
    source: impl std::io::Read,
    file: &str,
    spec: &Spec,
    visit: impl FnMut(u64, &[f64]) -> Result<(), RowError>,
) -> Result<Summary, ReadError> {
    rows::read(source, file, spec, visit)
}

/// A whole numeric table: every column, as columns.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Column names.
    pub names: Vec<String>,
    /// Columns, in the header's order.
    pub columns: Vec<Vec<f64>>,
}

impl Table {
    /// The column named `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.names.iter().position(|n| n == name).map(|i| self.columns[i].as_slice())
    }
}

/// Every column of the numeric table at `path` whose header names `key`.
pub fn read_table(path: &Path, key: &str) -> Result<Table, ReadError> {
    let mut columns: Vec<Vec<f64>> = vec![];
    let summary = read_path(path, &Spec::all(key), |_, v| {
        if columns.is_empty() {
            columns = vec![vec![]; v.len()];
        }
        for (c, x) in columns.iter_mut().zip(v) {
            c.push(*x);
        }
        Ok(())
    })?;
    if columns.is_empty() {
        columns = vec![vec![]; summary.names.len()];
    }
    Ok(Table { names: summary.names, columns })
}

#[cfg(test)]
mod tests;
