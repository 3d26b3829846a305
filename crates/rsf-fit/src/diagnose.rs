//! Diagnosis: what a fitted model gets wrong, which extension fixes it, and the gain.
//!
//! 1. Fit the baseline (one state variable, Slip or Aging law).
//! 2. Fit each candidate extension: the other law (`evolution_law`), a second state variable
//!    (`second_state_variable`), the Kato–Tullis cut-off (`cutoff_velocity`), a slip trend g·δ
//!    (`slip_trend`), a free stiffness (`stiffness`).
//! 3. Score each by ΔBIC computed with the *effective* number of independent samples: lab
//!    residuals are correlated in time, and with n samples of AR(1) noise of lag-one
//!    correlation ρ the data carry about n (1 − ρ)/(1 + ρ) independent values. Scaling the
//!    log-likelihood difference by n_eff/n keeps correlated noise from passing for an effect.
//! 4. Held-out test: fit on the first part of the record, predict the rest, before and after.
//! 5. The cause is the candidate with the lowest ΔBIC_eff if it is below −10 ("very strong"
//!    evidence, Kass & Raftery 1995) and its held-out misfit is not worse than the baseline's;
//!    else `none`. The runner-up and every score are reported.

use crate::data::Record;
use crate::fit::{FitError, FitOptions, FitResult, Prepared, fit, model_curve, parameter_map, prepare};
use crate::segment::Segment;
use serde::Serialize;
use std::collections::BTreeMap;

/// Decisive ΔBIC_eff (negative: the extension is better).
pub const DECISIVE: f64 = -10.0;

/// Diagnosis settings.
#[derive(Clone, Debug)]
pub struct DiagnoseOptions {
    /// Baseline fit settings (one state variable).
    pub fit: FitOptions,
    /// Run the held-out test.
    pub heldout: bool,
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
}

/// One candidate extension and its score.
#[derive(Clone, Debug, Serialize)]
pub struct Candidate {
    /// Cause name.
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
    /// The fit.
    #[serde(skip)]
    pub fit: Option<FitResult>,
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

fn evidence(base: &FitResult) -> Evidence {
    let c = &base.curve;
    let res: Vec<f64> = c.data.iter().zip(&c.model).map(|(d, m)| d - m).collect();
    let n = res.len() as f64;
    let rho = lag1(&res).clamp(-0.99, 0.99);
    let n_eff = (n * (1.0 - rho) / (1.0 + rho)).clamp(2.0, n);
    // residual trend against load-point displacement
    let xm = c.load_point.iter().sum::<f64>() / n;
    let rm = res.iter().sum::<f64>() / n;
    let sxx: f64 = c.load_point.iter().map(|x| (x - xm).powi(2)).sum();
    let sxr: f64 = c.load_point.iter().zip(&res).map(|(x, r)| (x - xm) * (r - rm)).sum();
    let slope = if sxx > 0.0 { sxr / sxx } else { 0.0 };
    let resid_var = res.iter().map(|r| (r - rm).powi(2)).sum::<f64>() / n;
    let se = (resid_var / sxx.max(1e-300) * n / n_eff).sqrt();
    let mut seg_rms: Vec<f64> = base.segments.iter().filter(|s| s.n > 0).map(|s| s.rms).collect();
    seg_rms.sort_by(f64::total_cmp);
    let med = seg_rms.get(seg_rms.len() / 2).copied().unwrap_or(0.0);
    let noise = (c.data.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() / (2.0 * (n - 1.0))).sqrt();
    Evidence {
        residual_lag1: rho,
        n_effective: n_eff,
        residual_trend_per_um: slope,
        residual_trend_t: slope / se.max(1e-300),
        segment_rms_ratio: seg_rms.last().copied().unwrap_or(0.0) / med.max(1e-300),
        misfit_over_noise: base.rms / noise.max(1e-300),
    }
}

/// ΔBIC and ΔAIC of `ext` against `base` with the log-likelihood scaled to n_eff.
fn scores(base: &FitResult, ext: &FitResult, n_eff: f64) -> (f64, f64) {
    let n = base.n as f64;
    let dll = (ext.log_likelihood - base.log_likelihood) * n_eff / n;
    let dk = ext.n_free as f64 - base.n_free as f64;
    (-2.0 * dll + dk * n_eff.ln(), -2.0 * dll + 2.0 * dk)
}

/// Held-out rms: fit on the record before `t_split`, predict after it.
fn heldout(rec: &Record, segs: &[Segment], opts: &FitOptions, t_split: f64) -> Option<f64> {
    let train = rec.window(rec.time[0], t_split);
    let tsegs: Vec<Segment> = segs
        .iter()
        .filter(|s| s.t0 < t_split)
        .map(|s| {
            let mut s = s.clone();
            s.i1 = s.i1.min(train.len() - 1);
            s.t1 = s.t1.min(t_split);
            s
        })
        .collect();
    let o = FitOptions { mu0_per_segment: false, ..opts.clone() };
    let pt = prepare(&train, &tsegs, &o).ok()?;
    let ft = fit(&pt, &o).ok()?;
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
    (n > 0).then(|| (ss / n as f64).sqrt())
}

/// Where to split for the held-out test: the start of the segment nearest 2/3 of the record.
fn split_time(rec: &Record, segs: &[Segment]) -> f64 {
    let (t0, t1) = (rec.time[0], rec.time[rec.len() - 1]);
    let target = t0 + (t1 - t0) * 2.0 / 3.0;
    segs.iter()
        .skip(2)
        .map(|s| s.t0)
        .filter(|t| (t - t0) > 0.4 * (t1 - t0) && (t - t0) < 0.85 * (t1 - t0))
        .min_by(|a, b| (a - target).abs().total_cmp(&(b - target).abs()))
        .unwrap_or(target)
}

/// Runs the diagnosis on a record with its segments.
pub fn diagnose(rec: &Record, segs: &[Segment], opts: &DiagnoseOptions) -> Result<Diagnosis, FitError> {
    let base_opts = &opts.fit;
    if base_opts.laws.len() != 1 {
        return Err(FitError::Setup("the baseline has one state variable".into()));
    }
    let base_law = base_opts.laws[0].name();
    let p: Prepared = prepare(rec, segs, base_opts)?;
    let base = fit(&p, base_opts)?;
    let ev = evidence(&base);
    let t_split = split_time(&p.record, &p.segments);
    let ho_base = if opts.heldout { heldout(&p.record, &p.segments, base_opts, t_split) } else { None };
    let law = |n: &str| rsf_laws::law_by_name(n, |q| Some(if q == "vc" { 0.01 } else { 1.0 })).expect("built-in law");
    let other = if base_law == "aging" { "slip" } else { "aging" };
    let mut tries: Vec<(&str, String, FitOptions)> = vec![];
    tries.push((
        "evolution_law",
        format!("{other} law instead of {base_law}"),
        FitOptions { laws: vec![law(other)], ..base_opts.clone() },
    ));
    tries.push((
        "second_state_variable",
        format!("second state variable ({base_law})"),
        FitOptions { laws: vec![law(&base_law), law(&base_law)], ..base_opts.clone() },
    ));
    tries.push((
        "cutoff_velocity",
        "Kato–Tullis law with cut-off velocity Vc".into(),
        FitOptions { laws: vec![law("kato-tullis")], ..base_opts.clone() },
    ));
    tries.push(("slip_trend", "slip trend g·slip".into(), FitOptions { fit_slip_trend: true, ..base_opts.clone() }));
    if !base_opts.fit_stiffness {
        tries.push(("stiffness", "stiffness fitted".into(), FitOptions { fit_stiffness: true, ..base_opts.clone() }));
    }
    // every candidate starts from the baseline optimum (Kato–Tullis with Vc far below any slip
    // rate, where it is the Slip law), so an extension can only improve on the baseline
    let bp = &base.params;
    let vmin = p.segments.iter().filter(|s| s.v > 0.0).map(|s| s.v).fold(f64::INFINITY, f64::min);
    let from_base = |o: &mut FitOptions, vc: bool| {
        o.initial = vec![
            ("mu0".into(), bp.mu0),
            ("a".into(), bp.a),
            ("b1".into(), bp.b[0]),
            ("dc1".into(), bp.dc[0]),
            ("k".into(), bp.k),
        ];
        if vc {
            o.initial.push(("vc1".into(), 1e-3 * vmin));
        }
    };
    for (cause, _, o) in tries.iter_mut() {
        match *cause {
            "cutoff_velocity" => from_base(o, true),
            "slip_trend" | "stiffness" => from_base(o, false),
            _ => {}
        }
    }
    // a candidate the data cannot constrain (e.g. b2 running to its bound) must not dominate the
    // run time: each candidate fit gets a third of the baseline budget
    for (_, _, o) in tries.iter_mut() {
        o.time_budget = (base_opts.time_budget / 3.0).max(2.0);
    }
    let mut candidates = vec![];
    for (cause, ext, o) in tries {
        let t = std::time::Instant::now();
        let Ok(pc) = prepare(rec, segs, &o) else { continue };
        // the cut-off: Vc far below every slip rate is the baseline, but there the gradient in
        // Vc vanishes; also start at the slowest sliding rate and above it, keep the best
        let f = if cause == "cutoff_velocity" {
            [1e-3, 0.3, 3.0]
                .iter()
                .filter_map(|&m| {
                    let mut oc = o.clone();
                    if let Some(v) = oc.initial.iter_mut().find(|(n, _)| n == "vc1") {
                        v.1 = m * vmin;
                    }
                    fit(&pc, &oc).ok()
                })
                .min_by(|a, b| a.rms.total_cmp(&b.rms))
        } else {
            fit(&pc, &o).ok()
        };
        let Some(f) = f else { continue };
        if std::env::var_os("RSF_DIAGNOSE_TIMING").is_some() {
            eprintln!("diagnose: {cause} fitted in {:.2} s", t.elapsed().as_secs_f64());
        }
        let (dbic, daic) = scores(&base, &f, ev.n_effective);
        let ho = if opts.heldout { heldout(&pc.record, &pc.segments, &o, t_split) } else { None };
        let mut effect = BTreeMap::new();
        let pr = &f.params;
        match cause {
            "evolution_law" => {
                effect.insert("law".into(), serde_json::json!(other));
            }
            "second_state_variable" => {
                effect.insert("b2".into(), serde_json::json!(pr.b[1]));
                effect.insert("dc2".into(), serde_json::json!(pr.dc[1]));
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
        candidates.push(Candidate {
            cause: cause.into(),
            extension: ext,
            delta_bic: dbic,
            delta_aic: daic,
            rms_ratio: f.rms / base.rms,
            heldout_rms_before: ho_base,
            heldout_rms_after: ho,
            effect,
            fit: Some(f),
        });
    }
    candidates.sort_by(|a, b| a.delta_bic.total_cmp(&b.delta_bic));
    let best = candidates.first();
    let heldout_ok = |c: &Candidate| match (c.heldout_rms_before, c.heldout_rms_after) {
        (Some(b), Some(a)) => a <= 1.05 * b,
        _ => true,
    };
    let chosen = best.filter(|c| c.delta_bic < DECISIVE && heldout_ok(c));
    let runner_up = candidates.get(if chosen.is_some() { 1 } else { 0 }).map(|c| (c.cause.clone(), c.delta_bic));
    let (cause, reason, extended, gain, effect, confidence) = match chosen {
        Some(c) => (
            c.cause.clone(),
            format!(
                "{} improves the fit decisively: ΔBIC = {:.1} with n_eff = {:.0} (threshold {DECISIVE}), rms ratio {:.3}{}",
                c.extension,
                c.delta_bic,
                ev.n_effective,
                c.rms_ratio,
                match (c.heldout_rms_before, c.heldout_rms_after) {
                    (Some(b), Some(a)) => format!(", held-out rms {b:.2e} → {a:.2e}"),
                    _ => String::new(),
                }
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
            match best {
                Some(b) => format!(
                    "no extension earns its parameters: best is {} with ΔBIC = {:.1} (needs < {DECISIVE}) with n_eff = {:.0}",
                    b.extension, b.delta_bic, ev.n_effective
                ),
                None => "no candidate could be fitted".into(),
            },
            None,
            None,
            BTreeMap::new(),
            best.map(|b| b.delta_bic).unwrap_or(0.0),
        ),
    };
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
    })
}
