//! Break-time uncertainty: samples that the protocol's timing cannot predict are left out.
//!
//! A protocol reconstructed from a noisy load point (encoder noise σ_x) knows each break only to
//! about σ_x/|Δv| (Δv the velocity change there): the split between two lines moves until the
//! lines part by more than the noise. Right after a break the model friction changes fast
//! (dμ/dt up to k·Δv while the spring loads), so a timing error δt misplaces it by |dμ/dt|·δt —
//! on a stiff machine far more than the noise, whatever the physics. Every model, baseline and
//! extension alike, misfits there, and the extensions with the most freedom gain the most: a
//! false cause. So the diagnosis leaves out the samples near each break where
//! `TIMING_SIGMAS` × σ_x/|Δv| × |dμ/dt| of the baseline model exceeds the friction noise. On a
//! clean load point σ_x is round-off and nothing is left out.

use rsf_fit::fit::{FitResult, Prepared};
use rsf_fit::segment::Segment;
use serde::Serialize;

/// Break-time errors are taken this many standard deviations wide.
pub const TIMING_SIGMAS: f64 = 3.0;

/// The samples left out for break-time uncertainty.
#[derive(Clone, Debug, Serialize)]
pub struct TimingMask {
    /// Load-point noise about the protocol's lines, µm (robust: 1.4826 × median |residual|).
    pub load_point_sigma_um: f64,
    /// Left-out time windows, s (inclusive).
    pub windows: Vec<(f64, f64)>,
    /// Samples left out.
    pub samples: usize,
}

/// The load-point noise about the protocol's lines, µm (robust).
pub(super) fn load_point_sigma(p: &Prepared) -> f64 {
    let mut r: Vec<f64> = p
        .segments
        .iter()
        .flat_map(|s| {
            (s.i0..=s.i1).map(move |i| (p.record.load_point[i] - (s.lp0 + s.v * (p.record.time[i] - s.t0))).abs())
        })
        .collect();
    if r.is_empty() {
        return 0.0;
    }
    let mid = r.len() / 2;
    let (_, m, _) = r.select_nth_unstable_by(mid, f64::total_cmp);
    1.4826 * *m
}

/// The mask for the baseline fit `base` on `p`; `None` when nothing is to be left out.
pub(super) fn timing_mask(p: &Prepared, base: &FitResult) -> Option<TimingMask> {
    let sx = load_point_sigma(p);
    let c = &base.curve;
    if !(sx > 0.0) || c.time.len() < 3 {
        return None;
    }
    let (windows, samples) = unpredictable(&c.time, &c.model, &p.segments, sx, base.rms);
    (samples > 0).then_some(TimingMask { load_point_sigma_um: sx, windows, samples })
}

/// The samples of a model `model` at `time` that the breaks' timing cannot predict, with the
/// load point's noise `sx` (µm) about the lines of `segments` and the friction noise `noise`:
/// near each break, from [`TIMING_SIGMAS`] × σ_x/|Δv| before it, while that timing error would
/// move the model by more than the noise. The time windows (inclusive) and their samples.
pub(super) fn unpredictable(
    time: &[f64],
    model: &[f64],
    segments: &[Segment],
    sx: f64,
    noise: f64,
) -> (Vec<(f64, f64)>, usize) {
    let n = time.len();
    let mut windows: Vec<(f64, f64)> = vec![];
    let mut samples = 0;
    if !(sx > 0.0) || n < 3 {
        return (windows, samples);
    }
    // the model's friction rate at each used sample (centred differences)
    let rate = |k: usize| {
        let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
        let dt = time[b] - time[a];
        if dt > 0.0 { ((model[b] - model[a]) / dt).abs() } else { 0.0 }
    };
    for j in 1..segments.len() {
        let (s0, s1) = (&segments[j - 1], &segments[j]);
        let dv = (s1.v - s0.v).abs();
        if !(dv > 0.0) {
            continue;
        }
        let dt_break = TIMING_SIGMAS * sx / dv;
        // from the last sample before the break's uncertainty onward, while the timing error
        // would misplace the model by more than the noise
        let tb = s1.t0;
        let first = time.partition_point(|&t| t < tb - dt_break);
        // a break whose timing error moves the model by less than the noise anywhere costs
        // nothing (a clean load point: σ_x is round-off)
        let fast = (first..n).take_while(|&k| time[k] <= s1.t1).any(|k| rate(k) * dt_break > noise);
        if !fast {
            continue;
        }
        let mut last = None;
        for k in first..n {
            if time[k] > tb + dt_break && rate(k) * dt_break <= noise {
                break;
            }
            last = Some(k);
        }
        if let Some(l) = last {
            samples += l + 1 - first;
            windows.push((time[first], time[l]));
        }
    }
    (windows, samples)
}
