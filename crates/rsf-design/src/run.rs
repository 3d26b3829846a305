//! The design itself: the credible models, the proposals scored in parallel, the ranking.

use super::basis::{Basis, Rebuilt};
use super::criterion::{Whitened, expected_lack_of_fit, information_gain};
use super::models::{Credible, Source, credible, prepare_model, source, with_alpha};
use super::result::{Design, EffectGain, EffectStderr, PairScore, PredictedCurve, Ranked};
use super::space::{Primitive, Proposal, SEQUENCE_SEEDS, Sampling, sampling, sequences, singles};
use super::standard::standards;
use super::{DesignOptions, EFFECT_HALVING, SCORE_TIE, SETTLE_DCHI2, STICK_SLIP_FACTOR};
use rsf_diagnose::{Cause, DiagnoseOptions, Diagnosis, NoiseModel, diagnose, noisy};
use rsf_fit::data::Record;
use rsf_fit::fit::{FitError, LoadingMode, parameter_map, predict, prepare, record_span};
use rsf_fit::parallel::par_map;
use rsf_fit::segment::Segment;
use rsf_solvers::SolveError;

/// One model's raw predictions of one proposal.
struct Raw {
    central: Vec<f64>,
    jac: Vec<f64>,
    draws: Vec<Vec<f64>>,
    /// Per new time, the largest slip rate since the previous one at the fit or any draw, µm/s.
    peak: Vec<f64>,
    /// When a draw's slip rate first blew up (past the solver's limit,
    /// [`rsf_solvers::MAX_SLIP_RATE`]), s after the record's end.
    blew_up: Option<f64>,
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
    design_basis(rec, segs, &Basis::of(d)?, o)
}

/// The next segment that best tells apart the credible models of the diagnosis written as
/// `json` by `rsf diagnose --json` on `rec` with the options `dopts` ([`Rebuilt::from_json`]).
pub fn design_from_json(
    rec: &Record,
    segs: &[Segment],
    json: &str,
    dopts: &DiagnoseOptions,
    o: &DesignOptions,
) -> Result<Design, FitError> {
    let rebuilt = Rebuilt::from_json(rec, segs, json, dopts)?;
    let mut out = design_basis(rec, segs, &rebuilt.basis(), o)?;
    out.notes.splice(0..0, rebuilt.notes.iter().cloned());
    Ok(out)
}

/// The next segment that best tells apart the credible models of `d`.
pub fn design_basis(rec: &Record, segs: &[Segment], d: &Basis<'_>, o: &DesignOptions) -> Result<Design, FitError> {
    if !(o.v_range.0 > 0.0 && o.v_range.1 >= o.v_range.0 && o.v_range.1.is_finite()) {
        return Err(FitError::Setup(format!("v-range {:?}: needs 0 < low ≤ high", o.v_range)));
    }
    if !(o.max_time > 0.0 && o.max_hold >= 0.0 && o.max_slip > 0.0) {
        return Err(FitError::Setup("max-time and max-slip must be positive, max-hold not negative".into()));
    }
    let base_opts = d.baseline_options.clone();
    if !(o.max_sigma_change >= 0.0 && o.max_sigma_change < 1.0) {
        return Err(FitError::Setup(format!(
            "max-sigma-change {}: needs 0 ≤ fraction < 1 of the record's normal stress",
            o.max_sigma_change
        )));
    }
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
    let mut sources: Vec<Source> = models.into_iter().filter_map(|(info, fit, opts)| source(info, fit, opts)).collect();
    // the slip scale of the proposals: the baseline's Dc (an added state's Dc may be
    // unconstrained; the grid's 30 Dc reaches the slow states a record can show)
    let dc_ref = d.baseline.params.dc.first().copied().unwrap_or(10.0).max(1e-3);
    // normal-stress changes: only on a record of constant σ as the fits see it (a measured
    // history already makes α one of the diagnosis's candidates, and the changes would be
    // stated against it), and only when one fits the constraints
    let constant = o.max_sigma_change > 0.0 && prepare(rec, segs, &base_opts)?.normal_stress.is_none();
    let sigma = constant && singles(v_end, dc_ref, o, true).iter().any(Proposal::changes_normal_stress);
    if o.max_sigma_change > 0.0 && !constant {
        notes.push(
            "the record's normal stress varies: α is among the diagnosis's candidates, and normal-stress changes are not proposed on top of a measured history".into(),
        );
    } else if constant && !sigma {
        notes.push(format!(
            "no change of normal stress fits the constraints (the smallest is {} %, at the record's last velocity within --v-range): none is proposed",
            super::space::SIGMA_CHANGES[0] * 100.0
        ));
    }
    if sigma && !sources.iter().any(|s| s.info.cause == Cause::NormalStressCoupling) {
        match sources.first().map(|best| with_alpha(rec, segs, best)) {
            Some(Ok(a)) => sources.push(a),
            Some(Err(e)) => notes.push(format!("normal_stress_coupling left out: {e}")),
            None => {}
        }
    }
    let models: Vec<Credible> =
        sources.into_iter().enumerate().filter_map(|(i, s)| prepare_model(rec, segs, s, o, i as u64).ok()).collect();
    // the named effect's parameters: those its model adds to the baseline's
    let base_free = parameter_map(&prepare(rec, segs, &base_opts)?, &base_opts)?.free_names();
    let effect = models
        .iter()
        .position(|m| m.info.cause == d.cause && m.info.name == d.cause.as_str() && d.cause.is_candidate())
        .map(|i| {
            let subset: Vec<usize> = models[i]
                .map
                .free_names()
                .iter()
                .enumerate()
                .filter(|(_, n)| !base_free.contains(n))
                .map(|(k, _)| k)
                .collect();
            (i, subset)
        })
        .filter(|(_, subset)| !subset.is_empty());
    if models.len() < 2 && effect.is_none() {
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
            standards: vec![],
            curves: vec![],
            notes,
        });
    }
    // the record's fastest load-point velocity, µm/s
    let v_fast = segs.iter().map(|s| s.v).fold(v_end, f64::max);
    let ctx = Scorer { models: &models, v_fast, noise: &noise, dt_slide, dt_hold, effect: effect.as_ref() };
    let first = singles(v_end, dc_ref, o, sigma);
    if first.is_empty() {
        return Err(FitError::Setup(format!(
            "no proposal fits the constraints (--max-time {} s, --max-hold {} s, --max-slip {} µm, --v-range {},{} µm/s; a segment lasts at least {} s)",
            o.max_time,
            o.max_hold,
            o.max_slip,
            o.v_range.0,
            o.v_range.1,
            super::space::MIN_SEGMENT_S
        )));
    }
    let seq_guess = if o.sequences { SEQUENCE_SEEDS * (SEQUENCE_SEEDS - 1) } else { 0 };
    let total = first.len() + seq_guess;
    let done = std::sync::atomic::AtomicUsize::new(0);
    let tick = |what: &str| {
        let k = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if let Some(pr) = &o.progress {
            pr(k.min(total), total, what);
        }
    };
    let mut tried = first.len();
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
        let seeds: Vec<Proposal> =
            scored.iter().filter(|r| !r.stick_slip).take(SEQUENCE_SEEDS).map(|r| r.proposal.clone()).collect();
        let seqs = sequences(&seeds, o);
        tried += seqs.len();
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
    if tried > scored.len() {
        notes.push(format!(
            "{} of {tried} proposals left out: a credible model's fit cannot be run through them (a run-away, or the solver's step budget)",
            tried - scored.len()
        ));
    }
    let runaway = scored.iter().filter(|r| r.stick_slip).count();
    if runaway > 0 {
        notes.push(format!(
            "{runaway} of {} proposals rank last: a credible model, at its fit or a draw, runs away in them (a slip rate above {STICK_SLIP_FACTOR}× the fastest load point: stick-slip)",
            scored.len()
        ));
    }
    let top = &scored[0];
    let top_fast = top.segments.iter().map(|s| s.0).fold(v_fast, f64::max);
    if !top.stick_slip && top.peak_slip_rate > STICK_SLIP_FACTOR * top_fast {
        notes.push(format!(
            "the best proposal changes σ, and the slip that forces in a credible model reaches {:.3e} µm/s ({:.0}× the fastest load point): forced slip is not screened as stick-slip, but the sample may slip dynamically there",
            top.peak_slip_rate,
            top.peak_slip_rate / top_fast
        ));
    }
    let best = scored[0].proposal.clone();
    let curves = ctx.score(&best, v_end).map(|(_, c)| c).unwrap_or_default();
    let mut scored_standards: Vec<Ranked> = vec![];
    for (kind, p) in standards(v_end, scored[0].machine_time_s, dc_ref, o) {
        match ctx.score(&p, v_end) {
            Some((r, _)) => scored_standards.push(Ranked { standard: Some(kind), ..r }),
            // as a proposal would be: left out, and said
            None => notes.push(format!(
                "the standard {} ({}) is left out: a credible model's fit cannot be run through it (a run-away, \
                 or the solver's step budget)",
                kind,
                p.describe(v_end)
            )),
        }
    }
    // the best as the ranking orders them: one in which no model runs away, then the score
    let standards = scored_standards;
    let standard =
        standards.iter().max_by(|a, b| b.stick_slip.cmp(&a.stick_slip).then(a.score.total_cmp(&b.score))).cloned();
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
        standards,
        curves,
        summary,
        notes,
    })
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
    /// The record's fastest load-point velocity, µm/s.
    v_fast: f64,
    noise: &'a NoiseModel,
    dt_slide: f64,
    dt_hold: f64,
    /// The named effect's model and its parameters' places in that model's θ.
    effect: Option<&'a (usize, Vec<usize>)>,
}

impl Scorer<'_> {
    fn predict(&self, m: &Credible, next: &[rsf_core::Segment], s: &Sampling) -> Option<Raw> {
        let c = predict(&m.p, &m.map, &m.opts, &m.theta, next, &s.times, true).ok()?;
        // the fit's own peak slip rate from a solve without derivatives
        let mut peak = predict(&m.p, &m.map, &m.opts, &m.theta, next, &s.times, false).ok()?.peak_slip_rate;
        let (mut draws, mut blew_up) = (Vec::with_capacity(m.draws.len()), None::<f64>);
        let span = record_span(&m.p);
        for th in &m.draws {
            match predict(&m.p, &m.map, &m.opts, th, next, &s.times, false) {
                Ok(d) => {
                    for (p, q) in peak.iter_mut().zip(&d.peak_slip_rate) {
                        *p = p.max(*q);
                    }
                    draws.push(d.mu);
                }
                // in the appended segments (a draw that runs away within the record itself
                // stands for nothing, as below)
                Err(SolveError::BlowUp { t, .. }) if t >= span => {
                    let at = t - span;
                    blew_up = Some(blew_up.map_or(at, |b| b.min(at)));
                }
                // a draw the solver cannot run otherwise stands for nothing: left out
                Err(_) => {}
            }
        }
        Some(Raw { central: c.mu, jac: c.jac, draws, peak, blew_up })
    }

    /// The largest slip rate of any model at any draw through `prop` (sampled at `times`), µm/s,
    /// and whether some model runs away in a step or a hold of it: faster than
    /// [`STICK_SLIP_FACTOR`] × the fastest load point of the record and the proposal, or past
    /// the solver's limit. The slip a change of σ forces is not judged (see
    /// [`STICK_SLIP_FACTOR`]).
    fn stick_slip(&self, prop: &Proposal, times: &[f64], raws: &[Raw]) -> (f64, bool) {
        let v_fast = prop.segments().iter().map(|s| s.0).fold(self.v_fast, f64::max);
        let judged = |p: &Primitive| match p {
            Primitive::Step { .. } | Primitive::Hold { .. } => true,
            Primitive::NormalStress { .. } => false,
        };
        let limits: Vec<f64> = prop
            .parts_at(times)
            .into_iter()
            .map(|p| if judged(p) { STICK_SLIP_FACTOR * v_fast } else { f64::INFINITY })
            .collect();
        let peak = raws.iter().flat_map(|r| r.peak.iter().copied()).fold(0.0, f64::max);
        let over = raws.iter().any(|r| {
            r.blew_up.is_some_and(|t| judged(prop.parts_at(&[t])[0])) || r.peak.iter().zip(&limits).any(|(p, l)| p > l)
        });
        (peak, over)
    }

    /// The proposal scored, with the models' curves.
    fn score(&self, prop: &Proposal, v_end: f64) -> Option<(Ranked, Vec<PredictedCurve>)> {
        let next = prop.protocol();
        let s = sampling(prop, self.dt_slide, self.dt_hold);
        let raws: Vec<Raw> = self.models.iter().map(|m| self.predict(m, &next, &s)).collect::<Option<_>>()?;
        let (peak_slip_rate, stick_slip) = self.stick_slip(prop, &s.times, &raws);
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
        let effect = self.effect.and_then(|(i, subset)| {
            let m = &self.models[*i];
            let (sds, gain_nats) = information_gain(&white[*i], &m.sqrt_cov, subset)?;
            let parameters = subset
                .iter()
                .zip(sds)
                .map(|(&k, (now, after))| {
                    let names = m.map.free_names();
                    // log-fitted: the value and its standard error by the delta method
                    let (value, scale) =
                        if m.map.is_log(k) { (m.theta[k].exp(), m.theta[k].exp()) } else { (m.theta[k], 1.0) };
                    EffectStderr {
                        name: names[k].clone(),
                        value,
                        stderr_now: now * scale,
                        stderr_expected: after * scale,
                    }
                })
                .collect();
            let per = gain_nats.max(0.0) / subset.len() as f64;
            Some(EffectGain {
                model: m.info.name.clone(),
                gain_nats,
                score: 1.0 - (-per / EFFECT_HALVING).exp(),
                parameters,
            })
        });
        let score: f64 = pairs.iter().map(|p| 1.0 - (-p.dchi2 / SETTLE_DCHI2).exp()).sum::<f64>()
            + effect.as_ref().map_or(0.0, |e| e.score);
        let t = prop.machine_time();
        Some((
            Ranked {
                rank: 0,
                kind: prop.kind(),
                description: prop.describe(v_end),
                proposal: prop.clone(),
                segments: prop.segments(),
                normal_stress: prop.sigma_levels(),
                machine_time_s: t,
                slip_um: prop.slip(),
                samples: s.samples,
                score,
                score_per_hour: score / (t / 3600.0).max(1e-12),
                lead_pair_dchi2: pairs.first().map_or(0.0, |p| p.dchi2),
                pairs,
                peak_slip_rate,
                stick_slip,
                effect,
                standard: None,
            },
            curves,
        ))
    }
}

/// Best first, those in which a model runs away ([`Ranked::stick_slip`]) after all others: of
/// the proposals left, those within [`SCORE_TIE`] (pairs) of the best score left are a tie, and
/// the one of the shortest machine time (then the higher score) comes next; ranks set.
fn rank(v: &mut Vec<Ranked>) {
    let mut left = std::mem::take(v);
    left.sort_by(|a, b| {
        a.stick_slip
            .cmp(&b.stick_slip)
            .then(b.score.total_cmp(&a.score))
            .then(a.machine_time_s.total_cmp(&b.machine_time_s))
    });
    while let Some((top, class)) = left.first().map(|r| (r.score, r.stick_slip)) {
        let tied = left.iter().take_while(|r| r.stick_slip == class && r.score >= top - SCORE_TIE).count().max(1);
        let next = (0..tied)
            .min_by(|&a, &b| left[a].machine_time_s.total_cmp(&left[b].machine_time_s).then(a.cmp(&b)))
            .unwrap_or(0);
        v.push(left.remove(next));
    }
    for (i, r) in v.iter_mut().enumerate() {
        r.rank = i + 1;
    }
}

fn summarize(best: &Ranked, standard: Option<&Ranked>, models: &[Credible]) -> String {
    let mut s = String::new();
    if best.stick_slip {
        s += &format!(
            "every proposal risks stick-slip (a credible model reaches {:.3e} µm/s in the best); ",
            best.peak_slip_rate
        );
    }
    s += &format!("next: {} ({:.2} h of machine time): ", best.description, best.machine_time_s / 3600.0);
    let settled: f64 = best.pairs.iter().map(|p| 1.0 - (-p.dchi2 / SETTLE_DCHI2).exp()).sum();
    if models.len() >= 2 {
        s += &format!(
            "expected to settle {settled:.1} of {} model pairs; {} vs {}: expected Δχ² {:.0}",
            best.pairs.len(),
            models[0].info.name,
            models[1].info.name,
            best.lead_pair_dchi2
        );
    } else {
        s += &format!("one credible model ({}): the segment that best measures its effect", models[0].info.name);
    }
    if let Some(e) = &best.effect {
        let each: Vec<String> = e
            .parameters
            .iter()
            .map(|p| format!("{} {:.3e} ± {:.2e} → ± {:.2e}", p.name, p.value, p.stderr_now, p.stderr_expected))
            .collect();
        s += &format!("; the effect's standard errors expected: {}", each.join(", "));
    }
    if let Some(st) = standard {
        s += &format!(
            " (the best standard segment of the same time, {}: score {:.2} against {:.2})",
            st.description, st.score, best.score
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ranked(score: f64, machine_time_s: f64, p: Primitive) -> Ranked {
        Ranked {
            rank: 0,
            kind: "step",
            description: String::new(),
            proposal: Proposal { parts: vec![p] },
            segments: vec![],
            normal_stress: vec![],
            machine_time_s,
            slip_um: 0.0,
            samples: 0,
            score,
            score_per_hour: 0.0,
            lead_pair_dchi2: 0.0,
            pairs: vec![],
            peak_slip_rate: 0.0,
            stick_slip: false,
            effect: None,
            standard: None,
        }
    }

    /// Scores within SCORE_TIE (0.05 pair) of the best are a tie, won by the shorter proposal,
    /// even where a multiple of 1 % of the top score falls between them (a fixed bucketing of
    /// 1 % of the top split these); 0.1 pair apart is not a tie.
    #[test]
    fn near_ties_go_to_the_shorter_proposal() {
        let h = Primitive::Hold { hold_s: 1e4, v: 1.0, slip: 10.0 };
        let mut v = vec![
            ranked(14.9991, 11170.0, h),
            ranked(14.9964, 10263.0, h),
            ranked(10.0, 10.0, h),
            ranked(14.0, 100.0, h),
            ranked(14.9, 50.0, h),
        ];
        rank(&mut v);
        let times: Vec<f64> = v.iter().map(|r| r.machine_time_s).collect();
        assert_eq!(times, vec![10263.0, 11170.0, 50.0, 100.0, 10.0]);
        assert_eq!(v.iter().map(|r| r.rank).collect::<Vec<_>>(), vec![1, 2, 3, 4, 5]);
    }

    /// A proposal in which a model runs away ranks after every other, whatever its score, and
    /// does not tie with a safe one.
    #[test]
    fn a_proposal_that_runs_away_ranks_last() {
        let h = Primitive::Hold { hold_s: 1e4, v: 1.0, slip: 10.0 };
        let risky = |score, t| Ranked { stick_slip: true, ..ranked(score, t, h) };
        let mut v = vec![risky(20.0, 100.0), ranked(3.0, 500.0, h), risky(19.99, 10.0), ranked(2.99, 50.0, h)];
        rank(&mut v);
        let got: Vec<(bool, f64)> = v.iter().map(|r| (r.stick_slip, r.machine_time_s)).collect();
        assert_eq!(got, vec![(false, 50.0), (false, 500.0), (true, 10.0), (true, 100.0)]);
    }
}
