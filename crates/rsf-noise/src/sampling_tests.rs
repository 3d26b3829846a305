//! Tests of the noise model in time (`sampling.rs`, `state_space.rs`): each noise made by its own recursion at the
//! sample times, not by the synthesis under test.

use super::*;
use crate::state_space::whiten;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// A lab's variable sampling: 100 Hz for 8 s after each of `events` changes, then 2 Hz for
/// 300 s — 800 + 600 samples per event.
fn lab_times(events: usize) -> Vec<f64> {
    let mut t = vec![];
    let mut t0 = 0.0;
    for _ in 0..events {
        t.extend((0..800).map(|i| t0 + 0.01 * i as f64));
        t.extend((0..600).map(|i| t0 + 8.0 + 0.5 * i as f64));
        t0 += 308.0;
    }
    t
}

fn normals(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n).map(|_| StandardNormal.sample(&mut rng)).collect()
}

/// OU noise by its exact recursion at the sample times — the generator the records
/// used, not this module's synthesis.
fn ou(times: &[f64], s: f64, tau: f64, seed: u64) -> Vec<f64> {
    let z = normals(times.len(), seed);
    let mut e = vec![s * z[0]; times.len()];
    for i in 1..times.len() {
        let phi = (-(times[i] - times[i - 1]) / tau).exp();
        e[i] = phi * e[i - 1] + s * (1.0 - phi * phi).sqrt() * z[i];
    }
    e
}

/// `base` plus a random walk in time of `step`·√(Δt) per sample.
fn with_walk(times: &[f64], base: &[f64], step: f64, seed: u64) -> Vec<f64> {
    let z = normals(times.len(), seed);
    let mut walk = 0.0;
    (0..times.len())
        .map(|i| {
            if i > 0 {
                walk += step * (times[i] - times[i - 1]).sqrt() * z[i];
            }
            base[i] + walk
        })
        .collect()
}

#[test]
fn stretches_split_at_a_change_of_interval_and_tolerate_jitter() {
    let mut t = lab_times(3);
    for (i, x) in t.iter_mut().enumerate() {
        *x += 1e-4 * ((i * 7919) % 13) as f64 / 13.0; // ±1 % of 0.01 s
    }
    let st = stretches(&t);
    assert!(is_variable(&t));
    let long: Vec<_> = st.iter().filter(|s| s.len >= MIN_STRETCH).collect();
    assert_eq!(long.len(), 6, "{st:?}");
    assert!(long.iter().all(|s| (s.dt - 0.01).abs() < 1e-4 || (s.dt - 0.5).abs() < 1e-3), "{long:?}");
    let uniform: Vec<f64> = (0..5000).map(|i| 0.1 * i as f64).collect();
    assert!(!is_variable(&uniform));
    // a removed spike (one interval doubled) leaves a record uniform; seconds left out after a
    // break (a break-timing mask: 8 samples) make it a record in time, where a gap is a gap
    let spike: Vec<f64> = uniform.iter().copied().enumerate().filter(|&(i, _)| i != 2500).map(|(_, t)| t).collect();
    assert!(!is_variable(&spike));
    let masked: Vec<f64> =
        uniform.iter().copied().enumerate().filter(|&(i, _)| !(2500..2508).contains(&i)).map(|(_, t)| t).collect();
    assert!(is_variable(&masked));
}

/// The case: AR(1) noise in time (τ = 3 s) on variable sampling is not drift, and
/// its information for a slow effect is far above the index model's collapse to n_eff ≈ 2.
#[test]
fn ou_noise_on_variable_sampling_is_ou_not_drift() {
    let t = lab_times(12);
    let r = ou(&t, 2e-4, 3.0, 1);
    let m = NoiseModel::fit_at(&r, &t).0;
    assert!(m.sampling.is_some());
    assert!(m.drift_share < 0.15, "{m:?}");
    assert!(m.ar1_tau_s > 1.5 && m.ar1_tau_s < 6.0, "τ {}", m.ar1_tau_s);
    // about 1 + T/(2τ) = 617 independent values for a constant offset (the OU part's
    // information does not grow with the sampling rate)
    assert!(m.n_effective > 300.0 && m.n_effective < 1_200.0, "n_eff {}", m.n_effective);
    // the index model of the same residuals reads drift
    let index = NoiseModel::fit(&r, median_interval(&t));
    assert!(index.n_effective < 0.2 * m.n_effective, "{} vs {}", index.n_effective, m.n_effective);
}

/// A random walk in time on white noise is found as drift (β near 2), with little
/// information for a slow effect.
#[test]
fn drift_in_time_on_variable_sampling_is_drift() {
    let t = lab_times(12);
    let w: Vec<f64> = normals(t.len(), 2).iter().map(|z| 2e-4 * z).collect();
    let r = with_walk(&t, &w, 3e-6, 3);
    let m = NoiseModel::fit_at(&r, &t).0;
    assert!(m.drift_amplitude > 0.0 && m.drift_beta >= 1.4, "{m:?}");
    let mean = r.iter().sum::<f64>() / r.len() as f64;
    let var: f64 = r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / r.len() as f64;
    let var_w = 4e-8;
    assert!(m.drift_share > 0.3 * (var - var_w) / var, "share {} vs {}", m.drift_share, (var - var_w) / var);
    assert!(m.n_effective < 0.05 * t.len() as f64, "{}", m.n_effective);
}

/// The Kalman likelihood of white noise under a white model is the Gaussian one.
#[test]
fn the_state_space_likelihood_of_white_noise_is_gaussian() {
    let t = lab_times(2);
    let r: Vec<f64> = normals(t.len(), 4).iter().map(|z| 3e-4 * z).collect();
    let mut m = NoiseModel::white(9e-8, r.len(), 0.01);
    m.sampling = Some(VariableSampling {
        stretches: 4,
        intervals: 2,
        interval_range_s: [0.01, 0.5],
        samples_in_stretches: r.len(),
        span_s: t[t.len() - 1],
        drift_time_constants_s: vec![],
    });
    let mean = r.iter().sum::<f64>() / r.len() as f64;
    let ss: f64 = r.iter().map(|x| (x - mean).powi(2)).sum();
    let expect = -0.5 * (r.len() as f64 * 9e-8f64.ln() + ss / 9e-8);
    assert!((m.log_likelihood_at(&r, &t) - expect).abs() < 1e-6 * expect.abs());
}

/// Replicates drawn in time from a fitted model give back its parts.
#[test]
fn synthesis_in_time_reproduces_the_model() {
    let t = lab_times(12);
    let r = ou(&t, 2e-4, 3.0, 5);
    let m = NoiseModel::fit_at(&r, &t).0;
    let x = m.synthesize_at(&t, &mut ChaCha8Rng::seed_from_u64(6));
    let refit = NoiseModel::fit_at(&x, &t).0;
    let total = |m: &NoiseModel| m.white_variance + m.ar1_variance;
    assert!((total(&refit) / total(&m) - 1.0).abs() < 0.15, "{} {}", total(&refit), total(&m));
    assert!((refit.ar1_tau_s / m.ar1_tau_s - 1.0).abs() < 0.3, "{} {}", refit.ar1_tau_s, m.ar1_tau_s);
    assert!((refit.n_effective / m.n_effective - 1.0).abs() < 0.5, "{} {}", refit.n_effective, m.n_effective);
}

/// The whitening of `rsf design` is Σ^(-1/2): whitened dot products equal xᵀΣ⁻¹y for the dense
/// covariance of white (scaled per sample) plus OU noise, solved directly.
#[test]
fn whitening_gives_the_dense_covariances_quadratic_forms() {
    let times: Vec<f64> = (0..120).map(|i| 0.1 * i as f64 + 0.02 * ((i * 7 % 5) as f64)).collect();
    let n = times.len();
    let (white, ar, tau) = (4e-8, 9e-8, 1.5);
    let m = NoiseModel { ar1_variance: ar, ar1_tau_s: tau, ar1_phi: 0.9, ..NoiseModel::white(white, n, 0.1) };
    let scale: Vec<f64> = (0..n).map(|i| 1.0 / (1.0 + (i % 4) as f64)).collect();
    let sigma = nalgebra::DMatrix::from_fn(n, n, |i, j| {
        ar * (-(times[i] - times[j]).abs() / tau).exp() + if i == j { white * scale[i] } else { 0.0 }
    });
    let x: Vec<f64> = normals(n, 11).iter().map(|z| 1e-4 * z).collect();
    let y: Vec<f64> = (0..n).map(|i| 1e-4 * (0.3 * times[i]).sin() + 2e-4).collect();
    let chol = sigma.cholesky().unwrap();
    let dense = |a: &[f64], b: &[f64]| {
        let sb = chol.solve(&nalgebra::DVector::from_column_slice(b));
        nalgebra::DVector::from_column_slice(a).dot(&sb)
    };
    let mut w = vec![x.clone(), y.clone()];
    whiten(&m, &times, &scale, &mut w);
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>();
    for (got, want) in
        [(dot(&w[0], &w[0]), dense(&x, &x)), (dot(&w[0], &w[1]), dense(&x, &y)), (dot(&w[1], &w[1]), dense(&y, &y))]
    {
        assert!((got / want - 1.0).abs() < 1e-9, "{got} vs {want}");
    }
}

/// Whether the noise has a drift is the exact likelihood's choice, not the pooled spectra's: a
/// random walk of 3e-6/√s on OU noise (σ 2e-4, τ 3 s) that Whittle's estimate leaves out is
/// worth 10 in the exact likelihood's BIC, and the model keeps it. (On the main before, the
/// model was Whittle's, with no drift.)
#[test]
fn the_exact_likelihood_chooses_whether_there_is_a_drift() {
    let t = lab_times(12);
    let r = with_walk(&t, &ou(&t, 2e-4, 3.0, 26), 3e-6, 126);
    let n = r.len();
    let mean = r.iter().sum::<f64>() / n as f64;
    let var = r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
    let st = stretches(&t);
    let pl = pools(&r, &t, &st);
    let w = Whittle { pl: &pl, var, dt0: median_interval(&t), span: t[n - 1] - t[0], n, st: &st };
    let whittle = w.estimate(&|_| true).unwrap();
    assert_eq!(whittle.drift_amplitude, 0.0, "{whittle:?}");
    let bic = |m: &NoiseModel| kalman(m, &r, &t).0 - 0.5 * (n as f64).ln() * m.parameters() as f64;
    let (m, ll) = NoiseModel::fit_at(&r, &t);
    assert!(m.drift_amplitude > 0.0, "{m:?}");
    assert_eq!(ll, kalman(&m, &r, &t).0);
    assert!(bic(&m) > bic(&whittle) + 5.0, "{} vs {}", bic(&m), bic(&whittle));
}

/// Several residual vectors scored in one filter pass get each its own likelihood, exactly.
#[test]
fn one_pass_scores_each_vector_as_its_own_pass() {
    let t = lab_times(4);
    let a = ou(&t, 2e-4, 3.0, 40);
    let b: Vec<f64> = normals(t.len(), 41).iter().zip(&a).map(|(z, x)| x + 1e-4 * z).collect();
    let m = NoiseModel::fit_at(&b, &t).0;
    assert!(m.sampling.is_some());
    let both = m.log_likelihoods_at(&[&a, &b], &t);
    assert_eq!(both, vec![m.log_likelihood_at(&a, &t), m.log_likelihood_at(&b, &t)]);
}
