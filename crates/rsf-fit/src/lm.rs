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
    /// The Gauss–Newton step's predicted gain fell below the tolerance in log-likelihood units
    /// ([`Convergence::lnl_tolerance`]).
    #[serde(rename = "predicted gain below tolerance")]
    Converged,
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
            Self::Converged => "predicted gain below tolerance",
        }
    }
}

impl StopReason {
    /// Whether LM stopped at an optimum (every reason but the iteration limit: a vanished
    /// gradient, a step or a reduction below round-off, a gain below the tolerance, damping
    /// against a minimum or a wall).
    pub fn at_optimum(self) -> bool {
        match self {
            Self::GradientVanished
            | Self::SmallReduction
            | Self::SmallStep
            | Self::DampingDiverged
            | Self::Converged => true,
            Self::IterationLimit => false,
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
    // the lower triangle, packed row by row, accumulated over the residuals in order
    let mut lower = vec![0.0; m * (m + 1) / 2];
    let mut g = DVector::<f64>::zeros(m);
    let mut ssr = 0.0;
    for ri in &e.r {
        ssr += ri * ri;
    }
    for (row, &ri) in e.j.chunks_exact(m.max(1)).zip(&e.r) {
        let mut start = 0;
        for (k, &rk) in row.iter().enumerate() {
            g[k] += rk * ri;
            for (a, &rl) in lower[start..=start + k].iter_mut().zip(row) {
                *a += rk * rl;
            }
            start += k + 1;
        }
    }
    let mut a = DMatrix::<f64>::zeros(m, m);
    let mut start = 0;
    for k in 0..m {
        for l in 0..=k {
            a[(k, l)] = lower[start + l];
            a[(l, k)] = lower[start + l];
        }
        start += k + 1;
    }
    (a, g, ssr)
}

/// How accurately the objective is to be computed: a search far from its optimum needs a
/// descent direction, not the last digits (see [`Convergence::coarse_above`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Accuracy {
    /// The caller's loose setting (e.g. a looser integrator tolerance).
    Coarse,
    /// The caller's full setting: every reported sum of squares is computed so.
    Fine,
}

/// When Levenberg–Marquardt stops, and whether it may evaluate coarsely far from the optimum.
///
/// Both tests are in units of the Gaussian log-likelihood of the samples,
/// ln L = −(N/2) ln(SSR + SSR₀) + const ([`LnlScale`]): a change ΔSSR moves it by about
/// (N/2) ΔSSR/(SSR + SSR₀). The Gauss–Newton step's predicted reduction gᵀA⁻¹g (the
/// *decrement*, g = Jᵀr, A = JᵀJ) bounds what is left to gain while the quadratic model holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Convergence {
    /// Iteration limit.
    pub max_iter: usize,
    /// Stop (evaluating finely) when the decrement is below this in ln L units; `None`: only
    /// the relative-reduction, step and damping tests.
    pub lnl_tolerance: Option<f64>,
    /// Evaluate with [`Accuracy::Coarse`] while the decrement exceeds this in ln L units, then
    /// finely to the end (never back); `None`: always finely. A coarse search that would stop
    /// switches to fine evaluations instead, so every result is a fine one.
    pub coarse_above: Option<f64>,
    /// What a unit of ln L is.
    pub scale: LnlScale,
}

/// The samples behind the residuals: ln L = −(N/2) ln(SSR + SSR₀). A residual per sample has
/// N = their number and SSR₀ = 0; residuals of bin means (a count c each, weighted by √c)
/// stand for N samples and leave out the scatter inside the bins, SSR₀.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LnlScale {
    /// N; `None`: the number of residuals.
    pub samples: Option<f64>,
    /// SSR₀.
    pub ssr_offset: f64,
}

impl Convergence {
    /// LM's own tests only, every evaluation fine.
    pub fn iterations(max_iter: usize) -> Self {
        Self { max_iter, lnl_tolerance: None, coarse_above: None, scale: LnlScale { samples: None, ssr_offset: 0.0 } }
    }
}

/// The Gauss–Newton decrement gᵀA⁻¹g in ln L units, (N/2)·gᵀA⁻¹g/(SSR + SSR₀); NaN where A is
/// singular (an unidentified direction: the test then does not apply).
fn decrement_lnl(a: &DMatrix<f64>, g: &DVector<f64>, ssr: f64, n: usize, scale: &LnlScale) -> f64 {
    let mut l = a.clone();
    for k in 0..a.nrows() {
        // a relative ridge of round-off size, so that a merely ill-conditioned A factors
        l[(k, k)] += 1e-12 * a[(k, k)].max(1e-300);
    }
    match l.cholesky() {
        Some(c) => 0.5 * scale.samples.unwrap_or(n as f64) * g.dot(&c.solve(g)) / (ssr + scale.ssr_offset).max(1e-300),
        None => f64::NAN,
    }
}

/// An evaluation with its normal equations: (residuals and Jacobian, JᵀJ, Jᵀr, SSR).
type Normal = (Eval, DMatrix<f64>, DVector<f64>, f64);

/// The switch to fine evaluations at θ: the sum of squares and its gradient recomputed there.
fn refine<E>(
    f: &mut impl FnMut(&[f64], Accuracy) -> Result<Eval, E>,
    theta: &[f64],
    m: usize,
    evals: &mut usize,
) -> Result<Normal, E> {
    *evals += 1;
    let e = f(theta, Accuracy::Fine)?;
    let (a, g, s) = normal_equations(&e, m);
    Ok((e, a, g, s))
}

/// Minimises Σ r(θ)² from `theta0`. `f` returns `Err` where the model cannot be evaluated
/// (e.g. an unstable trial point); such a trial step is rejected and the damping raised.
pub fn minimize<E>(
    theta0: &[f64],
    mut f: impl FnMut(&[f64]) -> Result<Eval, E>,
    max_iter: usize,
) -> Result<LmResult, E> {
    minimize_with(theta0, |t, _| f(t), &Convergence::iterations(max_iter))
}

/// [`minimize`] under the tests of `c`; `f` is told how accurately to evaluate.
pub fn minimize_with<E>(
    theta0: &[f64],
    f: impl FnMut(&[f64], Accuracy) -> Result<Eval, E>,
    c: &Convergence,
) -> Result<LmResult, E> {
    minimize_in(theta0, &[], f, c)
}

/// The components of θ that sit on a bound of `bounds` with the gradient pushing them out
/// (g = Jᵀr > 0 at a lower bound: the step −A⁻¹g would cross it): they are held there for the
/// step (the active set).
fn active_set(theta: &[f64], bounds: &[(f64, f64)], g: &DVector<f64>) -> Vec<bool> {
    if bounds.is_empty() {
        return vec![false; theta.len()];
    }
    theta
        .iter()
        .zip(bounds)
        .enumerate()
        .map(|(k, (&t, &(lo, hi)))| (t <= lo && g[k] > 0.0) || (t >= hi && g[k] < 0.0))
        .collect()
}

/// `a` and `g` with the active components taken out: their rows and columns of `a` replaced
/// by the identity and their gradient by 0, so that a step leaves them where they are.
fn reduced(a: &DMatrix<f64>, g: &DVector<f64>, active: &[bool]) -> (DMatrix<f64>, DVector<f64>) {
    let m = g.len();
    let ar = DMatrix::from_fn(m, m, |i, j| match (active[i], active[j]) {
        (false, false) => a[(i, j)],
        _ => f64::from(u8::from(i == j)),
    });
    let gr = DVector::from_fn(m, |i, _| if active[i] { 0.0 } else { g[i] });
    (ar, gr)
}

/// [`minimize_with`] inside the box `bounds` (θ's own scale, one `(lo, hi)` per component;
/// empty: none). A component on a bound that the gradient pushes out is held there for the step
/// (the active set), the others take the reduced step, and a step that would cross a bound is
/// shortened to end on it: a fit whose optimum has a parameter at its bound (α = 0 on a record
/// that has no normal-stress coupling) moves the other parameters to their optimum instead of
/// stalling against the wall. A point inside the box with no bound active takes exactly the steps of
/// the unbounded search.
pub fn minimize_in<E>(
    theta0: &[f64],
    bounds: &[(f64, f64)],
    mut f: impl FnMut(&[f64], Accuracy) -> Result<Eval, E>,
    c: &Convergence,
) -> Result<LmResult, E> {
    let m = theta0.len();
    let bounds = if bounds.len() == m { bounds } else { &[] };
    let mut theta = theta0.to_vec();
    let mut accuracy = if c.coarse_above.is_some() { Accuracy::Coarse } else { Accuracy::Fine };
    let mut e = match f(&theta, accuracy) {
        Ok(e) => e,
        // where the coarse setting cannot evaluate the start, the fine one decides
        Err(_) if accuracy == Accuracy::Coarse => {
            accuracy = Accuracy::Fine;
            f(&theta, accuracy)?
        }
        Err(err) => return Err(err),
    };
    let mut evals = 1;
    let (mut a, mut g, mut ssr) = normal_equations(&e, m);
    let mut mu = 1e-3 * (0..m).map(|k| a[(k, k)]).fold(0.0, f64::max).max(1e-300);
    let mut nu = 2.0;
    let reason;
    let mut it = 0;
    loop {
        // the step and the tests work on the free components (all of them, inside the box)
        let active = active_set(&theta, bounds, &g);
        let any_active = active.iter().any(|&x| x);
        let (a_free, g_free) = if any_active { reduced(&a, &g, &active) } else { (a.clone(), g.clone()) };
        let stop = if it >= c.max_iter {
            Some(StopReason::IterationLimit)
        } else if g_free.amax() <= 1e-14 * ssr.max(1e-300).sqrt() {
            Some(StopReason::GradientVanished)
        } else {
            let dec = (c.lnl_tolerance.is_some() || accuracy == Accuracy::Coarse)
                .then(|| decrement_lnl(&a_free, &g_free, ssr, e.r.len(), &c.scale));
            match (accuracy, dec) {
                (Accuracy::Coarse, Some(d)) if c.coarse_above.is_some_and(|x| d < x) => {
                    (e, a, g, ssr) = refine(&mut f, &theta, m, &mut evals)?;
                    accuracy = Accuracy::Fine;
                    continue;
                }
                (Accuracy::Fine, Some(d)) if c.lnl_tolerance.is_some_and(|x| d < x) => Some(StopReason::Converged),
                _ => None,
            }
        };
        if let Some(r) = stop {
            // a coarse search that would stop goes on with fine evaluations (no further iterations
            // at the limit: the result is then the fine value at the last point)
            if accuracy == Accuracy::Coarse {
                (e, a, g, ssr) = refine(&mut f, &theta, m, &mut evals)?;
                accuracy = Accuracy::Fine;
                if r != StopReason::IterationLimit {
                    continue;
                }
            }
            reason = r;
            break;
        }
        it += 1;
        // (A + μ diag(A)) δ = −g, with a floor on the diagonal for unidentified directions
        let mut lhs = a_free.clone();
        for k in 0..m {
            lhs[(k, k)] += mu * a_free[(k, k)].max(1e-12 * mu.max(1.0));
        }
        let Some(ch) = lhs.cholesky() else {
            mu *= nu;
            nu *= 2.0;
            continue;
        };
        let mut delta = ch.solve(&(-&g_free));
        let step_small = delta.norm() <= 1e-12 * (DVector::from_column_slice(&theta).norm() + 1e-12);
        // a step that would cross a bound is shortened to end on the first bound it meets (its
        // direction kept: still a descent direction); that parameter is then held there while the
        // gradient pushes it out
        let mut shortened = false;
        let reach = bounds
            .iter()
            .zip(&theta)
            .zip(delta.iter())
            .map(|((&(lo, hi), &t), &d)| {
                if t + d > hi {
                    (hi - t) / d
                } else if t + d < lo {
                    (lo - t) / d
                } else {
                    1.0
                }
            })
            .fold(1.0_f64, f64::min)
            .max(0.0);
        if reach < 1.0 {
            delta *= reach;
            shortened = true;
        }
        let mut trial: Vec<f64> = theta.iter().zip(delta.iter()).map(|(t, d)| t + d).collect();
        // the bound met exactly, not a rounding beyond it
        for (t, &(lo, hi)) in trial.iter_mut().zip(bounds) {
            *t = t.clamp(lo, hi);
        }
        evals += 1;
        let mut small_reduction = false;
        let accepted = match f(&trial, accuracy) {
            Ok(et) => {
                let ssr_t: f64 = et.r.iter().map(|x| x * x).sum();
                // predicted reduction of the quadratic model: δᵀ(μDδ − g) for the damped step
                // itself, −2gᵀδ − δᵀAδ for one that held components or was shortened
                let pred: f64 = if any_active || shortened {
                    -2.0 * g.dot(&delta) - delta.dot(&(&a * &delta))
                } else {
                    delta
                        .iter()
                        .enumerate()
                        .map(|(k, d)| d * (mu * a[(k, k)].max(1e-12 * mu.max(1.0)) * d - g[k]))
                        .sum()
                };
                let rho = (ssr - ssr_t) / pred.max(1e-300);
                if ssr_t.is_finite() && rho > 0.0 {
                    let rel = (ssr - ssr_t) / ssr.max(1e-300);
                    theta = trial;
                    e = et;
                    (a, g, ssr) = normal_equations(&e, m);
                    mu *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                    nu = 2.0;
                    small_reduction = rel < 1e-10;
                    true
                } else {
                    false
                }
            }
            Err(_) => false,
        };
        let stop = if accepted {
            small_reduction.then_some(StopReason::SmallReduction)
        } else if step_small {
            Some(StopReason::SmallStep)
        } else {
            mu *= nu;
            nu *= 2.0;
            (mu > 1e20).then_some(StopReason::DampingDiverged)
        };
        if let Some(r) = stop {
            if accuracy == Accuracy::Coarse {
                (e, a, g, ssr) = refine(&mut f, &theta, m, &mut evals)?;
                accuracy = Accuracy::Fine;
                // the damping that diverged on coarse values starts again
                if r == StopReason::DampingDiverged {
                    mu = 1e-3 * (0..m).map(|k| a[(k, k)]).fold(0.0, f64::max).max(1e-300);
                    nu = 2.0;
                }
                continue;
            }
            reason = r;
            break;
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

    /// An optimum outside the box: y = p0·x + p1·x² fitted to data made with p1 = −0.5 and
    /// p1 bounded below by 0. The box's optimum has p1 = 0 and p0 at the least-squares slope of
    /// the data on x alone; refusing every step across the bound (the old way, an evaluation
    /// that fails there) stalls p0 short of it.
    #[test]
    fn an_optimum_on_a_bound_moves_the_other_parameters_to_theirs() {
        let xs: Vec<f64> = (1..=20).map(|i| i as f64 * 0.1).collect();
        let ys: Vec<f64> = xs.iter().map(|x| 1.5 * x - 0.5 * x * x).collect();
        let model = |p: &[f64]| -> Eval {
            let r = xs.iter().zip(&ys).map(|(x, y)| p[0] * x + p[1] * x * x - y).collect();
            let j = xs.iter().flat_map(|x| [*x, x * x]).collect();
            Eval { r, j }
        };
        let slope = xs.iter().zip(&ys).map(|(x, y)| x * y).sum::<f64>() / xs.iter().map(|x| x * x).sum::<f64>();
        let boxed = minimize_in(
            &[1.0, 0.3],
            &[(-10.0, 10.0), (0.0, 10.0)],
            |p, _| Ok::<_, ()>(model(p)),
            &Convergence::iterations(200),
        )
        .unwrap();
        assert_eq!(boxed.theta[1], 0.0);
        assert!((boxed.theta[0] - slope).abs() < 1e-9, "{boxed:?} vs slope {slope}");
        assert!(boxed.reason.at_optimum(), "{:?}", boxed.reason);
        // the wall as a failed evaluation: the search stops short
        let walled = minimize(&[1.0, 0.3], |p| if p[1] < 0.0 { Err(()) } else { Ok(model(p)) }, 200).unwrap();
        assert!((walled.theta[0] - slope).abs() > 1e-3, "{walled:?}");
        // inside the box, the same steps as without it
        let free = minimize(&[1.0, 0.3], |p| Ok::<_, ()>(model(p)), 200).unwrap();
        let wide = minimize_in(
            &[1.0, 0.3],
            &[(-10.0, 10.0), (-10.0, 10.0)],
            |p, _| Ok::<_, ()>(model(p)),
            &Convergence::iterations(200),
        )
        .unwrap();
        assert_eq!(free.theta, wide.theta);
        assert_eq!(free.iterations, wide.iterations);
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

    /// A noisy exponential decay: residuals of N samples, and its exact-precision optimum.
    fn decay_problem(coarse_bias: f64) -> impl FnMut(&[f64], Accuracy) -> Result<Eval, ()> {
        let ts: Vec<f64> = (0..2000).map(|i| i as f64 * 0.005).collect();
        // deterministic "noise" of σ ≈ 0.01
        let ys: Vec<f64> = ts
            .iter()
            .enumerate()
            .map(|(i, t)| 2.0 * (-1.3 * t).exp() + 0.01 * ((i * 7919 % 1000) as f64 / 500.0 - 1.0))
            .collect();
        move |p: &[f64], acc: Accuracy| {
            // a coarse evaluation is off by a smooth error, as a looser solver is
            let bias = if acc == Accuracy::Coarse { coarse_bias } else { 0.0 };
            let mut r = vec![];
            let mut j = vec![];
            for (t, y) in ts.iter().zip(&ys) {
                let e = (-p[1] * t).exp();
                r.push(p[0] * e * (1.0 + bias) - y);
                j.extend([e, -p[0] * t * e]);
            }
            Ok(Eval { r, j })
        }
    }

    /// Stopping on the Gauss–Newton decrement ends within the tolerance of the optimum's ln L,
    /// in fewer evaluations than LM's relative-reduction test.
    #[test]
    fn the_decrement_test_stops_within_its_tolerance() {
        let full = minimize_with(&[1.0, 0.1], decay_problem(0.0), &Convergence::iterations(200)).unwrap();
        let c = Convergence { lnl_tolerance: Some(1e-3), ..Convergence::iterations(200) };
        let r = minimize_with(&[1.0, 0.1], decay_problem(0.0), &c).unwrap();
        assert_eq!(r.reason, StopReason::Converged);
        let dlnl = 0.5 * 2000.0 * (r.ssr / full.ssr).ln();
        assert!((0.0..1e-3).contains(&dlnl), "ln L short of the optimum's by {dlnl}");
        assert!(r.evaluations < full.evaluations, "{} vs {}", r.evaluations, full.evaluations);
    }

    /// A coarse phase (here a 1% bias) never reaches the result: the search ends on fine
    /// evaluations, at the fine optimum.
    #[test]
    fn a_coarse_phase_ends_in_fine_evaluations() {
        let full = minimize_with(&[1.0, 0.1], decay_problem(0.0), &Convergence::iterations(200)).unwrap();
        let c = Convergence { lnl_tolerance: Some(1e-3), coarse_above: Some(100.0), ..Convergence::iterations(200) };
        let r = minimize_with(&[1.0, 0.1], decay_problem(0.01), &c).unwrap();
        assert_eq!(r.reason, StopReason::Converged);
        assert!((0.5 * 2000.0 * (r.ssr / full.ssr).ln()).abs() < 1e-3, "{} vs {}", r.ssr, full.ssr);
        assert!((r.theta[0] - full.theta[0]).abs() < 1e-4 && (r.theta[1] - full.theta[1]).abs() < 1e-4, "{r:?}");
        // a limit reached while coarse still reports the fine value there
        let c1 = Convergence { max_iter: 1, ..c };
        let mut f = decay_problem(0.01);
        let r1 = minimize_with(&[1.0, 0.1], &mut f, &c1).unwrap();
        let fine: f64 = f(&r1.theta, Accuracy::Fine).unwrap().r.iter().map(|x| x * x).sum();
        assert_eq!(r1.ssr, fine);
    }
}
