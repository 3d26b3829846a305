//! The data side of a fit: which samples, with which weights, and starting values from the
//! record itself.

use super::{FitError, FitOptions, NORMAL_STRESS_VARIES, NormalStressMode, Weighting};
use crate::data::Record;
use crate::segment::Segment;
use rsf_core::NormalStressRecord;

/// The data-dependent part of a fit, shared by LM, MCMC and per-segment fits.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// The record, from the first moving segment on.
    pub record: Record,
    /// Its segments (indices into `record`).
    pub segments: Vec<Segment>,
    /// Used sample indices.
    pub used: Vec<usize>,
    /// Their weights (mean square 1).
    pub weights: Vec<f64>,
    /// Their segment indices.
    pub seg_of: Vec<usize>,
    /// Initial slip rate (steady state), µm/s.
    pub v_init: f64,
    /// The normal stress that drives the model (record times, simplified), when it does.
    pub normal_stress: Option<NormalStressRecord>,
    /// σ_ref, MPa: the normal stress at the first used sample (k = K/σ_ref); 1 without one.
    pub sigma_ref: f64,
    /// When the used points are bin means of a large record ([`super::Binning`]): what they
    /// summarise.
    pub binning: Option<super::Binning>,
}

impl Prepared {
    /// Samples the used point `r` stands for: 1, or its bin's count ([`super::Binning`]).
    pub fn count(&self, r: usize) -> f64 {
        self.binning.as_ref().map_or(1.0, |b| b.counts[r] as f64)
    }

    /// The friction scatter inside point `r`'s bin that is noise (0 for a sample).
    pub fn within(&self, r: usize) -> f64 {
        self.binning.as_ref().map_or(0.0, |b| b.within[r])
    }

    /// Samples the used points stand for.
    pub fn samples(&self) -> usize {
        self.binning.as_ref().map_or(self.used.len(), |b| b.samples)
    }
}

/// Vertices of a measured σ(t) are kept to within this fraction of its median, or twice the
/// sample-to-sample noise if that is larger: a σ error ε shifts friction by about μ ε until
/// the spring relaxes it, so 1e-4 keeps that below 1e-4 in μ, under lab noise.
pub const NORMAL_STRESS_TOLERANCE: f64 = 1e-4;

/// The normal-stress history a fit drives the model with: `None` when the record has no σ
/// column, when `mode` is constant, or (auto) when σ varies less than [`NORMAL_STRESS_VARIES`].
pub fn driving_normal_stress(rec: &Record, mode: NormalStressMode) -> Option<NormalStressRecord> {
    if rec.normal_stress.len() != rec.len() || rec.len() < 2 || mode == NormalStressMode::Constant {
        return None;
    }
    let mut sorted = rec.normal_stress.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let range = sorted[sorted.len() - 1] - sorted[0];
    if mode == NormalStressMode::Auto && range <= NORMAL_STRESS_VARIES * median {
        return None;
    }
    // sample-to-sample noise: MAD of first differences / (0.6745 √2)
    let mut d: Vec<f64> = rec.normal_stress.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    d.sort_by(f64::total_cmp);
    let noise = d[d.len() / 2] / (0.6745 * std::f64::consts::SQRT_2);
    let h = NormalStressRecord { time: rec.time.clone(), sigma: rec.normal_stress.clone() };
    Some(h.simplified((NORMAL_STRESS_TOLERANCE * median).max(2.0 * noise)))
}

/// Selects the samples and weights, and trims the record to its first moving segment.
pub fn prepare(record: &Record, segments: &[Segment], opts: &FitOptions) -> Result<Prepared, FitError> {
    let first = segments
        .iter()
        .position(|s| s.v > 0.0)
        .ok_or_else(|| FitError::Setup("the record has no moving segment".into()))?;
    // the model starts in steady state: start where the load point first moves
    let i_start = segments[first].i0;
    let rec = Record {
        time: record.time[i_start..].to_vec(),
        load_point: record.load_point[i_start..].to_vec(),
        mu: record.mu[i_start..].to_vec(),
        normal_stress: record.normal_stress.get(i_start..).map(<[f64]>::to_vec).unwrap_or_default(),
        source: record.source.clone(),
        dropped_duplicate_times: record.dropped_duplicate_times,
        dropped_invalid: record.dropped_invalid,
        warnings: record.warnings.clone(),
    };
    let segs: Vec<Segment> =
        segments[first..].iter().map(|s| Segment { i0: s.i0 - i_start, i1: s.i1 - i_start, ..s.clone() }).collect();
    if segs.len() < 2 {
        return Err(FitError::Setup(
            "the record is one segment of constant load-point velocity: a, b and Dc cannot be told apart \
             without a velocity change (a step or a hold); include data before and after a change"
                .into(),
        ));
    }
    let mut used = Vec::new();
    let mut seg_of = Vec::new();
    for (k, s) in segs.iter().enumerate() {
        for i in s.i0..=s.i1 {
            let keep = match opts.window_um {
                None => true,
                Some(w) if k == 0 => rec.load_point[s.i1] - rec.load_point[i] <= w,
                Some(w) => s.v == 0.0 || (rec.load_point[i] - s.lp0).abs() <= w,
            };
            let t = rec.time[i];
            if keep && !opts.exclude.iter().any(|&(a, b)| a <= t && t <= b) {
                used.push(i);
                seg_of.push(k);
            }
        }
    }
    if used.len() < 10 {
        return Err(FitError::Setup(format!("only {} samples fall in the fit windows", used.len())));
    }
    let mut count = vec![0usize; segs.len()];
    for &s in &seg_of {
        count[s] += 1;
    }
    let mut weights: Vec<f64> = match opts.weighting {
        Weighting::Uniform => vec![1.0; used.len()],
        Weighting::EqualSegments => seg_of.iter().map(|&s| 1.0 / (count[s] as f64).sqrt()).collect(),
    };
    let ms = weights.iter().map(|w| w * w).sum::<f64>() / weights.len() as f64;
    weights.iter_mut().for_each(|w| *w /= ms.sqrt());
    let v_init = segs[0].v;
    let normal_stress = driving_normal_stress(&rec, opts.normal_stress);
    let sigma_ref = normal_stress.as_ref().map(|h| h.sigma[0]).unwrap_or(1.0);
    let p = Prepared {
        record: rec,
        segments: segs,
        used,
        weights,
        seg_of,
        v_init,
        normal_stress,
        sigma_ref,
        binning: None,
    };
    // a large record is fitted on bin means (a varying normal stress keeps every sample: its
    // steps fall inside segments)
    Ok(match opts.bins {
        super::BinMeans::Replace { above, fraction } if p.used.len() > above && p.normal_stress.is_none() => {
            super::bins::bin(&p, fraction)
        }
        super::BinMeans::Replace { .. } | super::BinMeans::Search { .. } | super::BinMeans::Off => p,
    })
}

/// Data-derived starting values: `(mu0, a, b_total, dc)` from the velocity steps (a from the
/// peak or trough after a step, a − b from the steady states before and after, Dc from the
/// slip over which the transient decays by 1 − 1/e).
pub fn initial_guess(p: &Prepared) -> (f64, f64, f64, f64) {
    let r = &p.record;
    let tail_median = |s: &Segment| {
        let n = s.i1 + 1 - s.i0;
        let mut v: Vec<f64> = r.mu[s.i1 + 1 - (n / 4).max(1)..=s.i1].to_vec();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let mu0 = tail_median(&p.segments[0]);
    let (mut as_, mut ambs, mut dcs) = (vec![], vec![], vec![]);
    for w in p.segments.windows(2) {
        let (s0, s1) = (&w[0], &w[1]);
        if !(s0.v > 0.0 && s1.v > 0.0) || (s1.v / s0.v).ln().abs() < 0.2 {
            continue;
        }
        let l = (s1.v / s0.v).ln();
        let before = tail_median(s0);
        let after = tail_median(s1);
        let n = s1.i1 + 1 - s1.i0;
        let early = &r.mu[s1.i0..s1.i0 + (n / 3).max(1)];
        let (ipk, pk) = if l > 0.0 {
            early.iter().enumerate().fold((0, f64::NEG_INFINITY), |a, (i, &m)| if m > a.1 { (i, m) } else { a })
        } else {
            early.iter().enumerate().fold((0, f64::INFINITY), |a, (i, &m)| if m < a.1 { (i, m) } else { a })
        };
        as_.push((pk - before) / l);
        ambs.push((after - before) / l);
        let target = pk + (after - pk) * (1.0 - (-1f64).exp());
        let i_pk = s1.i0 + ipk;
        let cross = (i_pk..=s1.i1).find(|&i| (r.mu[i] - target) * (pk - target) <= 0.0).unwrap_or(s1.i1);
        dcs.push((r.load_point[cross] - r.load_point[i_pk]).abs());
    }
    let med = |mut v: Vec<f64>, d: f64| {
        v.retain(|x| x.is_finite());
        if v.is_empty() {
            return d;
        }
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let a = med(as_, 0.01).clamp(1e-4, 0.1);
    let amb = med(ambs, -0.002).clamp(-0.05, 0.05);
    let dc = med(dcs, 10.0).clamp(0.1, 1e4);
    (mu0, a, (a - amb).max(1e-4), dc.max(0.1))
}
