//! Any law reshaped in its state: the same rate, read at a state bent by an exponent p about
//! the law's state scale, so that p = 1 is the law itself. The diagnosis's form test
//! (`rsf-diagnose/src/form.rs`) fits it to ask whether the law named has the right dependence on
//! state, and any law — built in, from a text file, from Python — has it without writing it.

use crate::registry::{LawEntry, LawParameter, Start};
use rsf_core::{DynStateLaw, Jet, Real, StateArgs, StateLaw};
use std::sync::Arc;

/// A reshaped law's name is its law's with this suffix (`prz-reshaped`); the registry derives
/// its entry from the law's ([`entry`]), and refuses the suffix in a name it is given.
pub const RESHAPED_SUFFIX: &str = "-reshaped";

/// The exponent's name in fits and results (`p1` for state 1).
pub const EXPONENT: &str = "p";

/// The exponent's range and fitting scale: a tenth to ten times the law's own curvature in
/// ln θ, far beyond any law published (power-law healing exponents 0.3–3), fitted as a
/// logarithm from the law itself (p = 1).
pub const EXPONENT_SPEC: LawParameter =
    LawParameter { name: EXPONENT, unit: "", lo: 0.1, hi: 10.0, log: true, start: Start::Value(1.0) };

/// The law `inner` read at the state θ' = θ_ref (θ/θ_ref)^p, with θ_ref = s·Dc/V (s the law's
/// [`theta_scale`](StateLaw::theta_scale), so that θ_ref is the steady state of every law
/// whose steady state is s·Dc/V, and stays one for every p):
///
/// `dθ/dt = G_inner(V, θ', Dc, b, dτ/dt)`, p dimensionless (> 0).
///
/// In Ω = Vθ/(s Dc) the reshaped Aging law is power-law aging, 1 − Ω^p; the reshaped
/// Perrin–Rice–Zheng law is 1 − Ω^(2p); the reshaped Slip law −p Ω^p ln Ω. The friction term is
/// the inner law's, `b ln(V0 θ/(s Dc))`. The derivatives are the inner law's jet by the chain
/// rule: exact when the inner law's are.
#[derive(Clone, Debug)]
pub struct Reshaped {
    /// The law reshaped.
    pub inner: Arc<dyn DynStateLaw>,
    /// The exponent p (dimensionless, > 0; 1 is the inner law).
    pub p: f64,
}

impl Reshaped {
    /// `inner` at p = 1; an error when `inner` has a parameter named [`EXPONENT`] already.
    pub fn new(inner: Arc<dyn DynStateLaw>) -> Result<Self, String> {
        if inner.parameters().iter().any(|(n, _)| *n == EXPONENT) {
            return Err(format!(
                "law `{}` has a parameter `{EXPONENT}` of its own, the name of the reshaping exponent",
                inner.name()
            ));
        }
        Ok(Self { inner, p: 1.0 })
    }

    /// The reshaped point: θ' and its log-derivative factors.
    fn bent(&self, s: &StateArgs<f64>) -> (StateArgs<f64>, f64) {
        let theta_ref = self.inner.theta_scale() * s.dc / s.v;
        let r = s.theta / theta_ref;
        let theta = theta_ref * r.powf(self.p);
        (StateArgs { theta, ..*s }, r.ln())
    }
}

impl StateLaw for Reshaped {
    /// Plain values: the derivatives come from [`jet`](Self::jet) by the chain rule over the
    /// inner law's, so this is never asked for dual numbers (their parts would be zero).
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        R::from(self.inner.rate(&self.bent(&s.plain()).0))
    }

    fn name(&self) -> String {
        format!("{}{RESHAPED_SUFFIX}", self.inner.name())
    }

    fn parameters(&self) -> Vec<(&'static str, f64)> {
        let mut v = self.inner.parameters();
        v.push((EXPONENT, self.p));
        v
    }

    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), String> {
        if name == EXPONENT {
            self.p = value;
            Ok(())
        } else {
            self.inner = self.inner.with_parameter(name, value)?;
            Ok(())
        }
    }

    fn validate(&self) -> Result<(), String> {
        if !(self.p > 0.0 && self.p.is_finite()) {
            return Err(format!("{EXPONENT} = {} must be positive (the reshaping exponent)", self.p));
        }
        self.inner.validate()
    }

    /// θ' = θ_ref r^p with r = θ/θ_ref ∝ Vθ/Dc: ∂θ'/∂θ = p θ'/θ, ∂θ'/∂V = (p − 1) θ'/V,
    /// ∂θ'/∂Dc = (1 − p) θ'/Dc.
    fn jet(&self, s: &StateArgs<f64>) -> Jet {
        let (b, _) = self.bent(s);
        let j = self.inner.jet(&b);
        let p = self.p;
        Jet {
            rate: j.rate,
            d_v: j.d_v + j.d_theta * (p - 1.0) * b.theta / s.v,
            d_theta: j.d_theta * p * b.theta / s.theta,
            d_stress_rate: j.d_stress_rate,
            d_dc: j.d_dc + j.d_theta * (1.0 - p) * b.theta / s.dc,
            d_b: j.d_b,
        }
    }

    /// ∂/∂p = ∂G/∂θ' · θ' ln r, exact; the inner law's own parameters at the bent state.
    fn parameter_derivative(&self, name: &str, s: &StateArgs<f64>) -> Option<f64> {
        let (b, ln_r) = self.bent(s);
        if name == EXPONENT {
            Some(self.inner.jet(&b).d_theta * b.theta * ln_r)
        } else {
            self.inner.parameter_derivative(name, &b)
        }
    }

    fn theta_scale(&self) -> f64 {
        self.inner.theta_scale()
    }

    /// The inner law's steady state θ_i, unbent: θ = θ_ref (θ_i/θ_ref)^(1/p).
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        let theta_ref = self.inner.theta_scale() * dc / v;
        let ti = self.inner.steady_state_theta(v, dc)?;
        Ok(theta_ref * (ti / theta_ref).powf(1.0 / self.p))
    }
}

/// `law` reshaped, at p = 1 (the law itself).
pub fn reshaped(law: Arc<dyn DynStateLaw>) -> Result<Arc<dyn DynStateLaw>, String> {
    Ok(Arc::new(Reshaped::new(law)?))
}

/// The registry entry of `base` reshaped: `base`'s parameters then [`EXPONENT_SPEC`], never a
/// candidate of its own (the diagnosis reshapes the law it names, `rsf-diagnose/src/form.rs`).
pub fn entry(base: &LawEntry) -> Result<LawEntry, String> {
    if base.parameter(EXPONENT).is_some() {
        return Err(format!(
            "law `{}` has a parameter `{EXPONENT}` of its own, the name of the reshaping exponent",
            base.name()
        ));
    }
    let mut parameters = base.parameters().to_vec();
    parameters.push(EXPONENT_SPEC);
    let n = base.parameters().len();
    let b = base.clone();
    let words = format!("{} reshaped in state (exponent p)", base.words());
    Ok(LawEntry::new(&format!("{}{RESHAPED_SUFFIX}", base.name()), &words, parameters, move |v: &[f64]| {
        let inner = b.build(|name| b.parameters().iter().position(|q| q.name == name).map(|i| v[i]))?;
        let mut r = Reshaped::new(inner)?;
        r.p = v[n];
        Ok(Arc::new(r) as Arc<dyn DynStateLaw>)
    })
    .with_origin(base.origin().clone())
    .with_candidate(false))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Aging, Prz, Slip};

    fn at(p: f64, inner: Arc<dyn DynStateLaw>) -> Reshaped {
        Reshaped { inner, p }
    }

    #[test]
    fn reshaped_aging_is_power_law_aging() {
        let l = at(1.7, Arc::new(Aging));
        for &(v, theta, dc) in &[(1.0, 3.0, 10.0), (0.01, 1e4, 5.0), (30.0, 0.01, 2.0)] {
            let omega: f64 = v * theta / dc;
            let want = 1.0 - omega.powf(1.7);
            let got = l.theta_rate(&StateArgs::new(v, theta, dc, 0.01));
            assert!((got - want).abs() <= 1e-12 * want.abs().max(1.0), "{got} {want}");
        }
    }

    #[test]
    fn reshaped_prz_is_its_power_and_keeps_its_steady_state() {
        let l = at(0.9, Arc::new(Prz));
        let (v, theta, dc) = (2.0, 7.0, 4.0);
        let omega: f64 = v * theta / (2.0 * dc);
        let got = l.theta_rate(&StateArgs::new(v, theta, dc, 0.01));
        assert!((got - (1.0 - omega.powf(1.8))).abs() < 1e-12);
        let ss = StateLaw::steady_state_theta(&l, v, dc).unwrap();
        assert!((ss - 2.0 * dc / v).abs() < 1e-12 * ss);
        assert_eq!(StateLaw::theta_scale(&l), 2.0);
    }

    #[test]
    fn at_one_it_is_the_law() {
        let l = at(1.0, Arc::new(Slip));
        let s = StateArgs::new(3.0, 0.4, 2.0, 0.01);
        let (a, b) = (StateLaw::jet(&l, &s), StateLaw::jet(&Slip, &s));
        for (x, y) in [(a.rate, b.rate), (a.d_v, b.d_v), (a.d_theta, b.d_theta), (a.d_dc, b.d_dc)] {
            assert!((x - y).abs() <= 1e-13 * y.abs().max(1e-300), "{x} {y}");
        }
    }

    #[test]
    fn the_jet_is_the_derivative_of_the_rate() {
        let l = at(1.6, Arc::new(Slip));
        let s = StateArgs::new(3.0, 0.4, 2.0, 0.01);
        let j = StateLaw::jet(&l, &s);
        let f = |v: f64, th: f64, dc: f64| l.theta_rate(&StateArgs::new(v, th, dc, 0.01));
        let cd = |g: &dyn Fn(f64) -> f64, x: f64| {
            let h = 1e-6 * x;
            (g(x + h) - g(x - h)) / (2.0 * h)
        };
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * b.abs().max(1e-9);
        assert!(close(j.d_v, cd(&|x| f(x, s.theta, s.dc), s.v)));
        assert!(close(j.d_theta, cd(&|x| f(s.v, x, s.dc), s.theta)));
        assert!(close(j.d_dc, cd(&|x| f(s.v, s.theta, x), s.dc)));
        let dp = StateLaw::parameter_derivative(&l, EXPONENT, &s).unwrap();
        let fp = |p: f64| at(p, Arc::new(Slip)).theta_rate(&s);
        assert!(close(dp, cd(&fp, 1.6)));
    }

    #[test]
    fn the_registry_knows_every_law_reshaped() {
        let e = crate::registry::find("kato-tullis-reshaped").unwrap();
        assert_eq!(e.parameters().iter().map(|p| p.name).collect::<Vec<_>>(), vec!["vc", "p"]);
        assert!(!e.candidate());
        let l = crate::law_by_name("kato-tullis-reshaped", |n| Some(if n == "p" { 1.3 } else { 0.5 })).unwrap();
        assert_eq!(l.parameters(), vec![("vc", 0.5), ("p", 1.3)]);
        assert!(crate::registry::find("prz-reshaped-reshaped").is_err());
        assert!(crate::registry::check_name("mine-reshaped").is_err());
    }
}
