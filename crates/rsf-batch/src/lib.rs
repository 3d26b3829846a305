//! A lab's archive: a manifest of records, each fitted and/or diagnosed, one summary row each.
//!
//! The per-record work ([`run_entry`]) and the summary table ([`summary_csv`]) live here, in
//! one place, so that `rsf batch` on one machine and Python's `fit_many`/`diagnose_many` on a
//! Dask cluster give the same table, byte for byte. What is machine-specific (files written
//! safely, resumption, the progress bar, the summary figure) stays in the command.
//!
//! | file | what |
//! |---|---|
//! | `manifest.rs` | the manifest (CSV with `file`, `stiffness` and per-record options) or a folder |
//! | `work.rs` | one record: read, segment, fit and/or diagnose, never a panic out |
//! | `row.rs` | the summary row of a record and the summary table |

mod manifest;
mod place;
mod row;
mod work;

pub use manifest::{
    Column, Entry, RecordOptions, folder_entries, read_manifest, read_manifest_allowing_outside, register_law_files,
};
pub use row::{Cell, CellKind, Param, Row, Status, SummaryTable, spreadsheet_safe, summary_csv, summary_table};
pub use work::{FIT_STARTS, Job, Outcome, run_entry};
