//! The form test: does the law of the model named have the record's dependence on state?
//!
//! The event, level and quiet tests (`adequacy.rs`) compare the named model's residuals with the
//! noise. A law near the truth in form — Perrin–Rice–Zheng's quadratic healing where the sample
//! heals as Ω^1.8, a cut-off bending the Slip law where the truth bends the Aging law's power —
//! leaves a misfit of the noise's size, and AR(1) noise of a few seconds makes a hold's early and
//! late residuals differ as much under the truth. Such a misfit is found by a model that nests
//! both: the model named with each state's law read at a reshaped state,
//! θ' = θ_ref (θ/θ_ref)^p (`rsf_laws::reshaped`), p = 1 being the law named; and the best
//! credible rival on the menu reshaped the same way (a cut-off that mimics power-law aging is
//! not bent into it by its own exponent, while the Aging–Slip law is).
//!
//! **What counts.** A reshaped model is fitted warm from its model's optimum, and its model is
//! refitted back from the reshaped optimum with the exponents at 1: a reshaped fit can leave a
//! local optimum its model was stuck in, and that gain is the search's, not the form's. Its
//! ΔBIC is taken against the better of that back-fit and the model named refitted warm from its
//! own optimum (for a rival, also against the rival's back-fit), each scored as candidates are
//! (`evidence::scores`).
//!
//! **Verdict.** A reshaped model decisively better ([`DECISIVE`]) is then calibrated as a
//! candidate is (`null.rs`): replicates of the model named plus the reshaped fit's noise (and the
//! record's load-point noise, re-segmented), each refitted with the model named and the model
//! reshaped, give the gain's null distribution. The law named is not the record's when the
//! observed gain would arise by chance less often than the false-alarm level (or, where the
//! replicates only lose, beyond ten times the decisive ΔBIC; the level is divided by the number of
//! reshaped models tried, the best of which was chosen): the model is inadequate, whatever
//! p comes to (a p at its bound is reported as such: the direction is measured, the value is
//! not). Without null replicates (`--null-replicates 0`) the decisive ΔBIC alone decides.
//!
//! **On a noisy load point.** The test relies on the breaks' times: a break misplaced by δt
//! misplaces the friction's transient by up to k·|Δv|·δt, which a reshaped law partly absorbs.
//! The segmentation places a noisy break where its segments' lines cross, to a fraction of
//! σ_x/|Δv| (`rsf_fit::segment`), and the null's replicates carry the record's load-point noise
//! and are segmented afresh, so the test runs there too. (With breaks at the best split of the
//! noisy samples — off by one or two samples, 0.4 s on a 5 Hz record — it rejected six true
//! models in the detection studies, and its replicates, whose load point followed the record's
//! own split, did not reproduce that error: docs/diagnose/detection.md, "The form test".)
//!
//! **The direct effect.** The same test is run with the model named given a rate-dependent
//! direct effect, ∂f/∂ln V = a + a₁ ln(V/V0) (`rsf_core::Model::a_slope`): a direct effect that
//! grows or falls with the slip rate bends the steady state in ln V and makes the jumps of up-
//! and down-steps differ, which a law of state mimics in part (the Aging–Slip law's asymmetric
//! transients) and no reshaping of state reproduces. Fitted, back-fitted and calibrated as a
//! reshaped law is, with one added parameter.
//!
//! This is a test of the model named, not a candidate: a reshaped law is never named as the
//! cause. For a `none` verdict the model named is the baseline (`none` claims it explains the
//! record), reshaped in state and direct effect, with no rival: an effect each candidate on the
//! menu mimics too little to be decisive (a direct effect that varies with the slip rate) is
//! found there, and the verdict is `unexplained`.

use super::candidate::Ctx;
use super::cause::Cause;
use super::decide::BLIND_DECISIVE;
use super::evidence::{Noisy, noisy, scores};
use super::null::{NullCalibration, gain, replicate, replicate_load_point, sequential};
use super::rule::Family;
use super::{DECISIVE, DiagnoseOptions};
use rsf_fit::data::Record;
use rsf_fit::fit::{FitOptions, FitResult, ParamName, Params, Prepared, prepare};
use rsf_fit::parallel::par_map;
use rsf_fit::segment::{Segment, SegmentOptions, detect};
use rsf_laws::reshaped::{EXPONENT, reshaped};
use serde::Serialize;
use std::sync::Arc;

/// What a form test changes in a model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Reshaping {
    /// Each state's law read at a reshaped state θ_ref(θ/θ_ref)^p.
    State,
    /// The direct effect made rate dependent: ∂f/∂ln V = a + a₁ ln(V/V0).
    DirectEffect,
}

/// The form test of one fitted model: the best of the reshaped models against it.
#[derive(Clone, Debug, Serialize)]
pub struct FormTest {
    /// The cause whose model was reshaped: the one named, or a rival's.
    pub model: Cause,
    /// What was reshaped: the laws' state, or the direct effect.
    pub reshaping: Reshaping,
    /// Whether that is the model named (else the best credible rival on the menu, reshaped).
    pub named: bool,
    /// The laws reshaped, one per state variable (their names as in results).
    pub laws: Vec<String>,
    /// The fitted exponents p, one per state variable (1: the law's own form; empty when the
    /// direct effect was reshaped).
    pub p: Vec<f64>,
    /// The fitted rate dependence a₁ of the direct effect and a₁/a (when it was reshaped).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub a_slope: Option<(f64, f64)>,
    /// ΔBIC of the reshaped model against the model named, both refitted alike (negative:
    /// reshaped better).
    pub delta_bic: f64,
    /// rms of the reshaped fit over the model named's refit.
    pub rms_ratio: f64,
    /// Exponents (`p1`) or a₁ (`a_slope`) at a bound of their range: the direction is
    /// measured, not the value.
    pub at_bound: Vec<String>,
    /// The null distribution of the reshaped model's gain under the model named (run when the
    /// gain is decisive).
    pub null: Option<NullCalibration>,
    /// The verdict: the reshaped model's gain is decisive and would not arise by chance.
    pub misfit: bool,
}

impl FormTest {
    /// Whether a reshaped model fits decisively better, beyond chance: the law named is not
    /// the record's.
    pub fn inadequate(&self) -> bool {
        self.misfit
    }

    /// Whether a rival's law, reshaped, explains the record decisively better than the model
    /// named (ΔBIC below [`DECISIVE`], the evidence every extension must show), by no more than
    /// chance under the model named: a model without the cause named then does as well as the
    /// model with it, and the record does not tell which it needs (`undecided`,
    /// [`super::Apart::Form`]). Seed 40 record 13 of the `--outside` study (power-law aging
    /// under 1/f noise): the Aging–Slip law reshaped gained ΔBIC −168 over the cut-off named,
    /// within what its replicates reach (false-alarm probability 0.06), and the cut-off was named.
    pub fn rival_does_as_well(&self) -> bool {
        !self.named && !self.misfit && self.delta_bic < DECISIVE
    }

    /// Why the record is `undecided` between the cause `named` and the `rival` whose law,
    /// reshaped, does as well ([`FormTest::rival_does_as_well`]), in words.
    pub(super) fn as_well_words(&self, named: Cause, rival: Cause) -> String {
        let chance = self
            .null
            .as_ref()
            .map_or(String::new(), |n| format!(" (false-alarm probability {:.1e})", n.false_alarm_probability));
        format!(
            "{rival}'s law ({}) read at a reshaped state explains the record better than {named}'s model (ΔBIC {:.1}), \
             by no more than the record's noise gives it{chance}: a model without {named} does as well",
            self.laws.join(", "),
            self.delta_bic
        )
    }

    /// The test in words.
    pub fn words(&self) -> String {
        let p: Vec<String> = self
            .p
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let bound =
                    if self.at_bound.contains(&format!("{EXPONENT}{}", i + 1)) { " (at its bound)" } else { "" };
                format!("{p:.2}{bound}")
            })
            .collect();
        let laws = self.laws.join(" and ");
        let what = match (self.reshaping, self.named) {
            (Reshaping::State, true) => format!("{laws} read at a reshaped state θ_ref(θ/θ_ref)^p"),
            (Reshaping::State, false) => {
                format!("the rival {} ({laws}) read at a reshaped state θ_ref(θ/θ_ref)^p", self.model)
            }
            (Reshaping::DirectEffect, _) => format!("{laws} with a direct effect a + a₁ ln(V/V0)"),
        };
        // the fitted values in words: the exponents, or a₁
        let p = match self.a_slope {
            Some((a1, ratio)) => {
                let bound = if self.at_bound.iter().any(|n| n == "a_slope") { " (at its bound)" } else { "" };
                vec![format!("a₁ {a1:.2e}, a₁/a {ratio:+.3}{bound}")]
            }
            None => vec![format!("p = {}", p.join(", "))],
        };
        let (whose, holds) = match self.reshaping {
            Reshaping::State => ("its law's dependence on state", "its law's form holds"),
            Reshaping::DirectEffect => ("its direct effect", "its direct effect holds"),
        };
        let chance = self.null.as_ref().map_or(String::new(), |n| {
            format!(
                ", false-alarm probability {:.1e} (at most {:.1e}; {} of {} replicates reached it)",
                n.false_alarm_probability, n.false_alarm_upper, n.exceeded, n.replicates
            )
        });
        if self.misfit {
            format!(
                "{whose} is not the record's: {what} fits decisively better ({}, ΔBIC {:.1}, rms ratio {:.3}{chance})",
                p.join(", "),
                self.delta_bic,
                self.rms_ratio
            )
        } else if self.delta_bic < DECISIVE && self.null.as_ref().is_some_and(|n| n.uninformative) {
            format!(
                "{holds}: {what} gains ΔBIC {:.1} ({}), but its null replicates only lost, so they \
                 describe nothing, and the gain is short of the {BLIND_DECISIVE:.0} asked then{chance}",
                self.delta_bic,
                p.join(", ")
            )
        } else if self.delta_bic < DECISIVE {
            format!(
                "{holds}: {what} gains ΔBIC {:.1} ({}), no more than the record's noise gives it{chance}",
                self.delta_bic,
                p.join(", ")
            )
        } else {
            format!("{holds} ({what}: {}, ΔBIC {:+.1})", p.join(", "), self.delta_bic)
        }
    }
}

/// A model as fitted: its cause, options and fit.
pub(super) type Fitted<'a> = (Cause, &'a FitOptions, &'a FitResult);

/// A refit: the prepared record, the fit and its residuals' noise.
struct Refit {
    p: Prepared,
    f: FitResult,
    n: Noisy,
}

/// `o`'s model fitted to `rec` (segments `segs`) warm from `from`, one start, on a candidate's
/// budget, as it is or reshaped.
fn refit(
    ctx: &Ctx,
    rec: &Record,
    segs: &[Segment],
    o: &FitOptions,
    from: &Params,
    shape: Option<Reshaping>,
) -> Option<Refit> {
    let laws = match shape {
        Some(Reshaping::State) => {
            o.laws.iter().map(|l| reshaped(Arc::clone(l))).collect::<Result<Vec<_>, String>>().ok()?
        }
        Some(Reshaping::DirectEffect) | None => o.laws.clone(),
    };
    let fit_a_slope = o.fit_a_slope || shape == Some(Reshaping::DirectEffect);
    // a₁ is measured within the slip rates the record's baseline reaches
    let a_slope_range = if fit_a_slope { Some(ctx.v_range) } else { o.a_slope_range };
    let or = FitOptions {
        laws,
        fit_a_slope,
        a_slope_range,
        starts: 1,
        budget: ctx.cand_opts.budget,
        threads: 1,
        ..o.clone()
    };
    let p = prepare(rec, segs, &or).ok()?;
    let f = ctx.fit_best(&p, &or, from, 1)?;
    let n = noisy(&f);
    Some(Refit { p, f, n })
}

/// The form test of the model named, `named`, against itself reshaped and each of `rivals`
/// reshaped (module doc): the best of them. `None` when no model could be reshaped (a law with
/// a parameter named [`EXPONENT`]) or fitted.
pub(super) fn form_test(ctx: &Ctx, named: Fitted, rivals: &[Fitted], family: Family) -> Option<FormTest> {
    let (rec, segs) = (ctx.rec, ctx.segs);
    // (is it the model named, what is reshaped, (cause, options, its fit)): the model named's
    // state and direct effect, each rival's state
    // (a model that already fits a₁ has no direct effect to reshape)
    let models: Vec<(bool, Reshaping, Fitted)> =
        [(true, Reshaping::State, named), (true, Reshaping::DirectEffect, named)]
            .into_iter()
            .filter(|&(_, shape, (_, o, _))| shape == Reshaping::State || !o.fit_a_slope)
            .chain(rivals.iter().map(|&r| (false, Reshaping::State, r)))
            .collect();
    let o_named = named.1;
    // the model named refitted as it is, then each model reshaped
    let jobs: Vec<(Option<Reshaping>, &FitOptions, &FitResult)> = std::iter::once((None, o_named, named.2))
        .chain(models.iter().map(|&(_, shape, (_, o, f))| (Some(shape), o, f)))
        .collect();
    let mut first =
        par_map(&jobs, ctx.opts.threads, |&(shape, o, f)| refit(ctx, rec, segs, o, &f.params, shape)).into_iter();
    let control = first.next().flatten()?;
    let shaped: Vec<Option<Refit>> = first.collect();
    // each model back from its reshaped optimum, exponents at 1 and a₁ at 0
    let back = par_map(&(0..models.len()).collect::<Vec<_>>(), ctx.opts.threads, |&i| {
        refit(ctx, rec, segs, models[i].2.1, &shaped[i].as_ref()?.f.params, None)
    });
    let better = |a: &Refit, b: &Refit| scores(&a.f, &a.n, &b.f, &b.n).0 < 0.0;
    let tried: Vec<(FormTest, &Refit, &Refit)> = models
        .iter()
        .zip(&shaped)
        .zip(&back)
        .filter_map(|((&(is_named, reshaping, (cause, o, _)), r), b)| {
            let r = r.as_ref()?;
            // what the model named reaches without the exponents
            let against = match b.as_ref() {
                Some(b) if is_named && better(&control, b) => b,
                _ => &control,
            };
            let (mut delta_bic, _) = scores(&against.f, &against.n, &r.f, &r.n);
            // a rival's exponents must earn against the rival itself, from the same optimum
            if let Some(b) = b.as_ref().filter(|_| !is_named) {
                delta_bic = delta_bic.max(scores(&b.f, &b.n, &r.f, &r.n).0);
            }
            let names: Vec<String> = o.laws.iter().map(|l| l.name()).collect();
            let added: Vec<String> = match reshaping {
                Reshaping::State => (1..=names.len()).map(|i| format!("{EXPONENT}{i}")).collect(),
                Reshaping::DirectEffect => vec![ParamName::ASlope.text()],
            };
            let (p, a_slope) = match reshaping {
                Reshaping::State => {
                    (added.iter().map(|e| r.f.params.law_params.get(e).copied().unwrap_or(f64::NAN)).collect(), None)
                }
                Reshaping::DirectEffect => (vec![], Some((r.f.params.a_slope, r.f.params.a_slope / r.f.params.a))),
            };
            let at_bound = r.f.at_bound.iter().filter(|n| added.contains(n)).cloned().collect();
            let t = FormTest {
                model: cause,
                reshaping,
                named: is_named,
                laws: names,
                p,
                a_slope,
                delta_bic,
                rms_ratio: r.f.rms / against.f.rms,
                at_bound,
                null: None,
                misfit: false,
            };
            Some((t, against, r))
        })
        .collect();
    let i = (0..tried.len()).min_by(|&a, &b| tried[a].0.delta_bic.total_cmp(&tried[b].0.delta_bic))?;
    let (mut best, against, r) = (tried[i].0.clone(), tried[i].1, tried[i].2);
    if !(best.delta_bic < DECISIVE) {
        return Some(best);
    }
    let shaped_opts =
        models.iter().find(|m| m.0 == best.named && m.1 == best.reshaping && m.2.0 == best.model).map(|m| m.2)?;
    // the level the best gain is held to: shared by the reshapings tried and the family
    let level = ctx.opts.false_alarm_level / tried.len().max(1) as f64 * family.share();
    if ctx.opts.null_replicates > 0 {
        let observed = gain(&against.f, &against.n, &r.f, &r.n);
        best.null = null(ctx, &control, o_named, (best.reshaping, shaped_opts), observed, &r.n, level);
    }
    best.misfit = significant(ctx.opts, best.delta_bic, best.null.as_ref(), level);
    Some(best)
}

/// Whether a decisive gain (`delta_bic`), the best of the reshaped models tried, is beyond
/// chance under its `null` (none: no replicates were asked for, and the decisive ΔBIC decides):
/// below `level` — the false-alarm level divided by the reshapings tried (Bonferroni: the best
/// of several gains is chosen before its null is drawn, and each reshaping tried is one more
/// chance for the truth to lose) and shared by the test's family (`rule.rs`'s `Family`) — or,
/// where the replicates only lose (their null describes nothing), beyond ten times the decisive
/// ΔBIC.
fn significant(opts: &DiagnoseOptions, delta_bic: f64, null: Option<&NullCalibration>, level: f64) -> bool {
    match null {
        None => opts.null_replicates == 0,
        Some(n) if n.uninformative => delta_bic < BLIND_DECISIVE,
        Some(n) => n.false_alarm_probability < level,
    }
}

/// The null distribution of the gain `observed` (2 Δln L) of the reshaped `shaped` model over
/// the model named (`o_named`, refitted as `control`): replicates of the control's curve plus
/// the reshaped fit's noise `nr` (and the record's load-point noise, re-segmented), each refitted
/// with the model named from the control's optimum and with the model reshaped from the fit it
/// was reshaped from.
fn null(
    ctx: &Ctx,
    control: &Refit,
    o_named: &FitOptions,
    (reshaping, shaped): (Reshaping, Fitted),
    observed: f64,
    nr: &Noisy,
    level: f64,
) -> Option<NullCalibration> {
    let (_, o_shaped, from_shaped) = shaped;
    let added = match reshaping {
        Reshaping::State => o_shaped.laws.len(),
        Reshaping::DirectEffect => 1,
    };
    let dk = added + from_shaped.n_free.saturating_sub(control.f.n_free);
    let one = |seed: &u64| -> Option<f64> {
        let mut rec = replicate(&control.p, &control.f, &nr.model, *seed);
        let segs = match ctx.lp_noise {
            Some(sx) => {
                replicate_load_point(&control.p, &mut rec, sx, *seed);
                detect(&rec.time, &rec.load_point, &SegmentOptions::default())
            }
            None => control.p.segments.clone(),
        };
        let fb = refit(ctx, &rec, &segs, o_named, &control.f.params, None)?;
        let fr = refit(ctx, &rec, &segs, o_shaped, &from_shaped.params, Some(reshaping))?;
        Some(gain(&fb.f, &fb.n, &fr.f, &fr.n))
    };
    sequential(ctx.opts, level, observed, dk, one)
}
