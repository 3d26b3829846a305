//! The diagnosis in words: the verdict paragraph, and parameters with names, units and errors.

use super::esc;
use rsf_diagnose::{
    AdequacyTest, Apart, Cause, DECISIVE, Diagnosis, Effect, EffectEntry, EffectKey, EffectValue, Evidence,
};
use rsf_fit::fit::{FitResult, ParamName};
use rsf_plot::{fmt_num, fmt_pair, fmt_value, fmt_with_err};

/// A cause in words, as the object of "the data need …".
pub(crate) fn cause_words(cause: Cause) -> &'static str {
    match cause {
        Cause::None => "no extension",
        Cause::EvolutionLaw => "a different evolution law",
        Cause::SecondStateVariable => "a second state variable",
        Cause::CutoffVelocity => "a cut-off velocity",
        Cause::SlipTrend => "a slip trend",
        Cause::Stiffness => "a different machine stiffness",
        Cause::NormalStressCoupling => "a coupling of state to normal-stress changes",
        Cause::Unexplained => "something outside the menu",
        Cause::Undecided => "one of two extensions",
    }
}

/// χ²/dof of the per-event Dc above which the events disagree on Dc, worth saying (a
/// consistent Dc scatters with χ²/dof ≈ 1; 4 is well past chance for ≥ 3 events).
const DC_SPREAD_CHI2: f64 = 4.0;
/// d ln Dc / d ln(step or hold) worth naming beside the spread (5% per e-fold).
const DC_SLOPE_NOTED: f64 = 0.05;
/// |t| of the residuals' trend with ln V, or of their drift with displacement, worth naming
/// as the reason (a trend at 3σ, or 2σ for the slip trend whose candidate is itself tested).
const LN_V_TREND_T: f64 = 3.0;
/// As [`LN_V_TREND_T`], for the residuals' drift with load-point displacement.
const SLIP_TREND_T: f64 = 2.0;
/// Worst segment's misfit over the median segment's worth naming as slow transients.
const SEGMENT_RMS_NOTED: f64 = 2.0;

/// `slip` → `Slip`, `slip+aging` → `Slip + Aging`, `kato-tullis` → `Kato–Tullis`.
pub(crate) fn law_words(law: &str) -> String {
    // a registered law by its words ("power-law aging"); a law the registry does not hold (a
    // diagnosis read back in another process) by its name, capitalised
    let one = |l: &str| match l.parse::<rsf_laws::Law>() {
        Ok(law) => law.words().to_string(),
        Err(_) if rsf_laws::registry::find(l).is_ok_and(|e| !e.words().is_empty()) => {
            rsf_laws::registry::find(l).map(|e| e.words().to_string()).unwrap_or_default()
        }
        Err(_) => {
            let mut c = l.chars();
            c.next().map(|f| f.to_uppercase().chain(c).collect()).unwrap_or_default()
        }
    };
    law.split('+').map(one).collect::<Vec<_>>().join(" + ")
}

/// `2` → `₂`.
pub(crate) fn subscript(n: usize) -> String {
    const D: [char; 10] = ['₀', '₁', '₂', '₃', '₄', '₅', '₆', '₇', '₈', '₉'];
    n.to_string().chars().map(|c| D[c.to_digit(10).unwrap_or(0) as usize]).collect()
}

const VC: &str = "cut-off velocity: time-dependent healing only below it";
const ALPHA: &str = "Linker–Dieterich coupling of state to normal-stress changes";

/// Name, unit and meaning of an effect parameter: its own words for the keys that are not fit
/// parameters (the law, a share) and for the unindexed Vc, α, c and w; the fit parameter's
/// otherwise.
pub(crate) fn effect_meta(key: &EffectKey) -> (String, &'static str, &'static str) {
    match key {
        EffectKey::Law => ("law".into(), "", "evolution law(s) of the extended model"),
        EffectKey::BOtherFraction => {
            ("share of b".into(), "", "share of the evolution effect carried by the other law")
        }
        EffectKey::Vc => ("Vc".into(), "µm/s", VC),
        EffectKey::Alpha => ("α".into(), "", ALPHA),
        EffectKey::C => ("c".into(), "", "Nagata's stress-weakening coefficient"),
        EffectKey::W => ("w".into(), "", "aging share of one state's evolution rate"),
        EffectKey::B2 | EffectKey::Dc2 | EffectKey::G | EffectKey::K | EffectKey::LawParameter(_) => {
            param_meta(key.text())
        }
    }
}

/// Name (with subscripts), unit and meaning of a fit parameter, by its parsed [`ParamName`]
/// (a name that does not parse is shown as written).
pub(crate) fn param_meta(key: &str) -> (String, &'static str, &'static str) {
    let Some(p) = ParamName::parse(key) else {
        return (key.to_string(), "", "");
    };
    match p {
        ParamName::Mu0 => ("μ₀".into(), "", "steady-state friction at the reference rate"),
        ParamName::A => ("a".into(), "", "direct effect"),
        ParamName::K => ("k".into(), "/µm", "machine stiffness (friction per µm of load point)"),
        ParamName::G => ("g".into(), "/µm", "friction change per µm of slip"),
        ParamName::ASlope => ("a₁".into(), "", "change of the direct effect per e-fold of slip rate"),
        ParamName::B(i) => (
            format!("b{}", subscript(i)),
            "",
            if i == 2 { "evolution effect of the second state" } else { "evolution effect" },
        ),
        ParamName::Dc(i) => (
            format!("Dc{}", subscript(i)),
            "µm",
            if i == 2 { "slip distance of the second state" } else { "slip distance" },
        ),
        ParamName::Alpha(i) => (format!("α{}", subscript(i)), "", ALPHA),
        ParamName::Law(name, i) if name == "vc" => (format!("Vc{}", subscript(i)), "µm/s", VC),
        ParamName::Law(name, i) => (format!("{name}{}", subscript(i)), "", "the law's own parameter"),
        ParamName::Mu0Seg(s) => (format!("μ₀ offset{}", subscript(s)), "", "friction offset of this segment"),
    }
}

/// An effect value, formatted with its unit and, from the fit `f`, the standard error of the
/// fitted parameter it is.
pub(crate) fn effect_value(e: &EffectEntry, f: Option<&FitResult>) -> String {
    let (_, unit, _) = effect_meta(&e.key);
    match &e.value {
        EffectValue::Number(x) => {
            let se = f.zip(e.parameter.as_ref()).and_then(|(f, p)| f.stderr.get(&p.text()).copied());
            fmt_with_err(*x, se.unwrap_or(f64::NAN), unit)
        }
        EffectValue::Law(s) => law_words(s),
    }
}

/// An effect in one line: `b₂ = 0.00401, Dc₂ = 59.6 µm` (without uncertainties; escaped HTML).
pub fn effect_summary(effect: &Effect) -> String {
    let parts: Vec<String> =
        effect.entries().iter().map(|e| format!("{} = {}", effect_meta(&e.key).0, effect_value(e, None))).collect();
    esc(&parts.join(", "))
}

/// The parameters of a fit as rows (name, value with unit and ± where fitted, fixed or not):
/// μ₀, a, b and Dc per state, law parameters, k, and g and a₁ when fitted or set.
pub fn param_rows(f: &FitResult) -> Vec<(String, String, bool)> {
    let p = &f.params;
    let mut v: Vec<(String, f64)> = vec![("mu0".into(), p.mu0), ("a".into(), p.a)];
    for (i, (b, dc)) in p.b.iter().zip(&p.dc).enumerate() {
        v.push((format!("b{}", i + 1), *b));
        v.push((format!("dc{}", i + 1), *dc));
    }
    v.extend(p.law_params.iter().map(|(k, x)| (k.clone(), *x)));
    v.push(("k".into(), p.k));
    for (name, x) in [(ParamName::G, p.g), (ParamName::ASlope, p.a_slope)] {
        if f.reports(&name) {
            v.push((name.text(), x));
        }
    }
    v.into_iter()
        .map(|(k, x)| {
            let (name, unit, _) = param_meta(&k);
            match f.stderr.get(&k) {
                Some(se) => (name, fmt_with_err(x, *se, unit), true),
                None => (name, fmt_value(x, unit), false),
            }
        })
        .collect()
}

/// A held-out comparison `before → after`, or empty.
pub(crate) fn heldout_words(before: Option<f64>, after: Option<f64>) -> Option<String> {
    Some(fmt_pair(before?, after?, 3))
}

/// What in the baseline residuals points at `cause`.
fn because(cause: Cause, d: &Diagnosis) -> String {
    let e: &Evidence = &d.evidence;
    let generic = format!(
        "the baseline misfit is {}× the noise estimated from sample-to-sample differences, with residuals \
         correlated from sample to sample (lag-one ρ = {})",
        fmt_num(e.misfit_over_noise, 2),
        fmt_num(e.residual_lag1, 2)
    );
    let ln_v = match (e.residual_vs_ln_v, e.residual_vs_ln_v_t) {
        (Some(s), Some(t)) if t.abs() > LN_V_TREND_T => Some(format!(
            "the baseline residuals trend with the logarithm of slip rate ({} per e-fold of V, t = {})",
            fmt_num(s, 2),
            fmt_num(t, 2)
        )),
        _ => None,
    };
    match cause {
        Cause::EvolutionLaw => match e.dc_consistency_chi2 {
            Some(chi2) if chi2 > DC_SPREAD_CHI2 => {
                let mut s = format!(
                    "the steps and holds refitted one at a time need different Dc (spread χ²/dof = {}",
                    fmt_num(chi2, 3)
                );
                if let Some(x) = e.dc_vs_ln_step.filter(|x| x.abs() > DC_SLOPE_NOTED) {
                    s += &format!("; ln Dc changes by {} per e-fold of step size", fmt_num(x, 2));
                }
                if let Some(x) = e.dc_vs_ln_hold.filter(|x| x.abs() > DC_SLOPE_NOTED) {
                    s += &format!("; by {} per e-fold of hold time", fmt_num(x, 2));
                }
                s + ")"
            }
            _ => ln_v.unwrap_or(generic),
        },
        Cause::CutoffVelocity => ln_v.unwrap_or(generic),
        Cause::SlipTrend if e.residual_trend_t.abs() > SLIP_TREND_T => format!(
            "the baseline residuals drift with load-point displacement ({} per µm, t = {})",
            fmt_num(e.residual_trend_per_um, 2),
            fmt_num(e.residual_trend_t, 2)
        ),
        Cause::Stiffness => match e.k_reload_slope {
            Some(k) => format!(
                "the elastic reloading slopes give k ≈ {} against the nominal {}",
                fmt_value(k, "/µm"),
                fmt_value(d.baseline.params.k, "/µm")
            ),
            None => generic,
        },
        Cause::SecondStateVariable if e.segment_rms_ratio > SEGMENT_RMS_NOTED => format!(
            "the baseline leaves slow transients: residuals correlated from sample to sample (lag-one ρ = {}) \
             and the worst segment's misfit {}× the median segment's",
            fmt_num(e.residual_lag1, 2),
            fmt_num(e.segment_rms_ratio, 2)
        ),
        Cause::SlipTrend
        | Cause::SecondStateVariable
        | Cause::None
        | Cause::NormalStressCoupling
        | Cause::Unexplained
        | Cause::Undecided => generic,
    }
}

/// What the data need, with the effect's numbers: "a second state variable (b₂ = …, Dc₂ = … µm)" (for
/// `unexplained`, what the best partial extension adds).
fn need(d: &Diagnosis) -> String {
    let f = d.extended.as_ref();
    let entries = d.effect.entries();
    let val = |k: EffectKey| entries.iter().find(|e| e.key == k).map(|e| effect_value(e, f));
    let base_law = law_words(d.baseline.params.laws.first().map(String::as_str).unwrap_or("slip"));
    // for `unexplained`, the best partial extension; for `undecided`, the better of the two
    let cause = match (d.cause, d.partial) {
        (Cause::Unexplained | Cause::Undecided, Some(p)) => p,
        (c, _) => c,
    };
    let plain = cause_words(cause).to_string();
    match cause {
        Cause::EvolutionLaw => match (d.effect.law.as_deref(), val(EffectKey::BOtherFraction)) {
            (Some(l), Some(share)) if l.contains('+') => {
                format!("a mixture of evolution laws ({}): a share {share} of b heals by the other law", law_words(l))
            }
            (Some(l), _) => {
                // a built-in law's own parameter (c, w) and a registered law's (power-law aging's n)
                let own = entries
                    .iter()
                    .filter(|e| matches!(e.key, EffectKey::C | EffectKey::W | EffectKey::LawParameter(_)))
                    .map(|e| format!("{} = {}", effect_meta(&e.key).0, effect_value(e, f)))
                    .collect::<Vec<_>>();
                let own = if own.is_empty() { String::new() } else { format!(" ({})", own.join(", ")) };
                format!("the {} law{own} instead of the {base_law} law", law_words(l))
            }
            _ => plain,
        },
        Cause::SecondStateVariable => match (val(EffectKey::B2), val(EffectKey::Dc2)) {
            (Some(b), Some(dc)) => format!("a second state variable (b₂ = {b}, Dc₂ = {dc})"),
            _ => plain,
        },
        Cause::CutoffVelocity => match val(EffectKey::Vc) {
            Some(v) => format!("a cut-off velocity: the Kato–Tullis law with Vc = {v}"),
            None => plain,
        },
        Cause::SlipTrend => match val(EffectKey::G) {
            Some(g) => format!("a slip trend in friction, g = {g}"),
            None => plain,
        },
        Cause::Stiffness => match val(EffectKey::K) {
            Some(k) => {
                format!(
                    "a machine stiffness of k = {k} instead of the nominal {}",
                    fmt_value(d.baseline.params.k, "/µm")
                )
            }
            None => plain,
        },
        Cause::NormalStressCoupling => match val(EffectKey::Alpha) {
            Some(a) => format!("a Linker–Dieterich coupling of state to normal-stress changes, α = {a}"),
            None => plain,
        },
        Cause::None | Cause::Unexplained | Cause::Undecided => plain,
    }
}

/// The verdict in one paragraph of plain words (escaped HTML): what the data need and why,
/// what it gains, and how sure the diagnosis is; or, for `none`, that the baseline stands and
/// what came closest.
pub fn verdict(d: &Diagnosis) -> String {
    let n_eff = format!("n_eff = {} of {} samples", fmt_num(d.evidence.n_effective.round(), 6), d.baseline.n);
    let laws: Vec<String> = d.baseline.params.laws.iter().map(|l| law_words(l)).collect();
    let baseline = format!(
        "baseline ({} law, {} state variable{})",
        laws.join(" + "),
        ["no", "one", "two", "three"].get(laws.len()).map_or(laws.len().to_string(), |w| w.to_string()),
        if laws.len() == 1 { "" } else { "s" }
    );
    if let (Cause::Unexplained, Some(dis)) = (d.cause, &d.disagreement) {
        let held_out = match (dis.heldout_rms_before, dis.heldout_rms_after) {
            (Some(b), Some(a)) => format!(
                "predicts the held-out part worse than the baseline (rms {} → {})",
                fmt_num(b, 3),
                fmt_num(a, 3)
            ),
            _ => "cannot be fitted to the held-out test's training part".into(),
        };
        let s = format!(
            "No cause is named: the record's parts disagree. {} scores better on the whole record (ΔBIC = {}) but \
             {held_out}, while {} predicts it no worse than the baseline does{}. A model that explained the record would do both; the record \
             has too few events with a quiet stretch as long as their transient to test either against its noise. \
             The cause may lie outside the menu: a law or effect the library does not have.",
            dis.extension,
            fmt_num(dis.delta_bic, 3),
            need(d),
            match &d.gain {
                Some(g) => format!(" (ΔBIC = {})", fmt_num(g.delta_bic, 3)),
                None => String::new(),
            }
        );
        return esc(&s);
    }
    if d.cause == Cause::Unexplained {
        let a = &d.adequacy;
        let who = match d.partial {
            Some(_) => format!("even the best extension, {},", need(d)),
            None => format!("the {baseline}"),
        };
        // where the misfit was found: by each test that found it, in the diagnosis's words
        let found: Vec<String> = a
            .misfits()
            .into_iter()
            .filter_map(|t| match t {
                AdequacyTest::Events => {
                    let worst: Vec<String> = a
                        .events
                        .iter()
                        .take(3)
                        .map(|e| {
                            format!(
                                "the {} at t = {} s ({}× its placebos)",
                                e.event,
                                fmt_num(e.t, 4),
                                fmt_num(e.ratio, 2)
                            )
                        })
                        .collect();
                    Some(format!(
                        "where the protocol's events are, an event-locked misfit of rms {} against a noise band of {} \
                         ({}× the noise's variance; a chance of {} under noise alone){}",
                        fmt_num(a.event_rms, 2),
                        fmt_num(a.noise_rms, 2),
                        fmt_num(a.excess, 3),
                        fmt_num(a.p_value, 2),
                        if worst.is_empty() { String::new() } else { format!(", worst {}", worst.join(", ")) }
                    ))
                }
                AdequacyTest::Levels => a.levels.words(),
                AdequacyTest::Quiet => a.quiet.words(),
                AdequacyTest::Coherence => Some(format!("compared with each other, {}", a.coherence.words())),
                AdequacyTest::Form => a.form.as_ref().map(|f| f.words()),
            })
            .collect();
        let mut found = found;
        if found.is_empty() {
            found.push("beyond the noise".into());
        }
        let mut s = format!("No model on the menu explains the record: {who} still misfits — {}", found.join("; "));
        if let Some(g) = &d.gain {
            s += &format!("; the partial extension gains ΔBIC = {}", fmt_num(g.delta_bic, 3));
        }
        s += ". The cause lies outside the menu: a law or effect the library does not have.";
        return esc(&s);
    }
    if let (Cause::Undecided, [(a, da), (b, db)]) = (d.cause, &d.undecided[..]) {
        let margin = || {
            format!(
                "within {} of each other, where a difference of {} would be decisive",
                fmt_num(rsf_diagnose::UNDECIDED_DBIC, 2),
                fmt_num(-DECISIVE, 2)
            )
        };
        let apart = match (d.apart, d.lead) {
            (Some(Apart::Unconverged), _) => "the second scoring better at a point short of its optimum (its fit did \
                                              not converge), and its optimum at least as well"
                .to_string(),
            (Some(Apart::Lead), Some(l)) => format!(
                "apart by more than the margin of {} but, with no event to test the better one's model against the \
                 noise, with predictions so alike that its lead, {} in ln L, is {} times the spread the noise alone \
                 gives it (chance {}): another draw of the noise could reverse it",
                fmt_num(rsf_diagnose::UNDECIDED_DBIC, 2),
                fmt_num(l.lead, 3),
                fmt_num(l.z, 2),
                fmt_num(l.p, 2)
            ),
            (Some(Apart::Form), _) => match d.adequacy.form.as_ref() {
                Some(f) => format!(
                    "the first apart from the second by more than the margin of {}, but the second's law ({}) read \
                     at a reshaped state explains the record better than the first's model, by ΔBIC = {}, no more \
                     than the record's noise gives it: a model without the first does as well",
                    fmt_num(rsf_diagnose::UNDECIDED_DBIC, 2),
                    f.laws.join(", "),
                    fmt_num(f.delta_bic, 3)
                ),
                None => margin(),
            },
            (Some(Apart::Margin | Apart::Lead) | None, _) => margin(),
        };
        let shown = match d.apart {
            Some(Apart::Unconverged | Apart::Form) => "first",
            Some(Apart::Margin | Apart::Lead) | None => "better",
        };
        let s = format!(
            "The record needs more than the {baseline}, but it does not tell which of two extensions: {} \
             (ΔBIC = {}) or {} (ΔBIC = {}), {apart}. No cause is named; the fit shown is the {shown} one's, {}. \
             rsf design plans the experiment that tells them apart.",
            cause_words(*a),
            fmt_num(*da, 3),
            cause_words(*b),
            fmt_num(*db, 3),
            need(d)
        );
        return esc(&s);
    }
    if d.cause == Cause::None || d.gain.is_none() {
        let mut s = format!("The {baseline} explains the record; no extension earns its parameters");
        let best = d.candidates.iter().min_by(|a, b| a.delta_bic.total_cmp(&b.delta_bic));
        match best {
            Some(b) => {
                s += &format!(
                    ": best was {} with ΔBIC = {} (decisive needs < {}, with {n_eff})",
                    b.extension,
                    fmt_num(b.delta_bic, 3),
                    fmt_num(DECISIVE, 3)
                );
                let set_aside: Vec<String> = d
                    .candidates
                    .iter()
                    .filter(|c| c.delta_bic < DECISIVE)
                    .map(|c| {
                        let why = if !c.at_bound.is_empty() {
                            format!("{} ran to a bound", c.at_bound.join(", "))
                        } else if let Some(w) = &c.unresolved {
                            w.clone()
                        } else if let (Some(b), Some(a)) = (c.heldout_rms_before, c.heldout_rms_after) {
                            if a > 1.05 * b {
                                format!(
                                    "it predicts the held-out part worse ({})",
                                    heldout_words(Some(b), Some(a)).unwrap_or_default()
                                )
                            } else {
                                "it did not pass the credibility checks".into()
                            }
                        } else {
                            "it did not pass the credibility checks".into()
                        };
                        format!("{} (ΔBIC = {}) was set aside because {why}", c.extension, fmt_num(c.delta_bic, 3))
                    })
                    .collect();
                if !set_aside.is_empty() {
                    s += &format!("; {}", set_aside.join("; "));
                }
            }
            None => s += ": no candidate could be fitted",
        }
        return esc(&(s + "."));
    }
    let g = d.gain.as_ref().expect("checked above");
    let rms_after = d.extended.as_ref().map(|e| e.rms).unwrap_or(d.baseline.rms * g.rms_ratio);
    let mut s = format!(
        "The data need {}, because {}; it gains ΔBIC = {} (rms {}",
        need(d),
        because(d.cause, d),
        fmt_num(g.delta_bic, 3),
        fmt_pair(d.baseline.rms, rms_after, 3)
    );
    s += &match heldout_words(g.heldout_rms_before, g.heldout_rms_after) {
        Some(h) => format!(", held-out {h})"),
        None => ", no held-out test)".into(),
    };
    let null = d.candidates.iter().find(|c| c.cause == d.cause).and_then(|c| c.null.as_ref());
    let sure = if g.delta_bic < DECISIVE {
        format!(
            "decisive (ΔBIC < {} with {n_eff}){}",
            fmt_num(DECISIVE, 3),
            null.map_or(String::new(), |n| format!(
                ", and a gain this large arises by chance under the baseline with probability {} (at most {} as \
                 far as {} noise replicates can tell; {} reached it)",
                fmt_num(n.false_alarm_probability, 2),
                fmt_num(n.false_alarm_upper, 2),
                n.replicates,
                n.exceeded
            ))
        )
    } else {
        format!("not decisive (ΔBIC ≥ {})", fmt_num(DECISIVE, 3))
    };
    s += &format!("; how sure: {sure}");
    match &d.runner_up {
        Some((c, dbic)) => {
            let close =
                if (dbic - g.delta_bic).abs() < 10.0 { " — close: the two are hard to tell apart" } else { "" };
            s += &format!("; runner-up {} with ΔBIC = {}{close}", cause_words(*c), fmt_num(*dbic, 3));
        }
        None => s += "; no runner-up",
    }
    s += ".";
    if let Some(sec) = &d.secondary {
        s += &format!(
            " On top of it the data need {}: a further ΔBIC = {} ({}).",
            cause_words(sec.cause),
            fmt_num(sec.delta_bic, 3),
            sec.effect
                .entries()
                .iter()
                .map(|e| format!("{} = {}", effect_meta(&e.key).0, effect_value(e, Some(&sec.fit))))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    esc(&s)
}

#[cfg(test)]
mod tests {
    use super::param_meta;

    /// Fit parameters read by their parsed name, effect keys by theirs.
    #[test]
    fn parameter_names_read_as_the_field_writes_them() {
        assert_eq!(param_meta("mu0").0, "μ₀");
        assert_eq!(param_meta("dc2"), ("Dc₂".into(), "µm", "slip distance of the second state"));
        assert_eq!(param_meta("vc1").1, "µm/s");
        assert_eq!(super::effect_meta(&rsf_diagnose::EffectKey::Vc).0, "Vc");
        assert_eq!(param_meta("alpha1").0, "α₁");
        assert_eq!(param_meta("c1").0, "c₁");
        assert_eq!(super::effect_meta(&rsf_diagnose::EffectKey::BOtherFraction).0, "share of b");
        assert_eq!(param_meta("not a name").0, "not a name");
    }
}
