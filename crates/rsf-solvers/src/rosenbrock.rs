//! The Rosenbrock stepper, written once for every stiffly accurate tableau (`tableau/`):
//! Rodas4 and Rodas5P are this loop with different coefficients.
//!
//! Each step is one exact Jacobian, one LU of `I/(hγ) − J` and one linear solve per stage —
//! no Newton iteration — so the exact Jacobian every rsf law provides through dual numbers is
//! used to the full. Step control: the elementary controller h_new = h·(0.9/err)^(1/q) with
//! q = embedded order + 1 (Hairer & Wanner's RODAS), factors clamped to [1/6, 5].

use crate::lu::Lu;
use crate::ode::{
    Integrated, IntegrationError, OdeSystem, Reached, StepStats, Tolerances, clip_step, emit_dense, error_norm,
    initial_step,
};
use crate::tableau::RosenbrockTableau;
use nalgebra::{SMatrix, SVector};

/// With `leave_when_nonstiff`, the stepper returns [`Reached::Switch`] after this many
/// consecutive accepted steps on which an explicit method would have been stable with the
/// same step (hysteresis: one step is no trend).
pub(crate) const NONSTIFF_STEPS: u32 = 15;

/// An explicit order-5 pair is stable for h·ρ(J) below about 3.3 on the negative real axis; a
/// step is called non-stiff below this (half of it: the explicit step must be comfortably
/// stable, not at the edge, or the switch would flip back at once).
pub(crate) const NONSTIFF_H_RHO: f64 = 1.5;

/// Integrates one piece with the tableau `tab`. `leave_when_nonstiff` lets the automatic method
/// hand a non-stiff stretch back to the explicit stepper.
#[allow(clippy::too_many_arguments)]
pub(crate) fn integrate<const S: usize, const R: usize, const D: usize, Sys: OdeSystem<D>>(
    tab: &RosenbrockTableau<S, R>,
    (tol, max_steps): (&Tolerances, u64),
    sys: &Sys,
    (t0, y0, t1, h0): (f64, SVector<f64, D>, f64, f64),
    t_out: &[f64],
    out: &mut impl FnMut(f64, &SVector<f64, D>),
    stats: &mut StepStats,
    leave_when_nonstiff: bool,
) -> Result<Reached<D>, IntegrationError> {
    let span = t1 - t0;
    let (mut t, mut y, mut h) = (t0, y0, h0);
    let (mut next_out, mut reject, mut steps, mut nonstiff) = (0, false, 0u64, 0u32);
    let expo = 1.0 / tab.err_order;
    // stage nodes and γ sums, needed only when f depends on t
    let mut nodes: Option<([f64; S], [f64; S])> = None;
    loop {
        let (f0, jac) = sys.rhs_and_jacobian(t, &y);
        stats.rhs_evals += 1;
        stats.jacobian_evals += 1;
        let f_t = sys.time_derivative(t, &y);
        let (c_node, d_sum) = match f_t {
            Some(_) => *nodes.get_or_insert_with(|| tab.nodes()),
            None => ([0.0; S], [0.0; S]),
        };
        if h <= 0.0 {
            h = initial_step(sys, t, &y, &f0, span, tab.err_order as i32, tol, stats);
        }
        // the dominant eigenvalue of J, bounded by the system (default: the row-sum norm)
        let rho = if leave_when_nonstiff { sys.spectral_radius_bound(&jac) } else { 0.0 };
        loop {
            if steps >= max_steps {
                return Err(IntegrationError::TooManySteps { t, steps });
            }
            steps += 1;
            let (h_step, last) = clip_step(t, h, t1, span)?;
            h = h_step;
            let w = SMatrix::<f64, D, D>::identity() * (1.0 / (h * tab.gamma)) - jac;
            let lu = Lu::new(w).ok_or(IntegrationError::Singular { t })?;
            stats.lu_decompositions += 1;
            let ih = 1.0 / h;
            let mut k = [SVector::<f64, D>::zeros(); S];
            let mut arg = y;
            // a time-dependent system adds h d_i ∂f/∂t to stage i (Hairer & Wanner IV.7, 7.4')
            let ft_term = |i: usize| f_t.map(|ft| ft * (h * d_sum[i])).unwrap_or_else(SVector::zeros);
            k[0] = lu.solve(f0 + ft_term(0));
            for i in 1..S {
                arg = y;
                let mut rhs_c = SVector::<f64, D>::zeros();
                for j in 0..i {
                    arg += k[j] * tab.a[i][j];
                    rhs_c += k[j] * tab.c[i][j];
                }
                k[i] = lu.solve(sys.rhs(t + c_node[i] * h, &arg) + rhs_c * ih + ft_term(i));
            }
            stats.rhs_evals += S as u64 - 1;
            // stiffly accurate: the last stage's argument plus its increment
            let y1 = arg + k[S - 1];
            let err = error_norm(sys, &k[S - 1], &y, &y1, tol);
            let fac = if err.is_finite() { (err.powf(expo) / 0.9).clamp(0.2, 6.0) } else { 10.0 };
            if err <= 1.0 {
                let t_new = if last { t1 } else { t + h };
                if let Err(reason) = sys.accepted(t_new, &y1) {
                    return Err(IntegrationError::Stopped { t: t_new, reason });
                }
                stats.accepted += 1;
                let yc = y;
                let dense = || {
                    let mut kk = [SVector::<f64, D>::zeros(); R];
                    for (r, row) in tab.h.iter().enumerate() {
                        for i in 0..S {
                            kk[r] += k[i] * row[i];
                        }
                    }
                    move |s: f64| {
                        let mut inner = kk[R - 1];
                        for r in (0..R - 1).rev() {
                            inner = kk[r] + inner * s;
                        }
                        yc * (1.0 - s) + (y1 + inner * (1.0 - s)) * s
                    }
                };
                emit_dense(t_out, &mut next_out, (t, h, t_new), &y1, dense, out);
                let mut h_new = h / fac;
                if reject {
                    h_new = h_new.min(h);
                }
                reject = false;
                y = y1;
                t = t_new;
                if last {
                    return Ok(Reached::End(Integrated { y, h_next: h_new }));
                }
                nonstiff = if leave_when_nonstiff && h * rho < NONSTIFF_H_RHO { nonstiff + 1 } else { 0 };
                if nonstiff >= NONSTIFF_STEPS {
                    return Ok(Reached::Switch { t, y, h: h_new });
                }
                h = h_new;
                break;
            }
            stats.rejected += 1;
            h /= fac;
            reject = true;
        }
    }
}
