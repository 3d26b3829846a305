//! The last check of a segmentation: a segment whose line leaves the noise is split.
//!
//! Bottom-up merging starts from runs of several samples and consolidation absorbs segments
//! shorter than `min_duration`, so a short fast step of a few samples (a 300 µm/s step of 8
//! samples in a gouge staircase) can end up inside its neighbour. Such a segment is grossly
//! inconsistent with its own line. The split test is the merge rule run backwards: binary
//! segmentation splits while a split lowers the residual sum of squares by more than the merge
//! penalty (in units of the noise variance) — such pieces would never have been merged — and
//! the pieces are kept only when their lines then explain the segment within the noise and each
//! is a hold next to motion or moves at a velocity at least `STEP_RATIO` from its neighbours'.
//! That keeps the test to protocol changes: a servo's overshoot is not a few lines, and the
//! curvature of a drifting or settling load point splits into pieces of similar velocity. (A
//! 10-sample hold between two minutes of sliding is absorbed by consolidation as a transient; it
//! comes back here.)

use super::moments::Moments;

/// Two pieces are a protocol step only if their velocities differ by this factor or more (0.3
/// decades; lab steps are 0.5–3.5 decades): a slowly curving load point is not split.
const STEP_RATIO: f64 = 2.0;

/// Each piece of a split keeps at least this many samples: a line through three samples still
/// has a residual, and shorter stubs are put right by the exact break refinement that follows.
const MIN_PIECE: usize = 3;

/// Splits every segment of `bounds` (sample indices; the last entry is n) whose line misfits by
/// more than `penalty · s2` into moving lines of clearly different velocity that explain it
/// within the noise. A stub of fewer than `MIN_PIECE` samples at either end of a segment (a
/// break a sample or two off) is handed to the neighbour instead. Returns whether anything
/// changed.
pub(super) fn split_misfits(
    time: &[f64],
    lp: &[f64],
    bounds: &mut Vec<usize>,
    s2: f64,
    penalty: f64,
    is_hold: &dyn Fn(&Moments) -> bool,
) -> bool {
    let n_all = time.len();
    let mut out = vec![bounds[0]];
    // whether the last boundary in `out` was moved back by an end stub
    let mut moved_end = false;
    for w in bounds.windows(2) {
        let (i0, i1) = (w[0], w[1]);
        let (t, x) = (&time[i0..i1], &lp[i0..i1]);
        let mut cuts = vec![];
        binary_splits(t, x, (s2, penalty), MAX_DEPTH, (0, true, true), &mut cuts);
        tidy(t, x, &mut cuts, is_hold);
        let mut end = i1;
        if !cuts.is_empty() && explains(t, x, &cuts, (s2, penalty), is_hold) {
            for &c in &cuts {
                let at = i0 + c;
                if c < MIN_PIECE {
                    // a stub at the start belongs to the segment before (none before the first),
                    // unless that one handed over a stub too: together they are a short step
                    if moved_end {
                        out.push(at);
                    } else if out.len() > 1 {
                        *out.last_mut().unwrap() = at;
                    }
                } else if i1 - at < MIN_PIECE {
                    // …and one at the end to the segment after
                    if i1 < n_all {
                        end = at;
                    }
                } else {
                    out.push(at);
                }
            }
        }
        moved_end = end != i1;
        out.push(end);
    }
    let changed = out != *bounds;
    *bounds = out;
    changed
}

/// Binary segmentation goes at most this deep (up to 8 pieces): enough for a short step with a
/// few samples of each neighbour on either side.
const MAX_DEPTH: usize = 3;

/// Recursive best two-line splits of `t, x` while a split lowers the misfit by more than
/// `penalty · s2`; the cuts (relative to `t`, plus `offset`) in increasing order. `at_start` and
/// `at_end` say whether the slice touches the segment's ends, where stubs may be cut off.
fn binary_splits(
    t: &[f64],
    x: &[f64],
    (s2, penalty): (f64, f64),
    depth: usize,
    (offset, at_start, at_end): (usize, bool, bool),
    cuts: &mut Vec<usize>,
) {
    let n = t.len();
    if depth == 0 || n < 4 {
        return;
    }
    // a piece its line explains within the noise is not split further
    let whole = Moments::of(t, x).sse();
    if whole <= ((n - 2) as f64 + penalty) * s2 {
        return;
    }
    let min = |end: bool| if end { 1 } else { MIN_PIECE };
    let Some((sse, j)) = best_split(t, x, (min(at_start), min(at_end))) else { return };
    if whole - sse <= penalty * s2 {
        return;
    }
    binary_splits(&t[..j], &x[..j], (s2, penalty), depth - 1, (offset, at_start, false), cuts);
    cuts.push(offset + j);
    binary_splits(&t[j..], &x[j..], (s2, penalty), depth - 1, (offset + j, false, at_end), cuts);
}

/// The split of `t, x` into two least-squares lines (of at least `min.0` and `min.1` samples)
/// with the least total misfit: (misfit, index of the first sample of the right piece).
fn best_split(t: &[f64], x: &[f64], min: (usize, usize)) -> Option<(f64, usize)> {
    let n = t.len();
    // suffix moments, then one sweep of prefix moments: O(n)
    let mut suffix = vec![Moments::default(); n + 1];
    for i in (0..n).rev() {
        suffix[i] = Moments::of(&t[i..=i], &x[i..=i]).merge(&suffix[i + 1]);
    }
    let mut prefix = Moments::default();
    let mut best: Option<(f64, usize)> = None;
    for j in 1..n {
        prefix = prefix.merge(&Moments::of(&t[j - 1..j], &x[j - 1..j]));
        if j < min.0 || n - j < min.1 {
            continue;
        }
        let sse = prefix.sse() + suffix[j].sse();
        if best.is_none_or(|b| sse < b.0) {
            best = Some((sse, j));
        }
    }
    best
}

/// Whether two pieces are different protocol segments: a hold next to a moving piece, or two
/// moving pieces whose velocities differ by `STEP_RATIO` or more (in the same direction).
fn distinct(a: &Moments, b: &Moments, is_hold: &dyn Fn(&Moments) -> bool) -> bool {
    match (is_hold(a), is_hold(b)) {
        (true, true) => false,
        (true, false) | (false, true) => true,
        (false, false) => {
            let (va, vb) = (a.slope(), b.slope());
            va.signum() == vb.signum() && (va / vb).abs().max((vb / va).abs()) >= STEP_RATIO
        }
    }
}

/// The pieces between `cuts` (stubs at the ends not counted).
fn pieces(t: &[f64], x: &[f64], cuts: &[usize]) -> Vec<(usize, Moments)> {
    let mut edges = vec![0];
    edges.extend_from_slice(cuts);
    edges.push(t.len());
    edges.windows(2).map(|w| (w[1] - w[0], Moments::of(&t[w[0]..w[1]], &x[w[0]..w[1]]))).collect()
}

/// Binary segmentation places its later cuts relative to its first, which need not be a true
/// break (a short step between two slow stretches is first cut inside): inner pieces of similar
/// velocity are joined again and each remaining inner cut moved to the best split between its
/// neighbours, twice.
fn tidy(t: &[f64], x: &[f64], cuts: &mut Vec<usize>, is_hold: &dyn Fn(&Moments) -> bool) {
    let stub = |c: usize| c < MIN_PIECE || t.len() - c < MIN_PIECE;
    for _ in 0..2 {
        let mut k = 0;
        while k < cuts.len() {
            let lo = if k == 0 { 0 } else { cuts[k - 1] };
            let hi = cuts.get(k + 1).copied().unwrap_or(t.len());
            // a stub at an end is never joined: it goes to the neighbouring segment
            let same = !stub(cuts[k])
                && !distinct(
                    &Moments::of(&t[lo..cuts[k]], &x[lo..cuts[k]]),
                    &Moments::of(&t[cuts[k]..hi], &x[cuts[k]..hi]),
                    is_hold,
                );
            if same {
                cuts.remove(k);
            } else {
                k += 1;
            }
        }
        for k in 0..cuts.len() {
            if stub(cuts[k]) {
                continue;
            }
            let lo = if k == 0 { 0 } else { cuts[k - 1] };
            let hi = cuts.get(k + 1).copied().unwrap_or(t.len());
            if let Some((_, j)) = best_split(&t[lo..hi], &x[lo..hi], (MIN_PIECE, MIN_PIECE)) {
                cuts[k] = lo + j;
            }
        }
    }
}

/// Whether the pieces between `cuts` are a protocol: together their lines leave only noise (a
/// servo's overshoot or a settling load point is not a few lines, and is left to the body-line
/// refinement), and every piece but the end stubs differs from its neighbours (`distinct`).
fn explains(
    t: &[f64],
    x: &[f64],
    cuts: &[usize],
    (s2, penalty): (f64, f64),
    is_hold: &dyn Fn(&Moments) -> bool,
) -> bool {
    let all = pieces(t, x, cuts);
    let sse: f64 = all.iter().map(|p| p.1.sse()).sum();
    let dof = t.len() as f64 - 2.0 * all.len() as f64;
    let body: Vec<&Moments> = all.iter().filter(|p| p.0 >= MIN_PIECE).map(|p| &p.1).collect();
    sse <= (dof.max(0.0) + penalty) * s2 && body.windows(2).all(|w| distinct(w[0], w[1], is_hold))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn never_hold(_: &Moments) -> bool {
        false
    }

    #[test]
    fn a_short_fast_step_inside_a_slow_one_is_split_out() {
        // 100 µm/s for 20 samples, then 300 µm/s for 8, sampled at 20 Hz, no noise
        let t: Vec<f64> = (0..28).map(|i| i as f64 * 0.05).collect();
        let x: Vec<f64> =
            t.iter().map(|&ti| if ti <= 0.95 + 1e-9 { 100.0 * ti } else { 95.0 + 300.0 * (ti - 0.95) }).collect();
        let mut b = vec![0, 28];
        assert!(split_misfits(&t, &x, &mut b, 0.01, 100.0, &never_hold));
        assert_eq!(b, vec![0, 20, 28]);
    }

    #[test]
    fn a_curving_load_point_is_not_split() {
        // a servo settling: velocity falls smoothly by 30 % over the segment
        let t: Vec<f64> = (0..400).map(|i| i as f64 * 0.05).collect();
        let x: Vec<f64> = t.iter().map(|&ti| 10.0 * ti - 0.15 * ti * ti / 2.0 * 10.0 / 20.0).collect();
        let mut b = vec![0, 400];
        assert!(!split_misfits(&t, &x, &mut b, 1e-6, 60.0, &never_hold));
        assert_eq!(b, vec![0, 400]);
    }
}
