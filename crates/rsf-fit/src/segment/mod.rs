//! Detecting the loading protocol from the load-point record alone.
//!
//! The record is cut into pieces of constant load-point velocity by bottom-up merging of
//! straight-line fits to x_lp(t): start from short runs of samples, repeatedly merge the
//! adjacent pair whose merged line fit raises the residual sum of squares least, and stop when
//! every merge would cost more than a penalty times the noise variance (a BIC-like rule). Each
//! run keeps centred moments (count, means, M2, co-moment), which combine exactly and stably
//! (Chan et al.), so a merge costs O(1). Then neighbours whose velocities differ by less than a
//! ratio are fused (correlated noise and servo wobble must not create steps), velocities are
//! classified (hold: slope not different from zero), and each boundary is refined to the
//! sample that minimises the two-line misfit; on a noisy load point it then moves to where the
//! two segments' lines cross (`refine::crossing_breaks`), which is far more precise than any
//! split of noisy samples. Working on samples with time as the abscissa
//! makes the method indifferent to changes of sampling rate.

mod consolidate;
mod moments;
mod normal;
mod refine;
mod split;

use consolidate::consolidate;
use moments::Moments;
pub use normal::{
    NORMAL_STRESS_EVENT, NORMAL_STRESS_PAUSE_S, NORMAL_STRESS_SMOOTHING_S, NormalStressEvent, normal_stress_events,
};
use serde::Serialize;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A segment whose load point travels less than this over its duration (µm) is a hold: far below
/// any lab encoder's resolution (≈ 10 nm) and any commanded creep (the slowest lab rates, ~1e-4
/// µm/s, move 0.1 µm in 1000 s), yet far above the round-off of a clean load-point record.
pub const HOLD_TRAVEL_UM: f64 = 5e-3;

/// What a segment is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SegmentKind {
    /// The first segment (the state before any detected change).
    Initial,
    /// Faster than the previous moving segment.
    StepUp,
    /// Slower than the previous moving segment.
    StepDown,
    /// Load point at rest.
    Hold,
    /// Moving again after a hold.
    Reslide,
}

impl SegmentKind {
    /// Short name for tables.
    pub fn name(self) -> &'static str {
        match self {
            Self::Initial => "initial",
            Self::StepUp => "step-up",
            Self::StepDown => "step-down",
            Self::Hold => "hold",
            Self::Reslide => "reslide",
        }
    }
}

/// A segment of constant load-point velocity: samples `i0..=i1`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Segment {
    /// First sample index.
    pub i0: usize,
    /// Last sample index (inclusive).
    pub i1: usize,
    /// Start time, s (time of sample i0; for later segments, the refined break time).
    pub t0: f64,
    /// End time, s.
    pub t1: f64,
    /// Load point at the start, µm (from the line fit).
    pub lp0: f64,
    /// Load-point velocity, µm/s (0 for holds).
    pub v: f64,
    /// Kind.
    pub kind: SegmentKind,
}

/// Segmentation settings.
#[derive(Clone, Copy, Debug)]
pub struct SegmentOptions {
    /// Adjacent moving segments whose velocities differ by less than this factor are one.
    pub min_ratio: f64,
    /// Merge penalty in units of the noise variance (per breakpoint).
    pub penalty: f64,
    /// Segments shorter than this many samples are absorbed by a neighbour.
    pub min_samples: usize,
    /// Segments shorter than this (s) are absorbed by a neighbour, shortest first: servo
    /// oscillation and bursts of encoder noise must not become protocol steps.
    pub min_duration: f64,
}

impl Default for SegmentOptions {
    fn default() -> Self {
        Self { min_ratio: 1.3, penalty: 0.0, min_samples: 5, min_duration: 0.3 }
    }
}

#[derive(PartialEq)]
struct Cand {
    cost: f64,
    left: usize,
    stamp: (u32, u32),
}
impl Eq for Cand {}
impl PartialOrd for Cand {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Cand {
    fn cmp(&self, o: &Self) -> Ordering {
        o.cost.total_cmp(&self.cost) // min-heap
    }
}

/// Detects segments of constant load-point velocity in `(time, lp)`.
pub fn detect(time: &[f64], lp: &[f64], opts: &SegmentOptions) -> Vec<Segment> {
    let n = time.len();
    if n < 4 {
        return vec![];
    }
    // runs of at least 4 samples, at most n/4000 of the record
    let run = (n / 4000).max(4);
    let mut starts: Vec<usize> = (0..n).step_by(run).collect();
    if n - starts[starts.len() - 1] < 3 && starts.len() > 1 {
        starts.pop();
    }
    let mut mom: Vec<Moments> = starts
        .iter()
        .enumerate()
        .map(|(k, &s)| {
            let e = starts.get(k + 1).copied().unwrap_or(n);
            Moments::of(&time[s..e], &lp[s..e])
        })
        .collect();
    // noise variance: median within-run residual variance, floored by the encoder quantum
    let mut within: Vec<f64> = mom.iter().filter(|m| m.n > 2.0).map(|m| m.sse() / (m.n - 2.0)).collect();
    within.sort_by(f64::total_cmp);
    let med = within.get(within.len() / 2).copied().unwrap_or(0.0);
    let quantum = lp.windows(2).map(|w| (w[1] - w[0]).abs()).filter(|d| *d > 0.0).fold(f64::INFINITY, f64::min);
    let q2 = if quantum.is_finite() { quantum * quantum / 12.0 } else { 0.0 };
    let s2 = med.max(q2).max(1e-30);
    let penalty = if opts.penalty > 0.0 { opts.penalty } else { 10.0 * (n as f64).ln() };

    // bottom-up merging over a linked list of runs
    let m = mom.len();
    let mut next: Vec<usize> = (1..=m).collect();
    let mut prev: Vec<usize> = (0..m).map(|i| i.wrapping_sub(1)).collect();
    let mut alive = vec![true; m];
    let mut version = vec![0u32; m];
    let mut heap = BinaryHeap::new();
    // Chow-type test: the SSE increase of a merge against the pooled residual variance of the
    // two runs (never below the global noise), so that bursts of heavy load-point noise are
    // judged by their own variance and quiet stretches by theirs.
    let cost = |a: &Moments, b: &Moments| {
        let pooled = (a.sse() + b.sse()) / (a.n + b.n - 4.0).max(1.0);
        (a.merge(b).sse() - a.sse() - b.sse()) * s2 / pooled.max(s2)
    };
    for i in 0..m.saturating_sub(1) {
        heap.push(Cand { cost: cost(&mom[i], &mom[i + 1]), left: i, stamp: (0, 0) });
    }
    while let Some(c) = heap.pop() {
        let l = c.left;
        let r = next[l];
        if !alive[l] || r >= m || !alive[r] || c.stamp != (version[l], version[r]) {
            continue;
        }
        if c.cost > penalty * s2 {
            break;
        }
        mom[l] = mom[l].merge(&mom[r]);
        alive[r] = false;
        next[l] = next[r];
        if next[l] < m {
            prev[next[l]] = l;
        }
        version[l] += 1;
        if next[l] < m {
            let rr = next[l];
            heap.push(Cand { cost: cost(&mom[l], &mom[rr]), left: l, stamp: (version[l], version[rr]) });
        }
        let p = prev[l];
        if p < m && alive[p] {
            heap.push(Cand { cost: cost(&mom[p], &mom[l]), left: p, stamp: (version[p], version[l]) });
        }
    }
    // surviving runs → (start sample, moments)
    let mut segs: Vec<(usize, Moments)> = Vec::new();
    let mut i = 0;
    while i < m {
        if alive[i] {
            segs.push((starts[i], mom[i]));
        }
        i = if alive[i] { next[i] } else { i + 1 };
    }
    // fuse neighbours of similar velocity (or both at rest) and absorb tiny segments, until stable
    // at rest: a slope within three standard errors of zero, or a travel over the segment below
    // HOLD_TRAVEL_UM (on a clean load point the standard error is round-off) or below the noise
    // the median of σ² χ²_k/k lies below σ² (k = run − 2 degrees of freedom; by 30% for runs of
    // four samples): a hold's slope is judged against its real standard error, with the median
    // divided by that of χ²_k/k (Wilson–Hilferty)
    let dof = (run as f64 - 2.0).max(1.0);
    let s2_hold = s2 / (1.0 - 2.0 / (9.0 * dof)).powi(3);
    let is_hold = |mo: &Moments| {
        let travel = mo.slope().abs() * (12.0 * mo.stt / mo.n.max(1.0)).sqrt();
        let (slope, se) = (mo.slope().abs(), mo.slope_se(s2_hold).max(1e-12));
        // a travel within three noise σ is no measurable motion — unless the slope stands out
        // of its error by far (a slow step of 3e-4 µm/s over 1300 s travels 0.4 µm, 30 errors)
        slope < 3.0 * se || travel < HOLD_TRAVEL_UM || (travel < 3.0 * s2.sqrt() && slope < 10.0 * se)
    };
    let similar = |a: &Moments, b: &Moments| {
        let (ha, hb) = (is_hold(a), is_hold(b));
        if ha || hb {
            return ha && hb;
        }
        let (va, vb) = (a.slope(), b.slope());
        va.signum() == vb.signum() && (va / vb).abs().max((vb / va).abs()) < opts.min_ratio
    };
    consolidate(&mut segs, time, n, opts, &similar);
    // each boundary to the exact break between its neighbours' lines, then once more after the
    // refined boundaries have been consolidated (a merge changes a neighbour's line)
    let mut bounds: Vec<usize> = segs.iter().map(|s| s.0).collect();
    bounds.push(n);
    let margin = 3 * run + opts.min_samples;
    // round-off of a clean load-point record
    let floor2 = (1e-10 * (1.0 + lp.iter().fold(0.0f64, |m, x| m.max(x.abs())))).powi(2);
    refine::absorb_ramps(time, lp, &mut bounds, margin, s2, floor2, &is_hold);
    refine::exact_breaks(time, lp, &mut bounds, margin, &is_hold);
    let mut segs: Vec<(usize, Moments)> =
        bounds.windows(2).map(|w| (w[0], Moments::of(&time[w[0]..w[1]], &lp[w[0]..w[1]]))).collect();
    consolidate(&mut segs, time, n, opts, &similar);
    let mut bounds: Vec<usize> = segs.iter().map(|s| s.0).collect();
    bounds.push(n);
    refine::absorb_ramps(time, lp, &mut bounds, margin, s2, floor2, &is_hold);
    refine::exact_breaks(time, lp, &mut bounds, margin, &is_hold);
    // a segment its own line cannot explain hides a step (split.rs); a stub split off next to a
    // break joins the neighbour it belongs to, and the breaks are refined again
    for _ in 0..4 {
        // the unbiased noise variance: the test compares sums of squares with their expectation
        if !split::split_misfits(time, lp, &mut bounds, s2_hold.max(floor2), penalty, &is_hold) {
            break;
        }
        let seg = |a: usize, b: usize| Moments::of(&time[a..b], &lp[a..b]);
        let mut k = 1;
        while k + 1 < bounds.len() {
            if similar(&seg(bounds[k - 1], bounds[k]), &seg(bounds[k], bounds[k + 1])) {
                bounds.remove(k);
            } else {
                k += 1;
            }
        }
        refine::exact_breaks(time, lp, &mut bounds, margin, &is_hold);
    }
    // on a noisy load point the lines' crossing places a break better than the best split
    refine::crossing_breaks(time, lp, &mut bounds, (s2_hold, floor2), opts.min_samples, &is_hold);
    // final fits and kinds
    let mut out: Vec<Segment> = Vec::new();
    let mut last_moving: Option<f64> = None;
    for k in 0..bounds.len() - 1 {
        let (i0, i1) = (bounds[k], bounds[k + 1] - 1);
        let mo = Moments::of(&time[i0..=i1], &lp[i0..=i1]);
        let hold = is_hold(&mo);
        let v = if hold { 0.0 } else { mo.slope() };
        let kind = if k == 0 {
            SegmentKind::Initial
        } else if hold {
            SegmentKind::Hold
        } else if out.last().is_some_and(|s| s.v == 0.0) {
            SegmentKind::Reslide
        } else if v > last_moving.unwrap_or(v) {
            SegmentKind::StepUp
        } else {
            SegmentKind::StepDown
        };
        if !hold {
            last_moving = Some(v);
        }
        // break time between the previous sample and this one: where the two lines meet
        let t0 = if k == 0 {
            time[i0]
        } else {
            let p = out.last().unwrap();
            let (lp_p, v_p, t_p) = (p.lp0, p.v, p.t0);
            let x0 = mo.mx - v * mo.mt; // this line: x = x0 + v t
            let tb = if (v - v_p).abs() > 0.0 { (x0 - (lp_p - v_p * t_p)) / (v_p - v) } else { time[i0] };
            // the break lies between the last sample of one segment and the first of the next
            // (inclusive: records often sample exactly at the switch)
            if tb.is_finite() { tb.clamp(time[i0 - 1], time[i0]) } else { 0.5 * (time[i0 - 1] + time[i0]) }
        };
        if let Some(p) = out.last_mut() {
            p.t1 = t0;
        }
        let lp0 = mo.mx + v * (t0 - mo.mt);
        out.push(Segment { i0, i1, t0, t1: time[i1], lp0, v, kind });
    }
    out
}

/// A segment as a user gives it (times in s, velocity in µm/s): the override of detection.
#[derive(Clone, Copy, Debug, serde::Deserialize)]
pub struct SegmentSpec {
    /// Start time, s.
    pub t0: f64,
    /// End time, s.
    pub t1: f64,
    /// Load-point velocity, µm/s (0 = hold).
    pub v: f64,
}

/// Segments from user-given times and velocities (e.g. `rsf segments --json` output, edited):
/// each sample belongs to the segment whose [t0, t1) holds it; kinds are recomputed. Errors
/// name the offending segment.
pub fn from_specs(time: &[f64], lp: &[f64], specs: &[SegmentSpec]) -> Result<Vec<Segment>, String> {
    if specs.is_empty() {
        return Err("the segments file lists no segments".into());
    }
    let mut out: Vec<Segment> = Vec::new();
    let mut last_moving: Option<f64> = None;
    for (k, s) in specs.iter().enumerate() {
        if !(s.t1 > s.t0) || !s.v.is_finite() {
            return Err(format!(
                "segment {}: needs t1 > t0 and a finite v (got t0 {}, t1 {}, v {})",
                k + 1,
                s.t0,
                s.t1,
                s.v
            ));
        }
        if let Some(p) = specs.get(k.wrapping_sub(1)).filter(|_| k > 0) {
            if s.t0 < p.t1 - 1e-9 {
                return Err(format!("segment {}: starts at {} s, before segment {} ends ({} s)", k + 1, s.t0, k, p.t1));
            }
        }
        let i0 = time.partition_point(|&t| t < s.t0);
        let last = k + 1 == specs.len();
        let i1 = if last { time.partition_point(|&t| t <= s.t1) } else { time.partition_point(|&t| t < s.t1) };
        if i1 <= i0 {
            return Err(format!("segment {}: no samples between {} and {} s", k + 1, s.t0, s.t1));
        }
        let kind = if k == 0 {
            SegmentKind::Initial
        } else if s.v == 0.0 {
            SegmentKind::Hold
        } else if out.last().is_some_and(|p| p.v == 0.0) {
            SegmentKind::Reslide
        } else if s.v > last_moving.unwrap_or(s.v) {
            SegmentKind::StepUp
        } else {
            SegmentKind::StepDown
        };
        if s.v != 0.0 {
            last_moving = Some(s.v);
        }
        out.push(Segment { i0, i1: i1 - 1, t0: s.t0, t1: s.t1, lp0: lp[i0] - s.v * (time[i0] - s.t0), v: s.v, kind });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic pseudo-noise (no RNG dependency in this unit test).
    fn noise(i: usize) -> f64 {
        let x = ((i as f64 * 12.9898).sin() * 43758.5453).fract();
        x - 0.5
    }

    /// Synthetic record: protocol of (v, duration), sampling interval per segment, noise.
    fn synth(proto: &[(f64, f64, f64)], amp: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let (mut t, mut x, mut breaks) = (vec![0.0], vec![0.0], vec![]);
        let (mut tc, mut xc) = (0.0, 0.0);
        for &(v, d, dt) in proto {
            let n = (d / dt).round() as usize;
            for _ in 0..n {
                tc += dt;
                xc += v * dt;
                t.push(tc);
                x.push(xc);
            }
            breaks.push(tc);
        }
        breaks.pop();
        let xn = x.iter().enumerate().map(|(i, &v)| v + amp * noise(i)).collect();
        (t, xn, breaks)
    }

    #[test]
    fn finds_steps_holds_and_rate_changes() {
        // 3 µm/s, steps down 1 and 2 decades, back up, a hold, a reslide; sampling 10 Hz,
        // 100 Hz around the steps, noise 0.05 µm
        let proto = [
            (3.0, 30.0, 0.1),
            (0.3, 60.0, 0.01),
            (0.03, 300.0, 0.1),
            (3.0, 20.0, 0.01),
            (0.0, 200.0, 0.1),
            (3.0, 20.0, 0.01),
            (3.0, 10.0, 0.1),
        ];
        let (t, x, breaks) = synth(&proto, 0.05);
        let segs = detect(&t, &x, &SegmentOptions::default());
        let kinds: Vec<_> = segs.iter().map(|s| s.kind).collect();
        assert_eq!(
            kinds,
            vec![
                SegmentKind::Initial,
                SegmentKind::StepDown,
                SegmentKind::StepDown,
                SegmentKind::StepUp,
                SegmentKind::Hold,
                SegmentKind::Reslide
            ],
            "{segs:#?}"
        );
        for (k, (s, (b, p))) in segs.iter().skip(1).zip(breaks.iter().zip(&proto[1..])).enumerate() {
            // the break is known to about σ/|Δv| (σ of uniform noise ±0.025 µm: 0.0144 µm)
            let dv = (p.0 - proto[k].0).abs();
            let tol = (3.0 * 0.0144 / dv).max(0.05);
            assert!((s.t0 - b).abs() < tol, "break at {} vs {b} (tolerance {tol})", s.t0);
            assert!((s.v - p.0).abs() <= 0.02 * p.0 + 1e-9, "v {} vs {}", s.v, p.0);
        }
    }

    /// Steps of 0.5 to 3.5 decades from 3 µm/s (down to 0.00095 µm/s), 20 µm each, with an
    /// encoder quantum of 0.08 µm and white noise: every step is found, at the right velocity.
    #[test]
    fn finds_decade_steps_through_encoder_quantisation() {
        let mut proto = vec![(3.0, 10.0, 0.1)];
        for m in [0.5, 1.5, 2.5, 3.5] {
            let vf = 3.0 * 10f64.powf(-m);
            proto.push((vf, 20.0 / vf, if vf < 0.01 { 2.0 } else { 0.1 }));
            proto.push((3.0, 20.0 / 3.0, 0.1));
        }
        let (t, x, _) = synth(&proto, 0.02);
        let xq: Vec<f64> = x.iter().map(|v| (v / 0.08).round() * 0.08).collect();
        let segs = detect(&t, &xq, &SegmentOptions::default());
        assert_eq!(segs.len(), proto.len(), "{segs:#?}");
        for (s, p) in segs.iter().zip(&proto) {
            assert!((s.v / p.0 - 1.0).abs() < 0.03, "v {} vs {}", s.v, p.0);
        }
    }
}
