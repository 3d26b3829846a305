//! Parameter layout and exact parameter derivatives of the spring-slider (for forward
//! sensitivities).

use super::SpringSlider;
use crate::model::Model;

/// Number of global parameters in the sensitivity layout: `mu0, a, k, g, a_slope`.
pub const N_GLOBAL: usize = 5;

/// Parameters per state variable in the layout of [`n_params`]: `b, dc, q, alpha`.
pub const PER_STATE: usize = 4;

/// Number of entries of the fixed block of the parameter layout with `n` state variables:
/// `[mu0, a, k, g, a_slope, b_1, dc_1, q_1, alpha_1, …, b_n, dc_n, q_n, alpha_n]`, where g is
/// the slip trend, `a_slope` the rate dependence a₁ of the direct effect, `q_i` the law's first own parameter (Kato–Tullis `vc`, Nagata `c`; unused for laws
/// without one) and `alpha_i` the Linker–Dieterich normal-stress coupling. A law with more than
/// one own parameter has the others after this block ([`extra_law_parameters`]); the whole
/// layout has [`n_params_of`] entries.
pub fn n_params(n_states: usize) -> usize {
    N_GLOBAL + PER_STATE * n_states
}

/// The laws' own parameters past each law's first, in layout order: they follow the fixed
/// block of [`n_params`], state by state and in each law's own order, as `(state, name)`
/// (0-based state).
pub fn extra_law_parameters(model: &Model) -> Vec<(usize, &'static str)> {
    model
        .states
        .iter()
        .enumerate()
        .flat_map(|(i, s)| s.law.parameters().into_iter().skip(1).map(move |(name, _)| (i, name)))
        .collect()
}

/// Number of entries of the whole parameter layout of `model`: the fixed block of
/// [`n_params`] and the [`extra_law_parameters`] after it.
pub fn n_params_of(model: &Model) -> usize {
    n_params(model.states.len()) + extra_law_parameters(model).len()
}

/// Index of `b_i` (0-based state `i`) in the layout of [`n_params`]; `dc_i`, `q_i` and
/// `alpha_i` follow.
pub fn state_offset(i: usize) -> usize {
    N_GLOBAL + PER_STATE * i
}

impl Model {
    /// The parameters in the layout of [`n_params_of`] (an unused law-parameter slot is 0).
    pub fn parameter_vector(&self) -> Vec<f64> {
        let mut p = vec![self.mu0, self.a, self.stiffness, self.slip_trend, self.a_slope];
        for s in &self.states {
            p.extend([s.b, s.dc, s.law.parameters().first().map(|x| x.1).unwrap_or(0.0), s.alpha]);
        }
        for s in &self.states {
            p.extend(s.law.parameters().iter().skip(1).map(|x| x.1));
        }
        p
    }

    /// A copy with the parameters `p` (layout of [`n_params_of`]); each law's own parameter is
    /// set by name. The error names a law that rejects its value.
    pub fn with_parameter_vector(&self, p: &[f64]) -> Result<Model, String> {
        let want = n_params_of(self);
        if p.len() != want {
            return Err(format!("{} parameters given for {want} expected", p.len()));
        }
        let mut m = self.clone();
        m.mu0 = p[0];
        m.a = p[1];
        m.stiffness = p[2];
        m.slip_trend = p[3];
        m.a_slope = p[4];
        for (i, s) in m.states.iter_mut().enumerate() {
            s.b = p[state_offset(i)];
            s.dc = p[state_offset(i) + 1];
            s.alpha = p[state_offset(i) + 3];
            if let Some((name, _)) = s.law.parameters().first().copied() {
                s.law = s.law.with_parameter(name, p[state_offset(i) + 2])?;
            }
        }
        let extra = extra_law_parameters(self);
        for (k, (i, name)) in extra.into_iter().enumerate() {
            let s = &mut m.states[i];
            s.law = s.law.with_parameter(name, p[n_params(self.states.len()) + k])?;
        }
        Ok(m)
    }
}

/// Index of a named parameter in the layout of [`n_params_of`]: `mu0`, `a`, `k`, `b1`, `dc1`,
/// `q1` (or the law's own first parameter's name, e.g. `vc1`), `alpha1`, `b2`, …, and a law's
/// further parameters by name (`w1`); `b`/`dc`/`alpha` alone mean state 1.
pub fn param_index(model: &Model, name: &str) -> Option<usize> {
    match name {
        "mu0" => return Some(0),
        "a" => return Some(1),
        "k" | "stiffness" => return Some(2),
        "g" | "slip_trend" => return Some(3),
        "a_slope" => return Some(4),
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
            if own.first().map(|p| p.0) == Some(other) {
                return Some(off + 2);
            }
            extra_law_parameters(model)
                .iter()
                .position(|&(s, nm)| s == i - 1 && nm == other)
                .map(|k| n_params(model.states.len()) + k)
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
        let xr = y[0] - self.ln_v0;
        dtau_dy[0] = if m.eta == 0.0 { m.a + m.a_slope * xr } else { m.a + m.a_slope * xr + m.eta * y[0].exp() };
        dtau_dp[0] = 1.0;
        dtau_dp[1] = xr;
        dtau_dp[4] = 0.5 * xr * xr;
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

    /// `∂y0/∂p` of the steady-state start at slip rate `v` (column-major `(N + 2) × P`, P the
    /// fixed block of [`n_params`] or the whole layout of [`n_params_of`]): only ln θ_i
    /// depends on the parameters (on Dc_i and the law's own parameters), by central
    /// differences of the law's steady state (exact for laws with θ_ss ∝ Dc).
    pub fn steady_state_sensitivity(model: &Model, v: f64, s0: &mut [f64]) -> Result<(), String> {
        let n = model.states.len();
        let d = n + 2;
        s0.iter_mut().for_each(|x| *x = 0.0);
        if s0.len() == d * n_params_of(model) {
            for (k, (i, name)) in extra_law_parameters(model).into_iter().enumerate() {
                let s = &model.states[i];
                let q = s.law.parameters().iter().find(|p| p.0 == name).map_or(0.0, |p| p.1);
                let h = 1e-6 * q.abs().max(1e-12);
                let th = |qq: f64| s.law.with_parameter(name, qq)?.steady_state_theta(v, s.dc).map(f64::ln);
                s0[(n_params(n) + k) * d + 1 + i] = (th(q + h)? - th(q - h)?) / (2.0 * h);
            }
        }
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

    /// `∂f/∂q` at time `t` of one of the laws' own parameters past the first (`name` of state
    /// `i`, 0-based; [`extra_law_parameters`]) into `col` (length N + 2): the parameter enters
    /// the rate of state i alone, so only the rows ln V and ln θ_i are non-zero. Exact where the
    /// law gives [`parameter_derivative`](crate::StateLaw::parameter_derivative), else a central
    /// difference of its rate (relative step 1e-6), as for the first own parameter.
    pub fn extra_parameter_column(
        &self,
        t: f64,
        y: &[f64],
        i: usize,
        name: &str,
        col: &mut [f64],
    ) -> Result<(), String> {
        self.check_sensitivity_support()?;
        let m = self.model;
        col.iter_mut().for_each(|c| *c = 0.0);
        let st = m.states.get(i).ok_or_else(|| format!("no state {}", i + 1))?;
        let v = y[0].exp();
        let theta = y[1 + i].exp();
        let (s, _) = self.sigma(t);
        let tau_rate = m.stiffness * (self.v_lp - v) / s;
        let args = self.args(i, v, theta, tau_rate, s);
        let dg_dq = match st.law.parameter_derivative(name, &args) {
            Some(d) => d,
            None => {
                let q =
                    st.law.parameters().iter().find(|p| p.0 == name).map(|p| p.1).ok_or_else(|| {
                        format!("law `{}` of state {} has no parameter `{name}`", st.law.name(), i + 1)
                    })?;
                let h = 1e-6 * q.abs().max(1e-12);
                let rate = |qq: f64| st.law.rate_with_parameter(name, qq, &args);
                (rate(q + h)? - rate(q - h)?) / (2.0 * h)
            }
        };
        let dz_dq = dg_dq / theta;
        col[1 + i] = dz_dq;
        col[0] = -st.b * dz_dq / (m.direct_slope(y[0]) + m.eta * v);
        Ok(())
    }
}
