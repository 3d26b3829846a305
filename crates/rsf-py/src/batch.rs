//! The per-record work of `rsf batch` for Python's `fit_many`/`diagnose_many`: entries, one
//! record's row, the summary table — the same Rust code as the command, so the tables agree
//! byte for byte. Rows cross as JSON text (float round trip exact: serde_json's
//! `float_roundtrip`), which is what Dask ships between machines anyway.

use crate::value_error;
use pyo3::prelude::*;
use rsf_batch::{
    Entry, Job, RecordOptions, Row, folder_entries, read_manifest, read_manifest_allowing_outside, run_entry,
    summary_csv,
};

/// The records of a manifest (CSV) or a folder, as a JSON list of entries; records outside
/// the manifest's folder only with `allow_outside`.
#[pyfunction]
#[pyo3(signature = (path, allow_outside=false))]
pub fn batch_entries(path: &str, allow_outside: bool) -> PyResult<String> {
    let p = std::path::Path::new(path);
    let e = if p.is_dir() {
        folder_entries(p)
    } else if allow_outside {
        read_manifest_allowing_outside(p)
    } else {
        read_manifest(p)
    }
    .map_err(value_error)?;
    serde_json::to_string(&e).map_err(value_error)
}

/// Checks batch-wide options (JSON of the manifest's option columns); the error names the option.
#[pyfunction]
pub fn batch_check_options(defaults_json: &str) -> PyResult<()> {
    rsf_batch::register_law_files(defaults_json).map_err(value_error)?;
    let d: RecordOptions = serde_json::from_str(defaults_json).map_err(value_error)?;
    d.check().map_err(|(c, e)| value_error(format!("{c}: {e}")))
}

/// One record's summary row (JSON): `entry_json` one element of [`batch_entries`], the
/// batch-wide options, what to do. The GIL is released while the record is worked on.
#[pyfunction]
#[pyo3(signature = (entry_json, defaults_json, fit, diagnose, threads=1))]
pub fn batch_row(
    py: Python<'_>,
    entry_json: &str,
    defaults_json: &str,
    fit: bool,
    diagnose: bool,
    threads: usize,
) -> PyResult<String> {
    // a worker of another process knows only the built-in laws until it reads the law files
    rsf_batch::register_law_files(entry_json).map_err(value_error)?;
    rsf_batch::register_law_files(defaults_json).map_err(value_error)?;
    let e: Entry = serde_json::from_str(entry_json).map_err(value_error)?;
    let d: RecordOptions = serde_json::from_str(defaults_json).map_err(value_error)?;
    let row = py.detach(|| run_entry(&e, &d, Job { fit, diagnose }, threads).row);
    serde_json::to_string(&row).map_err(value_error)
}

/// The summary table (CSV text) of rows given as JSON, in their order.
#[pyfunction]
pub fn batch_summary(rows_json: Vec<String>) -> PyResult<String> {
    let rows: Vec<Row> =
        rows_json.iter().map(|r| serde_json::from_str(r)).collect::<Result<_, _>>().map_err(value_error)?;
    Ok(summary_csv(&rows))
}
