//! The non-dimensional spring-slider of Bhattacharya et al. (2022), Eqs. 9–12.
//!
//! Scale slip rate by the initial (pre-hold or pre-step) slip rate `V_i`, time by `Dc_1/V_i`
//! and each state variable by `Dc_j/V_i`:
//!
//! ```text
//! V' = V/V_i,   T = V_i t / Dc_1,   θ'_j = V_i θ_j / Dc_j,   Δμ = μ − μ_ss(V_i)
//!
//! dΔμ/dT   = k Dc_1 (V_lp/V_i − V')                                   (Eq. 9)
//! Δμ       = a ln V' + Σ_j b_j ln(θ'_j / s_j)                         (Eq. 10)
//! dθ'_j/dT = (Dc_1/Dc_j) · G_j(V, θ_j) evaluated at V = V_i V', θ_j = Dc_j θ'_j / V_i
//!                                                                      (Eqs. 11–12)
//! ```
//!
//! For laws with no velocity scale of their own (Aging, Slip, PRZ, Nagata),
//! `G_j(V_i V', Dc_j θ'_j/V_i)` depends on V' and θ'_j only, so V_i drops out: a hold
//! (V_lp = 0) from any V_i traces the same Δμ(T), i.e. the same Δμ versus `V_i t`. A step
//! down to V_f follows that hold trajectory while V' ≫ V_f/V_i. Kato–Tullis's cut-off Vc is
//! such a velocity scale and breaks the identity; so does a rate-dependent direct effect
//! (`Model::a_slope`, whose a + a₁ ln(V/V0) ties friction to V0). Radiation damping and a
//! rate-dependent direct effect are excluded (η = 0, a₁ = 0).

use crate::law::StateArgs;
use crate::model::Model;

/// The non-dimensional system for `model` started at steady state at slip rate `v_i` (µm/s).
#[derive(Clone, Copy, Debug)]
pub struct Nondimensional<'a> {
    /// The dimensional model (classic form, η = 0, a₁ = 0).
    pub model: &'a Model,
    /// Initial slip rate V_i, µm/s.
    pub v_i: f64,
}

impl<'a> Nondimensional<'a> {
    /// Non-dimensional time `T = V_i t / Dc_1`.
    pub fn time(&self, t: f64) -> f64 {
        self.v_i * t / self.model.states[0].dc
    }

    /// Δμ from non-dimensional variables `y = (ln V', ln θ'_1, …)` (Eq. 10).
    pub fn delta_mu(&self, y: &[f64]) -> f64 {
        let m = self.model;
        m.a * y[0] + m.states.iter().zip(&y[1..]).map(|(s, z)| s.b * (z - s.law.theta_scale().ln())).sum::<f64>()
    }

    /// Maps dimensional `(V, θ_j)` to non-dimensional `y = (ln V', ln θ'_j)`.
    pub fn to_nondimensional(&self, v: f64, theta: &[f64]) -> Vec<f64> {
        let mut y = vec![(v / self.v_i).ln()];
        y.extend(self.model.states.iter().zip(theta).map(|(s, t)| (self.v_i * t / s.dc).ln()));
        y
    }

    /// `dy/dT` for `y = (ln V', ln θ'_1, …, ln θ'_N)` at load-point velocity ratio
    /// `vlp_ratio = V_lp / V_i` (Eqs. 9–12).
    pub fn rhs(&self, vlp_ratio: f64, y: &[f64], dy: &mut [f64]) {
        let m = self.model;
        let dc1 = m.states[0].dc;
        let vp = y[0].exp();
        let dmu_dt_nd = m.stiffness * dc1 * (vlp_ratio - vp);
        // dimensional stress rate dτ/dt = (V_i/Dc_1) dΔμ/dT
        let stress_rate = self.v_i / dc1 * dmu_dt_nd;
        let v = self.v_i * vp;
        let mut psi_rate = 0.0;
        for (j, s) in m.states.iter().enumerate() {
            let theta_nd = y[1 + j].exp();
            let theta = s.dc * theta_nd / self.v_i;
            let g = s.law.rate(&StateArgs { stress_rate, ..StateArgs::new(v, theta, s.dc, s.b) });
            // d ln θ'/dT = (Dc_1/Dc_j) G / θ'
            let z = dc1 / s.dc * g / theta_nd;
            dy[1 + j] = z;
            psi_rate += s.b * z;
        }
        dy[0] = (dmu_dt_nd - psi_rate) / m.a;
    }
}
