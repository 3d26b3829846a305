//! The fault as a large ODE system: per cell, ln V, ln θ of each state variable, and slip.
//!
//! The unknowns follow rsf's log form: `x = ln V` and `z = ln θ` need no absolute tolerance
//! however far V falls between events (1e-15 m/s at depth) or rises in them (m/s). Slip rate is
//! an unknown, not solved for: differentiating the balance `τ0 + K(δ − V_p t) − η V = σ f(V, θ)`
//! in time gives, per cell,
//!
//! `dx/dt = (Σ_j K_ij (V_j − V_p) − σ ∂f/∂Ψ dΨ/dt) / (σ ∂f/∂ln V + η V)`,
//!
//! with `Ψ = Σ_k b_k ln(V0 θ_k/Dc_k)` and `dz_k/dt = G_k(V, θ_k)/θ_k` (the aging law of the
//! benchmark, the slip law, or two state variables) — the formulation of QDYN, here in log
//! variables. Every friction and state evaluation goes through [`rsf_core::element`]. The layout
//! of `y` is blocks of n: ln V, then ln θ of each state, then slip.

use crate::elastic::Kernel;
use crate::params::{Bp1, EvolutionLaw};
use rsf_core::FrictionForm;
use rsf_core::element::{friction, ln_theta_rate, psi_term};
use rsf_laws::{Aging, Slip};
use rsf_solvers::{LargeSystem, Tolerances};

/// The BP1-QD fault discretised into `n` cells over [0, W_f].
pub struct Fault {
    /// Parameters.
    pub p: Bp1,
    /// a at each cell centre.
    pub a: Vec<f64>,
    /// Cell size, m.
    pub dz: f64,
    eta: f64,
    kernel: Kernel,
    v: Vec<f64>,
    rate: Vec<f64>,
}

/// d ln θ/dt of one state of law `law` (one branch per call: cheap beside the exponentials).
#[inline]
fn ln_rate(law: EvolutionLaw, x: f64, z: f64, dc: f64, b: f64) -> f64 {
    match law {
        EvolutionLaw::Aging => ln_theta_rate(&Aging, x, z, dc, b),
        EvolutionLaw::Slip => ln_theta_rate(&Slip, x, z, dc, b),
    }
}

impl Fault {
    /// `n` equal cells.
    pub fn new(p: Bp1, n: usize) -> Self {
        let dz = p.wf / n as f64;
        let a = (0..n).map(|i| p.a((i as f64 + 0.5) * dz)).collect();
        let kernel = Kernel::new(p.mu(), p.wf, n);
        Self { eta: p.eta(), a, dz, kernel, v: vec![0.0; n], rate: vec![0.0; n], p }
    }

    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.a.len()
    }

    /// Depth of cell `i`'s centre, m.
    pub fn depth(&self, i: usize) -> f64 {
        (i as f64 + 0.5) * self.dz
    }

    /// The benchmark's initial state: V = V_init, the depth-dependent θ, zero slip.
    pub fn initial_state(&self) -> Vec<f64> {
        let n = self.cells();
        let mut y = vec![self.p.v_init.ln(); n];
        for k in 0..self.p.states() {
            let shift = (self.p.state(k).2 / self.p.dc).ln();
            y.extend((0..n).map(|i| self.p.ln_theta_init(self.depth(i)) + shift));
        }
        y.extend(std::iter::repeat_n(0.0, n));
        y
    }

    /// The shear stress on cell `i` (the strength σ f), Pa, in state `y`.
    pub fn shear_stress(&self, y: &[f64], i: usize) -> f64 {
        shear_stress(&self.p, &self.a, y, i)
    }
}

/// Index of cell `i`'s slip in `y` for a fault of `n` cells with parameters `p`.
pub fn slip_index(p: &Bp1, n: usize, i: usize) -> usize {
    (1 + p.states()) * n + i
}

/// Ψ of cell `i` in state `y`.
fn psi(p: &Bp1, n: usize, y: &[f64], i: usize) -> f64 {
    (0..p.states())
        .map(|k| {
            let (_, b, dc) = p.state(k);
            psi_term(b, p.v0, dc, 1.0, y[(1 + k) * n + i])
        })
        .sum()
}

/// The shear stress (the strength σ f), Pa, on cell `i` of a fault with parameters `p` and
/// a(z) values `a`, in state `y`.
pub fn shear_stress(p: &Bp1, a: &[f64], y: &[f64], i: usize) -> f64 {
    let n = a.len();
    p.sigma * friction(FrictionForm::Regularized, p.f0, a[i], p.v0, y[i], psi(p, n, y, i)).value
}

impl LargeSystem for Fault {
    fn dim(&self) -> usize {
        (2 + self.p.states()) * self.cells()
    }

    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String> {
        let n = self.cells();
        let p = &self.p;
        let m = p.states();
        for i in 0..n {
            self.v[i] = y[i].exp();
        }
        if let Some(i) = self.v.iter().position(|v| !v.is_finite()) {
            return Err(format!("slip rate not finite at depth {:.0} m", self.depth(i)));
        }
        self.kernel.stressing_rate(&self.v, p.vp, &mut self.rate);
        for i in 0..n {
            let (x, v) = (y[i], self.v[i]);
            let f = friction(FrictionForm::Regularized, p.f0, self.a[i], p.v0, x, psi(p, n, y, i));
            let mut psi_rate = 0.0;
            for k in 0..m {
                let (law, b, dc) = p.state(k);
                let zr = ln_rate(law, x, y[(1 + k) * n + i], dc, b);
                dy[(1 + k) * n + i] = zr;
                psi_rate += b * zr;
            }
            dy[i] = (self.rate[i] - p.sigma * f.d_psi * psi_rate) / (p.sigma * f.d_ln_v + self.eta * v);
            dy[(1 + m) * n + i] = v;
        }
        Ok(())
    }

    fn error_scale(&self, i: usize, y0: f64, y1: f64, tol: &Tolerances) -> f64 {
        // ln V and ln θ: an absolute error on the log is a relative error on V and θ
        if i < (1 + self.p.states()) * self.cells() { tol.rtol } else { tol.atol + tol.rtol * y0.abs().max(y1.abs()) }
    }
}
