//! Large records fitted on bin means that carry the same information.
//!
//! A 1 kHz record of 10⁶ samples holds far fewer independent features than samples: away from
//! the first instants after a velocity change the model friction changes slowly, and a bin of
//! c consecutive samples can be replaced by its mean with weight √c. For noise of one σ the
//! weighted least-squares objective on the means differs from the one on the samples by a
//! constant (the within-bin scatter) plus the model's curvature inside a bin, so the optimum,
//! the Jacobian's normal matrix Σ c j jᵀ and hence the standard errors are the full
//! computation's. The within-bin sums of squares are kept, so that the rms, the likelihood,
//! AIC and BIC are those of the samples.
//!
//! **Bins.** Within each segment, a bin starting at time t after the segment's start spans at
//! most `BIN_FRACTION` × (t − t₀) — one sample right after a change, growing with the time since
//! it: a transient that decays over a time τ is sampled by ≳ 1/`BIN_FRACTION` bins per τ, and
//! the model's curvature inside a bin shifts a bin mean by ≲ (`BIN_FRACTION`)²/24 of the
//! transient's size (4e-7 of it: 1e-8 in friction for a 0.03 transient, against lab noise of
//! 1e-4). Bins never cross a segment break or a gap in the used samples (an excluded window).
//! The load point of the bins (their means) drives a record-loading model; their times are the
//! mean times; the last sample before each break or gap is a bin of its own, so the load point's
//! corner at a break stays where it is.

use super::Prepared;
use crate::data::Record;
use crate::segment::Segment;

/// Records with more used samples than this are fitted on bin means: below it, the fit on the
/// samples takes a few seconds; above it, the time grows with the samples (10⁶ samples:
/// 23 s in record loading before bins, docs/BENCHMARKS.md).
pub const BIN_ABOVE: usize = 100_000;

/// A bin spans at most this fraction of the time since its segment's start (see the module
/// text for the error it allows). Measured on a 10⁶-sample record (docs/BENCHMARKS.md): at 0.01
/// the parameters moved by up to 0.2 standard errors from the fit on every sample, at 0.003 by
/// at most 0.02, with 11,540 bins and the fit under a second.
pub const BIN_FRACTION: f64 = 0.003;

/// Whether a fit works on bin means, and what its result then describes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BinMeans {
    /// Every sample is fitted.
    Off,
    /// A record of more than `above` used samples is replaced by bin means when it is prepared:
    /// the optimum, the curve, the residuals and the covariance are the bins' (`rsf fit` on a
    /// large record: nothing is ever evaluated on the 10⁷ samples).
    Replace {
        /// Used samples above which the record is binned.
        above: usize,
        /// A bin spans at most this fraction of the time since its segment's start.
        fraction: f64,
    },
    /// The optimum is sought on bin means of a record of more than `above` used samples; the
    /// result — curve, residuals, likelihood, covariance — is then evaluated on every sample at
    /// that optimum (the diagnosis: its noise model reads the residuals sample by sample, and
    /// the search is the part that repeats).
    Search {
        /// Used samples above which the search runs on bin means.
        above: usize,
        /// A bin spans at most this fraction of the time since its segment's start.
        fraction: f64,
    },
}

impl BinMeans {
    /// The bin means [`super::fit`] searches on for `p` under this rule, when it searches on
    /// bins rather than on `p` itself (a varying normal stress keeps every sample: its steps
    /// fall inside segments).
    pub(super) fn search_points(self, p: &Prepared) -> Option<Prepared> {
        match self {
            Self::Search { above, fraction }
                if p.binning.is_none() && p.normal_stress.is_none() && p.used.len() > above =>
            {
                Some(bin(p, fraction))
            }
            Self::Search { .. } | Self::Replace { .. } | Self::Off => None,
        }
    }
}

/// What the bins of a binned [`Prepared`] summarise.
#[derive(Clone, Debug)]
pub struct Binning {
    /// Samples per used point (bin).
    pub counts: Vec<u32>,
    /// Each bin's friction scatter that is noise (about a line, ≈ (c − 1) σ²).
    pub within: Vec<f64>,
    /// Samples in all.
    pub samples: usize,
    /// Σ ln w over the samples (the likelihood's normalisation).
    pub sum_ln_w: f64,
}

/// The friction samples' scatter inside a bin that the noise makes: about a straight line in
/// time (the model's own slope inside a bin is not noise: about the mean, it added 0.7 % to the
/// sum of squares of a 10⁶-sample record), scaled by (c − 1)/(c − 2) for the line's extra degree
/// of freedom, so that it estimates (c − 1) σ² as the scatter about the mean does for noise
/// alone. Two samples: about their mean.
fn scatter(idx: &[usize], t: &[f64], y: &[f64], ym: f64) -> f64 {
    let c = idx.len();
    if c < 3 {
        return idx.iter().map(|&i| (y[i] - ym).powi(2)).sum();
    }
    let tm = idx.iter().map(|&i| t[i]).sum::<f64>() / c as f64;
    let (mut stt, mut sty) = (0.0, 0.0);
    for &i in idx {
        stt += (t[i] - tm).powi(2);
        sty += (t[i] - tm) * (y[i] - ym);
    }
    let slope = if stt > 0.0 { sty / stt } else { 0.0 };
    let ss: f64 = idx.iter().map(|&i| (y[i] - ym - slope * (t[i] - tm)).powi(2)).sum();
    ss * (c - 1) as f64 / (c - 2) as f64
}

/// The rows of a binned record: bin means and the unused samples between them.
#[derive(Default)]
struct Rows {
    time: Vec<f64>,
    load_point: Vec<f64>,
    mu: Vec<f64>,
    /// The first original sample each row stands for (increasing): maps segment bounds.
    first_of: Vec<usize>,
}

impl Rows {
    fn push(&mut self, t: f64, lp: f64, mu: f64, first: usize) {
        self.time.push(t);
        self.load_point.push(lp);
        self.mu.push(mu);
        self.first_of.push(first);
    }
    /// The original samples `from..until` as they are.
    fn raw(&mut self, r: &Record, from: usize, until: usize) {
        for i in from..until {
            self.push(r.time[i], r.load_point[i], r.mu[i], i);
        }
    }
}

/// `p` with its used samples replaced by bin means (weights × √count), each bin spanning at
/// most `fraction` of the time since its segment's start. The samples that are not used (before
/// the first used one, in an excluded window) stay in the record as they are, unused: a
/// record-loading model is driven through them, and a protocol-loading model keeps its clock
/// at the record's first sample.
pub(super) fn bin(p: &Prepared, fraction: f64) -> Prepared {
    let r = &p.record;
    let mut rows = Rows::default();
    let (mut used, mut counts, mut within, mut weights, mut seg_of) = (vec![], vec![], vec![], vec![], vec![]);
    let mut sum_ln_w = 0.0;
    // the first original sample not yet written
    let mut raw_from = 0;
    let mut k = 0;
    while k < p.used.len() {
        let (i0, sg, w) = (p.used[k], p.seg_of[k], p.weights[k]);
        let t_seg = p.segments[sg].t0;
        let span = fraction * (r.time[i0] - t_seg).max(0.0);
        // the sample after `e` continues `e`'s run: same segment, no gap
        let continues =
            |e: usize| e + 1 < p.used.len() && p.seg_of[e + 1] == p.seg_of[e] && p.used[e + 1] == p.used[e] + 1;
        let mut e = k + 1;
        // consecutive samples of one segment, no gap, within the span; the last sample of a run
        // is a bin of its own, so that a record-loading model's load point keeps its corner at
        // each break (a bin's mean time lies up to half its span before the break)
        while e < p.used.len() && continues(e - 1) && continues(e) && r.time[p.used[e]] - r.time[i0] <= span {
            e += 1;
        }
        rows.raw(r, raw_from, i0);
        let c = (e - k) as f64;
        let idx = &p.used[k..e];
        let mean = |v: &[f64]| idx.iter().map(|&i| v[i]).sum::<f64>() / c;
        let m = mean(&r.mu);
        used.push(rows.time.len());
        rows.push(mean(&r.time), mean(&r.load_point), m, i0);
        within.push(scatter(idx, &r.time, &r.mu, m));
        counts.push((e - k) as u32);
        weights.push(w * c.sqrt());
        seg_of.push(sg);
        sum_ln_w += c * w.ln();
        raw_from = p.used[e - 1] + 1;
        k = e;
    }
    rows.raw(r, raw_from, r.time.len());
    let Rows { time, load_point, mu, first_of } = rows;
    let row_of = |i: usize| first_of.partition_point(|&f| f <= i).saturating_sub(1);
    let segments = p.segments.iter().map(|s| Segment { i0: row_of(s.i0), i1: row_of(s.i1), ..s.clone() }).collect();
    let record = Record {
        time,
        load_point,
        mu,
        normal_stress: vec![],
        source: p.record.source.clone(),
        dropped_duplicate_times: p.record.dropped_duplicate_times,
        dropped_invalid: p.record.dropped_invalid,
        warnings: p.record.warnings.clone(),
    };
    Prepared {
        record,
        segments,
        used,
        weights,
        seg_of,
        binning: Some(Binning { samples: p.used.len(), counts, within, sum_ln_w }),
        v_init: p.v_init,
        normal_stress: p.normal_stress.clone(),
        sigma_ref: p.sigma_ref,
    }
}
