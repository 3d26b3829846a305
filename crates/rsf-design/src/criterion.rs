//! The expected discrimination of one proposal between two models: the rival's expected lack
//! of fit when the other is true, under the record's noise and the rival's freedom to
//! re-adjust its parameters within what the record allows.

use nalgebra::{DMatrix, DVector};
use rsf_diagnose::{NoiseModel, whiten};

/// One model's predictions of one proposal, whitened by the noise model.
pub(super) struct Whitened {
    /// At the fitted parameters.
    pub(super) central: Vec<f64>,
    /// At the draws from the covariance.
    pub(super) draws: Vec<Vec<f64>>,
    /// B = J L (J the friction's derivatives in θ, L the covariance's square root), whitened.
    b: DMatrix<f64>,
    /// Cholesky factor of I + BᵀB.
    chol: Option<nalgebra::Cholesky<f64, nalgebra::Dyn>>,
}

impl Whitened {
    /// Whitens a model's predictions: `central` friction with its derivatives `jac` (n × m,
    /// row-major) and the covariance square root `sqrt_cov` (m × m), and the friction of each
    /// draw; the noise's white part at point i divided by `counts[i]`.
    pub(super) fn new(
        noise: &NoiseModel,
        times: &[f64],
        counts: &[f64],
        central: Vec<f64>,
        jac: &[f64],
        sqrt_cov: &DMatrix<f64>,
        draws: Vec<Vec<f64>>,
    ) -> Self {
        let n = central.len();
        let m = sqrt_cov.nrows();
        let j = DMatrix::from_row_slice(n, m, jac);
        let b = &j * sqrt_cov;
        let scale: Vec<f64> = counts.iter().map(|c| 1.0 / c).collect();
        let mut vs: Vec<Vec<f64>> = Vec::with_capacity(1 + draws.len() + m);
        vs.push(central);
        vs.extend(draws);
        vs.extend((0..m).map(|c| b.column(c).iter().copied().collect()));
        whiten(noise, times, &scale, &mut vs);
        let cols: Vec<Vec<f64>> = vs.split_off(vs.len() - m);
        let central = vs.remove(0);
        let bw = DMatrix::from_fn(n, m, |r, c| cols[c][r]);
        let chol = (DMatrix::identity(m, m) + bw.transpose() * &bw).cholesky();
        Self { central, draws: vs, b: bw, chol }
    }

    /// The lack of fit of this model (the rival) to a whitened truth-minus-rival difference r
    /// with its parameters free within their covariance: rᵀ(I + BBᵀ)⁻¹r by Woodbury,
    /// rᵀr − gᵀ(I + BᵀB)⁻¹g with g = Bᵀr.
    fn lack_of_fit(&self, r: &DVector<f64>) -> f64 {
        let rr = r.dot(r);
        let Some(ch) = &self.chol else { return rr };
        let g = self.b.transpose() * r;
        (rr - g.dot(&ch.solve(&g))).max(0.0)
    }
}

/// The information a proposal adds on a subset of one model's parameters (D-optimality on the
/// effect's parameters): with B the whitened J L and L the covariance's square root, the
/// posterior covariance after the new data is C' = L (I + BᵀB)⁻¹ Lᵀ against C = L Lᵀ now.
/// Returns each parameter's standard error now and expected after (θ scale), and the gain
/// ½ ln(det C_E / det C'_E) in nats over the subset E; `None` when C_E is singular.
pub(super) fn information_gain(
    model: &Whitened,
    sqrt_cov: &DMatrix<f64>,
    subset: &[usize],
) -> Option<(Vec<(f64, f64)>, f64)> {
    let m = sqrt_cov.nrows();
    let inner = match &model.chol {
        Some(ch) => ch.inverse(),
        None => DMatrix::identity(m, m),
    };
    let now = sqrt_cov * sqrt_cov.transpose();
    let after = sqrt_cov * inner * sqrt_cov.transpose();
    let pick = |c: &DMatrix<f64>| DMatrix::from_fn(subset.len(), subset.len(), |i, j| c[(subset[i], subset[j])]);
    let (cn, ca) = (pick(&now), pick(&after));
    let (dn, da) = (cn.determinant(), ca.determinant());
    if !(dn > 0.0 && da > 0.0) {
        return None;
    }
    let sds = subset.iter().map(|&k| (now[(k, k)].max(0.0).sqrt(), after[(k, k)].max(0.0).sqrt())).collect();
    Some((sds, 0.5 * (dn.ln() - da.ln())))
}

/// Δ_ij: the expected lack of fit of `rival` when `truth` is true, averaged over the truth's
/// draws (its fitted parameters when it has none).
pub(super) fn expected_lack_of_fit(truth: &Whitened, rival: &Whitened) -> f64 {
    let one = |t: &[f64]| {
        let r = DVector::from_iterator(t.len(), t.iter().zip(&rival.central).map(|(a, b)| a - b));
        rival.lack_of_fit(&r)
    };
    if truth.draws.is_empty() {
        return one(&truth.central);
    }
    truth.draws.iter().map(|d| one(d)).sum::<f64>() / truth.draws.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn white(n: usize) -> (NoiseModel, Vec<f64>, Vec<f64>) {
        (NoiseModel::white(1e-8, n, 0.1), (0..n).map(|i| 0.1 * (i + 1) as f64).collect(), vec![1.0; n])
    }

    #[test]
    fn a_fixed_rival_misfits_by_the_white_sum_of_squares() {
        let n = 50;
        let (noise, t, c) = white(n);
        let d: Vec<f64> = (0..n).map(|i| 1e-4 * (i as f64 / 10.0).sin()).collect();
        let zero = DMatrix::zeros(1, 1);
        let truth = Whitened::new(&noise, &t, &c, d.clone(), &vec![0.0; n], &zero, vec![]);
        let rival = Whitened::new(&noise, &t, &c, vec![0.0; n], &vec![0.0; n], &zero, vec![]);
        let want: f64 = d.iter().map(|x| x * x / 1e-8).sum();
        let got = expected_lack_of_fit(&truth, &rival);
        assert!((got / want - 1.0).abs() < 1e-9, "{got} {want}");
    }

    /// One parameter measured by n samples of white noise σ with unit sensitivity: its variance
    /// goes from s² to 1/(1/s² + n/σ²), and the gain is half the log of the ratio.
    #[test]
    fn information_gain_is_the_posterior_shrinkage() {
        let n = 30;
        let (noise, t, c) = white(n);
        let s = 1e-4;
        let w = Whitened::new(&noise, &t, &c, vec![0.0; n], &vec![1.0; n], &DMatrix::from_element(1, 1, s), vec![]);
        let (sds, gain) = information_gain(&w, &DMatrix::from_element(1, 1, s), &[0]).unwrap();
        let after = (1.0 / (1.0 / (s * s) + n as f64 / 1e-8)).sqrt();
        assert!((sds[0].0 / s - 1.0).abs() < 1e-12);
        assert!((sds[0].1 / after - 1.0).abs() < 1e-9, "{} {after}", sds[0].1);
        assert!((gain - (s / after).ln()).abs() < 1e-9);
    }

    #[test]
    fn a_rival_free_to_shift_absorbs_an_offset() {
        let n = 40;
        let (noise, t, c) = white(n);
        // truth = rival + 1e-4 everywhere; the rival's μ0 (∂f/∂μ0 = 1) has a prior sd of 1
        let truth = Whitened::new(&noise, &t, &c, vec![1e-4; n], &vec![0.0; n], &DMatrix::zeros(1, 1), vec![]);
        let free =
            Whitened::new(&noise, &t, &c, vec![0.0; n], &vec![1.0; n], &DMatrix::from_element(1, 1, 1.0), vec![]);
        assert!(expected_lack_of_fit(&truth, &free) < 1e-3);
        // with a prior sd of 1e-5 it cannot: (1e-4)²/σ² n shrunk by 1/(1 + n s²/σ²)
        let s = 1e-5;
        let tight = Whitened::new(&noise, &t, &c, vec![0.0; n], &vec![1.0; n], &DMatrix::from_element(1, 1, s), vec![]);
        let want = n as f64 * 1e-8 / 1e-8 / (1.0 + n as f64 * s * s / 1e-8);
        let got = expected_lack_of_fit(&truth, &tight);
        assert!((got / want - 1.0).abs() < 1e-9, "{got} {want}");
    }
}
