//! The diagnosis: baseline, reconstruction check, evidence, candidates, held-out tests, the
//! null calibration, the decision.

use super::adequacy::adequacy;
use super::baseline::{baseline, continued};
use super::candidate::{Ctx, FullFit, rescore};
use super::cause::Cause;
use super::combination::secondary;
use super::decide::{ineligible, judge_adequacy, pair_words, unconverged_rival, verdict};
use super::events::{dc_consistency, event_windows, fit_event};
use super::evidence::{evidence, noisy, reload_stiffness};
use super::form::form_test;
use super::heldout::{heldout, sigma_first_changes_after, split_time};
use super::rule::{AdequacyVerdict, Family};
use super::starts::slip_rate_range;
use super::timing::{load_point_sigma, timing_mask};
use super::{Apart, Candidate, DECISIVE, DiagnoseOptions, Diagnosis, EventFit};
use rsf_fit::data::{Record, isolated_spikes};
use rsf_fit::fit::{BinMeans, FitError, FitOptions, FitResult, LoadingMode, Prepared, Weighting, fit, prepare};
use rsf_fit::parallel::par_map;
use rsf_fit::segment::Segment;

/// Starting points of a candidate's fit from the baseline optimum: the optimum itself and one
/// restart with Dc tripled (the scaled restarts of a cold fit, see `fit::fit`).
const CANDIDATE_STARTS: usize = 2;
/// Slip-rate range of the Vc profile when the baseline gives none, µm/s (lab rates).
const DEFAULT_V_RANGE: (f64, f64) = (1e-3, 1e3);
/// Each candidate fit gets this share of the baseline's work budget: a candidate the data
/// cannot constrain (b2 running to its bound) must not dominate the work.
const CANDIDATE_BUDGET_SHARE: f64 = 1.0 / 3.0;
/// At most this many decisive candidates are put to the null calibration (each costs
/// `null_replicates` pairs of refits); the rest keep their place in the table.
const MAX_CALIBRATED: usize = 3;

enum Job {
    /// A candidate's fit on the whole record (and its held-out test when that waits for it).
    Candidate(Cause),
    /// A candidate's held-out test, beside its fit.
    Heldout(Cause, Box<FitOptions>),
    Event(usize, usize),
}

/// A held-out test's outcome: the prediction's rms and the training fit.
type HeldOut = Option<(f64, FitResult)>;

enum Done {
    /// The fit on the whole record, and the held-out test when it ran in the same job.
    Candidate(Cause, Option<Box<(FullFit, Option<HeldOut>)>>),
    Heldout(Cause, Box<HeldOut>),
    Event(Option<EventFit>),
}

/// The options of the diagnosis's fits (before the loading check and the break-timing mask):
/// uniform weights, bins that search rather than replace, one thread per fit.
pub fn diagnosis_fit_options(opts: &DiagnoseOptions) -> FitOptions {
    // uniform weights: the likelihood of noise of one σ everywhere, as lab noise is, so that
    // ΔBIC has its nominal calibration (with segment weights a free parameter acting only in
    // sparsely sampled segments would gain about mean(w²) per parameter on pure noise)
    // the optimum sought on bin means, each result evaluated on every sample: the noise model
    // reads the residuals sample by sample
    // (bins that would replace the samples search instead)
    let bins = match opts.fit.bins {
        BinMeans::Replace { above, fraction } => BinMeans::Search { above, fraction },
        b @ (BinMeans::Off | BinMeans::Search { .. }) => b,
    };
    // one thread per fit: the fits run as parallel jobs (the baseline's starts get `opts.threads`)
    FitOptions { weighting: Weighting::Uniform, bins, threads: 1, ..opts.fit.clone() }
}

/// The record without its isolated spikes (bad samples, not friction), its segments re-indexed,
/// and the spikes' times.
pub fn without_spikes(rec: &Record, segs: &[Segment]) -> (Record, Vec<Segment>, Vec<f64>) {
    let spikes = isolated_spikes(&rec.mu);
    let clean = rec.without(&spikes);
    let segs: Vec<Segment> = segs
        .iter()
        .map(|s| {
            let i0 = clean.time.partition_point(|&t| t < rec.time[s.i0]);
            let i1 = clean.time.partition_point(|&t| t <= rec.time[s.i1]).saturating_sub(1).max(i0);
            Segment { i0, i1, ..s.clone() }
        })
        .collect();
    let spikes_removed: Vec<f64> = spikes.iter().map(|&i| rec.time[i]).collect();
    (clean, segs, spikes_removed)
}

/// Runs the diagnosis on a record with its segments.
pub fn diagnose(rec: &Record, segs: &[Segment], opts: &DiagnoseOptions) -> Result<Diagnosis, FitError> {
    let o = diagnosis_fit_options(opts);
    if o.laws.len() != 1 {
        return Err(FitError::Setup("the baseline has one state variable".into()));
    }
    // isolated spikes are bad samples, not friction: out before anything is fitted to them
    let (clean, segs, spikes_removed) = without_spikes(rec, segs);
    let (rec, segs) = (&clean, &segs[..]);
    // each stage's and job's wall time on stderr (profiling only)
    let timing_log = opts.stage_times;
    let clock = std::time::Instant::now();
    let lap = |what: &str| {
        if timing_log {
            eprintln!("diagnose: {what} done at {:.2} s", clock.elapsed().as_secs_f64());
        }
    };
    let (base_opts, p, base, reconstruction) = baseline(rec, segs, &o, opts.threads)?;
    lap("baseline and reconstruction check");
    let mask = timing_mask(&p, &base);
    // the load-point noise the null replicates re-segment with, masked or not
    let lp_noise = mask.as_ref().map(|m| m.load_point_sigma_um);
    let (base_opts, p, base, timing) = match mask {
        Some(m) if opts.timing_mask && base_opts.loading == LoadingMode::Protocol => {
            // refit without the samples the protocol's timing cannot predict, from the optimum
            // added to what the reconstruction check already left out (a short suspect
            // segment stays out of every fit, as the report says)
            let exclude = base_opts.exclude.iter().chain(&m.windows).copied().collect();
            let mut om = FitOptions { exclude, ..base_opts.clone() };
            // a few samples fewer: one start, warm from the optimum
            let warm = FitOptions { initial: base.params.as_initial(), starts: 1, ..om.clone() };
            let pm = prepare(rec, segs, &om)?;
            let bm = fit(&pm, &warm)?;
            om.initial = base_opts.initial.clone();
            (om, pm, bm, Some(m))
        }
        _ => (base_opts, p, base, None),
    };
    lap("break-timing mask");
    let base_noise = noisy(&base);
    let mut ev = evidence(&base, &base_noise);
    ev.k_reload_slope = reload_stiffness(&p);
    let t_split = split_time(&p.record, &p.segments);
    let sigma_held_out = sigma_first_changes_after(p.normal_stress.as_ref(), t_split);
    // the baseline's held-out fit first: every extension's held-out fit starts from it
    let ho_base = if opts.heldout {
        let oh = FitOptions { mu0_per_segment: false, ..base_opts.clone() };
        let threads = opts.threads;
        heldout(
            &p.record,
            &p.segments,
            &oh,
            // cold, as the baseline on the whole record: continued past a late run-away
            &|pt: &Prepared, ot: &FitOptions| {
                let fit = |p: &Prepared, o: &FitOptions| fit(p, &FitOptions { threads, ..o.clone() });
                continued(&pt.record, &pt.segments, pt, ot, &fit).ok()
            },
            t_split,
        )
    } else {
        None
    };
    lap("held-out baseline");
    let v_range = slip_rate_range(&base).unwrap_or(DEFAULT_V_RANGE);
    let load_point_sigma = load_point_sigma(&p);
    let ctx = Ctx {
        rec,
        segs,
        opts,
        // each candidate fit gets CANDIDATE_BUDGET_SHARE of the baseline budget and, starting
        // from the baseline optimum, fewer starts: the scaled restarts of a cold
        // fit explore what the baseline's own multi-start already explored (a second state
        // keeps its two extra starts, b2 of either sign)
        cand_opts: FitOptions {
            budget: base_opts.budget.scaled(CANDIDATE_BUDGET_SHARE),
            starts: base_opts.starts.min(CANDIDATE_STARTS),
            ..base_opts.clone()
        },
        base_law: base_opts.laws[0].name(),
        base_opts,
        p,
        base_noise,
        base,
        ev,
        v_range,
        t_split,
        sigma_held_out,
        ho_base_noise: ho_base.as_ref().map(|(_, f)| noisy(f)),
        ho_base,
        lp_noise,
        load_point_sigma,
    };
    let causes: Vec<Cause> = Cause::candidates()
        .filter(|&c| !(c == Cause::Stiffness && ctx.base_opts.fit_stiffness))
        // α acts only through changes of σ
        .filter(|&c| c != Cause::NormalStressCoupling || ctx.p.normal_stress.is_some())
        .collect();
    // each held-out test beside its candidate's fit, where it does not wait for the fit's choice
    let beside: Vec<(Cause, FitOptions)> = match ctx.ho_base {
        Some(_) => causes.iter().filter_map(|&c| ctx.single_variant(c).map(|o| (c, o))).collect(),
        None => vec![],
    };
    let mut jobs: Vec<Job> = causes.iter().map(|&c| Job::Candidate(c)).collect();
    jobs.extend(beside.iter().map(|(c, o)| Job::Heldout(*c, Box::new(o.clone()))));
    if opts.per_segment {
        jobs.extend(event_windows(&ctx.p).into_iter().map(|(a, b)| Job::Event(a, b)));
    }
    let done_count = std::sync::atomic::AtomicUsize::new(0);
    let results = par_map(&jobs, opts.threads, |job| {
        let clock = std::time::Instant::now();
        let (what, out) = match job {
            Job::Candidate(c) => {
                let full = ctx.full_fit(*c).map(|ff| {
                    // the held-out test of the way the fit chose, when it could not run beside
                    let ho =
                        (ctx.ho_base.is_some() && !beside.iter().any(|b| b.0 == *c)).then(|| ctx.heldout_fit(&ff.o));
                    Box::new((ff, ho))
                });
                (c.to_string(), Done::Candidate(*c, full))
            }
            Job::Heldout(c, o) => (format!("{c} held out"), Done::Heldout(*c, Box::new(ctx.heldout_fit(o)))),
            Job::Event(a, b) => {
                (format!("segment {}", b + 1), Done::Event(fit_event(&ctx.p, &ctx.base_opts, &ctx.base, *a, *b)))
            }
        };
        if timing_log {
            eprintln!("diagnose: {what} in {:.2} s", clock.elapsed().as_secs_f64());
        }
        let d = done_count.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if let Some(pr) = &opts.progress {
            pr(d, jobs.len(), &what);
        }
        out
    });
    let mut fulls = vec![];
    let mut unfitted_causes = vec![];
    let mut heldouts = vec![];
    let mut per_segment = vec![];
    for r in results {
        match r {
            Done::Candidate(c, Some(b)) => fulls.push((c, *b)),
            Done::Candidate(c, None) => unfitted_causes.push(c),
            Done::Heldout(c, h) => heldouts.push((c, *h)),
            Done::Event(e) => per_segment.extend(e),
        }
    }
    let fulls: Vec<(Cause, FullFit, HeldOut)> = fulls
        .into_iter()
        .map(|(c, (ff, ho))| {
            let ho =
                ho.unwrap_or_else(|| heldouts.iter().position(|h| h.0 == c).and_then(|i| heldouts.swap_remove(i).1));
            (c, ff, ho)
        })
        .collect();
    // a full fit that its own training fit beats on the whole record is continued from there
    let continued = par_map(&fulls, opts.threads, |(_, ff, ho)| {
        ho.as_ref().and_then(|(_, ft)| ctx.continued_from_training(ff, ft))
    });
    lap("continued fits");
    let mut fulls: Vec<(Cause, FullFit, HeldOut)> = fulls
        .into_iter()
        .zip(continued)
        .map(|((c, mut ff, ho), better)| {
            if let Some(f) = better {
                ff.replace(f);
            }
            (c, ff, ho)
        })
        .collect();
    rescore(&ctx.base, &ctx.base_noise, fulls.iter_mut().map(|x| &mut x.1));
    let mut candidates: Vec<Candidate> = fulls.into_iter().map(|(c, ff, ho)| ctx.candidate(c, ff, ho)).collect();
    let mut ev = ctx.ev.clone();
    (ev.dc_consistency_chi2, ev.dc_vs_ln_step, ev.dc_vs_ln_hold) = dc_consistency(&per_segment);
    candidates.sort_by(|a, b| a.delta_bic.total_cmp(&b.delta_bic));
    // the null calibration, best first, for decisive candidates that are otherwise credible,
    // until one passes
    let level = opts.false_alarm_level;
    if opts.null_replicates > 0 {
        let mut tried = 0;
        for c in candidates.iter_mut() {
            // a candidate the held-out test cannot judge waits for the null's verdict
            let awaiting = c.heldout_uninformative && c.null.is_none() && c.at_bound.is_empty();
            if !(c.delta_bic < DECISIVE) || (ineligible(c, level).is_some() && !awaiting) || tried == MAX_CALIBRATED {
                continue;
            }
            tried += 1;
            let clock = std::time::Instant::now();
            c.null = ctx.calibrate(c);
            if timing_log {
                eprintln!("diagnose: null calibration of {} in {:.2} s", c.cause, clock.elapsed().as_secs_f64());
            }
            if let Some(pr) = &opts.progress {
                pr(jobs.len(), jobs.len(), &format!("null calibration of {}", c.cause));
            }
            if ineligible(c, level).is_none() {
                break;
            }
        }
    }
    let decisive: Vec<&Candidate> = candidates.iter().filter(|c| c.delta_bic < DECISIVE).collect();
    let chosen = decisive.iter().copied().find(|c| ineligible(c, level).is_none());
    let rejected: Vec<String> =
        decisive.iter().take_while(|c| ineligible(c, level).is_some()).filter_map(|c| ineligible(c, level)).collect();
    // the runner-up: the best other credible candidate (set-aside ones are named in the reason),
    // else the best other one (with no winner, simply the best-scoring candidate)
    let others = || candidates.iter().filter(|c| chosen.is_none_or(|ch| ch.cause != c.cause));
    let runner_up = others()
        .find(|c| chosen.is_none() || ineligible(c, level).is_none())
        .or_else(|| others().next())
        .map(|c| (c.cause, c.delta_bic));
    lap("candidates, events and null calibration");
    let secondary = match chosen {
        Some(c1) if opts.combinations => secondary(&ctx, c1, &decisive, level),
        _ => None,
    };
    lap("combinations");
    let mut v = verdict(ctx.ev.n_effective, chosen, &candidates, &rejected, &secondary);
    // the adequacy of the model named (with its second cause), or of the baseline for `none`:
    // a cause is named only when its model explains the events to the noise level
    let named_fit = secondary.as_ref().map(|s| &s.fit).or(chosen.and_then(|c| c.fit.as_ref())).unwrap_or(&ctx.base);
    // the fit's own uncertainty, for the level and quiet tests' nulls
    let named_opts = match (&secondary, chosen) {
        (Some(s), _) => s.options.as_ref(),
        (None, Some(c)) => c.options.as_ref(),
        (None, None) => Some(&ctx.base_opts),
    };
    let effect = || {
        named_opts.and_then(|o| super::sensitivity::fit_effect(ctx.rec, ctx.segs, o, named_fit, ctx.load_point_sigma))
    };
    // the noise model of the named fit's own residuals: the quiet test's, and the drift the
    // reason reports (the baseline's was fitted once already)
    let named_noisy = match (&secondary, chosen.and_then(|c| c.fit.as_ref())) {
        (None, None) => None,
        _ => Some(noisy(named_fit)),
    };
    let named_noise = named_noisy.as_ref().map_or_else(|| ctx.base_noise.model.clone(), |n| n.model.clone());
    let adequacy = adequacy(named_fit, &ctx.p.segments, ctx.load_point_sigma, Some(&effect), Some(&named_noise));
    // a named model's tests each at the full level; the baseline's share it (`rule.rs`'s
    // `Family`): any one of them finding misfit makes a `none` record `unexplained`
    let family = match chosen {
        Some(_) => Family::ALONE,
        None => adequacy.baseline_family(),
    };
    let adequacy = adequacy.held_to(family);
    // the form test (`form.rs`) of the model the other tests found no misfit in: the cause's, with
    // the best other credible decisive candidate (a rival whose law, reshaped, nests the record's
    // where the named one's does not), or the baseline's for `none` (which claims the baseline
    // explains the record: a rate-dependent direct effect or a law's reshaped state, each short
    // of a decisive candidate on the menu, is found there)
    let form = match named_opts {
        Some(o) if adequacy.verdict != AdequacyVerdict::Inadequate && (chosen.is_none() || named_noisy.is_some()) => {
            let named_causes = [chosen.map(|c| c.cause), secondary.as_ref().map(|s| s.cause)];
            let rival = chosen.and_then(|_| {
                decisive
                    .iter()
                    .filter(|c| !named_causes.contains(&Some(c.cause)) && ineligible(c, level).is_none())
                    .find_map(|c| Some((c.cause, c.options.as_ref()?, c.fit.as_ref()?)))
            });
            let named_cause = secondary.as_ref().map(|s| s.cause).or(chosen.map(|c| c.cause)).unwrap_or(Cause::None);
            form_test(&ctx, (named_cause, o, named_fit), &Vec::from_iter(rival), family)
        }
        _ => None,
    };
    let adequacy = adequacy.with_form(form);
    lap("adequacy and form test");
    judge_adequacy(&mut v, &adequacy, chosen, &decisive, &candidates);
    // two causes the record cannot tell apart: the best other credible, decisive candidate
    // within UNDECIDED_DBIC of the one chosen, or, where the model chosen could not be tested
    // against the noise, further but with a lead within its chance spread (`lead.rs`: another
    // draw of the noise could reverse it). Then the record prefers neither, so the verdict
    // names neither (`undecided`, both with their scores; the fit, gain and effect given are
    // the better one's). Not when a combination is named (it beat the cause alone) or the
    // model chosen misfits (`unexplained` says more).
    let rival = match chosen {
        Some(c1) if secondary.is_none() && v.cause == c1.cause => {
            candidates.iter().find(|c| c.cause != c1.cause && c.delta_bic < DECISIVE && ineligible(c, level).is_none())
        }
        _ => None,
    };
    let lead = match (chosen.and_then(|c| c.fit.as_ref()), rival.and_then(|c| c.fit.as_ref())) {
        (Some(f1), Some(f2)) if f1.curve.time == f2.curve.time => {
            let ((r1, times), (r2, _)) = (super::evidence::residuals(f1), super::evidence::residuals(f2));
            let side = |r, f: &rsf_fit::fit::FitResult| super::lead::Side { residuals: r, n_free: f.n_free };
            super::lead::lead(side(&r1, f1), side(&r2, f2), times, ctx.base.n, &named_noise)
        }
        _ => None,
    };
    // the lead decides only where no test could confirm that the model chosen explains the
    // record (`lead.rs`): there, that neither model is the truth is the live possibility
    let lead_decides = match adequacy.verdict {
        AdequacyVerdict::Untestable => true,
        AdequacyVerdict::Adequate | AdequacyVerdict::Inadequate => false,
    };
    let close = match (chosen, rival) {
        (Some(c1), Some(c2))
            if c2.delta_bic - c1.delta_bic < super::UNDECIDED_DBIC
                || (lead_decides && lead.is_some_and(|l| !l.holds(level))) =>
        {
            Some((c1, c2))
        }
        _ => None,
    };
    // else a rival set aside only because its fit did not converge that scores better than the
    // one chosen even at a point short of its optimum (`decide.rs`)
    let unconverged = match (chosen, close) {
        (Some(c1), None) if secondary.is_none() && v.cause == c1.cause => {
            unconverged_rival(c1, &candidates).map(|c2| (c1, c2))
        }
        _ => None,
    };
    // else a rival whose law, reshaped, explains the record decisively better than the model
    // chosen, by no more than the noise gives it (the form test found no misfit): a model
    // without the cause chosen does as well as the model with it
    let reshaped = match (chosen, close.or(unconverged), adequacy.form.as_ref()) {
        (Some(c1), None, Some(f)) if secondary.is_none() && v.cause == c1.cause && f.rival_does_as_well() => {
            candidates.iter().find(|c| c.cause == f.model).map(|c2| (c1, c2))
        }
        _ => None,
    };
    let undecided: Vec<(Cause, f64)> = close
        .or(unconverged)
        .or(reshaped)
        .map_or(vec![], |(c1, c2)| vec![(c1.cause, c1.delta_bic), (c2.cause, c2.delta_bic)]);
    let apart = match (&undecided[..], unconverged, reshaped, lead) {
        ([], ..) => None,
        (_, Some(_), _, _) => Some(Apart::Unconverged),
        (_, None, Some(_), _) => Some(Apart::Form),
        ([(_, da), (_, db)], None, None, Some(_)) if db - da >= super::UNDECIDED_DBIC => Some(Apart::Lead),
        (_, None, None, _) => Some(Apart::Margin),
    };
    if let (&[(a, da), (b, db)], Some(apart)) = (&undecided[..], apart) {
        v.cause = Cause::Undecided;
        v.partial = Some(a);
        let why = match (apart, lead) {
            (Apart::Form, _) => adequacy.form.as_ref().map_or_else(
                || format!("{b}'s law, reshaped, explains the record as well as {a}'s model"),
                |f| f.as_well_words(a, b),
            ),
            (Apart::Unconverged, _) => format!(
                "{b} scores better at a point short of its optimum (its fit did not converge; a fit of its model run \
                 longer, `rsf fit … --max-iter`, finds that optimum), and its optimum scores at least as well"
            ),
            (Apart::Lead, Some(l)) => format!(
                "both explain the record better than the baseline, and, with nothing to test {a}'s model against \
                 the noise, its lead is within what the noise makes between two such models ({:.1} in ln L, {:.2} \
                 times its chance spread, chance {:.2})",
                l.lead, l.z, l.p
            ),
            (Apart::Margin | Apart::Lead, _) => format!(
                "both explain the record better than the baseline, within {} of each other",
                super::UNDECIDED_DBIC
            ),
        };
        v.reason = format!(
            "undecided between {a} (ΔBIC {da:.1}) and {b} (ΔBIC {db:.1}): {why}, so the record does not tell which \
             it needs{}; rsf design plans the experiment that does (before: {})",
            pair_words(a, b),
            v.reason
        );
    }
    let super::decide::Verdict { cause, mut reason, extended, gain, effect, confidence, partial, disagreement } = v;
    // what could not be fitted from any start is named, never silently missing
    let unfitted: Vec<String> = unfitted_causes
        .iter()
        .map(|c| format!("{c} (every way)"))
        .chain(candidates.iter().flat_map(|c| c.unfitted_ways.iter().map(move |w| format!("{} ({w})", c.cause))))
        .collect();
    if !unfitted.is_empty() {
        reason += &format!("; not fitted from any start, so not among the candidates: {}", unfitted.join(", "));
    }
    // the drift left in the residuals of the model named (the baseline's hold the named cause's
    // misfit as well, which their noise model reads as drift)
    let noise_drift = Some(&named_noise).filter(|m| m.drift_share >= super::DRIFT_NOTE_SHARE).map(|m| {
        super::NoiseDrift { rms: (m.drift_share * m.variance).sqrt(), share: m.drift_share, beta: m.drift_beta }
    });
    if let Some(d) = &noise_drift {
        reason += &format!("; {}", d.words(adequacy.quiet.inadequate()));
    }
    Ok(Diagnosis {
        cause,
        confidence,
        reason,
        evidence: ev,
        extended,
        gain,
        effect,
        partial,
        adequacy,
        disagreement,
        runner_up,
        undecided,
        apart,
        lead,
        unfitted_causes,
        noise_drift,
        secondary,
        per_segment,
        heldout_split_t: ctx.t_split,
        reconstruction,
        timing,
        spikes_removed,
        loading: ctx.base_opts.loading,
        candidates: candidates.clone(),
        baseline_options: Some(ctx.base_opts.clone()),
        baseline: ctx.base,
    })
}
