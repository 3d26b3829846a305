//! The noise model at a record's sample times: which form applies (in sample index for a
//! uniformly sampled record, `noise.rs`; in time for a variably sampled one, `sampling.rs`), so
//! that neither of those files depends on the other's choice.

use super::noise::{MAX_DRIFT_GRID, NoiseModel};
use super::sampling;
use super::state_space;

/// The noise model at sample times: in sample index for a uniformly sampled record, in time
/// for a variably sampled one (`sampling.rs`).
impl NoiseModel {
    /// Fits the model to residuals `r` at sample `times` (s): in sample index for a uniformly
    /// sampled record ([`NoiseModel::fit`]), in time for a variably sampled one
    /// (`sampling.rs`). Returns the model and the residuals' log-likelihood under it
    /// ([`NoiseModel::log_likelihood_at`]).
    pub fn fit_at(r: &[f64], times: &[f64]) -> (NoiseModel, f64) {
        if sampling::is_variable(times) {
            sampling::fit(r, times)
        } else {
            let m = NoiseModel::fit(r, sampling::median_interval(times));
            let ll = m.log_likelihood(r);
            (m, ll)
        }
    }

    /// The log-likelihood of residuals `r` at sample `times` under this model: Whittle's for
    /// a model fitted in sample index ([`NoiseModel::log_likelihood`]), the exact Gaussian one
    /// of the state-space form for a model in time.
    pub fn log_likelihood_at(&self, r: &[f64], times: &[f64]) -> f64 {
        match &self.sampling {
            None => self.log_likelihood(r),
            Some(_) => state_space::log_likelihood(self, r, times),
        }
    }

    /// [`NoiseModel::log_likelihood_at`] of several residual vectors at the same sample
    /// `times` (each as long as `times`): for a model in time one filter pass serves them all.
    pub fn log_likelihoods_at(&self, rs: &[&[f64]], times: &[f64]) -> Vec<f64> {
        match &self.sampling {
            None => rs.iter().map(|r| self.log_likelihood(r)).collect(),
            Some(_) => state_space::log_likelihoods(self, rs, times),
        }
    }

    /// Noise at the sample `times` (s). For a model in time, every part in time
    /// (`sampling.rs`). Otherwise the white and AR(1) parts per sample, the drift part in
    /// time — drawn on a uniform grid at the model's median interval and interpolated — so
    /// that a record sampled densely after steps and sparsely in holds gets its drift where
    /// real drift is, in time, not in sample count.
    pub fn synthesize_at<R: rand::Rng + ?Sized>(&self, times: &[f64], rng: &mut R) -> Vec<f64> {
        if self.sampling.is_some() {
            return state_space::synthesize(self, times, rng);
        }
        let n = times.len();
        let short = NoiseModel { drift_amplitude: 0.0, ..self.clone() };
        let mut e = short.synthesize(n, rng);
        if self.drift_amplitude > 0.0 && n > 1 && self.dt > 0.0 {
            let t0 = times[0];
            let span = times[n - 1] - t0;
            let m = ((span / self.dt).ceil() as usize + 2).min(MAX_DRIFT_GRID);
            let step = span / (m - 1) as f64;
            let drift = NoiseModel { white_variance: 0.0, ar1_variance: 0.0, ..self.clone() };
            let grid = drift.synthesize(m, rng);
            for (x, &t) in e.iter_mut().zip(times) {
                let u = ((t - t0) / step).clamp(0.0, (m - 1) as f64);
                let k = (u.floor() as usize).min(m - 2);
                let w = u - k as f64;
                *x += grid[k] * (1.0 - w) + grid[k + 1] * w;
            }
        }
        e
    }
}
