//! Posterior sampling by adaptive Metropolis (Haario, Saksman & Tamminen 2001).
//!
//! Parameters: the fit's free parameters on their fitting scale (logarithms for a, k, Dc, Vc)
//! and ln σ, the noise level. Likelihood: Gaussian, independent samples of equal variance,
//! `−n ln σ − Σ r² / (2σ²)`; flat priors on those scales. The LM fit's segment weights are a
//! choice of what to fit, not a noise model, so they do not enter the likelihood (with them,
//! the intervals under-cover: 0.81 instead of 0.95 in the calibration test). Chains start from the LM
//! optimum perturbed by its covariance, run in parallel threads, each with its own ChaCha8
//! stream derived from the seed and the chain number, so a run is reproducible whatever the
//! thread scheduling. The proposal covariance is the LM covariance until the chain has 500
//! samples, then the chain's own covariance (updated every 100 steps) scaled by 2.38²/d.
//! Reported: posterior medians and 95% intervals on the physical scale, split-R̂ and the
//! effective sample size (Geyer's initial positive sequence), per parameter.

use crate::fit::{FitOptions, FitResult, Prepared, model_curve, parameter_map};
use crate::progress::Progress;
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Instant;

/// MCMC settings.
#[derive(Clone)]
pub struct McmcOptions {
    /// Total samples over all chains (after which burn-in is discarded).
    pub samples: usize,
    /// Number of chains (≥ 2 for R̂).
    pub chains: usize,
    /// Seed.
    pub seed: u64,
    /// Fraction of each chain discarded as burn-in.
    pub burn_fraction: f64,
    /// Integrator tolerance for the forward model.
    pub rtol: f64,
    /// Told the samples drawn so far over all chains (every [`PROGRESS_EVERY`] per chain).
    pub progress: Option<Progress>,
}

/// A chain reports progress every this many steps.
pub const PROGRESS_EVERY: usize = 50;

impl Default for McmcOptions {
    fn default() -> Self {
        Self { samples: 20000, chains: 4, seed: 1, burn_fraction: 0.5, rtol: 1e-6, progress: None }
    }
}

impl std::fmt::Debug for McmcOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("McmcOptions")
            .field("samples", &self.samples)
            .field("chains", &self.chains)
            .field("seed", &self.seed)
            .field("burn_fraction", &self.burn_fraction)
            .field("rtol", &self.rtol)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

/// Posterior summary of one parameter (physical scale).
#[derive(Clone, Debug, Serialize)]
pub struct Posterior {
    /// Posterior median.
    pub median: f64,
    /// 95% credible interval.
    pub ci95: [f64; 2],
    /// Split-R̂ (< 1.01–1.05 means the chains agree).
    pub rhat: f64,
    /// Effective sample size over all chains.
    pub ess: f64,
}

/// MCMC result.
#[derive(Clone, Debug, Serialize)]
pub struct McmcResult {
    /// Per parameter (free parameters and `sigma`).
    pub params: BTreeMap<String, Posterior>,
    /// Acceptance rate.
    pub acceptance: f64,
    /// Chains.
    pub chains: usize,
    /// Samples per chain (including burn-in).
    pub steps_per_chain: usize,
    /// Forward simulations run.
    pub simulations: usize,
    /// Wall time, s.
    pub wall_s: f64,
    /// Forward simulations per second (all threads).
    pub simulations_per_s: f64,
    /// Seed.
    pub seed: u64,
    /// The draws after burn-in, chain after chain, in physical units: one row per draw, columns
    /// [`sample_names`](Self::sample_names) (not serialised: the JSON carries the summaries).
    #[serde(skip)]
    pub samples: Vec<Vec<f64>>,
    /// Column names of `samples`: the free parameters, then `sigma`.
    #[serde(skip)]
    pub sample_names: Vec<String>,
}

/// Runs the sampler around the fit `best`.
pub fn run(p: &Prepared, opts: &FitOptions, best: &FitResult, m: &McmcOptions) -> Result<McmcResult, String> {
    let map = parameter_map(p, opts).map_err(|e| e.to_string())?;
    let names = map.free_names();
    let d = names.len() + 1;
    // bin means of a large record (`fit::bins`): each stands for its count of samples, and the
    // scatter inside the bins is part of every sum of squares
    let n = p.samples() as f64;
    let within: f64 = (0..p.used.len()).map(|r| p.within(r)).sum();
    let data: Vec<f64> = p.used.iter().map(|&i| p.record.mu[i]).collect();
    let log_post = |x: &[f64]| -> f64 {
        if opts.cancelled() {
            return f64::NEG_INFINITY;
        }
        let Ok(mu) = model_curve(p, &map, opts, &x[..d - 1], m.rtol) else {
            return f64::NEG_INFINITY;
        };
        let ls = x[d - 1];
        let ssr: f64 =
            mu.iter().zip(&data).enumerate().map(|(r, (a, b))| p.count(r) * (a - b).powi(2)).sum::<f64>() + within;
        if !ssr.is_finite() {
            return f64::NEG_INFINITY;
        }
        -n * ls - ssr / (2.0 * (2.0 * ls).exp())
    };
    // start: LM optimum and covariance (σ: ln of the rms, variance 1/(2n))
    let mut x0 = best.theta.clone();
    x0.push(best.rms.ln());
    let mut c0 = DMatrix::<f64>::zeros(d, d);
    for a in 0..d - 1 {
        for b in 0..d - 1 {
            c0[(a, b)] = best.cov_theta[a * (d - 1) + b];
        }
    }
    c0[(d - 1, d - 1)] = 1.0 / (2.0 * n);
    for k in 0..d {
        if !(c0[(k, k)].is_finite() && c0[(k, k)] > 0.0) {
            c0[(k, k)] = 1e-6;
        }
    }
    let chains = m.chains.max(1);
    let steps = (m.samples / chains).max(200);
    let start = Instant::now();
    // the samples drawn over all chains, for the progress observer
    let drawn = std::sync::atomic::AtomicUsize::new(0);
    let total = steps * chains;
    let tick = || {
        let done = drawn.fetch_add(PROGRESS_EVERY, std::sync::atomic::Ordering::Relaxed) + PROGRESS_EVERY;
        if let Some(p) = &m.progress {
            p(done.min(total), total, "MCMC samples");
        }
    };
    // one chain per thread, each with its own seeded stream: the same draws on any schedule
    let ids: Vec<usize> = (0..chains).collect();
    let results: Vec<(Vec<Vec<f64>>, usize)> =
        crate::parallel::par_map(&ids, chains, |&c| chain(c, steps, &x0, &c0, m.seed, &log_post, &tick));
    if opts.cancelled() {
        return Err("cancelled".into());
    }
    let wall = start.elapsed().as_secs_f64();
    let burn = ((steps as f64) * m.burn_fraction) as usize;
    let accepted: usize = results.iter().map(|r| r.1).sum();
    let mut params = BTreeMap::new();
    let to_phys_k = |k: usize, v: f64| if k == d - 1 || map.is_log(k) { v.exp() } else { v };
    // the draws after burn-in, chain after chain, in physical units
    let samples: Vec<Vec<f64>> = results
        .iter()
        .flat_map(|(ch, _)| ch[burn..].iter().map(|x| x.iter().enumerate().map(|(k, &v)| to_phys_k(k, v)).collect()))
        .collect();
    let mut sample_names = names.clone();
    sample_names.push("sigma".into());
    for k in 0..d {
        let per_chain: Vec<Vec<f64>> =
            results.iter().map(|(ch, _)| ch[burn..].iter().map(|x| x[k]).collect()).collect();
        let to_phys = |v: f64| if k == d - 1 || map.is_log(k) { v.exp() } else { v };
        let mut all: Vec<f64> = per_chain.iter().flatten().map(|&v| to_phys(v)).collect();
        all.sort_by(f64::total_cmp);
        let q = |f: f64| all[((all.len() - 1) as f64 * f).round() as usize];
        let name = if k == d - 1 { "sigma".to_string() } else { names[k].clone() };
        params.insert(
            name,
            Posterior {
                median: q(0.5),
                ci95: [q(0.025), q(0.975)],
                rhat: split_rhat(&per_chain),
                ess: ess(&per_chain),
            },
        );
    }
    let sims = steps * chains;
    Ok(McmcResult {
        params,
        acceptance: accepted as f64 / sims as f64,
        chains,
        steps_per_chain: steps,
        simulations: sims,
        wall_s: wall,
        simulations_per_s: sims as f64 / wall,
        seed: m.seed,
        samples,
        sample_names,
    })
}

fn chain(
    c: usize,
    steps: usize,
    x0: &[f64],
    c0: &DMatrix<f64>,
    seed: u64,
    log_post: &(dyn Fn(&[f64]) -> f64 + Sync),
    tick: &(dyn Fn() + Sync),
) -> (Vec<Vec<f64>>, usize) {
    let d = x0.len();
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15).wrapping_add(c as u64 + 1));
    let sd = 2.38 * 2.38 / d as f64;
    let chol = |cov: &DMatrix<f64>| {
        let mut cv = cov * sd;
        for k in 0..d {
            cv[(k, k)] += 1e-12 * cov[(k, k)].abs().max(1e-20);
        }
        cv.cholesky().map(|ch| ch.l())
    };
    let mut l = chol(c0).unwrap_or_else(|| DMatrix::identity(d, d) * 1e-4);
    let draw = |rng: &mut ChaCha8Rng, l: &DMatrix<f64>| {
        let z = DVector::<f64>::from_fn(d, |_, _| rng.sample(StandardNormal));
        l * z
    };
    // overdispersed start: two standard deviations of the LM covariance
    let mut x = DVector::from_column_slice(x0);
    let l0 = chol(c0).unwrap_or_else(|| DMatrix::identity(d, d) * 1e-4);
    for _ in 0..20 {
        let trial = &x + draw(&mut rng, &l0) * (2.0 / sd.sqrt());
        if log_post(trial.as_slice()).is_finite() {
            x = trial;
            break;
        }
    }
    let mut lp = log_post(x.as_slice());
    let mut out = Vec::with_capacity(steps);
    let (mut mean, mut m2) = (DVector::<f64>::zeros(d), DMatrix::<f64>::zeros(d, d));
    let mut accepted = 0;
    for i in 0..steps {
        let y = &x + draw(&mut rng, &l);
        let lq = log_post(y.as_slice());
        let u: f64 = rng.random();
        if lq.is_finite() && (lq - lp) > u.ln() {
            x = y;
            lp = lq;
            accepted += 1;
        }
        out.push(x.as_slice().to_vec());
        // running mean and covariance (Welford) for adaptation
        let cnt = (i + 1) as f64;
        let delta = &x - &mean;
        mean += &delta / cnt;
        m2 += &delta * (&x - &mean).transpose();
        if i >= 500 && i % 100 == 0 {
            if let Some(nl) = chol(&(&m2 / (cnt - 1.0))) {
                l = nl;
            }
        }
        if i % PROGRESS_EVERY == PROGRESS_EVERY - 1 {
            tick();
        }
    }
    (out, accepted)
}

/// Split-R̂ of Gelman et al. (2013, BDA3 §11.4).
pub fn split_rhat(chains: &[Vec<f64>]) -> f64 {
    let halves: Vec<&[f64]> = chains
        .iter()
        .flat_map(|c| {
            let h = c.len() / 2;
            [&c[..h], &c[h..2 * h]]
        })
        .filter(|h| h.len() > 1)
        .collect();
    let m = halves.len() as f64;
    if m < 2.0 {
        return f64::NAN;
    }
    let n = halves[0].len() as f64;
    let means: Vec<f64> = halves.iter().map(|h| h.iter().sum::<f64>() / n).collect();
    let grand = means.iter().sum::<f64>() / m;
    let b = n / (m - 1.0) * means.iter().map(|x| (x - grand).powi(2)).sum::<f64>();
    let w = halves
        .iter()
        .zip(&means)
        .map(|(h, mu)| h.iter().map(|x| (x - mu).powi(2)).sum::<f64>() / (n - 1.0))
        .sum::<f64>()
        / m;
    let var = (n - 1.0) / n * w + b / n;
    if w > 0.0 { (var / w).sqrt() } else { 1.0 }
}

/// Effective sample size summed over chains (Geyer's initial positive sequence per chain).
pub fn ess(chains: &[Vec<f64>]) -> f64 {
    chains
        .iter()
        .map(|c| {
            let n = c.len();
            if n < 4 {
                return n as f64;
            }
            let mean = c.iter().sum::<f64>() / n as f64;
            let var = c.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
            if var == 0.0 {
                return n as f64;
            }
            let rho =
                |lag: usize| (0..n - lag).map(|i| (c[i] - mean) * (c[i + lag] - mean)).sum::<f64>() / (n as f64 * var);
            let mut tau = -1.0;
            let mut lag = 0;
            while lag + 1 < n {
                let pair = rho(lag) + rho(lag + 1);
                if pair <= 0.0 {
                    break;
                }
                tau += 2.0 * pair;
                lag += 2;
            }
            n as f64 / tau.max(1.0)
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rhat_and_ess_behave() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let iid: Vec<Vec<f64>> = (0..4).map(|_| (0..2000).map(|_| rng.sample(StandardNormal)).collect()).collect();
        let r = split_rhat(&iid);
        assert!((r - 1.0).abs() < 0.01, "{r}");
        let e = ess(&iid);
        assert!(e > 5000.0, "{e}");
        // chains stuck in different places
        let bad: Vec<Vec<f64>> =
            (0..4).map(|c| (0..2000).map(|i| c as f64 + 1e-3 * (i as f64).sin()).collect()).collect();
        assert!(split_rhat(&bad) > 2.0);
        // an AR(1) chain with φ = 0.9 has ESS ≈ n (1 − φ)/(1 + φ)
        let mut x = 0.0;
        let ar: Vec<f64> = (0..20000)
            .map(|_| {
                let z: f64 = rng.sample(StandardNormal);
                x = 0.9 * x + z;
                x
            })
            .collect();
        let e = ess(&[ar]);
        assert!((e / (20000.0 * 0.1 / 1.9) - 1.0).abs() < 0.3, "{e}");
    }
}
