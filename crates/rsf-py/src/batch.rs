//! The per-record work of `rsf batch` for Python's `fit_many`/`diagnose_many`: entries, one
//! record's row, the summary table — the same Rust code as the command, so the tables agree
//! byte for byte. Rows cross as JSON text (float round trip exact: serde_json's
//! `float_roundtrip`), which is what Dask ships between machines anyway.

use crate::value_error;
use pyo3::prelude::*;
use pyo3::types::PyList;
use rsf_batch::{
    Cell, CellKind, Entry, Job, RecordOptions, Row, Status, folder_entries, read_manifest,
    read_manifest_allowing_outside, run_entry, summary_csv, summary_table,
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

/// The row of a record whose task never returned one (its Dask worker was killed, or the task
/// raised): `crashed`, with `error` and the entry's meta cells, so that the other records'
/// rows are kept.
#[pyfunction]
pub fn batch_crashed_row(entry_json: &str, error: &str) -> PyResult<String> {
    let e: Entry = serde_json::from_str(entry_json).map_err(value_error)?;
    let mut row = Row::failed(&e.name, Status::Crashed, error.to_string());
    row.meta = e.meta;
    serde_json::to_string(&row).map_err(value_error)
}

/// The summary table of rows given as JSON, typed as `rsf batch` types it (the cells before
/// the CSV's spreadsheet-safe quoting): the header, each column's kind (`text`, `number`,
/// `count`) and each column's values (str; float, NaN for none; int or None).
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn batch_table(
    py: Python<'_>,
    rows_json: Vec<String>,
) -> PyResult<(Vec<String>, Vec<&'static str>, Vec<Py<PyAny>>)> {
    let rows: Vec<Row> =
        rows_json.iter().map(|r| serde_json::from_str(r)).collect::<Result<_, _>>().map_err(value_error)?;
    let t = summary_table(&rows);
    let mut columns = Vec::with_capacity(t.header.len());
    let mut kinds = Vec::with_capacity(t.header.len());
    for (j, kind) in t.kinds.iter().enumerate() {
        let cells = t.rows.iter().map(|r| &r[j]);
        let list = match kind {
            CellKind::Text => {
                kinds.push("text");
                PyList::new(py, cells.map(|c| c.text()))?
            }
            CellKind::Number => {
                kinds.push("number");
                PyList::new(
                    py,
                    cells.map(|c| match c {
                        Cell::Number(x) => x.unwrap_or(f64::NAN),
                        Cell::Text(_) | Cell::Count(_) => f64::NAN,
                    }),
                )?
            }
            CellKind::Count => {
                kinds.push("count");
                PyList::new(
                    py,
                    cells.map(|c| match c {
                        Cell::Count(n) => *n,
                        Cell::Text(_) | Cell::Number(_) => None,
                    }),
                )?
            }
        };
        columns.push(list.into_any().unbind());
    }
    Ok((t.header, kinds, columns))
}

/// The summary table (CSV text) of rows given as JSON, in their order.
#[pyfunction]
pub fn batch_summary(rows_json: Vec<String>) -> PyResult<String> {
    let rows: Vec<Row> =
        rows_json.iter().map(|r| serde_json::from_str(r)).collect::<Result<_, _>>().map_err(value_error)?;
    Ok(summary_csv(&rows))
}
