//! The design itself: the credible models, the proposals scored in parallel, the ranking.

use super::criterion::{Whitened, expected_lack_of_fit};
use super::result::{Design, DesignModel, PairScore, PredictedCurve, Ranked};
use super::space::{Proposal, SEQUENCE_SEEDS, Sampling, sampling, sequences, singles, standard};
use super::{DesignOptions, SCORE_TIE, SETTLE_DCHI2};
use crate::data::Record;
use crate::diagnose::{Cause, DiagnoseOptions, Diagnosis, NoiseModel, diagnose, noisy, par_map};
use crate::fit::{FitError, FitOptions, FitResult, LoadingMode, ParamMap, Prepared, parameter_map, predict, prepare};
use crate::segment::Segment;
use nalgebra::DMatrix;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// Attempts per wanted draw before a model makes do with fewer.
const DRAW_ATTEMPTS: usize = 20;

/// A credible model, ready to predict.
struct Credible {
    info: DesignModel,
    opts: FitOptions,
    p: Prepared,
    map: ParamMap,
    theta: Vec<f64>,
    /// S with S Sᵀ = the inflated covariance of θ.
    sqrt_cov: DMatrix<f64>,
    draws: Vec<Vec<f64>>,
}

/// One model's raw predictions of one proposal.
struct Raw {
    central: Vec<f64>,
    jac: Vec<f64>,
    draws: Vec<Vec<f64>>,
}

/// Diagnoses the record, then designs the next segment ([`design_from`]).
pub fn design(
    rec: &Record,
    segs: &[Segment],
    dopts: &DiagnoseOptions,
    o: &DesignOptions,
) -> Result<(Diagnosis, Design), FitError> {
    let d = diagnose(rec, segs, dopts)?;
    let out = design_from(rec, segs, &d, o)?;
    Ok((d, out))
}

/// The next segment that best tells apart the credible models of the diagnosis `d` of `rec`
/// (with its segments `segs`).
pub fn design_from(rec: &Record, segs: &[Segment], d: &Diagnosis, o: &DesignOptions) -> Result<Design, FitError> {
    if !(o.v_range.0 > 0.0 && o.v_range.1 >= o.v_range.0 && o.v_range.1.is_finite()) {
        return Err(FitError::Setup(format!("v-range {:?}: needs 0 < low ≤ high", o.v_range)));
    }
    if !(o.max_time > 0.0 && o.max_hold >= 0.0 && o.max_slip > 0.0) {
        return Err(FitError::Setup("max-time and max-slip must be positive, max-hold not negative".into()));
    }
    let base_opts = d
        .baseline_options
        .clone()
        .ok_or_else(|| FitError::Setup("the diagnosis carries no baseline options to design from".into()))?;
    let mut notes = vec![];
    let models = credible(d, &base_opts, o, &mut notes);
    let last = segs.last().ok_or_else(|| FitError::Setup("the record has no segments".into()))?;
    let v_end = if last.v > 0.0 { last.v } else { segs.iter().rev().find(|s| s.v > 0.0).map_or(1.0, |s| s.v) };
    let (dt_slide, dt_hold) = intervals(rec, segs);
    let best_fit = models[0].1;
    let noise = noisy(best_fit).model;
    if d.loading == LoadingMode::Record {
        notes.push(
            "the diagnosis fitted with the measured load point; the predictions run the detected protocol".into(),
        );
    }
    let models: Vec<Credible> = models
        .into_iter()
        .enumerate()
        .filter_map(|(i, (info, fit, opts))| prepare_model(rec, segs, info, fit, opts, o, i as u64).ok())
        .collect();
    if models.len() < 2 {
        let only = models.first().map_or("none".to_string(), |m| m.info.name.clone());
        return Ok(Design {
            cause: d.cause,
            summary: format!(
                "one credible model ({only}): the record already decides between the causes; no next segment is needed to tell them apart"
            ),
            models: models.into_iter().map(|m| m.info).collect(),
            v_end,
            dt_slide_s: dt_slide,
            dt_hold_s: dt_hold,
            noise,
            proposals: vec![],
            standard: None,
            curves: vec![],
            notes,
        });
    }
    // the slip scale of the proposals: the baseline's Dc (an added state's Dc may be
    // unconstrained; the grid's 30 Dc reaches the slow states a record can show)
    let dc_ref = d.baseline.params.dc.first().copied().unwrap_or(10.0).max(1e-3);
    let ctx = Scorer { models: &models, noise: &noise, dt_slide, dt_hold };
    let first = singles(v_end, dc_ref, o);
    let seq_guess = if o.sequences { SEQUENCE_SEEDS * (SEQUENCE_SEEDS - 1) } else { 0 };
    let total = first.len() + seq_guess;
    let done = std::sync::atomic::AtomicUsize::new(0);
    let tick = |what: &str| {
        let k = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if let Some(pr) = &o.progress {
            pr(k.min(total), total, what);
        }
    };
    let mut scored: Vec<Ranked> = par_map(&first, o.threads, |p| {
        let r = ctx.score(p, v_end).map(|(r, _)| r);
        tick("proposal");
        r
    })
    .into_iter()
    .flatten()
    .collect();
    if scored.is_empty() {
        return Err(FitError::Setup("no proposal could be predicted by every credible model".into()));
    }
    rank(&mut scored);
    if o.sequences {
        let seeds: Vec<Proposal> = scored.iter().take(SEQUENCE_SEEDS).map(|r| r.proposal.clone()).collect();
        let seqs = sequences(&seeds, o);
        scored.extend(
            par_map(&seqs, o.threads, |p| {
                let r = ctx.score(p, v_end).map(|(r, _)| r);
                tick("sequence");
                r
            })
            .into_iter()
            .flatten(),
        );
        rank(&mut scored);
    }
    let best = scored[0].proposal.clone();
    let curves = ctx.score(&best, v_end).map(|(_, c)| c).unwrap_or_default();
    let standard = ctx.score(&standard(v_end, scored[0].machine_time_s, o.max_slip), v_end).map(|(r, _)| r);
    let summary = summarize(&scored[0], standard.as_ref(), &models);
    Ok(Design {
        cause: d.cause,
        models: models.into_iter().map(|m| m.info).collect(),
        v_end,
        dt_slide_s: dt_slide,
        dt_hold_s: dt_hold,
        noise,
        proposals: scored,
        standard,
        curves,
        summary,
        notes,
    })
}

/// The credible models, best first: the model of the diagnosis's cause (the baseline for
/// `none`: a candidate that scores better but failed a check is not yet the answer), and each
/// candidate with a fit, no parameter at a bound, an effect the record resolves, and a ΔBIC
/// within the window of the best, its Occam penalty not counted.
fn credible<'a>(
    d: &'a Diagnosis,
    base_opts: &FitOptions,
    o: &DesignOptions,
    notes: &mut Vec<String>,
) -> Vec<(DesignModel, &'a FitResult, FitOptions)> {
    let base_law = base_opts.laws[0].name();
    let entry = |name: String, cause: Cause, extension: String, delta_bic: f64, f: &FitResult| DesignModel {
        name,
        cause,
        extension,
        delta_bic,
        params: f.params.clone(),
        stderr_theta: vec![],
        draws: 0,
    };
    let mut all: Vec<(DesignModel, &FitResult, FitOptions, f64)> = vec![(
        entry("baseline".into(), Cause::None, format!("{base_law} law, one state"), 0.0, &d.baseline),
        &d.baseline,
        base_opts.clone(),
        0.0,
    )];
    let ln_n = (d.baseline.n.max(3) as f64).ln();
    for c in &d.candidates {
        let (Some(f), Some(oc)) = (&c.fit, &c.options) else { continue };
        if !c.at_bound.is_empty() || c.unresolved.is_some() {
            notes.push(format!(
                "{} left out: {}",
                c.cause,
                c.unresolved.clone().unwrap_or_else(|| format!("{} at a bound", c.at_bound.join(", ")))
            ));
            continue;
        }
        // the parameters it adds, from the two criteria: ΔBIC − ΔAIC = Δk (ln n − 2)
        let dk = ((c.delta_bic - c.delta_aic) / (ln_n - 2.0)).max(0.0);
        all.push((entry(c.cause.as_str().into(), c.cause, c.extension.clone(), c.delta_bic, f), f, oc.clone(), dk));
    }
    let best = all.iter().map(|m| m.0.delta_bic).fold(f64::INFINITY, f64::min);
    // within the window of the best, Occam's penalty for the parameters it adds not counted
    // against it: an extension that gains nothing (the effect where the record never went)
    // stays credible while the best is the baseline
    let mut keep: Vec<(DesignModel, &FitResult, FitOptions)> = all
        .into_iter()
        .filter(|(m, _, _, dk)| m.cause == d.cause || m.delta_bic - best <= o.credible_dbic + dk * ln_n)
        .map(|(m, f, oc, _)| (m, f, oc))
        .collect();
    keep.sort_by(|a, b| a.0.delta_bic.total_cmp(&b.0.delta_bic));
    keep
}

/// A model with its parameter map, inflated covariance square root and draws.
fn prepare_model(
    rec: &Record,
    segs: &[Segment],
    mut info: DesignModel,
    fit: &FitResult,
    opts: FitOptions,
    o: &DesignOptions,
    index: u64,
) -> Result<Credible, FitError> {
    let p = prepare(rec, segs, &opts)?;
    let map = parameter_map(&p, &opts)?;
    let m = fit.theta.len();
    if map.free_names().len() != m || fit.cov_theta.len() != m * m {
        return Err(FitError::Setup(format!("{}: its fit has no covariance", info.name)));
    }
    // correlated residuals carry n_eff samples' worth of information, not n
    let nm = noisy(fit).model;
    let inflate = (fit.curve.data.len() as f64 / nm.n_effective.max(1.0)).max(1.0);
    let cov = DMatrix::from_row_slice(m, m, &fit.cov_theta) * inflate;
    let cov = (&cov + cov.transpose()) * 0.5;
    let eig = cov.clone().symmetric_eigen();
    let sqrt_cov = &eig.eigenvectors * DMatrix::from_diagonal(&eig.eigenvalues.map(|l| l.max(0.0).sqrt()));
    let mut rng = ChaCha8Rng::seed_from_u64(o.seed.wrapping_mul(0x9E37_79B9).wrapping_add(index));
    // draws outside the physical bounds are drawn again (a truncated normal), up to
    // DRAW_ATTEMPTS per draw wanted: a parameter the record leaves unconstrained keeps the
    // draws that are physical
    let mut draws = vec![];
    for _ in 0..o.draws * DRAW_ATTEMPTS {
        if draws.len() == o.draws {
            break;
        }
        let z = nalgebra::DVector::from_fn(m, |_, _| StandardNormal.sample(&mut rng));
        let dz = &sqrt_cov * z;
        let th: Vec<f64> = fit.theta.iter().zip(dz.iter()).map(|(a, b)| a + b).collect();
        if map.in_bounds(&th) {
            draws.push(th);
        }
    }
    info.stderr_theta = map.free_names().into_iter().zip((0..m).map(|k| cov[(k, k)].sqrt())).collect();
    info.draws = draws.len();
    Ok(Credible { info, opts, p, map, theta: fit.theta.clone(), sqrt_cov, draws })
}

/// The sampling interval in holds of a record that has none, s: labs slow their sampling in
/// holds, to 1 Hz or less.
const DEFAULT_HOLD_INTERVAL: f64 = 1.0;

/// The record's median sampling intervals while sliding and in holds, s (in holds
/// [`DEFAULT_HOLD_INTERVAL`] when it has none, or its sliding interval if that is longer).
fn intervals(rec: &Record, segs: &[Segment]) -> (f64, f64) {
    let median = |moving: bool| {
        let mut d: Vec<f64> = segs
            .iter()
            .filter(|s| (s.v > 0.0) == moving && s.i1 > s.i0)
            .flat_map(|s| rec.time[s.i0..=s.i1].windows(2).map(|w| w[1] - w[0]))
            .filter(|d| *d > 0.0)
            .collect();
        d.sort_by(f64::total_cmp);
        d.get(d.len() / 2).copied()
    };
    let slide = median(true).unwrap_or(1.0);
    (slide, median(false).unwrap_or(slide.max(DEFAULT_HOLD_INTERVAL)))
}

struct Scorer<'a> {
    models: &'a [Credible],
    noise: &'a NoiseModel,
    dt_slide: f64,
    dt_hold: f64,
}

impl Scorer<'_> {
    fn predict(&self, m: &Credible, next: &[rsf_core::Segment], s: &Sampling) -> Option<Raw> {
        let c = predict(&m.p, &m.map, &m.opts, &m.theta, next, &s.times, true).ok()?;
        let draws = m
            .draws
            .iter()
            .filter_map(|th| predict(&m.p, &m.map, &m.opts, th, next, &s.times, false).ok())
            .map(|p| p.mu);
        Some(Raw { central: c.mu, jac: c.jac, draws: draws.collect() })
    }

    /// The proposal scored, with the models' curves.
    fn score(&self, prop: &Proposal, v_end: f64) -> Option<(Ranked, Vec<PredictedCurve>)> {
        let next: Vec<rsf_core::Segment> =
            prop.segments().iter().map(|&(v, d)| rsf_core::Segment::for_duration(v, d)).collect();
        let s = sampling(prop, self.dt_slide, self.dt_hold);
        let raws: Vec<Raw> = self.models.iter().map(|m| self.predict(m, &next, &s)).collect::<Option<_>>()?;
        let curves = raws
            .iter()
            .zip(self.models)
            .map(|(r, m)| PredictedCurve {
                model: m.info.name.clone(),
                time: s.times.clone(),
                mu: r.central.clone(),
                mu_sd: (0..s.times.len())
                    .map(|i| {
                        let n = r.draws.len() as f64;
                        if n < 2.0 {
                            return 0.0;
                        }
                        let mean = r.draws.iter().map(|d| d[i]).sum::<f64>() / n;
                        (r.draws.iter().map(|d| (d[i] - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
                    })
                    .collect(),
            })
            .collect();
        let white: Vec<Whitened> = raws
            .into_iter()
            .zip(self.models)
            .map(|(r, m)| Whitened::new(self.noise, &s.times, &s.counts, r.central, &r.jac, &m.sqrt_cov, r.draws))
            .collect();
        let mut pairs = vec![];
        for i in 0..white.len() {
            for j in i + 1..white.len() {
                let dchi2 =
                    0.5 * (expected_lack_of_fit(&white[i], &white[j]) + expected_lack_of_fit(&white[j], &white[i]));
                pairs.push(PairScore {
                    a: self.models[i].info.name.clone(),
                    b: self.models[j].info.name.clone(),
                    dchi2,
                });
            }
        }
        let score: f64 = pairs.iter().map(|p| 1.0 - (-p.dchi2 / SETTLE_DCHI2).exp()).sum();
        let t = prop.machine_time();
        Some((
            Ranked {
                rank: 0,
                kind: prop.kind(),
                description: prop.describe(v_end),
                proposal: prop.clone(),
                segments: prop.segments(),
                machine_time_s: t,
                slip_um: prop.slip(),
                samples: s.samples,
                score,
                score_per_hour: score / (t / 3600.0).max(1e-12),
                lead_pair_dchi2: pairs[0].dchi2,
                pairs,
            },
            curves,
        ))
    }
}

/// Best first: by score, scores within [`SCORE_TIE`] of the best score's scale one bucket,
/// broken by the shorter machine time; ranks set.
fn rank(v: &mut [Ranked]) {
    let top = v.iter().map(|r| r.score).fold(0.0, f64::max).max(1e-12);
    let bucket = |r: &Ranked| (r.score / (SCORE_TIE * top)).floor() as i64;
    v.sort_by(|a, b| bucket(b).cmp(&bucket(a)).then(a.machine_time_s.total_cmp(&b.machine_time_s)));
    for (i, r) in v.iter_mut().enumerate() {
        r.rank = i + 1;
    }
}

fn summarize(best: &Ranked, standard: Option<&Ranked>, models: &[Credible]) -> String {
    let lead = format!("{} vs {}", models[0].info.name, models[1].info.name);
    let mut s = format!(
        "next: {} ({:.2} h of machine time): expected to settle {:.1} of {} model pairs; {lead}: expected Δχ² {:.0}",
        best.description,
        best.machine_time_s / 3600.0,
        best.score,
        best.pairs.len(),
        best.lead_pair_dchi2
    );
    if let Some(st) = standard {
        s += &format!(
            " (a one-decade step down and back of the same time: {:.1} pairs, Δχ² {:.0})",
            st.score, st.lead_pair_dchi2
        );
    }
    s
}
