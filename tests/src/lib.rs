//! Helpers shared by rsf's cross-crate tests: reference files and the shared data folder.
#![forbid(unsafe_code)]

use std::path::{Path, PathBuf};

/// The code blocks of docs/laws.md, compiled and run as doctests (they use the example law
/// crate `my_rsf_law`, which no longer carries them, so that it can be copied out alone).
#[doc = include_str!("../../docs/laws.md")]
pub mod laws_md {}

/// This crate's directory.
pub fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The bundled data directory `tests/data`.
pub fn data_dir() -> PathBuf {
    crate_dir().join("data")
}

/// `../shared/data/<name>` beside the checkout, if present. Tests that need unlicensed records
/// use this and print a clear SKIP line when it is absent (CI always has it).
pub fn shared_data(name: &str) -> Option<PathBuf> {
    let p = crate_dir().join("..").join("..").join("shared").join("data").join(name);
    if p.exists() { Some(p) } else { None }
}

/// A numeric CSV with a header row naming `time_s`: (column names, columns), read by the one
/// record reader ([`rsf_record::read_table`]).
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let t = rsf_record::read_table(path, "time_s").unwrap_or_else(|e| panic!("{e}"));
    (t.names, t.columns)
}

/// `cases.json` of the reference set.
pub fn reference_cases() -> serde_json::Value {
    let p = data_dir().join("reference/rsfmodel/cases.json");
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

use rsf_core::{Loading, Model, Segment, StateVariable};
use rsf_solvers::{Dopri5, OutputTimes, Problem, Rodas4, Solution};

/// One-state model with a built-in law by name (`vc`/`c` taken from `extra` where needed).
pub fn model1(law: &str, a: f64, b: f64, dc: f64, k: f64, extra: f64) -> Model {
    let law = rsf_laws::law_by_name(law, |_| Some(extra)).unwrap();
    Model::new(0.6, 1.0, a, k).with_state(StateVariable::from_shared(law, b, dc))
}

/// Solves with both integrators at `rtol`; returns (explicit, implicit).
pub fn both(p: &Problem, rtol: f64) -> (Solution, Solution) {
    let e = rsf_solvers::solve(p, &Dopri5::new(rtol, rtol * 1e-3)).unwrap();
    let i = rsf_solvers::solve(p, &Rodas4::new(rtol, rtol * 1e-3)).unwrap();
    (e, i)
}

/// A problem from (v, duration) segments, sampled every `dt`.
pub fn problem(model: Model, v_init: f64, segs: &[(f64, f64)], dt: f64) -> Problem {
    let segs = segs.iter().map(|&(v, d)| Segment::for_duration(v, d)).collect();
    Problem::new(model, Loading::Segments(segs), v_init, dt)
}

/// Same, with output at the given times.
pub fn problem_at(model: Model, v_init: f64, segs: &[(f64, f64)], times: Vec<f64>) -> Problem {
    let mut p = problem(model, v_init, segs, 1.0);
    p.output = OutputTimes::Times(times);
    p
}

// The user guide's code blocks are compiled and run as doctests of this crate.
#[doc = include_str!("../../docs/solvers.md")]
pub mod guide_solvers {}
#[doc = include_str!("../../docs/library.md")]
pub mod guide_library {}
