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
/// dx/dt   = (dτ/dt − gV − ∂f/∂Ψ · Σ b_i dz_i/dt) / (∂f/∂x + ηV)  (time derivative of the balance)
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

    /// Shear stress τ = f + ηV + gδ carried by the spring (the friction a load cell measures).
    pub fn stress(&self, y: &[f64]) -> f64 {
        let n = self.model.states.len();
        let m = self.model;
        let psi = m.psi_from_ln_theta(&y[1..=n]);
        m.form.friction(m.mu0, m.a, m.v0, y[0], psi) + m.eta * y[0].exp() + m.slip_trend * y[n + 1]
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
            (tau_rate - m.slip_trend * v - fe.f_psi * psi_rate) / (fe.f_x + m.eta * v)
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
        let num = tau_rate - m.slip_trend * v - fe.f_psi * psi_rate;
        let den = fe.f_x + m.eta * v;
        let xdot = num / den;
        dy[0] = xdot;
        // column x
        let dnum_dx = dtau_dx - m.slip_trend * v - fe.f_psi * dpsi_rate_dx - psi_rate * fe.d_fpsi_dl;
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

/// Number of global parameters in the sensitivity layout: `mu0, a, k, g`.
pub const N_GLOBAL: usize = 4;

/// Number of model parameters for sensitivities with `n` state variables: the layout is
/// `[mu0, a, k, g, b_1, dc_1, q_1, …, b_n, dc_n, q_n]`, where g is the slip trend and `q_i` the
/// law's first own parameter (Kato–Tullis `vc`, Nagata `c`; unused for laws without one).
pub fn n_params(n_states: usize) -> usize {
    N_GLOBAL + 3 * n_states
}

/// Index of `b_i` (0-based state `i`) in the layout of [`n_params`]; `dc_i` and `q_i` follow.
pub fn state_offset(i: usize) -> usize {
    N_GLOBAL + 3 * i
}

impl Model {
    /// The parameters in the layout of [`n_params`] (an unused law-parameter slot is 0).
    pub fn parameter_vector(&self) -> Vec<f64> {
        let mut p = vec![self.mu0, self.a, self.stiffness, self.slip_trend];
        for s in &self.states {
            p.extend([s.b, s.dc, s.law.parameters().first().map(|x| x.1).unwrap_or(0.0)]);
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
            if let Some((name, _)) = s.law.parameters().first().copied() {
                s.law = s.law.with_parameter(name, p[state_offset(i) + 2])?;
            }
        }
        Ok(m)
    }
}

/// Index of a named parameter in the layout of [`n_params`]: `mu0`, `a`, `k`, `b1`, `dc1`,
/// `q1` (or the law's own name, e.g. `vc1`), `b2`, …; `b`/`dc` alone mean state 1.
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
        "q" if !model.states[i - 1].law.parameters().is_empty() => Some(off + 2),
        other => {
            let own = model.states[i - 1].law.parameters();
            if own.first().map(|p| p.0) == Some(other) { Some(off + 2) } else { None }
        }
    }
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

    /// `∂f/∂p`: the derivative of the right-hand side with respect to the parameters of
    /// [`n_params`], column-major `(N + 2) × P` into `fp`. Classic form only. The law's own
    /// parameter enters through a central difference of its rate (relative step 1e-6);
    /// everything else is exact.
    pub fn parameter_jacobian(&self, y: &[f64], fp: &mut [f64]) -> Result<(), String> {
        self.check_sensitivity_support()?;
        let m = self.model;
        let n = m.states.len();
        let d = n + 2;
        fp.iter_mut().for_each(|v| *v = 0.0);
        let at = |r: usize, c: usize| c * d + r;
        let v = y[0].exp();
        let tau_rate = m.stiffness * (self.v_lp - v);
        let den = m.a + m.eta * v;
        let mut psi_rate = 0.0;
        let mut dpsi_dk = 0.0;
        for (i, s) in m.states.iter().enumerate() {
            let theta = y[1 + i].exp();
            let args = StateArgs { v, theta, dc: s.dc, b: s.b, stress_rate: tau_rate };
            let j = s.law.jet(&args);
            let zdot = j.rate / theta;
            psi_rate += s.b * zdot;
            let off = state_offset(i);
            let dz_dk = j.d_stress_rate * (self.v_lp - v) / theta;
            let dz_db = j.d_b / theta;
            let dz_ddc = j.d_dc / theta;
            fp[at(1 + i, 2)] = dz_dk;
            fp[at(1 + i, off)] = dz_db;
            fp[at(1 + i, off + 1)] = dz_ddc;
            dpsi_dk += s.b * dz_dk;
            fp[at(0, off)] = -(zdot + s.b * dz_db) / den;
            fp[at(0, off + 1)] = -s.b * dz_ddc / den;
            if let Some((name, q)) = s.law.parameters().first().copied() {
                let h = 1e-6 * q.abs().max(1e-12);
                let rate = |qq: f64| s.law.with_parameter(name, qq).map(|l| l.rate(&args));
                let dz_dq = (rate(q + h)? - rate(q - h)?) / (2.0 * h) / theta;
                fp[at(1 + i, off + 2)] = dz_dq;
                fp[at(0, off + 2)] = -s.b * dz_dq / den;
            }
        }
        let xdot = (tau_rate - m.slip_trend * v - psi_rate) / den;
        fp[at(0, 1)] = -xdot / den;
        fp[at(0, 2)] = ((self.v_lp - v) - dpsi_dk) / den;
        fp[at(0, 3)] = -v / den;
        Ok(())
    }

    /// Gradients of the spring stress τ = f(V, θ) + ηV: `∂τ/∂y` (length N + 2) and the
    /// explicit `∂τ/∂p` (length [`n_params`]). Classic form only.
    pub fn stress_gradients(&self, y: &[f64], dtau_dy: &mut [f64], dtau_dp: &mut [f64]) -> Result<(), String> {
        self.check_sensitivity_support()?;
        let m = self.model;
        let n = m.states.len();
        dtau_dy.iter_mut().for_each(|v| *v = 0.0);
        dtau_dp.iter_mut().for_each(|v| *v = 0.0);
        dtau_dy[0] = m.a + m.eta * y[0].exp();
        dtau_dp[0] = 1.0;
        dtau_dp[1] = y[0] - m.v0.ln();
        dtau_dy[n + 1] = m.slip_trend;
        dtau_dp[3] = y[n + 1];
        let lv0 = m.v0.ln();
        for (i, s) in m.states.iter().enumerate() {
            dtau_dy[1 + i] = s.b;
            let off = state_offset(i);
            dtau_dp[off] = lv0 + y[1 + i] - (s.law.theta_scale() * s.dc).ln();
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FrictionForm, Real, StateArgs, StateLaw, StateVariable};

    #[derive(Debug, Clone)]
    struct Aging;
    impl StateLaw for Aging {
        fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
            -(s.v * s.theta / s.dc) + 1.0
        }
    }
    #[derive(Debug, Clone)]
    struct Slip;
    impl StateLaw for Slip {
        fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
            let o = s.v * s.theta / s.dc;
            -(o * o.ln())
        }
    }
    /// Nagata-like: depends on the stress rate.
    #[derive(Debug, Clone)]
    struct StressRate;
    impl StateLaw for StressRate {
        fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
            -(s.v * s.theta / s.dc) + 1.0 - s.theta * s.stress_rate * 2.0 / s.b
        }
    }

    fn models() -> Vec<Model> {
        let base = |k: f64| Model::new(0.6, 1.0, 0.011, k);
        vec![
            base(0.05).with_state(StateVariable::new(Slip, 0.015, 3.0)),
            base(0.05).with_state(StateVariable::new(Aging, 0.015, 3.0)).with_eta(0.3),
            base(0.002)
                .with_state(StateVariable::new(Slip, 0.008, 3.0))
                .with_state(StateVariable::new(Aging, 0.006, 40.0))
                .with_state(StateVariable::new(StressRate, 0.004, 10.0)),
            base(0.02)
                .with_state(StateVariable::new(Slip, 0.015, 3.0))
                .with_form(FrictionForm::Regularized)
                .with_eta(0.01),
            Model { mu0: 0.05, ..base(0.02).with_state(StateVariable::new(Aging, 0.02, 1.0)) }
                .with_form(FrictionForm::Regularized),
            base(0.03).with_state(StateVariable::new(Aging, 0.015, 3.0)).with_slip_trend(-3e-5),
            base(f64::INFINITY).with_state(StateVariable::new(Slip, 0.015, 3.0)),
        ]
    }

    #[test]
    fn jacobian_matches_central_differences() {
        for (mi, m) in models().iter().enumerate() {
            let d = m.states.len() + 2;
            for &v_lp in &[0.0, 0.3, 10.0] {
                let sys = SpringSlider::new(m, v_lp);
                // a point off steady state
                let mut y: Vec<f64> = (0..d).map(|i| 0.3 * (i as f64 + 1.0).sin()).collect();
                y[0] = -4.0 + mi as f64;
                let mut f = vec![0.0; d];
                let mut jac = vec![0.0; d * d];
                sys.jacobian(&y, &mut f, &mut jac);
                let mut f2 = vec![0.0; d];
                sys.rhs(&y, &mut f2);
                for i in 0..d {
                    assert!((f[i] - f2[i]).abs() <= 1e-14 * f[i].abs().max(1e-300), "model {mi}: rhs mismatch");
                }
                for c in 0..d {
                    let h = 1e-6;
                    let (mut yp, mut ym) = (y.clone(), y.clone());
                    yp[c] += h;
                    ym[c] -= h;
                    let (mut fp, mut fm) = (vec![0.0; d], vec![0.0; d]);
                    sys.rhs(&yp, &mut fp);
                    sys.rhs(&ym, &mut fm);
                    for r in 0..d {
                        let fd = (fp[r] - fm[r]) / (2.0 * h);
                        let ex = jac[c * d + r];
                        let scale = fd.abs().max(ex.abs()).max(1e-8);
                        assert!(
                            (fd - ex).abs() / scale < 1e-6,
                            "model {mi} v_lp {v_lp}: J[{r},{c}] exact {ex:e} vs fd {fd:e}"
                        );
                    }
                }
            }
        }
    }

    /// ∂f/∂p and ∂τ/∂p against central differences of the RHS and stress under parameter
    /// perturbations of a rebuilt model.
    #[test]
    fn parameter_jacobian_matches_central_differences() {
        #[derive(Debug, Clone)]
        struct Kt {
            vc: f64,
        }
        impl StateLaw for Kt {
            fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
                let o = s.v * s.theta / s.dc;
                (-(s.v / self.vc)).exp() - o * o.ln()
            }
            fn parameters(&self) -> Vec<(&'static str, f64)> {
                vec![("vc", self.vc)]
            }
            fn set_parameter(&mut self, _: &str, v: f64) -> Result<(), String> {
                self.vc = v;
                Ok(())
            }
        }
        let base = Model::new(0.6, 1.0, 0.011, 0.02)
            .with_state(StateVariable::new(Slip, 0.009, 3.0))
            .with_state(StateVariable::new(StressRate, 0.004, 20.0))
            .with_state(StateVariable::new(Kt { vc: 0.3 }, 0.003, 7.0))
            .with_eta(0.01)
            .with_slip_trend(2e-5);
        let rebuild = |p: &[f64]| base.with_parameter_vector(p).unwrap();
        let d = 5;
        let np = n_params(3);
        let y = [-1.0, 0.8, 2.5, 1.2, 3.0];
        let pv = base.parameter_vector();
        let sys = SpringSlider::new(&base, 0.7);
        let mut fp = vec![0.0; d * np];
        sys.parameter_jacobian(&y, &mut fp).unwrap();
        let (mut gy, mut gp) = (vec![0.0; d], vec![0.0; np]);
        sys.stress_gradients(&y, &mut gy, &mut gp).unwrap();
        for j in 0..np {
            if j == state_offset(1) + 2 || pv[j] == 0.0 {
                continue; // q of a law without parameters
            }
            let h = 1e-6 * pv[j].abs();
            let (mut pp, mut pm) = (pv.clone(), pv.clone());
            pp[j] += h;
            pm[j] -= h;
            let (mp, mm) = (rebuild(&pp), rebuild(&pm));
            let (mut fpp, mut fmm) = (vec![0.0; d], vec![0.0; d]);
            SpringSlider::new(&mp, 0.7).rhs(&y, &mut fpp);
            SpringSlider::new(&mm, 0.7).rhs(&y, &mut fmm);
            for r in 0..d {
                let fd = (fpp[r] - fmm[r]) / (2.0 * h);
                let ex = fp[j * d + r];
                assert!((fd - ex).abs() <= 1e-6 * fd.abs().max(ex.abs()).max(1e-6), "df{r}/dp{j}: {ex:e} vs {fd:e}");
            }
            let tfd = (SpringSlider::new(&mp, 0.7).stress(&y) - SpringSlider::new(&mm, 0.7).stress(&y)) / (2.0 * h);
            assert!((tfd - gp[j]).abs() < 1e-6 * tfd.abs().max(1e-6), "dtau/dp{j}: {} vs {tfd}", gp[j]);
        }
    }

    #[test]
    fn steady_state_has_zero_rates_when_loaded_at_that_velocity() {
        for m in models().iter().take(5) {
            let y = SpringSlider::steady_state(m, 2.5).unwrap();
            let sys = SpringSlider::new(m, 2.5);
            let mut f = vec![0.0; y.len()];
            sys.rhs(&y, &mut f);
            for (i, fi) in f.iter().enumerate().take(y.len() - 1) {
                assert!(fi.abs() < 1e-13, "component {i}: {fi}");
            }
            assert!((f[y.len() - 1] - 2.5).abs() < 1e-13);
        }
        // with a slip trend, steady sliding is not a fixed point: friction must fall by gV
        let m = &models()[5];
        let y = SpringSlider::steady_state(m, 2.5).unwrap();
        let mut f = vec![0.0; y.len()];
        SpringSlider::new(m, 2.5).rhs(&y, &mut f);
        assert!((f[0] - (-m.slip_trend * 2.5 / m.a)).abs() < 1e-15);
    }
}
