//! The Aging law without its healing term (QDYN's `itheta_law = 0`).

use rsf_core::{LnArgs, Real, StateArgs, StateLaw};

/// The Aging law without healing, `dθ/dt = −Vθ/Dc = −Ω`.
///
/// The Aging law's slip-weakening term alone: θ decays with slip (by e every Dc) and never
/// grows in stationary contact. It is the Aging law's limit far above steady state (Ω ≫ 1,
/// where 1 − Ω ≈ −Ω), used for fast dynamic slip in earthquake-cycle codes (QDYN's "aging law
/// in the no-healing approximation", `itheta_law = 0`). It has **no steady state**: at any
/// V > 0, θ → 0. So it cannot describe steady sliding, is never a candidate of the diagnosis
/// and cannot start a fit from steady state; it serves hosts that start from their own θ
/// (`Problem::initial_theta`, the C ABI's per-element kernels).
///
/// Ruina, A. (1983), Slip instability and state variable friction laws, J. Geophys. Res. 88,
/// 10359–10370 (the Aging law); Luo, Y., Ampuero, J.-P. et al., QDYN: a Quasi-DYNamic
/// earthquake simulator (v1.1), Zenodo (2017), for this limit's use.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AgingNoHealing;

impl StateLaw for AgingNoHealing {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        -(s.v * s.theta / s.dc)
    }
    fn name(&self) -> String {
        "aging-no-healing".into()
    }
    /// −V/Dc: θ's relative rate does not depend on θ.
    fn ln_theta_rate(&self, s: &LnArgs) -> f64 {
        -s.v_dc
    }
    /// None: dθ/dt < 0 for every θ > 0 at V > 0.
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        Err(format!(
            "the aging law without healing has no steady state (dθ/dt = −Vθ/Dc < 0 at V = {v:e} µm/s, Dc = {dc} µm): \
             start it from a given θ"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// θ decays by e over a slip of Dc at any constant V, and not at all at V = 0.
    #[test]
    fn theta_decays_by_e_per_dc_of_slip() {
        let (dc, theta0) = (20.0, 7.0);
        for v in [1e-3, 1.0, 300.0] {
            // exact solution θ(t) = θ0 exp(−V t/Dc); the rate at θ0 is −V θ0/Dc
            let g = AgingNoHealing.theta_rate(&StateArgs::new(v, theta0, dc, 0.01));
            assert_eq!(g, -v * theta0 / dc);
            let l = AgingNoHealing.ln_theta_rate(&LnArgs::new(v.ln(), theta0.ln(), dc, 0.01));
            assert!((l - g / theta0).abs() <= 1e-15 * (g / theta0).abs());
        }
        assert_eq!(AgingNoHealing.theta_rate(&StateArgs::new(0.0, theta0, dc, 0.01)), 0.0);
        assert!(AgingNoHealing.steady_state_theta(1.0, dc).is_err());
    }
}
