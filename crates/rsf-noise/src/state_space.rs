//! The noise model in time of a variably sampled record as a state-space process: its exact
//! likelihood, the whitening it implies, and its replicates (`sampling.rs` estimates it).
//!
//! **Likelihood.** The exact Gaussian likelihood of the residuals at their own times, by a
//! Kalman filter: the OU part is one state, the drift a sum of OU processes with time
//! constants from T down by half decades (the classic sum-of-relaxations form of a power law,
//! weights ∝ τ_k^(β−1), scaled to P(ν) by least squares in log over the band). Cost
//! O(n K²), K ≤ 1 + [`MAX_DRIFT_COMPONENTS`]. n_eff = σ²·1ᵀΣ⁻¹1, the information for a
//! constant offset, from the same filter.
//!
//! **Replicates.** White noise per sample, the OU part by its exact recursion at the sample
//! times, the drift synthesised on a uniform grid in time and interpolated.

use rand_distr::{Distribution, StandardNormal};

use super::noise::{MAX_DRIFT_GRID, NoiseModel};

/// Drift components per decade of time constant: at two, the sum of relaxations follows the
/// power law to a few per cent between its ends.
const COMPONENTS_PER_DECADE: f64 = 2.0;
/// At most this many drift components (7 decades below the span).
const MAX_DRIFT_COMPONENTS: usize = 14;
/// Drift components stop where the drift's power falls below this share of the white noise's
/// at the shortest interval: below it they change the likelihood by less than its rounding.
const DRIFT_FLOOR: f64 = 1e-3;

/// The drift part as OU processes (time constant s, variance): from the span down by
/// [`COMPONENTS_PER_DECADE`] until the drift's power is [`DRIFT_FLOOR`] of the white noise's
/// at the shortest interval `dt_min`, weights ∝ τ^(β−1) scaled to P(ν) = A·Δ₀·(ν T)^(−β) by
/// least squares in ln P over the band the components cover.
pub(super) fn drift_components(m: &NoiseModel, dt_min: f64) -> Vec<(f64, f64)> {
    if !(m.drift_amplitude > 0.0) {
        return vec![];
    }
    let span = m.drift_n * m.dt;
    let target = |nu: f64| m.drift_amplitude * m.dt * (nu * span).powf(-m.drift_beta);
    let white_psd = m.white_variance.max(1e-3 * m.variance) * dt_min;
    let ratio = 10f64.powf(1.0 / COMPONENTS_PER_DECADE);
    let mut taus = vec![];
    let mut tau = span;
    while taus.len() < MAX_DRIFT_COMPONENTS && tau >= 0.5 * dt_min {
        taus.push(tau);
        if target(1.0 / (std::f64::consts::TAU * tau)) < DRIFT_FLOOR * white_psd && taus.len() >= 2 {
            break;
        }
        tau /= ratio;
    }
    let shape = |nu: f64| -> f64 {
        taus.iter()
            .map(|&t| 2.0 * t.powf(m.drift_beta - 1.0) * t / (1.0 + (std::f64::consts::TAU * nu * t).powi(2)))
            .sum()
    };
    // the band the components cover: from the lowest resolved frequency to the last corner
    let (lo, hi) =
        ((1.0 / span).ln(), (1.0 / (std::f64::consts::TAU * taus[taus.len() - 1])).ln().max((1.0 / span).ln()));
    const POINTS: usize = 24;
    let lnc = (0..POINTS)
        .map(|i| {
            let nu = (lo + (hi - lo) * i as f64 / (POINTS - 1) as f64).exp();
            target(nu).ln() - shape(nu).ln()
        })
        .sum::<f64>()
        / POINTS as f64;
    let c = lnc.exp();
    taus.iter().map(|&t| (t, c * t.powf(m.drift_beta - 1.0))).collect()
}

/// The model's correlated parts in time as OU processes (time constant s, variance): the
/// drift's relaxations, then the AR(1) part read as the OU of time constant `ar1_tau_s` (a
/// model fitted in sample index is read in time so too). The white part is per sample.
pub(crate) fn time_parts(m: &NoiseModel) -> Vec<(f64, f64)> {
    let dt_min = m.sampling.as_ref().map_or(m.dt, |s| s.interval_range_s[0]);
    let mut parts: Vec<(f64, f64)> = drift_components(m, dt_min);
    if m.ar1_variance > 0.0 && m.ar1_tau_s > 0.0 {
        parts.push((m.ar1_tau_s, m.ar1_variance));
    }
    parts
}

/// The Kalman filter at `times` under the model's parts in time (white per sample, OU, the
/// drift's relaxations), run on the residuals `r` (their mean taken out: every model fits μ0)
/// and on a constant 1 at once — the gains do not depend on the data. Returns the
/// log-likelihood of `r`, −½Σ(ln Sᵢ + vᵢ²/Sᵢ) with innovations vᵢ of variance Sᵢ, and 1ᵀΣ⁻¹1.
pub(super) fn kalman(m: &NoiseModel, r: &[f64], times: &[f64]) -> (f64, f64) {
    let (ll, info) = kalman_many(m, &[r], times);
    (ll[0], info)
}

/// The Kalman filter's covariance under a model's parts in time (white per sample, OU, the
/// drift's relaxations): it does not depend on the data, so the likelihood and the whitening
/// share it and carry their own state means.
struct Filter {
    parts: Vec<(f64, f64)>,
    k: usize,
    r_white: f64,
    /// The state covariance.
    p: [[f64; MAX_STATES]; MAX_STATES],
    /// Each state's decay over the last interval.
    f: [f64; MAX_STATES],
    /// P·1: each state's covariance with the observation.
    ph: [f64; MAX_STATES],
}

/// The filter's states at most: the OU part and the drift's components.
const MAX_STATES: usize = MAX_DRIFT_COMPONENTS + 1;

impl Filter {
    fn new(m: &NoiseModel) -> Filter {
        let parts = time_parts(m);
        let k = parts.len().min(MAX_STATES);
        let mut p = [[0.0; MAX_STATES]; MAX_STATES];
        for (i, &(_, s2)) in parts.iter().take(k).enumerate() {
            p[i][i] = s2;
        }
        let r_white = m.white_variance.max(1e-9 * m.variance).max(1e-300);
        Filter { parts, k, r_white, p, f: [0.0; MAX_STATES], ph: [0.0; MAX_STATES] }
    }

    /// The prediction over an interval of `d` s: the covariance, and the decays `f` the state
    /// means are to be multiplied by ([`Filter::decay`]).
    fn advance(&mut self, d: f64) {
        let k = self.k;
        for c in 0..k {
            self.f[c] = (-d / self.parts[c].0).exp();
        }
        for a in 0..k {
            for b in 0..k {
                self.p[a][b] *= self.f[a] * self.f[b];
            }
            self.p[a][a] += self.parts[a].1 * (1.0 - self.f[a] * self.f[a]);
        }
    }

    /// A state mean carried over the last interval.
    fn decay(&self, x: &mut [f64; MAX_STATES]) {
        for c in 0..self.k {
            x[c] *= self.f[c];
        }
    }

    /// The innovation's variance at a sample whose white part is `white_scale` times the
    /// model's.
    fn innovation_variance(&mut self, white_scale: f64) -> f64 {
        let mut s = self.r_white * white_scale;
        for a in 0..self.k {
            self.ph[a] = self.p[a][..self.k].iter().sum();
            s += self.ph[a];
        }
        s.max(1e-300)
    }

    /// A state mean's prediction of the observation.
    fn predicted(&self, x: &[f64; MAX_STATES]) -> f64 {
        x[..self.k].iter().sum()
    }

    /// A state mean updated by its innovation `v` (of variance `s`).
    fn correct(&self, x: &mut [f64; MAX_STATES], v: f64, s: f64) {
        for a in 0..self.k {
            x[a] += self.ph[a] / s * v;
        }
    }

    /// The covariance after the observation (of innovation variance `s`).
    fn observed(&mut self, s: f64) {
        for a in 0..self.k {
            for b in 0..self.k {
                self.p[a][b] -= self.ph[a] * self.ph[b] / s;
            }
        }
    }
}

/// [`kalman`] on several residual vectors at the same `times` at once: the covariance and the
/// gains are shared (they do not depend on the data), so each vector more costs its state mean
/// only. Their log-likelihoods, and 1ᵀΣ⁻¹1.
fn kalman_many(m: &NoiseModel, rs: &[&[f64]], times: &[f64]) -> (Vec<f64>, f64) {
    let mut filter = Filter::new(m);
    let means: Vec<f64> = rs.iter().map(|r| r.iter().sum::<f64>() / r.len().max(1) as f64).collect();
    // a state mean per vector and one for the constant
    let mut xs = vec![[0.0; MAX_STATES]; rs.len()];
    let mut x1 = [0.0; MAX_STATES];
    let mut lls = vec![0.0; rs.len()];
    let mut info = 0.0;
    for (i, &t) in times.iter().enumerate() {
        if i > 0 {
            filter.advance(t - times[i - 1]);
            filter.decay(&mut x1);
            for x in xs.iter_mut() {
                filter.decay(x);
            }
        }
        let s = filter.innovation_variance(1.0);
        for ((x, r), (ll, mean)) in xs.iter_mut().zip(rs).zip(lls.iter_mut().zip(&means)) {
            let v = r[i] - mean - filter.predicted(x);
            *ll -= 0.5 * (s.ln() + v * v / s);
            filter.correct(x, v, s);
        }
        let v1 = 1.0 - filter.predicted(&x1);
        info += v1 * v1 / s;
        filter.correct(&mut x1, v1, s);
        filter.observed(s);
    }
    (lls, info)
}

/// Whitens vectors at `times` under the model's parts in time (white, OU, the drift's
/// relaxations; a model fitted in sample index read in time, its AR(1) part as the OU of
/// time constant `ar1_tau_s`): each vector x becomes its Kalman innovations over their
/// standard deviations, so that xᵀΣ⁻¹y is the dot product of the whitened x and y. The white
/// part's variance at sample i is `white_scale[i]` times the model's (a point standing for the
/// mean of c samples: 1/c). Unlike the likelihood, the mean is kept: a constant offset
/// between two models' predictions is information.
pub fn whiten(m: &NoiseModel, times: &[f64], white_scale: &[f64], xs: &mut [Vec<f64>]) {
    let mut filter = Filter::new(m);
    let mut x = vec![[0.0; MAX_STATES]; xs.len()];
    for (i, &t) in times.iter().enumerate() {
        if i > 0 {
            filter.advance((t - times[i - 1]).max(0.0));
            for xv in x.iter_mut() {
                filter.decay(xv);
            }
        }
        let s = filter.innovation_variance(white_scale.get(i).copied().unwrap_or(1.0));
        let sd = s.sqrt();
        for (xv, v) in x.iter_mut().zip(xs.iter_mut()) {
            let innov = v[i] - filter.predicted(xv);
            v[i] = innov / sd;
            filter.correct(xv, innov, s);
        }
        filter.observed(s);
    }
}

/// The exact Gaussian log-likelihood of residuals `r` at `times` under a model in time.
pub(super) fn log_likelihood(m: &NoiseModel, r: &[f64], times: &[f64]) -> f64 {
    if r.len() < 2 {
        return 0.0;
    }
    kalman(m, r, times).0
}

/// [`log_likelihood`] of several residual vectors at the same `times` (each as long as
/// `times`), in one pass.
pub(super) fn log_likelihoods(m: &NoiseModel, rs: &[&[f64]], times: &[f64]) -> Vec<f64> {
    if times.len() < 2 {
        return vec![0.0; rs.len()];
    }
    kalman_many(m, rs, times).0
}

/// Noise at `times` under a model in time: white per sample, the OU part by its recursion,
/// the drift on a uniform grid in time (at most [`MAX_DRIFT_GRID`] points) interpolated.
pub(super) fn synthesize<R: rand::Rng + ?Sized>(m: &NoiseModel, times: &[f64], rng: &mut R) -> Vec<f64> {
    let n = times.len();
    let mut e: Vec<f64> = (0..n)
        .map(|_| {
            let z: f64 = StandardNormal.sample(rng);
            m.white_variance.sqrt() * z
        })
        .collect();
    if m.ar1_variance > 0.0 && m.ar1_tau_s > 0.0 {
        let s = m.ar1_variance.sqrt();
        let z0: f64 = StandardNormal.sample(rng);
        let mut o = s * z0;
        for i in 0..n {
            if i > 0 {
                let phi = (-(times[i] - times[i - 1]) / m.ar1_tau_s).exp();
                let z: f64 = StandardNormal.sample(rng);
                o = phi * o + s * (1.0 - phi * phi).sqrt() * z;
            }
            e[i] += o;
        }
    }
    if m.drift_amplitude > 0.0 && n > 1 {
        let span = times[n - 1] - times[0];
        let points = ((span / m.dt).ceil() as usize + 2).min(MAX_DRIFT_GRID);
        let step = span / (points - 1) as f64;
        // the drift per grid sample: (Δ₀/step)·A at the lowest frequency, 1/(span) Hz
        let drift = NoiseModel {
            white_variance: 0.0,
            ar1_variance: 0.0,
            drift_amplitude: m.drift_amplitude * m.dt / step,
            drift_n: span / step,
            sampling: None,
            ..m.clone()
        };
        let grid = drift.synthesize(points, rng);
        for (x, &t) in e.iter_mut().zip(times) {
            let u = ((t - times[0]) / step).clamp(0.0, (points - 1) as f64);
            let k = (u.floor() as usize).min(points - 2);
            let w = u - k as f64;
            *x += grid[k] * (1.0 - w) + grid[k + 1] * w;
        }
    }
    e
}
