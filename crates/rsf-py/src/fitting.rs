//! Fits and diagnoses from numpy arrays: the CLI's options as keywords, results as the CLI's
//! JSON, the GIL released while the work runs on a worker thread and Ctrl-C honoured (the main
//! thread polls Python's signal handlers and sets the fit's cancel flag).

use crate::value_error;
use numpy::PyReadonlyArray1;
use pyo3::prelude::*;
use rsf_diagnose::{DiagnoseOptions, diagnose as run_diagnose};
use rsf_fit::data::Record;
use rsf_fit::fit::{FitOptions, LoadingMode, fit as run_fit, prepare};
use rsf_fit::segment::{SegmentOptions, detect};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A record from three arrays (and optionally the normal stress, MPa), checked as the CSV
/// reader checks a file, its plausibility included (refused unless `accept_implausible`, when
/// each finding is returned as a warning of the record).
pub(crate) fn record(
    time: PyReadonlyArray1<f64>,
    lp: PyReadonlyArray1<f64>,
    mu: PyReadonlyArray1<f64>,
    normal_stress: Option<PyReadonlyArray1<f64>>,
    accept_implausible: bool,
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
    if time.len() < rsf_fit::data::MIN_ROWS {
        return Err(value_error(format!(
            "a record needs at least {} samples (got {})",
            rsf_fit::data::MIN_ROWS,
            time.len()
        )));
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
    let mut rec =
        Record { time, load_point: lp, mu, normal_stress: sn, source: "numpy arrays".into(), ..Default::default() };
    let found = rsf_fit::data::plausible::check(&rec);
    if !found.is_empty() {
        let texts: Vec<String> = found.iter().map(rsf_fit::data::plausible::Implausible::text).collect();
        if !accept_implausible {
            return Err(value_error(format!(
                "the record does not look like a friction experiment: {}. If it is right, pass accept_implausible=True",
                texts.join("; ")
            )));
        }
        rec.warnings = texts.into_iter().map(|t| format!("accepted as plausible: {t}")).collect();
    }
    Ok(rec)
}

/// What looks wrong with a record of three arrays (empty when it looks like a friction
/// experiment): the words of `rsf_fit::data::plausible::check`.
#[pyfunction]
pub fn implausible(
    time: PyReadonlyArray1<f64>,
    load_point: PyReadonlyArray1<f64>,
    mu: PyReadonlyArray1<f64>,
) -> PyResult<Vec<String>> {
    let rec = record(time, load_point, mu, None, true)?;
    Ok(rec.warnings.iter().map(|w| w.trim_start_matches("accepted as plausible: ").to_string()).collect())
}

/// A closed vocabulary's value from Python's string, by the type's own `FromStr` (the one the
/// CLI and manifests use); a `ValueError` naming the names otherwise.
pub(crate) fn word<T: std::str::FromStr<Err = String>>(s: &str) -> PyResult<T> {
    s.parse().map_err(value_error)
}

pub(crate) fn fit_options(law: &str, stiffness: f64, loading: &str, fit_stiffness: bool) -> PyResult<FitOptions> {
    if !(stiffness > 0.0 && stiffness.is_finite()) {
        return Err(value_error(format!("stiffness {stiffness} must be positive and finite (1/µm)")));
    }
    let law = word::<rsf_laws::registry::LawName>(law)?.with_starting_values().map_err(value_error)?;
    let mut o = FitOptions::new(vec![law], stiffness);
    o.loading = word::<LoadingMode>(loading)?;
    o.fit_stiffness = fit_stiffness;
    Ok(o)
}

/// Runs `work` on a worker thread with the GIL released, polling Python's signal handlers
/// every 50 ms on this (the main) thread; a KeyboardInterrupt sets `cancel`, waits for the
/// work to wind down (one model evaluation) and is raised.
pub(crate) fn interruptible<T: Send>(
    py: Python<'_>,
    cancel: &Arc<AtomicBool>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    std::thread::scope(|sc| {
        let h = sc.spawn(work);
        let mut interrupted = None;
        while !h.is_finished() {
            py.detach(|| std::thread::sleep(std::time::Duration::from_millis(50)));
            if interrupted.is_none() {
                if let Err(e) = py.check_signals() {
                    cancel.store(true, Ordering::Relaxed);
                    interrupted = Some(e);
                }
            }
        }
        let out = py.detach(|| h.join()).map_err(|_| value_error("the fit panicked"))?;
        match interrupted {
            Some(e) => Err(e),
            None => Ok(out),
        }
    })
}

fn alpha_fit(fit_alpha: Option<&str>) -> PyResult<rsf_fit::fit::AlphaFit> {
    fit_alpha.map_or(Ok(rsf_fit::fit::AlphaFit::Fixed), word)
}

/// Fits a law to a record (arrays); returns the CLI's fit JSON (with `mcmc` when asked) and
/// the MCMC draws (rows × (free parameters, sigma)) with their column names.
#[pyfunction]
#[pyo3(signature = (time, load_point, mu, stiffness, law="slip", loading="protocol", fit_stiffness=false,
    normal_stress=None, normal_stress_mode="auto", fit_alpha=None, laws=None, fit_slip_trend=false,
    fix=vec![], initial=vec![], rtol=1e-7, starts=4, mcmc=None, chains=4, seed=1, progress=false,
    window_um=None, mu0_per_segment=false, weights="equal", per_segment=false, threads=0, max_iter=100,
    accept_implausible=false, uncertainty="noise-model", fit_a_slope=false))]
#[allow(clippy::too_many_arguments)]
pub fn fit_json(
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
    laws: Option<Vec<String>>,
    fit_slip_trend: bool,
    fix: Vec<String>,
    initial: Vec<(String, f64)>,
    rtol: f64,
    starts: usize,
    mcmc: Option<usize>,
    chains: usize,
    seed: u64,
    progress: bool,
    window_um: Option<f64>,
    mu0_per_segment: bool,
    weights: &str,
    per_segment: bool,
    threads: usize,
    max_iter: usize,
    accept_implausible: bool,
    uncertainty: &str,
    fit_a_slope: bool,
) -> PyResult<FitOut> {
    if max_iter == 0 {
        return Err(value_error("max_iter must be at least 1"));
    }
    let rec = record(time, load_point, mu, normal_stress, accept_implausible)?;
    let mut opts = fit_options(law, stiffness, loading, fit_stiffness)?;
    if let Some(names) = laws {
        if names.is_empty() || names.len() > 3 {
            return Err(value_error(format!(
                "1 to 3 state variables are supported by the fitter (got {})",
                names.len()
            )));
        }
        opts.laws = names
            .iter()
            .map(|n| word::<rsf_laws::registry::LawName>(n)?.with_starting_values().map_err(value_error))
            .collect::<PyResult<_>>()?;
    }
    opts.normal_stress = word::<rsf_fit::fit::NormalStressMode>(normal_stress_mode)?;
    opts.alpha = alpha_fit(fit_alpha)?;
    opts.fit_slip_trend = fit_slip_trend;
    opts.fit_a_slope = fit_a_slope;
    opts.fix = fix.iter().map(|c| word::<rsf_fit::fit::Constraint>(c)).collect::<PyResult<_>>()?;
    opts.initial =
        initial.into_iter().map(|(n, v)| Ok((word::<rsf_fit::fit::ParamName>(&n)?, v))).collect::<PyResult<_>>()?;
    if !(rtol > 0.0 && rtol < 1e-2) {
        return Err(value_error(format!("rtol {rtol} must be in (0, 1e-2)")));
    }
    opts.rtol = rtol;
    opts.starts = starts.max(1);
    opts.max_iter = max_iter;
    if let Some(w) = window_um {
        if !(w > 0.0 && w.is_finite()) {
            return Err(value_error(format!("window_um {w} must be positive (µm)")));
        }
    }
    opts.window_um = window_um;
    opts.mu0_per_segment = mu0_per_segment;
    opts.weighting = word::<rsf_fit::fit::Weighting>(weights)?;
    opts.uncertainty = word::<rsf_fit::fit::Uncertainty>(uncertainty)?;
    let cancel = Arc::new(AtomicBool::new(false));
    opts.cancel = Some(cancel.clone());
    let out = interruptible(py, &cancel, || -> Result<_, String> {
        let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
        let prep = prepare(&rec, &segs, &opts).map_err(|e| e.to_string())?;
        // the starts side by side; the per-event refits run as parallel jobs of one thread each
        let res = run_fit(&prep, &FitOptions { threads, ..opts.clone() }).map_err(|e| e.to_string())?;
        let mc = match mcmc {
            None => None,
            Some(n) => {
                let m = rsf_fit::mcmc::McmcOptions {
                    samples: n,
                    chains: chains.max(1),
                    seed,
                    progress: progress.then(|| -> rsf_fit::progress::Progress {
                        // a line per tenth of the draws
                        Arc::new(|done, total, what: &str| {
                            let step = (total / 10).max(rsf_fit::mcmc::PROGRESS_EVERY);
                            if done % step < rsf_fit::mcmc::PROGRESS_EVERY {
                                eprintln!("rsf.fit: {done}/{total} {what}");
                            }
                        })
                    }),
                    ..rsf_fit::mcmc::McmcOptions::default()
                };
                Some(rsf_fit::mcmc::run(&prep, &opts, &res, &m)?)
            }
        };
        // the refits of `rsf fit --per-segment`: each step and hold alone
        let per = if per_segment { rsf_diagnose::per_event_fits(&prep, &opts, &res, 0) } else { vec![] };
        Ok((res, mc, per))
    })?
    .map_err(value_error)?;
    let (res, mc, per) = out;
    let mut json = serde_json::to_value(&res).map_err(value_error)?;
    if per_segment {
        json["per_segment"] = serde_json::to_value(&per).map_err(value_error)?;
    }
    let (samples, names) = match mc {
        Some(m) => {
            json["mcmc"] = serde_json::to_value(&m).map_err(value_error)?;
            (m.samples, m.sample_names)
        }
        None => (vec![], vec![]),
    };
    let c = &res.curve;
    let curve = vec![
        ("time".to_string(), c.time.clone()),
        ("load_point".into(), c.load_point.clone()),
        ("data".into(), c.data.clone()),
        ("model".into(), c.model.clone()),
        ("slip_rate".into(), c.slip_rate.clone()),
    ];
    Ok((serde_json::to_string(&json).map_err(value_error)?, samples, names, curve))
}

/// The fit JSON, the MCMC draws with their column names, and the fitted curve's columns.
type FitOut = (String, Vec<Vec<f64>>, Vec<String>, Vec<(String, Vec<f64>)>);

/// A diagnosis's options from the Python arguments (`rsf.diagnose` and `rsf.design`), with the
/// flag Ctrl-C sets to cancel it.
pub(crate) fn diagnose_options(
    baseline: &str,
    stiffness: f64,
    loading: &str,
    normal_stress_mode: &str,
    seed: u64,
    threads: usize,
) -> PyResult<(DiagnoseOptions, Arc<AtomicBool>)> {
    let baseline = word::<rsf_diagnose::Baseline>(baseline)?;
    let mut fo = fit_options(baseline.name(), stiffness, loading, false)?;
    fo.normal_stress = word::<rsf_fit::fit::NormalStressMode>(normal_stress_mode)?;
    let cancel = Arc::new(AtomicBool::new(false));
    fo.cancel = Some(cancel.clone());
    Ok((DiagnoseOptions { seed, threads, ..DiagnoseOptions::new(fo) }, cancel))
}

/// Diagnoses a record (arrays) as `rsf diagnose` does; returns the CLI's diagnosis JSON and
/// the self-contained HTML report (`rsf diagnose --report`), which is also written to
/// `report` when given.
#[pyfunction]
#[pyo3(signature = (time, load_point, mu, stiffness, baseline="slip", loading="protocol", seed=1, threads=0,
    normal_stress=None, normal_stress_mode="auto", report=None, name="record", progress=false,
    stiffness_uncertainty=rsf_diagnose::STIFFNESS_UNCERTAINTY, accept_implausible=false))]
#[allow(clippy::too_many_arguments)]
pub fn diagnose_json(
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
    report: Option<&str>,
    name: &str,
    progress: bool,
    stiffness_uncertainty: f64,
    accept_implausible: bool,
) -> PyResult<(String, String)> {
    let rec = record(time, load_point, mu, normal_stress, accept_implausible)?;
    let (mut dopts, cancel) = diagnose_options(baseline, stiffness, loading, normal_stress_mode, seed, threads)?;
    if !(stiffness_uncertainty > 0.0 && stiffness_uncertainty < 1.0) {
        return Err(value_error(format!(
            "stiffness_uncertainty {stiffness_uncertainty} must lie between 0 and 1 (a fraction of the nominal)"
        )));
    }
    dopts.stiffness_uncertainty = stiffness_uncertainty;
    if progress {
        dopts.progress = Some(Arc::new(|done, all, what: &str| eprintln!("rsf.diagnose: {done}/{all} {what}")));
    }
    let d = interruptible(py, &cancel, || {
        let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
        run_diagnose(&rec, &segs, &dopts).map_err(|e| e.to_string())
    })?
    .map_err(value_error)?;
    let html = rsf_report::diagnosis_html(&d, name);
    if let Some(path) = report {
        std::fs::write(path, &html).map_err(|e| value_error(format!("writing {path}: {e}")))?;
    }
    Ok((serde_json::to_string(&d).map_err(value_error)?, html))
}
