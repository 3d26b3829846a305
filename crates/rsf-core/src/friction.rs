//! The direct-effect part of the friction law: classic logarithmic or regularized (asinh).

use serde::{Deserialize, Serialize};

/// How friction depends on slip rate.
///
/// With `Ψ = Σ_i b_i ln(V0 θ_i / (s_i Dc_i))` (the state contribution):
///
/// * `Classic`: `mu = mu0 + a ln(V/V0) + Ψ`. Undefined at V = 0.
/// * `Regularized`: `mu = a asinh( V/(2V0) · exp((mu0 + Ψ)/a) )`, the form used by
///   fault-simulation codes (e.g. SEAS benchmarks); finite at V = 0 and equal to the classic
///   form to relative order `exp(−2(mu/a))` when `mu/a` is large.
///
/// The regularized form is evaluated through `L = ln(V/(2V0)) + (mu0 + Ψ)/a`, never forming
/// `exp((mu0 + Ψ)/a)` alone, so it cannot overflow for small `a`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FrictionForm {
    /// `mu = mu0 + a ln(V/V0) + Ψ`.
    #[default]
    Classic,
    /// `mu = a asinh(V/(2V0) exp((mu0 + Ψ)/a))`.
    Regularized,
}

/// Friction and its sensitivities at one point; `x = ln V`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrictionEval {
    /// ∂f/∂x.
    pub f_x: f64,
    /// ∂f/∂Ψ.
    pub f_psi: f64,
    /// ∂(f_x)/∂L and ∂(f_psi)/∂L, with ∂L/∂x = 1 and ∂L/∂Ψ = 1/a (zero for the classic form).
    pub d_fx_dl: f64,
    pub d_fpsi_dl: f64,
    /// ∂(f_x)/∂x outside L: the rate dependence a₁ of the direct effect (`Model::a_slope`;
    /// 0 from the forms themselves).
    pub bend_fx_dx: f64,
}

/// Above this l, asinh(e^l) = l + ln 2 and its slope is 1 to the last bit (e^(−2l) < 4e-18 is
/// lost beside 1): the usual regime of lab and fault friction, where (μ0 + Ψ)/a is 30–100,
/// needs no transcendental call.
const ASINH_LINEAR_L: f64 = 20.0;

/// `asinh(e^l)` and its derivative `1/sqrt(1 + e^(−2l))`, without overflow for either sign of
/// `l`, sharing one exponential.
#[inline]
pub fn asinh_exp_and_slope(l: f64) -> (f64, f64) {
    if l > ASINH_LINEAR_L {
        // what the next branch gives, exactly
        (l + std::f64::consts::LN_2, 1.0)
    } else if l > 0.0 {
        let e = (-2.0 * l).exp();
        let r = (1.0 + e).sqrt();
        (l + (1.0 + r).ln(), 1.0 / r)
    } else {
        let e = l.exp();
        (e.asinh(), e / (1.0 + e * e).sqrt())
    }
}

impl FrictionForm {
    /// Friction at `x = ln V` for state contribution `psi`.
    pub fn friction(self, mu0: f64, a: f64, v0: f64, x: f64, psi: f64) -> f64 {
        self.friction_ln(mu0, a, v0.ln(), x, psi)
    }

    /// [`friction`](Self::friction) given `ln_v0 = ln V0`, for callers that evaluate it often
    /// with one V0 (a solution's rows).
    #[inline]
    pub fn friction_ln(self, mu0: f64, a: f64, ln_v0: f64, x: f64, psi: f64) -> f64 {
        match self {
            Self::Classic => mu0 + a * (x - ln_v0) + psi,
            Self::Regularized => a * asinh_exp_and_slope(x - (std::f64::consts::LN_2 + ln_v0) + (mu0 + psi) / a).0,
        }
    }

    #[inline]
    pub(crate) fn eval(self, mu0: f64, a: f64, v0: f64, x: f64, psi: f64) -> FrictionEval {
        match self {
            Self::Classic => FrictionEval { f_x: a, f_psi: 1.0, d_fx_dl: 0.0, d_fpsi_dl: 0.0, bend_fx_dx: 0.0 },
            Self::Regularized => {
                let l = x - (2.0 * v0).ln() + (mu0 + psi) / a;
                let c = asinh_exp_and_slope(l).1;
                // dc/dL = c (1 − c²)
                let dc = c * (1.0 - c * c);
                FrictionEval { f_x: a * c, f_psi: c, d_fx_dl: a * dc, d_fpsi_dl: dc, bend_fx_dx: 0.0 }
            }
        }
    }

    /// The slip rate V (µm/s) at which friction equals `mu` for state contribution `psi`
    /// (the inverse of [`friction`](Self::friction)); `None` where no positive V exists
    /// (regularized form with `mu <= 0`).
    pub fn slip_rate(self, mu0: f64, a: f64, v0: f64, mu: f64, psi: f64) -> Option<f64> {
        match self {
            Self::Classic => Some(v0 * ((mu - mu0 - psi) / a).exp()),
            Self::Regularized => {
                if mu <= 0.0 {
                    return None;
                }
                // V = 2 V0 exp(−(mu0+Ψ)/a) sinh(mu/a), with ln sinh(s) = s + ln((1 − e^(−2s))/2).
                let s = mu / a;
                let ln_sinh = s + (0.5 * (-(-2.0 * s).exp_m1())).ln();
                Some((((2.0 * v0).ln()) - (mu0 + psi) / a + ln_sinh).exp())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The shortcut above l = 20 is bit-identical to the full formula.
    #[test]
    fn the_asinh_shortcut_is_exact() {
        for l in [20.0 + 1e-9, 20.5, 35.0, 80.0, 700.0] {
            let r = (1.0 + (-2.0f64 * l).exp()).sqrt();
            let (v, c) = asinh_exp_and_slope(l);
            assert_eq!((v.to_bits(), c.to_bits()), ((l + (1.0 + r).ln()).to_bits(), (1.0 / r).to_bits()), "l {l}");
        }
        // far below zero: asinh(e^l) ≈ e^l to full relative precision, not 0
        let (v, _) = asinh_exp_and_slope(-50.0);
        assert!((v / (-50.0f64).exp() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn regularized_matches_classic_far_from_zero_and_inverts() {
        let (mu0, a, v0) = (0.6, 0.01, 1.0);
        for &x in &[-20.0, -5.0, 0.0, 3.0] {
            let psi = 0.02;
            let c = FrictionForm::Classic.friction(mu0, a, v0, x, psi);
            let r = FrictionForm::Regularized.friction(mu0, a, v0, x, psi);
            // difference is O(exp(-2 mu/a)) = exp(-120): zero in f64
            assert_relative_eq!(c, r, max_relative = 1e-14);
            for form in [FrictionForm::Classic, FrictionForm::Regularized] {
                let v = form.slip_rate(mu0, a, v0, form.friction(mu0, a, v0, x, psi), psi).unwrap();
                assert_relative_eq!(v.ln(), x, epsilon = 1e-9);
            }
        }
        // Near V = 0 the regularized law goes to zero instead of −∞.
        let r = FrictionForm::Regularized.friction(mu0, a, v0, -1000.0, 0.0);
        assert!((0.0..1e-300).contains(&r));
        // no overflow for tiny a
        let r = FrictionForm::Regularized.friction(0.7, 1e-4, 1.0, 0.0, 0.0);
        assert_relative_eq!(r, 0.7 - 1e-4 * 2f64.ln() + 1e-4 * 2f64.ln(), epsilon = 1e-12);
    }

    #[test]
    fn regularized_derivatives_match_finite_differences() {
        let (mu0, a, v0, psi) = (0.1, 0.02, 1.0, 0.01);
        for &x in &[-8.0, -4.0, -1.0, 2.0] {
            let e = FrictionForm::Regularized.eval(mu0, a, v0, x, psi);
            let h = 1e-6;
            let fd_x = (FrictionForm::Regularized.friction(mu0, a, v0, x + h, psi)
                - FrictionForm::Regularized.friction(mu0, a, v0, x - h, psi))
                / (2.0 * h);
            let fd_p = (FrictionForm::Regularized.friction(mu0, a, v0, x, psi + h)
                - FrictionForm::Regularized.friction(mu0, a, v0, x, psi - h))
                / (2.0 * h);
            assert_relative_eq!(e.f_x, fd_x, max_relative = 1e-7, epsilon = 1e-12);
            assert_relative_eq!(e.f_psi, fd_p, max_relative = 1e-7, epsilon = 1e-12);
            let fd_l = (FrictionForm::Regularized.eval(mu0, a, v0, x + h, psi).f_psi
                - FrictionForm::Regularized.eval(mu0, a, v0, x - h, psi).f_psi)
                / (2.0 * h);
            assert_relative_eq!(e.d_fpsi_dl, fd_l, max_relative = 1e-6, epsilon = 1e-10);
        }
    }
}
