//! The explicit stepper, written once for the FSAL pairs (Dopri5 and Tsit5, 7 stages of order
//! 5(4); Vern6, 9 stages of order 6(5)): stages, PI step control (Hairer, Nørsett & Wanner,
//! Solving ODEs I, II.4, code DOPRI5: β = 0.04, safety 0.9, factors in [1/10, 5]), dense output
//! from the pair, and Hairer's stiffness detection for the automatic method.

use crate::ode::{
    Integrated, IntegrationError, OdeSystem, Reached, StepStats, Tolerances, clip_step, emit_dense, initial_step,
    mean_square_error,
};
use nalgebra::SVector;

/// The most slopes a pair keeps per step, dense-output stages included (Vern6: 9 + 1).
pub(crate) const MAX_STAGES: usize = 10;

/// The slopes of one step: `k[0..STAGES]` from the step, the rest for a lazy interpolant.
pub(crate) type Slopes<const D: usize> = [SVector<f64, D>; MAX_STAGES];

/// An explicit pair with FSAL whose last two nodes are both 1 (c_{s−1} = c_s = 1), so that
/// ‖k_s − k_{s−1}‖ / ‖y1 − y_{s−1}‖ estimates the dominant eigenvalue of the Jacobian for free.
pub(crate) trait ExplicitPair {
    /// Stages per step, the last being f(y1) (FSAL).
    const STAGES: usize;
    /// Rows 2..=STAGES of a_ij (row i has i − 1 entries; row STAGES holds the weights of the
    /// propagated solution), then any rows of the interpolant's extra stages.
    const A: &'static [&'static [f64]];
    /// Error weights b̂ − b over the `STAGES` slopes.
    const E: &'static [f64];
    /// Order of the embedded (lower-order) solution: the local error estimate is O(h^(q+1)).
    const EMBEDDED_ORDER: i32;
    /// Hairer's stiffness test: a step is stiff when h·ρ exceeds this, just inside the border
    /// of the pair's stability region on the negative real axis.
    const STIFF_H_RHO: f64;
    /// The factor the error estimate is multiplied by before the step controller sees it: 1
    /// unless the estimate is measured to be conservative for the propagated solution (so
    /// that a tolerance means what it says; see `Vern6`).
    const ESTIMATE_SCALE: f64 = 1.0;
    /// The dense output of a step from `(t, y0)` to `y1` of size `h` with slopes `k`, at
    /// θ ∈ [0, 1] (`step` = (t, y0, y1, h)). A pair whose interpolant needs extra stages evaluates them here (only for
    /// steps that hold an output time), counting them in `stats`.
    fn dense<const D: usize, S: OdeSystem<D>>(
        k: &mut Slopes<D>,
        step: (f64, &SVector<f64, D>, &SVector<f64, D>, f64),
        sys: &S,
        stats: &mut StepStats,
    ) -> impl Fn(f64) -> SVector<f64, D>;
}

/// …and the stepper hands the piece to the implicit method after this many stiff steps in a
/// row (hysteresis: a single step at the border is no trend).
pub(crate) const STIFF_STEPS: u32 = 15;

/// How often a non-stiff run is tested for stiffness, in accepted steps: the test costs an
/// extra stage sum and two norms, 2% of a Vern6 solve when done on every step, and a stiff
/// stretch is still caught within this many steps of its start.
const STIFF_TEST_EVERY: u64 = 4;

/// `y + h Σ_j row_j k_j`: the argument of the stage whose a-row is `row`, summed as
/// `(y + h Σ_{j<last} row_j k_j) + (h row_last) k_last` so that only one multiply-add waits for
/// the newest slope (the rest is computed while its right-hand side runs: the stages are
/// latency-bound, and this took 8% off a Vern6 solve).
#[inline(always)]
pub(crate) fn stage_arg<const D: usize>(
    y: &SVector<f64, D>,
    h: f64,
    row: &[f64],
    k: &[SVector<f64, D>],
) -> SVector<f64, D> {
    let last = row.len() - 1;
    let mut acc = SVector::<f64, D>::zeros();
    for (kj, a) in k[..last].iter().zip(&row[..last]) {
        if *a != 0.0 {
            acc += kj * *a;
        }
    }
    (y + acc * h) + k[last] * (h * row[last])
}

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
    const { assert!(P::STAGES <= MAX_STAGES && P::STAGES >= 3) };
    let (a, ns) = (P::A, P::STAGES);
    let (beta, safe, facc1, facc2) = (0.04, 0.9, 1.0 / 0.2, 1.0 / 10.0);
    let ln_safe = f64::ln(safe);
    let expo1 = 1.0 / (P::EMBEDDED_ORDER as f64 + 1.0) - beta * 0.75;
    // DOPRI5's err^expo1 / facold^β, as one exponential of logarithms (two powf calls per step
    // cost as much as a right-hand side of the Slip law)
    let mut ln_facold: f64 = 1e-4f64.ln();
    let (mut t, mut y) = (t0, y0);
    let mut k: Slopes<D> = [SVector::<f64, D>::zeros(); MAX_STAGES];
    k[0] = sys.rhs(t, &y);
    stats.rhs_evals += 1;
    let span = t1 - t0;
    let mut h =
        if h0 > 0.0 { h0.min(span) } else { initial_step(sys, t, &y, &k[0], span, P::EMBEDDED_ORDER + 1, tol, stats) };
    // the nodes c_i = Σ_j a_ij (a time-dependent system's stage times t + c_i h)
    let mut c = [0.0; MAX_STAGES];
    for (ci, row) in c[1..].iter_mut().zip(a) {
        *ci = row.iter().sum();
    }
    let (mut next_out, mut reject, mut steps, mut stiff) = (0, false, 0u64, 0u32);
    loop {
        if steps >= max_steps {
            return Err(IntegrationError::TooManySteps { t, steps });
        }
        steps += 1;
        let (h_step, last) = clip_step(t, h, t1, span)?;
        h = h_step;
        let mut arg = y;
        for i in 1..ns {
            let row = a[i - 1];
            arg = stage_arg(&y, h, row, &k);
            // the last stage is at t + h exactly
            let ti = if i == ns - 1 { t + h } else { t + c[i] * h };
            k[i] = sys.rhs(ti, &arg);
        }
        stats.rhs_evals += ns as u64 - 1;
        // FSAL: the last stage's argument is the new solution
        let y1 = arg;
        let mut err_vec = k[0] * P::E[0];
        for (ki, e) in k[1..ns].iter().zip(&P::E[1..]) {
            err_vec += ki * *e;
        }
        // ln of the RMS error norm, ½ ln(mean square): no square root on the critical path; a
        // step is accepted when it is ≤ 0, and a non-finite norm is +∞
        let ms = mean_square_error(sys, &(err_vec * (h * P::ESTIMATE_SCALE)), &y, &y1, tol);
        let ln_err = if ms.is_finite() { 0.5 * ms.ln() } else { f64::INFINITY };
        if ln_err <= 0.0 {
            let t_new = if last { t1 } else { t + h };
            if let Err(reason) = sys.accepted(t_new, &y1) {
                return Err(IntegrationError::Stopped { t: t_new, reason });
            }
            stats.accepted += 1;
            emit_dense(t_out, &mut next_out, (t, h, t_new), &y1, || P::dense(&mut k, (t, &y, &y1, h), sys, stats), out);
            // h_new = h / clamp(err^expo1 / facold^β / safe, facc2, facc1), as one exponential
            let grow = (ln_safe - expo1 * ln_err + beta * ln_facold).exp().clamp(1.0 / facc1, 1.0 / facc2);
            ln_facold = ln_err.max(1e-4f64.ln());
            let mut h_new = h * grow;
            if reject {
                h_new = h_new.min(h);
            }
            reject = false;
            // tested on every STIFF_TEST_EVERY-th accepted step until one looks stiff, then on
            // every step while the stiff run lasts (in the spirit of DOPRI5's NSTIFF; one
            // non-stiff step ends the run and the sparse testing resumes)
            if leave_when_stiff && (stiff > 0 || stats.accepted.is_multiple_of(STIFF_TEST_EVERY)) {
                // the argument of the stage before the last (also at c = 1)
                let y_prev = stage_arg(&y, h, a[ns - 3], &k);
                let den = (y1 - y_prev).norm();
                let h_rho = if den > 0.0 { h * (k[ns - 1] - k[ns - 2]).norm() / den } else { 0.0 };
                stiff = if h_rho > P::STIFF_H_RHO { stiff + 1 } else { 0 };
            }
            k[0] = k[ns - 1];
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
            let shrink = if ln_err.is_finite() { ((expo1 * ln_err).exp() / safe).min(facc1) } else { 10.0 };
            h /= shrink;
            reject = true;
        }
    }
}
