//! The sections of the diagnosis page, one function each, in page order.

use super::words::{cause_words, effect_meta, effect_value, heldout_words, law_words, param_rows};
use super::{chart, charts, effect_summary, esc, table, verdict};
use rsf_diagnose::{DECISIVE, Diagnosis};
use rsf_fit::fit::FitResult;
use rsf_plot::{fmt_common, fmt_num, fmt_pair, fmt_value, fmt_with_err};

/// `ΔBIC` as it is shown in tables: one decimal below 1000 in magnitude, else 4 digits.
fn score(x: f64) -> String {
    if x.is_finite() && x.abs() < 1000.0 { format!("{x:.1}").replacen('-', "−", 1) } else { fmt_num(x, 4) }
}

/// The title.
pub(super) fn header(_d: &Diagnosis, name: &str) -> String {
    format!("<h1>rsf diagnose: {}</h1>\n", esc(name))
}

/// The verdict paragraph, then what was diagnosed and the engine's own reason.
pub(super) fn verdict_section(d: &Diagnosis) -> String {
    let cause = d.cause.to_string();
    let b = &d.baseline;
    let class = if cause == "none" { "verdict none" } else { "verdict" };
    let loading = format!("{:?}", b.loading).to_lowercase();
    format!(
        "<p class=\"{class}\">{}</p>\n<p class=\"sub\">Cause: <b>{}</b> · baseline: {} law, one state variable, k = {} \
         (nominal) · {} samples in {} segments · loading by {loading}.</p>\n",
        verdict(d),
        esc(&cause),
        esc(&law_words(b.params.laws.first().map(String::as_str).unwrap_or(""))),
        esc(&fmt_value(b.params.k, "/µm")),
        b.n,
        b.segments.len(),
    )
}

/// The gain of the extension (and of a second cause on top of it).
pub(super) fn gain(d: &Diagnosis) -> String {
    let Some(g) = &d.gain else {
        return "<h2>Gain</h2><p>No extension is decisive: the baseline stands (see the candidates below).</p>\n"
            .into();
    };
    let ext_rms = d.extended.as_ref().map(|e| e.rms).unwrap_or(d.baseline.rms * g.rms_ratio);
    // for `undecided`, the gain is the better one's of the two
    let who = match (d.cause, d.partial) {
        (rsf_diagnose::Cause::Undecided, Some(p)) => format!("{} (undecided)", cause_words(p)),
        (c, _) => cause_words(c).to_string(),
    };
    let mut rows = vec![(
        "chosen".to_string(),
        vec![
            format!("<l>{}", esc(&who)),
            score(g.delta_bic),
            score(g.delta_aic),
            fmt_pair(d.baseline.rms, ext_rms, 3),
            fmt_num(g.rms_ratio, 4),
            heldout_words(g.heldout_rms_before, g.heldout_rms_after).unwrap_or_else(|| "–".into()),
        ],
    )];
    if let Some(s) = &d.secondary {
        rows.push((
            "second".into(),
            vec![
                format!("<l>+ {} (against the first extension)", esc(cause_words(s.cause))),
                score(s.delta_bic),
                "–".into(),
                fmt_pair(ext_rms, s.fit.rms, 3),
                fmt_num(s.rms_ratio, 4),
                heldout_words(s.heldout_rms_before, s.heldout_rms_after).unwrap_or_else(|| "–".into()),
            ],
        ));
    }
    let head = [
        "<l>extension",
        "ΔBIC<sub>eff</sub>",
        "ΔAIC<sub>eff</sub>",
        "rms before → after",
        "rms ratio",
        "held-out rms before → after",
    ];
    format!(
        "<h2>Gain</h2>{}<p class=\"note\">ΔBIC and ΔAIC use the effective number of independent samples \
         (n<sub>eff</sub> = {} of {}); below {} is decisive. The held-out test fits the record before t = {} s and \
         predicts the rest.</p>\n",
        table("", &head, &rows),
        fmt_num(d.evidence.n_effective.round(), 6),
        d.baseline.n,
        fmt_num(DECISIVE, 3),
        fmt_num(d.heldout_split_t, 4)
    )
}

/// The effect's parameters: name, value with unit and uncertainty, meaning.
pub(super) fn effect(d: &Diagnosis) -> String {
    let mut rows = Vec::new();
    let mut add = |class: &str, effect: &rsf_diagnose::Effect, f: Option<&FitResult>| {
        for e in &effect.entries() {
            let (name, _, meaning) = effect_meta(&e.key);
            rows.push((
                class.to_string(),
                vec![format!("<l>{}", esc(&name)), esc(&effect_value(e, f)), format!("<l>{}", esc(meaning))],
            ));
        }
    };
    add("", &d.effect, d.extended.as_ref());
    if let Some(s) = &d.secondary {
        add("second", &s.effect, Some(&s.fit));
    }
    if rows.is_empty() {
        return String::new();
    }
    format!(
        "<h2>Effect</h2>{}<p class=\"note\">± one standard error from the covariance of the extended fit{}.</p>\n",
        table("", &["<l>parameter", "value", "<l>meaning"], &rows),
        if d.secondary.is_some() { " (green: the second cause, from the combined fit)" } else { "" }
    )
}

/// Fitted parameters of the baseline, the extended and the combined model side by side.
pub(super) fn parameters(d: &Diagnosis) -> String {
    let mut fits: Vec<(String, &FitResult)> = vec![("baseline".into(), &d.baseline)];
    if let Some(e) = &d.extended {
        fits.push((format!("with {}", cause_words(d.cause)), e));
    }
    if let Some(s) = &d.secondary {
        fits.push((format!("and {}", cause_words(s.cause)), &s.fit));
    }
    let rows_of: Vec<Vec<(String, String, bool)>> = fits.iter().map(|(_, f)| param_rows(f)).collect();
    // row order: the longest list's, then any names only the others have
    let mut names: Vec<String> = Vec::new();
    let mut by_len: Vec<&Vec<(String, String, bool)>> = rows_of.iter().collect();
    by_len.sort_by_key(|r| std::cmp::Reverse(r.len()));
    for r in by_len {
        for (n, _, _) in r {
            if !names.contains(n) {
                names.push(n.clone());
            }
        }
    }
    let mut rows: Vec<(String, Vec<String>)> = names
        .iter()
        .map(|n| {
            let mut cells = vec![format!("<l>{}", esc(n))];
            for r in &rows_of {
                cells.push(match r.iter().find(|x| &x.0 == n) {
                    Some((_, v, true)) => esc(v),
                    Some((_, v, false)) => format!("{} (fixed)", esc(v)),
                    None => "–".into(),
                });
            }
            (String::new(), cells)
        })
        .collect();
    let mut extra = |label: &str, f: &dyn Fn(&FitResult) -> String| {
        let mut cells = vec![format!("<l>{label}")];
        cells.extend(fits.iter().map(|(_, x)| f(x)));
        rows.push((String::new(), cells));
    };
    extra("laws", &|f| esc(&law_words(&f.params.laws.join("+"))));
    extra("free parameters", &|f| f.n_free.to_string());
    let rms = fmt_common(&fits.iter().map(|(_, f)| f.rms).collect::<Vec<_>>(), 3);
    rows.insert(rows.len() - 1, (String::new(), std::iter::once("<l>rms misfit".to_string()).chain(rms).collect()));
    let mut head = vec!["<l>parameter".to_string()];
    head.extend(fits.iter().map(|(h, _)| esc(h)));
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    format!(
        "<h2>Fitted parameters</h2>{}<p class=\"note\">μ₀ at the reference rate V₀ = {}; ± one standard error.</p>\n",
        table("", &head, &rows),
        esc(&fmt_value(d.baseline.params.v0, "µm/s"))
    )
}

/// Data, baseline and extended model, residuals, against load point.
pub(super) fn models(d: &Diagnosis) -> String {
    let ext = if d.extended.is_some() {
        format!(", red the model with {}", esc(cause_words(d.cause)))
    } else {
        String::new()
    };
    format!(
        "<h2>Data, models and residuals</h2><p class=\"note\">Grey: data; blue: the baseline{ext}. Shaded: every \
         other segment of the protocol. Dashed: the held-out split (t = {} s): the held-out fits saw only the \
         record before it.</p>{}\n",
        fmt_num(d.heldout_split_t, 4),
        chart(charts::models_svg(d))
    )
}

/// Residual rms per segment and residuals against slip rate.
pub(super) fn residuals(d: &Diagnosis) -> String {
    format!("<h2>Where the residuals are</h2>{}\n", chart(charts::residuals_svg(d)))
}

/// The noise model of the baseline residuals: its parts with standard errors, the drift's
/// share, n_eff, and the residual spectrum against the model's.
pub(super) fn noise(d: &Diagnosis) -> String {
    let Some(m) = &d.evidence.noise else { return String::new() };
    let pm =
        |v: f64, e: f64| if e.is_finite() { format!("{} ± {}", fmt_num(v, 3), fmt_num(e, 2)) } else { fmt_num(v, 3) };
    let mut rows = vec![(
        String::new(),
        vec![
            "<l>white noise rms".into(),
            pm(m.white_variance.sqrt(), m.stderr.white_variance / (2.0 * m.white_variance.sqrt().max(1e-300))),
        ],
    )];
    if m.ar1_variance > 0.0 {
        rows.push((
            String::new(),
            vec![
                "<l>AR(1) rms, correlation time (s)".into(),
                format!("{}, {}", fmt_num(m.ar1_variance.sqrt(), 3), fmt_num(m.ar1_tau_s, 3)),
            ],
        ));
    }
    if m.drift_amplitude > 0.0 {
        rows.push((
            String::new(),
            vec![
                "<l>drift (1/f-like) rms, exponent β".into(),
                format!(
                    "{}, {}",
                    fmt_num((m.drift_share * m.variance).sqrt(), 3),
                    pm(m.drift_beta, m.stderr.drift_beta)
                ),
            ],
        ));
    }
    rows.push((
        String::new(),
        vec!["<l>drift share of the residual variance".into(), format!("{:.1}%", 100.0 * m.drift_share)],
    ));
    rows.push((
        String::new(),
        vec!["<l>n_eff for a slow effect (of n samples)".into(), format!("{} of {}", fmt_num(m.n_effective, 3), m.n)],
    ));
    format!(
        "<h2>Noise</h2><p>The baseline residuals' spectrum, fitted by Whittle's likelihood with a white, an \
         AR(1) and a power-law (drift) part; each model is scored with its own fitted noise, and the null \
         replicates draw this spectrum.</p>{}{}\n",
        table("", &["part", "value"], &rows),
        chart(charts::noise_svg(d))
    )
}

/// Per-event refits: Dc against step size and hold, and their table.
pub(super) fn events(d: &Diagnosis) -> String {
    if d.per_segment.is_empty() {
        return String::new();
    }
    let rms = fmt_common(&d.per_segment.iter().map(|e| e.rms).collect::<Vec<_>>(), 3);
    let rows: Vec<(String, Vec<String>)> = d
        .per_segment
        .iter()
        .zip(rms)
        .map(|(e, rms)| {
            (
                String::new(),
                vec![
                    format!("<l>{}", e.event),
                    fmt_num(e.t, 5),
                    format!("{} → {}", fmt_num(e.v_before, 3), fmt_num(e.v_after, 3)),
                    e.hold_s.map_or("–".into(), |h| fmt_num(h, 4)),
                    fmt_num(e.a, 3),
                    fmt_num(e.b[0], 3),
                    esc(&fmt_with_err(e.dc[0], e.dc[0] * e.ln_dc_stderr, "")),
                    rms,
                ],
            )
        })
        .collect();
    let head = ["<l>event", "t (s)", "V before → after (µm/s)", "hold (s)", "a", "b", "Dc (µm)", "rms"];
    let chi2 = d
        .evidence
        .dc_consistency_chi2
        .map_or(String::new(), |c| format!(" Here the spread of ln Dc about its mean is χ²/dof = {}.", fmt_num(c, 3)));
    format!(
        "<h2>Each step and hold refitted alone</h2><p class=\"note\">One law with one Dc should serve every event; \
         Dc that drifts with step size or hold duration points at the evolution law.{chi2}</p>{}{}\n",
        chart(charts::events_svg(d)),
        table("", &head, &rows)
    )
}

/// Every candidate extension and its score.
pub(super) fn candidates(d: &Diagnosis) -> String {
    // held-out rms in one form down both columns
    let n = d.candidates.len();
    let nan = f64::NAN;
    let held: Vec<f64> = d.candidates.iter().map(|c| c.heldout_rms_before.unwrap_or(nan)).collect();
    let held =
        fmt_common(&[held, d.candidates.iter().map(|c| c.heldout_rms_after.unwrap_or(nan)).collect()].concat(), 3);
    let rows: Vec<(String, Vec<String>)> = d
        .candidates
        .iter()
        .enumerate()
        .map(|(i, c)| {
            // the one named, or for `undecided` the two the record cannot tell apart
            let named = c.cause == d.cause || d.undecided.iter().any(|u| u.0 == c.cause);
            let class = if named { "chosen" } else { "" };
            let bic =
                if c.delta_bic < DECISIVE { format!("<b>{}</b>", score(c.delta_bic)) } else { score(c.delta_bic) };
            (
                class.to_string(),
                vec![
                    format!("<l>{}", esc(cause_words(c.cause))),
                    format!("<l>{}", esc(&c.extension)),
                    bic,
                    score(c.delta_aic),
                    fmt_num(c.rms_ratio, 4),
                    held[i].clone(),
                    held[n + i].clone(),
                    format!("<l>{}", if c.at_bound.is_empty() { "–".into() } else { esc(&c.at_bound.join(", ")) }),
                    c.null.as_ref().map_or("–".into(), |n| {
                        format!(
                            "{} ≤ {} ({}/{})",
                            fmt_num(n.false_alarm_probability, 2),
                            fmt_num(n.false_alarm_upper, 2),
                            n.exceeded,
                            n.replicates
                        )
                    }),
                    format!("<l>{}", effect_summary(&c.effect)),
                ],
            )
        })
        .collect();
    let head = [
        "<l>cause",
        "<l>extension",
        "ΔBIC<sub>eff</sub>",
        "ΔAIC<sub>eff</sub>",
        "rms ratio",
        "held-out rms, baseline",
        "held-out rms, extended",
        "<l>at bound",
        "P(false alarm) ≤ bound (replicates reaching it / drawn)",
        "<l>effect",
    ];
    format!(
        "<h2>Candidates</h2><p class=\"note\">Each extension fitted from the baseline optimum. Bold: decisive \
         (ΔBIC<sub>eff</sub> &lt; {}); shaded: the one named (for an undecided verdict, the two the record \
         cannot tell apart). A candidate is named only if it is also credible: \
         held-out rms at most 5 % worse than the baseline's, no parameter run to a bound, and a gain that \
         noise replicates of the baseline reach with probability below the false-alarm level (1 % by \
         default), also at the bound: the probability where the null's scale is at its 95 % upper limit, \
         as far as the replicates drawn can tell it.</p>{}\
         <p class=\"note\">The diagnosis engine's reason: {}</p>\n",
        fmt_num(DECISIVE, 3),
        table("wide", &head, &rows),
        esc(&d.reason)
    )
}

/// The numbers read from the baseline residuals.
pub(super) fn evidence(d: &Diagnosis) -> String {
    let e = &d.evidence;
    let opt = |x: Option<f64>, sig: usize| x.map_or("–".to_string(), |v| fmt_num(v, sig));
    let with_t = |x: Option<f64>, t: Option<f64>, unit: &str| match (x, t) {
        (Some(x), Some(t)) => format!("{} (t = {})", esc(&fmt_value(x, unit)), fmt_num(t, 2)),
        (Some(x), None) => esc(&fmt_value(x, unit)),
        _ => "–".into(),
    };
    let rows: Vec<(&str, String, &str)> = vec![
        (
            "residual lag-one correlation ρ",
            fmt_num(e.residual_lag1, 3),
            "near 1: residuals vary slowly (misfit structure or correlated noise)",
        ),
        (
            "effective independent samples n<sub>eff</sub>",
            format!("{} of {}", fmt_num(e.n_effective.round(), 6), d.baseline.n),
            "n (1 − ρ)/(1 + ρ): what the scores count",
        ),
        (
            "misfit / noise",
            fmt_num(e.misfit_over_noise, 3),
            "baseline rms over the noise from sample-to-sample differences",
        ),
        (
            "residual trend with load point",
            with_t(Some(e.residual_trend_per_um), Some(e.residual_trend_t), "/µm"),
            "a slip trend shows here",
        ),
        ("worst / median segment rms", fmt_num(e.segment_rms_ratio, 3), "large: one part of the protocol is missed"),
        (
            "residual trend with ln V",
            with_t(e.residual_vs_ln_v, e.residual_vs_ln_v_t, ""),
            "healing too fast or slow at low slip rate",
        ),
        ("per-event Dc spread χ²/dof", opt(e.dc_consistency_chi2, 3), "≈ 1 when one Dc serves every step and hold"),
        ("d ln Dc / d ln(step size)", opt(e.dc_vs_ln_step, 3), "≠ 0: the evolution law"),
        ("d ln Dc / d ln(hold)", opt(e.dc_vs_ln_hold, 3), "≠ 0: the evolution law"),
        (
            "k from reloading slopes",
            e.k_reload_slope.map_or("–".into(), |k| esc(&fmt_value(k, "/µm"))),
            "against the nominal stiffness",
        ),
    ];
    let rows: Vec<(String, Vec<String>)> = rows
        .into_iter()
        .map(|(a, b, c)| (String::new(), vec![format!("<l>{a}"), b, format!("<l>{}", esc(c))]))
        .collect();
    format!(
        "<h2>Evidence from the baseline residuals</h2>{}\n",
        table("", &["<l>quantity", "value", "<l>what it says"], &rows)
    )
}

/// What was done to the record before physics was judged: a protocol-reconstruction problem
/// worked around, isolated spikes left out, rows with repeated times dropped.
pub(super) fn record_quality(d: &Diagnosis) -> String {
    let mut items = vec![];
    if let Some(r) = &d.reconstruction {
        items.push(format!("<li><b>Protocol problem:</b> {}</li>", esc(&r.message)));
    }
    if let Some(m) = &d.timing {
        items.push(format!(
            "<li>The load point scatters by {} about the protocol, so its break times are uncertain: {} samples \
             near {} breaks, where that uncertainty moves the model by more than the noise, were left out of \
             every fit.</li>",
            esc(&fmt_value(m.load_point_sigma_um, "µm")),
            m.samples,
            m.windows.len()
        ));
    }
    if !d.spikes_removed.is_empty() {
        let t: Vec<String> = d.spikes_removed.iter().take(12).map(|t| fmt_num(*t, 6)).collect();
        items.push(format!(
            "<li>{} isolated single-sample spike{} left out of every fit (t = {}{} s).</li>",
            d.spikes_removed.len(),
            if d.spikes_removed.len() == 1 { "" } else { "s" },
            t.join(", "),
            if d.spikes_removed.len() > 12 { ", …" } else { "" }
        ));
    }
    if d.baseline.steps > 0 && d.baseline.budget_hit.is_some() {
        items.push("<li>The baseline fit stopped at its work budget before it converged.</li>".into());
    }
    if items.is_empty() {
        return String::new();
    }
    format!("<h2>The record</h2><ul class=\"note\">{}</ul>\n", items.join(""))
}
