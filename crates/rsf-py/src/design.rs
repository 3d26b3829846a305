//! `rsf.design`: the next experiment, as `rsf design` does.

use crate::fitting::{diagnose_options, interruptible, record};
use crate::value_error;
use numpy::PyReadonlyArray1;
use pyo3::prelude::*;
use rsf_design::{DesignOptions, design as run_design, design_from_json, protocol_toml};
use rsf_fit::segment::{SegmentOptions, detect};

/// Designs the next segment of a record (arrays) as `rsf design` does; returns the design's
/// JSON, the HTML page and the best proposal's TOML protocol (empty when there is none); from
/// `diagnosis` (the JSON of `rsf diagnose` / `rsf.diagnose` of the same record and options)
/// instead of diagnosing again when given.
#[pyfunction]
#[pyo3(signature = (time, load_point, mu, stiffness, baseline="slip", loading="protocol", v_range=(1e-3, 300.0),
    max_hold=1e4, max_time=14400.0, max_slip=1000.0, max_sigma_change=0.0, credible=rsf_design::CREDIBLE_DBIC,
    draws=rsf_design::DRAWS, sequences=true, seed=1, threads=0, name="record", diagnosis=None,
    accept_implausible=false))]
#[allow(clippy::too_many_arguments)]
pub fn design_json(
    py: Python<'_>,
    time: PyReadonlyArray1<f64>,
    load_point: PyReadonlyArray1<f64>,
    mu: PyReadonlyArray1<f64>,
    stiffness: f64,
    baseline: &str,
    loading: &str,
    v_range: (f64, f64),
    max_hold: f64,
    max_time: f64,
    max_slip: f64,
    max_sigma_change: f64,
    credible: f64,
    draws: usize,
    sequences: bool,
    seed: u64,
    threads: usize,
    name: &str,
    diagnosis: Option<String>,
    accept_implausible: bool,
) -> PyResult<(String, String, String)> {
    let rec = record(time, load_point, mu, None, accept_implausible)?;
    let (dopts, cancel) = diagnose_options(baseline, stiffness, loading, "auto", seed, threads)?;
    let o = DesignOptions {
        credible_dbic: credible,
        v_range,
        max_hold,
        max_time,
        max_slip,
        max_sigma_change,
        draws,
        sequences,
        seed,
        threads,
        progress: None,
    };
    let d = interruptible(py, &cancel, || {
        let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
        match &diagnosis {
            // its models refitted from their reported parameters, not diagnosed again
            Some(json) => design_from_json(&rec, &segs, json, &dopts, &o).map_err(|e| e.to_string()),
            None => run_design(&rec, &segs, &dopts, &o).map(|(_, d)| d).map_err(|e| e.to_string()),
        }
    })?
    .map_err(value_error)?;
    let html = rsf_report::design_html(&d, name);
    let toml = protocol_toml(&d, 1).unwrap_or_default();
    Ok((serde_json::to_string(&d).map_err(value_error)?, html, toml))
}
