//! `rsf fit`.

use crate::args::{DiagnoseArgs, DiagnosisArgs, FitArgs};
use anyhow::{Context, Result, bail};
use rsf_diagnose::{EventFit, event_windows, per_event_fits};
use rsf_fit::fit::{FitOptions, FitResult, LoadingMode, ParamName, fit, prepare};
use rsf_fit::segment::{SegmentOptions, detect};
use serde::Serialize;
use std::time::Instant;

#[derive(Serialize)]
struct Output<'a> {
    data: String,
    #[serde(flatten)]
    fit: &'a FitResult,
    #[serde(skip_serializing_if = "Option::is_none")]
    mcmc: Option<rsf_fit::mcmc::McmcResult>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    per_segment: Vec<EventFit>,
    wall_s: f64,
}

/// A progress bar on stderr (hidden off a terminal) and the library's observer that drives it:
/// the library reports, the CLI draws.
pub(crate) fn progress_bar(template: &str) -> (indicatif::ProgressBar, rsf_fit::progress::Progress) {
    let bar = indicatif::ProgressBar::with_draw_target(None, indicatif::ProgressDrawTarget::stderr());
    bar.set_style(
        indicatif::ProgressStyle::with_template(template).unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let drawn = bar.clone();
    let progress: rsf_fit::progress::Progress = std::sync::Arc::new(move |done, total, what: &str| {
        drawn.set_length(total as u64);
        drawn.set_position(done as u64);
        drawn.set_message(what.to_string());
    });
    (bar, progress)
}

pub fn options(a: &FitArgs) -> Result<FitOptions> {
    let kinds: Vec<rsf_laws::registry::LawName> = match &a.laws {
        Some(l) => l.split(',').map(|s| s.trim().parse()).collect::<Result<_, _>>().map_err(anyhow::Error::msg)?,
        None => vec![a.law.parse().map_err(anyhow::Error::msg)?; a.states],
    };
    if kinds.is_empty() || kinds.len() > 3 {
        bail!("1 to 3 state variables are supported by the fitter (got {})", kinds.len());
    }
    let laws =
        kinds.iter().map(|l| l.with_starting_values()).collect::<Result<Vec<_>, _>>().map_err(anyhow::Error::msg)?;
    if !(a.stiffness > 0.0 && a.stiffness.is_finite()) {
        bail!("--stiffness {} must be positive and finite (1/µm)", a.stiffness);
    }
    let mut o = FitOptions::new(laws, a.stiffness);
    o.fit_stiffness = a.fit_stiffness;
    o.fit_slip_trend = a.fit_slip_trend;
    o.fit_a_slope = a.fit_a_slope;
    o.alpha = a.fit_alpha.unwrap_or(rsf_fit::fit::AlphaFit::Fixed);
    o.normal_stress = a.read.normal_stress_mode;
    o.fix = a.fix.clone();
    o.mu0_per_segment = a.mu0_per_segment;
    o.window_um = a.window_um;
    o.weighting = a.weights;
    o.loading = a.loading;
    o.uncertainty = a.uncertainty;
    o.rtol = a.rtol;
    o.starts = a.starts;
    if a.max_iter == 0 {
        bail!("--max-iter must be at least 1");
    }
    o.max_iter = a.max_iter;
    if a.every_sample {
        o.bins = rsf_fit::fit::BinMeans::Off;
    }
    for i in &a.initial {
        let (n, v) = i.split_once('=').with_context(|| format!("--initial `{i}`: expected NAME=VALUE"))?;
        let name = n.trim().parse::<rsf_fit::fit::ParamName>().map_err(|e| anyhow::anyhow!("--initial `{i}`: {e}"))?;
        o.initial.push((name, v.trim().parse().with_context(|| format!("--initial `{i}`"))?));
    }
    Ok(o)
}

pub fn run(a: &FitArgs) -> Result<()> {
    let start = Instant::now();
    let mut files = crate::output::Files::default().input("record", &a.data);
    if let Some(s) = &a.segments {
        files = files.input("--segments file", s);
    }
    files.output("--json", a.json.as_deref()).output("--plot", a.plot.as_deref()).check()?;
    let opts = options(a)?;
    let rec = a.read.read(&a.data)?;
    let segs = match &a.segments {
        Some(path) => {
            let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
            let specs: Vec<rsf_fit::segment::SegmentSpec> = serde_json::from_str(&text)
                .with_context(|| format!("{}: expected a JSON array of {{t0, t1, v}}", path.display()))?;
            rsf_fit::segment::from_specs(&rec.time, &rec.load_point, &specs)
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?
        }
        None => detect(&rec.time, &rec.load_point, &SegmentOptions { min_ratio: a.min_ratio, ..Default::default() }),
    };
    let prep = prepare(&rec, &segs, &opts)?;
    let used = match &prep.binning {
        Some(b) => format!("{} used, as {} bin means (--every-sample: each)", b.samples, prep.used.len()),
        None => format!("{} used", prep.used.len()),
    };
    eprintln!(
        "rsf fit: {} samples, {} segments, {used}; laws {:?}",
        rec.len(),
        prep.segments.len(),
        opts.laws.iter().map(|l| l.name()).collect::<Vec<_>>()
    );
    // the starts side by side; the per-event refits below run as parallel jobs of one thread each
    let res = fit(&prep, &FitOptions { threads: a.threads, ..opts.clone() })?;
    if opts.loading == LoadingMode::Record {
        // load-point noise drives a record-driven model: k σ_lp of friction noise
        let (mut ss, mut n) = (0.0, 0usize);
        for s in &prep.segments {
            let (t, x) = (&prep.record.time[s.i0..=s.i1], &prep.record.load_point[s.i0..=s.i1]);
            for (ti, xi) in t.iter().zip(x) {
                ss += (xi - (s.lp0 + s.v * (ti - s.t0))).powi(2);
                n += 1;
            }
        }
        let sigma_lp = (ss / n.max(1) as f64).sqrt();
        if res.params.k * sigma_lp > 0.3 * res.rms {
            eprintln!(
                "rsf fit: warning: the load-point record scatters by {sigma_lp:.3} µm about its segments, which drives \
                 k·σ = {:.2e} of friction noise into the record-driven model (fit rms {:.2e}); consider --loading protocol",
                res.params.k * sigma_lp,
                res.rms
            );
        }
    }
    let mut per_segment = vec![];
    if a.per_segment {
        // the refits of `rsf diagnose`: each event alone, the model running from the record's start
        per_segment = per_event_fits(&prep, &opts, &res, 0);
        let events = event_windows(&prep).len();
        if per_segment.len() < events {
            eprintln!(
                "rsf fit: {} of {events} events not refitted alone (the window does not pin the parameters down within a tenth of the full fit's step budget)",
                events - per_segment.len()
            );
        }
    }
    let mcmc = match a.mcmc {
        Some(n) => {
            let (bar, progress) = progress_bar("MCMC {bar:40} {pos}/{len} samples, {per_sec}, eta {eta}");
            let m = rsf_fit::mcmc::McmcOptions {
                samples: n,
                chains: a.chains,
                seed: a.seed,
                progress: Some(progress),
                ..Default::default()
            };
            let r = rsf_fit::mcmc::run(&prep, &opts, &res, &m).map_err(anyhow::Error::msg);
            bar.finish_and_clear();
            Some(r?)
        }
        None => None,
    };
    let wall = start.elapsed().as_secs_f64();
    crate::write_stdout(&summary(&res, mcmc.as_ref(), &per_segment))?;
    eprintln!("rsf fit: {:.2} s", wall);
    if let Some(p) = &a.plot {
        let name = a.data.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
        crate::plot::fit(&res, p, &name).with_context(|| format!("writing {}", p.display()))?;
    }
    if let Some(j) = &a.json {
        let out = Output { data: a.data.display().to_string(), fit: &res, mcmc, per_segment, wall_s: wall };
        crate::output::write_bytes(j, serde_json::to_string_pretty(&out)? + "\n")?;
    }
    // a fit that did not converge has printed and written its best point, marked so; the
    // exit status says it is not a result
    if let Some(why) = res.convergence_text() {
        bail!("{why} (outputs written with \"converged\": false)");
    }
    Ok(())
}

fn summary(r: &FitResult, mcmc: Option<&rsf_fit::mcmc::McmcResult>, per: &[EventFit]) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let p = &r.params;
    let _ = writeln!(s, "laws: {}   v0 = {:.6} µm/s   k = {:.6e} /µm", p.laws.join(", "), p.v0, p.k);
    let _ = writeln!(s, "{:>10} {:>14} {:>14} {:>28}", "param", "value", "stderr", "95% interval (linearised)");
    let mut row = |name: &str, v: f64| {
        let se = r.stderr.get(name).copied();
        let ci = r.ci95.get(name);
        let _ = writeln!(
            s,
            "{:>10} {:>14.6e} {:>14} {:>28}",
            name,
            v,
            se.map(|x| format!("{x:.3e}")).unwrap_or_else(|| "fixed".into()),
            ci.map(|c| format!("[{:.5e}, {:.5e}]", c[0], c[1])).unwrap_or_default()
        );
    };
    row("mu0", p.mu0);
    row("a", p.a);
    for i in 0..p.b.len() {
        row(&format!("b{}", i + 1), p.b[i]);
        row(&format!("dc{}", i + 1), p.dc[i]);
    }
    for (k, v) in &p.law_params {
        row(k, *v);
    }
    row("k", p.k);
    for (name, x) in [(ParamName::G, p.g), (ParamName::ASlope, p.a_slope)] {
        if r.reports(&name) {
            row(&name.text(), x);
        }
    }
    for (i, al) in p.alpha.iter().enumerate() {
        row(&format!("alpha{}", i + 1), *al);
    }
    let _ = writeln!(s, "{}", uncertainty_line(r));
    if let Some(sn) = p.normal_stress {
        let _ = writeln!(s, "normal stress drives the model (σ_ref = {sn} MPa: k = K/σ_ref)");
    }
    let _ = writeln!(
        s,
        "rms {:.3e}  n {}  free {}  logL {:.1}  AIC {:.1}  BIC {:.1}  ({} LM iterations: {})",
        r.rms, r.n, r.n_free, r.log_likelihood, r.aic, r.bic, r.iterations, r.stop_reason
    );
    if let Some(why) = r.convergence_text() {
        let _ = writeln!(s, "NOT CONVERGED: {why}");
    }
    if !r.at_bound.is_empty() {
        let _ = writeln!(
            s,
            "note: {} ended at a physical bound: the data do not constrain {} (the model may be missing an effect; see rsf diagnose)",
            r.at_bound.join(", "),
            if r.at_bound.len() == 1 { "it" } else { "them" }
        );
    }
    if let Some(m) = mcmc {
        let _ = writeln!(
            s,
            "MCMC: {} chains × {} steps, acceptance {:.2}, {:.0} simulations/s",
            m.chains, m.steps_per_chain, m.acceptance, m.simulations_per_s
        );
        let _ = writeln!(s, "{:>10} {:>14} {:>30} {:>8} {:>8}", "param", "median", "95% credible", "R-hat", "ESS");
        for (k, v) in &m.params {
            let _ = writeln!(
                s,
                "{:>10} {:>14.6e} {:>30} {:>8.3} {:>8.0}",
                k,
                v.median,
                format!("[{:.5e}, {:.5e}]", v.ci95[0], v.ci95[1]),
                v.rhat,
                v.ess
            );
        }
    }
    if !per.is_empty() {
        let _ = writeln!(
            s,
            "per-event fits (each step and hold alone):\n{:>4} {:>6} {:>10} {:>9} {:>9} {:>8} {:>10} {:>10} {:>9} {:>9}",
            "seg", "event", "kind", "V_i", "V_f", "hold_s", "a", "b1", "dc1", "rms"
        );
        for x in per {
            let _ = writeln!(
                s,
                "{:>4} {:>6} {:>10} {:>9.4} {:>9.4} {:>8} {:>10.5} {:>10.5} {:>9.3} {:>9.2e}",
                x.segment,
                x.event.name(),
                x.kind.name(),
                x.v_before,
                x.v_after,
                x.hold_s.map_or("–".to_string(), |h| format!("{h:.1}")),
                x.a,
                x.b[0],
                x.dc[0],
                x.rms
            );
        }
    }
    let _ = writeln!(s, "segments:");
    for g in &r.segments {
        let _ = writeln!(
            s,
            "{:>4} {:>10} t {:>10.2}–{:<10.2} v {:>10.5} µm/s  n {:>6}  rms {:.2e}",
            g.index,
            g.kind.name(),
            g.t0,
            g.t1,
            g.v,
            g.n,
            g.rms
        );
    }
    s
}

/// The diagnosis's options from the command line, checked before any work (the outputs'
/// paths are checked by the caller first): `rsf diagnose` and `rsf design` alike.
pub(crate) fn diagnose_options(a: &DiagnosisArgs) -> Result<rsf_diagnose::DiagnoseOptions> {
    if !(a.stiffness > 0.0 && a.stiffness.is_finite()) {
        bail!("--stiffness {} must be positive and finite (1/µm)", a.stiffness);
    }
    let baseline: rsf_diagnose::Baseline = a.baseline.parse().map_err(anyhow::Error::msg)?;
    let mut fo = FitOptions::new(vec![baseline.law().map_err(anyhow::Error::msg)?], a.stiffness);
    fo.loading = a.loading;
    fo.normal_stress = a.read.normal_stress_mode;
    if let Some(g) = a.wall_clock_guard {
        if !(g > 0.0) {
            bail!("--wall-clock-guard {g} must be positive (s)");
        }
        fo.budget.wall_clock_guard = Some(g);
    }
    if !(a.false_alarm_level > 0.0 && a.false_alarm_level < 1.0) {
        bail!("--false-alarm-level {} must lie between 0 and 1", a.false_alarm_level);
    }
    if !(a.stiffness_uncertainty > 0.0 && a.stiffness_uncertainty < 1.0) {
        bail!(
            "--stiffness-uncertainty {} must lie between 0 and 1 (a fraction of the nominal)",
            a.stiffness_uncertainty
        );
    }
    Ok(rsf_diagnose::DiagnoseOptions {
        heldout: !a.no_heldout,
        stiffness_uncertainty: a.stiffness_uncertainty,
        stage_times: a.stage_times,
        seed: a.seed,
        threads: a.threads,
        null_replicates: a.null_replicates,
        false_alarm_level: a.false_alarm_level,
        ..rsf_diagnose::DiagnoseOptions::new(fo)
    })
}

/// `rsf diagnose`.
pub fn diagnose(args: &DiagnoseArgs) -> Result<()> {
    let start = Instant::now();
    let a = &args.d;
    crate::output::Files::default()
        .input("record", &a.data)
        .output("--json", args.json.as_deref())
        .output("--report", args.report.as_deref())
        .check()?;
    let opts = diagnose_options(a)?;
    let rec = a.read.read(&a.data)?;
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    eprintln!(
        "rsf diagnose: {} samples, {} segments; fitting the baseline, then the extensions, held-out tests and per-event refits…",
        rec.len(),
        segs.len()
    );
    let (bar, progress) = progress_bar("diagnose {bar:30} {pos}/{len} fits, {elapsed} {msg}");
    let level = opts.false_alarm_level;
    let d = rsf_diagnose::diagnose(&rec, &segs, &rsf_diagnose::DiagnoseOptions { progress: Some(progress), ..opts })?;
    bar.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();
    let mut out = format!("cause: {}\n{}\n", d.cause, d.reason);
    if let Some(r) = &d.reconstruction {
        out += &format!("protocol problem: {}\n", r.message);
    }
    if let Some((c, s)) = &d.runner_up {
        out += &format!("runner-up: {c} (ΔBIC {s:.1})\n");
    }
    if let [(a, da), (b, db)] = d.undecided[..] {
        out += &format!("undecided: {a} (ΔBIC {da:.1}) or {b} (ΔBIC {db:.1}); the fit shown is {a}'s\n");
    } else if let Some(p) = d.partial {
        out += &format!("best partial extension: {p}\n");
    }
    if let (Some(l), Some((r, _))) = (&d.lead, &d.runner_up) {
        out += &format!(
            "lead over {r}: {:.1} in ln L, {:.2} times the spread the noise alone gives it (chance {:.3}; holds below {})\n",
            l.lead, l.z, l.p, level
        );
    }
    let l = &d.adequacy.levels;
    let c = &d.adequacy.coherence;
    let q = &d.adequacy.quiet;
    out += &format!(
        "adequacy: {} (events {}: excess {:.2}, p {:.3}, {} of {} tested{}{}{}{})\n",
        d.adequacy.verdict.as_str(),
        d.adequacy.event_verdict.as_str(),
        d.adequacy.excess,
        d.adequacy.p_value,
        d.adequacy.windows,
        d.adequacy.events_total,
        // where the events could not be tested against the noise, the coherence test's
        match (d.adequacy.event_verdict, c.verdict) {
            (rsf_diagnose::AdequacyVerdict::Untestable, rsf_diagnose::AdequacyVerdict::Untestable) => {
                format!("; compared with each other: untestable, {} of {} events", c.compared, c.windows)
            }
            (rsf_diagnose::AdequacyVerdict::Untestable, v) => format!(
                "; compared with each other: {} ({} events agree: excess {:.2}, p {})",
                v.as_str(),
                c.compared,
                c.excess,
                rsf_diagnose::p_words(c.p_value)
            ),
            (rsf_diagnose::AdequacyVerdict::Adequate | rsf_diagnose::AdequacyVerdict::Inadequate, _) => String::new(),
        },
        if l.p_value.is_finite() {
            format!(
                "; levels {} across {} step{}: excess {:.2}, p {}",
                if l.inadequate() { "off" } else { "fit" },
                l.steps.len(),
                if l.steps.len() == 1 { "" } else { "s" },
                l.excess,
                rsf_diagnose::p_words(l.p_value)
            )
        } else {
            String::new()
        },
        if q.ratio.is_finite() {
            format!(
                "; {} quiet stretches wander {:.2}× as much as its noise model says, in variance (p {}){}",
                q.stretches.len(),
                q.ratio,
                rsf_diagnose::p_words(if q.ratio < 1.0 { q.p_below } else { q.p_above }),
                if q.drift_is_misfit() {
                    ": its slow residual is misfit, not drift"
                } else if q.stretches_misfit() {
                    ": misfit after the transients"
                } else {
                    ""
                }
            )
        } else {
            String::new()
        },
        d.adequacy.family_words().map_or_else(String::new, |f| format!("; {f}"))
    );
    if let Some(f) = &d.adequacy.form {
        out += &format!("form test: {}\n", f.words());
    }
    if let Some(s) = &d.secondary {
        out += &format!(
            "second cause: {} on top of {}: ΔBIC {:.1}, rms ratio {:.4}, effect {}\n",
            s.cause,
            d.cause,
            s.delta_bic,
            s.rms_ratio,
            serde_json::to_string(&s.effect)?
        );
    }
    out += &format!(
        "evidence: residual lag-1 {:.2}, n_eff {:.0} of {}, residual trend {:.2e}/µm (t = {:.1}), segment rms max/median {:.1}, misfit/noise {:.1}\n",
        d.evidence.residual_lag1,
        d.evidence.n_effective,
        d.baseline.n,
        d.evidence.residual_trend_per_um,
        d.evidence.residual_trend_t,
        d.evidence.segment_rms_ratio,
        d.evidence.misfit_over_noise
    );
    let opt = |x: Option<f64>, p: usize| x.map_or("–".to_string(), |v| format!("{v:.p$}"));
    out += &format!(
        "residual vs ln V: slope {} (t = {}); per-event Dc: χ²/dof {}, d ln Dc/d ln(step) {}, d ln Dc/d ln(hold) {} over {} events; k from reload slopes {}\n",
        d.evidence.residual_vs_ln_v.map_or("–".into(), |v| format!("{v:.2e}")),
        opt(d.evidence.residual_vs_ln_v_t, 1),
        opt(d.evidence.dc_consistency_chi2, 1),
        opt(d.evidence.dc_vs_ln_step, 2),
        opt(d.evidence.dc_vs_ln_hold, 2),
        d.per_segment.len(),
        d.evidence.k_reload_slope.map_or("–".into(), |k| format!("{k:.3e}/µm"))
    );
    out += &format!(
        "{:24} {:>10} {:>10} {:>10} {:>13} {:>22}  effect\n",
        "candidate", "ΔBIC", "ΔAIC", "rms ratio", "P(false) ≤", "held-out rms"
    );
    for c in &d.candidates {
        out += &format!(
            "{:24} {:>10.1} {:>10.1} {:>10.4} {:>13} {:>22}  {}\n",
            c.cause,
            c.delta_bic,
            c.delta_aic,
            c.rms_ratio,
            c.null
                .as_ref()
                .map_or("–".into(), |n| format!("{:.0e} ≤ {:.0e}", n.false_alarm_probability, n.false_alarm_upper)),
            match (c.heldout_rms_before, c.heldout_rms_after) {
                (Some(b), Some(a)) => format!("{b:.2e} → {a:.2e}"),
                _ => "–".into(),
            },
            serde_json::to_string(&c.effect)?
                + &if c.at_bound.is_empty() {
                    String::new()
                } else {
                    format!(" (at bound: {})", c.at_bound.join(", "))
                }
        );
    }
    crate::write_stdout(&out)?;
    eprintln!("rsf diagnose: {wall:.1} s");
    if let Some(j) = &args.json {
        let mut v = serde_json::to_value(&d)?;
        v["data"] = serde_json::json!(a.data.display().to_string());
        crate::output::write_bytes(j, serde_json::to_string_pretty(&v)? + "\n")?;
    }
    if let Some(r) = &args.report {
        let name = a.data.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
        crate::output::write_bytes(r, rsf_report::diagnosis_html(&d, &name))?;
    }
    Ok(())
}

/// What the standard errors assume, in one line: the noise model and how much it widens them.
fn uncertainty_line(r: &FitResult) -> String {
    match &r.noise {
        None if r.bins.is_some() => "uncertainty: independent residuals of one σ (white noise): a fit on bin means \
             has no sample residuals to fit a noise model to (--every-sample for the noise-model form)"
            .into(),
        None => "uncertainty: independent residuals of one σ (white noise)".into(),
        Some(n) => {
            let ratios: Vec<f64> = r
                .stderr
                .iter()
                .filter_map(|(k, se)| Some(se / n.stderr_white.get(k)?))
                .filter(|x| x.is_finite())
                .collect();
            let lo = ratios.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = ratios.iter().copied().fold(0.0, f64::max);
            let ar = if n.ar1_sd > 0.0 {
                format!(", AR(1) {:.1e} (τ {:.3} s)", n.ar1_sd, n.ar1_tau_s)
            } else {
                String::new()
            };
            let drift = if n.drift_share > 0.0 {
                format!(", drift {:.0} % of the variance (β {:.1})", 100.0 * n.drift_share, n.drift_beta)
            } else {
                String::new()
            };
            let widen = if ratios.is_empty() {
                String::new()
            } else {
                format!("; stderr {lo:.2}–{hi:.2}× the white-noise form (--uncertainty white)")
            };
            format!("uncertainty: under the residuals' noise model: white {:.1e}{ar}{drift}{widen}", n.white_sd)
        }
    }
}
