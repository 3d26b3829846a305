//! The built-in laws pass the kit, and deliberately wrong laws fail it on the property that
//! is wrong, with a shrunk input.

use rsf_core::{Jet, LnArgs, Real, StateArgs, StateLaw};
use rsf_laws::{Aging, AgingNoHealing, AgingSlip, KatoTullis, Nagata, Prz, Slip};
use rsf_testkit::{Claims, Outcome, Property, check};

fn passes<L: StateLaw>(law: L, claims: Claims) {
    let report = check(&law, &claims).unwrap_or_else(|f| panic!("{f}"));
    assert_eq!(report.outcomes.len(), Property::ALL.len());
    println!("{report}");
}

#[test]
fn aging_conforms() {
    passes(Aging, Claims::new().steady_state_dc_over_v());
}

#[test]
fn slip_conforms() {
    passes(Slip, Claims::new().steady_state_dc_over_v());
}

#[test]
fn prz_conforms() {
    passes(Prz, Claims::new().steady_state_dc_over_v());
}

/// The Aging law without healing passes with its claim of no steady state (its solver
/// properties start from θ = Dc/V_i), and fails `steady_state` without it.
#[test]
fn aging_without_healing_conforms_and_claims_no_steady_state() {
    passes(AgingNoHealing, Claims::new().no_steady_state());
    let f = check(&AgingNoHealing, &Claims::new().cases(32)).unwrap_err();
    assert_eq!(f.property, Property::SteadyState, "{f}");
    // and Aging, which has one, fails the claim of none
    let f = check(&Aging, &Claims::new().no_steady_state().cases(32)).unwrap_err();
    assert_eq!(f.property, Property::SteadyState, "{f}");
    assert!(f.reason.contains("claims no steady state"), "{f}");
}

#[test]
fn nagata_conforms() {
    passes(Nagata { c: 2.0 }, Claims::new().steady_state_dc_over_v());
}

/// The built-in laws with a parameter of their own (Kato–Tullis vc, Nagata c, the Aging–Slip
/// mixture's w) give its derivative exactly, and the kit checks it against central
/// differences (issue 39: on the main before it, the property was skipped for all three).
#[test]
fn builtin_parameter_derivatives_are_exact_and_checked() {
    let reports = [
        check(&KatoTullis { vc: 0.05 }, &Claims::new().velocity_parameter("vc")),
        check(&Nagata { c: 2.0 }, &Claims::new().steady_state_dc_over_v()),
        check(&AgingSlip { w: 0.3 }, &Claims::new().steady_state_dc_over_v()),
    ];
    for r in reports {
        let r = r.unwrap_or_else(|f| panic!("{f}"));
        let pd = r.outcomes.iter().find(|(p, _)| *p == Property::ParameterDerivative).unwrap();
        assert!(matches!(pd.1, Outcome::Passed(_)), "{r}");
    }
}

#[test]
fn kato_tullis_conforms_and_is_not_held_to_the_identity() {
    let report =
        check(&KatoTullis { vc: 0.05 }, &Claims::new().velocity_parameter("vc")).unwrap_or_else(|f| panic!("{f}"));
    let vit = report.outcomes.iter().find(|(p, _)| *p == Property::ViTIdentity).unwrap();
    assert!(matches!(vit.1, Outcome::Skipped(_)), "{report}");
}

/// Kato–Tullis without `vc` named as a velocity: time scaling fails (Vc sets a time scale).
#[test]
fn an_unclaimed_velocity_scale_is_caught() {
    let f = check(&KatoTullis { vc: 0.05 }, &Claims::new().cases(64)).unwrap_err();
    assert_eq!(f.property, Property::TimeScaling, "{f}");
    assert!(f.to_string().contains("minimal input"), "{f}");
}

/// The Slip law with a hand-written Jacobian that forgets the `+ 1` of ∂(Ω ln Ω)/∂Ω.
#[derive(Debug, Clone)]
struct WrongJacobian;
impl StateLaw for WrongJacobian {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        Slip.theta_rate(s)
    }
    fn jet(&self, s: &StateArgs<f64>) -> Jet {
        let omega = s.v * s.theta / s.dc;
        let l = omega.ln();
        Jet {
            rate: -omega * l,
            d_v: -(s.theta / s.dc) * l,
            d_theta: -(s.v / s.dc) * l,
            d_stress_rate: 0.0,
            d_dc: (omega / s.dc) * l,
            d_b: 0.0,
        }
    }
}

#[test]
fn a_wrong_jacobian_is_caught() {
    let f = check(&WrongJacobian, &Claims::new().steady_state_dc_over_v().cases(64)).unwrap_err();
    assert_eq!(f.property, Property::Jacobian, "{f}");
    assert!(f.reason.contains("dual numbers"), "{f}");
    println!("{f}");
}

/// PRZ's rate with the Aging law's steady state (θ = Dc/V instead of 2Dc/V).
#[derive(Debug, Clone)]
struct WrongSteadyState;
impl StateLaw for WrongSteadyState {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        Prz.theta_rate(s)
    }
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        Ok(dc / v)
    }
}

#[test]
fn a_wrong_steady_state_is_caught() {
    let f = check(&WrongSteadyState, &Claims::new().cases(64)).unwrap_err();
    assert_eq!(f.property, Property::SteadyState, "{f}");
    assert!(f.reason.contains("not a root"), "{f}");
}

/// A law that claims θ_ss = Dc/V while its root is at 2Dc/V (PRZ without its θ scale).
#[derive(Debug, Clone)]
struct WrongClaim;
impl StateLaw for WrongClaim {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        Prz.theta_rate(s)
    }
}

#[test]
fn a_false_closed_form_claim_is_caught() {
    let f = check(&WrongClaim, &Claims::new().steady_state_dc_over_v().cases(64)).unwrap_err();
    assert_eq!(f.property, Property::SteadyState, "{f}");
    assert!(f.reason.contains("claimed"), "{f}");
}

/// The Aging law with a log form that drops the 1/θ term's exponent.
#[derive(Debug, Clone)]
struct WrongLogForm;
impl StateLaw for WrongLogForm {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        Aging.theta_rate(s)
    }
    fn ln_theta_rate(&self, s: &LnArgs) -> f64 {
        -s.z - s.v_dc
    }
}

#[test]
fn a_wrong_log_form_is_caught() {
    let f = check(&WrongLogForm, &Claims::new().cases(64)).unwrap_err();
    assert_eq!(f.property, Property::LogForm, "{f}");
}

/// Healing with an absolute time scale hidden in the law (1 s): passes pointwise checks only
/// if time scaling is not checked — the kit names time scaling.
#[derive(Debug, Clone)]
struct HiddenClock;
impl StateLaw for HiddenClock {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        let omega = s.v * s.theta / s.dc;
        -omega + 1.0 + (-s.theta).exp() * 0.5
    }
}

#[test]
fn a_hidden_time_scale_is_caught() {
    let f = check(&HiddenClock, &Claims::new().cases(64)).unwrap_err();
    assert!(matches!(f.property, Property::SteadyState | Property::TimeScaling), "{f}");
}

/// Same law, same claims: the same report or failure every time (no clock, no environment).
#[test]
fn runs_are_deterministic() {
    let a = check(&KatoTullis { vc: 0.05 }, &Claims::new().cases(32)).unwrap_err();
    let b = check(&KatoTullis { vc: 0.05 }, &Claims::new().cases(32)).unwrap_err();
    assert_eq!(a, b);
}
