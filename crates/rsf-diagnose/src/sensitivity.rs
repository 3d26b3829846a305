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
//!
//! The protocol's velocities are not fitted but read from the load point, and a slow segment's
//! is uncertain: its line fit's slope error is σ_x/√Σ(t − t̄)², σ_x the load point's noise. At
//! 3·10⁻⁴ µm/s over 1000 s with an encoder noise of 0.06 µm that is 2 % of V, and the model's
//! level there moves by |a − b|·0.02 ≈ 5e-5 — locked to the step, as a misfit is (record 17 of
//! the 111-record set's seed 2: a second state named right, its levels off at p = 3e-4 by
//! ±6e-5 at the two steps up from its slowest segments). So each sliding segment whose
//! velocity is uncertain by more than [`NEGLIGIBLE_VELOCITY_ERROR`] adds the model's change for
//! one standard error of it, an error independent of the others and of the fit's.

use rsf_fit::data::Record;
use rsf_fit::fit::{
    FitOptions, FitResult, LoadingMode, ParamMap, Prepared, covariance_under, model_curve, parameter_map, prepare,
};
use rsf_fit::segment::Segment;

/// A segment's velocity known to better than this fraction is taken as exact: it moves friction
/// by at most a·10⁻³ ≈ 10⁻⁵ (a ≤ 0.01), a tenth of the quietest lab's noise.
pub const NEGLIGIBLE_VELOCITY_ERROR: f64 = 1e-3;

/// The model's change (at the fit's samples) for a step in each free parameter, and the
/// parameters' covariance in units of those steps (row-major).
#[derive(Clone, Debug)]
pub struct FitEffect {
    /// One curve per free parameter: model(θ + h_i e_i) − model(θ), h_i its white-noise
    /// standard error.
    pub changes: Vec<Vec<f64>>,
    /// cov[i·m + j] = cov(θ_i, θ_j) / (h_i h_j), under the residuals' noise model.
    pub cov: Vec<f64>,
    /// One curve per sliding segment whose velocity the load point leaves uncertain (protocol
    /// loading): the model's change for one standard error of that velocity, each independent.
    pub velocities: Vec<Vec<f64>>,
}

/// The fit effect of `f`, fitted with options `o` on `rec` and `segs`, with the load point's
/// noise `load_point_sigma_um` (µm) about the protocol's lines; `None` when the fit has
/// no covariance to size its steps, or the model cannot be evaluated at the fit's samples again.
pub fn fit_effect(
    rec: &Record,
    segs: &[Segment],
    o: &FitOptions,
    f: &FitResult,
    load_point_sigma_um: f64,
) -> Option<FitEffect> {
    let m = f.theta.len();
    if m == 0 || f.cov_theta.len() != m * m {
        return None;
    }
    let mut p = prepare(rec, segs, o).ok()?;
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
    let velocities = match o.loading {
        LoadingMode::Protocol => velocity_changes(&mut p, &map, o, &f.theta, &base, load_point_sigma_um),
        LoadingMode::Record => vec![],
    };
    Some(FitEffect { changes, cov: c.transpose().as_slice().to_vec(), velocities })
}

/// The model's change for one standard error of each sliding segment's velocity (its line
/// fit's, from the load point's noise `sx` (µm) about the protocol), for the segments uncertain by more
/// than [`NEGLIGIBLE_VELOCITY_ERROR`] of their velocity; `base` the model at `theta`.
fn velocity_changes(
    p: &mut Prepared,
    map: &ParamMap,
    o: &FitOptions,
    theta: &[f64],
    base: &[f64],
    sx: f64,
) -> Vec<Vec<f64>> {
    if !(sx > 0.0) {
        return vec![];
    }
    let mut out = vec![];
    for j in 0..p.segments.len() {
        let s = &p.segments[j];
        if !(s.v > 0.0) || s.i1 <= s.i0 {
            continue;
        }
        let t = &p.record.time[s.i0..=s.i1];
        let mean = t.iter().sum::<f64>() / t.len() as f64;
        let spread: f64 = t.iter().map(|x| (x - mean).powi(2)).sum();
        let sd = sx / spread.sqrt();
        if !(sd > NEGLIGIBLE_VELOCITY_ERROR * s.v) {
            continue;
        }
        let v = s.v;
        p.segments[j].v = v + sd;
        let curve = model_curve(p, map, o, theta, o.rtol);
        p.segments[j].v = v;
        if let Ok(c) = curve {
            out.push(c.iter().zip(base).map(|(c, b)| c - b).collect());
        }
    }
    out
}
