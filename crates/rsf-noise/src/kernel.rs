//! The covariance the noise model implies between samples at their times, applied to vectors:
//! Σx in O(n·K) for K correlated parts, never forming Σ.
//!
//! Σ is the model's form in time (`sampling.rs`): white noise per sample (its variance scaled
//! per point, so that a bin mean of c samples has σ²/c), plus OU processes — the AR(1) part with
//! its correlation time, and the drift as its sum of relaxations — each with covariance
//! s²·exp(−|tᵢ − tⱼ|/τ). An exponential kernel applied to a vector is two recursions, one
//! forward (the terms with tⱼ ≤ tᵢ) and one backward (tⱼ > tᵢ), each factor ≤ 1.
//!
//! This is what a fit needs for its parameters' covariance under the noise model, the
//! sandwich H⁻¹ JᵀW²ΣW²J H⁻¹ (`rsf-fit`'s `fit/covariance.rs`).

use super::noise::NoiseModel;
use super::state_space::time_parts;

impl NoiseModel {
    /// Σx for `x` at sample `times` (s, non-decreasing): the white part's variance at point i
    /// is `white_scale[i]` times the model's (1 where absent), the correlated parts are the
    /// model's in time.
    pub fn covariance_times(&self, times: &[f64], white_scale: &[f64], x: &[f64]) -> Vec<f64> {
        let n = x.len().min(times.len());
        let mut y: Vec<f64> =
            (0..n).map(|i| self.white_variance * white_scale.get(i).copied().unwrap_or(1.0) * x[i]).collect();
        for (tau, s2) in time_parts(self) {
            if !(tau > 0.0 && s2 > 0.0) {
                continue;
            }
            // forward: Σ_{j ≤ i} e^{−(tᵢ − tⱼ)/τ} xⱼ
            let mut f = 0.0;
            for i in 0..n {
                if i > 0 {
                    f *= (-(times[i] - times[i - 1]).max(0.0) / tau).exp();
                }
                f += x[i];
                y[i] += s2 * f;
            }
            // backward: Σ_{j > i} e^{−(tⱼ − tᵢ)/τ} xⱼ
            let mut g = 0.0;
            for i in (0..n.saturating_sub(1)).rev() {
                g = (g + x[i + 1]) * (-(times[i + 1] - times[i]).max(0.0) / tau).exp();
                y[i] += s2 * g;
            }
        }
        y
    }

    /// The correlated parts in time as (time constant s, variance), for a reader who wants Σ
    /// written out: the drift's relaxations, then the AR(1) part.
    pub fn parts_in_time(&self) -> Vec<(f64, f64)> {
        time_parts(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// Σx by the recursions equals the dense Σ written from the parts, on a variably sampled
    /// record (bursts and a hold) with all three parts and per-point white scales.
    #[test]
    fn recursions_equal_the_dense_matrix() {
        let mut times = vec![];
        let mut t = 3.0;
        for i in 0..300 {
            t += if i < 100 {
                0.01
            } else if i < 140 {
                2.5
            } else {
                0.05
            };
            times.push(t);
        }
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let r = NoiseModel { drift_amplitude: 0.0, ..NoiseModel::white(1e-8, times.len(), 0.05) };
        // a model with white, AR(1) and drift: fitted to synthetic noise so its fields are coherent
        let m0 = NoiseModel {
            ar1_variance: 4e-8,
            ar1_phi: 0.9,
            ar1_tau_s: 0.4,
            drift_amplitude: 2e-7,
            drift_beta: 1.2,
            ..r
        };
        let e = m0.synthesize_at(&times, &mut rng);
        let (m, _) = NoiseModel::fit_at(&e, &times);
        let parts = m.parts_in_time();
        let scale: Vec<f64> = (0..times.len()).map(|i| 1.0 / (1 + i % 3) as f64).collect();
        let x: Vec<f64> = (0..times.len()).map(|i| ((i as f64) * 0.37).sin() + 0.2).collect();
        let y = m.covariance_times(&times, &scale, &x);
        let mut worst: f64 = 0.0;
        for i in 0..times.len() {
            let mut d = m.white_variance * scale[i] * x[i];
            for j in 0..times.len() {
                for &(tau, s2) in &parts {
                    d += s2 * (-(times[i] - times[j]).abs() / tau).exp() * x[j];
                }
            }
            worst = worst.max((d - y[i]).abs() / d.abs().max(1e-30));
        }
        assert!(worst < 1e-9, "relative error {worst}");
        assert!(!parts.is_empty());
    }
}
