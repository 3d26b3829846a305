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

/// Runs rsf's conformance kit (`rsf_testkit`) on a registered law by name, or on a law file:
/// returns the report's text; a property that fails raises ValueError with the property, the
/// reason and the smallest input found. A Python function's derivatives are central
/// differences, so its `jacobian` is checked against the kit's own differences alone.
#[pyfunction]
#[pyo3(signature = (law, cases=None, steady_state_dc_over_v=false))]
pub fn check_law(py: Python<'_>, law: &str, cases: Option<u32>, steady_state_dc_over_v: bool) -> PyResult<String> {
    let path = std::path::Path::new(law);
    let entry = if law.ends_with(".toml") || path.exists() {
        rsf_laws::text_law::load(path).map_err(value_error)?
    } else {
        registry::find(law).map_err(value_error)?
    };
    let mut claims = rsf_testkit::Claims::new();
    if steady_state_dc_over_v {
        claims = claims.steady_state_dc_over_v();
    }
    if let Some(n) = cases {
        claims = claims.cases(n);
    }
    let report = match entry.origin() {
        Origin::Python => {
            let built = entry.with_starting_values().map_err(value_error)?;
            let Some(pylaw) = built.as_any().downcast_ref::<PyLaw>() else {
                return Err(value_error(format!("law `{}` is not a Python function", entry.name())));
            };
            let claims = rsf_testkit::registered::claims_from_units(&entry, claims).derivatives_by_differences();
            // the kit calls the function many times: let other Python threads run between calls
            let pylaw = pylaw.clone();
            py.detach(|| rsf_testkit::check(&pylaw, &claims))
        }
        Origin::BuiltIn(_) | Origin::Rust | Origin::TextFile(_) => {
            py.detach(|| rsf_testkit::check_entry(&entry, claims)).map_err(value_error)?
        }
    };
    report.map(|r| r.to_string()).map_err(|f| value_error(f.to_string()))
}
