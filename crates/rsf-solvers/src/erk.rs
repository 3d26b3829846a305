//! The explicit stepper, written once for the 7-stage FSAL pairs of order 5(4) (Dopri5,
//! Tsit5): stages, PI step control (Hairer, Nørsett & Wanner, Solving ODEs I, II.4, code
//! DOPRI5: β = 0.04, safety 0.9, factors in [1/10, 5]), dense output from the pair, and
//! Hairer's stiffness detection for the automatic method.

use crate::ode::{
    Integrated, IntegrationError, OdeSystem, Reached, StepStats, Tolerances, clip_step, emit_dense, error_norm,
    initial_step,
};
use nalgebra::SVector;

/// A 7-stage explicit pair with FSAL whose last two nodes are both 1 (c6 = c7 = 1), so that
/// ‖k7 − k6‖ / ‖y1 − y6‖ estimates the dominant eigenvalue of the Jacobian for free.
pub(crate) trait ExplicitPair {
    /// Rows 2–7 of a_ij (row 7: the weights of the propagated solution).
    const A: [[f64; 6]; 6];
    /// Error weights over the 7 slopes (k7 = f(y1)).
    const E: [f64; 7];
    /// The dense output of a step from `y0` to `y1` of size `h` with slopes `k`, at θ ∈ [0, 1].
    fn dense<const D: usize>(
        k: &[SVector<f64, D>; 7],
        y0: &SVector<f64, D>,
        y1: &SVector<f64, D>,
        h: f64,
    ) -> impl Fn(f64) -> SVector<f64, D>;
}

/// Hairer's test (DOPRI5): a step is stiff when h·ρ exceeds this, near the border of the
/// stability region of an order-5 pair on the negative real axis.
pub(crate) const STIFF_H_RHO: f64 = 3.25;

/// …and the stepper hands the piece to the implicit method after this many stiff steps in a
/// row (hysteresis: a single step at the border is no trend).
pub(crate) const STIFF_STEPS: u32 = 15;

/// Integrates one piece with the pair `P`. `leave_when_stiff` lets the automatic method take
/// over a stiff stretch with the implicit stepper.
#[allow(clippy::too_many_arguments)]
pub(crate) fn integrate<P: ExplicitPair, const D: usize, S: OdeSystem<D>>(
    (tol, max_steps): (&Tolerances, u64),
    sys: &S,
    (t0, y0, t1, h0): (f64, SVector<f64, D>, f64, f64),
    t_out: &[f64],
    out: &mut impl FnMut(f64, &SVector<f64, D>),
    stats: &mut StepStats,
    leave_when_stiff: bool,
) -> Result<Reached<D>, IntegrationError> {
    let a = &P::A;
    let (beta, safe, facc1, facc2) = (0.04, 0.9, 1.0 / 0.2, 1.0 / 10.0);
    let expo1 = 0.2 - beta * 0.75;
    let mut facold: f64 = 1e-4;
    let (mut t, mut y) = (t0, y0);
    let mut k = [SVector::<f64, D>::zeros(); 7];
    k[0] = sys.rhs(t, &y);
    stats.rhs_evals += 1;
    let span = t1 - t0;
    let mut h = if h0 > 0.0 { h0.min(span) } else { initial_step(sys, t, &y, &k[0], span, 5, tol, stats) };
    // the nodes c_i = Σ_j a_ij (a time-dependent system's stage times t + c_i h)
    let c: [f64; 6] = std::array::from_fn(|i| a[i].iter().sum());
    let (mut next_out, mut reject, mut steps, mut stiff) = (0, false, 0u64, 0u32);
    loop {
        if steps >= max_steps {
            return Err(IntegrationError::TooManySteps { t, steps });
        }
        steps += 1;
        let (h_step, last) = clip_step(t, h, t1, span)?;
        h = h_step;
        let mut arg = y;
        for i in 1..7 {
            let mut acc = k[0] * a[i - 1][0];
            for j in 1..i {
                acc += k[j] * a[i - 1][j];
            }
            arg = y + acc * h;
            // the last stage is at t + h exactly (c7 = 1)
            let ti = if i == 6 { t + h } else { t + c[i - 1] * h };
            k[i] = sys.rhs(ti, &arg);
        }
        stats.rhs_evals += 6;
        // FSAL: the last stage's argument is the new solution; the one before it is y6
        let y1 = arg;
        let mut err_vec = k[0] * P::E[0];
        for i in 1..7 {
            err_vec += k[i] * P::E[i];
        }
        let err = error_norm(sys, &(err_vec * h), &y, &y1, tol);
        let fac11 = err.powf(expo1);
        if err <= 1.0 {
            let t_new = if last { t1 } else { t + h };
            if let Err(reason) = sys.accepted(t_new, &y1) {
                return Err(IntegrationError::Stopped { t: t_new, reason });
            }
            stats.accepted += 1;
            emit_dense(t_out, &mut next_out, (t, h, t_new), &y1, || P::dense(&k, &y, &y1, h), out);
            let fac = (fac11 / facold.powf(beta) / safe).clamp(facc2, facc1);
            facold = err.max(1e-4);
            let mut h_new = h / fac;
            if reject {
                h_new = h_new.min(h);
            }
            reject = false;
            if leave_when_stiff {
                // y6 = y + h Σ a_6j k_j: recover it from the stage-6 row
                let mut acc = k[0] * a[4][0];
                for j in 1..5 {
                    acc += k[j] * a[4][j];
                }
                let y6 = y + acc * h;
                let den = (y1 - y6).norm();
                let h_rho = if den > 0.0 { h * (k[6] - k[5]).norm() / den } else { 0.0 };
                stiff = if h_rho > STIFF_H_RHO { stiff + 1 } else { 0 };
            }
            k[0] = k[6];
            y = y1;
            t = t_new;
            if last {
                return Ok(Reached::End(Integrated { y, h_next: h_new }));
            }
            if stiff >= STIFF_STEPS {
                return Ok(Reached::Switch { t, y, h: h_new });
            }
            h = h_new;
        } else {
            stats.rejected += 1;
            let shrink = if err.is_finite() { (fac11 / safe).min(facc1) } else { 10.0 };
            h /= shrink;
            reject = true;
        }
    }
}
