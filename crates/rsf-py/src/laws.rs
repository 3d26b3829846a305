//! The law registry from Python: law files, Python functions with their own parameters, and the
//! names known — the same registry the CLI, fits and diagnoses read.

use crate::pylaw::PyLaw;
use crate::value_error;
use pyo3::prelude::*;
use rsf_laws::registry::{self, LawEntry, LawParameter, Origin, Start};
use std::sync::Arc;

/// Registers the law of a law file (TOML); returns its name.
#[pyfunction]
pub fn register_law_file(path: std::path::PathBuf) -> PyResult<String> {
    rsf_laws::text_law::register_file(&path).map_err(value_error)
}

/// The names of every registered law, the built-in ones first.
#[pyfunction]
pub fn law_names() -> Vec<String> {
    registry::all().iter().map(|e| e.name().to_string()).collect()
}

/// Registers a Python callable `f(v, theta, dc, b, stress_rate, *params)` as law `name`, with
/// its parameters as (name, unit, lo, hi, log, start); returns the name. `candidate`: whether
/// the diagnosis tries it.
#[pyfunction]
#[pyo3(signature = (name, f, words, params, candidate=true))]
pub fn register_py_law(
    name: &str,
    f: Py<PyAny>,
    words: &str,
    params: Vec<(String, String, f64, f64, bool, f64)>,
    candidate: bool,
) -> PyResult<String> {
    let specs: Vec<LawParameter> = params
        .iter()
        .map(|(n, unit, lo, hi, log, start)| LawParameter {
            name: registry::intern(n),
            unit: registry::intern(unit),
            lo: *lo,
            hi: *hi,
            log: *log,
            start: Start::Value(*start),
        })
        .collect();
    let base = PyLaw::new(f, name.to_string());
    let names: Vec<&'static str> = specs.iter().map(|p| p.name).collect();
    let entry = LawEntry::new(name, words, specs, move |v: &[f64]| {
        Ok(Arc::new(base.clone().with_params(names.iter().copied().zip(v.iter().copied()).collect())))
    })
    .with_origin(Origin::Python)
    .with_candidate(candidate);
    registry::register(entry).map_err(value_error)?;
    Ok(name.to_string())
}
