//! Levenberg–Marquardt for small parameter vectors and many residuals.
//!
//! Hand-written (not rmpfit) because one forward-sensitivity solve yields residuals and
//! Jacobian together, which a callback split into "residuals" and "Jacobian" would compute
//! twice; bounds are handled by reparametrisation upstream. Damping follows Nielsen (1999):
//! gain-ratio updates of μ with Marquardt's diagonal scaling.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Why Levenberg–Marquardt stopped (serialised as the sentence it displays).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum StopReason {
    /// The gradient is zero to round-off.
    #[serde(rename = "gradient vanished")]
    GradientVanished,
    /// An accepted step reduced the sum of squares by less than 1e-10 of it.
    #[serde(rename = "relative reduction below 1e-10")]
    SmallReduction,
    /// A rejected step was already below 1e-12 of |θ|.
    #[serde(rename = "step below 1e-12")]
    SmallStep,
    /// The damping grew past 1e20: at a minimum, or against a wall where the model cannot be
    /// evaluated (a physical bound, a budget).
    #[serde(rename = "damping diverged (at a minimum or a wall)")]
    DampingDiverged,
    /// `max_iter` iterations.
    #[serde(rename = "iteration limit")]
    IterationLimit,
}

impl StopReason {
    /// The sentence.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::GradientVanished => "gradient vanished",
            Self::SmallReduction => "relative reduction below 1e-10",
            Self::SmallStep => "step below 1e-12",
            Self::DampingDiverged => "damping diverged (at a minimum or a wall)",
            Self::IterationLimit => "iteration limit",
        }
    }
}

impl std::fmt::Display for StopReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Residuals r (length n) and Jacobian ∂r/∂θ (n × m, row-major in a flat vector) at θ.
pub struct Eval {
    /// Residuals.
    pub r: Vec<f64>,
    /// Jacobian, row-major `j[i * m + k]`.
    pub j: Vec<f64>,
}

/// Outcome of a minimisation.
#[derive(Clone, Debug)]
pub struct LmResult {
    /// Parameters at the minimum.
    pub theta: Vec<f64>,
    /// Sum of squared residuals there.
    pub ssr: f64,
    /// Iterations taken.
    pub iterations: usize,
    /// Residual evaluations.
    pub evaluations: usize,
    /// Why it stopped.
    pub reason: StopReason,
}

fn normal_equations(e: &Eval, m: usize) -> (DMatrix<f64>, DVector<f64>, f64) {
    let mut a = DMatrix::<f64>::zeros(m, m);
    let mut g = DVector::<f64>::zeros(m);
    let mut ssr = 0.0;
    for (i, &ri) in e.r.iter().enumerate() {
        let row = &e.j[i * m..(i + 1) * m];
        ssr += ri * ri;
        for k in 0..m {
            g[k] += row[k] * ri;
            for l in 0..=k {
                a[(k, l)] += row[k] * row[l];
            }
        }
    }
    for k in 0..m {
        for l in 0..k {
            a[(l, k)] = a[(k, l)];
        }
    }
    (a, g, ssr)
}

/// Minimises Σ r(θ)² from `theta0`. `f` returns `Err` where the model cannot be evaluated
/// (e.g. an unstable trial point); such a trial step is rejected and the damping raised.
pub fn minimize<E>(
    theta0: &[f64],
    mut f: impl FnMut(&[f64]) -> Result<Eval, E>,
    max_iter: usize,
) -> Result<LmResult, E> {
    let m = theta0.len();
    let mut theta = theta0.to_vec();
    let mut e = f(&theta)?;
    let mut evals = 1;
    let (mut a, mut g, mut ssr) = normal_equations(&e, m);
    let mut mu = 1e-3 * (0..m).map(|k| a[(k, k)]).fold(0.0, f64::max).max(1e-300);
    let mut nu = 2.0;
    let mut reason = StopReason::IterationLimit;
    let mut it = 0;
    while it < max_iter {
        it += 1;
        if g.amax() <= 1e-14 * ssr.max(1e-300).sqrt() {
            reason = StopReason::GradientVanished;
            break;
        }
        // (A + μ diag(A)) δ = −g, with a floor on the diagonal for unidentified directions
        let mut lhs = a.clone();
        for k in 0..m {
            lhs[(k, k)] += mu * a[(k, k)].max(1e-12 * mu.max(1.0));
        }
        let Some(ch) = lhs.cholesky() else {
            mu *= nu;
            nu *= 2.0;
            continue;
        };
        let delta = ch.solve(&(-&g));
        let step_small = delta.norm() <= 1e-12 * (DVector::from_column_slice(&theta).norm() + 1e-12);
        let trial: Vec<f64> = theta.iter().zip(delta.iter()).map(|(t, d)| t + d).collect();
        evals += 1;
        let accepted = match f(&trial) {
            Ok(et) => {
                let ssr_t: f64 = et.r.iter().map(|x| x * x).sum();
                // predicted reduction of the quadratic model
                let pred: f64 = delta
                    .iter()
                    .enumerate()
                    .map(|(k, d)| d * (mu * a[(k, k)].max(1e-12 * mu.max(1.0)) * d - g[k]))
                    .sum();
                let rho = (ssr - ssr_t) / pred.max(1e-300);
                if ssr_t.is_finite() && rho > 0.0 {
                    let rel = (ssr - ssr_t) / ssr.max(1e-300);
                    theta = trial;
                    e = et;
                    let (a2, g2, s2) = normal_equations(&e, m);
                    a = a2;
                    g = g2;
                    ssr = s2;
                    mu *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                    nu = 2.0;
                    if rel < 1e-10 {
                        reason = StopReason::SmallReduction;
                        break;
                    }
                    true
                } else {
                    false
                }
            }
            Err(_) => false,
        };
        if !accepted {
            if step_small {
                reason = StopReason::SmallStep;
                break;
            }
            mu *= nu;
            nu *= 2.0;
            if mu > 1e20 {
                reason = StopReason::DampingDiverged;
                break;
            }
        }
    }
    let _ = &e;
    Ok(LmResult { theta, ssr, iterations: it, evaluations: evals, reason })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock's valley as least squares: r = (10 (y − x²), 1 − x).
    #[test]
    fn solves_rosenbrock() {
        let f = |t: &[f64]| -> Result<Eval, ()> {
            let (x, y) = (t[0], t[1]);
            Ok(Eval { r: vec![10.0 * (y - x * x), 1.0 - x], j: vec![-20.0 * x, 10.0, -1.0, 0.0] })
        };
        let r = minimize(&[-1.2, 1.0], f, 200).unwrap();
        assert!((r.theta[0] - 1.0).abs() < 1e-8 && (r.theta[1] - 1.0).abs() < 1e-8, "{r:?}");
    }

    /// Exponential decay fit with a failing region (θ1 < 0 is "unstable").
    #[test]
    fn fits_an_exponential_and_survives_failed_evaluations() {
        let ts: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
        let ys: Vec<f64> = ts.iter().map(|t| 2.0 * (-1.3 * t).exp()).collect();
        let f = |p: &[f64]| -> Result<Eval, &str> {
            if p[1] < 0.0 {
                return Err("unstable");
            }
            let mut r = vec![];
            let mut j = vec![];
            for (t, y) in ts.iter().zip(&ys) {
                let e = (-p[1] * t).exp();
                r.push(p[0] * e - y);
                j.extend([e, -p[0] * t * e]);
            }
            Ok(Eval { r, j })
        };
        let r = minimize(&[1.0, 0.1], f, 200).unwrap();
        assert!((r.theta[0] - 2.0).abs() < 1e-8 && (r.theta[1] - 1.3).abs() < 1e-8, "{r:?}");
    }
}
