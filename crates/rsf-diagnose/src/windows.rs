//! Event windows in log-time bins: a window's bin means of the residuals, the break shifts it
//! is judged under, its spread Q about its mean (the event test's statistic, `adequacy.rs`) and
//! its profile (the coherence test's, `coherence.rs`). A transient decays in log time, so the
//! bins grow by half a decade from a thousandth of the window.

/// Bins of a window: the first from its start to 10⁻³ of its length, then one per half decade
/// (10^−2.5 = 3.16e-3, …).
pub(super) const BIN_EDGES: [f64; 8] =
    [0.0, 1e-3, 3.162_277_660_168_379_5e-3, 1e-2, 3.162_277_660_168_379_5e-2, 1e-1, 3.162_277_660_168_379_5e-1, 1.0];
/// Bins of a window.
pub(super) const BINS: usize = BIN_EDGES.len() - 1;
/// A window whose samples fill fewer than this many bins is left out (its shape unseen).
const MIN_BINS: usize = 3;
/// Break shifts tried on each side of zero, evenly over the break-time uncertainty
/// ([`break_shifts`]): a tenth of it apart, so the best one misplaces the break by at most a
/// twentieth of the uncertainty.
const BREAK_SHIFT_STEPS: i32 = 10;
/// A break uncertain by less than this fraction of its window is not shifted: a thousandth of
/// the window's first bin, where the break's timing matters most.
const NEGLIGIBLE_SHIFT: f64 = 1e-6;
/// A window of fewer samples is left out: sampled at a tenth of its length or coarser, its
/// transient's first part — where the event's timing matters most and the model changes
/// fastest — rests on one or two samples, whose misfit to a break read a fraction of a sample
/// late is far from linear in the shift and is not taken out with it. (A step to 300 µm/s
/// logged at 10 Hz, a window of 0.43 s, and a step to 3 µm/s logged at 1 Hz, 5.9 s: each
/// made a record whose model is its truth look inadequate.)
pub const MIN_WINDOW_SAMPLES: usize = 10;

/// A window's bins: (bin index, mean residual, mean shape) of each bin its samples fill.
pub(super) type Bins = Vec<(usize, f64, f64)>;

/// The window [t0, t0 + len)'s samples averaged in bins of time since t0: the residuals, and
/// `shape` (the event's own nuisance, the model's rate of change after the event as (time since
/// the event, rate) pairs: a shift of the event's time) at the same times. `None` for a window
/// of fewer than [`MIN_WINDOW_SAMPLES`] or [`MIN_BINS`] filled bins.
pub(super) fn window_bins(time: &[f64], res: &[f64], shape: &[(f64, f64)], t0: f64, len: f64) -> Option<Bins> {
    let i0 = time.partition_point(|&t| t < t0);
    let i1 = time.partition_point(|&t| t < t0 + len);
    let used = i0..i1;
    if used.len() < MIN_WINDOW_SAMPLES {
        return None;
    }
    // bin sums of the residuals and of the shape
    let mut sums = [(0.0f64, 0.0f64, 0usize); BINS];
    for i in used {
        let b = bin_of((time[i] - t0) / len);
        sums[b].0 += res[i];
        sums[b].1 += interpolate(shape, time[i] - t0);
        sums[b].2 += 1;
    }
    let bins: Bins = sums
        .iter()
        .enumerate()
        .filter(|(_, s)| s.2 > 0)
        .map(|(b, s)| (b, s.0 / s.2 as f64, s.1 / s.2 as f64))
        .collect();
    (bins.len() >= MIN_BINS).then_some(bins)
}

/// The bin of a sample at `u` (time since the window's start over its length).
fn bin_of(u: f64) -> usize {
    BIN_EDGES[1..].partition_point(|&e| e <= u).min(BINS - 1)
}

/// Q of a window's bins with `offset` added to its bin means: their spread about their mean,
/// after the part along the shape's bin means is taken out (a linear shift of the event's
/// time, so the spread can only shrink, in an event window and in its placebos alike).
fn spread(bins: &Bins, offset: &[f64; BINS]) -> f64 {
    let n = bins.len() as f64;
    let r = |&(b, r, _): &(usize, f64, f64)| r + offset[b];
    let (mr, mg) = (bins.iter().map(r).sum::<f64>() / n, bins.iter().map(|m| m.2).sum::<f64>() / n);
    let (rg, gg) = bins.iter().fold((0.0, 0.0), |(rg, gg), m| (rg + (r(m) - mr) * (m.2 - mg), gg + (m.2 - mg).powi(2)));
    let shift = if gg > 0.0 { rg / gg } else { 0.0 };
    bins.iter().map(|m| (r(m) - mr - shift * (m.2 - mg)).powi(2)).sum::<f64>() / n
}

/// A window's profile for the coherence test (`coherence.rs`): its bin means after the best
/// of the break shifts `shifts`, with the part along a constant, `time_fraction` (each bin's
/// mean time since the window's start over its length: a drift's slope) and, in a window of
/// five bins or more, the shape's bin means taken out by least squares; the shift whose
/// profile is smallest is the one taken.
/// Zeros in the bins the window does not fill; `None` when nothing is left.
pub(super) fn least_shift_profile(
    bins: &Bins,
    shifts: &[[f64; BINS]],
    time_fraction: &[f64; BINS],
) -> Option<[f64; BINS]> {
    let n = bins.len() as f64;
    // the nuisance columns over the filled bins, centred (the constant) and made orthonormal
    let centred = |v: Vec<f64>| {
        let m = v.iter().sum::<f64>() / n;
        v.into_iter().map(|x| x - m).collect::<Vec<f64>>()
    };
    let mut basis: Vec<Vec<f64>> = vec![];
    // the slope first; the shape only where two bins' worth of shape would still be left
    let mut columns = vec![bins.iter().map(|m| time_fraction[m.0]).collect::<Vec<f64>>()];
    if bins.len() >= PROFILE_SHAPE_BINS {
        columns.push(bins.iter().map(|m| m.2).collect());
    }
    for column in columns {
        let mut c = centred(column);
        let scale = c.iter().map(|x| x * x).sum::<f64>().sqrt();
        for q in &basis {
            let dot: f64 = c.iter().zip(q).map(|(a, b)| a * b).sum();
            c.iter_mut().zip(q).for_each(|(a, b)| *a -= dot * b);
        }
        let norm = c.iter().map(|x| x * x).sum::<f64>().sqrt();
        // a column that adds nothing new (an empty shape, or one along the slope) is dropped
        if norm > 1e-9 * scale && norm > 0.0 {
            basis.push(c.into_iter().map(|x| x / norm).collect());
        }
    }
    let mut best: Option<(f64, Vec<f64>)> = None;
    for o in shifts {
        let mut y = centred(bins.iter().map(|&(b, r, _)| r + o[b]).collect());
        for q in &basis {
            let dot: f64 = y.iter().zip(q).map(|(a, b)| a * b).sum();
            y.iter_mut().zip(q).for_each(|(a, b)| *a -= dot * b);
        }
        let ss: f64 = y.iter().map(|x| x * x).sum();
        if best.as_ref().is_none_or(|b| ss < b.0) {
            best = Some((ss, y));
        }
    }
    let (ss, y) = best?;
    (ss > 0.0).then(|| {
        let mut out = [0.0; BINS];
        for (m, v) in bins.iter().zip(y) {
            out[m.0] = v;
        }
        out
    })
}

/// Each bin's mean time since `t0` over `len` across the window's samples (0 where empty).
pub(super) fn bin_time_fractions(time: &[f64], t0: f64, len: f64) -> [f64; BINS] {
    let i0 = time.partition_point(|&t| t < t0);
    let i1 = time.partition_point(|&t| t < t0 + len);
    let mut sums = [(0.0f64, 0usize); BINS];
    for &t in &time[i0..i1] {
        let u = (t - t0) / len;
        let b = bin_of(u);
        sums[b].0 += u;
        sums[b].1 += 1;
    }
    sums.map(|(s, k)| if k > 0 { s / k as f64 } else { 0.0 })
}

/// A profile takes the model's own rate out too only in a window of at least this many filled
/// bins: with the mean, the slope and the rate out, two bins' worth of shape remain.
const PROFILE_SHAPE_BINS: usize = 5;

/// One window's Q with no break shift (the linear one only).
#[cfg(test)]
fn window_q(time: &[f64], res: &[f64], shape: &[(f64, f64)], t0: f64, len: f64) -> Option<f64> {
    window_bins(time, res, shape, t0, len).map(|b| spread(&b, &[0.0; BINS]))
}

/// The least Q over the break shifts: each shift's bin-mean change of the model added in turn.
pub(super) fn least_q(bins: &Bins, shifts: &[[f64; BINS]]) -> f64 {
    shifts.iter().map(|o| spread(bins, o)).fold(f64::INFINITY, f64::min)
}

/// The break shifts an event window and its placebos are judged under: for each shift δ in
/// [−d, d] (`d` the event's break-time uncertainty, s), the bin means over the event window's
/// samples of m(t) − m(t − δ), the change of the model were the break δ later (the data then
/// follow m(t − δ), and their residual about it is the residual about m plus that change). A
/// break misread by a few samples misplaces a fast transient by far more than the linear shift
/// takes out (a reslide's rise, sampled at 100 Hz and read 0.035 s off by an encoder noise of
/// 0.19 µm at 10 µm/s, left an event-locked misfit of 3× the noise in a model that was the
/// truth). Zero shift is always among them.
pub(super) fn break_shifts(time: &[f64], model: &[f64], t0: f64, len: f64, d: f64) -> Vec<[f64; BINS]> {
    let mut out = vec![[0.0; BINS]];
    // a clean load point (σ_x round-off) leaves no shift worth trying
    if !(d > NEGLIGIBLE_SHIFT * len && d.is_finite()) {
        return out;
    }
    let i0 = time.partition_point(|&t| t < t0);
    let i1 = time.partition_point(|&t| t < t0 + len);
    // the model around the window (from d before it), as (time, value) pairs to interpolate
    let j0 = time.partition_point(|&t| t < t0 - d).saturating_sub(1);
    let curve: Vec<(f64, f64)> = (j0..i1).map(|i| (time[i], model[i])).collect();
    for k in (-BREAK_SHIFT_STEPS..=BREAK_SHIFT_STEPS).filter(|&k| k != 0) {
        let delta = d * k as f64 / BREAK_SHIFT_STEPS as f64;
        let mut sums = [(0.0f64, 0usize); BINS];
        for i in i0..i1 {
            let b = bin_of((time[i] - t0) / len);
            sums[b].0 += model[i] - interpolate(&curve, time[i] - delta);
            sums[b].1 += 1;
        }
        let mut o = [0.0; BINS];
        for (b, s) in sums.iter().enumerate().filter(|(_, s)| s.1 > 0) {
            o[b] = s.0 / s.1 as f64;
        }
        out.push(o);
    }
    out
}

/// `shape` (sorted by its first member) at `x`, linearly interpolated, held at its ends.
fn interpolate(shape: &[(f64, f64)], x: f64) -> f64 {
    let k = shape.partition_point(|p| p.0 < x);
    match (k.checked_sub(1).and_then(|j| shape.get(j)), shape.get(k)) {
        (Some(&(xa, ya)), Some(&(xb, yb))) if xb > xa => ya + (yb - ya) * (x - xa) / (xb - xa),
        (_, Some(&(_, y))) | (Some(&(_, y)), None) => y,
        (None, None) => 0.0,
    }
}

/// The model's rate after the event at `t0`, over `len` s: (time since `t0`, rate) pairs.
pub(super) fn event_shape(time: &[f64], rate: &[f64], t0: f64, len: f64) -> Vec<(f64, f64)> {
    let i0 = time.partition_point(|&t| t < t0);
    let i1 = time.partition_point(|&t| t < t0 + len);
    (i0..i1).map(|i| (time[i] - t0, rate[i])).collect()
}

/// The model's rate of change at each sample, friction/s (central differences; one-sided at
/// the ends).
pub(super) fn model_rate(time: &[f64], model: &[f64]) -> Vec<f64> {
    let n = time.len();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n.saturating_sub(1)));
            let dt = time[b] - time[a];
            if dt > 0.0 { (model[b] - model[a]) / dt } else { 0.0 }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A window's profile for the coherence test keeps a transient's shape but loses its mean
    /// and a drift's slope across it.
    #[test]
    fn a_profile_keeps_a_shape_and_loses_offset_and_slope() {
        let time: Vec<f64> = (0..4000).map(|i| i as f64 * 0.05).collect();
        let frac = bin_time_fractions(&time, 0.0, 200.0);
        let bins_of = |res: &[f64]| window_bins(&time, res, &[], 0.0, 200.0).unwrap();
        // an offset plus a drift's slope: nothing left
        let drift: Vec<f64> = time.iter().map(|t| 2e-4 + 1e-6 * t).collect();
        let p = least_shift_profile(&bins_of(&drift), &[[0.0; BINS]], &frac);
        assert!(p.is_none_or(|p| p.iter().all(|x| x.abs() < 1e-12)), "{p:?}");
        // a decaying transient: its early bins stand out, of the transient's sign
        let transient: Vec<f64> = time.iter().map(|t| 1e-3 * (-t / 2.0).exp()).collect();
        let p = least_shift_profile(&bins_of(&transient), &[[0.0; BINS]], &frac).unwrap();
        let rms = (p.iter().map(|x| x * x).sum::<f64>() / BINS as f64).sqrt();
        assert!(rms > 1e-5, "{p:?}");
        assert!(p.iter().all(|x| *x <= p[0]) && p[0] > 0.0, "{p:?}");
    }

    /// Bins: a window's samples fall in the bins of their time since its start.
    #[test]
    fn a_step_shaped_residual_has_spread_and_a_flat_one_none() {
        let time: Vec<f64> = (0..1000).map(|i| i as f64 * 0.1).collect();
        let flat = vec![1e-3; 1000];
        let still = vec![];
        assert!(window_q(&time, &flat, &still, 0.0, 100.0).unwrap() < 1e-30);
        let decaying: Vec<f64> = time.iter().map(|t| 1e-3 * (-t / 2.0).exp()).collect();
        let q = window_q(&time, &decaying, &still, 0.0, 100.0).unwrap();
        assert!(q > 1e-8, "{q}");
        // too few bins filled: a window of three samples
        assert_eq!(window_q(&time, &flat, &still, 0.0, 0.25), None);
    }

    /// A residual that is the model's transient shifted in time (a break time read late) is
    /// taken out; a misfit of another shape is not.
    #[test]
    fn a_shifted_break_is_not_a_misfit() {
        let time: Vec<f64> = (0..2000).map(|i| i as f64 * 0.01).collect();
        let model: Vec<f64> = time.iter().map(|t| 0.6 + 0.01 * (-t / 0.5).exp()).collect();
        let late: Vec<f64> = time.iter().map(|t| 0.6 + 0.01 * (-(t - 0.003) / 0.5).exp()).collect();
        let rate = model_rate(&time, &model);
        let res: Vec<f64> = late.iter().zip(&model).map(|(d, m)| d - m).collect();
        let shape = event_shape(&time, &rate, 0.0, 20.0);
        let raw = window_q(&time, &res, &[], 0.0, 20.0).unwrap();
        let shifted = window_q(&time, &res, &shape, 0.0, 20.0).unwrap();
        assert!(shifted < 1e-4 * raw, "{shifted:e} vs {raw:e}");
        let other: Vec<f64> = time.iter().map(|t| 1e-4 * (t / 20.0)).collect();
        let q = window_q(&time, &other, &shape, 0.0, 20.0).unwrap();
        assert!(q > 1e-11, "{q:e}");
    }

    /// A reslide read 0.035 s late (a kink: the spring starts loading) leaves a misfit the
    /// linear shift cannot take out; the best break shift within a 0.057 s uncertainty does.
    /// A break 0.2 s late, beyond the uncertainty, and a misfit of another shape stay.
    #[test]
    fn a_break_misread_within_its_uncertainty_is_not_a_misfit() {
        let time: Vec<f64> = (0..1000).map(|i| -1.0 + i as f64 * 0.01).collect();
        let reslide = |t: f64| if t < 0.0 { 0.6 } else { 0.6 + 0.03 * (1.0 - (-t / 0.5).exp()) };
        let model: Vec<f64> = time.iter().map(|&t| reslide(t)).collect();
        let rate = model_rate(&time, &model);
        let shape = event_shape(&time, &rate, 0.0, 8.0);
        let misfit = |late: f64| -> Vec<f64> { time.iter().zip(&model).map(|(&t, m)| reslide(t - late) - m).collect() };
        let q = |res: &[f64], d: f64| {
            let bins = window_bins(&time, res, &shape, 0.0, 8.0).unwrap();
            least_q(&bins, &break_shifts(&time, &model, 0.0, 8.0, d))
        };
        let res = misfit(0.035);
        let linear = q(&res, 0.0);
        assert!(linear > 1e-9, "{linear:e}");
        assert!(q(&res, 0.057) < 1e-3 * linear, "{:e} vs {linear:e}", q(&res, 0.057));
        let far = misfit(0.2);
        assert!(q(&far, 0.057) > 0.1 * q(&far, 0.0), "{:e}", q(&far, 0.057));
        let other: Vec<f64> = time.iter().map(|&t| if t > 0.0 { 3e-4 * (-t / 2.0).exp() } else { 0.0 }).collect();
        assert!(q(&other, 0.057) > 0.5 * q(&other, 0.0), "{:e} vs {:e}", q(&other, 0.057), q(&other, 0.0));
    }
}
