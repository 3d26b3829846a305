//! The compiled part of the Python package `rsf` (`rsf._rsf`): thin functions over the Rust
//! crates, numpy arrays in and out, results of fits and diagnoses as the CLI's JSON (the
//! Python layer in `python/rsf/__init__.py` turns them into dicts). Solves, fits and
//! diagnoses run with the GIL released; every error becomes a `ValueError` with the Rust
//! message.
#![forbid(unsafe_code)]

mod batch;
mod design;
mod fitting;
mod laws;
mod pylaw;
mod spec;

use numpy::{PyArray1, PyArray2, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rsf_fit::data::{ReadOptions, read_record};
use rsf_solvers::SolveError as RustSolveError;
use std::path::Path;

pyo3::create_exception!(
    _rsf,
    SolveError,
    PyValueError,
    "A forward solve failed: the message names the time and values reached; attributes `time` \
     (s), `slip_rate` (µm/s) and `mu` where known (a blow-up), `piece` and `v_lp` for an \
     integrator failure."
);

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A solver error as `rsf.SolveError` with its numbers as attributes; bad input stays a
/// `ValueError`.
fn solve_error(py: Python<'_>, e: &RustSolveError) -> PyErr {
    let set = |err: &PyErr, k: &str, v: f64| {
        let _ = err.value(py).setattr(k, v);
    };
    match e {
        RustSolveError::BlowUp { t, v, mu, .. } => {
            let err = SolveError::new_err(e.to_string());
            set(&err, "time", *t);
            set(&err, "slip_rate", *v);
            set(&err, "mu", *mu);
            err
        }
        RustSolveError::Integration { piece, v_lp, v, source } => {
            let err = SolveError::new_err(e.to_string());
            let t = match source {
                rsf_solvers::IntegrationError::StepSizeUnderflow { t, .. }
                | rsf_solvers::IntegrationError::TooManySteps { t, .. }
                | rsf_solvers::IntegrationError::Stopped { t, .. }
                | rsf_solvers::IntegrationError::Singular { t } => *t,
            };
            set(&err, "time", t);
            set(&err, "slip_rate", *v);
            set(&err, "v_lp", *v_lp);
            let _ = err.value(py).setattr("piece", *piece);
            err
        }
        _ => value_error(e),
    }
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
#[pyo3(signature = (toml_text, base_dir=None, name="protocol.toml", time=None, load_point=None, laws=None))]
fn simulate_toml<'py>(
    py: Python<'py>,
    toml_text: &str,
    base_dir: Option<&str>,
    name: &str,
    time: Option<PyReadonlyArray1<f64>>,
    load_point: Option<PyReadonlyArray1<f64>>,
    laws: Option<Vec<Option<Py<PyAny>>>>,
) -> PyResult<Bound<'py, PyDict>> {
    let p = rsf_solvers::protocol::parse(toml_text, base_dir.map(Path::new), name).map_err(value_error)?;
    run(py, p, time, load_point, laws)
}

/// Solves the protocol that Python objects describe: `spec` is a dict of the protocol file's
/// shape (`model`, `loading`, `output`, `solver`, `initial`; lists of dicts for states and
/// segments), checked by the same rules as a file, errors naming the field. No text between.
#[pyfunction]
#[pyo3(signature = (spec, base_dir=None, name="Python objects", time=None, load_point=None, laws=None))]
fn simulate_spec<'py>(
    py: Python<'py>,
    spec: &Bound<'py, PyDict>,
    base_dir: Option<&str>,
    name: &str,
    time: Option<PyReadonlyArray1<f64>>,
    load_point: Option<PyReadonlyArray1<f64>>,
    laws: Option<Vec<Option<Py<PyAny>>>>,
) -> PyResult<Bound<'py, PyDict>> {
    let table = spec::table(spec, "")?;
    let p = rsf_solvers::protocol::from_table(table, base_dir.map(Path::new), name).map_err(value_error)?;
    run(py, p, time, load_point, laws)
}

/// A parsed protocol solved: Python laws put in place of their states' placeholders, a measured
/// load point (`time`, `load_point`) in place of the loading, the GIL released for the solve.
fn run<'py>(
    py: Python<'py>,
    mut p: rsf_solvers::protocol::Protocol,
    time: Option<PyReadonlyArray1<f64>>,
    load_point: Option<PyReadonlyArray1<f64>>,
    laws: Option<Vec<Option<Py<PyAny>>>>,
) -> PyResult<Bound<'py, PyDict>> {
    // Python laws replace the placeholder laws of their states
    let mut py_laws = vec![];
    for (i, f) in laws.unwrap_or_default().into_iter().enumerate() {
        let Some(f) = f else { continue };
        let st = p.problem.model.states.get_mut(i).ok_or_else(|| value_error(format!("no state {}", i + 1)))?;
        let name =
            f.bind(py).getattr("__name__").and_then(|n| n.extract::<String>()).unwrap_or_else(|_| "python".into());
        let law = pylaw::PyLaw::new(f, name);
        py_laws.push(law.clone());
        st.law = std::sync::Arc::new(law);
    }
    match (time, load_point) {
        (None, None) => {}
        (Some(t), Some(x)) => {
            let changes_sigma = match &p.problem.loading {
                rsf_core::Loading::Segments(segs) => segs.iter().any(|s| s.changes_normal_stress()),
                rsf_core::Loading::Record(_) => p.problem.normal_stress.is_some(),
            };
            if changes_sigma {
                return Err(value_error(
                    "the protocol changes the normal stress along its own loading; a measured load point \
                     cannot replace that loading (give the normal stress in a record instead)",
                ));
            }
            let rec = rsf_core::LoadRecord { time: t.as_slice()?.to_vec(), load_point: x.as_slice()?.to_vec() };
            rec.validate().map_err(|e| value_error(format!("load-point arrays: {e}")))?;
            p.problem.output = rsf_solvers::OutputTimes::Times(rec.time.clone());
            p.problem.loading = rsf_core::Loading::Record(rec);
        }
        _ => return Err(value_error("give both time and load_point, or neither")),
    }
    let sol = py.detach(|| p.method.solve(&p.problem));
    // an exception the callable raised matters only when the solve failed: a trial stage the
    // solver rejected (an explicit method's overshoot to V = 1e237, say) costs nothing. Every
    // Python law of the model is asked: the placeholders' and the registered ones'.
    if sol.is_err() {
        let registered = p.problem.model.states.iter().filter_map(|st| st.law.as_any().downcast_ref::<pylaw::PyLaw>());
        for l in py_laws.iter().chain(registered) {
            if let Some(e) = l.error.lock().unwrap_or_else(|e| e.into_inner()).take() {
                return Err(e);
            }
        }
    }
    solution_dict(py, sol.map_err(|e| solve_error(py, &e))?)
}

/// Reads a lab record with the CLI's column options; returns `time_s`, `load_point_um`, `mu`
/// (and `normal_stress_mpa` with `normal_col`).
#[pyfunction]
#[pyo3(signature = (path, time_col="time_s", lp_col="load_point_um", mu_col="mu", normal_col=None, drop_invalid=false,
    accept_implausible=false))]
fn read_record_columns<'py>(
    py: Python<'py>,
    path: &str,
    time_col: &str,
    lp_col: &str,
    mu_col: &str,
    normal_col: Option<&str>,
    drop_invalid: bool,
    accept_implausible: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = ReadOptions {
        time_col: time_col.into(),
        lp_col: lp_col.into(),
        mu_col: mu_col.into(),
        normal_col: normal_col.map(str::to_string),
        invalid: if drop_invalid { rsf_fit::data::InvalidRows::Drop } else { rsf_fit::data::InvalidRows::Error },
        accept_implausible,
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
    d.set_item("warnings", rec.warnings)?;
    Ok(d)
}

/// Checks protocol text as `rsf simulate` does and returns the file's own contents as JSON
/// (every table and field as written), from which the Python layer builds its objects.
#[pyfunction]
#[pyo3(signature = (toml_text, base_dir=None, name="protocol.toml"))]
fn protocol_json(toml_text: &str, base_dir: Option<&str>, name: &str) -> PyResult<String> {
    rsf_solvers::protocol::parse(toml_text, base_dir.map(Path::new), name).map_err(value_error)?;
    let v: toml::Value = toml::from_str(toml_text).map_err(value_error)?;
    serde_json::to_string(&v).map_err(value_error)
}

/// The compiled module.
#[pymodule]
fn _rsf(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simulate_toml, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_spec, m)?)?;
    m.add_function(wrap_pyfunction!(read_record_columns, m)?)?;
    m.add_function(wrap_pyfunction!(protocol_json, m)?)?;
    m.add_function(wrap_pyfunction!(fitting::fit_json, m)?)?;
    m.add_function(wrap_pyfunction!(fitting::implausible, m)?)?;
    m.add_function(wrap_pyfunction!(fitting::diagnose_json, m)?)?;
    m.add_function(wrap_pyfunction!(design::design_json, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_entries, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_check_options, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_row, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_summary, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_table, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_crashed_row, m)?)?;
    m.add_function(wrap_pyfunction!(laws::register_law_file, m)?)?;
    m.add_function(wrap_pyfunction!(laws::law_names, m)?)?;
    m.add_function(wrap_pyfunction!(laws::register_py_law, m)?)?;
    m.add_function(wrap_pyfunction!(laws::check_law, m)?)?;
    m.add("SolveError", m.py().get_type::<SolveError>())?;
    // the built-in law names, from the one registry (rsf_laws::Law)
    m.add("LAW_NAMES", rsf_laws::Law::NAMES.to_vec())?;
    Ok(())
}
