//! Protocol files (TOML) for `rsf simulate`.
//!
//! The parameter rules live in one place — [`Model::validate`](rsf_core::Model::validate), [`Segment::duration`](rsf_core::Segment::duration),
//! [`LoadRecord::validate`](rsf_core::LoadRecord::validate) — and this module maps their errors back to the file and line of
//! the offending field.
//!
//! ```
//! let text = r#"
//! [model]
//! mu0 = 0.65
//! v0 = 1.0
//! a = 0.013
//! stiffness = 0.065
//! [[model.state]]
//! law = "slip"
//! b = 0.016
//! dc = 2.07
//! [loading]
//! v_init = 3.0
//! [[loading.segment]]
//! v = 0.3
//! displacement = 10.0
//! [output]
//! dt = 1.0
//! "#;
//! let p = rsf_solvers::protocol::parse(text, None, "example.toml").unwrap();
//! let sol = p.method.solve(&p.problem).unwrap();
//! assert_eq!(sol.time.last(), Some(&(10.0 / 0.3)));
//! ```

mod build;
mod raw;

use crate::Method;
use crate::solve::Problem;
use build::build;
use raw::{InMemory, RawFile, WithSpans};
use std::ops::Range;
use std::path::{Path, PathBuf};

pub use crate::record::{ReadRecord, RecordColumns, read_load_record};

/// A parsed protocol: the problem and the chosen method.
#[derive(Clone, Debug)]
pub struct Protocol {
    /// The forward problem.
    pub problem: Problem,
    /// The integrator selected in `[solver]`.
    pub method: Method,
    /// Measured friction at the record's times, when `[loading] friction_column` names one
    /// (for plots and misfit summaries; the forward model does not use it).
    pub measured_friction: Option<Vec<f64>>,
    /// The measured record `[loading] record` reads, resolved against the protocol's folder
    /// (an input that no output may overwrite).
    pub record: Option<PathBuf>,
}

/// A protocol error, naming file, line and field where known.
#[derive(Debug, Clone, PartialEq)]
pub struct ProtocolError {
    /// File name as given.
    pub file: String,
    /// 1-based line, if known.
    pub line: Option<usize>,
    /// The field, e.g. `model.state[2].dc`.
    pub field: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for ProtocolError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        write!(f, ": ")?;
        if let Some(field) = &self.field {
            write!(f, "`{field}`: ")?;
        }
        write!(f, "{}", self.message)
    }
}
impl std::error::Error for ProtocolError {}

/// Default solver settings.
pub const DEFAULT_METHOD: &str = "auto";
/// Default relative tolerance.
pub const DEFAULT_RTOL: f64 = 1e-9;
/// Default absolute tolerance (µm of slip).
pub const DEFAULT_ATOL: f64 = 1e-12;

/// Reads and parses a protocol file; a `record` path is relative to the file.
pub fn load(path: &Path) -> Result<Protocol, ProtocolError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| ProtocolError {
        file: name.clone(),
        line: None,
        field: None,
        message: format!("cannot read: {e}"),
    })?;
    parse(&text, path.parent(), &name)
}

/// Parses protocol text. `base` resolves a relative `record` path; `file` names the source
/// in messages.
pub fn parse(text: &str, base: Option<&Path>, file: &str) -> Result<Protocol, ProtocolError> {
    let line_of = |span: &Range<usize>| text[..span.start.min(text.len())].matches('\n').count() + 1;
    let raw: RawFile<WithSpans> = toml::from_str(text).map_err(|e| ProtocolError {
        file: file.to_string(),
        line: e.span().as_ref().map(line_of),
        field: None,
        message: e.message().to_string(),
    })?;
    build(raw, base, file, &line_of)
}

/// Builds a protocol from a table of the protocol file's shape built in memory (what the
/// Python objects hold): checked by the same rules as [`parse`], errors naming the field
/// (`model.state[1].dc`), with no line. `name` names the source in messages.
pub fn from_table(table: toml::Table, base: Option<&Path>, name: &str) -> Result<Protocol, ProtocolError> {
    let raw: RawFile<InMemory> = table.try_into().map_err(|e: toml::de::Error| ProtocolError {
        file: name.to_string(),
        line: None,
        field: None,
        message: e.message().to_string(),
    })?;
    build(raw, base, name, &|_| 0)
}
