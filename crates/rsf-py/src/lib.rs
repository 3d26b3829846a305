//! The compiled part of the Python package `rsf` (`rsf._rsf`): thin functions over the Rust
//! crates, numpy arrays in and out, results of fits and diagnoses as the CLI's JSON (the
//! Python layer in `python/rsf/__init__.py` turns them into dicts). Solves, fits and
//! diagnoses run with the GIL released; every error becomes a `ValueError` with the Rust
//! message.

use numpy::{PyArray1, PyArray2, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rsf_fit::data::{ReadOptions, Record, read_record};
use rsf_fit::diagnose::{DiagnoseOptions, diagnose as run_diagnose};
use rsf_fit::fit::{FitOptions, LoadingMode, fit as run_fit, prepare};
use rsf_fit::segment::{SegmentOptions, detect};
use std::path::Path;

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A solution as a dict of numpy arrays (θ as rows × states).
fn solution_dict<'py>(py: Python<'py>, sol: rsf_solvers::Solution) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let rows = sol.len();
    let n = sol.theta.len();
    let mut theta = vec![vec![0.0; n]; rows];
    for (k, col) in sol.theta.iter().enumerate() {
        for (r, v) in col.iter().enumerate() {
            theta[r][k] = *v;
        }
    }
    d.set_item("time_s", PyArray1::from_vec(py, sol.time))?;
    d.set_item("load_point_um", PyArray1::from_vec(py, sol.load_point))?;
    d.set_item("mu", PyArray1::from_vec(py, sol.mu))?;
    d.set_item("slip_rate_um_s", PyArray1::from_vec(py, sol.slip_rate))?;
    d.set_item("slip_um", PyArray1::from_vec(py, sol.slip))?;
    d.set_item("theta_s", PyArray2::from_vec2(py, &theta).map_err(value_error)?)?;
    if !sol.peak_slip_rate.is_empty() {
        d.set_item("peak_slip_rate_um_s", PyArray1::from_vec(py, sol.peak_slip_rate))?;
    }
    if !sol.normal_stress.is_empty() {
        d.set_item("normal_stress_mpa", PyArray1::from_vec(py, sol.normal_stress))?;
    }
    d.set_item("method", sol.method)?;
    d.set_item("steps", sol.stats.accepted)?;
    Ok(d)
}

/// Solves a protocol given as TOML text (the format of `rsf simulate`); `base_dir` resolves a
/// measured record's path. With `time` (s) and `load_point` (µm) arrays the load point follows
/// them instead of the protocol's loading (piecewise linear, as a record file), with output at
/// those times. Returns the solution's columns as numpy arrays.
#[pyfunction]
#[pyo3(signature = (toml_text, base_dir=None, name="protocol.toml", time=None, load_point=None))]
fn simulate_toml<'py>(
    py: Python<'py>,
    toml_text: &str,
    base_dir: Option<&str>,
    name: &str,
    time: Option<PyReadonlyArray1<f64>>,
    load_point: Option<PyReadonlyArray1<f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut p = rsf_solvers::protocol::parse(toml_text, base_dir.map(Path::new), name).map_err(value_error)?;
    match (time, load_point) {
        (None, None) => {}
        (Some(t), Some(x)) => {
            let rec = rsf_core::LoadRecord { time: t.as_slice()?.to_vec(), load_point: x.as_slice()?.to_vec() };
            rec.validate().map_err(|e| value_error(format!("load-point arrays: {e}")))?;
            p.problem.output = rsf_solvers::OutputTimes::Times(rec.time.clone());
            p.problem.loading = rsf_core::Loading::Record(rec);
        }
        _ => return Err(value_error("give both time and load_point, or neither")),
    }
    let sol = py.detach(|| p.method.solve(&p.problem)).map_err(value_error)?;
    solution_dict(py, sol)
}

/// Reads a lab record with the CLI's column options; returns `time_s`, `load_point_um`, `mu`
/// (and `normal_stress_mpa` with `normal_col`).
#[pyfunction]
#[pyo3(signature = (path, time_col="time_s", lp_col="load_point_um", mu_col="mu", normal_col=None))]
fn read_record_columns<'py>(
    py: Python<'py>,
    path: &str,
    time_col: &str,
    lp_col: &str,
    mu_col: &str,
    normal_col: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = ReadOptions {
        time_col: time_col.into(),
        lp_col: lp_col.into(),
        mu_col: mu_col.into(),
        normal_col: normal_col.map(str::to_string),
        ..ReadOptions::default()
    };
    let rec = read_record(Path::new(path), &opts).map_err(value_error)?;
    let d = PyDict::new(py);
    d.set_item("time_s", PyArray1::from_vec(py, rec.time))?;
    d.set_item("load_point_um", PyArray1::from_vec(py, rec.load_point))?;
    d.set_item("mu", PyArray1::from_vec(py, rec.mu))?;
    if normal_col.is_some() {
        d.set_item("normal_stress_mpa", PyArray1::from_vec(py, rec.normal_stress))?;
    }
    Ok(d)
}

/// A record from three arrays (and optionally the normal stress, MPa), checked as the CSV
/// reader checks a file.
fn record(
    time: PyReadonlyArray1<f64>,
    lp: PyReadonlyArray1<f64>,
    mu: PyReadonlyArray1<f64>,
    normal_stress: Option<PyReadonlyArray1<f64>>,
) -> PyResult<Record> {
    let sn = match normal_stress {
        Some(a) => a.as_slice()?.to_vec(),
        None => vec![],
    };
    if !sn.is_empty() && sn.len() != time.len()? {
        return Err(value_error(format!("normal_stress has {} values for {} times", sn.len(), time.len()?)));
    }
    if let Some(i) = sn.iter().position(|x| !(*x > 0.0 && x.is_finite())) {
        return Err(value_error(format!("normal_stress[{i}] = {} must be positive and finite (MPa)", sn[i])));
    }
    let (time, lp, mu) = (time.as_slice()?.to_vec(), lp.as_slice()?.to_vec(), mu.as_slice()?.to_vec());
    if time.len() != lp.len() || time.len() != mu.len() {
        return Err(value_error(format!(
            "time, load_point and mu differ in length ({}, {}, {})",
            time.len(),
            lp.len(),
            mu.len()
        )));
    }
    if time.len() < 10 {
        return Err(value_error(format!("a record needs at least 10 samples (got {})", time.len())));
    }
    for (name, col) in [("time", &time), ("load_point", &lp), ("mu", &mu)] {
        if let Some(i) = col.iter().position(|x| !x.is_finite()) {
            return Err(value_error(format!("{name}[{i}] is not finite ({})", col[i])));
        }
    }
    if let Some(i) = time.windows(2).position(|w| !(w[1] > w[0])) {
        return Err(value_error(format!(
            "time must increase strictly: time[{}] = {} after time[{i}] = {}",
            i + 1,
            time[i + 1],
            time[i]
        )));
    }
    Ok(Record { time, load_point: lp, mu, normal_stress: sn, source: "numpy arrays".into(), ..Default::default() })
}

fn normal_stress_mode(mode: &str) -> PyResult<rsf_fit::fit::NormalStressMode> {
    use rsf_fit::fit::NormalStressMode as M;
    Ok(match mode {
        "auto" => M::Auto,
        "record" => M::Record,
        "constant" => M::Constant,
        other => return Err(value_error(format!("normal_stress_mode `{other}`: use auto, record or constant"))),
    })
}

fn fit_options(law: &str, stiffness: f64, loading: &str, fit_stiffness: bool) -> PyResult<FitOptions> {
    if !(stiffness > 0.0 && stiffness.is_finite()) {
        return Err(value_error(format!("stiffness {stiffness} must be positive and finite (1/µm)")));
    }
    let law = rsf_laws::law_by_name(law, |p| Some(if p == "vc" { 0.01 } else { 1.0 })).map_err(value_error)?;
    let mut o = FitOptions::new(vec![law], stiffness);
    o.loading = match loading {
        "protocol" => LoadingMode::Protocol,
        "record" => LoadingMode::Record,
        other => return Err(value_error(format!("loading `{other}`: use protocol or record"))),
    };
    o.fit_stiffness = fit_stiffness;
    Ok(o)
}

/// Fits a one-state law to a record (arrays); returns the CLI's fit JSON.
#[pyfunction]
#[pyo3(signature = (time, load_point, mu, stiffness, law="slip", loading="protocol", fit_stiffness=false,
    normal_stress=None, normal_stress_mode="auto", fit_alpha=None))]
#[allow(clippy::too_many_arguments)]
fn fit_json(
    py: Python<'_>,
    time: PyReadonlyArray1<f64>,
    load_point: PyReadonlyArray1<f64>,
    mu: PyReadonlyArray1<f64>,
    stiffness: f64,
    law: &str,
    loading: &str,
    fit_stiffness: bool,
    normal_stress: Option<PyReadonlyArray1<f64>>,
    normal_stress_mode: &str,
    fit_alpha: Option<&str>,
) -> PyResult<String> {
    let rec = record(time, load_point, mu, normal_stress)?;
    let mut opts = fit_options(law, stiffness, loading, fit_stiffness)?;
    opts.normal_stress = self::normal_stress_mode(normal_stress_mode)?;
    opts.alpha = match fit_alpha {
        None => rsf_fit::fit::AlphaFit::Fixed,
        Some("shared") => rsf_fit::fit::AlphaFit::Shared,
        Some("per-state") => rsf_fit::fit::AlphaFit::PerState,
        Some(other) => return Err(value_error(format!("fit_alpha `{other}`: use shared or per-state"))),
    };
    let res = py
        .detach(|| {
            let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
            let prep = prepare(&rec, &segs, &opts).map_err(|e| e.to_string())?;
            run_fit(&prep, &opts).map_err(|e| e.to_string())
        })
        .map_err(value_error)?;
    serde_json::to_string(&res).map_err(value_error)
}

/// Diagnoses a record (arrays) as `rsf diagnose` does; returns the CLI's diagnosis JSON.
#[pyfunction]
#[pyo3(signature = (time, load_point, mu, stiffness, baseline="slip", loading="protocol", seed=1, threads=0,
    normal_stress=None, normal_stress_mode="auto"))]
#[allow(clippy::too_many_arguments)]
fn diagnose_json(
    py: Python<'_>,
    time: PyReadonlyArray1<f64>,
    load_point: PyReadonlyArray1<f64>,
    mu: PyReadonlyArray1<f64>,
    stiffness: f64,
    baseline: &str,
    loading: &str,
    seed: u64,
    threads: usize,
    normal_stress: Option<PyReadonlyArray1<f64>>,
    normal_stress_mode: &str,
) -> PyResult<String> {
    if baseline != "slip" && baseline != "aging" {
        return Err(value_error(format!("baseline `{baseline}`: use slip or aging")));
    }
    let rec = record(time, load_point, mu, normal_stress)?;
    let mut fo = fit_options(baseline, stiffness, loading, false)?;
    fo.normal_stress = self::normal_stress_mode(normal_stress_mode)?;
    let d = py
        .detach(|| {
            let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
            run_diagnose(&rec, &segs, &DiagnoseOptions { seed, threads, ..DiagnoseOptions::new(fo) })
                .map_err(|e| e.to_string())
        })
        .map_err(value_error)?;
    serde_json::to_string(&d).map_err(value_error)
}

/// The compiled module.
#[pymodule]
fn _rsf(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simulate_toml, m)?)?;
    m.add_function(wrap_pyfunction!(read_record_columns, m)?)?;
    m.add_function(wrap_pyfunction!(fit_json, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose_json, m)?)?;
    Ok(())
}
