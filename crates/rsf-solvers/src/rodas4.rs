//! Rodas4: a 6-stage, L-stable, stiffly accurate Rosenbrock method of order 4(3) with a
//! 3rd-order dense output, using the system's exact Jacobian.
//!
//! Hand-written for the same reasons as [`Dopri5`](crate::Dopri5): tiny fixed-size systems,
//! exact stops at load-point discontinuities, and clear failure reports. Rosenbrock methods
//! need no Newton iteration: each step is one Jacobian, one LU of `I/(hγ) − J` and six
//! linear solves, so an exact Jacobian (which every rsf law provides through dual numbers)
//! is used to the full.
//!
//! Coefficients: Hairer & Wanner, Solving ODEs II, 2nd ed., VI.4 (code RODAS), in the
//! increment form `(I/(hγ) − J) k_i = f(y + Σ a_ij k_j) + Σ (c_ij/h) k_j`.

use crate::ode::{
    Integrated, IntegrationError, Integrator, OdeSystem, StepStats, Tolerances, clip_step, emit_dense, error_norm,
    initial_step,
};
use nalgebra::{SMatrix, SVector};

/// Implicit (linearly implicit) Rodas4 with exact Jacobian. For stiff problems: very stiff
/// machines, tiny Dc, steps to fast slip rates, multi-state laws with widely separated Dc.
#[derive(Clone, Copy, Debug)]
pub struct Rodas4 {
    /// Tolerances.
    pub tol: Tolerances,
    /// Step budget per [`integrate`](Integrator::integrate) call.
    pub max_steps: u64,
}

impl Rodas4 {
    /// With relative and absolute tolerances.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Self { tol: Tolerances { rtol, atol }, max_steps: 2_000_000 }
    }
}

const GAMMA: f64 = 0.25;
const A21: f64 = 1.544;
const A31: f64 = 0.9466785280815826;
const A32: f64 = 0.2557011698983284;
const A41: f64 = 3.314825187068521;
const A42: f64 = 2.896124015972201;
const A43: f64 = 0.9986419139977817;
const A51: f64 = 1.221224509226641;
const A52: f64 = 6.019134481288629;
const A53: f64 = 12.53708332932087;
const A54: f64 = -0.6878860361058950;
const C21: f64 = -5.6688;
const C31: f64 = -2.430093356833875;
const C32: f64 = -0.2063599157091915;
const C41: f64 = -0.1073529058151375;
const C42: f64 = -9.594562251023355;
const C43: f64 = -20.47028614809616;
const C51: f64 = 7.496443313967647;
const C52: f64 = -10.24680431464352;
const C53: f64 = -33.99990352819905;
const C54: f64 = 11.70890893206160;
const C61: f64 = 8.083246795921522;
const C62: f64 = -7.981132988064893;
const C63: f64 = -31.52159432874371;
const C64: f64 = 16.31930543123136;
const C65: f64 = -6.058818238834054;
const H21: f64 = 10.12623508344586;
const H22: f64 = -7.487995877610167;
const H23: f64 = -34.80091861555747;
const H24: f64 = -7.992771707568823;
const H25: f64 = 1.025137723295662;
const H31: f64 = -0.6762803392801253;
const H32: f64 = 6.087714651680015;
const H33: f64 = 16.43084320892478;
const H34: f64 = 24.76722511418386;
const H35: f64 = -6.594389125716872;

/// LU factorisation with partial pivoting of a small dense matrix, in place.
struct Lu<const D: usize> {
    m: SMatrix<f64, D, D>,
    piv: [usize; D],
}

impl<const D: usize> Lu<D> {
    fn new(mut m: SMatrix<f64, D, D>) -> Option<Self> {
        let mut piv = [0usize; D];
        for k in 0..D {
            let mut p = k;
            let mut best = m[(k, k)].abs();
            for i in k + 1..D {
                if m[(i, k)].abs() > best {
                    best = m[(i, k)].abs();
                    p = i;
                }
            }
            if best == 0.0 || !best.is_finite() {
                return None;
            }
            piv[k] = p;
            if p != k {
                m.swap_rows(p, k);
            }
            let inv = 1.0 / m[(k, k)];
            for i in k + 1..D {
                let l = m[(i, k)] * inv;
                m[(i, k)] = l;
                for j in k + 1..D {
                    m[(i, j)] -= l * m[(k, j)];
                }
            }
        }
        Some(Self { m, piv })
    }

    #[inline]
    fn solve(&self, mut b: SVector<f64, D>) -> SVector<f64, D> {
        for k in 0..D {
            b.swap_rows(k, self.piv[k]);
        }
        for i in 0..D {
            let mut s = b[i];
            for j in 0..i {
                s -= self.m[(i, j)] * b[j];
            }
            b[i] = s;
        }
        for i in (0..D).rev() {
            let mut s = b[i];
            for j in i + 1..D {
                s -= self.m[(i, j)] * b[j];
            }
            b[i] = s / self.m[(i, i)];
        }
        b
    }
}

impl Integrator for Rodas4 {
    fn name(&self) -> &'static str {
        "rodas4"
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
        let span = t1 - t0;
        let mut t = t0;
        let mut y = y0;
        let mut h = h0;
        let mut next_out = 0;
        let mut reject = false;
        let mut steps = 0u64;
        let mut fresh = true;
        let (mut f0, mut jac) = (SVector::<f64, D>::zeros(), SMatrix::<f64, D, D>::zeros());
        loop {
            if fresh {
                let (f, j) = sys.rhs_and_jacobian(&y);
                f0 = f;
                jac = j;
                stats.rhs_evals += 1;
                stats.jacobian_evals += 1;
                if h <= 0.0 {
                    h = initial_step(sys, &y, &f0, span, 4, tol, stats);
                }
                fresh = false;
            }
            if steps >= self.max_steps {
                return Err(IntegrationError::TooManySteps { t, steps });
            }
            steps += 1;
            let (h_step, last) = clip_step(t, h, t1, span)?;
            h = h_step;
            let w = SMatrix::<f64, D, D>::identity() * (1.0 / (h * GAMMA)) - jac;
            let lu = Lu::new(w).ok_or(IntegrationError::Singular { t })?;
            stats.lu_decompositions += 1;
            let ih = 1.0 / h;
            let k1 = lu.solve(f0);
            let k2 = lu.solve(sys.rhs(&(y + k1 * A21)) + k1 * (C21 * ih));
            let k3 = lu.solve(sys.rhs(&(y + k1 * A31 + k2 * A32)) + (k1 * C31 + k2 * C32) * ih);
            let k4 = lu.solve(sys.rhs(&(y + k1 * A41 + k2 * A42 + k3 * A43)) + (k1 * C41 + k2 * C42 + k3 * C43) * ih);
            let y5 = y + k1 * A51 + k2 * A52 + k3 * A53 + k4 * A54;
            let k5 = lu.solve(sys.rhs(&y5) + (k1 * C51 + k2 * C52 + k3 * C53 + k4 * C54) * ih);
            let y6 = y5 + k5;
            let k6 = lu.solve(sys.rhs(&y6) + (k1 * C61 + k2 * C62 + k3 * C63 + k4 * C64 + k5 * C65) * ih);
            stats.rhs_evals += 5;
            let y1 = y6 + k6;
            let err = error_norm(sys, &k6, &y, &y1, tol);
            let mut fac = (err.powf(0.25) / 0.9).clamp(0.2, 6.0);
            if !err.is_finite() {
                fac = 10.0;
            }
            if err <= 1.0 {
                if let Err(reason) = sys.check(&y1) {
                    return Err(IntegrationError::Stopped { t: t + h, reason });
                }
                stats.accepted += 1;
                let t_new = if last { t1 } else { t + h };
                let yc = y;
                let dense = || {
                    let d1 = k1 * H21 + k2 * H22 + k3 * H23 + k4 * H24 + k5 * H25;
                    let d2 = k1 * H31 + k2 * H32 + k3 * H33 + k4 * H34 + k5 * H35;
                    move |s: f64| yc * (1.0 - s) + (y1 + (d1 + d2 * s) * (1.0 - s)) * s
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
                    return Ok(Integrated { y, h_next: h_new });
                }
                h = h_new;
                fresh = true;
            } else {
                stats.rejected += 1;
                h /= fac;
                reject = true;
            }
        }
    }
}
