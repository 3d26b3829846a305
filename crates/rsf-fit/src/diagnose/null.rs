//! A null calibrated on the record's own noise: how often would an extension gain as much as it
//! did if the baseline were true?
//!
//! ΔBIC with an effective sample size corrects for AR(1) noise on average, but lab noise is not
//! exactly AR(1), an extension's extra parameters can soak up particular noise shapes (a slow
//! wander looks like a slip trend, a soft machine or a second state), and the chi-square
//! calibration of a likelihood ratio fails where a parameter sits at a boundary (b2 → 0, Vc → 0).
//! So the candidate's gain is compared with its distribution under the fitted baseline plus
//! the fitted noise model, by parametric bootstrap: each replicate is the baseline's model
//! curve plus noise with the residuals' σ and correlation time (an Ornstein–Uhlenbeck process
//! in time, so variable sampling is honoured), refitted with the baseline and with the
//! candidate exactly as the record was. With tens of replicates the far tail cannot be
//! counted, so the replicates' gains G = −ΔBIC_eff + Δk ln n_eff (the likelihood-ratio statistic
//! scaled by n_eff/n) are matched by moments to a scaled chi-square c·χ²_d (Satterthwaite), and
//! the false-alarm probability is its upper tail at the observed gain. The count of replicates
//! that reached the observed gain is reported beside it.

use super::evidence::{residual_correlation, scores};
use crate::data::Record;
use crate::fit::{FitResult, Prepared};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// Default false-alarm level: a cause is named only when a gain as large as the observed one
/// would arise by chance under the baseline less often than this.
pub const FALSE_ALARM_LEVEL: f64 = 0.01;

/// Default number of bootstrap replicates: enough for the first two moments of the null gain
/// to within about ±30%, which moves the tail probability at the 1% level by less than a
/// factor 2; each costs a baseline and a candidate refit.
pub const NULL_REPLICATES: usize = 16;

/// The null distribution of one candidate's gain.
#[derive(Clone, Debug, Serialize)]
pub struct NullCalibration {
    /// Replicates that could be refitted with both models.
    pub replicates: usize,
    /// Mean and standard deviation of the null gain G.
    pub gain_mean: f64,
    /// Standard deviation of G.
    pub gain_sd: f64,
    /// The observed gain G.
    pub gain_observed: f64,
    /// Replicates whose gain reached the observed one.
    pub exceeded: usize,
    /// P(G ≥ observed) under the fitted scaled chi-square c·χ²_d.
    pub false_alarm_probability: f64,
}

/// The noise model of a fit's residuals: σ and the OU correlation time (s) that gives the
/// residuals' lag-one correlation at the median sampling interval.
pub(super) fn noise_model(f: &FitResult) -> (f64, f64) {
    let (res, rho, _) = residual_correlation(f);
    let n = res.len() as f64;
    let mean = res.iter().sum::<f64>() / n;
    let sigma = (res.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / n).sqrt();
    let mut dts: Vec<f64> = f.curve.time.windows(2).map(|w| w[1] - w[0]).filter(|d| *d > 0.0).collect();
    dts.sort_by(f64::total_cmp);
    let dt = dts.get(dts.len() / 2).copied().unwrap_or(1.0);
    let tau = if rho > 0.0 { -dt / rho.ln() } else { 0.0 };
    (sigma, tau)
}

/// A replicate record: the baseline's model curve at the used samples plus OU noise.
pub(super) fn replicate(p: &Prepared, base: &FitResult, sigma: f64, tau: f64, seed: u64) -> Record {
    let mut rec = p.record.clone();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut e = 0.0;
    let mut t_prev = None::<f64>;
    for (r, &i) in p.used.iter().enumerate() {
        let z: f64 = StandardNormal.sample(&mut rng);
        let t = rec.time[i];
        e = match t_prev {
            Some(tp) if tau > 0.0 => {
                let phi = (-(t - tp) / tau).exp();
                phi * e + (1.0 - phi * phi).sqrt() * sigma * z
            }
            _ => sigma * z,
        };
        t_prev = Some(t);
        rec.mu[i] = base.curve.model[r] + e;
    }
    rec
}

/// Gives a replicate the load-point noise of the record (σ_x µm, white) about the protocol's
/// lines, so that re-segmenting it reproduces the protocol's timing errors: with a noisy load
/// point the reconstruction is part of what the null must replicate.
pub(super) fn replicate_load_point(p: &Prepared, rec: &mut Record, sigma_x: f64, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed_10ad_0000_0000);
    for s in &p.segments {
        for i in s.i0..=s.i1 {
            let z: f64 = StandardNormal.sample(&mut rng);
            rec.load_point[i] = s.lp0 + s.v * (rec.time[i] - s.t0) + sigma_x * z;
        }
    }
}

/// The gain G of `ext` over `base`: the n_eff-scaled likelihood-ratio statistic.
pub(super) fn gain(base: &FitResult, ext: &FitResult, n_eff: f64) -> f64 {
    let (dbic, _) = scores(base, ext, n_eff);
    let dk = ext.n_free as f64 - base.n_free as f64;
    -dbic + dk * n_eff.ln()
}

/// Calibrates the observed gain against the replicates' gains (`None` entries failed); `dk` is
/// the number of parameters the extension adds.
pub(super) fn calibrate(observed: f64, null: &[Option<f64>], dk: usize) -> Option<NullCalibration> {
    let g: Vec<f64> = null.iter().flatten().map(|g| g.max(0.0)).collect();
    if g.len() < 4 {
        return None;
    }
    let n = g.len() as f64;
    let mean = g.iter().sum::<f64>() / n;
    let var = g.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    // c·χ²_d with mean c d and variance 2 c² d; a degenerate null (every replicate's gain 0:
    // its moments say nothing) falls back to the textbook χ²_dk
    let p = if mean > 0.0 && var > 0.0 {
        let c = var / (2.0 * mean);
        let d = (2.0 * mean * mean / var).max(1e-3);
        ChiSquared::new(d).map(|chi| chi.sf(observed.max(0.0) / c)).unwrap_or(f64::NAN)
    } else {
        ChiSquared::new(dk.max(1) as f64).map(|chi| chi.sf(observed.max(0.0))).unwrap_or(f64::NAN)
    };
    Some(NullCalibration {
        replicates: g.len(),
        gain_mean: mean,
        gain_sd: var.sqrt(),
        gain_observed: observed,
        exceeded: g.iter().filter(|&&x| x >= observed).count(),
        false_alarm_probability: p,
    })
}
