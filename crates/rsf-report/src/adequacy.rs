//! The adequacy section of the diagnosis page: the event test, the level and quiet tests, and
//! the form test, in words, tables and figures.

use super::words::cause_words;
use super::{chart, charts, esc, table};
use rsf_diagnose::{Diagnosis, Reshaping};
use rsf_plot::fmt_num;

/// The adequacy test of the model named: in words, the figure of misfit by event against the
/// noise band, and the worst events.
pub(super) fn adequacy(d: &Diagnosis) -> String {
    let a = &d.adequacy;
    let what = match d.cause {
        rsf_diagnose::Cause::None => "the baseline".to_string(),
        _ if d.extended.is_some() => format!("the model with {}", cause_words(d.partial.unwrap_or(d.cause))),
        _ => "the baseline".to_string(),
    };
    let words = match a.event_verdict {
        rsf_diagnose::AdequacyVerdict::Untestable => format!(
            "{what}'s events could not be tested against the noise: fewer than {} events have a quiet stretch of \
             sliding as long as their transient ({} Dc of slip) to compare with. Compared with each other instead \
             (does the model misfit every step up and reslide, or every step down, the same way in log time, more \
             than any pattern of signs of noise would?): {}.",
            rsf_diagnose::MIN_WINDOWS,
            rsf_diagnose::WINDOW_DC,
            a.coherence.words()
        ),
        rsf_diagnose::AdequacyVerdict::Adequate => format!(
            "{what} explains the record to its noise level where the events are: over {} event windows the \
             misfit's bin means spread {}× as much (in variance) as in quiet windows of the same length (p = {}).{}",
            a.windows,
            fmt_num(a.excess, 3),
            fmt_num(a.p_value, 2),
            if a.windows < a.events_total {
                format!(
                    " Only {} of the record's {} events were tested: the others' windows have too few samples, or \
                     transients longer than every quiet stretch of sliding to compare with, and what the model \
                     does there is not judged.",
                    a.windows, a.events_total
                )
            } else {
                String::new()
            }
        ),
        rsf_diagnose::AdequacyVerdict::Inadequate => format!(
            "{what} does not explain the record: over {} event windows the misfit's bin means spread {}× as much \
             (in variance) as in quiet windows of the same length — a chance of {} under noise alone. The misfit is \
             locked to the protocol's events, so no noise model accounts for it.",
            a.windows,
            fmt_num(a.excess, 3),
            fmt_num(a.p_value, 2)
        ),
    };
    let words = match a.family_words() {
        Some(_) => format!(
            "{words} The baseline's {} tests (each that ran of the event, level and quiet tests, and the form \
             test) share the {} % level: each is held to {} %, so that noise alone calls a record with nothing \
             hidden unexplained less often than the level. A named model's tests are each held to the level \
             itself: a chance misfit there costs a cause, not a false alarm.",
            a.family.tests,
            fmt_num(100.0 * rsf_diagnose::ADEQUACY_LEVEL, 2),
            fmt_num(100.0 * a.family.level(), 3)
        ),
        None => words,
    };
    let rows: Vec<(String, Vec<String>)> = a
        .events
        .iter()
        .take(8)
        .map(|e| {
            (
                String::new(),
                vec![
                    format!("<l>{}", e.event),
                    e.segment.to_string(),
                    fmt_num(e.t, 5),
                    fmt_num(e.window_s, 3),
                    fmt_num(e.rms, 3),
                    fmt_num(e.ratio, 3),
                ],
            )
        })
        .collect();
    let head = ["<l>event", "segment", "t (s)", "window (s)", "misfit rms", "× its placebos"];
    format!(
        "<h2>Does the model explain the events?</h2><p class=\"note\">{}</p>{}{}{}\n",
        esc(&words),
        chart(charts::adequacy_svg(d)) + &chart(charts::coherence_svg(d)),
        if rows.is_empty() { String::new() } else { table("", &head, &rows) },
        levels(d) + &quiet(d) + &form(d)
    )
}

/// The quiet test: in words, and each quiet stretch's wander against the noise model's.
fn quiet(d: &Diagnosis) -> String {
    let q = &d.adequacy.quiet;
    if !q.ratio.is_finite() {
        return String::new();
    }
    let words = format!(
        "Quiet stretches: inside {} stretches of steady sliding, after each segment's transient, every model \
         predicts a constant friction, so the residuals there wander only as the noise does. They wander {}× as \
         much (in variance) as the noise model fitted to them ({}% of their variance in its drift) says \
         (p = {} for so little wander, were its claim no more than twice the truth; p = {} for so much). {}",
        q.stretches.len(),
        fmt_num(q.ratio, 3),
        fmt_num(100.0 * q.drift_share, 2),
        fmt_num(q.p_below, 2),
        fmt_num(q.p_above, 2),
        if q.drift_is_misfit() {
            "The slow part of the residuals is therefore not noise: it is misfit locked to the protocol (segments \
             at the wrong level, healing that is off after holds), which the noise model's slow part (its \
             drift, or an AR(1) part of long correlation time) absorbed. The model does not explain the record, \
             whatever its events say."
        } else if q.stretches_misfit() {
            "The model still misfits where its transients should be over: its approach to steady state is not \
             the record's, and the event test, whose quiet windows lie in these stretches, cannot see it. The \
             model does not explain the record."
        } else {
            "The noise model describes the residuals where no model can carry error."
        }
    );
    let rows: Vec<(String, Vec<String>)> = q
        .stretches
        .iter()
        .map(|x| {
            (String::new(), vec![fmt_num(x.t[0], 5), fmt_num(x.t[1], 5), fmt_num(x.wander, 3), fmt_num(x.claimed, 3)])
        })
        .collect();
    let head = ["from t (s)", "to t (s)", "wander (last − first quarter)", "noise model's sd"];
    format!(
        "<p class=\"note\">{}</p>{}{}",
        esc(&words),
        chart(charts::quiet_svg(d)),
        if q.inadequate() { table("", &head, &rows) } else { String::new() }
    )
}

/// The level test: in words, and each step's change of level against its placebos'.
fn levels(d: &Diagnosis) -> String {
    let l = &d.adequacy.levels;
    if !l.p_value.is_finite() {
        return String::new();
    }
    let words = format!(
        "Levels: across {} steps between sliding segments, the residual's change of level (the mean over each \
         segment's end, after the step against before it) is {}× as large in variance as between two windows as \
         far apart where no step is, with the fit's own uncertainty allowed for (p = {}). {}",
        l.steps.len(),
        fmt_num(l.excess, 3),
        fmt_num(l.p_value, 2),
        if l.inadequate() {
            "Some segments sit at the wrong level — a misfit the event windows, which take their own mean out, \
             cannot see — so the model does not explain the record, whatever its events say."
        } else {
            "Each segment sits at its level to the noise."
        }
    );
    let rows: Vec<(String, Vec<String>)> = l
        .steps
        .iter()
        .take(8)
        .map(|x| {
            (
                String::new(),
                vec![
                    x.segment.to_string(),
                    fmt_num(x.t, 5),
                    fmt_num(x.ln_v_ratio.exp(), 3),
                    fmt_num(x.offset, 3),
                    fmt_num(x.noise, 3),
                    fmt_num(x.z, 3),
                ],
            )
        })
        .collect();
    let head = ["segment", "t (s)", "V after / before", "change of level", "noise band", "score"];
    format!("<p class=\"note\">{}</p>{}", esc(&words), table("", &head, &rows))
}

/// The form test: the law named, and the runner-up's, read at a reshaped state; or the model
/// named with a rate-dependent direct effect.
fn form(d: &Diagnosis) -> String {
    let Some(f) = &d.adequacy.form else {
        return String::new();
    };
    // the model judged: the baseline for a `none` verdict (or an `unexplained` one that named nothing)
    let named = match f.model {
        rsf_diagnose::Cause::None => "the baseline",
        _ => "the model named",
    };
    let whose = if f.named {
        format!("the law of {named} ({})", f.laws.join(" and "))
    } else {
        format!("the law of the best rival, {} ({})", cause_words(f.model), f.laws.join(" and "))
    };
    let (what, wrong) = match (f.reshaping, f.a_slope) {
        (Reshaping::DirectEffect, Some((a1, ratio))) => (
            format!(
                "{named} with a rate-dependent direct effect, ∂f/∂ln V = a + a₁ ln(V/V0) (a₁ = 0 is the \
                 model itself), fitted warm from its optimum: a₁ = {}, a₁/a = {}",
                fmt_num(a1, 3),
                fmt_num(ratio, 3)
            ),
            format!(
                "{named} has the wrong direct effect — one that changes with the slip rate, which bends the \
                 steady state and makes up- and down-steps jump unlike"
            ),
        ),
        (Reshaping::DirectEffect, None) | (Reshaping::State, _) => {
            let p: Vec<String> = f.p.iter().map(|p| fmt_num(*p, 3)).collect();
            (
                format!(
                    "{whose}, read at a reshaped state θ' = θ_ref (θ/θ_ref)^p (p = 1 is the law itself; θ_ref its \
                     steady state), fitted warm from its optimum: p = {}",
                    p.join(", ")
                ),
                format!(
                    "{named} has the wrong dependence on state — a near neighbour of the record's law, which \
                     the residual tests cannot tell from it at this noise"
                ),
            )
        }
    };
    let words = format!(
        "Form: {what}, ΔBIC {} against {named}, rms ratio {}. {}",
        fmt_num(f.delta_bic, 4),
        fmt_num(f.rms_ratio, 4),
        if f.misfit {
            format!("It fits decisively better: {wrong} — and explains nothing.")
        } else if f.delta_bic < rsf_diagnose::DECISIVE {
            format!(
                "The gain is no more than the record's noise gives the reshaped model when {named} is true \
                 (its null replicates): the model's form is the record's as far as the record can tell."
            )
        } else {
            "No reshaping earns its parameter: the model's form is the record's as far as the record can tell.".into()
        }
    );
    format!("<p class=\"note\">{}</p>", esc(&words))
}
