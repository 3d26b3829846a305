//! The spring-slider ODE in log variables, with its exact Jacobian.

use crate::law::StateArgs;
use crate::model::Model;

/// The spring-slider system during one piece of constant load-point velocity.
///
/// Variables `y = (x, z_1, …, z_N, δ)` with `x = ln V` (V in µm/s), `z_i = ln θ_i` (θ in s)
/// and `δ` the slip (µm). Log variables keep V and θ positive and turn the seven or more
/// orders of magnitude V spans during a hold into a range of about 16, which a plain
/// absolute tolerance controls: an error ε in `x` is a relative error ε in V.
///
/// Equations (τ = f(V, Ψ) + ηV is the stress the spring carries):
///
/// ```text
/// dz_i/dt = G_i(V, θ_i, dτ/dt) / θ_i
/// dτ/dt   = k (V_lp − V)
/// dx/dt   = (dτ/dt − ∂f/∂Ψ · Σ b_i dz_i/dt) / (∂f/∂x + ηV)     (time derivative of the balance)
/// dδ/dt   = V
/// ```
///
/// With infinite stiffness the slip rate is imposed: `dx/dt = 0` and V = V_lp.
#[derive(Clone, Copy, Debug)]
pub struct SpringSlider<'a> {
    /// The model.
    pub model: &'a Model,
    /// Load-point velocity during this piece, µm/s.
    pub v_lp: f64,
}

impl<'a> SpringSlider<'a> {
    /// The system for `model` loaded at `v_lp` (µm/s).
    pub fn new(model: &'a Model, v_lp: f64) -> Self {
        Self { model, v_lp }
    }

    /// Dimension N + 2.
    pub fn dim(&self) -> usize {
        self.model.states.len() + 2
    }

    /// Initial variables at steady state at slip rate `v` (µm/s), zero slip.
    pub fn steady_state(model: &Model, v: f64) -> Result<Vec<f64>, crate::ModelError> {
        let th = model.steady_state_thetas(v)?;
        let mut y = Vec::with_capacity(th.len() + 2);
        y.push(v.ln());
        y.extend(th.iter().map(|t| t.ln()));
        y.push(0.0);
        Ok(y)
    }

    /// Shear stress τ = f + ηV carried by the spring (the friction a load cell measures).
    pub fn stress(&self, y: &[f64]) -> f64 {
        let n = self.model.states.len();
        let m = self.model;
        let psi = m.psi_from_ln_theta(&y[1..=n]);
        m.form.friction(m.mu0, m.a, m.v0, y[0], psi) + m.eta * y[0].exp()
    }

    /// Stress rate dτ/dt at slip rate `v`.
    #[inline]
    fn stress_rate(&self, v: f64) -> f64 {
        if self.model.imposed_velocity() { 0.0 } else { self.model.stiffness * (self.v_lp - v) }
    }

    /// Right-hand side `dy/dt` into `dy` (both of length N + 2).
    #[inline]
    pub fn rhs(&self, y: &[f64], dy: &mut [f64]) {
        let m = self.model;
        let n = m.states.len();
        let x = y[0];
        let v = x.exp();
        let tau_rate = self.stress_rate(v);
        let mut psi_rate = 0.0;
        for (i, s) in m.states.iter().enumerate() {
            let theta = y[1 + i].exp();
            let g = s.law.rate(&StateArgs { v, theta, dc: s.dc, b: s.b, stress_rate: tau_rate });
            let zdot = g / theta;
            dy[1 + i] = zdot;
            psi_rate += s.b * zdot;
        }
        dy[0] = if m.imposed_velocity() {
            0.0
        } else {
            let fe = m.form.eval(m.mu0, m.a, m.v0, x, self.psi(y));
            (tau_rate - fe.f_psi * psi_rate) / (fe.f_x + m.eta * v)
        };
        dy[n + 1] = v;
    }

    #[inline]
    fn psi(&self, y: &[f64]) -> f64 {
        match self.model.form {
            // the classic form does not need Ψ for its derivatives
            crate::FrictionForm::Classic => 0.0,
            _ => self.model.psi_from_ln_theta(&y[1..=self.model.states.len()]),
        }
    }

    /// Exact Jacobian `∂(dy/dt)/∂y`, column-major into `jac` (length (N + 2)²), and the
    /// right-hand side into `dy`.
    pub fn jacobian(&self, y: &[f64], dy: &mut [f64], jac: &mut [f64]) {
        let m = self.model;
        let n = m.states.len();
        let d = n + 2;
        jac.iter_mut().for_each(|j| *j = 0.0);
        let at = |r: usize, c: usize| c * d + r;
        let x = y[0];
        let v = x.exp();
        let imposed = m.imposed_velocity();
        let tau_rate = self.stress_rate(v);
        let dtau_dx = if imposed { 0.0 } else { -m.stiffness * v };
        let mut psi_rate = 0.0;
        let mut dpsi_rate_dx = 0.0;
        for (i, s) in m.states.iter().enumerate() {
            let theta = y[1 + i].exp();
            let j = s.law.jet(&StateArgs { v, theta, dc: s.dc, b: s.b, stress_rate: tau_rate });
            let zdot = j.rate / theta;
            dy[1 + i] = zdot;
            let dz_dx = (j.d_v * v + j.d_stress_rate * dtau_dx) / theta;
            let dz_dz = j.d_theta - zdot;
            jac[at(1 + i, 0)] = dz_dx;
            jac[at(1 + i, 1 + i)] = dz_dz;
            psi_rate += s.b * zdot;
            dpsi_rate_dx += s.b * dz_dx;
        }
        dy[n + 1] = v;
        jac[at(n + 1, 0)] = v;
        if imposed {
            dy[0] = 0.0;
            return;
        }
        let fe = m.form.eval(m.mu0, m.a, m.v0, x, self.psi(y));
        let num = tau_rate - fe.f_psi * psi_rate;
        let den = fe.f_x + m.eta * v;
        let xdot = num / den;
        dy[0] = xdot;
        // column x
        let dnum_dx = dtau_dx - fe.f_psi * dpsi_rate_dx - psi_rate * fe.d_fpsi_dl;
        let dden_dx = fe.d_fx_dl + m.eta * v;
        jac[at(0, 0)] = (dnum_dx - xdot * dden_dx) / den;
        // columns z_j: ∂L/∂z_j = b_j / a
        for (jdx, s) in m.states.iter().enumerate() {
            let dl = s.b / m.a;
            let dnum = -fe.f_psi * s.b * jac[at(1 + jdx, 1 + jdx)] - psi_rate * fe.d_fpsi_dl * dl;
            let dden = fe.d_fx_dl * dl;
            jac[at(0, 1 + jdx)] = (dnum - xdot * dden) / den;
        }
    }
}
