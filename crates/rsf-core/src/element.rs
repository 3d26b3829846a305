//! Per-element kernels for fault-simulation codes: friction with its partials, the state
//! contribution, the state rate in log form with its partials, and the slip-rate solve of the
//! quasi-dynamic balance — for one fault element at a time, allocation-free, without building
//! a [`Model`](crate::Model).
//!
//! The functions are unit-agnostic: V, V0 and Dc in any consistent units (µm and s in rsf's
//! lab tools, m and s in `rsf-cycle`). `x = ln V` and `z = ln θ` are the log variables every
//! rsf integrator uses (no absolute tolerance needed however small V or θ become).
//!
//! ```
//! use rsf_core::element::{friction, psi_term, solve_slip_rate, state_rate_ln};
//! use rsf_core::FrictionForm;
//!
//! // SEAS BP1-QD at the surface: a = 0.010, b = 0.015, Dc = 8 mm, V0 = 1e-6 m/s, f0 = 0.6
//! let (a, b, dc, v0, f0) = (0.010, 0.015, 0.008, 1e-6, 0.6);
//! let z = (dc / 1e-9f64).ln(); // θ = Dc/Vp: steady state at Vp = 1e-9 m/s
//! let psi = psi_term(b, v0, dc, 1.0, z);
//! let f = friction(FrictionForm::Regularized, f0, a, v0, (1e-9f64).ln(), psi);
//! assert!((f.value - (f0 + (a - b) * (1e-9f64 / v0).ln())).abs() < 1e-12);
//! // the slip rate that balances 50 MPa × f − η V (η = 4.624 MPa s/m) is Vp again
//! let (sigma, eta) = (50e6, 4.624e6);
//! let r = solve_slip_rate(FrictionForm::Regularized, f0, a, v0, psi, sigma * f.value + eta * 1e-9, sigma, eta, -15.0).unwrap();
//! assert!((r.ln_v - (1e-9f64).ln()).abs() < 1e-10);
//! // the aging law in log form: ln θ stops changing at steady state
//! let s = state_rate_ln(&rsf_laws_free_aging(), (1e-9f64).ln(), z, dc, b);
//! assert!(s.rate.abs() < 1e-15);
//! # fn rsf_laws_free_aging() -> impl rsf_core::StateLaw {
//! #     #[derive(Debug, Clone)] struct Aging;
//! #     impl rsf_core::StateLaw for Aging {
//! #         fn theta_rate<R: rsf_core::Real>(&self, s: &rsf_core::StateArgs<R>) -> R { R::from(1.0) - s.v * s.theta / s.dc }
//! #     }
//! #     Aging
//! # }
//! ```

use crate::friction::asinh_exp_and_slope;
use crate::{FrictionForm, StateArgs, StateLaw};

mod cutoff;
pub use cutoff::{cutoff_friction, cutoff_psi_term};

/// Friction and its partial derivatives at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Friction {
    /// f (dimensionless).
    pub value: f64,
    /// ∂f/∂ln V.
    pub d_ln_v: f64,
    /// ∂f/∂Ψ (1 for the classic form).
    pub d_psi: f64,
}

/// Friction `f(ln V, Ψ)` of `form` with reference friction `f0` (μ0), direct-effect `a` and
/// reference slip rate `v0`, and its partials. `psi` is the state contribution, the sum of
/// [`psi_term`] over the state variables.
#[inline]
pub fn friction(form: FrictionForm, f0: f64, a: f64, v0: f64, ln_v: f64, psi: f64) -> Friction {
    friction_at(form, f0, a, reference_rate(form, v0).ln(), ln_v, psi)
}

/// The reference rate `form`'s friction is written with: V0 (classic) or 2V0 (regularized).
/// A host looping over elements that share V0 takes its log once and calls [`friction_at`].
#[inline]
pub fn reference_rate(form: FrictionForm, v0: f64) -> f64 {
    match form {
        FrictionForm::Classic => v0,
        FrictionForm::Regularized => 2.0 * v0,
    }
}

/// [`friction`] with `ln_ref = ln reference_rate(form, v0)` at hand (the same numbers).
#[inline]
pub fn friction_at(form: FrictionForm, f0: f64, a: f64, ln_ref: f64, ln_v: f64, psi: f64) -> Friction {
    match form {
        FrictionForm::Classic => Friction { value: f0 + a * (ln_v - ln_ref) + psi, d_ln_v: a, d_psi: 1.0 },
        FrictionForm::Regularized => {
            // one exponential for value and slope: with L = ln(V/(2V0)) + (f0 + Ψ)/a,
            // f = a asinh(e^L) and ∂f/∂L = 1/sqrt(1 + e^(−2L)), written for either sign of L
            let l = ln_v - ln_ref + (f0 + psi) / a;
            let (asinh, c) = asinh_exp_and_slope(l);
            let value = a * asinh;
            Friction { value, d_ln_v: a * c, d_psi: c }
        }
    }
}

/// One state variable's contribution to Ψ: `b ln(V0 θ / (s Dc))` with `z = ln θ` and the law's
/// θ scale `s` ([`StateLaw::theta_scale`], 1 for all but Perrin–Rice–Zheng). ∂/∂z = b.
#[inline]
pub fn psi_term(b: f64, v0: f64, dc: f64, theta_scale: f64, z: f64) -> f64 {
    b * (v0.ln() + z - (theta_scale * dc).ln())
}

/// d(ln θ)/dt of one state variable and its partials with respect to ln V and ln θ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateRate {
    /// d(ln θ)/dt, 1/s.
    pub rate: f64,
    /// ∂/∂ln V.
    pub d_ln_v: f64,
    /// ∂/∂ln θ.
    pub d_ln_theta: f64,
}

/// `d(ln θ)/dt = G(V, θ)/θ` of `law` at `x = ln V`, `z = ln θ` (no stress-rate dependence: the
/// laws fault codes use; Nagata's law needs the stress rate and goes through the full model).
#[inline]
pub fn state_rate_ln<L: StateLaw>(law: &L, x: f64, z: f64, dc: f64, b: f64) -> StateRate {
    let (v, theta) = (x.exp(), z.exp());
    let j = law.jet(&StateArgs::new(v, theta, dc, b));
    StateRate { rate: j.rate / theta, d_ln_v: j.d_v * v / theta, d_ln_theta: j.d_theta - j.rate / theta }
}

/// `d(ln θ)/dt = G(V, θ)/θ` alone, the cheap form of [`state_rate_ln`] for explicit
/// integrators that need no partials.
#[inline]
pub fn ln_theta_rate<L: StateLaw>(law: &L, x: f64, z: f64, dc: f64, b: f64) -> f64 {
    law.ln_theta_rate(&crate::LnArgs::new(x, z, dc, b))
}

/// The outcome of [`solve_slip_rate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlipRate {
    /// ln V of the root.
    pub ln_v: f64,
    /// Newton (or bisection) iterations used.
    pub iterations: u32,
}

/// Why [`solve_slip_rate`] found no root.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SlipRateError {
    /// Inputs not finite, or σ ≤ 0, or η < 0.
    BadInput,
    /// No V > 0 balances the stress (e.g. regularized form with τ ≤ 0, or classic form with
    /// η > 0 and τ ≤ 0).
    NoRoot,
    /// The iteration did not converge in its budget.
    NotConverged,
}

impl std::fmt::Display for SlipRateError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::BadInput => "slip-rate solve: inputs must be finite with sigma > 0 and eta >= 0",
            Self::NoRoot => "slip-rate solve: no positive slip rate balances the stress",
            Self::NotConverged => "slip-rate solve: did not converge",
        })
    }
}

impl std::error::Error for SlipRateError {}

/// Iteration budget of [`solve_slip_rate`]: a warm start needs 2–4 Newton steps, a cold one
/// ~12; bisection on a 100-decade bracket halves it to 1e-15 in ~60.
const MAX_ITERATIONS: u32 = 100;

/// Solves the quasi-dynamic balance `τ − η V = σ f(V, Ψ)` for ln V, given the elastic stress
/// `tau` (τ0 + elastic), normal stress `sigma` and radiation damping `eta` (stress per slip
/// rate): safeguarded Newton in ln V from `ln_v_guess` (a warm start: the previous value),
/// falling back to bisection inside a bracket that always holds the root. Converged when the
/// ln V step is below 1e-12.
pub fn solve_slip_rate(
    form: FrictionForm,
    f0: f64,
    a: f64,
    v0: f64,
    psi: f64,
    tau: f64,
    sigma: f64,
    eta: f64,
    ln_v_guess: f64,
) -> Result<SlipRate, SlipRateError> {
    if ![f0, a, v0, psi, tau, sigma, eta, ln_v_guess].iter().all(|x| x.is_finite()) || sigma <= 0.0 || eta < 0.0 {
        return Err(SlipRateError::BadInput);
    }
    // g(x) = σ f(x) + η e^x − τ is increasing in x; the root lies where g = 0
    let g = |x: f64| {
        let fr = friction(form, f0, a, v0, x, psi);
        let ev = if eta > 0.0 { eta * x.exp() } else { 0.0 };
        (sigma * fr.value + ev - tau, sigma * fr.d_ln_v + ev)
    };
    // a warm start first: plain Newton while it shrinks the residual (2–3 steps from the
    // previous value), the safeguarded bracket only if it does not
    let mut x = ln_v_guess;
    let mut r_prev = f64::INFINITY;
    for it in 1..=6 {
        let (gx, dg) = g(x);
        if gx == 0.0 {
            return Ok(SlipRate { ln_v: x, iterations: it });
        }
        if !(dg > 0.0) || !(gx.abs() < r_prev) {
            break;
        }
        r_prev = gx.abs();
        let step = gx / dg;
        if step.abs() > 1.0 {
            break;
        }
        x -= step;
        if step.abs() < 1e-12 {
            return Ok(SlipRate { ln_v: x, iterations: it });
        }
    }
    // bracket: above, V ≤ τ/η (damping alone) or the classic/regularized inverse of τ/σ
    let mut hi = match (eta > 0.0, form.slip_rate(f0, a, v0, tau / sigma, psi)) {
        (true, _) if tau > 0.0 => (tau / eta).ln(),
        (_, Some(v)) if v > 0.0 => v.ln(),
        _ => return Err(SlipRateError::NoRoot),
    };
    if g(hi).0 < 0.0 {
        hi += 1.0; // round-off at the bracket's end
    }
    let mut lo = hi - 1.0;
    while g(lo).0 > 0.0 {
        lo -= 2.0 * (hi - lo);
        if lo < -745.0 {
            return Err(SlipRateError::NoRoot);
        }
    }
    x = if ln_v_guess > lo && ln_v_guess < hi { ln_v_guess } else { 0.5 * (lo + hi) };
    for it in 1..=MAX_ITERATIONS {
        let (gx, dg) = g(x);
        if gx == 0.0 {
            return Ok(SlipRate { ln_v: x, iterations: it });
        }
        if gx > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let newton = x - gx / dg;
        let next = if dg > 0.0 && newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
        if (next - x).abs() < 1e-12 || hi - lo < 1e-13 {
            return Ok(SlipRate { ln_v: next, iterations: it });
        }
        x = next;
    }
    Err(SlipRateError::NotConverged)
}

/// The aging law for this crate's tests (the laws themselves live in rsf-laws, downstream).
#[cfg(test)]
#[derive(Debug, Clone)]
pub(crate) struct TestAging;

#[cfg(test)]
impl StateLaw for TestAging {
    fn theta_rate<R: crate::Real>(&self, s: &StateArgs<R>) -> R {
        R::from(1.0) - s.v * s.theta / s.dc
    }
}

#[cfg(test)]
mod tests {
    use super::TestAging as Aging;
    use super::*;
    use crate::{Model, StateVariable};

    /// The kernels agree with the model's own friction and with finite differences.
    #[test]
    fn kernels_match_the_model_and_finite_differences() {
        for form in [FrictionForm::Classic, FrictionForm::Regularized] {
            let m =
                Model { form, ..Model::new(0.6, 1.0, 0.011, 0.1) }.with_state(StateVariable::new(Aging, 0.015, 3.0));
            let (x, z) = (0.7f64, 1.3f64);
            let psi = psi_term(0.015, 1.0, 3.0, 1.0, z);
            assert!((psi - m.psi_from_ln_theta(&[z])).abs() < 1e-15);
            let f = friction(form, 0.6, 0.011, 1.0, x, psi);
            assert!((f.value - form.friction(0.6, 0.011, 1.0, x, psi)).abs() < 1e-15);
            let h = 1e-6;
            let fd = (friction(form, 0.6, 0.011, 1.0, x + h, psi).value
                - friction(form, 0.6, 0.011, 1.0, x - h, psi).value)
                / (2.0 * h);
            assert!((fd - f.d_ln_v).abs() < 1e-9, "{form:?}: {fd} vs {}", f.d_ln_v);
            let s = state_rate_ln(&Aging, x, z, 3.0, 0.015);
            assert!((s.rate - ln_theta_rate(&Aging, x, z, 3.0, 0.015)).abs() < 1e-14);
            let fdx = (state_rate_ln(&Aging, x + h, z, 3.0, 0.015).rate
                - state_rate_ln(&Aging, x - h, z, 3.0, 0.015).rate)
                / (2.0 * h);
            let fdz = (state_rate_ln(&Aging, x, z + h, 3.0, 0.015).rate
                - state_rate_ln(&Aging, x, z - h, 3.0, 0.015).rate)
                / (2.0 * h);
            assert!((fdx - s.d_ln_v).abs() < 1e-8 && (fdz - s.d_ln_theta).abs() < 1e-8, "{s:?} {fdx} {fdz}");
        }
    }

    /// The slip-rate solve inverts the balance from warm and cold starts, over 30 decades of V,
    /// for both forms, and says when there is no root.
    #[test]
    fn slip_rate_solve_inverts_the_balance() {
        let (f0, a, v0, sigma, eta) = (0.6, 0.01, 1e-6, 50e6, 4.624e6);
        for form in [FrictionForm::Classic, FrictionForm::Regularized] {
            for &x in &[-40.0, -20.7, -10.0, -3.0, 0.0, 1.5] {
                let psi = 0.01;
                let tau = sigma * friction(form, f0, a, v0, x, psi).value + eta * f64::exp(x);
                for guess in [x + 0.01, x - 3.0, 5.0, -60.0] {
                    let r = solve_slip_rate(form, f0, a, v0, psi, tau, sigma, eta, guess).unwrap();
                    assert!((r.ln_v - x).abs() < 1e-9, "{form:?} x {x} guess {guess}: {r:?}");
                    if (guess - x).abs() < 0.02 {
                        assert!(r.iterations <= 4, "{form:?} x {x}: warm start took {} iterations", r.iterations);
                    }
                }
            }
            assert_eq!(solve_slip_rate(form, f0, a, v0, 0.0, 1.0, -1.0, eta, 0.0), Err(SlipRateError::BadInput));
        }
        // the regularized friction is positive: a negative stress has no slip rate
        let reg = FrictionForm::Regularized;
        assert_eq!(solve_slip_rate(reg, f0, a, v0, 0.0, -1.0, sigma, eta, 0.0), Err(SlipRateError::NoRoot));
    }
}
