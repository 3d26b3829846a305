//! Parameter layout and exact parameter derivatives of the spring-slider (for forward
//! sensitivities).

use super::SpringSlider;
use crate::model::Model;

/// Number of global parameters in the sensitivity layout: `mu0, a, k, g`.
pub const N_GLOBAL: usize = 4;

/// Parameters per state variable in the layout of [`n_params`]: `b, dc, q, alpha`.
pub const PER_STATE: usize = 4;

/// Number of model parameters for sensitivities with `n` state variables: the layout is
/// `[mu0, a, k, g, b_1, dc_1, q_1, alpha_1, …, b_n, dc_n, q_n, alpha_n]`, where g is the slip
/// trend, `q_i` the law's first own parameter (Kato–Tullis `vc`, Nagata `c`; unused for laws
/// without one) and `alpha_i` the Linker–Dieterich normal-stress coupling.
pub fn n_params(n_states: usize) -> usize {
    N_GLOBAL + PER_STATE * n_states
}

/// Index of `b_i` (0-based state `i`) in the layout of [`n_params`]; `dc_i`, `q_i` and
/// `alpha_i` follow.
pub fn state_offset(i: usize) -> usize {
    N_GLOBAL + PER_STATE * i
}

impl Model {
    /// The parameters in the layout of [`n_params`] (an unused law-parameter slot is 0).
    pub fn parameter_vector(&self) -> Vec<f64> {
        let mut p = vec![self.mu0, self.a, self.stiffness, self.slip_trend];
        for s in &self.states {
            p.extend([s.b, s.dc, s.law.parameters().first().map(|x| x.1).unwrap_or(0.0), s.alpha]);
        }
        p
    }

    /// A copy with the parameters `p` (layout of [`n_params`]); each law's own parameter is set
    /// by name. The error names a law that rejects its value.
    pub fn with_parameter_vector(&self, p: &[f64]) -> Result<Model, String> {
        if p.len() < n_params(self.states.len()) {
            return Err(format!("{} parameters for {} expected", p.len(), n_params(self.states.len())));
        }
        let mut m = self.clone();
        m.mu0 = p[0];
        m.a = p[1];
        m.stiffness = p[2];
        m.slip_trend = p[3];
        for (i, s) in m.states.iter_mut().enumerate() {
            s.b = p[state_offset(i)];
            s.dc = p[state_offset(i) + 1];
            s.alpha = p[state_offset(i) + 3];
            if let Some((name, _)) = s.law.parameters().first().copied() {
                s.law = s.law.with_parameter(name, p[state_offset(i) + 2])?;
            }
        }
        Ok(m)
    }
}

/// Index of a named parameter in the layout of [`n_params`]: `mu0`, `a`, `k`, `b1`, `dc1`,
/// `q1` (or the law's own name, e.g. `vc1`), `alpha1`, `b2`, …; `b`/`dc`/`alpha` alone mean
/// state 1.
pub fn param_index(model: &Model, name: &str) -> Option<usize> {
    match name {
        "mu0" => return Some(0),
        "a" => return Some(1),
        "k" | "stiffness" => return Some(2),
        "g" | "slip_trend" => return Some(3),
        _ => {}
    }
    let split = name.find(|c: char| c.is_ascii_digit()).unwrap_or(name.len());
    let (base, num) = name.split_at(split);
    let i: usize = if num.is_empty() { 1 } else { num.parse().ok()? };
    if i == 0 || i > model.states.len() {
        return None;
    }
    let off = state_offset(i - 1);
    match base {
        "b" => Some(off),
        "dc" => Some(off + 1),
        "alpha" => Some(off + 3),
        "q" if !model.states[i - 1].law.parameters().is_empty() => Some(off + 2),
        other => {
            let own = model.states[i - 1].law.parameters();
            if own.first().map(|p| p.0) == Some(other) { Some(off + 2) } else { None }
        }
    }
}

/// A law's own first parameter (name, value), the `q_i` of [`n_params`]'s layout; `None` for
/// a law without one.
pub type LawParameter = Option<(&'static str, f64)>;

/// The [`LawParameter`] of each state of `model`, in state order.
pub fn law_parameters(model: &Model) -> Vec<LawParameter> {
    model.states.iter().map(|s| s.law.parameters().first().copied()).collect()
}

/// Where [`SpringSlider::jacobians`] writes `∂f/∂p`, and the laws' own parameters it perturbs.
pub(crate) struct ParamJacobian<'a> {
    /// Column-major `(N + 2) × P`.
    pub(crate) fp: &'a mut [f64],
    pub(crate) law_parameters: &'a [LawParameter],
}

impl SpringSlider<'_> {
    fn check_sensitivity_support(&self) -> Result<(), String> {
        if self.model.form != crate::FrictionForm::Classic {
            return Err("parameter sensitivities need the classic friction form".into());
        }
        if self.model.imposed_velocity() {
            return Err("parameter sensitivities need a finite stiffness".into());
        }
        Ok(())
    }

    /// `∂f/∂p` at time `t`: the derivative of the right-hand side with respect to the
    /// parameters of [`n_params`], column-major `(N + 2) × P` into `fp`. Classic form only.
    /// The law's own parameter enters through a central difference of its rate (relative step
    /// 1e-6); everything else is exact.
    pub fn parameter_jacobian(&self, t: f64, y: &[f64], fp: &mut [f64]) -> Result<(), String> {
        let d = self.dim();
        let (mut dy, mut jac) = (vec![0.0; d], vec![0.0; d * d]);
        self.sensitivity_jacobians(t, y, &mut dy, &mut jac, fp, &law_parameters(self.model))
    }

    /// The right-hand side into `dy`, [`jacobian`](Self::jacobian) into `jac` and
    /// [`parameter_jacobian`](Self::parameter_jacobian) into `fp`, from one evaluation of each
    /// law's jet: the right-hand side of a forward-sensitivity solve, dS/dt = J S + ∂f/∂p.
    /// `law_parameters` is [`law_parameters`] of the model (computed once by the caller).
    /// Each output equals what its own method gives, to the bit.
    pub fn sensitivity_jacobians(
        &self,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
        jac: &mut [f64],
        fp: &mut [f64],
        law_parameters: &[LawParameter],
    ) -> Result<(), String> {
        self.check_sensitivity_support()?;
        if law_parameters.len() != self.model.states.len() {
            return Err(format!("{} law parameters for {} states", law_parameters.len(), self.model.states.len()));
        }
        self.jacobians(t, y, dy, jac, Some(ParamJacobian { fp, law_parameters }))
    }

    /// Gradients of the friction τ/σ = f(V, θ) + ηV + gδ: `∂τ/∂y` (length N + 2) and the
    /// explicit `∂τ/∂p` (length [`n_params`]; 0 for α). Classic form only.
    pub fn stress_gradients(&self, y: &[f64], dtau_dy: &mut [f64], dtau_dp: &mut [f64]) -> Result<(), String> {
        self.check_sensitivity_support()?;
        let m = self.model;
        let n = m.states.len();
        dtau_dy.iter_mut().for_each(|v| *v = 0.0);
        dtau_dp.iter_mut().for_each(|v| *v = 0.0);
        // ln V0 and ln Dc from the system's per-piece constants (a sensitivity solve takes these
        // gradients at every output row)
        dtau_dy[0] = if m.eta == 0.0 { m.a } else { m.a + m.eta * y[0].exp() };
        dtau_dp[0] = 1.0;
        dtau_dp[1] = y[0] - self.ln_v0;
        dtau_dy[n + 1] = m.slip_trend;
        dtau_dp[3] = y[n + 1];
        for (i, s) in m.states.iter().enumerate() {
            dtau_dy[1 + i] = s.b;
            let off = state_offset(i);
            let scale = s.law.theta_scale();
            let ln_sdc = if scale == 1.0 && i < super::DC_CACHED { self.ln_dc[i] } else { (scale * s.dc).ln() };
            dtau_dp[off] = self.ln_v0 + y[1 + i] - ln_sdc;
            dtau_dp[off + 1] = -s.b / s.dc;
        }
        Ok(())
    }

    /// `∂y0/∂p` of the steady-state start at slip rate `v` (column-major `(N + 2) × P`):
    /// only ln θ_i depends on the parameters (on Dc_i and the law's own parameter), by central
    /// differences of the law's steady state (exact for laws with θ_ss ∝ Dc).
    pub fn steady_state_sensitivity(model: &Model, v: f64, s0: &mut [f64]) -> Result<(), String> {
        let n = model.states.len();
        let d = n + 2;
        s0.iter_mut().for_each(|x| *x = 0.0);
        for (i, s) in model.states.iter().enumerate() {
            let off = state_offset(i);
            let lnth = |dc: f64| s.law.steady_state_theta(v, dc).map(f64::ln);
            let h = 1e-6 * s.dc;
            s0[(off + 1) * d + 1 + i] = (lnth(s.dc + h)? - lnth(s.dc - h)?) / (2.0 * h);
            if let Some((name, q)) = s.law.parameters().first().copied() {
                let h = 1e-6 * q.abs().max(1e-12);
                let th = |qq: f64| s.law.with_parameter(name, qq)?.steady_state_theta(v, s.dc).map(f64::ln);
                s0[(off + 2) * d + 1 + i] = (th(q + h)? - th(q - h)?) / (2.0 * h);
            }
        }
        Ok(())
    }
}
