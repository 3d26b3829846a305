//! A researcher's own crate: it adds a law to rsf without touching rsf's crates, and registers
//! it so that every entry point of rsf can use it by name.
#![forbid(unsafe_code)]

use rsf_core::{Real, StateArgs, StateLaw};
use rsf_laws::registry::{self, LawEntry, LawParameter, Start};
use std::sync::Arc;

/// Power-law aging, `dθ/dt = 1 − Ω^n`, Ω = Vθ/Dc (n dimensionless, > 0).
///
/// n = 1 is Dieterich's Aging law; larger n collapses the state faster after a step up or a
/// reslide and heals the same in a hold. Steady state θ = Dc/V for every n.
#[derive(Debug, Clone, Copy)]
pub struct PowerAging {
    /// The exponent n.
    pub n: f64,
}

impl StateLaw for PowerAging {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        -(s.v * s.theta / s.dc).powf(self.n) + 1.0
    }
    // Everything below is optional; a fit of `n` needs `parameters` and `set_parameter`.
    fn name(&self) -> String {
        NAME.into()
    }
    fn parameters(&self) -> Vec<(&'static str, f64)> {
        vec![("n", self.n)]
    }
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), String> {
        match name {
            "n" => {
                self.n = value;
                Ok(())
            }
            _ => Err(format!("law `{NAME}` has no parameter `{name}`")),
        }
    }
    /// Exact ∂(dθ/dt)/∂n = −Ω^n ln Ω (fits use it for n's sensitivity).
    fn parameter_derivative(&self, name: &str, s: &StateArgs<f64>) -> Option<f64> {
        let omega = s.v * s.theta / s.dc;
        (name == "n").then(|| -omega.powf(self.n) * omega.ln())
    }
    fn validate(&self) -> Result<(), String> {
        if self.n > 0.0 && self.n.is_finite() { Ok(()) } else { Err(format!("n = {} must be positive", self.n)) }
    }
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        Ok(dc / v)
    }
}

/// The law's name in protocols, on the command line and in results.
pub const NAME: &str = "power-aging-rs";

/// Registers [`PowerAging`] under [`NAME`], with `n` fitted in [0.2, 5] from 1 (the Aging
/// law). Call it once before using rsf by name (the CLI, a protocol, a manifest, a diagnosis).
pub fn register() -> Result<(), String> {
    let n = LawParameter { name: "n", unit: "", lo: 0.2, hi: 5.0, log: false, start: Start::Value(1.0) };
    registry::register(LawEntry::new(NAME, "power-law aging (Rust)", vec![n], |p| Ok(Arc::new(PowerAging { n: p[0] }))))
}
