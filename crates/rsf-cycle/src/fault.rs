//! The fault as a large ODE system: per cell, ln V, ln θ and slip.
//!
//! The unknowns follow rsf's log form: `x = ln V` and `z = ln θ` need no absolute tolerance
//! however far V falls between events (1e-15 m/s at depth) or rises in them (m/s). Slip rate is
//! an unknown, not solved for: differentiating the balance `τ0 + K(δ − V_p t) − η V = σ f(V, θ)`
//! in time gives, per cell,
//!
//! `dx/dt = (Σ_j K_ij (V_j − V_p) − σ ∂f/∂Ψ dΨ/dt) / (σ ∂f/∂ln V + η V)`,
//!
//! with `Ψ = b ln(V0 θ/Dc)` and `dz/dt = G(V, θ)/θ` (the aging law) — the formulation of QDYN,
//! here in log variables. Every friction and state evaluation goes through
//! [`rsf_core::element`].

use crate::elastic::Kernel;
use crate::params::{Bp1, EvolutionLaw};
use rsf_core::element::{friction, ln_theta_rate, psi_term};
use rsf_core::{FrictionForm, StateLaw};
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
        y.extend((0..n).map(|i| self.p.ln_theta_init(self.depth(i))));
        y.extend(std::iter::repeat_n(0.0, n));
        y
    }

    /// The shear stress on cell `i` (the strength σ f), Pa, in state `y`.
    pub fn shear_stress(&self, y: &[f64], i: usize) -> f64 {
        shear_stress(&self.p, &self.a, y, i)
    }
}

/// The shear stress (the strength σ f), Pa, on cell `i` of a fault with parameters `p` and
/// a(z) values `a`, in state `y` (ln V, ln θ, slip per cell).
pub fn shear_stress(p: &Bp1, a: &[f64], y: &[f64], i: usize) -> f64 {
    let n = a.len();
    let psi = psi_term(p.b0, p.v0, p.dc, 1.0, y[n + i]);
    p.sigma * friction(FrictionForm::Regularized, p.f0, a[i], p.v0, y[i], psi).value
}

impl LargeSystem for Fault {
    fn dim(&self) -> usize {
        3 * self.cells()
    }

    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String> {
        match self.p.law {
            EvolutionLaw::Aging => self.rhs_with(&Aging, y, dy),
            EvolutionLaw::Slip => self.rhs_with(&Slip, y, dy),
        }
    }

    fn error_scale(&self, i: usize, y0: f64, y1: f64, tol: &Tolerances) -> f64 {
        // ln V and ln θ: an absolute error on the log is a relative error on V and θ
        if i < 2 * self.cells() { tol.rtol } else { tol.atol + tol.rtol * y0.abs().max(y1.abs()) }
    }
}

impl Fault {
    /// The right-hand side with the state law `law` (monomorphised per law).
    fn rhs_with<L: StateLaw>(&mut self, law: &L, y: &[f64], dy: &mut [f64]) -> Result<(), String> {
        let n = self.cells();
        let p = &self.p;
        for i in 0..n {
            self.v[i] = y[i].exp();
        }
        if let Some(i) = self.v.iter().position(|v| !v.is_finite()) {
            return Err(format!("slip rate not finite at depth {:.0} m", self.depth(i)));
        }
        self.kernel.stressing_rate(&self.v, p.vp, &mut self.rate);
        let (dx, rest) = dy.split_at_mut(n);
        let (dz, dd) = rest.split_at_mut(n);
        for i in 0..n {
            let (x, z, v) = (y[i], y[n + i], self.v[i]);
            let psi = psi_term(p.b0, p.v0, p.dc, 1.0, z);
            let f = friction(FrictionForm::Regularized, p.f0, self.a[i], p.v0, x, psi);
            let zr = ln_theta_rate(law, x, z, p.dc, p.b0);
            dz[i] = zr;
            dx[i] = (self.rate[i] - p.sigma * f.d_psi * p.b0 * zr) / (p.sigma * f.d_ln_v + self.eta * v);
            dd[i] = v;
        }
        Ok(())
    }
}
