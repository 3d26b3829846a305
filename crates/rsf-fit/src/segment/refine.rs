//! Exact break refinement: each boundary moves to the sample where the record leaves one
//! segment's line for the next one's, and on a noisy load point to where the two lines cross.
//!
//! Each neighbour's line is fitted on its *body* (the segment without a margin next to the
//! boundary, where the first segmentation may be a few samples off); a hold's line is flat. The
//! break is the split that minimises the squared distance of the samples in between to their
//! own segment's line. On a clean load point this is exact to the sample whatever the sampling
//! rates on either side (a 1 Hz hold next to a 10 Hz reslide), because both lines are exact
//! there; with encoder noise it is the maximum-likelihood split given the two lines.

use super::moments::Moments;

/// A line x = x0 + v (t − t0) through a body of samples.
#[derive(Clone, Copy, Debug)]
struct Line {
    t0: f64,
    x0: f64,
    v: f64,
}

impl Line {
    fn of(m: &Moments, hold: bool) -> Line {
        Line { t0: m.mt, x0: m.mx, v: if hold { 0.0 } else { m.slope() } }
    }
    fn at(&self, t: f64) -> f64 {
        self.x0 + self.v * (t - self.t0)
    }
}

/// Each body line is fitted on at most this many times the margin of samples next to it: near
/// enough to the break that a load point which is not quite piecewise linear (a servo that
/// settles, a drifting encoder) is judged by its local lines, long enough to average encoder
/// noise.
const BODY_PER_MARGIN: usize = 10;

/// The lines of the bodies of segments `s0..s` and `s1..s2` (each without up to `margin`
/// samples next to the other, at most a quarter of it, and no longer than `BODY_PER_MARGIN`
/// margins); `None` when a body is too short.
fn body_lines(
    time: &[f64],
    lp: &[f64],
    (s0, s, s1, s2): (usize, usize, usize, usize),
    margin: usize,
    is_hold: &dyn Fn(&Moments) -> bool,
) -> Option<(Line, Line, usize, usize)> {
    let ma = margin.min((s - s0) / 4);
    let mb = margin.min((s2 - s1) / 4);
    let len = BODY_PER_MARGIN * margin.max(2);
    let (body_a, body_b) = ((s - ma).saturating_sub(len).max(s0)..s - ma, s1 + mb..(s1 + mb + len).min(s2));
    if body_a.len() < 2 || body_b.len() < 2 {
        return None;
    }
    let ma_ = Moments::of(&time[body_a.clone()], &lp[body_a]);
    let mb_ = Moments::of(&time[body_b.clone()], &lp[body_b]);
    Some((Line::of(&ma_, is_hold(&ma_)), Line::of(&mb_, is_hold(&mb_)), s - ma, s1 + mb))
}

/// The split j in lo..=hi minimising the squared distance of samples lo..j to line `a` and of
/// j..hi to line `b`, with that distance. The first minimum wins: a sample lying on both lines
/// (sampled exactly at the switch) opens the later segment, and round-off must not move it.
fn best_split(time: &[f64], lp: &[f64], a: &Line, b: &Line, lo: usize, hi: usize) -> (f64, usize) {
    let ea = |i: usize| (lp[i] - a.at(time[i])).powi(2);
    let eb = |i: usize| (lp[i] - b.at(time[i])).powi(2);
    let mut cost: f64 = (lo..hi).map(eb).sum();
    let mut best = (cost, lo);
    for j in lo..hi {
        cost += ea(j) - eb(j);
        if cost < best.0 - 1e-12 * best.0.abs() - 1e-300 {
            best = (cost, j + 1);
        }
    }
    best
}

/// Removes short transition segments that the two lines around them explain within the noise:
/// a bottom-up run straddling a break (1 Hz hold samples on one side, 100 Hz on the other)
/// survives as a "ramp" of intermediate velocity that no protocol has. `s2` is the load-point
/// noise variance; the floor `floor2` stands for round-off on a clean record.
pub(super) fn absorb_ramps(
    time: &[f64],
    lp: &[f64],
    bounds: &mut Vec<usize>,
    margin: usize,
    s2: f64,
    floor2: f64,
    is_hold: &dyn Fn(&Moments) -> bool,
) {
    let mut k = 1;
    // segment k spans bounds[k]..bounds[k + 1]; it needs a neighbour on each side
    while k + 2 < bounds.len() {
        let (s0, s, s1, s2_) = (bounds[k - 1], bounds[k], bounds[k + 1], bounds[k + 2]);
        let explained = body_lines(time, lp, (s0, s, s1, s2_), margin, is_hold).and_then(|(la, lb, lo, hi)| {
            let (cost, j) = best_split(time, lp, &la, &lb, lo, hi);
            // the samples in question fit the two lines as well as noise allows
            (cost <= (2.0 * (hi - lo) as f64 + 10.0) * s2.max(floor2)).then_some(j)
        });
        match explained {
            Some(j) => {
                bounds[k] = j.clamp(s0 + 1, s2_ - 1);
                bounds.remove(k + 1);
            }
            None => k += 1,
        }
    }
}

/// Moves every inner boundary of `bounds` (sample indices; the last entry is n) to the exact
/// break. `margin` is how far (in samples) a boundary may still be off; `is_hold` classifies a
/// body. Two passes, so a boundary sees its neighbours' refined positions.
pub(super) fn exact_breaks(
    time: &[f64],
    lp: &[f64],
    bounds: &mut [usize],
    margin: usize,
    is_hold: &dyn Fn(&Moments) -> bool,
) {
    for _ in 0..2 {
        for b in 1..bounds.len().saturating_sub(1) {
            let (s0, s, s1) = (bounds[b - 1], bounds[b], bounds[b + 1]);
            let Some((la, lb, lo, hi)) = body_lines(time, lp, (s0, s, s, s1), margin, is_hold) else { continue };
            let best = best_split(time, lp, &la, &lb, lo, hi);
            // a segment keeps at least one sample
            bounds[b] = best.1.clamp(s0 + 1, s1 - 1);
        }
    }
}

/// Moves every inner boundary of `bounds` to the sample interval where its neighbours' lines,
/// each fitted on its whole segment, cross. On a noisy load point the split of `exact_breaks`
/// is only good to the samples within σ_x/|Δv| of the break — one to a few samples, each of which
/// misplaces the friction's transient by k·|Δv|·dt — while two lines fitted on hundreds of
/// samples cross within a small fraction of that. The crossing is taken only within
/// [`CROSSING_SIGMAS`] × σ_x/|Δv| plus one sample interval of the split (the split is good to
/// σ_x/|Δv|, or to a sample where that is shorter; beyond, the lines do not describe the break: a
/// servo settling, a segment too short); a segment keeps `min_samples`. `s2` is the load-point
/// noise variance, `floor2` its round-off: a crossing outside the split's interval by no more
/// than round-off leaves the boundary where it is (a clean record sampled at the switch). Three
/// passes, each line refitted on the samples the last pass gave it.
pub(super) fn crossing_breaks(
    time: &[f64],
    lp: &[f64],
    bounds: &mut [usize],
    (s2, floor2): (f64, f64),
    min_samples: usize,
    is_hold: &dyn Fn(&Moments) -> bool,
) {
    let line = |a: usize, b: usize| {
        let m = Moments::of(&time[a..b], &lp[a..b]);
        Line::of(&m, is_hold(&m))
    };
    let (sx, round_off) = (s2.max(floor2).sqrt(), ROUND_OFF_FACTOR * floor2.sqrt());
    for _ in 0..3 {
        let mut moved = false;
        for b in 1..bounds.len().saturating_sub(1) {
            let (s0, s, s1) = (bounds[b - 1], bounds[b], bounds[b + 1]);
            let (la, lb) = (line(s0, s), line(s, s1));
            let dv = (la.v - lb.v).abs();
            if !(dv > 0.0) {
                continue;
            }
            let tb = time[s] + (lb.at(time[s]) - la.at(time[s])) / (la.v - lb.v);
            let (lo, hi) = (time[s - 1] - round_off / dv, time[s] + round_off / dv);
            if !tb.is_finite() || (lo..=hi).contains(&tb) {
                continue;
            }
            // the split is good to σ_x/|Δv|, and to a sample where that is shorter than one
            let reach = CROSSING_SIGMAS * sx / dv + (time[s] - time[s - 1]);
            if tb < time[s - 1] - reach || tb > time[s] + reach {
                continue;
            }
            // the first sample at or after the crossing opens the later segment
            let j = time.partition_point(|&t| t < tb);
            if j >= s0 + min_samples.max(1) && j + min_samples.max(1) <= s1 && j != s {
                bounds[b] = j;
                moved = true;
            }
        }
        if !moved {
            break;
        }
    }
}

/// A crossing this many load-point noise σ / |Δv| (plus a sample) from the split is still the
/// break's: the split's own uncertainty, three standard deviations wide.
const CROSSING_SIGMAS: f64 = 3.0;

/// Crossings outside the split's interval by less than this many round-off units of the load
/// point (over |Δv|) are round-off: the boundary stays.
const ROUND_OFF_FACTOR: f64 = 1e3;
