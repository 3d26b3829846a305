//! Exact derivatives against central differences; steady states.

use super::*;
use crate::{FrictionForm, Piece, Real, StateArgs, StateLaw, StateVariable};

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
/// Depends on the normal stress and its rate (a user's law may).
#[derive(Debug, Clone)]
struct SigmaLaw;
impl StateLaw for SigmaLaw {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        -(s.v * s.theta / s.dc) + 1.0 + s.theta * s.normal_stress_rate * 0.01 / s.normal_stress
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
        base(0.02).with_state(StateVariable::new(Slip, 0.015, 3.0)).with_form(FrictionForm::Regularized).with_eta(0.01),
        Model { mu0: 0.05, ..base(0.02).with_state(StateVariable::new(Aging, 0.02, 1.0)) }
            .with_form(FrictionForm::Regularized),
        base(0.03).with_state(StateVariable::new(Aging, 0.015, 3.0)).with_slip_trend(-3e-5),
        base(f64::INFINITY).with_state(StateVariable::new(Slip, 0.015, 3.0)),
        // a rate-dependent direct effect: ∂f/∂ln V = a + a₁ ln(V/V0) (7)
        base(0.05).with_state(StateVariable::new(Slip, 0.015, 3.0)).with_a_slope(6e-4),
        base(0.02)
            .with_state(StateVariable::new(Aging, 0.008, 3.0))
            .with_state(StateVariable::new(StressRate, 0.004, 10.0))
            .with_a_slope(-5e-4),
    ]
}

#[test]
fn jacobian_matches_central_differences() {
    let mut all = models();
    // normal-stress ramps with Linker–Dieterich coupling (a σ-dependent law among them)
    all.push(
        Model::new(0.6, 1.0, 0.011, 0.002)
            .with_state(StateVariable::new(Slip, 0.008, 3.0).with_alpha(0.3))
            .with_state(StateVariable::new(Aging, 0.006, 40.0).with_alpha(0.1))
            .with_state(StateVariable::new(StressRate, 0.004, 10.0))
            .with_normal_stress(10.0)
            .with_eta(0.01)
            .with_slip_trend(2e-5),
    );
    all.push(
        Model::new(0.6, 1.0, 0.011, 0.03)
            .with_state(StateVariable::new(SigmaLaw, 0.015, 3.0).with_alpha(0.4))
            .with_form(FrictionForm::Regularized)
            .with_normal_stress(5.0),
    );
    all.push(
        Model::new(0.6, 1.0, 0.011, f64::INFINITY)
            .with_state(StateVariable::new(Slip, 0.015, 3.0).with_alpha(0.2))
            .with_normal_stress(5.0),
    );
    for (mi, m) in all.iter().enumerate() {
        let d = m.states.len() + 2;
        let ramp = m.normal_stress.is_some();
        for &v_lp in &[0.0, 0.3, 10.0] {
            let piece = Piece {
                t0: 2.0,
                t1: 10.0,
                lp0: 0.0,
                v: v_lp,
                sigma0: if ramp { 12.0 } else { 1.0 },
                sigma_rate: if ramp { -0.7 } else { 0.0 },
            };
            let sys = SpringSlider::for_piece(m, &piece);
            let t = 5.0;
            // a point off steady state
            let mut y: Vec<f64> = (0..d).map(|i| 0.3 * (i as f64 + 1.0).sin()).collect();
            y[0] = -4.0 + (mi % 10) as f64;
            let mut f = vec![0.0; d];
            let mut jac = vec![0.0; d * d];
            sys.jacobian(t, &y, &mut f, &mut jac);
            let mut f2 = vec![0.0; d];
            sys.rhs(t, &y, &mut f2);
            for i in 0..d {
                assert!((f[i] - f2[i]).abs() <= 1e-14 * f[i].abs().max(1e-300), "model {mi}: rhs mismatch");
            }
            for c in 0..d {
                // the right-hand side is linear in δ: a larger step only cuts round-off
                let h = if c == d - 1 { 1e-2 } else { 1e-6 };
                let (mut yp, mut ym) = (y.clone(), y.clone());
                yp[c] += h;
                ym[c] -= h;
                let (mut fp, mut fm) = (vec![0.0; d], vec![0.0; d]);
                sys.rhs(t, &yp, &mut fp);
                sys.rhs(t, &ym, &mut fm);
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
            // ∂f/∂t against a central difference in time
            let mut ft = vec![0.0; d];
            sys.time_derivative(t, &y, &mut ft);
            let (mut fp, mut fm) = (vec![0.0; d], vec![0.0; d]);
            sys.rhs(t + 1e-5, &y, &mut fp);
            sys.rhs(t - 1e-5, &y, &mut fm);
            for r in 0..d {
                let fd = (fp[r] - fm[r]) / 2e-5;
                assert!((fd - ft[r]).abs() <= 1e-6 * fd.abs().max(1e-8), "model {mi}: df{r}/dt {} vs {fd}", ft[r]);
                if !ramp {
                    assert_eq!(ft[r], 0.0);
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
    for ramp in [false, true] {
        let mut base = Model::new(0.6, 1.0, 0.011, 0.02)
            .with_state(StateVariable::new(Slip, 0.009, 3.0))
            .with_state(StateVariable::new(StressRate, 0.004, 20.0))
            .with_state(StateVariable::new(Kt { vc: 0.3 }, 0.003, 7.0))
            .with_eta(0.01)
            .with_slip_trend(2e-5)
            .with_a_slope(4e-4);
        let piece = if ramp {
            base = base.with_normal_stress(10.0);
            base.states[0].alpha = 0.3;
            base.states[2].alpha = 0.15;
            Piece { t0: 0.0, t1: 10.0, lp0: 0.0, v: 0.7, sigma0: 11.0, sigma_rate: 0.4 }
        } else {
            Piece { t0: 0.0, t1: 10.0, lp0: 0.0, v: 0.7, sigma0: 1.0, sigma_rate: 0.0 }
        };
        let t = 3.0;
        let rebuild = |p: &[f64]| base.with_parameter_vector(p).unwrap();
        let d = 5;
        let np = n_params(3);
        let y = [-1.0, 0.8, 2.5, 1.2, 3.0];
        let pv = base.parameter_vector();
        let sys = SpringSlider::for_piece(&base, &piece);
        let mut fp = vec![0.0; d * np];
        sys.parameter_jacobian(t, &y, &mut fp).unwrap();
        let (mut gy, mut gp) = (vec![0.0; d], vec![0.0; np]);
        sys.stress_gradients(&y, &mut gy, &mut gp).unwrap();
        // the one-pass form a sensitivity solve calls: its right-hand side and J are `jacobian`'s
        // bit for bit (the parameter derivatives leave them alone), its ∂f/∂p
        // `parameter_jacobian`'s, and the right-hand side agrees with `rhs`
        let (mut dy, mut jac, mut dy1, mut jac1, mut fp1) =
            (vec![0.0; d], vec![0.0; d * d], vec![0.0; d], vec![0.0; d * d], vec![1.0; d * np]);
        sys.jacobian(t, &y, &mut dy, &mut jac);
        sys.sensitivity_jacobians(t, &y, &mut dy1, &mut jac1, &mut fp1, &law_parameters(&base)).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!((bits(&dy), bits(&jac), bits(&fp)), (bits(&dy1), bits(&jac1), bits(&fp1)));
        let mut rhs = vec![0.0; d];
        sys.rhs(t, &y, &mut rhs);
        for (r, (a, b)) in rhs.iter().zip(&dy).enumerate() {
            assert!((a - b).abs() <= 1e-14 * a.abs().max(1e-12), "dy{r}: rhs {a:e}, jacobian {b:e}");
        }
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
            SpringSlider::for_piece(&mp, &piece).rhs(t, &y, &mut fpp);
            SpringSlider::for_piece(&mm, &piece).rhs(t, &y, &mut fmm);
            for r in 0..d {
                let fd = (fpp[r] - fmm[r]) / (2.0 * h);
                let ex = fp[j * d + r];
                assert!((fd - ex).abs() <= 1e-6 * fd.abs().max(ex.abs()).max(1e-6), "df{r}/dp{j}: {ex:e} vs {fd:e}");
            }
            let tfd = (SpringSlider::new(&mp, 0.7).stress(&y) - SpringSlider::new(&mm, 0.7).stress(&y)) / (2.0 * h);
            assert!((tfd - gp[j]).abs() < 1e-6 * tfd.abs().max(1e-6), "dtau/dp{j}: {} vs {tfd}", gp[j]);
        }
    }
}

/// The step map against the closed forms: θ_i⁺ = θ_i⁻ (σ⁻/σ⁺)^(α_i/b_i), μ⁺ = μ⁻ σ⁻/σ⁺ at
/// finite stiffness (so V⁺ = V⁻ exp((μ⁺ − μ⁻ + Σ α_i ln(σ⁺/σ⁻))/a) in the classic form), and
/// μ jumping by −Σ α_i ln(σ⁺/σ⁻) at V = V_lp with infinite stiffness.
#[test]
fn normal_stress_step_matches_closed_forms() {
    let two = |k: f64| {
        Model::new(0.6, 1.0, 0.011, k)
            .with_state(StateVariable::new(Slip, 0.009, 3.0).with_alpha(0.3))
            .with_state(StateVariable::new(Aging, 0.006, 30.0).with_alpha(0.1))
            .with_normal_stress(10.0)
    };
    for (sm, sp) in [(10.0f64, 13.0f64), (10.0, 8.0)] {
        let ln_r: f64 = (sp / sm).ln();
        let alphas = 0.3 + 0.1;
        // finite stiffness
        let m = two(0.01);
        let sys = SpringSlider::new(&m, 1.0);
        let y0 = vec![0.2, 1.1, 3.3, 7.0];
        let mut y = y0.clone();
        sys.normal_stress_step(&mut y, sm, sp).unwrap();
        assert!((y[1] - (y0[1] - 0.3 / 0.009 * ln_r)).abs() < 1e-13);
        assert!((y[2] - (y0[2] - 0.1 / 0.006 * ln_r)).abs() < 1e-13);
        let (mu0, mu1) = (sys.stress(&y0), sys.stress(&y));
        assert!((mu1 - mu0 * sm / sp).abs() < 1e-15, "tau continuous");
        let x_expected = y0[0] + (mu1 - mu0 + alphas * ln_r) / m.a;
        assert!((y[0] - x_expected).abs() < 1e-12, "{} vs {x_expected}", y[0]);
        assert_eq!(y[3], y0[3]);
        // infinite stiffness
        let m = two(f64::INFINITY);
        let sys = SpringSlider::new(&m, 1.0);
        let mut y = y0.clone();
        sys.normal_stress_step(&mut y, sm, sp).unwrap();
        assert_eq!(y[0], y0[0]);
        assert!((sys.stress(&y) - sys.stress(&y0) + alphas * ln_r).abs() < 1e-14);
        // regularized form with damping: τ continuous through the iterative slip-rate solve
        let m = two(0.01).with_form(FrictionForm::Regularized).with_eta(1e-3);
        let sys = SpringSlider::new(&m, 1.0);
        let mut y = y0.clone();
        sys.normal_stress_step(&mut y, sm, sp).unwrap();
        assert!((sys.stress(&y) - sys.stress(&y0) * sm / sp).abs() < 1e-12, "regularized: τ continuous");
        // a rate-dependent direct effect: the quadratic's root keeps τ continuous, on the branch
        // where the local slope a + a₁ ln(V/V0) is positive, for either sign of a₁
        for a_slope in [2e-4, -2e-4] {
            let m = two(0.01).with_a_slope(a_slope);
            let sys = SpringSlider::new(&m, 1.0);
            let mut y = y0.clone();
            sys.normal_stress_step(&mut y, sm, sp).unwrap();
            assert!((sys.stress(&y) - sys.stress(&y0) * sm / sp).abs() < 1e-14, "a_slope {a_slope}: τ continuous");
            assert!(m.direct_slope(y[0]) > 0.0);
        }
    }
}

/// The quadratic inversion of a rate-dependent direct effect: exact round trips over ten
/// decades of V for either sign of a₁, and `None` beyond the friction's extremum.
#[test]
fn rate_dependent_direct_effect_inverts() {
    for a_slope in [1e-3, -1e-3, 1e-9, 0.0] {
        let m =
            Model::new(0.6, 1.0, 0.011, 0.01).with_state(StateVariable::new(Slip, 0.009, 3.0)).with_a_slope(a_slope);
        for x in [-5.0f64, -1.0, 0.0, 0.5, 5.0] {
            let psi = 0.013;
            let mu = m.form.friction(m.mu0, m.a, m.v0, x, psi) + 0.5 * a_slope * x * x;
            let v = m.slip_rate(mu, psi).unwrap();
            assert!((v.ln() - x).abs() < 1e-12, "a_slope {a_slope}, x {x}: {}", v.ln());
        }
    }
    // a₁ > 0: friction has its minimum μ0 + Ψ − a²/(2a₁) at ln(V/V0) = −a/a₁
    let m = Model::new(0.6, 1.0, 0.011, 0.01).with_state(StateVariable::new(Slip, 0.009, 3.0)).with_a_slope(1e-3);
    assert!(m.slip_rate(0.6 - 0.011 * 0.011 / 2e-3 - 1e-6, 0.0).is_none());
    assert!(m.validate().is_ok());
    assert!(m.clone().with_eta(0.1).validate().is_err());
    assert!(m.with_form(FrictionForm::Regularized).validate().is_err());
}

#[test]
fn steady_state_has_zero_rates_when_loaded_at_that_velocity() {
    for m in models().iter().take(5).chain(&models()[7..]) {
        let y = SpringSlider::steady_state(m, 2.5).unwrap();
        let sys = SpringSlider::new(m, 2.5);
        let mut f = vec![0.0; y.len()];
        sys.rhs(0.0, &y, &mut f);
        for (i, fi) in f.iter().enumerate().take(y.len() - 1) {
            assert!(fi.abs() < 1e-13, "component {i}: {fi}");
        }
        assert!((f[y.len() - 1] - 2.5).abs() < 1e-13);
    }
    // with a slip trend, steady sliding is not a fixed point: friction must fall by gV
    let m = &models()[5];
    let y = SpringSlider::steady_state(m, 2.5).unwrap();
    let mut f = vec![0.0; y.len()];
    SpringSlider::new(m, 2.5).rhs(0.0, &y, &mut f);
    assert!((f[0] - (-m.slip_trend * 2.5 / m.a)).abs() < 1e-15);
}
