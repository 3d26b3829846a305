//! The diagnosis's baseline: its cold fit, continued past a late run-away, and the protocol
//! reconstruction check under protocol loading.

use super::heldout::training;
use super::reconstruction::{SUSPECT_SEGMENT_RATIO, exclude_short, judge, worst_segment};
use rsf_fit::data::Record;
use rsf_fit::fit::{FitError, FitOptions, FitResult, LoadingMode, Prepared, fit, prepare};
use rsf_fit::segment::Segment;
use rsf_solvers::SolveError;

/// The baseline under `o`, and — under protocol loading — the reconstruction check: a segment
/// that misfits far above the others is refitted with record loading, and if the misfit goes
/// away there the protocol is blamed and the diagnosis continues with record loading.
pub(super) fn baseline(
    rec: &Record,
    segs: &[Segment],
    o: &FitOptions,
    threads: usize,
) -> Result<(FitOptions, Prepared, FitResult, Option<super::Reconstruction>), FitError> {
    let p = prepare(rec, segs, o)?;
    // nothing else runs yet: the starts side by side (the returned options keep one thread,
    // for the fits that run as parallel jobs later)
    let fit = |p: &Prepared, o: &FitOptions| fit(p, &FitOptions { threads, ..o.clone() });
    let base = continued(rec, segs, &p, o, &fit)?;
    if o.loading == LoadingMode::Protocol {
        if let Some((i, ratio)) = worst_segment(&base).filter(|w| w.1 > SUSPECT_SEGMENT_RATIO) {
            let or = FitOptions { loading: LoadingMode::Record, ..o.clone() };
            let pr = prepare(rec, segs, &or)?;
            // the check: one start, warm from the protocol optimum; when the protocol is to
            // blame, the record-loading baseline is then fitted in full
            let check = FitOptions { initial: base.params.as_initial(), starts: 1, ..or.clone() };
            if let Ok(fr) = fit(&pr, &check) {
                if let Some(r) = judge(&base, &fr, i, ratio) {
                    let full = fit(&pr, &or)?;
                    return Ok((or, pr, full, Some(r)));
                }
            }
            // record loading could not clear it: a short suspect segment is left out
            if let Some(r) = exclude_short(&base) {
                let mut oe = o.clone();
                oe.exclude.extend(r.excluded.iter().copied());
                let pe = prepare(rec, segs, &oe)?;
                let be = fit(&pe, &oe)?;
                return Ok((oe, pe, be, Some(r)));
            }
        }
    }
    Ok((o.clone(), p, base, None))
}

/// Steps of the continuation in the size of a record's changes of σ ([`continued`]): the
/// record's σ history scaled about its first value by these fractions in turn, each fit
/// starting from the one before. A quarter of a 20 % drop is the 5 % drop that a start fitted
/// to the record before it follows; each step after it a further quarter.
const SIGMA_CONTINUATION: [f64; 3] = [0.25, 0.5, 0.75];

/// The cold fit of `p` (`rec` with its segments `segs`), continued when every start blows up
/// at some time t: a start far from the optimum can be driven to run away by a large change
/// late in the record (a drop of σ forces fast slip, which a poor start cannot follow). The
/// record before the segment where it blew up is fitted first, and its optimum starts the fit
/// of the whole record. When that runs away too and the record's σ varies, the changes of σ
/// are grown to their measured size in steps ([`SIGMA_CONTINUATION`]), each fit starting from
/// the optimum of the one before: the parameters follow the data as the forced slip grows. The
/// first error is returned when that does not work either.
pub(super) fn continued(
    rec: &Record,
    segs: &[Segment],
    p: &Prepared,
    o: &FitOptions,
    fit: &dyn Fn(&Prepared, &FitOptions) -> Result<FitResult, FitError>,
) -> Result<FitResult, FitError> {
    let first = fit(p, o);
    let Err(FitError::Start(SolveError::BlowUp { t, .. })) = &first else { return first };
    // the solver's time: the record's own under record loading, from the prepared record's
    // start under protocol loading (`fit::forward`); the segment where it blew up
    let t_abs = match o.loading {
        LoadingMode::Record => *t,
        LoadingMode::Protocol => p.record.time.first().copied().unwrap_or(0.0) + t,
    };
    let cut = segs.iter().map(|s| s.t0).filter(|&t0| t0 <= t_abs && t0 > rec.time[0]).fold(f64::NAN, f64::max);
    if !cut.is_finite() {
        return first;
    }
    let (train, tsegs) = training(rec, segs, cut);
    let Ok(ft) = prepare(&train, &tsegs, o).and_then(|pt| fit(&pt, o)) else { return first };
    let from = |f: &FitResult| FitOptions { initial: f.params.as_initial(), ..o.clone() };
    let whole = fit(p, &from(&ft));
    if whole.is_ok() || rec.normal_stress.is_empty() {
        return whole.or(first);
    }
    let mut at = ft;
    for lambda in SIGMA_CONTINUATION {
        let mut scaled = rec.clone();
        let s0 = rec.normal_stress[0];
        for s in &mut scaled.normal_stress {
            *s = s0 + lambda * (*s - s0);
        }
        match prepare(&scaled, segs, o).and_then(|ps| fit(&ps, &from(&at))) {
            Ok(f) => at = f,
            Err(_) => return first,
        }
    }
    fit(p, &from(&at)).or(first)
}
