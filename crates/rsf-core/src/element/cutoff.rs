//! The cut-off-velocity friction of Okubo (1989) and Weeks (1993), QDYN's `i_rns_law = 1`:
//!
//! `f = f0 − a ln(V1/V + 1) + Σ b ln(V2 θ/Dc + 1)`
//!
//! Below the direct effect's cut-off V1 the direct term is `a ln(V/V1)`, the classic one with
//! V0 = V1; above it the direct effect saturates (f no longer grows with V). Above the
//! evolution effect's cut-off V2 (θ ≪ Dc/V2) the state term vanishes; below it the term is
//! `b ln(V2 θ/Dc)`, the classic one with V0 = V2. Both logs are written as the softplus
//! `ln(1 + e^u)` of a log argument, so neither overflows nor loses digits however small V or
//! θ become, and both partials are logistic functions of the same argument.

use super::Friction;

/// `ln(1 + e^u)` and its derivative `1/(1 + e^(−u))`, accurate for every finite `u`.
#[inline]
fn softplus_and_slope(u: f64) -> (f64, f64) {
    let e = (-u.abs()).exp();
    let value = u.max(0.0) + e.ln_1p();
    let slope = if u >= 0.0 { 1.0 / (1.0 + e) } else { e / (1.0 + e) };
    (value, slope)
}

/// Cut-off friction `f0 − a ln(V1/V + 1) + Ψ` at `ln_v` with the state contribution `psi`
/// (the sum of [`cutoff_psi_term`]), and its partials: ∂f/∂ln V = a V1/(V1 + V), ∂f/∂Ψ = 1.
/// `v1` (the direct effect's cut-off velocity) is in the units of V.
#[inline]
pub fn cutoff_friction(f0: f64, a: f64, v1: f64, ln_v: f64, psi: f64) -> Friction {
    let (sp, slope) = softplus_and_slope(v1.ln() - ln_v);
    Friction { value: f0 - a * sp + psi, d_ln_v: a * slope, d_psi: 1.0 }
}

/// One state variable's cut-off contribution `b ln(V2 θ/(s Dc) + 1)` at `z = ln θ` and its
/// partial with respect to ln θ, `b V2 θ/(V2 θ + s Dc)`; `s` is the law's θ scale (1 for all
/// but Perrin–Rice–Zheng) and `v2` the evolution effect's cut-off velocity.
#[inline]
pub fn cutoff_psi_term(b: f64, v2: f64, dc: f64, theta_scale: f64, z: f64) -> (f64, f64) {
    let (sp, slope) = softplus_and_slope(v2.ln() + z - (theta_scale * dc).ln());
    (b * sp, b * slope)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed forms written as the papers write them, where they are well conditioned.
    #[test]
    fn matches_the_closed_forms() {
        let (f0, a, b, dc, v1, v2): (f64, f64, f64, f64, f64, f64) = (0.6, 0.001, 0.0015, 1e-5, 1e-3, 1e-1);
        for &v in &[1e-12, 1e-9, 1e-6, 1e-3, 1e-1, 10.0] {
            for &theta in &[1e-6, 1e-4, 1e-2, 1.0, 1e3] {
                let (psi, dpsi) = cutoff_psi_term(b, v2, dc, 1.0, f64::ln(theta));
                let f = cutoff_friction(f0, a, v1, f64::ln(v), psi);
                let want = f0 - a * (v1 / v + 1.0).ln() + b * (v2 * theta / dc + 1.0).ln();
                assert!((f.value - want).abs() < 1e-15, "f at V {v}, θ {theta}: {} vs {want}", f.value);
                let dmu_dv = a * v1 / v / (v1 + v);
                assert!((f.d_ln_v / v - dmu_dv).abs() <= 1e-14 * dmu_dv, "∂f/∂V at V {v}");
                let dmu_dtheta = b * v2 / (v2 * theta + dc);
                assert!((dpsi / theta - dmu_dtheta).abs() <= 1e-14 * dmu_dtheta, "∂f/∂θ at θ {theta}");
                assert_eq!(f.d_psi, 1.0);
            }
        }
    }

    /// The limits the cut-offs are defined by: V ≪ V1 and θ ≫ Dc/V2 give the classic form;
    /// V ≫ V1 saturates the direct effect and θ ≪ Dc/V2 removes the state term.
    #[test]
    fn classic_and_saturated_limits() {
        let (f0, a, b, dc, v1, v2): (f64, f64, f64, f64, f64, f64) = (0.6, 0.01, 0.015, 1e-5, 1e-3, 1e-1);
        let (x, z) = (f64::ln(1e-12), f64::ln(1e4));
        let classic = f0 + a * (x - v1.ln()) + b * (v2.ln() + z - dc.ln());
        let f = cutoff_friction(f0, a, v1, x, cutoff_psi_term(b, v2, dc, 1.0, z).0);
        assert!((f.value - classic).abs() < 2e-10, "{} vs {classic}", f.value); // a V/V1 + b Dc/(V2 θ) = 1.6e-10
        let g = cutoff_friction(f0, a, v1, f64::ln(1e6), cutoff_psi_term(b, v2, dc, 1.0, f64::ln(1e-14)).0);
        assert!((g.value - f0).abs() < 1e-9, "{}", g.value);
        // no overflow or lost digit at the ends of the double range
        for u in [-700.0, -40.0, 0.0, 40.0, 700.0] {
            let (s, d) = softplus_and_slope(u);
            assert!(s.is_finite() && d.is_finite() && (0.0..=1.0).contains(&d));
        }
        assert_eq!(softplus_and_slope(-700.0).0, (-700.0f64).exp());
    }

    /// The partials against central differences.
    #[test]
    fn partials_are_the_derivatives() {
        let (f0, a, b, dc, v1, v2, s) = (0.6, 0.01, 0.015, 1e-5, 1e-3, 1e-1, 2.0);
        let h = 1e-6;
        for &(x, z) in &[(-7.0, -2.0), (-3.0, 5.0), (0.0, -9.0)] {
            let f = |x: f64| cutoff_friction(f0, a, v1, x, 0.0).value;
            let fd = (f(x + h) - f(x - h)) / (2.0 * h);
            assert!((cutoff_friction(f0, a, v1, x, 0.0).d_ln_v - fd).abs() < 1e-9);
            let p = |z: f64| cutoff_psi_term(b, v2, dc, s, z).0;
            let pd = (p(z + h) - p(z - h)) / (2.0 * h);
            assert!((cutoff_psi_term(b, v2, dc, s, z).1 - pd).abs() < 1e-9);
        }
    }
}
