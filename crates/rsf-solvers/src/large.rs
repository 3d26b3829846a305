//! Integration of large systems (thousands of unknowns on the heap): the fault-simulation
//! sibling of [`Integrator`](crate::Integrator), for earthquake-cycle models where each
//! right-hand side is an elastic interaction over every element.
//!
//! [`LargeTsit5`] is the Tsitouras 5(4) pair of [`Tsit5`](crate::Tsit5) (the same
//! coefficients, `tableau/tsit5.rs`) on slices, with Hairer's PI step control and the **max**
//! norm of the scaled error: in a cycle model one element nucleating an event must control the
//! step, which an RMS over thousands of quiet elements would hide (QDYN's RKF45 and the SEAS
//! groups' RK methods use the max norm for the same reason). The stage buffers are allocated
//! once per call; the system may keep its own workspaces (it is called through `&mut`).

use crate::ode::{IntegrationError, StepStats, Tolerances, h_min};
use crate::tableau::tsit5::{A, E};

/// `dy/dt = f(t, y)` with `y` of fixed length [`dim`](LargeSystem::dim).
pub trait LargeSystem {
    /// Number of unknowns.
    fn dim(&self) -> usize;
    /// Writes `f(t, y)` into `dy`; an `Err` stops the integration with its message.
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String>;
    /// The error scale of component `i` (an error equal to it is just acceptable). Default
    /// `atol + rtol·max(|y0|, |y1|)`; log variables want `rtol` alone.
    fn error_scale(&self, i: usize, y0: f64, y1: f64, tol: &Tolerances) -> f64 {
        let _ = i;
        tol.atol + tol.rtol * y0.abs().max(y1.abs())
    }
}

/// What the observer tells the integrator after an accepted step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Go on.
    Continue,
    /// Stop here (the observer has what it needs).
    Stop,
}

/// Adaptive Tsitouras 5(4) for large systems.
#[derive(Clone, Copy, Debug)]
pub struct LargeTsit5 {
    /// Tolerances.
    pub tol: Tolerances,
    /// Step budget per call.
    pub max_steps: u64,
    /// Largest step, s (e.g. a fraction of the output interval); infinite by default.
    pub h_max: f64,
}

impl LargeTsit5 {
    /// With relative and absolute tolerances.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Self { tol: Tolerances { rtol, atol }, max_steps: 50_000_000, h_max: f64::INFINITY }
    }

    /// Integrates `sys` from `(t0, y)` to `t1`, updating `y` in place. After every accepted
    /// step `observe(t, y, stats)` may record output or events, or stop early. `h0 > 0`
    /// proposes the first step. Returns the time reached.
    pub fn integrate<S: LargeSystem>(
        &self,
        sys: &mut S,
        t0: f64,
        y: &mut [f64],
        t1: f64,
        h0: f64,
        mut observe: impl FnMut(f64, &[f64], &StepStats) -> Flow,
        stats: &mut StepStats,
    ) -> Result<f64, IntegrationError> {
        let n = sys.dim();
        assert_eq!(y.len(), n, "state length differs from LargeSystem::dim");
        let stop = |t: f64, e: String| IntegrationError::Stopped { t, reason: e };
        let mut k: Vec<Vec<f64>> = vec![vec![0.0; n]; 7];
        let (mut arg, mut y1) = (vec![0.0; n], vec![0.0; n]);
        sys.rhs(t0, y, &mut k[0]).map_err(|e| stop(t0, e))?;
        stats.rhs_evals += 1;
        let (beta, safe, facc1, facc2) = (0.04, 0.9, 5.0, 0.1);
        let expo1 = 0.2 - beta * 0.75;
        let mut facold: f64 = 1e-4;
        let mut t = t0;
        let mut h = if h0 > 0.0 { h0 } else { ((t1 - t0) * 1e-6).max(h_min(t0)) }.min(self.h_max);
        let (mut steps, mut reject) = (0u64, false);
        // the nodes c_i of stages 2–7 (row sums of a_ij)
        let c: [f64; 6] = std::array::from_fn(|i| A[i].iter().sum());
        while t < t1 {
            if steps >= self.max_steps {
                return Err(IntegrationError::TooManySteps { t, steps });
            }
            steps += 1;
            let last = t + h >= t1;
            if last {
                h = t1 - t;
            }
            if h < h_min(t) {
                return Err(IntegrationError::StepSizeUnderflow { t, h });
            }
            for s in 1..7 {
                for i in 0..n {
                    let mut acc = 0.0;
                    for j in 0..s {
                        acc += A[s - 1][j] * k[j][i];
                    }
                    arg[i] = y[i] + h * acc;
                }
                sys.rhs(t + c[s - 1] * h, &arg, &mut k[s]).map_err(|e| stop(t, e))?;
            }
            stats.rhs_evals += 6;
            // FSAL: the last stage's argument is the new solution
            y1.copy_from_slice(&arg);
            let mut err: f64 = 0.0;
            for i in 0..n {
                let mut e = 0.0;
                for j in 0..7 {
                    e += E[j] * k[j][i];
                }
                err = err.max((h * e).abs() / sys.error_scale(i, y[i], y1[i], &self.tol));
            }
            if !err.is_finite() {
                err = f64::INFINITY;
            }
            let fac11 = err.powf(expo1);
            if err <= 1.0 {
                stats.accepted += 1;
                t = if last { t1 } else { t + h };
                y.copy_from_slice(&y1);
                k.swap(0, 6);
                let fac = (fac11 / facold.powf(beta) / safe).clamp(facc2, facc1);
                facold = err.max(1e-4);
                let mut h_new = (h / fac).min(self.h_max);
                if reject {
                    h_new = h_new.min(h);
                }
                reject = false;
                if observe(t, y, stats) == Flow::Stop {
                    return Ok(t);
                }
                h = h_new;
            } else {
                stats.rejected += 1;
                h /= if err.is_finite() { (fac11 / safe).min(facc1) } else { 10.0 };
                reject = true;
            }
        }
        Ok(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of 200 decoupled linear oscillators with known solution, and a stiff-ish
    /// diffusion line: the large stepper reaches the tolerance and agrees with the small one.
    struct Osc {
        n: usize,
    }
    impl LargeSystem for Osc {
        fn dim(&self) -> usize {
            2 * self.n
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String> {
            for i in 0..self.n {
                let w = 1.0 + i as f64 / self.n as f64;
                dy[2 * i] = w * y[2 * i + 1];
                dy[2 * i + 1] = -w * y[2 * i];
            }
            Ok(())
        }
    }

    #[test]
    fn oscillators_to_tolerance_with_observer() {
        let n = 200;
        let mut y: Vec<f64> = (0..n).flat_map(|_| [1.0, 0.0]).collect();
        let mut stats = StepStats::default();
        let mut seen = 0;
        let t = LargeTsit5::new(1e-9, 1e-12)
            .integrate(
                &mut Osc { n },
                0.0,
                &mut y,
                10.0,
                0.0,
                |_, _, _| {
                    seen += 1;
                    Flow::Continue
                },
                &mut stats,
            )
            .unwrap();
        assert_eq!(t, 10.0);
        assert_eq!(seen, stats.accepted);
        let err = (0..n)
            .map(|i| {
                let w = 1.0 + i as f64 / n as f64;
                ((y[2 * i] - (w * 10.0).cos()).abs()).max((y[2 * i + 1] + (w * 10.0).sin()).abs())
            })
            .fold(0.0, f64::max);
        assert!(err < 1e-7, "max error {err:e} in {} steps", stats.accepted);
        // an early stop from the observer
        let mut y: Vec<f64> = (0..n).flat_map(|_| [1.0, 0.0]).collect();
        let t = LargeTsit5::new(1e-9, 1e-12)
            .integrate(
                &mut Osc { n },
                0.0,
                &mut y,
                10.0,
                0.0,
                |t, _, _| if t > 1.0 { Flow::Stop } else { Flow::Continue },
                &mut stats,
            )
            .unwrap();
        assert!(t > 1.0 && t < 2.0);
    }
}
