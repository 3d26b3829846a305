//! The spring-slider ODE in log variables, with its exact Jacobian.

mod dispatch;
mod sensitivity;
#[cfg(test)]
mod tests;

pub use dispatch::{DynLaws, LawDispatch, SameLaw};
use sensitivity::ParamJacobian;
pub use sensitivity::{
    LawParameter, N_GLOBAL, PER_STATE, extra_law_parameters, law_parameters, n_params, n_params_of, param_index,
    state_offset,
};

use crate::law::{LnArgs, StateArgs};
use crate::loading::Piece;
use crate::model::Model;

/// The spring-slider system during one piece of constant load-point velocity and constant
/// normal-stress rate.
///
/// Variables `y = (x, z_1, …, z_N, δ)` with `x = ln V` (V in µm/s), `z_i = ln θ_i` (θ in s)
/// and `δ` the slip (µm). Log variables keep V and θ positive and turn the seven or more
/// orders of magnitude V spans during a hold into a range of about 16, which a plain
/// absolute tolerance controls: an error ε in `x` is a relative error ε in V.
///
/// With normal stress σ(t) and `s = σ/σ_ref`, the friction μ = f(V, Ψ) + ηV + gδ is the shear
/// stress τ over σ, and the spring acts on τ: dτ/dt = K (V_lp − V) with K = k σ_ref. So
///
/// ```text
/// dz_i/dt = G_i(V, θ_i, …)/θ_i − (α_i/b_i) ṡ/s                      (Linker–Dieterich)
/// dμ/dt   = (k (V_lp − V) − μ ṡ)/s =: R
/// dx/dt   = (R − gV − ∂f/∂Ψ · Σ b_i dz_i/dt) / (∂f/∂x + ηV)          (time derivative of μ)
/// dδ/dt   = V
/// ```
///
/// At constant normal stress (s = 1, ṡ = 0) these are exactly the equations without it. With
/// infinite stiffness the slip rate is imposed: `dx/dt = 0` and V = V_lp. A ramp of σ makes the
/// system depend on time; [`time_derivative`](Self::time_derivative) gives ∂f/∂t for the
/// implicit methods.
#[derive(Clone, Copy, Debug)]
pub struct SpringSlider<'a> {
    /// The model (read only: the constructors cache quantities derived from it, such as ln Dc
    /// and 1/a; build a new system for a changed model).
    pub model: &'a Model,
    /// Load-point velocity during this piece, µm/s.
    pub v_lp: f64,
    /// σ/σ_ref at `t0`.
    s0: f64,
    /// d(σ/σ_ref)/dt, 1/s.
    s_rate: f64,
    /// Start of the piece, s (the origin of the σ ramp).
    t0: f64,
    /// ln Dc and 1/Dc of the first [`DC_CACHED`] states, computed once per piece instead of
    /// once per right-hand side.
    ln_dc: [f64; DC_CACHED],
    inv_dc: [f64; DC_CACHED],
    /// 1/s0 (exactly 1 at the reference normal stress).
    inv_s0: f64,
    /// 1/a, for the classic form without radiation damping, where dx/dt divides by a.
    inv_a: f64,
    /// ln V0 and the constant part of Ψ = Σ b_i (ln V0 + z_i − ln(s_i Dc_i)), Σ b_i (ln V0 −
    /// ln s_i − ln Dc_i): Ψ is then `psi0 + Σ b_i z_i`, with no logarithm per evaluation (a
    /// solution's rows evaluate it once each).
    ln_v0: f64,
    psi0: f64,
    /// The classic form's friction gathered into one linear form in the log variables,
    /// f = `classic0` + a x + Σ b_i z_i with `classic0` = μ0 − a ln V0 + `psi0` (what
    /// [`FrictionForm::friction`](crate::FrictionForm::friction) gives, with its constants
    /// summed once): the friction of a 100,000-row solution costs as much as its integration.
    classic0: f64,
}

/// How many states' Dc a [`SpringSlider`] keeps at hand (more states compute theirs). The right
/// hand side is latency-bound: a division or a logarithm in its dependency chain costs as much
/// as the arithmetic around it, so per-piece constants are precomputed.
const DC_CACHED: usize = 8;

impl<'a> SpringSlider<'a> {
    /// The system for `model` loaded at `v_lp` (µm/s) at constant normal stress σ_ref.
    pub fn new(model: &'a Model, v_lp: f64) -> Self {
        let (mut ln_dc, mut inv_dc) = ([0.0; DC_CACHED], [0.0; DC_CACHED]);
        for ((l, i), st) in ln_dc.iter_mut().zip(inv_dc.iter_mut()).zip(&model.states) {
            *l = st.dc.ln();
            *i = 1.0 / st.dc;
        }
        let ln_v0 = model.v0.ln();
        let psi0 = model
            .states
            .iter()
            .enumerate()
            .map(|(i, st)| {
                let ln_dc = if i < DC_CACHED { ln_dc[i] } else { st.dc.ln() };
                let s = st.law.theta_scale();
                st.b * (ln_v0 - if s == 1.0 { 0.0 } else { s.ln() } - ln_dc)
            })
            .sum();
        Self {
            model,
            v_lp,
            s0: 1.0,
            s_rate: 0.0,
            t0: 0.0,
            ln_dc,
            inv_dc,
            inv_s0: 1.0,
            inv_a: 1.0 / model.a,
            ln_v0,
            psi0,
            classic0: model.mu0 - model.a * ln_v0 + psi0,
        }
    }

    /// The state contribution Ψ = Σ b_i ln(V0 θ_i / (s_i Dc_i)) at `y`.
    #[inline]
    fn state_psi(&self, y: &[f64]) -> f64 {
        self.psi0 + self.model.states.iter().zip(&y[1..]).map(|(s, z)| s.b * z).sum::<f64>()
    }

    /// The system during `piece`: its load-point velocity and its normal stress (MPa, relative
    /// to the model's σ_ref).
    pub fn for_piece(model: &'a Model, piece: &Piece) -> Self {
        let sr = model.sigma_ref();
        let s0 = piece.sigma0 / sr;
        Self { s0, s_rate: piece.sigma_rate / sr, t0: piece.t0, inv_s0: 1.0 / s0, ..Self::new(model, piece.v) }
    }

    /// Whether the right-hand side depends on time (a normal-stress ramp).
    pub fn time_dependent(&self) -> bool {
        self.s_rate != 0.0
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

    /// Shear stress over normal stress, τ/σ = f + ηV + gδ: the friction a load cell measures.
    /// Inlined: it is evaluated once per output row, up to millions of times per solve.
    #[inline]
    pub fn stress(&self, y: &[f64]) -> f64 {
        let n = self.model.states.len();
        let m = self.model;
        let f = match m.form {
            crate::FrictionForm::Classic => {
                self.classic0 + m.a * y[0] + m.states.iter().zip(&y[1..]).map(|(s, z)| s.b * z).sum::<f64>()
            }
            form => form.friction_ln(m.mu0, m.a, self.ln_v0, y[0], self.state_psi(y)),
        };
        let f = if m.a_slope != 0.0 {
            let xr = y[0] - self.ln_v0;
            f + 0.5 * m.a_slope * xr * xr
        } else {
            f
        };
        let damping = if m.eta != 0.0 { m.eta * y[0].exp() } else { 0.0 };
        f + damping + m.slip_trend * y[n + 1]
    }

    /// `(s, ṡ/s)` at time `t`: normal stress over σ_ref, and its logarithmic rate (1/s).
    #[inline]
    fn sigma(&self, t: f64) -> (f64, f64) {
        if self.s_rate == 0.0 {
            (self.s0, 0.0)
        } else {
            let s = self.s0 + self.s_rate * (t - self.t0);
            (s, self.s_rate / s)
        }
    }

    /// The arguments of state `i`'s law at slip rate `v`, θ and shear-stress rate over σ.
    #[inline]
    fn args(&self, i: usize, v: f64, theta: f64, stress_rate: f64, s: f64) -> StateArgs<f64> {
        let st = &self.model.states[i];
        let sr = self.model.sigma_ref();
        StateArgs {
            v,
            theta,
            dc: st.dc,
            b: st.b,
            stress_rate,
            normal_stress: s * sr,
            normal_stress_rate: self.s_rate * sr,
        }
    }

    /// Right-hand side `dy/dt` at time `t` into `dy` (both of length N + 2). The states' rates
    /// come from their laws' log forms ([`StateLaw::ln_theta_rate`](crate::StateLaw)): with
    /// the Slip law the only transcendental call left is V = e^x.
    #[inline]
    pub fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.rhs_with(&DynLaws, t, y, dy)
    }

    /// [`rhs`](Self::rhs) reaching the laws through `laws` (see [`LawDispatch`]).
    #[inline]
    pub fn rhs_with(&self, laws: &impl LawDispatch, t: f64, y: &[f64], dy: &mut [f64]) {
        let m = self.model;
        let n = m.states.len();
        let x = y[0];
        let v = x.exp();
        let (s, log_rate) = self.sigma(t);
        let imposed = m.imposed_velocity();
        let tau_rate = if imposed {
            0.0
        } else if self.s_rate == 0.0 {
            m.stiffness * (self.v_lp - v) * self.inv_s0
        } else {
            m.stiffness * (self.v_lp - v) / s
        };
        let sr = m.sigma_ref();
        // the sums start at −0.0, the identity of IEEE addition, so that no addition to zero
        // sits on the latency-bound chain; `psi_rate_a` = Σ (b_i/a) d ln θ_i/dt has the 1/a of
        // the classic form's dx/dt applied to each term, off the chain
        let (mut psi_rate, mut psi_rate_a) = (-0.0, -0.0);
        for (i, st) in m.states.iter().enumerate() {
            let (ln_dc, inv_dc) =
                if i < DC_CACHED { (self.ln_dc[i], self.inv_dc[i]) } else { (st.dc.ln(), 1.0 / st.dc) };
            let la = LnArgs {
                x,
                v,
                v_dc: v * inv_dc,
                z: y[1 + i],
                dc: st.dc,
                inv_dc,
                ln_dc,
                b: st.b,
                stress_rate: tau_rate,
                normal_stress: s * sr,
                normal_stress_rate: self.s_rate * sr,
            };
            let mut zdot = laws.ln_rate(m, i, &la);
            if st.alpha != 0.0 && log_rate != 0.0 {
                zdot -= st.alpha / st.b * log_rate;
            }
            dy[1 + i] = zdot;
            psi_rate += st.b * zdot;
            psi_rate_a += (st.b * self.inv_a) * zdot;
        }
        dy[0] = if imposed {
            0.0
        } else if log_rate == 0.0 && m.eta == 0.0 && m.form == crate::FrictionForm::Classic && m.a_slope == 0.0 {
            // ∂f/∂x = a, ∂f/∂Ψ = 1: dx/dt = (τ̇ − gV − Ψ̇)/a
            (tau_rate * self.inv_a - (m.slip_trend * self.inv_a) * v) - psi_rate_a
        } else {
            let fe = self.friction_eval(x, y);
            let r = if log_rate == 0.0 { tau_rate } else { tau_rate - log_rate * self.stress(y) };
            (r - m.slip_trend * v - fe.f_psi * psi_rate) / (fe.f_x + m.eta * v)
        };
        dy[n + 1] = v;
    }

    /// The friction's partials at `x = ln V` and `y`: the form's, with the rate dependence of
    /// the direct effect added (∂f/∂x gains a₁ (x − ln V0), whose own x-derivative a₁ is
    /// `bend_fx_dx`; it does not depend on Ψ).
    #[inline]
    fn friction_eval(&self, x: f64, y: &[f64]) -> crate::friction::FrictionEval {
        let m = self.model;
        let mut fe = m.form.eval(m.mu0, m.a, m.v0, x, self.psi(y));
        if m.a_slope != 0.0 {
            fe.f_x += m.a_slope * (x - self.ln_v0);
            fe.bend_fx_dx = m.a_slope;
        }
        fe
    }

    #[inline]
    fn psi(&self, y: &[f64]) -> f64 {
        match self.model.form {
            // the classic form does not need Ψ for its derivatives
            crate::FrictionForm::Classic => 0.0,
            _ => self.state_psi(y),
        }
    }

    /// Exact Jacobian `∂(dy/dt)/∂y` at time `t`, column-major into `jac` (length (N + 2)²), and
    /// the right-hand side into `dy`.
    pub fn jacobian(&self, t: f64, y: &[f64], dy: &mut [f64], jac: &mut [f64]) {
        // without parameter derivatives nothing can fail
        let _ = self.jacobians(t, y, dy, jac, None);
    }

    /// [`jacobian`](Self::jacobian), and with `params` also `∂f/∂p` (see
    /// [`parameter_jacobian`](Self::parameter_jacobian)) from the same law jets: one pass over
    /// the states serves both, which is what a forward-sensitivity right-hand side needs at
    /// every stage. `params` requires the classic form and a finite stiffness (checked by the
    /// public callers). The error names a law that rejects a perturbed parameter value.
    pub(crate) fn jacobians(
        &self,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
        jac: &mut [f64],
        mut params: Option<ParamJacobian<'_>>,
    ) -> Result<(), String> {
        let m = self.model;
        let n = m.states.len();
        let d = n + 2;
        jac.iter_mut().for_each(|j| *j = 0.0);
        if let Some(p) = params.as_mut() {
            p.fp.iter_mut().for_each(|v| *v = 0.0);
        }
        let at = |r: usize, c: usize| c * d + r;
        let x = y[0];
        let v = x.exp();
        let (s, log_rate) = self.sigma(t);
        let imposed = m.imposed_velocity();
        let tau_rate = if imposed { 0.0 } else { m.stiffness * (self.v_lp - v) / s };
        let dtau_dx = if imposed { 0.0 } else { -m.stiffness * v / s };
        // the classic form's ∂f/∂x + ηV (the parameter derivatives' denominator), with the
        // direct effect's rate dependence
        let xr = x - self.ln_v0;
        let den_classic = m.a + m.a_slope * xr + m.eta * v;
        let mut psi_rate = 0.0;
        let mut dpsi_rate_dx = 0.0;
        let mut dpsi_dk = 0.0;
        for (i, st) in m.states.iter().enumerate() {
            let theta = y[1 + i].exp();
            let args = self.args(i, v, theta, tau_rate, s);
            let j = st.law.jet(&args);
            let g_theta = j.rate / theta;
            let mut zdot = g_theta;
            if st.alpha != 0.0 && log_rate != 0.0 {
                zdot -= st.alpha / st.b * log_rate;
            }
            dy[1 + i] = zdot;
            let dz_dx = (j.d_v * v + j.d_stress_rate * dtau_dx) / theta;
            // ∂(G/θ)/∂z = ∂G/∂θ − G/θ; the coupling term does not depend on z
            let dz_dz = j.d_theta - g_theta;
            jac[at(1 + i, 0)] = dz_dx;
            jac[at(1 + i, 1 + i)] = dz_dz;
            psi_rate += st.b * zdot;
            dpsi_rate_dx += st.b * dz_dx;
            if let Some(p) = params.as_mut() {
                let (fp, den) = (&mut *p.fp, den_classic);
                let off = state_offset(i);
                let dz_dk = j.d_stress_rate * (self.v_lp - v) / s / theta;
                let mut dz_db = j.d_b / theta;
                let dz_ddc = j.d_dc / theta;
                if log_rate != 0.0 {
                    // the coupling −(α/b) ṡ/s
                    dz_db += st.alpha / (st.b * st.b) * log_rate;
                    fp[at(1 + i, off + 3)] = -log_rate / st.b;
                    fp[at(0, off + 3)] = log_rate / den;
                }
                fp[at(1 + i, 2)] = dz_dk;
                fp[at(1 + i, off)] = dz_db;
                fp[at(1 + i, off + 1)] = dz_ddc;
                dpsi_dk += st.b * dz_dk;
                fp[at(0, off)] = -(zdot + st.b * dz_db) / den;
                fp[at(0, off + 1)] = -st.b * dz_ddc / den;
                // the law's own parameter: exact where the law gives it, else a central
                // difference of its rate (relative step 1e-6)
                if let Some((name, q)) = p.law_parameters[i] {
                    let dg_dq = match st.law.parameter_derivative(name, &args) {
                        Some(d) => d,
                        None => {
                            let h = 1e-6 * q.abs().max(1e-12);
                            let rate = |qq: f64| st.law.rate_with_parameter(name, qq, &args);
                            (rate(q + h)? - rate(q - h)?) / (2.0 * h)
                        }
                    };
                    let dz_dq = dg_dq / theta;
                    fp[at(1 + i, off + 2)] = dz_dq;
                    fp[at(0, off + 2)] = -st.b * dz_dq / den;
                }
            }
        }
        dy[n + 1] = v;
        jac[at(n + 1, 0)] = v;
        if imposed {
            dy[0] = 0.0;
            return Ok(());
        }
        let fe = self.friction_eval(x, y);
        let mu = if log_rate == 0.0 { 0.0 } else { self.stress(y) };
        let r = if log_rate == 0.0 { tau_rate } else { tau_rate - log_rate * mu };
        let num = r - m.slip_trend * v - fe.f_psi * psi_rate;
        let den = fe.f_x + m.eta * v;
        let xdot = num / den;
        dy[0] = xdot;
        // column x (∂μ/∂x = f_x + ηV enters R through −(ṡ/s) μ)
        let dr_dx = dtau_dx - log_rate * den;
        let dnum_dx = dr_dx - m.slip_trend * v - fe.f_psi * dpsi_rate_dx - psi_rate * fe.d_fpsi_dl;
        let dden_dx = fe.d_fx_dl + fe.bend_fx_dx + m.eta * v;
        jac[at(0, 0)] = (dnum_dx - xdot * dden_dx) / den;
        // columns z_j: ∂L/∂z_j = b_j / a, ∂μ/∂z_j = f_Ψ b_j
        for (jdx, st) in m.states.iter().enumerate() {
            let dl = st.b / m.a;
            let dnum = -fe.f_psi * st.b * jac[at(1 + jdx, 1 + jdx)]
                - psi_rate * fe.d_fpsi_dl * dl
                - log_rate * fe.f_psi * st.b;
            let dden = fe.d_fx_dl * dl;
            jac[at(0, 1 + jdx)] = (dnum - xdot * dden) / den;
        }
        // column δ: μ carries gδ
        jac[at(0, n + 1)] = -log_rate * m.slip_trend / den;
        if let Some(p) = params {
            // the global columns (the classic form: xdot = (R − gV − Ψ̇)/(a + ηV) as above)
            let fp = p.fp;
            fp[at(0, 1)] = -xdot / den_classic;
            fp[at(0, 2)] = ((self.v_lp - v) / s - dpsi_dk) / den_classic;
            fp[at(0, 3)] = -v / den_classic;
            // a₁ enters ∂f/∂x as a₁ (x − ln V0)
            fp[at(0, 4)] = -xdot * xr / den_classic;
            if log_rate != 0.0 {
                // R = k (V_lp − V)/s − (ṡ/s) μ: μ's own parameter dependence
                let mut gy = vec![0.0; d];
                let mut gp = vec![0.0; n_params(n)];
                self.stress_gradients(y, &mut gy, &mut gp)?;
                for (jp, g) in gp.iter().enumerate() {
                    fp[at(0, jp)] -= log_rate * g / den_classic;
                }
            }
        }
        Ok(())
    }

    /// `∂f/∂t` at time `t` into `dfdt` (zero unless the normal stress ramps): the right-hand side
    /// depends on time only through σ(t), so ∂f/∂t = ∂f/∂s · ṡ, by a central difference in s
    /// (relative step 1e-7: the truncation error of a smooth function at that step is below
    /// 1e-12 relative, far under any tolerance the implicit methods are run at).
    pub fn time_derivative(&self, t: f64, y: &[f64], dfdt: &mut [f64]) {
        if self.s_rate == 0.0 {
            dfdt.iter_mut().for_each(|x| *x = 0.0);
            return;
        }
        let dt = self.ramp_time_step(t);
        let mut fp = vec![0.0; y.len()];
        self.rhs(t + dt, y, &mut fp);
        self.rhs(t - dt, y, dfdt);
        for (o, p) in dfdt.iter_mut().zip(&fp) {
            *o = (p - *o) / (2.0 * dt);
        }
    }

    /// The time step (s) of a central difference in t under a normal-stress ramp: the time in
    /// which σ changes by 1e-7 of itself (the step [`time_derivative`](Self::time_derivative)
    /// takes; systems that augment this one difference theirs with it too). Infinite at
    /// constant σ.
    pub fn ramp_time_step(&self, t: f64) -> f64 {
        if self.s_rate == 0.0 { f64::INFINITY } else { (1e-7 * self.sigma(t).0 / self.s_rate).abs() }
    }

    /// Applies an instantaneous normal-stress step σ⁻ → σ⁺ (MPa) to `y` at a fixed load point:
    /// the spring does not move, so τ = σ μ is continuous (μ⁺ = μ⁻ σ⁻/σ⁺); each state jumps to
    /// θ_i (σ⁻/σ⁺)^(α_i/b_i) (Linker & Dieterich 1992); the slip rate follows from the friction
    /// law at μ⁺ (with infinite stiffness V stays V_lp and μ jumps with θ instead).
    pub fn normal_stress_step(&self, y: &mut [f64], sigma_minus: f64, sigma_plus: f64) -> Result<(), String> {
        let m = self.model;
        let n = m.states.len();
        let ln_ratio = (sigma_minus / sigma_plus).ln();
        let mu_plus = self.stress(y) * (sigma_minus / sigma_plus);
        for (i, st) in m.states.iter().enumerate() {
            if st.alpha != 0.0 {
                y[1 + i] += st.alpha / st.b * ln_ratio;
            }
        }
        if m.imposed_velocity() {
            return Ok(());
        }
        let psi = self.state_psi(y);
        let target = mu_plus - m.slip_trend * y[n + 1];
        let fail = |why: String| {
            format!(
                "no slip rate carries friction {mu_plus} after the normal-stress step {sigma_minus} → {sigma_plus} MPa: {why}"
            )
        };
        if m.eta != 0.0 && m.a_slope != 0.0 {
            return Err(fail("a rate-dependent direct effect with radiation damping has no slip-rate solve".into()));
        }
        y[0] = if m.eta == 0.0 {
            // the friction law inverted in closed form
            match m.slip_rate(target, psi) {
                Some(v) if v > 0.0 && v.is_finite() => v.ln(),
                _ => return Err(fail("the friction law has no positive root".into())),
            }
        } else {
            crate::element::solve_slip_rate(m.form, m.mu0, m.a, m.v0, psi, target, 1.0, m.eta, y[0])
                .map_err(|e| fail(e.to_string()))?
                .ln_v
        };
        Ok(())
    }
}
