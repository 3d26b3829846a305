//! The SVG charts of fits and diagnoses, on [`rsf_plot`].

use super::words::{cause_words, law_words, param_rows};
use rsf_diagnose::Diagnosis;
use rsf_fit::fit::{Curve, FitResult};
use rsf_plot::{BLACK, GREY, PALETTE, Panel, PlotError, RGBColor, Series, fmt_num, render, render_stack};

const BASELINE: RGBColor = PALETTE[0];
const EXTENDED: RGBColor = PALETTE[1];
const LOAD_POINT: &str = "load-point displacement (µm)";

/// At most `max` sample indices of `n`, evenly strided (a figure needs no more).
fn thin(n: usize, max: usize) -> Vec<usize> {
    (0..n).step_by(n.div_ceil(max.max(1)).max(1)).collect()
}

/// Load-point spans of every other segment of a curve (segments 2, 4, …), to shade.
fn bands(c: &Curve) -> Vec<(f64, f64)> {
    let n = c.segment.iter().max().map_or(0, |m| m + 1);
    let mut span = vec![(f64::INFINITY, f64::NEG_INFINITY); n];
    for (&s, &x) in c.segment.iter().zip(&c.load_point) {
        span[s] = (span[s].0.min(x), span[s].1.max(x));
    }
    span.into_iter().enumerate().filter(|(s, b)| s % 2 == 1 && b.0 < b.1).map(|(_, b)| b).collect()
}

/// The model of a curve as lines, one per segment so that gaps are not bridged; labelled once.
fn model_lines(c: &Curve, idx: &[usize], label: &str, color: RGBColor) -> Vec<Series> {
    let mut out: Vec<Series> = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    let mut seg = None;
    for &i in idx.iter().filter(|&&i| i < c.model.len() && i < c.segment.len()) {
        if seg.is_some_and(|s| s != c.segment[i]) && !cur.is_empty() {
            out.push(Series::line(None, std::mem::take(&mut cur), color));
        }
        seg = Some(c.segment[i]);
        cur.push((c.load_point[i], c.model[i]));
    }
    if !cur.is_empty() {
        out.push(Series::line(None, cur, color));
    }
    if let Some(first) = out.first_mut() {
        first.label = Some(label.to_string());
    }
    out
}

fn residuals(c: &Curve, idx: &[usize]) -> Vec<(f64, f64)> {
    idx.iter().filter(|&&i| i < c.model.len()).map(|&i| (c.load_point[i], c.data[i] - c.model[i])).collect()
}

/// The parameters of a fit for a chart title, with ± where fitted: `a = 0.0104 ± 0.0002,
/// b = 0.00965 ± 0.00012, Dc = 12.3 ± 0.4 µm` (the subscript 1 dropped for one state).
pub fn fit_title(r: &FitResult) -> String {
    let one = r.params.b.len() == 1;
    param_rows(r)
        .into_iter()
        .filter(|(n, _, _)| n != "μ₀" && n != "k" && n != "g")
        .map(|(n, v, _)| format!("{} = {v}", if one { n.trim_end_matches('₁').to_string() } else { n }))
        .collect::<Vec<_>>()
        .join(", ")
}

/// k and g of a fit for a chart title, `(fixed)` when not fitted.
fn machine_title(r: &FitResult) -> String {
    param_rows(r)
        .into_iter()
        .filter(|(n, _, _)| n == "k" || n == "g")
        .map(|(n, v, fitted)| format!("{n} = {v}{}", if fitted { "" } else { " (fixed)" }))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `rsf fit --plot`: data, model and residuals of a fit against load-point displacement, the
/// parameters (± standard error) in the titles, every other segment shaded.
pub fn fit_svg(r: &FitResult, name: &str) -> Result<String, PlotError> {
    let c = &r.curve;
    let idx = thin(c.time.len(), 4000);
    let bands = bands(c);
    let mut top = Panel::new(fit_title(r), LOAD_POINT, "friction μ");
    top.bands = bands.clone();
    top = top.with(Series::dots("data".to_string(), idx.iter().map(|&i| (c.load_point[i], c.data[i])).collect(), GREY));
    for s in model_lines(c, &idx, "model", EXTENDED) {
        top = top.with(s);
    }
    let mut bottom =
        Panel::new(format!("residuals; {}", machine_title(r)), LOAD_POINT, "residual (data − model)").zero_line();
    bottom.bands = bands;
    bottom = bottom.with(Series::dots(None, residuals(c, &idx), BASELINE));
    let title =
        format!("{name} — {} law, rms {} over {} samples", law_words(&r.params.laws.join("+")), fmt_num(r.rms, 3), r.n);
    render_stack(&title, &[(top, 440), (bottom, 270)], 1000)
}

/// Data with the baseline and the extended model, and both residuals, against load point; the
/// held-out split dashed.
pub fn models_svg(d: &Diagnosis) -> Result<String, PlotError> {
    let b = &d.baseline.curve;
    let ext = d.extended.as_ref().map(|e| &e.curve).filter(|e| e.time.len() == b.time.len());
    let idx = thin(b.time.len(), 3000);
    let bands = bands(b);
    let ext_label = format!("with {}", cause_words(d.cause));
    let mut top = Panel::new("", LOAD_POINT, "friction μ");
    top.bands = bands.clone();
    top = top.with(Series::dots("data".to_string(), idx.iter().map(|&i| (b.load_point[i], b.data[i])).collect(), GREY));
    top.series.extend(model_lines(b, &idx, "baseline", BASELINE));
    if let Some(e) = ext {
        top.series.extend(model_lines(e, &idx, &ext_label, EXTENDED));
    }
    let mut bottom = Panel::new("", LOAD_POINT, "residual (data − model)").zero_line();
    bottom.bands = bands;
    bottom = bottom.with(Series::dots("baseline".to_string(), residuals(b, &idx), BASELINE));
    if let Some(e) = ext {
        bottom = bottom.with(Series::dots(ext_label, residuals(e, &idx), EXTENDED));
    }
    // the held-out split, at the load point of the first sample after it
    if let Some(i) = b.time.iter().position(|&t| t >= d.heldout_split_t).filter(|&i| i > 0) {
        let x = b.load_point[i];
        for p in [&mut top, &mut bottom] {
            let (lo, hi) = rsf_plot::chart::padded(p.series.iter().flat_map(|s| s.points.iter().map(|q| q.1)), false);
            p.y_range = Some((lo, hi));
            p.series.push(Series::dashed(None, vec![(x, lo), (x, hi)], BLACK));
        }
    }
    render_stack("", &[(top, 430), (bottom, 290)], 980)
}

/// Residual rms per segment, and residuals against the model slip rate (log axis).
pub fn residuals_svg(d: &Diagnosis) -> Result<String, PlotError> {
    let b = &d.baseline.curve;
    let ext = d.extended.as_ref().map(|e| &e.curve).filter(|e| e.time.len() == b.time.len());
    let ext_label = format!("with {}", cause_words(d.cause));
    let seg_rms = |c: &Curve| -> Vec<(f64, f64)> {
        let n = c.segment.iter().max().map_or(0, |m| m + 1);
        let mut acc = vec![(0.0, 0usize); n];
        for (k, &s) in c.segment.iter().enumerate() {
            acc[s].0 += (c.data[k] - c.model[k]).powi(2);
            acc[s].1 += 1;
        }
        acc.iter()
            .enumerate()
            .filter(|(_, a)| a.1 > 0)
            .map(|(i, a)| ((i + 1) as f64, (a.0 / a.1 as f64).sqrt()))
            .collect()
    };
    let idx = thin(b.time.len(), 3000);
    let vs_v = |c: &Curve| -> Vec<(f64, f64)> {
        if c.slip_rate.len() != c.data.len() {
            return vec![];
        }
        idx.iter().filter(|&&i| c.slip_rate[i] > 0.0).map(|&i| (c.slip_rate[i], c.data[i] - c.model[i])).collect()
    };
    let mut per_seg = Panel::new("rms misfit per segment", "segment", "rms residual").integer_x();
    per_seg = per_seg.with(Series::points("baseline".to_string(), seg_rms(b), BASELINE));
    let mut per_v = Panel::new("residuals against slip rate", "model slip rate V (µm/s)", "residual (data − model)")
        .log_x()
        .zero_line();
    per_v = per_v.with(Series::dots("baseline".to_string(), vs_v(b), BASELINE));
    if let Some(e) = ext {
        per_seg = per_seg.with(Series::points(ext_label.clone(), seg_rms(e), EXTENDED));
        per_v = per_v.with(Series::dots(ext_label, vs_v(e), EXTENDED));
    }
    render("", &[per_seg, per_v], 2, (490, 360))
}

/// The baseline residuals' spectrum (binned periodogram) and the fitted noise model's, log-log,
/// with the white level and the drift part drawn on their own.
pub fn noise_svg(d: &Diagnosis) -> Result<String, PlotError> {
    let Some(m) = d.evidence.noise.as_ref().filter(|m| !m.periodogram.is_empty()) else {
        return Err(PlotError("no noise model".into()));
    };
    let data: Vec<(f64, f64)> = m.periodogram.iter().filter(|p| p[1] > 0.0).map(|p| (p[0], p[1] * m.dt)).collect();
    let model: Vec<(f64, f64)> = m.periodogram.iter().map(|p| (p[0], p[2] * m.dt)).collect();
    // a variably sampled record's spectrum comes from stretches at several intervals, each with
    // its own aliasing and white level per Hz: the model is drawn at each bin, not as one line
    let model_series = match m.sampling {
        None => Series::line("fitted noise model".to_string(), model, BLACK),
        Some(_) => Series::dots("fitted noise model (at each stretch's bins)".to_string(), model, BLACK),
    };
    let mut panel =
        Panel::new("residual spectrum of the baseline", "frequency (Hz)", "power spectral density (friction²/Hz)")
            .log_x()
            .log_y()
            .with(Series::dots("residuals (binned periodogram)".to_string(), data, BASELINE))
            .with(model_series);
    if m.drift_amplitude > 0.0 {
        let drift = m.periodogram.iter().map(|p| (p[0], m.drift_psd(p[0]))).collect();
        panel = panel.with(Series::dashed(format!("drift part, ∝ f^-{:.1}", m.drift_beta), drift, EXTENDED));
    }
    let (lo, hi) = (m.periodogram[0][0], m.periodogram[m.periodogram.len() - 1][0]);
    panel = panel.with(Series::dashed(
        "white part".to_string(),
        vec![(lo, m.white_variance * m.dt), (hi, m.white_variance * m.dt)],
        GREY,
    ));
    render("", &[panel], 1, (760, 380))
}

/// Per-event Dc against step size and against hold duration, with one-standard-error bars.
/// Empty when there are fewer than two steps and two holds.
pub fn events_svg(d: &Diagnosis) -> Result<String, PlotError> {
    let steps: Vec<_> =
        d.per_segment.iter().filter(|e| e.hold_s.is_none() && e.v_before > 0.0 && e.v_after > 0.0).collect();
    let holds: Vec<_> = d.per_segment.iter().filter(|e| e.hold_s.is_some_and(|h| h > 0.0)).collect();
    let mut panels = Vec::new();
    // a panel needs two events to show a trend
    if steps.len() >= 2 {
        let pts = steps.iter().map(|e| ((e.v_after / e.v_before).log10(), e.dc[0])).collect();
        let err = steps.iter().map(|e| e.dc[0] * e.ln_dc_stderr).collect();
        panels.push(
            Panel::new("Dc refitted step by step", "step size log10(V after / V before)", "Dc (µm)")
                .with(Series::points(None, pts, BASELINE).y_err(err)),
        );
    }
    if holds.len() >= 2 {
        let pts = holds.iter().map(|e| (e.hold_s.unwrap_or(f64::NAN), e.dc[0])).collect();
        let err = holds.iter().map(|e| e.dc[0] * e.ln_dc_stderr).collect();
        // whole decades with room on both sides: a hold of exactly 100 s is not on the axis
        let (lo, hi) =
            rsf_plot::chart::padded(holds.iter().flat_map(|e| e.hold_s).flat_map(|h| [h / 1.5, h * 1.5]), true);
        panels.push(
            Panel::new("Dc refitted hold by hold", "hold duration (s)", "Dc (µm)")
                .log_x()
                .x_range(lo, hi)
                .with(Series::points(None, pts, EXTENDED).y_err(err)),
        );
    }
    if panels.is_empty() {
        return Ok(String::new());
    }
    render("", &panels, 2, (490, 340))
}

/// The adequacy test's figure: each tested event window's misfit (rms of its bin means) against
/// the time of its event, over the noise band (the same statistic in quiet placebo windows of
/// the same length: the band spans the median placebo set's rms and the level above which the
/// model is inadequate). Empty when the test could not run.
pub fn adequacy_svg(d: &Diagnosis) -> Result<String, PlotError> {
    let a = &d.adequacy;
    if a.events.is_empty() || !(a.noise_rms > 0.0) {
        return Ok(String::new());
    }
    let mut ev: Vec<_> = a.events.iter().collect();
    ev.sort_by(|x, y| x.t.total_cmp(&y.t));
    let steps: Vec<(f64, f64)> = ev.iter().filter(|e| e.event == "step").map(|e| (e.t, e.rms)).collect();
    let reslides: Vec<(f64, f64)> = ev.iter().filter(|e| e.event == "reslide").map(|e| (e.t, e.rms)).collect();
    let limit = a.noise_rms * rsf_diagnose::ADEQUACY_EXCESS.sqrt();
    let mut panel = Panel::new(
        format!("Misfit by event: {} (excess {})", a.verdict.as_str(), fmt_num(a.excess, 3)),
        "time of the event (s)",
        "event-locked misfit (rms of bin means)",
    )
    .log_y()
    .band(a.noise_rms / 3.0, limit);
    if !steps.is_empty() {
        panel = panel.with(Series::points("velocity steps".to_string(), steps, BASELINE));
    }
    if !reslides.is_empty() {
        panel = panel.with(Series::points("reslides after holds".to_string(), reslides, EXTENDED));
    }
    let (t0, t1) = (ev.first().map_or(0.0, |e| e.t), ev.last().map_or(1.0, |e| e.t));
    panel = panel.with(Series::dashed(
        "noise band (quiet windows)".to_string(),
        vec![(t0, a.noise_rms), (t1, a.noise_rms)],
        GREY,
    ));
    render("", &[panel], 1, (760, 340))
}

/// Where the events could not be tested against quiet windows: each event's misfit profile in
/// log time since it (the coherence test's, `diagnose/coherence.rs`), steps up and reslides in
/// one colour, steps down in another — a wrong law's misfits lie on top of each other, noise's
/// scatter about zero. Empty when fewer than two events have a profile.
pub fn coherence_svg(d: &Diagnosis) -> Result<String, PlotError> {
    use rsf_diagnose::{AdequacyVerdict, EventDirection};
    let c = &d.adequacy.coherence;
    if d.adequacy.event_verdict != AdequacyVerdict::Untestable || c.profiles.len() < 2 {
        return Ok(String::new());
    }
    let mut panel = Panel::new(
        format!(
            "Misfit profiles by event: {}{}",
            c.verdict.as_str(),
            if c.p_value.is_finite() { format!(" (p {})", fmt_num(c.p_value, 2)) } else { String::new() }
        ),
        "time since the event / window length",
        "misfit profile (mean and slope taken out)",
    )
    .log_x();
    let (mut up_named, mut down_named) = (false, false);
    for e in &c.profiles {
        let (colour, named, label) = match e.direction {
            EventDirection::StepUp | EventDirection::Reslide => (BASELINE, &mut up_named, "steps up and reslides"),
            EventDirection::StepDown => (EXTENDED, &mut down_named, "steps down"),
        };
        let label = (!*named).then(|| label.to_string());
        *named = true;
        panel = panel.with(Series::line(label, e.points(), colour));
    }
    let (x0, x1) = (5e-4, 1.0);
    panel = panel.with(Series::dashed(None, vec![(x0, 0.0), (x1, 0.0)], GREY));
    render("", &[panel], 1, (760, 340))
}

/// The quiet test (`diagnose/quiet.rs`): each quiet stretch of sliding's wander (the residual's
/// mean over its last quarter minus its first), against the standard deviation the fitted noise
/// model gives it. Empty when no stretch was tested.
pub fn quiet_svg(d: &Diagnosis) -> Result<String, PlotError> {
    let q = &d.adequacy.quiet;
    if q.stretches.is_empty() {
        return Ok(String::new());
    }
    let mid = |t: [f64; 2]| 0.5 * (t[0] + t[1]);
    let floor = q.stretches.iter().map(|s| s.claimed).fold(f64::INFINITY, f64::min) * 1e-3;
    let seen: Vec<(f64, f64)> = q.stretches.iter().map(|s| (mid(s.t), s.wander.abs().max(floor))).collect();
    let claimed: Vec<(f64, f64)> = q.stretches.iter().map(|s| (mid(s.t), s.claimed)).collect();
    let panel = Panel::new(
        format!(
            "Quiet stretches: wander {}× the noise model's, in variance — {}",
            fmt_num(q.ratio, 3),
            if q.drift_is_misfit() {
                "its drift is misfit"
            } else if q.stretches_misfit() {
                "misfit after the transients"
            } else {
                "as the noise"
            }
        ),
        "middle of the quiet stretch (s)",
        "|wander| across the stretch (friction)",
    )
    .log_y()
    .with(Series::points("wander seen".to_string(), seen, BASELINE))
    .with(Series::points("the noise model's standard deviation".to_string(), claimed, GREY));
    render("", &[panel], 1, (760, 300))
}
