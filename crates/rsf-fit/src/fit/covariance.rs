//! Covariance of the fitted parameters at the optimum, and their standard errors and 95%
//! intervals.

use super::ParamMap;
use super::params::Slot;
use nalgebra::DMatrix;
use rsf_noise::NoiseModel;
use std::collections::BTreeMap;

/// Sandwich covariance of θ, (JᵀW²J)⁻¹ (JᵀW⁴J) (JᵀW²J)⁻¹ σ², from the unweighted Jacobian
/// `raw_j` (n × m, row-major), the sample weights and the noise variance `s2` (the usual
/// (JᵀJ)⁻¹σ² for uniform weights): independent residuals of one σ. A point that is the mean of
/// `counts[r]` samples (bins) has noise variance σ²/c: its term of the middle factor is
/// divided by c.
pub(super) fn covariance(raw_j: &[f64], weights: &[f64], counts: Option<&[u32]>, m: usize, s2: f64) -> DMatrix<f64> {
    let mut g = DMatrix::<f64>::zeros(m, m);
    for (r, w) in weights.iter().enumerate() {
        let row = &raw_j[r * m..(r + 1) * m];
        let c = counts.map_or(1.0, |c| c[r] as f64);
        for a in 0..m {
            for b in 0..m {
                g[(a, b)] += w.powi(4) / c * row[a] * row[b];
            }
        }
    }
    sandwich(&normal_matrix(raw_j, weights, m), &(g * s2))
}

/// Sandwich covariance of θ under correlated noise: (JᵀW²J)⁻¹ (JᵀW²ΣW²J) (JᵀW²J)⁻¹, Σ the
/// noise model's covariance between the points at `times` (`rsf-noise`, applied column by
/// column in O(n) each; a bin mean of c samples has the white part σ²/c, its correlated parts
/// are read at the bin's mean time). The estimator is the weighted least squares the fit ran;
/// only the noise it is judged under changes.
pub fn covariance_under(
    raw_j: &[f64],
    weights: &[f64],
    counts: Option<&[u32]>,
    times: &[f64],
    m: usize,
    noise: &NoiseModel,
) -> DMatrix<f64> {
    let n = weights.len();
    let scale: Vec<f64> = (0..n).map(|r| 1.0 / counts.map_or(1.0, |c| c[r] as f64)).collect();
    // the columns of W²J, and Σ applied to each
    let u: Vec<Vec<f64>> =
        (0..m).map(|a| (0..n).map(|r| weights[r] * weights[r] * raw_j[r * m + a]).collect()).collect();
    let su: Vec<Vec<f64>> = u.iter().map(|col| noise.covariance_times(times, &scale, col)).collect();
    let g = DMatrix::from_fn(m, m, |a, b| {
        let x: f64 = u[a].iter().zip(&su[b]).map(|(p, q)| p * q).sum();
        let y: f64 = u[b].iter().zip(&su[a]).map(|(p, q)| p * q).sum();
        0.5 * (x + y)
    });
    sandwich(&normal_matrix(raw_j, weights, m), &g)
}

/// JᵀW²J.
fn normal_matrix(raw_j: &[f64], weights: &[f64], m: usize) -> DMatrix<f64> {
    let mut h = DMatrix::<f64>::zeros(m, m);
    for (r, w) in weights.iter().enumerate() {
        let row = &raw_j[r * m..(r + 1) * m];
        for a in 0..m {
            for b in 0..m {
                h[(a, b)] += w * w * row[a] * row[b];
            }
        }
    }
    h
}

/// H⁻¹ G H⁻¹, inverted with column scaling (entries differ by many orders of magnitude) and an
/// SVD pseudo-inverse, so an unidentified direction shows as a huge variance, not a tiny one.
fn sandwich(h: &DMatrix<f64>, g: &DMatrix<f64>) -> DMatrix<f64> {
    let m = h.nrows();
    // nothing free (every parameter fixed): nothing to estimate, and nalgebra refuses an empty SVD
    if m == 0 {
        return DMatrix::zeros(0, 0);
    }
    let dsc: Vec<f64> = (0..m).map(|k| h[(k, k)].sqrt().max(1e-300)).collect();
    let hs = DMatrix::from_fn(m, m, |a, b| h[(a, b)] / (dsc[a] * dsc[b]));
    // nalgebra's plain SVD can iterate forever on non-finite input: check, and cap iterations
    let nan = || DMatrix::from_element(m, m, f64::NAN);
    let hsinv = if hs.iter().all(|x| x.is_finite()) && g.iter().all(|x| x.is_finite()) {
        match hs.clone().try_svd(true, true, 1e-15, 10_000) {
            Some(svd) => {
                let smax = svd.singular_values.max();
                svd.pseudo_inverse(1e-12 * smax).unwrap_or_else(|_| nan())
            }
            None => nan(),
        }
    } else {
        nan()
    };
    let hinv = DMatrix::from_fn(m, m, |a, b| hsinv[(a, b)] / (dsc[a] * dsc[b]));
    &hinv * g * &hinv
}

/// Standard errors and 95% intervals by name: asymmetric (exponentiated) for log-fitted
/// parameters, by the delta method through their source for derived ones.
pub(super) fn intervals(
    map: &ParamMap,
    theta: &[f64],
    cov: &DMatrix<f64>,
) -> (BTreeMap<String, [f64; 2]>, BTreeMap<String, f64>) {
    let full = map.full(theta);
    let mut ci95 = BTreeMap::new();
    let mut stderr = BTreeMap::new();
    for (k, name) in map.free_names().iter().enumerate() {
        let sd = cov[(k, k)].max(0.0).sqrt();
        let (lo, hi, se) = if map.is_log(k) {
            let v = theta[k].exp();
            ((theta[k] - 1.96 * sd).exp(), (theta[k] + 1.96 * sd).exp(), v * sd)
        } else {
            (theta[k] - 1.96 * sd, theta[k] + 1.96 * sd, sd)
        };
        ci95.insert(name.clone(), [lo, hi]);
        stderr.insert(name.clone(), se);
    }
    for (i, s) in map.slots.iter().enumerate() {
        if let Slot::Derived { src, sign, .. } = s {
            if let Some(se) = stderr.get(&map.names[*src]).copied() {
                let v = full[i];
                ci95.insert(map.names[i].clone(), [v - 1.96 * se * sign.abs(), v + 1.96 * se * sign.abs()]);
                stderr.insert(map.names[i].clone(), se);
            }
        }
    }
    (ci95, stderr)
}
