//! Consolidation of a bottom-up segmentation: similar neighbours fused, blips and tiny
//! segments absorbed.

use super::SegmentOptions;
use super::moments::Moments;

/// Fuses neighbours of similar velocity, removes blips and absorbs tiny segments until stable.
pub(super) fn consolidate(
    segs: &mut Vec<(usize, Moments)>,
    time: &[f64],
    n: usize,
    opts: &SegmentOptions,
    similar: &dyn Fn(&Moments, &Moments) -> bool,
) {
    let dur = |k: usize, segs: &[(usize, Moments)]| {
        let e = segs.get(k + 1).map(|s| s.0).unwrap_or(n) - 1;
        time[e] - time[segs[k].0]
    };
    loop {
        let mut changed = false;
        // neighbours of similar velocity
        let mut k = 0;
        while k + 1 < segs.len() {
            if similar(&segs[k].1, &segs[k + 1].1) {
                segs[k].1 = segs[k].1.merge(&segs[k + 1].1);
                segs.remove(k + 1);
                changed = true;
            } else {
                k += 1;
            }
        }
        // blips: a short segment between two similar ones (load-point stalls, servo bursts)
        let mut k = 1;
        while k + 1 < segs.len() {
            let short = dur(k, segs) < 0.1 * dur(k - 1, segs).min(dur(k + 1, segs));
            // …and its displacement anomaly is small next to its neighbours' travel (a stall
            // or a burst of noise is; a reslide between two holds is not)
            let v_nb = 0.5 * (segs[k - 1].1.slope() + segs[k + 1].1.slope());
            let anomaly = ((segs[k].1.slope() - v_nb) * dur(k, segs)).abs();
            let travel = v_nb.abs() * (dur(k - 1, segs) + dur(k + 1, segs));
            if short && similar(&segs[k - 1].1, &segs[k + 1].1) && anomaly < 0.1 * travel {
                let merged = segs[k - 1].1.merge(&segs[k].1).merge(&segs[k + 1].1);
                segs[k - 1].1 = merged;
                segs.drain(k..k + 2);
                changed = true;
            } else {
                k += 1;
            }
        }
        // tiny segments (few samples, shorter than min_duration, or a transition much shorter
        // than both neighbours) join the neighbour of closer velocity, shortest first
        loop {
            if segs.len() < 2 {
                break;
            }
            let tiny = |k: usize| {
                let few = (segs[k].1.n as usize) < opts.min_samples || dur(k, segs) < opts.min_duration;
                let inner = k > 0 && k + 1 < segs.len();
                let shortest_nb = if inner { dur(k - 1, segs).min(dur(k + 1, segs)) } else { 0.0 };
                let (vp, v, vn) = if inner {
                    (segs[k - 1].1.slope(), segs[k].1.slope(), segs[k + 1].1.slope())
                } else {
                    (0.0, 0.0, 0.0)
                };
                // a short transition (servo ramp) with a velocity between its neighbours'
                let ramp = inner && (v - vp) * (vn - v) > 0.0 && dur(k, segs) < 0.02 * shortest_nb;
                let transient = inner
                    && ((segs[k].1.n as usize) < 4 * opts.min_samples && dur(k, segs) < 0.2 * shortest_nb || ramp);
                few || transient
            };
            let Some(k) = (0..segs.len()).filter(|&k| tiny(k)).min_by(|&a, &b| dur(a, segs).total_cmp(&dur(b, segs)))
            else {
                break;
            };
            let v = segs[k].1.slope();
            let dist = |j: usize| {
                let w = segs[j].1.slope();
                if v > 0.0 && w > 0.0 { (v / w).ln().abs() } else { (v - w).abs() / v.abs().max(w.abs()).max(1e-12) }
            };
            let left = if k == 0 {
                false
            } else if k + 1 == segs.len() {
                true
            } else {
                dist(k - 1) <= dist(k + 1)
            };
            if left {
                segs[k - 1].1 = segs[k - 1].1.merge(&segs[k].1);
                segs.remove(k);
            } else {
                segs[k + 1].1 = segs[k].1.merge(&segs[k + 1].1);
                segs[k + 1].0 = segs[k].0;
                segs.remove(k);
            }
            changed = true;
        }
        if !changed {
            break;
        }
    }
}
