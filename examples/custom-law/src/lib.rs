//! A researcher's own crate: it adds a law to rsf without touching rsf's crates.
//! The code blocks of docs/laws.md are compiled and run as this crate's doctests.
#![doc = include_str!("../../../docs/laws.md")]
#![forbid(unsafe_code)]

use rsf_core::{Real, StateArgs, StateLaw};

/// A weighted mixture of the Aging and Slip laws:
/// `dθ/dt = w (1 − Ω) + (1 − w)(−Ω ln Ω)`, Ω = Vθ/Dc, 0 ≤ w ≤ 1.
///
/// `w = 1` is Dieterich's Aging law, `w = 0` Ruina's Slip law. Steady state θ = Dc/V for every
/// w. A one-parameter bridge between time- and slip-dependent healing.
#[derive(Debug, Clone, Copy)]
pub struct Mixture {
    /// Weight of the Aging law, 0 ≤ w ≤ 1.
    pub w: f64,
}

impl StateLaw for Mixture {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        let omega = s.v * s.theta / s.dc;
        (-omega + 1.0) * self.w - omega * omega.ln() * (1.0 - self.w)
    }
    fn name(&self) -> String {
        "mixture".into()
    }
    fn parameters(&self) -> Vec<(&'static str, f64)> {
        vec![("w", self.w)]
    }
    fn validate(&self) -> Result<(), String> {
        if (0.0..=1.0).contains(&self.w) { Ok(()) } else { Err(format!("w = {} must lie in [0, 1]", self.w)) }
    }
}
