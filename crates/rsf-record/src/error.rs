//! The reader's one error type, and the short forms of numbers and cells that its messages use.

use std::fmt;

/// What went wrong reading a record, with the file, the 1-based line and the column name where
/// they are known. Displayed as `FILE:LINE: column `NAME`: what is wrong`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}{}: {}{kind}", line.map(|l| format!(":{l}")).unwrap_or_default(), column.as_ref().map(|c| format!("column `{c}`: ")).unwrap_or_default())]
pub struct ReadError {
    /// The file (as the user named it).
    pub file: String,
    /// 1-based line, counting every line of the file (`\n`, `\r\n` and lone `\r` end a line).
    pub line: Option<u64>,
    /// Column name, as the header spells it.
    pub column: Option<String>,
    /// What is wrong.
    pub kind: ReadErrorKind,
}

/// The closed set of reasons a record is refused.
#[derive(Debug, Clone, PartialEq)]
pub enum ReadErrorKind {
    /// The operating system refused to open or read the file.
    Io(String),
    /// A NUL byte outside UTF-16 text: a binary file, not a text record.
    Binary,
    /// A line longer than [`crate::MAX_LINE_BYTES`] (a file without line breaks).
    LineTooLong,
    /// No line among the first [`crate::HEADER_SCAN_LINES`] names the key column.
    NoHeader {
        /// The column the header must name.
        key: String,
        /// The first non-blank line, shortened.
        first_line: Option<String>,
        /// The encoding the text was read in.
        encoding: crate::TextEncoding,
    },
    /// The header does not name a column that was asked for.
    NoColumn {
        /// The header's names.
        header: Vec<String>,
    },
    /// A row with another number of fields than the header (and the rows before it).
    Ragged {
        /// Fields of the header (and of the rows before).
        expected: usize,
        /// Fields of this row.
        found: usize,
    },
    /// A cell that does not read as a number.
    NotANumber {
        /// The cell, shortened to [`MAX_CELL_CHARS`] characters.
        cell: String,
    },
    /// NaN or ±infinity.
    NotFinite {
        /// The value.
        value: f64,
    },
    /// A value at or beyond what the column can hold (|v| ≥ [`crate::OVER_RANGE`], or the
    /// column's own bound such as |μ| ≤ [`crate::MAX_ABS_FRICTION`]).
    OverRange {
        /// The value.
        value: f64,
        /// The bound on |v|.
        limit: f64,
    },
    /// A value that instruments write for "no reading" ([`crate::SENTINELS`]).
    Sentinel {
        /// The value.
        value: f64,
    },
    /// A value of a column that must be positive (normal stress).
    NotPositive {
        /// The value.
        value: f64,
    },
    /// A time that does not increase.
    NotIncreasing {
        /// This row's value.
        value: f64,
        /// The previous row's.
        previous: f64,
    },
    /// A time equal to the previous row's (refused unless duplicates are dropped).
    Repeated {
        /// The value.
        value: f64,
    },
    /// Fewer data rows than a record needs.
    TooFewRows {
        /// Rows read.
        rows: usize,
        /// Rows needed.
        min: usize,
        /// The first line after the header that was not a data row, with its column and cell.
        first_skipped: Option<(u64, String, String)>,
    },
    /// A reason given by the caller's row check.
    Invalid(String),
}

/// Cells in messages are cut to this many characters (an 8 MB cell is not echoed).
pub const MAX_CELL_CHARS: usize = 40;

impl fmt::Display for ReadErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(m) => write!(f, "cannot read: {m}"),
            Self::Binary => write!(f, "a NUL byte: this is binary data, not a text record"),
            Self::LineTooLong => write!(
                f,
                "a line longer than {} MiB: not a record with one row a line (no line breaks?)",
                crate::MAX_LINE_BYTES >> 20
            ),
            Self::NoHeader { key, first_line, encoding } => write!(
                f,
                "no header line names the column `{key}` in the first {} lines (read as {}; first line: {})",
                crate::HEADER_SCAN_LINES,
                encoding.name(),
                first_line.as_deref().unwrap_or("none")
            ),
            Self::NoColumn { header } => write!(f, "no such column in the header ({})", header.join(",")),
            Self::Ragged { expected, found } => write!(
                f,
                "{found} fields where the header and the rows before have {expected} (a ragged row: a missing or extra delimiter?)"
            ),
            Self::NotANumber { cell } => write!(f, "`{cell}` is not a number"),
            Self::NotFinite { value } => write!(f, "{value} is not finite"),
            Self::OverRange { value, limit } => write!(
                f,
                "{} is out of range (|value| must be below {}): an over-range reading? (--drop-invalid drops such rows and counts them)",
                short_num(*value),
                short_num(*limit)
            ),
            Self::Sentinel { value } => write!(
                f,
                "{} is an instrument's no-reading value (--drop-invalid drops such rows and counts them)",
                short_num(*value)
            ),
            Self::NotPositive { value } => write!(f, "{} must be positive", short_num(*value)),
            Self::NotIncreasing { value, previous } => {
                write!(f, "time {} does not increase (previous {})", short_num(*value), short_num(*previous))
            }
            Self::Repeated { value } => write!(
                f,
                "time {} repeats the previous row's (use the option to drop duplicated times, \
                 `--duplicate-times drop`, if the logger writes two rows per tick)",
                short_num(*value)
            ),
            Self::TooFewRows { rows, min, first_skipped } => {
                write!(f, "{rows} data rows; at least {min} are needed")?;
                if let Some((line, col, cell)) = first_skipped {
                    write!(f, " (line {line}, the first after the header, has `{cell}` in column `{col}`)")?;
                }
                Ok(())
            }
            Self::Invalid(m) => f.write_str(m),
        }
    }
}

/// A number as a person reads it in a message: decimal for magnitudes from 1e-4 to 1e15,
/// otherwise with an exponent (`1e-300`, not three hundred zeros).
pub fn short_num(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e15).contains(&v.abs()) { format!("{v}") } else { format!("{v:e}") }
}

/// A cell cut to [`MAX_CELL_CHARS`] characters, saying how long it was.
pub fn short_cell(cell: &str) -> String {
    let n = cell.chars().count();
    if n <= MAX_CELL_CHARS {
        cell.to_string()
    } else {
        let head: String = cell.chars().take(MAX_CELL_CHARS).collect();
        format!("{head}… ({n} characters)")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_cells_are_short() {
        assert_eq!(short_num(1e-300), "1e-300");
        assert_eq!(short_num(9.9e37), "9.9e37");
        assert_eq!(short_num(0.61), "0.61");
        assert_eq!(short_num(-999999.0), "-999999");
        assert_eq!(short_num(0.0), "0");
        let long = "x".repeat(8_000_000);
        let s = short_cell(&long);
        assert!(s.len() < 80 && s.contains("8000000 characters"), "{s}");
        assert_eq!(short_cell("0.6"), "0.6");
    }
}
