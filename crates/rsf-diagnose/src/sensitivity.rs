//! How the named fit's own uncertainty moves its model: the model's change for one standard
//! error of each free parameter, and the parameters' correlations.
//!
//! A fitted parameter a little off moves the model in the same way at every event: its error
//! is locked to the protocol, as a misfit is, and placebos placed where no event is do not
//! carry it. The level test (`levels.rs`) adds it to its null: the covariance of the changes
//! of level it predicts, from the covariance of θ, propagated through the model. The
//! diagnosis's fits state a white-noise covariance; under the AR(1) and drift noise of a real
//! record that is too narrow (a fit's error grows with the noise's correlation), so the
//! covariance is taken again here under the noise model fitted to the fit's residuals: the
//! sandwich (JᵀJ)⁻¹ JᵀΣJ (JᵀJ)⁻¹ of the least squares the diagnosis ran (uniform weights), with J
//! from the same model changes.

use rsf_fit::data::Record;
use rsf_fit::fit::{FitOptions, FitResult, covariance_under, model_curve, parameter_map, prepare};
use rsf_fit::segment::Segment;

/// The model's change (at the fit's samples) for a step in each free parameter, and the
/// parameters' covariance in units of those steps (row-major).
#[derive(Clone, Debug)]
pub struct FitEffect {
    /// One curve per free parameter: model(θ + h_i e_i) − model(θ), h_i its white-noise
    /// standard error.
    pub changes: Vec<Vec<f64>>,
    /// cov[i·m + j] = cov(θ_i, θ_j) / (h_i h_j), under the residuals' noise model.
    pub cov: Vec<f64>,
}

/// The fit effect of `f`, fitted with options `o` on `rec` and `segs`; `None` when the fit has
/// no covariance to size its steps, or the model cannot be evaluated at the fit's samples again.
pub fn fit_effect(rec: &Record, segs: &[Segment], o: &FitOptions, f: &FitResult) -> Option<FitEffect> {
    let m = f.theta.len();
    if m == 0 || f.cov_theta.len() != m * m {
        return None;
    }
    let p = prepare(rec, segs, o).ok()?;
    let map = parameter_map(&p, o).ok()?;
    if map.free_names().len() != m {
        return None;
    }
    let base = model_curve(&p, &map, o, &f.theta, o.rtol).ok()?;
    if base.len() != f.curve.time.len() {
        return None;
    }
    let sd: Vec<f64> = (0..m).map(|i| f.cov_theta[i * m + i].max(0.0).sqrt()).collect();
    let mut changes = Vec::with_capacity(m);
    for i in 0..m {
        let mut change = vec![0.0; base.len()];
        if sd[i] > 0.0 && sd[i].is_finite() {
            // one standard error up, or down where up leaves the parameter's bounds
            for sign in [1.0, -1.0] {
                let mut theta = f.theta.clone();
                theta[i] += sign * sd[i];
                if let Ok(curve) = model_curve(&p, &map, o, &theta, o.rtol) {
                    change = curve.iter().zip(&base).map(|(c, b)| sign * (c - b)).collect();
                    break;
                }
            }
        }
        changes.push(change);
    }
    // J in units of the steps (the changes themselves, row-major), and the sandwich of the
    // least squares the diagnosis ran (uniform weights) under the residuals' noise
    let n = base.len();
    let jac: Vec<f64> = (0..n * m).map(|k| changes[k % m][k / m]).collect();
    let noise = super::evidence::noisy(f).model;
    let c = covariance_under(&jac, &vec![1.0; n], None, &f.curve.time, m, &noise);
    Some(FitEffect { changes, cov: c.transpose().as_slice().to_vec() })
}
