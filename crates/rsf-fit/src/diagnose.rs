//! Diagnosis: what a fitted model gets wrong, which extension fixes it, and the gain.
//!
//! 1. Fit the baseline (one state variable, Slip or Aging law), with uniform weights.
//! 2. Read the baseline residuals (correlation, trends against slip and ln V), estimate the
//!    machine stiffness from reloading slopes, and refit every step and hold alone to test
//!    whether one Dc serves them all.
//! 3. Fit each candidate extension from the baseline optimum: the other law or a mixture
//!    (`evolution_law`), a second state variable (`second_state_variable`), the Kato–Tullis
//!    cut-off (`cutoff_velocity`), a slip trend g·δ (`slip_trend`), a free stiffness
//!    (`stiffness`).
//! 4. Score each by ΔBIC computed with the *effective* number of independent samples: lab
//!    residuals are correlated in time, and with n samples of AR(1) noise of lag-one
//!    correlation ρ the data carry about n (1 − ρ)/(1 + ρ) independent values. Scaling the
//!    log-likelihood difference by n_eff/n keeps correlated noise from passing for an effect.
//! 5. Held-out test: fit on the first part of the record, predict the rest, before and after;
//!    the extension starts from the baseline's training optimum, never from a fit that saw the
//!    held-out part.
//! 6. The cause is the best-scoring candidate with ΔBIC_eff below −10 ("very strong" evidence,
//!    Kass & Raftery 1995) that is credible (held-out misfit not more than 5% worse, no
//!    parameter run to a bound); else `none`. The winner combined with the next credible
//!    candidates may add a second cause. The runner-up and every score are reported.
//!
//! Independent fits run in parallel on all cores.

use crate::data::Record;
use crate::fit::{FitError, FitOptions, FitResult, Params, Prepared, fit, model_curve, parameter_map, prepare};
use crate::segment::Segment;
use serde::Serialize;
use std::collections::BTreeMap;

/// Decisive ΔBIC_eff (negative: the extension is better).
pub const DECISIVE: f64 = -10.0;

/// Progress callback: (jobs done, jobs in all, what finished).
pub type Progress = std::sync::Arc<dyn Fn(usize, usize, &str) + Send + Sync>;

/// Diagnosis settings.
#[derive(Clone)]
pub struct DiagnoseOptions {
    /// Baseline fit settings (one state variable). The diagnosis always fits with uniform
    /// weights, whatever `fit.weighting` says: model comparison needs the likelihood of the
    /// noise, and lab noise has one σ throughout.
    pub fit: FitOptions,
    /// Run the held-out test.
    pub heldout: bool,
    /// Refit the baseline law step by step and hold by hold (parameter consistency).
    pub per_segment: bool,
    /// Try the winning extension combined with each other decisive one.
    pub combinations: bool,
    /// Threads for the independent fits (0: all cores).
    pub threads: usize,
    /// Called as fits finish.
    pub progress: Option<Progress>,
}

impl DiagnoseOptions {
    /// Everything on: held-out test, per-segment refits, combinations, all cores, no progress.
    pub fn new(fit: FitOptions) -> Self {
        Self { fit, heldout: true, per_segment: true, combinations: true, threads: 0, progress: None }
    }
}

impl std::fmt::Debug for DiagnoseOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DiagnoseOptions")
            .field("fit", &self.fit)
            .field("heldout", &self.heldout)
            .field("per_segment", &self.per_segment)
            .field("combinations", &self.combinations)
            .field("threads", &self.threads)
            .finish_non_exhaustive()
    }
}

/// Numbers from the baseline residuals that point at causes.
#[derive(Clone, Debug, Serialize)]
pub struct Evidence {
    /// Lag-one autocorrelation of the baseline residuals.
    pub residual_lag1: f64,
    /// Effective number of independent samples, n (1 − ρ)/(1 + ρ).
    pub n_effective: f64,
    /// Slope of the residuals against load-point displacement (friction per µm) and its t value.
    pub residual_trend_per_um: f64,
    /// t statistic of that slope with n_eff.
    pub residual_trend_t: f64,
    /// Largest per-segment rms over the median per-segment rms.
    pub segment_rms_ratio: f64,
    /// Baseline misfit over the noise estimated from sample-to-sample differences.
    pub misfit_over_noise: f64,
    /// Slope of the baseline residuals against ln V (model slip rate): a law that heals too
    /// fast or too slowly at low slip rates leaves residuals that trend with ln V.
    pub residual_vs_ln_v: Option<f64>,
    /// Its t value with n_eff.
    pub residual_vs_ln_v_t: Option<f64>,
    /// Per-event refits: spread of ln Dc between events in units of its standard error
    /// (reduced χ²; ≈ 1 when one Dc serves every step and hold).
    pub dc_consistency_chi2: Option<f64>,
    /// Slope of ln Dc against ln(V_after/V_before) over the velocity steps (the Aging law fitted
    /// with one Dc to Slip-law steps, or the reverse, gives Dc that depends on step direction).
    pub dc_vs_ln_step: Option<f64>,
    /// Slope of ln Dc against ln(hold duration) over the holds.
    pub dc_vs_ln_hold: Option<f64>,
    /// Machine stiffness (1/µm) from the elastic reloading slope at up-steps and reslides
    /// (median over events; the reload-slope method): a nominal k far from it points at
    /// `stiffness`.
    pub k_reload_slope: Option<f64>,
}

/// One step or hold refitted alone with the baseline law (free mu0, a, b, Dc).
#[derive(Clone, Debug, Serialize)]
pub struct EventFit {
    /// `step` or `hold`.
    pub event: String,
    /// Time of the change, s.
    pub t: f64,
    /// Load-point velocity before and after, µm/s.
    pub v_before: f64,
    /// After.
    pub v_after: f64,
    /// Hold duration, s (holds only).
    pub hold_s: Option<f64>,
    /// Fitted a, b, Dc (µm).
    pub a: f64,
    /// b.
    pub b: f64,
    /// Dc, µm.
    pub dc: f64,
    /// Standard error of ln Dc.
    pub ln_dc_stderr: f64,
    /// rms misfit of the window.
    pub rms: f64,
}

/// One candidate extension and its score.
#[derive(Clone, Debug, Serialize)]
pub struct Candidate {
    /// Cause name (`a+b` for a combination).
    pub cause: String,
    /// What was changed.
    pub extension: String,
    /// ΔBIC with n_eff (negative: better than the baseline).
    pub delta_bic: f64,
    /// ΔAIC with n_eff.
    pub delta_aic: f64,
    /// rms(extended) / rms(baseline).
    pub rms_ratio: f64,
    /// Held-out rms of the baseline and of this extension.
    pub heldout_rms_before: Option<f64>,
    /// Held-out rms of the extension.
    pub heldout_rms_after: Option<f64>,
    /// The effect's parameters (e.g. `b2`, `dc2`; `vc`; `g`; `k`; `law`).
    pub effect: BTreeMap<String, serde_json::Value>,
    /// Wall time of the candidate's fits, s.
    pub seconds: f64,
    /// Free parameters of its fit that ended at a physical bound (such a candidate is not
    /// named: the data do not constrain it).
    pub at_bound: Vec<String>,
    /// The fit.
    #[serde(skip)]
    pub fit: Option<FitResult>,
    /// Its held-out training fit (the start of a combination's held-out fit).
    #[serde(skip)]
    pub heldout_fit: Option<FitResult>,
    /// The options it was fitted with (the base of combinations).
    #[serde(skip)]
    pub options: Option<FitOptions>,
}

/// The gain of the chosen extension.
#[derive(Clone, Debug, Serialize)]
pub struct Gain {
    /// ΔBIC with n_eff.
    pub delta_bic: f64,
    /// ΔAIC with n_eff.
    pub delta_aic: f64,
    /// rms ratio.
    pub rms_ratio: f64,
    /// Held-out rms before.
    pub heldout_rms_before: Option<f64>,
    /// Held-out rms after.
    pub heldout_rms_after: Option<f64>,
}

/// A second cause found on top of the first.
#[derive(Clone, Debug, Serialize)]
pub struct Secondary {
    /// Cause name.
    pub cause: String,
    /// ΔBIC_eff of the combined model against the first extension alone.
    pub delta_bic: f64,
    /// rms(combined) / rms(first extension).
    pub rms_ratio: f64,
    /// Held-out rms of the first extension and of the combination.
    pub heldout_rms_before: Option<f64>,
    /// Held-out rms of the combination.
    pub heldout_rms_after: Option<f64>,
    /// Effect parameters of the combined fit.
    pub effect: BTreeMap<String, serde_json::Value>,
    /// The combined fit.
    pub fit: FitResult,
}

/// The diagnosis.
#[derive(Clone, Debug, Serialize)]
pub struct Diagnosis {
    /// `none`, `evolution_law`, `second_state_variable`, `cutoff_velocity`, `slip_trend`, `stiffness`.
    pub cause: String,
    /// The decisive statistic: ΔBIC_eff of the chosen extension (or of the best candidate for `none`).
    pub confidence: f64,
    /// Human-readable reason.
    pub reason: String,
    /// Residual evidence.
    pub evidence: Evidence,
    /// Baseline fit.
    pub baseline: FitResult,
    /// Extended fit (absent for `none`).
    pub extended: Option<FitResult>,
    /// Gain of the extension.
    pub gain: Option<Gain>,
    /// Effect parameters of the chosen extension.
    pub effect: BTreeMap<String, serde_json::Value>,
    /// Runner-up cause and its ΔBIC_eff.
    pub runner_up: Option<(String, f64)>,
    /// All candidates.
    pub candidates: Vec<Candidate>,
    /// A second cause that decisively improves on the first extension, when one does.
    pub secondary: Option<Secondary>,
    /// Per-event refits of the baseline law.
    pub per_segment: Vec<EventFit>,
    /// Held-out split time, s.
    pub heldout_split_t: f64,
}

fn lag1(r: &[f64]) -> f64 {
    let n = r.len();
    let m = r.iter().sum::<f64>() / n as f64;
    let v: f64 = r.iter().map(|x| (x - m).powi(2)).sum();
    if v == 0.0 {
        return 0.0;
    }
    r.windows(2).map(|w| (w[0] - m) * (w[1] - m)).sum::<f64>() / v
}

/// Least-squares slope of y on x and its t value when the residual scatter holds `n_eff`
/// independent values.
fn slope_t(x: &[f64], y: &[f64], n_eff: f64) -> Option<(f64, f64)> {
    let n = x.len() as f64;
    if x.len() < 3 {
        return None;
    }
    let xm = x.iter().sum::<f64>() / n;
    let ym = y.iter().sum::<f64>() / n;
    let sxx: f64 = x.iter().map(|v| (v - xm).powi(2)).sum();
    if !(sxx > 0.0) {
        return None;
    }
    let slope = x.iter().zip(y).map(|(a, b)| (a - xm) * (b - ym)).sum::<f64>() / sxx;
    let var = x.iter().zip(y).map(|(a, b)| (b - ym - slope * (a - xm)).powi(2)).sum::<f64>() / (n - 2.0).max(1.0);
    let se = (var / sxx * n / n_eff.clamp(3.0, n)).sqrt();
    Some((slope, slope / se.max(1e-300)))
}

fn evidence(base: &FitResult) -> Evidence {
    let c = &base.curve;
    let (res, rho, n_eff) = residual_correlation(base);
    let n = res.len() as f64;
    let (slope, t) = slope_t(&c.load_point, &res, n_eff).unwrap_or((0.0, 0.0));
    let mut seg_rms: Vec<f64> = base.segments.iter().filter(|s| s.n > 0).map(|s| s.rms).collect();
    seg_rms.sort_by(f64::total_cmp);
    let med = seg_rms.get(seg_rms.len() / 2).copied().unwrap_or(0.0);
    let noise = (c.data.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() / (2.0 * (n - 1.0))).sqrt();
    let (lnv, rv): (Vec<f64>, Vec<f64>) =
        c.slip_rate.iter().zip(&res).filter(|(v, _)| **v > 0.0).map(|(v, r)| (v.ln(), *r)).unzip();
    let vt = if c.slip_rate.len() == res.len() { slope_t(&lnv, &rv, n_eff) } else { None };
    Evidence {
        residual_lag1: rho,
        n_effective: n_eff,
        residual_trend_per_um: slope,
        residual_trend_t: t,
        segment_rms_ratio: seg_rms.last().copied().unwrap_or(0.0) / med.max(1e-300),
        misfit_over_noise: base.rms / noise.max(1e-300),
        residual_vs_ln_v: vt.map(|v| v.0),
        residual_vs_ln_v_t: vt.map(|v| v.1),
        dc_consistency_chi2: None,
        dc_vs_ln_step: None,
        dc_vs_ln_hold: None,
        k_reload_slope: None,
    }
}

/// Stiffness from the reloading slope dμ/dx_lp at the onset of up-steps and reslides. While the
/// friction rises through its direct effect, dμ/dx_lp = k (1 − V/V_lp); with V growing as
/// exp(Δμ/a) from V_before, a sample at fraction f of the rise to the peak has
/// V/V_lp ≈ (V_before/V_lp)^(1−f). The slope is fitted over f in [0.05, 0.4] and divided by the
/// mean of 1 − (V_before/V_lp)^(1−f) there (1 after a hold). Friction entering the event is
/// the median of the ten samples before it; the peak is the largest friction in the first third
/// of the segment; an event whose rise is under ten times the sample noise is skipped. Median
/// over the events; `None` when no event has four samples in the band.
fn reload_stiffness(p: &Prepared) -> Option<f64> {
    let s = &p.segments;
    let r = &p.record;
    let mut ks = vec![];
    for j in 1..s.len() {
        let Some(prev) = (0..j).rev().find(|&i| s[i].v > 0.0) else { continue };
        let (vb, va) = (if prev + 1 < j { 0.0 } else { s[prev].v }, s[j].v);
        if !(va > 1.5 * vb) {
            continue;
        }
        let (i0, i1) = (s[j].i0, s[j].i1);
        // friction entering the event: the median of the last samples before it, and their
        // sample-to-sample noise
        let pre: Vec<f64> = r.mu[i0.saturating_sub(9)..=i0].to_vec();
        if pre.len() < 4 {
            continue;
        }
        let mut sorted = pre.clone();
        sorted.sort_by(f64::total_cmp);
        let mu0 = sorted[sorted.len() / 2];
        let noise =
            (pre.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() / (2.0 * (pre.len() - 1) as f64)).sqrt();
        // the peak: the largest friction in the first third of the segment
        let i_end = i0 + (i1 - i0) / 3;
        let ip = (i0..=i_end).max_by(|&a, &b| r.mu[a].total_cmp(&r.mu[b])).unwrap_or(i0);
        let rise = r.mu[ip] - mu0;
        // the climb must stand well above the noise for its slope to mean anything
        if !(rise > 10.0 * noise) {
            continue;
        }
        let ratio = vb / va;
        let (mut xs, mut ys, mut corr) = (vec![], vec![], 0.0);
        for i in i0..=ip {
            let f = (r.mu[i] - mu0) / rise;
            if (0.05..=0.4).contains(&f) {
                xs.push(r.load_point[i]);
                ys.push(r.mu[i]);
                corr += 1.0 - ratio.powf(1.0 - f);
            }
        }
        if xs.len() < 4 {
            continue;
        }
        let n = xs.len() as f64;
        if let Some((slope, _)) = slope_t(&xs, &ys, n) {
            let k = slope / (corr / n);
            if k > 0.0 && k.is_finite() {
                ks.push(k);
            }
        }
    }
    if ks.is_empty() {
        return None;
    }
    ks.sort_by(f64::total_cmp);
    Some(ks[ks.len() / 2])
}

/// ΔBIC and ΔAIC of `ext` against `base` with the log-likelihood scaled to n_eff.
fn scores(base: &FitResult, ext: &FitResult, n_eff: f64) -> (f64, f64) {
    let n = base.n as f64;
    let dll = (ext.log_likelihood - base.log_likelihood) * n_eff / n;
    let dk = ext.n_free as f64 - base.n_free as f64;
    (-2.0 * dll + dk * n_eff.ln(), -2.0 * dll + 2.0 * dk)
}

/// A fit's residuals, their lag-one correlation ρ and the effective number of independent
/// samples n (1 − ρ)/(1 + ρ).
fn residual_correlation(f: &FitResult) -> (Vec<f64>, f64, f64) {
    let c = &f.curve;
    let res: Vec<f64> = c.data.iter().zip(&c.model).map(|(d, m)| d - m).collect();
    let n = res.len() as f64;
    let rho = lag1(&res).clamp(-0.99, 0.99);
    let n_eff = (n * (1.0 - rho) / (1.0 + rho)).clamp(2.0, n);
    (res, rho, n_eff)
}

/// n_eff of a fit's residuals.
fn n_eff_of(f: &FitResult) -> f64 {
    residual_correlation(f).2
}

/// The training part of a held-out test: the record before `t_split` and its segments (those
/// that start in it, cut at the split).
fn training(rec: &Record, segs: &[Segment], t_split: f64) -> (Record, Vec<Segment>) {
    let train = rec.window(rec.time[0], t_split);
    let n = train.len();
    let tsegs = segs
        .iter()
        .filter(|s| s.t0 < t_split && s.i0 < n)
        .map(|s| {
            let mut s = s.clone();
            s.i1 = s.i1.min(n.saturating_sub(1));
            s.t1 = s.t1.min(t_split);
            s
        })
        .collect();
    (train, tsegs)
}

/// Held-out test of the model `opts`: fitted on the record before `t_split`, it predicts the
/// rest; returns the rms of the prediction and the training fit (`train_fit` fits the prepared
/// training part). The baseline's training fit starts cold; an extension's starts from the
/// baseline's *training* optimum with its own parameters at their neutral values, as on the full
/// record — never from an optimum that has seen the held-out part.
fn heldout(
    rec: &Record,
    segs: &[Segment],
    opts: &FitOptions,
    train_fit: &dyn Fn(&Prepared, &FitOptions) -> Option<FitResult>,
    t_split: f64,
) -> Option<(f64, FitResult)> {
    let (train, tsegs) = training(rec, segs, t_split);
    let o = FitOptions { mu0_per_segment: false, ..opts.clone() };
    let pt = prepare(&train, &tsegs, &o).ok()?;
    let ft = train_fit(&pt, &o)?;
    let pf = prepare(rec, segs, &o).ok()?;
    let map_t = parameter_map(&pt, &o).ok()?;
    let map_f = parameter_map(&pf, &o).ok()?;
    if map_t.free_names() != map_f.free_names() {
        return None;
    }
    let mu = model_curve(&pf, &map_f, &o, &ft.theta, o.rtol).ok()?;
    let (mut ss, mut n) = (0.0, 0usize);
    for (k, &i) in pf.used.iter().enumerate() {
        if pf.record.time[i] > t_split {
            ss += (mu[k] - pf.record.mu[i]).powi(2);
            n += 1;
        }
    }
    (n > 0).then(|| ((ss / n as f64).sqrt(), ft))
}

/// Where to split for the held-out test: the start of the segment nearest 2/3 of the record
/// (within 40–85% of it) such that the training part holds at least one velocity change; with
/// no such segment (a record of one step or one hold), the later of 2/3 of the record and half
/// way from the first change to the end, so that the training part sees the change and the
/// start of the response.
fn split_time(rec: &Record, segs: &[Segment]) -> f64 {
    let (t0, t1) = (rec.time[0], rec.time[rec.len() - 1]);
    let target = t0 + (t1 - t0) * 2.0 / 3.0;
    // the first sliding segment after a change
    let first_event = segs.iter().skip(1).find(|s| s.v > 0.0).map(|s| s.t0);
    segs.iter()
        .skip(2)
        .map(|s| s.t0)
        .filter(|&t| first_event.is_some_and(|e| e < t))
        .filter(|t| (t - t0) > 0.4 * (t1 - t0) && (t - t0) < 0.85 * (t1 - t0))
        .min_by(|a, b| (a - target).abs().total_cmp(&(b - target).abs()))
        .unwrap_or_else(|| first_event.map_or(target, |e| target.max(e + 0.5 * (t1 - e))))
}

/// Maps `f` over `items` on `threads` threads (0: all cores), keeping order.
fn par_map<T: Sync, R: Send>(items: &[T], threads: usize, f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = if threads == 0 { std::thread::available_parallelism().map_or(1, |n| n.get()) } else { threads };
    let threads = threads.min(items.len()).max(1);
    if threads == 1 {
        return items.iter().map(&f).collect();
    }
    let next = std::sync::atomic::AtomicUsize::new(0);
    let out: Vec<std::sync::Mutex<Option<R>>> = items.iter().map(|_| std::sync::Mutex::new(None)).collect();
    std::thread::scope(|sc| {
        for _ in 0..threads {
            sc.spawn(|| {
                loop {
                    let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    if i >= items.len() {
                        break;
                    }
                    let r = f(&items[i]);
                    *out[i].lock().unwrap_or_else(|e| e.into_inner()) = Some(r);
                }
            });
        }
    });
    out.into_iter().map(|m| m.into_inner().unwrap_or_else(|e| e.into_inner()).expect("every item mapped")).collect()
}

/// The cause names of the candidate extensions, in the order they are tried.
pub const CAUSES: [&str; 5] = ["evolution_law", "second_state_variable", "cutoff_velocity", "slip_trend", "stiffness"];

fn builtin(n: &str) -> std::sync::Arc<dyn rsf_core::DynStateLaw> {
    rsf_laws::law_by_name(n, |q| Some(if q == "vc" { 0.01 } else { 1.0 })).expect("built-in law")
}

/// Applies the extension of `cause` to fit options (composable: a combination applies two).
/// `None` when it does not apply (e.g. the cut-off on top of a law change).
fn extend(o: &FitOptions, cause: &str, base_law: &str) -> Option<FitOptions> {
    let other = if base_law == "aging" { "slip" } else { "aging" };
    let mut o = o.clone();
    match cause {
        "evolution_law" => {
            if o.laws.iter().any(|l| l.name() != base_law) {
                return None;
            }
            o.laws = o.laws.iter().map(|_| builtin(other)).collect();
        }
        "second_state_variable" => {
            if o.laws.len() != 1 {
                return None;
            }
            let l = o.laws[0].clone();
            o.laws.push(l);
        }
        "cutoff_velocity" => {
            if o.laws[0].name() != base_law || o.laws.len() != 1 {
                return None;
            }
            o.laws[0] = builtin("kato-tullis");
        }
        "slip_trend" => {
            if o.fit_slip_trend {
                return None;
            }
            o.fit_slip_trend = true;
        }
        "stiffness" => {
            if o.fit_stiffness {
                return None;
            }
            o.fit_stiffness = true;
        }
        _ => return None,
    }
    Some(o)
}

fn effect_of(cause: &str, f: &FitResult) -> BTreeMap<String, serde_json::Value> {
    let mut effect = BTreeMap::new();
    let pr = &f.params;
    for c in cause.split('+') {
        match c {
            "evolution_law" => {
                effect.insert("law".into(), serde_json::json!(pr.laws.join("+")));
                if pr.b.len() == 2 {
                    // share of the evolution effect carried by the other law
                    effect.insert("b_other_fraction".into(), serde_json::json!(pr.b[1] / (pr.b[0] + pr.b[1])));
                }
            }
            "second_state_variable" => {
                // the states are exchangeable in the fit: report the slower one as the second
                let i = (0..pr.dc.len()).max_by(|&x, &y| pr.dc[x].total_cmp(&pr.dc[y])).unwrap_or(0);
                effect.insert("b2".into(), serde_json::json!(pr.b.get(i)));
                effect.insert("dc2".into(), serde_json::json!(pr.dc.get(i)));
            }
            "cutoff_velocity" => {
                effect.insert("vc".into(), serde_json::json!(pr.law_params.get("vc1")));
            }
            "slip_trend" => {
                effect.insert("g".into(), serde_json::json!(pr.g));
            }
            _ => {
                effect.insert("k".into(), serde_json::json!(pr.k));
            }
        }
    }
    effect
}

/// `from`'s parameters as starting values for the model `o` on `p`, keeping only the names that
/// model knows (a law parameter or a per-segment offset of the nested model may not be there).
fn initial_for(p: &Prepared, o: &FitOptions, from: &Params) -> Option<Vec<(String, f64)>> {
    let map = parameter_map(p, &FitOptions { initial: vec![], fix: vec![], ..o.clone() }).ok()?;
    let free = map.free_names();
    let global = ["mu0", "a", "k", "g"];
    Some(
        from.as_initial()
            .into_iter()
            .filter(|(n, _)| {
                global.contains(&n.as_str())
                    || free.iter().any(|x| x == n)
                    || ((n.starts_with('b') || n.starts_with("dc"))
                        && n.trim_start_matches(|c: char| c.is_ascii_alphabetic())
                            .parse::<usize>()
                            .is_ok_and(|i| i <= o.laws.len()))
            })
            .collect(),
    )
}

/// Fits `o` starting from `from` (an optimum of a nested model); the cut-off also from Vc at
/// and above the slowest sliding rate, keeping the best (far below every slip rate Kato–Tullis
/// is the Slip law, but there its gradient in Vc vanishes).
fn fit_from(p: &Prepared, o: &FitOptions, from: &Params, vmin: f64) -> Option<FitResult> {
    let mut o = o.clone();
    o.initial = initial_for(p, &o, from)?;
    let names = parameter_map(p, &FitOptions { initial: vec![], ..o.clone() }).ok()?.free_names();
    let has = |n: &str| names.iter().any(|x| x == n);
    if has("vc1") && !from.law_params.contains_key("vc1") {
        return [1e-3, 0.3, 3.0]
            .iter()
            .filter_map(|&m| {
                let mut oc = o.clone();
                oc.initial.push(("vc1".into(), m * vmin));
                fit(p, &oc).ok()
            })
            .max_by(|a, b| a.log_likelihood.total_cmp(&b.log_likelihood));
    }
    fit(p, &o).ok()
}

/// Per-event refits: each velocity step and each hold-and-reslide, fitted alone (from the second
/// half of the sliding before it to the end of the segment after it) with the baseline law.
fn event_windows(p: &Prepared) -> Vec<(usize, usize)> {
    let s = &p.segments;
    let mut out = vec![];
    for j in 1..s.len() {
        if s[j].v <= 0.0 {
            continue;
        }
        // the last sliding segment before j
        let Some(prev) = (0..j).rev().find(|&i| s[i].v > 0.0) else { continue };
        out.push((prev, j));
    }
    out
}

fn fit_event(p: &Prepared, opts: &FitOptions, base: &FitResult, prev: usize, j: usize) -> Option<EventFit> {
    let s = &p.segments;
    // the forward model runs from the start of the record (so the state entering the window is
    // the model's own, not an assumed steady state), the misfit counts only from the second half
    // of the sliding before the event to the end of the segment after it
    let mid = (s[prev].i0 + s[prev].i1) / 2;
    let mut o = FitOptions {
        laws: opts.laws.clone(),
        mu0_per_segment: false,
        fit_slip_trend: false,
        fit_stiffness: false,
        weighting: crate::fit::Weighting::Uniform,
        starts: 2,
        time_budget: 3.0,
        ..opts.clone()
    };
    let mut pw = prepare(&p.record, &s[..=j], &o).ok()?;
    o.initial = initial_for(&pw, &o, &base.params)?;
    o.initial.retain(|(n, _)| n != "mu0");
    let keep: Vec<usize> = (0..pw.used.len()).filter(|&r| pw.used[r] >= mid).collect();
    if keep.len() < 10 {
        return None;
    }
    pw.used = keep.iter().map(|&r| pw.used[r]).collect();
    pw.seg_of = keep.iter().map(|&r| pw.seg_of[r]).collect();
    pw.weights = vec![1.0; keep.len()];
    let f = fit(&pw, &o).ok()?;
    // a refit stopped by its time budget has not converged: its Dc would only add noise
    if f.stop_reason.contains(crate::fit::TIME_BUDGET_NOTE) {
        return None;
    }
    let ci = f.ci95.get("dc1")?;
    // the interval assumes independent noise: widen it by sqrt(n/n_eff) of the window residuals
    let inflate = (f.n as f64 / n_eff_of(&f)).sqrt();
    let hold = (j > prev + 1).then(|| (prev + 1..j).map(|i| s[i].t1 - s[i].t0).sum::<f64>());
    Some(EventFit {
        event: if hold.is_some() { "hold" } else { "step" }.into(),
        t: s[j].t0,
        v_before: s[prev].v,
        v_after: s[j].v,
        hold_s: hold,
        a: f.params.a,
        b: f.params.b[0],
        dc: f.params.dc[0],
        ln_dc_stderr: inflate * ((ci[1] / ci[0]).ln() / (2.0 * 1.96)).abs(),
        rms: f.rms,
    })
}

/// Consistency of the per-event Dc: reduced χ² of ln Dc about its weighted mean, and the slopes
/// of ln Dc against ln(step ratio) and ln(hold duration).
fn dc_consistency(ev: &[EventFit]) -> (Option<f64>, Option<f64>, Option<f64>) {
    let ok: Vec<&EventFit> = ev.iter().filter(|e| e.ln_dc_stderr.is_finite() && e.ln_dc_stderr > 0.0).collect();
    let chi2 = (ok.len() >= 2).then(|| {
        let w: Vec<f64> = ok.iter().map(|e| 1.0 / e.ln_dc_stderr.powi(2)).collect();
        let m = ok.iter().zip(&w).map(|(e, w)| w * e.dc.ln()).sum::<f64>() / w.iter().sum::<f64>();
        ok.iter().zip(&w).map(|(e, w)| w * (e.dc.ln() - m).powi(2)).sum::<f64>() / (ok.len() - 1) as f64
    });
    let line = |pts: Vec<(f64, f64)>| -> Option<f64> {
        let (x, y): (Vec<f64>, Vec<f64>) = pts.into_iter().unzip();
        slope_t(&x, &y, x.len() as f64).map(|s| s.0)
    };
    let steps = ok.iter().filter(|e| e.hold_s.is_none()).map(|e| ((e.v_after / e.v_before).ln(), e.dc.ln())).collect();
    let holds = ok.iter().filter_map(|e| e.hold_s.map(|h| (h.ln(), e.dc.ln()))).collect();
    (chi2, line(steps), line(holds))
}

enum Job {
    Candidate(&'static str),
    Event(usize, usize),
}

enum Done {
    Candidate(Option<Box<Candidate>>),
    Event(Option<EventFit>),
}

/// Runs the diagnosis on a record with its segments.
pub fn diagnose(rec: &Record, segs: &[Segment], opts: &DiagnoseOptions) -> Result<Diagnosis, FitError> {
    // uniform weights: the likelihood of noise of one σ everywhere, as lab noise is, so that
    // ΔBIC has its nominal calibration (with segment weights a free parameter acting only in
    // sparsely sampled segments would gain about mean(w²) per parameter on pure noise)
    let base_opts = &FitOptions { weighting: crate::fit::Weighting::Uniform, ..opts.fit.clone() };
    if base_opts.laws.len() != 1 {
        return Err(FitError::Setup("the baseline has one state variable".into()));
    }
    let timing = std::env::var_os("RSF_DIAGNOSE_TIMING").is_some();
    let clock = std::time::Instant::now();
    let base_law = base_opts.laws[0].name();
    let p: Prepared = prepare(rec, segs, base_opts)?;
    let base = fit(&p, base_opts)?;
    if timing {
        eprintln!("diagnose: baseline fitted in {:.2} s", clock.elapsed().as_secs_f64());
    }
    let mut ev = evidence(&base);
    ev.k_reload_slope = reload_stiffness(&p);
    let t_split = split_time(&p.record, &p.segments);
    let vmin = p.segments.iter().filter(|s| s.v > 0.0).map(|s| s.v).fold(f64::INFINITY, f64::min);
    // a candidate the data cannot constrain (e.g. b2 running to its bound) must not dominate the
    // run time: each candidate fit gets a third of the baseline budget
    let cand_opts = FitOptions { time_budget: (base_opts.time_budget / 3.0).max(2.0), ..base_opts.clone() };
    // the baseline's held-out fit first: every extension's held-out fit starts from it
    let ho_base = if opts.heldout {
        let o = FitOptions { mu0_per_segment: false, ..base_opts.clone() };
        heldout(&p.record, &p.segments, &o, &|pt: &Prepared, ot: &FitOptions| fit(pt, ot).ok(), t_split)
    } else {
        None
    };
    let mut jobs = vec![];
    for c in CAUSES {
        if c == "stiffness" && base_opts.fit_stiffness {
            continue;
        }
        jobs.push(Job::Candidate(c));
    }
    if opts.per_segment {
        jobs.extend(event_windows(&p).into_iter().map(|(a, b)| Job::Event(a, b)));
    }
    let done_count = std::sync::atomic::AtomicUsize::new(0);
    let total = jobs.len();
    let report = |what: &str| {
        let d = done_count.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if let Some(pr) = &opts.progress {
            pr(d, total, what);
        }
    };
    // the starting points of an extension's fit from a nested optimum: that optimum, and for a
    // free stiffness also the reload-slope k and softer machines (a stiff nominal k leaves no
    // gradient in k, and series compliance of gouge and assembly only ever softens a machine)
    let fit_best = |pc: &Prepared, o: &FitOptions, from: &Params| -> Option<FitResult> {
        let first = fit_from(pc, o, from, vmin);
        // only when the fit from the nominal k did not soften the machine: then the nominal may
        // sit where k has no gradient
        let stuck = first.as_ref().is_none_or(|f| f.params.k > 0.8 * from.k);
        if !(o.fit_stiffness && !base_opts.fit_stiffness && stuck) {
            return first;
        }
        let mut ks = vec![from.k / 4.0, from.k / 16.0];
        ks.extend(ev.k_reload_slope.filter(|k| (k / from.k).ln().abs() > 0.2));
        ks.into_iter()
            .filter_map(|k| fit_from(pc, o, &Params { k, ..from.clone() }, vmin))
            .chain(first)
            .max_by(|a, b| a.log_likelihood.total_cmp(&b.log_likelihood))
    };
    let run_candidate = |cause: &'static str| -> Option<Candidate> {
        let t = std::time::Instant::now();
        let mut tries: Vec<(String, FitOptions)> = vec![];
        if let Some(o) = extend(&cand_opts, cause, &base_law) {
            tries.push((describe(cause, &base_law), o));
        }
        // the other law alone, or a mixture: a state of each law sharing one Dc (healing partly
        // by time, partly by slip), whichever scores better
        if cause == "evolution_law" {
            let other = if base_law == "aging" { "slip" } else { "aging" };
            let mut om = cand_opts.clone();
            om.laws.push(builtin(other));
            om.fix.push("dc1-dc2=0".into());
            tries.push((format!("a mixture: {base_law} and {other} states sharing Dc"), om));
        }
        let (extension, o, pc, f) = tries
            .into_iter()
            .filter_map(|(ext, o)| {
                let pc = prepare(rec, segs, &o).ok()?;
                let f = fit_best(&pc, &o, &base.params)?;
                // a mixture has both states healing (b of one sign); b of opposite signs is a
                // difference of laws, not a share of time-dependent healing
                let mixture = o.laws.len() == 2 && o.laws[0].name() != o.laws[1].name();
                let ok = !mixture || f.params.b[0] * f.params.b[1] > 0.0;
                ok.then_some((ext, o, pc, f))
            })
            .min_by(|a, b| scores(&base, &a.3, ev.n_effective).0.total_cmp(&scores(&base, &b.3, ev.n_effective).0))?;
        let (dbic, daic) = scores(&base, &f, ev.n_effective);
        let ho = match (&ho_base, opts.heldout) {
            (Some((_, ft_base)), true) => heldout(
                &pc.record,
                &pc.segments,
                &o,
                &|pt: &Prepared, ot: &FitOptions| fit_best(pt, ot, &ft_base.params),
                t_split,
            ),
            _ => None,
        };
        // parameters at a bound that the baseline did not already have there
        let at_bound = f.at_bound.iter().filter(|n| !base.at_bound.contains(n)).cloned().collect();
        Some(Candidate {
            cause: cause.into(),
            extension,
            delta_bic: dbic,
            delta_aic: daic,
            rms_ratio: f.rms / base.rms,
            heldout_rms_before: ho_base.as_ref().map(|h| h.0),
            heldout_rms_after: ho.as_ref().map(|h| h.0),
            effect: effect_of(cause, &f),
            seconds: t.elapsed().as_secs_f64(),
            at_bound,
            fit: Some(f),
            heldout_fit: ho.map(|h| h.1),
            options: Some(o),
        })
    };
    let results = par_map(&jobs, opts.threads, |job| {
        let t = std::time::Instant::now();
        let (what, out) = match job {
            Job::Candidate(c) => (c.to_string(), Done::Candidate(run_candidate(c).map(Box::new))),
            Job::Event(a, b) => (format!("segment {}", b + 1), Done::Event(fit_event(&p, base_opts, &base, *a, *b))),
        };
        if timing {
            eprintln!("diagnose: {what} in {:.2} s", t.elapsed().as_secs_f64());
        }
        report(&what);
        out
    });
    let mut candidates = vec![];
    let mut per_segment = vec![];
    for r in results {
        match r {
            Done::Candidate(Some(c)) => candidates.push(*c),
            Done::Candidate(None) => {}
            Done::Event(e) => per_segment.extend(e),
        }
    }
    (ev.dc_consistency_chi2, ev.dc_vs_ln_step, ev.dc_vs_ln_hold) = dc_consistency(&per_segment);
    candidates.sort_by(|a, b| a.delta_bic.total_cmp(&b.delta_bic));
    // the held-out test passes when the extension predicts no more than 5% worse; it fails when
    // the extension's training fit fails where the baseline's did not (an extension the training
    // part cannot pin down is the overfitting the test is there to catch)
    let heldout_ok = |b: Option<f64>, a: Option<f64>| match (b, a) {
        (Some(b), Some(a)) => a <= 1.05 * b,
        (Some(_), None) => false,
        _ => true,
    };
    // why a decisive candidate is not eligible: it predicts the held-out part worse (it fits
    // the training data better but overfits), or its fit ran to a physical bound (the data do
    // not constrain the extension: e.g. a second state turned into a linear trend)
    let ineligible = |c: &Candidate| -> Option<String> {
        if !heldout_ok(c.heldout_rms_before, c.heldout_rms_after) {
            Some(match c.heldout_rms_after {
                Some(_) => format!("{} predicted the held-out part worse", c.cause),
                None => format!("{} could not be fitted to the held-out training part", c.cause),
            })
        } else if !c.at_bound.is_empty() {
            Some(format!("{} ran to a bound ({})", c.cause, c.at_bound.join(", ")))
        } else {
            None
        }
    };
    let decisive: Vec<&Candidate> = candidates.iter().filter(|c| c.delta_bic < DECISIVE).collect();
    let chosen = decisive.iter().copied().find(|c| ineligible(c).is_none());
    let rejected: Vec<String> =
        decisive.iter().take_while(|c| ineligible(c).is_some()).filter_map(|c| ineligible(c)).collect();
    // the runner-up: the best other credible candidate (set-aside ones are named in the reason),
    // else the best other one
    let others = || candidates.iter().filter(|c| chosen.is_none_or(|ch| ch.cause != c.cause));
    // (with no winner, simply the best-scoring candidate)
    let runner_up = others()
        .find(|c| chosen.is_none() || ineligible(c).is_none())
        .or_else(|| others().next())
        .map(|c| (c.cause.clone(), c.delta_bic));
    let rejected_note = if rejected.is_empty() {
        String::new()
    } else {
        format!(" (better-scoring but set aside: {})", rejected.join("; "))
    };
    // a second cause: the winner combined with each other decisive candidate, scored against
    // the winner alone with the winner's n_eff
    let secondary = match chosen {
        Some(c1) if opts.combinations => {
            let f1 = c1.fit.as_ref().expect("candidates carry their fit");
            // the two best other credible candidates: further ones explain less and cost as much
            let others: Vec<&Candidate> =
                decisive.iter().copied().filter(|c| ineligible(c).is_none() && c.cause != c1.cause).take(2).collect();
            let n1 = n_eff_of(f1);
            let o1 = c1.options.clone();
            let tries = par_map(&others, opts.threads, |c2| -> Option<Secondary> {
                let t = std::time::Instant::now();
                let o = extend(o1.as_ref()?, &c2.cause, &base_law)?;
                let pc = prepare(rec, segs, &o).ok()?;
                // from the winner's optimum, the added extension at its neutral value (as the
                // candidates start from the baseline's)
                let f = fit_best(&pc, &o, &f1.params);
                if timing {
                    eprintln!(
                        "diagnose: {} + {} in {:.2} s: {}",
                        c1.cause,
                        c2.cause,
                        t.elapsed().as_secs_f64(),
                        f.as_ref().map_or("failed".to_string(), |f| format!("rms ratio {:.4}", f.rms / f1.rms))
                    );
                }
                let f = f?;
                let (dbic, _) = scores(f1, &f, n1);
                // held out: from the winner's training optimum
                let ho = match (&c1.heldout_fit, opts.heldout) {
                    (Some(ft1), true) => heldout(
                        &pc.record,
                        &pc.segments,
                        &o,
                        &|pt: &Prepared, ot: &FitOptions| fit_best(pt, ot, &ft1.params),
                        t_split,
                    )
                    .map(|h| h.0),
                    _ => None,
                };
                Some(Secondary {
                    cause: c2.cause.clone(),
                    delta_bic: dbic,
                    rms_ratio: f.rms / f1.rms,
                    heldout_rms_before: c1.heldout_rms_after,
                    heldout_rms_after: ho,
                    effect: effect_of(&format!("{}+{}", c1.cause, c2.cause), &f),
                    fit: f,
                })
            });
            tries
                .into_iter()
                .flatten()
                .filter(|s| {
                    s.delta_bic < DECISIVE
                        && heldout_ok(s.heldout_rms_before, s.heldout_rms_after)
                        && s.fit.at_bound.iter().all(|n| f1.at_bound.contains(n))
                })
                .min_by(|a, b| a.delta_bic.total_cmp(&b.delta_bic))
        }
        _ => None,
    };
    let (cause, reason, extended, gain, effect, confidence) = match chosen {
        Some(c) => (
            c.cause.clone(),
            format!(
                "{} improves the fit decisively: ΔBIC = {:.1} with n_eff = {:.0} (threshold {DECISIVE}), rms ratio {:.3}{}{}{}",
                c.extension,
                c.delta_bic,
                ev.n_effective,
                c.rms_ratio,
                match (c.heldout_rms_before, c.heldout_rms_after) {
                    (Some(b), Some(a)) => format!(", held-out rms {b:.2e} → {a:.2e}"),
                    _ => String::new(),
                },
                match &secondary {
                    Some(s) => format!("; adding {} gains a further ΔBIC = {:.1}", s.cause, s.delta_bic),
                    None => String::new(),
                },
                rejected_note
            ),
            c.fit.clone(),
            Some(Gain {
                delta_bic: c.delta_bic,
                delta_aic: c.delta_aic,
                rms_ratio: c.rms_ratio,
                heldout_rms_before: c.heldout_rms_before,
                heldout_rms_after: c.heldout_rms_after,
            }),
            c.effect.clone(),
            c.delta_bic,
        ),
        None => (
            "none".into(),
            match candidates.first() {
                Some(_) if !rejected.is_empty() => format!(
                    "no extension is both decisive and credible: {} (n_eff = {:.0}); the baseline stands",
                    rejected.join("; "),
                    ev.n_effective
                ),
                Some(b) => format!(
                    "no extension earns its parameters: best is {} with ΔBIC = {:.1} (needs < {DECISIVE}) with n_eff = {:.0}",
                    b.extension, b.delta_bic, ev.n_effective
                ),
                None => "no candidate could be fitted".into(),
            },
            None,
            None,
            BTreeMap::new(),
            candidates.first().map(|b| b.delta_bic).unwrap_or(0.0),
        ),
    };
    if timing {
        eprintln!("diagnose: total {:.2} s", clock.elapsed().as_secs_f64());
    }
    Ok(Diagnosis {
        cause,
        confidence,
        reason,
        evidence: ev,
        baseline: base,
        extended,
        gain,
        effect,
        runner_up,
        candidates,
        secondary,
        per_segment,
        heldout_split_t: t_split,
    })
}

fn describe(cause: &str, base_law: &str) -> String {
    let other = if base_law == "aging" { "slip" } else { "aging" };
    match cause {
        "evolution_law" => format!("{other} law instead of {base_law}"),
        "second_state_variable" => format!("second state variable ({base_law})"),
        "cutoff_velocity" => "Kato–Tullis law with cut-off velocity Vc".into(),
        "slip_trend" => "slip trend g·slip".into(),
        _ => "stiffness fitted".into(),
    }
}
