//! The one-state Aging–Slip mixture (a built-in law with an own parameter, the aging share w).

use rsf_core::{LnArgs, Real, StateArgs, StateLaw};

/// One state evolving by a weighted sum of the Aging and Slip rates,
/// `dθ/dt = w (1 − Ω) − (1 − w) Ω ln Ω` (w, the aging share, dimensionless in [0, 1]).
///
/// Healing partly by time and partly by slip in one contact population: w = 1 is the Aging
/// law, w = 0 the Slip law. Steady state θ = Dc/V for every w. (The two-state form, a state of
/// each law, is a different model: there each law has its own b.)
///
/// Kato, N. & Tullis, T. E. (2001) discuss such composites; Bhattacharya et al. (2015), Critical
/// evaluation of state evolution laws in rate and state friction, J. Geophys. Res. 120,
/// 6365–6385, fit weighted Aging/Slip forms to velocity steps and holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AgingSlip {
    /// Aging share w of the evolution rate (dimensionless, 0–1).
    pub w: f64,
}

impl StateLaw for AgingSlip {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        let omega = s.v * s.theta / s.dc;
        (-omega + 1.0) * self.w - omega * omega.ln() * (1.0 - self.w)
    }
    fn name(&self) -> String {
        "aging-slip".into()
    }
    /// w (1/θ − V/Dc) − (1 − w)(V/Dc) ln Ω.
    fn ln_theta_rate(&self, s: &LnArgs) -> f64 {
        self.w * ((-s.z).exp() - s.v_dc) - (1.0 - self.w) * s.v * (s.inv_dc * (s.x + s.z - s.ln_dc))
    }
    fn parameters(&self) -> Vec<(&'static str, f64)> {
        vec![("w", self.w)]
    }
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), String> {
        match name {
            "w" => {
                self.w = value;
                Ok(())
            }
            _ => Err(format!("law `aging-slip` has no parameter `{name}`")),
        }
    }
    /// ∂/∂w = (1 − Ω) + Ω ln Ω, exact.
    fn parameter_derivative(&self, name: &str, s: &StateArgs<f64>) -> Option<f64> {
        let omega = s.v * s.theta / s.dc;
        (name == "w").then(|| 1.0 - omega + omega * omega.ln())
    }
    fn validate(&self) -> Result<(), String> {
        if (0.0..=1.0).contains(&self.w) {
            Ok(())
        } else {
            Err(format!("w = {} must lie in [0, 1] (the aging share)", self.w))
        }
    }
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        Ok(dc / v)
    }
}
