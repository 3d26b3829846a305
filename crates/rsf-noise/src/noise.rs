//! The noise model of a record's residuals, fitted to their spectrum: white noise, an AR(1)
//! (Lorentzian) part and a power-law part S ∝ f^(−β) — the slow 1/f-like drift of real friction
//! records (gouge layer evolution, temperature, servo and sensor drift).
//!
//! **Estimate.** The periodogram of the residuals (sample index as time; the median sampling
//! interval converts to Hz), averaged in bins of logarithmically growing width, is fitted by
//! the Whittle likelihood −Σ m_b (ln S_b + Ī_b/S_b). The shape parameters (β, φ) are searched
//! on a grid; at each grid point the three non-negative amplitudes are found by Whittle's
//! scoring (iteratively reweighted least squares with weights m/S²). Standard errors: the
//! Fisher information of the amplitudes, and the curvature of the profile likelihood along β
//! and φ.
//!
//! **Use.** The likelihood of a model's residuals under this noise is the Whittle quadratic
//! form Q(r) = Σ_j |R_j|²/(n S(f_j)) (the Gaussian rᵀΣ⁻¹r for a stationary covariance Σ), so
//! an extension's gain is Q(r_base) − Q(r_ext): an improvement at frequencies where the noise
//! has much power (slow drift) counts for little, one at frequencies where it is quiet (a
//! transient after a step) for much. The information for a slowly varying effect is
//! n_eff = n σ²/S(f₁) at the lowest resolved frequency f₁ = 1/n: n for white noise,
//! n(1 − ρ)/(1 + ρ) for AR(1), far less under 1/f drift. The null replicates draw noise with
//! the fitted spectrum ([`NoiseModel::synthesize`]).
//!
//! A variably sampled record (100 Hz after a step, 1 Hz in a hold) gets the same three parts
//! defined in time instead of sample index, an exact state-space likelihood and replicates in
//! time: `sampling.rs` ([`NoiseModel::fit_at`] chooses, in `timed.rs`).

use rand_distr::{Distribution, StandardNormal};
use rustfft::num_complex::Complex;
use serde::Serialize;

use super::whittle::{amplitude_stderr, amplitudes, ar1_shape, grid_stderr, periodogram};

/// Periodogram ordinates kept one by one at the lowest frequencies, where a drift's power is.
pub(super) const SINGLE_BINS: usize = 12;
/// Bins grow by this factor above them: ~150 bins for 10⁵ samples.
const BIN_GROWTH: f64 = 1.06;
/// Power-law exponents tried: from mild (β = 0.4) to a random walk (β = 2).
pub(super) const BETAS: [f64; 9] = [0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0];
/// AR(1) coefficients per sample tried (0: no AR part).
const PHIS: [f64; 12] = [0.0, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.98, 0.99, 0.995, 0.998, 0.999];
/// The drift of a replicate is drawn on at most this many time points (a 10⁵ s record at
/// 25 ms), then interpolated.
pub(super) const MAX_DRIFT_GRID: usize = 1 << 22;

/// The fitted noise spectrum of a residual series, per sample: S(f) for f in cycles per sample
/// (0 < f ≤ 1/2), normalised so that white noise of variance σ² has S = σ².
#[derive(Clone, Debug, Serialize)]
pub struct NoiseModel {
    /// White-noise variance.
    pub white_variance: f64,
    /// AR(1) part: its variance and lag-one coefficient per sample.
    pub ar1_variance: f64,
    /// AR(1) coefficient per sample.
    pub ar1_phi: f64,
    /// AR(1) correlation time, s (−dt/ln φ; 0 without an AR part).
    pub ar1_tau_s: f64,
    /// Power-law part: S = `drift_amplitude` · (f n)^(−β), its power at the lowest resolved
    /// frequency 1/n.
    pub drift_amplitude: f64,
    /// The power-law exponent β (1: flicker noise; 2: a random walk).
    pub drift_beta: f64,
    /// Standard errors of white variance, AR(1) variance, drift amplitude, β and φ (NaN where
    /// the likelihood does not bound them).
    pub stderr: NoiseStderr,
    /// Residual variance.
    pub variance: f64,
    /// Share of the residual variance in the power-law (drift) part.
    pub drift_share: f64,
    /// Effective number of independent samples for a slowly varying effect, n σ²/S(1/n).
    pub n_effective: f64,
    /// Samples.
    pub n: usize,
    /// Median sampling interval, s.
    pub dt: f64,
    /// The binned periodogram the model was fitted to: frequency (Hz), mean power, and the
    /// model's power there (the residual-spectrum figure of the report). For a variably sampled
    /// record, each stretch's power is scaled to the median interval (× Δ/`dt`), so that
    /// `power × dt` is friction²/Hz throughout.
    pub periodogram: Vec<[f64; 3]>,
    /// How the sampling entered the model: absent for a uniformly sampled record (the
    /// spectrum in sample index); for a variably sampled one, the stretches of one interval
    /// the spectrum in time was fitted to (`sampling.rs`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampling: Option<VariableSampling>,
    /// The drift part's reference length in median intervals: the lowest resolved frequency
    /// is 1/(`drift_n` · `dt`) Hz (n for a uniformly sampled record, span/`dt` otherwise).
    #[serde(skip)]
    pub(super) drift_n: f64,
}

/// A variably sampled record's stretches of one sampling interval, from which its noise
/// spectrum in time was estimated.
#[derive(Clone, Debug, Serialize)]
pub struct VariableSampling {
    /// Stretches of one interval long enough for a spectrum.
    pub stretches: usize,
    /// Distinct sampling intervals among them.
    pub intervals: usize,
    /// Shortest and longest of those intervals, s.
    pub interval_range_s: [f64; 2],
    /// Samples in those stretches (the rest enter the likelihood, not the spectrum).
    pub samples_in_stretches: usize,
    /// Time span of the record, s.
    pub span_s: f64,
    /// Time constants of the OU processes whose sum stands for the drift part in the
    /// likelihood, s.
    pub drift_time_constants_s: Vec<f64>,
}

/// Standard errors of the noise model's parameters.
#[derive(Clone, Debug, Default, Serialize)]
pub struct NoiseStderr {
    /// Of the white variance.
    pub white_variance: f64,
    /// Of the AR(1) variance.
    pub ar1_variance: f64,
    /// Of the drift amplitude.
    pub drift_amplitude: f64,
    /// Of β.
    pub drift_beta: f64,
    /// Of φ.
    pub ar1_phi: f64,
}

impl NoiseStderr {
    /// From the amplitudes' standard errors `se` (of amplitudes `a`) and the profile-curvature
    /// errors of β and φ, each computed only when its part is in the model (NaN otherwise).
    pub(super) fn of(se: [f64; 3], a: &[f64; 3], beta: impl FnOnce() -> f64, phi: impl FnOnce() -> f64) -> Self {
        NoiseStderr {
            white_variance: se[0],
            ar1_variance: se[1],
            drift_amplitude: se[2],
            drift_beta: if a[2] > 0.0 { beta() } else { f64::NAN },
            ar1_phi: if a[1] > 0.0 { phi() } else { f64::NAN },
        }
    }
}

/// The three spectral shapes at frequency `f` (cycles per sample) for `n` samples.
fn basis(f: f64, n: f64, beta: f64, phi: f64) -> [f64; 3] {
    [1.0, ar1_shape(f, phi), (f * n).powf(-beta)]
}

/// Bins of the periodogram: (mean frequency in cycles per sample, mean power, ordinates).
fn bins(p: &[f64], n: usize) -> Vec<(f64, f64, f64)> {
    let mut out = vec![];
    let mut j = 0;
    while j < p.len() {
        let width = if j < SINGLE_BINS { 1 } else { ((j as f64) * (BIN_GROWTH - 1.0)).ceil().max(1.0) as usize };
        let end = (j + width).min(p.len());
        let m = (end - j) as f64;
        let f = (j + 1..=end).map(|k| k as f64 / n as f64).sum::<f64>() / m;
        out.push((f, p[j..end].iter().sum::<f64>() / m, m));
        j = end;
    }
    out
}

impl NoiseModel {
    /// Fits the model to residuals `r` sampled every `dt` seconds (median interval), in sample
    /// index.
    pub fn fit(r: &[f64], dt: f64) -> NoiseModel {
        let n = r.len();
        let mean = r.iter().sum::<f64>() / n.max(1) as f64;
        let var = r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n.max(1) as f64;
        if n < 16 || !(var > 0.0) {
            return Self::white(var.max(0.0), n, dt);
        }
        let p = periodogram(r);
        let b = bins(&p, n);
        // BIC on the Whittle likelihood: ½ ln N per parameter, N the periodogram ordinates
        let penalty = 0.5 * (p.len() as f64).ln();
        let mut best = (f64::INFINITY, 0, 0, [var, 0.0, 0.0]);
        let mut table = vec![vec![f64::INFINITY; PHIS.len()]; BETAS.len()];
        for (ib, &beta) in BETAS.iter().enumerate() {
            for (ip, &phi) in PHIS.iter().enumerate() {
                let x: Vec<[f64; 3]> = b.iter().map(|&(f, _, _)| basis(f, n as f64, beta, phi)).collect();
                let (a, v) = amplitudes(&b, &x, var, phi > 0.0, penalty);
                table[ib][ip] = v;
                if v < best.0 {
                    best = (v, ib, ip, a);
                }
            }
        }
        let (_, ib, ip, a) = best;
        let (beta, phi) = (BETAS[ib], PHIS[ip]);
        let x: Vec<[f64; 3]> = b.iter().map(|&(f, _, _)| basis(f, n as f64, beta, phi)).collect();
        let se = amplitude_stderr(&b, &x, &a);
        let beta_profile: Vec<f64> = (0..BETAS.len()).map(|i| table[i][ip]).collect();
        let phi_profile: Vec<f64> = table[ib].clone();
        let model_power = |f: f64| {
            let xb = basis(f, n as f64, beta, phi);
            a[0] * xb[0] + a[1] * xb[1] + a[2] * xb[2]
        };
        // the drift part's share of the variance: ∫ S_drift df over the resolved band, as
        // the sum over the Fourier frequencies (two-sided: ×2/n)
        let drift_var: f64 = (1..=n / 2).map(|j| a[2] * (j as f64).powf(-beta)).sum::<f64>() * 2.0 / n as f64;
        let s1 = model_power(1.0 / n as f64);
        NoiseModel {
            white_variance: a[0],
            ar1_variance: a[1],
            ar1_phi: phi,
            ar1_tau_s: if phi > 0.0 { -dt / phi.ln() } else { 0.0 },
            drift_amplitude: a[2],
            drift_beta: beta,
            stderr: NoiseStderr::of(
                se,
                &a,
                || grid_stderr(&BETAS, &beta_profile, ib),
                || grid_stderr(&PHIS, &phi_profile, ip),
            ),
            variance: var,
            drift_share: (drift_var / var).clamp(0.0, 1.0),
            n_effective: (n as f64 * var / s1).clamp(2.0, n as f64),
            n,
            dt,
            periodogram: b.iter().map(|&(f, ibar, _)| [f / dt, ibar, model_power(f)]).collect(),
            sampling: None,
            drift_n: n as f64,
        }
    }

    /// White noise of variance `var`.
    pub fn white(var: f64, n: usize, dt: f64) -> NoiseModel {
        NoiseModel {
            white_variance: var,
            ar1_variance: 0.0,
            ar1_phi: 0.0,
            ar1_tau_s: 0.0,
            drift_amplitude: 0.0,
            drift_beta: BETAS[0],
            stderr: NoiseStderr::default(),
            variance: var,
            drift_share: 0.0,
            n_effective: n.max(2) as f64,
            n,
            dt,
            periodogram: vec![],
            sampling: None,
            drift_n: n as f64,
        }
    }

    /// S at `f` cycles per sample, for a series of `n` samples (the drift part's scale is set
    /// by the series the model was fitted to).
    pub fn power(&self, f: f64) -> f64 {
        let xb = basis(f, self.drift_n, self.drift_beta, self.ar1_phi);
        (self.white_variance * xb[0] + self.ar1_variance * xb[1] + self.drift_amplitude * xb[2]).max(1e-300)
    }

    /// The drift part's two-sided power spectral density at `nu` Hz, friction²/Hz.
    pub fn drift_psd(&self, nu: f64) -> f64 {
        self.drift_amplitude * (nu * self.dt * self.drift_n).powf(-self.drift_beta) * self.dt
    }

    /// Parameters of the model: the white variance, and an amplitude and a shape for each of
    /// the AR(1) and drift parts it uses.
    pub fn parameters(&self) -> usize {
        1 + 2 * usize::from(self.ar1_variance > 0.0) + 2 * usize::from(self.drift_amplitude > 0.0)
    }

    /// The Whittle log-likelihood of residuals `r` under this spectrum,
    /// −Σ_j (ln S(f_j) + I_j/S(f_j)) over the Fourier frequencies 0 < f_j ≤ 1/2 (the mean left
    /// out): for white noise of the residuals' own variance, (n/2)(−ln σ² − 1), the Gaussian
    /// log-likelihood of a least-squares fit up to a constant.
    pub fn log_likelihood(&self, r: &[f64]) -> f64 {
        let n = r.len();
        if n < 2 {
            return 0.0;
        }
        periodogram(r)
            .iter()
            .enumerate()
            .map(|(k, &i)| {
                let s = self.power((k + 1) as f64 / n as f64);
                -(s.ln() + i / s)
            })
            .sum()
    }

    /// The Whittle quadratic form Q(r) = Σ_j |R_j|²/(n S(f_j)), two-sided, the mean left out
    /// (every model fits μ0): rᵀΣ⁻¹r for the fitted stationary covariance.
    pub fn quadratic_form(&self, r: &[f64]) -> f64 {
        let n = r.len();
        if n < 2 {
            return 0.0;
        }
        let p = periodogram(r);
        let sum: f64 = p
            .iter()
            .enumerate()
            .map(|(k, &i)| {
                let j = k + 1;
                // the Nyquist ordinate (n even) appears once, the others twice
                let w = if 2 * j == n { 1.0 } else { 2.0 };
                w * i / self.power(j as f64 / n as f64)
            })
            .sum();
        sum
    }

    /// A series of `n` samples with this spectrum (Gaussian, stationary): drawn by spectral
    /// synthesis on 2n samples, of which the first n are kept (no wrap-around at the ends).
    pub fn synthesize<R: rand::Rng + ?Sized>(&self, n: usize, rng: &mut R) -> Vec<f64> {
        let m = 2 * n.max(1);
        let mut buf = vec![Complex::new(0.0, 0.0); m];
        for j in 1..=m / 2 {
            // frequencies of the doubled series, in cycles per sample
            let f = j as f64 / m as f64;
            let s = self.power(f) * m as f64;
            let (z1, z2): (f64, f64) = (StandardNormal.sample(rng), StandardNormal.sample(rng));
            if 2 * j == m {
                buf[j] = Complex::new(s.sqrt() * z1, 0.0);
            } else {
                let c = Complex::new(z1, z2) * (s / 2.0).sqrt();
                buf[j] = c;
                buf[m - j] = c.conj();
            }
        }
        super::fft::plan(m, rustfft::FftDirection::Inverse).process(&mut buf);
        buf[..n].iter().map(|c| c.re / m as f64).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn white(n: usize, s: f64, seed: u64) -> Vec<f64> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..n)
            .map(|_| {
                let z: f64 = StandardNormal.sample(&mut rng);
                s * z
            })
            .collect()
    }

    /// AR(1) by its recursion — a generator other than the spectral synthesis under test.
    fn ar1(n: usize, s: f64, phi: f64, seed: u64) -> Vec<f64> {
        let z = white(n, s, seed);
        let mut e = vec![z[0]; n];
        for i in 1..n {
            e[i] = phi * e[i - 1] + (1.0 - phi * phi).sqrt() * z[i];
        }
        e
    }

    /// A random walk's increments summed: β = 2 drift (also not by spectral synthesis).
    fn walk(n: usize, s: f64, seed: u64) -> Vec<f64> {
        let z = white(n, s, seed);
        z.iter()
            .scan(0.0, |acc, x| {
                *acc += x;
                Some(*acc)
            })
            .collect()
    }

    #[test]
    fn white_noise_is_found_white() {
        let r = white(20_000, 2e-4, 1);
        let m = NoiseModel::fit(&r, 0.1);
        assert!((m.white_variance / 4e-8 - 1.0).abs() < 0.05, "{m:?}");
        assert!(m.drift_share < 0.01 && m.n_effective > 0.8 * 20_000.0, "{} {}", m.drift_share, m.n_effective);
    }

    #[test]
    fn ar1_noise_gives_the_lag_one_n_eff() {
        let r = ar1(20_000, 2e-4, 0.9, 2);
        let m = NoiseModel::fit(&r, 0.1);
        let lag1 = n_eff_ar1(0.9, 20_000.0);
        assert!((m.n_effective / lag1 - 1.0).abs() < 0.35, "n_eff {} vs {lag1}: {m:?}", m.n_effective);
        assert!((m.ar1_phi - 0.9).abs() < 0.06 && m.drift_share < 0.2, "{m:?}");
    }

    fn n_eff_ar1(rho: f64, n: f64) -> f64 {
        n * (1.0 - rho) / (1.0 + rho)
    }

    #[test]
    fn drift_on_white_noise_is_measured() {
        let w = white(30_000, 2e-4, 3);
        let d = walk(30_000, 2e-6, 4);
        let r: Vec<f64> = w.iter().zip(&d).map(|(a, b)| a + b).collect();
        let m = NoiseModel::fit(&r, 0.1);
        let var_d = d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64;
        assert!(m.drift_amplitude > 0.0 && m.drift_beta >= 1.6, "{m:?}");
        assert!(m.drift_share > 0.3 * var_d / (var_d + 4e-8), "share {} vs {}", m.drift_share, var_d / (var_d + 4e-8));
        // far less information for a slow effect than the lag-one correlation claims
        assert!(m.n_effective < 0.05 * 30_000.0, "{}", m.n_effective);
    }

    #[test]
    fn synthesis_reproduces_the_spectrum_it_is_given() {
        let model = NoiseModel::fit(&ar1(20_000, 3e-4, 0.8, 5), 0.05);
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let x = model.synthesize(20_000, &mut rng);
        let refit = NoiseModel::fit(&x, 0.05);
        assert!((refit.variance / model.variance - 1.0).abs() < 0.1, "{} {}", refit.variance, model.variance);
        assert!((refit.n_effective / model.n_effective - 1.0).abs() < 0.35, "{refit:?}\n{model:?}");
    }

    #[test]
    fn the_quadratic_form_is_the_white_sum_of_squares() {
        let r = white(4_096, 1.0, 6);
        let m = NoiseModel::white(1.0, r.len(), 1.0);
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        let ss: f64 = r.iter().map(|x| (x - mean).powi(2)).sum();
        assert!((m.quadratic_form(&r) / ss - 1.0).abs() < 1e-9, "{} {ss}", m.quadratic_form(&r));
    }
}
