//! Dormand–Prince 5(4) with Hairer's 4th-order dense output and PI step-size control.
//!
//! Hand-written rather than taken from a crate: the state is 3–10 numbers, so per-step
//! overhead dominates and a stack-allocated, monomorphised stepper is several times faster
//! than general-purpose libraries (see docs/solvers.md); it also lets us stop exactly on every
//! load-point discontinuity and report failures with their time and values.
//!
//! Coefficients: Dormand & Prince (1980); dense output and controller: Hairer, Nørsett &
//! Wanner, Solving ODEs I, 2nd ed., II.5–II.6 (code DOPRI5).

use crate::ode::{
    Integrated, IntegrationError, Integrator, OdeSystem, StepStats, Tolerances, clip_step, emit_dense, error_norm,
    initial_step,
};
use nalgebra::SVector;

/// Explicit Dormand–Prince 5(4) with dense output. Best for the non-stiff problems that lab
/// spring-sliders usually are.
#[derive(Clone, Copy, Debug)]
pub struct Dopri5 {
    /// Tolerances.
    pub tol: Tolerances,
    /// Step budget per [`integrate`](Integrator::integrate) call.
    pub max_steps: u64,
}

impl Dopri5 {
    /// With relative and absolute tolerances.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Self { tol: Tolerances { rtol, atol }, max_steps: 2_000_000 }
    }
}

// The nodes c_i are not needed: the systems are autonomous within a piece.
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

impl Integrator for Dopri5 {
    fn name(&self) -> &'static str {
        "dopri5"
    }
    fn tolerances(&self) -> Tolerances {
        self.tol
    }

    fn integrate<const D: usize, S: OdeSystem<D>>(
        &self,
        sys: &S,
        t0: f64,
        y0: SVector<f64, D>,
        t1: f64,
        h0: f64,
        t_out: &[f64],
        out: &mut impl FnMut(f64, &SVector<f64, D>),
        stats: &mut StepStats,
    ) -> Result<Integrated<D>, IntegrationError> {
        let tol = &self.tol;
        let (beta, safe, facc1, facc2) = (0.04, 0.9, 1.0 / 0.2, 1.0 / 10.0);
        let expo1 = 0.2 - beta * 0.75;
        let mut facold: f64 = 1e-4;
        let mut t = t0;
        let mut y = y0;
        let mut k1 = sys.rhs(&y);
        stats.rhs_evals += 1;
        let span = t1 - t0;
        let mut h = if h0 > 0.0 { h0.min(span) } else { initial_step(sys, &y, &k1, span, 5, tol, stats) };
        let mut next_out = 0;
        let mut reject = false;
        let mut steps = 0u64;
        loop {
            if steps >= self.max_steps {
                return Err(IntegrationError::TooManySteps { t, steps });
            }
            steps += 1;
            let (h_step, last) = clip_step(t, h, t1, span)?;
            h = h_step;
            let k2 = sys.rhs(&(y + k1 * (h * A21)));
            let k3 = sys.rhs(&(y + (k1 * A31 + k2 * A32) * h));
            let k4 = sys.rhs(&(y + (k1 * A41 + k2 * A42 + k3 * A43) * h));
            let k5 = sys.rhs(&(y + (k1 * A51 + k2 * A52 + k3 * A53 + k4 * A54) * h));
            let ys = y + (k1 * A61 + k2 * A62 + k3 * A63 + k4 * A64 + k5 * A65) * h;
            let k6 = sys.rhs(&ys);
            let y1 = y + (k1 * A71 + k3 * A73 + k4 * A74 + k5 * A75 + k6 * A76) * h;
            let k7 = sys.rhs(&y1);
            stats.rhs_evals += 6;
            let err_vec = (k1 * E1 + k3 * E3 + k4 * E4 + k5 * E5 + k6 * E6 + k7 * E7) * h;
            let err = error_norm(sys, &err_vec, &y, &y1, tol);
            let fac11 = err.powf(expo1);
            if err <= 1.0 {
                // accepted
                if let Err(reason) = sys.check(&y1) {
                    return Err(IntegrationError::Stopped { t: t + h, reason });
                }
                stats.accepted += 1;
                let t_new = if last { t1 } else { t + h };
                let yc = y;
                let dense = || {
                    let ydiff = y1 - yc;
                    let bspl = k1 * h - ydiff;
                    let r4 = ydiff - k7 * h - bspl;
                    let r5 = (k1 * D1 + k3 * D3 + k4 * D4 + k5 * D5 + k6 * D6 + k7 * D7) * h;
                    move |s: f64| {
                        let s1 = 1.0 - s;
                        yc + (ydiff + (bspl + (r4 + r5 * s1) * s) * s1) * s
                    }
                };
                emit_dense(t_out, &mut next_out, (t, h, t_new), &y1, dense, out);
                let fac = (fac11 / facold.powf(beta) / safe).clamp(facc2, facc1);
                facold = err.max(1e-4);
                let mut h_new = h / fac;
                if reject {
                    h_new = h_new.min(h);
                }
                reject = false;
                k1 = k7;
                y = y1;
                t = t_new;
                if last {
                    return Ok(Integrated { y, h_next: h_new });
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
}
