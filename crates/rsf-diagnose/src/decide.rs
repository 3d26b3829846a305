//! The decision: which decisive candidate is credible, the verdict in words, and the start of a
//! combination from two optima.

use super::adequacy::Adequacy;
use super::cause::{Cause, Effect};
use super::rule::AdequacyVerdict;
use super::{Candidate, DECISIVE, Disagreement, Gain, Secondary};
use rsf_fit::fit::{FitResult, Params};

/// A candidate the held-out test cannot judge, or whose null replicates cannot calibrate it
/// (`NullCalibration::uninformative`), must earn ten times the decisive ΔBIC instead: one check
/// fewer, more evidence. (The detection study's record 55, plain friction with AR(1)
/// noise, spikes and encoder noise, scores a spurious cut-off of ΔBIC −34 that only the
/// held-out test caught; record 82's real cut-off scores −4006.)
pub(super) const BLIND_DECISIVE: f64 = 10.0 * DECISIVE;

/// An extension predicts the held-out part credibly when its rms there is at most this
/// multiple of the baseline's.
const HELDOUT_TOLERANCE: f64 = 1.05;

/// A candidate whose held-out prediction is worse but whose training part is blind to it, or
/// never saw the change of σ the held-out part holds (`Candidate::heldout_uninformative`), is
/// named only on an argument that does not use the full-record ΔBIC: the null calibration,
/// with noise drawn from the record's own fitted
/// spectrum (1/f drift included), at this fraction of the false-alarm level — one check is
/// missing, so the remaining one must be ten times as sure. (A spurious cut-off absorbing
/// drift in the holds of a 1/f-noise record had a held-out prediction 9× worse and passed the
/// white + AR(1) null; record 82's real one passes this at p < 1e-6.)
const BLIND_LEVEL_FACTOR: f64 = 0.1;

/// Why a decisive candidate is not named: it predicts the held-out part worse (it fits the
/// training data better but overfits), its fit did not converge (its effect is not measured), its fit ran to a physical bound (the data do not
/// constrain it: e.g. a second state turned into a linear trend), or its gain is not rare
/// under the baseline and the record's own noise.
pub(super) fn ineligible(c: &Candidate, level: f64) -> Option<String> {
    let worse = !heldout_ok(c.heldout_rms_before, c.heldout_rms_after);
    if c.heldout_uninformative && worse {
        // the held-out test cannot judge it: the null must, at a stricter level
        let strict = level * BLIND_LEVEL_FACTOR;
        return match &c.null {
            Some(n) if n.false_alarm_upper < strict => None,
            Some(n) => Some(format!(
                "{} predicted the held-out part worse, and its training part cannot see it; its gain arises by \
                 chance under the record's own noise with probability {:.2e} (at most {:.2e} as far as {} \
                 replicates tell), not below {strict:.0e}",
                c.cause, n.false_alarm_probability, n.false_alarm_upper, n.replicates
            )),
            None => Some(format!(
                "{} predicted the held-out part worse, and its training part cannot see it; no null calibration \
                 could judge it",
                c.cause
            )),
        };
    }
    if !c.heldout_uninformative && worse {
        Some(match c.heldout_rms_after {
            Some(_) => format!("{} predicted the held-out part worse", c.cause),
            None => format!("{} could not be fitted to the held-out training part", c.cause),
        })
    } else if let Some(why) = c.fit.as_ref().and_then(|f| f.convergence_text()) {
        // a gain measured at a point that is not an optimum, and an effect not measured
        Some(format!("{}: {why}", c.cause))
    } else if !c.at_bound.is_empty() {
        Some(format!("{} ran to a bound ({})", c.cause, c.at_bound.join(", ")))
    } else if let Some(why) = &c.unresolved {
        Some(format!("{}'s {why}", c.cause))
    } else if c.null.as_ref().is_some_and(|n| n.uninformative) && !(c.delta_bic < BLIND_DECISIVE) {
        Some(format!(
            "{}'s null replicates never gained (its fit lowers the likelihood on noise alone, so they cannot \
             calibrate it), and its ΔBIC {:.1} is not below {:.0}",
            c.cause, c.delta_bic, BLIND_DECISIVE
        ))
    } else {
        c.null.as_ref().filter(|n| !(n.false_alarm_upper < level)).map(|n| {
            if n.false_alarm_probability < level {
                format!(
                    "{}'s gain arises by chance under the baseline with probability {:.2e}, but with up to {:.2e} \
                     as far as {} noise replicates can tell ({} reached it): not surely below {level}",
                    c.cause, n.false_alarm_probability, n.false_alarm_upper, n.replicates, n.exceeded
                )
            } else {
                format!(
                    "{}'s gain arises by chance under the baseline with probability {:.2} ({} of {} noise replicates \
                     reached it)",
                    c.cause, n.false_alarm_probability, n.exceeded, n.replicates
                )
            }
        })
    }
}

/// A candidate set aside only because its fit did not converge (LM stopped on its iteration
/// limit or a budget) that already scores better than the cause chosen: it predicts the
/// held-out part as well as the baseline, and its ΔBIC, measured at the best point found, is an
/// upper bound on its optimum's. The model chosen is then beaten on the record by one whose
/// optimum is unknown, and is no longer the best explanation on the menu: the record is
/// `undecided` between them. (One scoring worse stays no rival, as before: a fit that does not
/// converge can be running off to a degenerate limit, as a cut-off whose Vc runs off above
/// 10⁵ µm/s does within 10 of Nagata's law on record 17 of the `--outside` study's seed 39.)
/// The detection study's seed 5 record 54, a slip trend of g 1e-7/µm on a gouge staircase: the
/// trend's fit exhausted its step budget at ΔBIC −33.4 (g 7.2e-8), and a Slip–Aging mixture at
/// −12.6 was named.
pub(super) fn unconverged_rival<'a>(chosen: &Candidate, candidates: &'a [Candidate]) -> Option<&'a Candidate> {
    candidates
        .iter()
        .filter(|c| c.cause != chosen.cause && !c.converged && c.fit.is_some())
        .filter(|c| c.delta_bic < super::DECISIVE && c.delta_bic < chosen.delta_bic)
        .filter(|c| heldout_ok(c.heldout_rms_before, c.heldout_rms_after))
        .min_by(|a, b| a.delta_bic.total_cmp(&b.delta_bic))
}

/// The held-out test passes when the extension predicts no more than 5% worse; it fails when
/// the extension's training fit fails where the baseline's did not (an extension the training
/// part cannot pin down is the overfitting the test is there to catch). A candidate whose
/// training part is blind to its effect by construction, or never saw the change of σ the
/// held-out part holds (`Candidate::heldout_uninformative`), is not judged by it.
pub(super) fn heldout_ok(before: Option<f64>, after: Option<f64>) -> bool {
    match (before, after) {
        (Some(b), Some(a)) => a <= HELDOUT_TOLERANCE * b,
        (Some(_), None) => false,
        _ => true,
    }
}

/// Without an adequacy test, the one check left on the model named is that the record's parts
/// agree about it: a candidate that scores better than the chosen one on the whole record but
/// predicts the held-out part worse than the baseline (or cannot be fitted to the training
/// part) contradicts it — one model fits the whole better, the other predicts the unseen part
/// better, and a model that explained the record would do both. Such a record gets no cause
/// named. (A candidate the held-out test cannot judge, `heldout_uninformative`, is no
/// contradiction.) In the `--outside` study with the law file registered, every untestable
/// record that named a wrong cause did so this way (a cut-off chosen after the evolution law's
/// better score was set aside on its held-out prediction); no correctly named untestable record
/// of the four study sets did (docs/diagnose/detection.md).
fn disagreement(chosen: &Candidate, candidates: &[Candidate]) -> Option<Disagreement> {
    candidates
        .iter()
        .filter(|o| o.cause != chosen.cause && o.delta_bic < chosen.delta_bic && o.delta_bic < DECISIVE)
        .find(|o| !o.heldout_uninformative && !heldout_ok(o.heldout_rms_before, o.heldout_rms_after))
        .map(|o| Disagreement {
            better: o.cause,
            extension: o.extension.clone(),
            delta_bic: o.delta_bic,
            heldout_rms_before: o.heldout_rms_before,
            heldout_rms_after: o.heldout_rms_after,
        })
}

/// The words of a [`Disagreement`] with the chosen candidate `c`.
fn disagreement_words(d: &Disagreement, c: &Candidate) -> String {
    let held_out = match (d.heldout_rms_before, d.heldout_rms_after) {
        (Some(b), Some(a)) => format!("predicts the held-out part worse than the baseline (rms {b:.2e} → {a:.2e})"),
        _ => "cannot be fitted to the held-out test's training part".into(),
    };
    format!(
        "{} scores better on the whole record (ΔBIC {:.1}) but {held_out}, while {} (ΔBIC {:.1}) predicts it{}; \
         a model that explained the record would do both, and the record's adequacy cannot be tested, so no \
         cause is named",
        d.extension,
        d.delta_bic,
        c.extension,
        c.delta_bic,
        match (c.heldout_rms_before, c.heldout_rms_after) {
            (Some(b), Some(a)) => format!(" (rms {b:.2e} → {a:.2e})"),
            _ => String::new(),
        }
    )
}

/// The start of a combination: the parameters `p1` of the first extension's fit, with the
/// parameters that the extension `cause2` adds taken from its own fit `p2`.
pub(super) fn merge(p1: &Params, p2: &Params, cause2: Cause) -> Params {
    let mut p = p1.clone();
    match cause2 {
        Cause::SecondStateVariable if p1.b.len() == 1 && p2.b.len() == 2 => {
            // the slower of the two states as the added one
            let i = if p2.dc[1] >= p2.dc[0] { 1 } else { 0 };
            p.b.push(p2.b[i]);
            p.dc.push(p2.dc[i]);
        }
        Cause::CutoffVelocity => p.law_params.extend(p2.law_params.iter().map(|(k, v)| (k.clone(), *v))),
        Cause::SlipTrend => p.g = p2.g,
        Cause::Stiffness => p.k = p2.k,
        Cause::NormalStressCoupling => p.alpha = p2.alpha.clone(),
        // nothing to carry over: the baseline, a second state the first fit already has, or
        // a law change (its fit starts from its own law's parameters)
        Cause::SecondStateVariable | Cause::None | Cause::EvolutionLaw | Cause::Unexplained | Cause::Undecided => {}
    }
    p
}

/// What the diagnosis concludes.
pub(super) struct Verdict {
    /// The cause named (`None` when no extension earns its parameters).
    pub cause: Cause,
    /// The reason in words.
    pub reason: String,
    /// The extended fit.
    pub extended: Option<FitResult>,
    /// What the extension gains.
    pub gain: Option<Gain>,
    /// How large the cause is.
    pub effect: Effect,
    /// ΔBIC of the chosen extension, or of the best candidate for `none`.
    pub confidence: f64,
    /// For `unexplained`: the best partial extension.
    pub partial: Option<Cause>,
    /// For `unexplained` on an untestable record: the parts' disagreement.
    pub disagreement: Option<Disagreement>,
}

/// The verdict after the adequacy test of the model it names: unchanged when the model explains
/// the events to the noise level; `unexplained` with the best partial extension when it does
/// not, or when the test cannot run and the record's parts disagree ([`disagreement`]).
pub(super) fn judge_adequacy(
    v: &mut Verdict,
    adequacy: &Adequacy,
    chosen: Option<&Candidate>,
    decisive: &[&Candidate],
    candidates: &[Candidate],
) {
    let reason = std::mem::take(&mut v.reason);
    v.reason = match adequacy.verdict {
        AdequacyVerdict::Inadequate => {
            // the best partial extension: the one named, else the best decisive candidate
            let best = chosen.or_else(|| decisive.first().copied());
            if let Some(b) = best.filter(|_| chosen.is_none()) {
                v.extended = b.fit.clone();
                v.gain = Some(Gain {
                    delta_bic: b.delta_bic,
                    delta_aic: b.delta_aic,
                    rms_ratio: b.rms_ratio,
                    heldout_rms_before: b.heldout_rms_before,
                    heldout_rms_after: b.heldout_rms_after,
                });
                v.effect = b.effect.clone();
                v.confidence = b.delta_bic;
            }
            v.partial = best.map(|b| b.cause);
            v.cause = Cause::Unexplained;
            // the model judged: the one named, else the baseline (a decisive candidate set aside
            // is the best partial extension, but the misfit found is the baseline's)
            match (best, chosen) {
                (Some(b), Some(_)) => format!(
                    "not explained: the best extension on the menu, {} (ΔBIC {:.1}), helps but {}; the named model's cause lies outside the menu (before: {reason})",
                    b.extension,
                    b.delta_bic,
                    adequacy.words()
                ),
                (Some(b), None) => format!(
                    "not explained: no extension on the menu is both decisive and credible (the best, {} at ΔBIC {:.1}, was set aside), and the baseline does not explain the record: {}; the cause lies outside the menu (before: {reason})",
                    b.extension,
                    b.delta_bic,
                    adequacy.words()
                ),
                (None, _) => format!(
                    "not explained: no extension on the menu earns its parameters, yet the baseline does not explain the record: {}; the cause lies outside the menu (before: {reason})",
                    adequacy.words()
                ),
            }
        }
        AdequacyVerdict::Adequate => format!("{reason}; {}", adequacy.words()),
        AdequacyVerdict::Untestable => match chosen.and_then(|c| disagreement(c, candidates).map(|d| (c, d))) {
            Some((c, d)) => {
                let words = disagreement_words(&d, c);
                v.partial = Some(c.cause);
                v.cause = Cause::Unexplained;
                v.disagreement = Some(d);
                format!("not explained: {words} (before: {reason})")
            }
            None => format!("{reason}; {}", adequacy.words()),
        },
    };
}

/// The cause, the reason in words, the extended fit, the gain, the effect and the confidence.
pub(super) fn verdict(
    n_eff: f64,
    chosen: Option<&Candidate>,
    candidates: &[Candidate],
    rejected: &[String],
    secondary: &Option<Secondary>,
) -> Verdict {
    let rejected_note = if rejected.is_empty() {
        String::new()
    } else {
        format!(" (better-scoring but set aside: {})", rejected.join("; "))
    };
    match chosen {
        Some(c) => Verdict {
            cause: c.cause,
            reason: format!(
                "{} improves the fit decisively: ΔBIC = {:.1} with n_eff = {:.0} (threshold {DECISIVE}), rms ratio {:.3}{}{}{}{}",
                c.extension,
                c.delta_bic,
                n_eff,
                c.rms_ratio,
                match (c.heldout_rms_before, c.heldout_rms_after) {
                    (Some(b), Some(a)) => format!(", held-out rms {b:.2e} → {a:.2e}"),
                    _ => String::new(),
                } + if c.heldout_uninformative && !heldout_ok(c.heldout_rms_before, c.heldout_rms_after) {
                    " (the held-out test cannot judge it: its training part cannot see the effect, or never saw \
                     the change of σ the held-out part holds)"
                } else {
                    ""
                },
                match &c.null {
                    Some(n) => format!(
                        ", false-alarm probability {:.1e} ({} of {} noise replicates reached its gain)",
                        n.false_alarm_probability, n.exceeded, n.replicates
                    ),
                    None => String::new(),
                },
                match secondary {
                    Some(s) => format!("; adding {} gains a further ΔBIC = {:.1}", s.cause, s.delta_bic),
                    None => String::new(),
                } + &if c.equally_good_laws.is_empty() {
                    String::new()
                } else {
                    // when no law is named, the list holds the one fitted too
                    let laws = &c.equally_good_laws;
                    let list = match laws.as_slice() {
                        [one] => format!("the {one} law explains"),
                        [rest @ .., last] => format!("the {} and {last} laws explain", rest.join(", ")),
                        [] => String::new(),
                    };
                    if c.law_undecided {
                        format!(
                            "; {} the record as well as each other with as few parameters (ΔBIC within {}): the \
                             record cannot tell them apart, so no law is named, only that the baseline's is not the \
                             record's",
                            list, -DECISIVE
                        )
                    } else {
                        format!(
                            "; {list} the record as well (ΔBIC within {}) with more parameters: the record cannot tell \
                             them apart, and the simplest is named",
                            -DECISIVE
                        )
                    }
                },
                rejected_note
            ),
            extended: c.fit.clone(),
            gain: Some(Gain {
                delta_bic: c.delta_bic,
                delta_aic: c.delta_aic,
                rms_ratio: c.rms_ratio,
                heldout_rms_before: c.heldout_rms_before,
                heldout_rms_after: c.heldout_rms_after,
            }),
            effect: c.effect.clone(),
            confidence: c.delta_bic,
            partial: None,
            disagreement: None,
        },
        None => Verdict {
            cause: Cause::None,
            reason: match candidates.first() {
                Some(_) if !rejected.is_empty() => format!(
                    "no extension is both decisive and credible: {} (n_eff = {n_eff:.0}); the baseline stands",
                    rejected.join("; "),
                ),
                Some(b) => format!(
                    "no extension earns its parameters: best is {} with ΔBIC = {:.1} (needs < {DECISIVE}) with n_eff = {n_eff:.0}",
                    b.extension, b.delta_bic
                ),
                None => "no candidate could be fitted".into(),
            },
            extended: None,
            gain: None,
            effect: Effect::default(),
            confidence: candidates.first().map(|b| b.delta_bic).unwrap_or(0.0),
            partial: None,
            disagreement: None,
        },
    }
}

/// What tells two causes apart, in words, for the pairs whose effects are alike in a way
/// worth explaining (empty for the others).
pub(super) fn pair_words(a: Cause, b: Cause) -> &'static str {
    let pair = |x: Cause, y: Cause| (a, b) == (x, y) || (a, b) == (y, x);
    if pair(Cause::CutoffVelocity, Cause::EvolutionLaw) {
        " — a cut-off and a share of time-dependent healing both strengthen long holds: a cut-off flattens \
         healing only in holds whose slip rate falls below Vc, a share of time-dependent healing also changes \
         the velocity steps"
    } else {
        ""
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn candidate(cause: Cause, delta_bic: f64, before: f64, after: f64) -> Candidate {
        Candidate {
            cause,
            extension: cause.as_str().into(),
            delta_bic,
            delta_aic: delta_bic,
            rms_ratio: 0.9,
            heldout_rms_before: Some(before),
            heldout_rms_after: Some(after),
            heldout_training_gain: None,
            heldout_uninformative: false,
            drift_share_after: 0.0,
            effect: Effect::default(),
            equally_good_laws: vec![],
            law_undecided: false,
            alternatives: vec![],
            unfitted_ways: vec![],
            adequacy_excess: f64::NAN,
            steps: 0,
            null: None,
            at_bound: vec![],
            unresolved: None,
            converged: true,
            fit: None,
            heldout_fit: None,
            options: None,
        }
    }

    /// The parts of a record disagree when a candidate scoring better than the one chosen
    /// predicts the held-out part worse than the baseline (record 23 of the `--outside` study
    /// before the level test caught it: the Aging–Slip law at ΔBIC −446 predicting 1.005e-3 →
    /// 1.074e-3 while the cut-off chosen at −424 predicted no worse); not when the better one
    /// predicts it too, nor when the held-out test cannot judge it.
    #[test]
    fn a_better_score_that_predicts_worse_is_a_disagreement() {
        let chosen = candidate(Cause::CutoffVelocity, -424.0, 1.005e-3, 1.005e-3);
        let better = candidate(Cause::EvolutionLaw, -446.0, 1.005e-3, 1.074e-3);
        let d = disagreement(&chosen, &[better.clone(), chosen.clone()]).expect("a disagreement");
        assert_eq!(d.better, Cause::EvolutionLaw);
        assert_eq!(d.heldout_rms_after, Some(1.074e-3));
        let agrees = candidate(Cause::EvolutionLaw, -446.0, 1.005e-3, 1.0e-3);
        assert!(disagreement(&chosen, &[agrees, chosen.clone()]).is_none());
        let blind = Candidate { heldout_uninformative: true, ..better.clone() };
        assert!(disagreement(&chosen, &[blind, chosen.clone()]).is_none());
        let worse_score = candidate(Cause::EvolutionLaw, -400.0, 1.005e-3, 1.074e-3);
        assert!(disagreement(&chosen, &[worse_score, chosen.clone()]).is_none());
    }
}
