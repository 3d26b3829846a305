//! Per-event refits: each step and each hold-and-reslide refitted alone with the baseline law,
//! and the consistency of Dc between them. `rsf diagnose` and `rsf fit --per-segment` both use
//! [`per_event_fits`].

use super::evidence::{n_eff_of, slope_t};
use super::starts::initial_for;
use rsf_fit::fit::{FitOptions, FitResult, Prepared, fit, prepare};
use rsf_fit::parallel::par_map;
use rsf_fit::segment::SegmentKind;
use serde::Serialize;

/// What an event is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum EventKind {
    /// A change of load-point velocity between two sliding segments.
    Step,
    /// A hold (load point at rest) and the reslide after it.
    Hold,
}

impl EventKind {
    /// The name in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Self::Step => "step",
            Self::Hold => "hold",
        }
    }
}

impl std::fmt::Display for EventKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One step or hold refitted alone with the baseline law (free a, b, Dc; machine stiffness and
/// the other options as in the full fit).
#[derive(Clone, Debug, Serialize)]
pub struct EventFit {
    /// Step or hold.
    pub event: EventKind,
    /// The segment after the change (1-based, as in `rsf segments`).
    pub segment: usize,
    /// Its kind.
    pub kind: SegmentKind,
    /// Time of the change, s.
    pub t: f64,
    /// Load-point velocity of the sliding before, µm/s.
    pub v_before: f64,
    /// …and after.
    pub v_after: f64,
    /// Hold duration, s (holds only).
    pub hold_s: Option<f64>,
    /// Fitted a.
    pub a: f64,
    /// Fitted b of each state variable.
    pub b: Vec<f64>,
    /// Fitted Dc of each state variable, µm.
    pub dc: Vec<f64>,
    /// Machine stiffness of the refit, 1/µm (the full fit's).
    pub k: f64,
    /// Standard error of ln Dc₁, widened for correlated residuals by sqrt(n / n_eff).
    pub ln_dc_stderr: f64,
    /// rms misfit of the window.
    pub rms: f64,
    /// Samples in the window.
    pub n: usize,
}

/// Every event of the record refitted alone, starting from the full fit `base` (its budget a
/// tenth of the full fit's); events a window cannot pin down are left out. `threads` as in
/// `DiagnoseOptions::threads` (the result does not depend on it).
pub fn per_event_fits(p: &Prepared, opts: &FitOptions, base: &FitResult, threads: usize) -> Vec<EventFit> {
    let windows = event_windows(p);
    par_map(&windows, threads, |&(prev, j)| fit_event(p, opts, base, prev, j)).into_iter().flatten().collect()
}

/// The events of a record as (last sliding segment before, segment after) index pairs: each
/// velocity step and each hold-and-reslide, refitted alone from the second half of the sliding
/// before it to the end of the segment after it.
pub fn event_windows(p: &Prepared) -> Vec<(usize, usize)> {
    let s = &p.segments;
    let mut out = vec![];
    for j in 1..s.len() {
        if s[j].v <= 0.0 {
            continue;
        }
        // the last sliding segment before j
        let Some(prev) = (0..j).rev().find(|&i| s[i].v > 0.0) else { continue };
        out.push((prev, j));
    }
    out
}

pub(super) fn fit_event(p: &Prepared, opts: &FitOptions, base: &FitResult, prev: usize, j: usize) -> Option<EventFit> {
    let s = &p.segments;
    // the forward model runs from the start of the record (so the state entering the window is
    // the model's own, not an assumed steady state), the misfit counts only from the second half
    // of the sliding before the event to the end of the segment after it
    let mid = (s[prev].i0 + s[prev].i1) / 2;
    let mut o = FitOptions {
        laws: opts.laws.clone(),
        mu0_per_segment: false,
        fit_slip_trend: false,
        fit_stiffness: false,
        weighting: rsf_fit::fit::Weighting::Uniform,
        // the window's interval is widened by its own n/n_eff below
        uncertainty: rsf_fit::fit::Uncertainty::White,
        starts: 2,
        // a tenth of the baseline's work: an event the window cannot pin down is dropped
        budget: opts.budget.scaled(0.1),
        ..opts.clone()
    };
    let mut pw = prepare(&p.record, &s[..=j], &o).ok()?;
    o.initial = initial_for(&pw, &o, &base.params)?;
    o.initial.retain(|(n, _)| *n != rsf_fit::fit::ParamName::Mu0);
    let keep: Vec<usize> = (0..pw.used.len()).filter(|&r| pw.used[r] >= mid).collect();
    if keep.len() < 10 {
        return None;
    }
    pw.used = keep.iter().map(|&r| pw.used[r]).collect();
    pw.seg_of = keep.iter().map(|&r| pw.seg_of[r]).collect();
    pw.weights = vec![1.0; keep.len()];
    let f = fit(&pw, &o).ok()?;
    // a refit stopped by its budget has not converged: its Dc would only add noise
    if f.budget_hit.is_some() {
        return None;
    }
    let ci = f.ci95.get("dc1")?;
    let hold = (j > prev + 1).then(|| (prev + 1..j).map(|i| s[i].t1 - s[i].t0).sum::<f64>());
    // the interval assumes independent noise: widen it by sqrt(n/n_eff) of the window residuals
    let inflate = (f.n as f64 / n_eff_of(&f)).sqrt();
    Some(EventFit {
        event: if hold.is_some() { EventKind::Hold } else { EventKind::Step },
        segment: j + 1,
        kind: s[j].kind,
        t: s[j].t0,
        v_before: s[prev].v,
        v_after: s[j].v,
        hold_s: hold,
        a: f.params.a,
        b: f.params.b.clone(),
        dc: f.params.dc.clone(),
        k: f.params.k,
        ln_dc_stderr: inflate * ((ci[1] / ci[0]).ln() / (2.0 * 1.96)).abs(),
        rms: f.rms,
        n: f.n,
    })
}

/// Consistency of the per-event Dc: reduced χ² of ln Dc about its weighted mean, and the slopes
/// of ln Dc against ln(step ratio) and ln(hold duration).
pub(super) fn dc_consistency(ev: &[EventFit]) -> (Option<f64>, Option<f64>, Option<f64>) {
    let ok: Vec<&EventFit> = ev.iter().filter(|e| e.ln_dc_stderr.is_finite() && e.ln_dc_stderr > 0.0).collect();
    let chi2 = (ok.len() >= 2).then(|| {
        let w: Vec<f64> = ok.iter().map(|e| 1.0 / e.ln_dc_stderr.powi(2)).collect();
        let m = ok.iter().zip(&w).map(|(e, w)| w * e.dc[0].ln()).sum::<f64>() / w.iter().sum::<f64>();
        ok.iter().zip(&w).map(|(e, w)| w * (e.dc[0].ln() - m).powi(2)).sum::<f64>() / (ok.len() - 1) as f64
    });
    let line = |pts: Vec<(f64, f64)>| -> Option<f64> {
        let (x, y): (Vec<f64>, Vec<f64>) = pts.into_iter().unzip();
        slope_t(&x, &y, x.len() as f64).map(|s| s.0)
    };
    let steps =
        ok.iter().filter(|e| e.hold_s.is_none()).map(|e| ((e.v_after / e.v_before).ln(), e.dc[0].ln())).collect();
    let holds = ok.iter().filter_map(|e| e.hold_s.map(|h| (h.ln(), e.dc[0].ln()))).collect();
    (chi2, line(steps), line(holds))
}
