//! Reconstruction checked before physics is blamed.
//!
//! A protocol reconstructed from the load-point record can be wrong at a break (a hold ended a
//! few samples late, a step at the wrong time); the model then misses one segment by far more
//! than any other, and every physical extension is tempted to explain that misfit. So after the
//! baseline fit under protocol loading, a segment whose residual rms stands far above the
//! others is put to a test that physics cannot pass: the baseline is refitted driven by the
//! measured load point itself. If the segment's misfit falls back among the others there, the
//! protocol was at fault: the problem is reported (segment, time, misfit before and after) and
//! the diagnosis goes on with record loading, so no physical cause is named from it. A physical
//! effect (a cut-off, healing of the wrong law) misfits under both loadings alike and is left to
//! the candidates.

use rsf_fit::fit::FitResult;
use rsf_fit::segment::SegmentKind;
use serde::Serialize;

/// A segment whose rms exceeds this multiple of the median segment rms is suspect.
pub const SUSPECT_SEGMENT_RATIO: f64 = 3.0;

/// Under record loading the suspect segment must come down to this multiple of the median
/// segment rms (from above `SUSPECT_SEGMENT_RATIO`) for the protocol to be blamed.
pub const RESOLVED_SEGMENT_RATIO: f64 = 2.0;

/// Record loading must not make the typical segment worse than this multiple of its misfit
/// under the protocol: a noisy load point (encoder noise) drives the model with that noise
/// (k·σ_x in friction), and then every segment misfits more — the suspect one falls among the
/// others without the protocol being at fault.
pub const RECORD_MEDIAN_TOLERANCE: f64 = 1.2;

/// A suspect segment with fewer samples than this is too short for its velocity and break times
/// to be reconstructed from a noisy load point (a 0.3 s step at 300 µm/s sampled at 10 Hz):
/// when record loading cannot settle the question, it is left out rather than explained.
pub const SHORT_SEGMENT_SAMPLES: usize = 30;

/// What the diagnosis did about a protocol problem.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Remedy {
    /// Drove the model by the measured load point.
    RecordLoading,
    /// Left the segments out of every fit (a short segment of a noisy load point).
    Excluded,
}

/// A protocol-reconstruction problem found and worked around.
#[derive(Clone, Debug, Serialize)]
pub struct Reconstruction {
    /// The segment (1-based, as in the fit's segment table) whose misfit stood out.
    pub segment: usize,
    /// Its kind.
    pub kind: SegmentKind,
    /// Its start time, s (the reconstructed break).
    pub t: f64,
    /// Its rms over the median segment rms under protocol loading.
    pub rms_ratio_protocol: f64,
    /// The same under record loading (absent when record loading could not test it).
    pub rms_ratio_record: Option<f64>,
    /// What the diagnosis did about it.
    pub remedy: Remedy,
    /// Time windows left out of every fit (s), for `Remedy::Excluded`.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub excluded: Vec<(f64, f64)>,
    /// In words.
    pub message: String,
}

/// The worst segment of a fit: (index into `segments`, rms / median rms).
pub(super) fn worst_segment(f: &FitResult) -> Option<(usize, f64)> {
    let mut rms: Vec<f64> = f.segments.iter().filter(|s| s.n > 0).map(|s| s.rms).collect();
    if rms.len() < 3 {
        return None;
    }
    rms.sort_by(f64::total_cmp);
    let med = rms[rms.len() / 2].max(1e-300);
    f.segments
        .iter()
        .enumerate()
        .filter(|(_, s)| s.n > 0)
        .map(|(i, s)| (i, s.rms / med))
        .max_by(|a, b| a.1.total_cmp(&b.1))
}

/// The median segment rms of a fit.
fn median_rms(f: &FitResult) -> Option<f64> {
    let mut rms: Vec<f64> = f.segments.iter().filter(|s| s.n > 0).map(|s| s.rms).collect();
    rms.sort_by(f64::total_cmp);
    rms.get(rms.len() / 2).map(|m| m.max(1e-300))
}

/// The segment of `record_fit` matching segment `i` of `protocol_fit` (same start time) and its
/// rms ratio there; `None` when record loading made the typical segment worse.
fn ratio_at(protocol_fit: &FitResult, record_fit: &FitResult, i: usize) -> Option<f64> {
    let t0 = protocol_fit.segments[i].t0;
    let med = median_rms(record_fit)?;
    if med > RECORD_MEDIAN_TOLERANCE * median_rms(protocol_fit)? {
        return None;
    }
    record_fit.segments.iter().find(|s| (s.t0 - t0).abs() < 1e-9).map(|s| s.rms / med)
}

/// The verdict on a suspect segment `i` of the protocol-loading baseline, given the
/// record-loading baseline: `Some` when the protocol is to blame.
pub(super) fn judge(protocol_fit: &FitResult, record_fit: &FitResult, i: usize, ratio: f64) -> Option<Reconstruction> {
    let after = ratio_at(protocol_fit, record_fit, i)?;
    let s = &protocol_fit.segments[i];
    (after <= RESOLVED_SEGMENT_RATIO).then(|| Reconstruction {
        segment: s.index,
        kind: s.kind,
        t: s.t0,
        rms_ratio_protocol: ratio,
        rms_ratio_record: Some(after),
        remedy: Remedy::RecordLoading,
        excluded: vec![],
        message: format!(
            "segment {} ({}, from t = {:.2} s) misfits {:.1}× the median segment under the reconstructed \
             protocol but {:.1}× when the model is driven by the measured load point: the protocol's \
             break there is wrong, not the physics; diagnosed with record loading",
            s.index,
            s.kind.name(),
            s.t0,
            ratio,
            after
        ),
    })
}

/// When record loading could not settle it: the run of suspect segments (rms above
/// `SUSPECT_SEGMENT_RATIO` × the median) that contains a short one (fewer than
/// `SHORT_SEGMENT_SAMPLES` samples), as a time window to leave out; `None` when no short segment
/// is suspect (a misfit in a long segment is left to the physics).
pub(super) fn exclude_short(protocol_fit: &FitResult) -> Option<Reconstruction> {
    let mut rms: Vec<f64> = protocol_fit.segments.iter().filter(|s| s.n > 0).map(|s| s.rms).collect();
    rms.sort_by(f64::total_cmp);
    let med = rms.get(rms.len() / 2)?.max(1e-300);
    let segs = &protocol_fit.segments;
    let suspect = |i: usize| segs[i].n > 0 && segs[i].rms > SUSPECT_SEGMENT_RATIO * med;
    let short = (0..segs.len()).find(|&i| suspect(i) && segs[i].n < SHORT_SEGMENT_SAMPLES)?;
    // the contiguous run of suspect segments around it
    let mut a = short;
    while a > 0 && suspect(a - 1) {
        a -= 1;
    }
    let mut b = short;
    while b + 1 < segs.len() && suspect(b + 1) {
        b += 1;
    }
    let ratio = segs[short].rms / med;
    let window = (segs[a].t0, segs[b].t1);
    Some(Reconstruction {
        segment: segs[short].index,
        kind: segs[short].kind,
        t: segs[short].t0,
        rms_ratio_protocol: ratio,
        rms_ratio_record: None,
        remedy: Remedy::Excluded,
        excluded: vec![window],
        message: format!(
            "segment {} ({}, from t = {:.2} s, {} samples) misfits {:.1}× the median segment; it is too short for its \
             velocity and breaks to be reconstructed from this load point, and record loading cannot test it (the \
             load point is noisy): segments {}–{} (t = {:.2}–{:.2} s) were left out of every fit",
            segs[short].index,
            segs[short].kind.name(),
            segs[short].t0,
            segs[short].n,
            ratio,
            segs[a].index,
            segs[b].index,
            window.0,
            window.1
        ),
    })
}
