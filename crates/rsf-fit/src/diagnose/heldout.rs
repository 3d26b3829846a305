//! The held-out test: fit on the first part of the record, predict the rest.

use crate::data::Record;
use crate::fit::{FitOptions, FitResult, Prepared, model_curve, parameter_map, prepare};
use crate::segment::Segment;

/// The training part of a held-out test: the record before `t_split` and its segments (those
/// that start in it, cut at the split).
pub(super) fn training(rec: &Record, segs: &[Segment], t_split: f64) -> (Record, Vec<Segment>) {
    let train = rec.window(rec.time[0], t_split);
    let n = train.len();
    let tsegs = segs
        .iter()
        .filter(|s| s.t0 < t_split && s.i0 < n)
        .map(|s| {
            let mut s = s.clone();
            s.i1 = s.i1.min(n.saturating_sub(1));
            s.t1 = s.t1.min(t_split);
            s
        })
        .collect();
    (train, tsegs)
}

/// Held-out test of the model `opts`: fitted on the record before `t_split`, it predicts the
/// rest; returns the rms of the prediction and the training fit (`train_fit` fits the prepared
/// training part). The baseline's training fit starts cold; an extension's starts from the
/// baseline's *training* optimum with its own parameters at their neutral values, as on the full
/// record — never from an optimum that has seen the held-out part.
pub(super) fn heldout(
    rec: &Record,
    segs: &[Segment],
    opts: &FitOptions,
    train_fit: &dyn Fn(&Prepared, &FitOptions) -> Option<FitResult>,
    t_split: f64,
) -> Option<(f64, FitResult)> {
    let (train, tsegs) = training(rec, segs, t_split);
    let o = FitOptions { mu0_per_segment: false, ..opts.clone() };
    let pt = prepare(&train, &tsegs, &o).ok()?;
    let ft = train_fit(&pt, &o)?;
    let pf = prepare(rec, segs, &o).ok()?;
    let map_t = parameter_map(&pt, &o).ok()?;
    let map_f = parameter_map(&pf, &o).ok()?;
    if map_t.free_names() != map_f.free_names() {
        return None;
    }
    let mu = model_curve(&pf, &map_f, &o, &ft.theta, o.rtol).ok()?;
    let (mut ss, mut n) = (0.0, 0usize);
    for (k, &i) in pf.used.iter().enumerate() {
        if pf.record.time[i] > t_split {
            ss += (mu[k] - pf.record.mu[i]).powi(2);
            n += 1;
        }
    }
    (n > 0).then(|| ((ss / n as f64).sqrt(), ft))
}

/// Where to split for the held-out test: the start of the segment nearest 2/3 of the record
/// (within 40–85% of it) such that the training part holds at least one velocity change; with
/// no such segment (a record of one step or one hold), the later of 2/3 of the record and half
/// way from the first change to the end, so that the training part sees the change and the
/// start of the response.
pub(super) fn split_time(rec: &Record, segs: &[Segment]) -> f64 {
    let (t0, t1) = (rec.time[0], rec.time[rec.len() - 1]);
    let target = t0 + (t1 - t0) * 2.0 / 3.0;
    // the first sliding segment after a change
    let first_event = segs.iter().skip(1).find(|s| s.v > 0.0).map(|s| s.t0);
    segs.iter()
        .skip(2)
        .map(|s| s.t0)
        .filter(|&t| first_event.is_some_and(|e| e < t))
        .filter(|t| (t - t0) > 0.4 * (t1 - t0) && (t - t0) < 0.85 * (t1 - t0))
        .min_by(|a, b| (a - target).abs().total_cmp(&(b - target).abs()))
        .unwrap_or_else(|| first_event.map_or(target, |e| target.max(e + 0.5 * (t1 - e))))
}
