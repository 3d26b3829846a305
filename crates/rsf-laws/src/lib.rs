//! # rsf-laws — state-evolution laws
//!
//! Each law is a small type implementing [`rsf_core::StateLaw`]; its doc comment gives the
//! equation, units and the paper it comes from. Notation: V slip rate (µm/s), θ state (s),
//! Dc characteristic slip distance (µm), Ω = Vθ/Dc, τ shear stress over normal stress.
//!
//! | name (protocol files) | type | dθ/dt |
//! |---|---|---|
//! | `aging` | [`Aging`] | `1 − Ω` |
//! | `slip` | [`Slip`] | `−Ω ln Ω` |
//! | `kato-tullis` | [`KatoTullis`] | `exp(−V/Vc) − Ω ln Ω` |
//! | `prz` | [`Prz`] | `1 − (Ω/2)²` |
//! | `nagata` | [`Nagata`] | `1 − Ω − (c/b) θ dτ/dt` |
//! | `aging-slip` | [`AgingSlip`] | `w (1 − Ω) − (1 − w) Ω ln Ω` |
//! | `aging-no-healing` | [`AgingNoHealing`] | `−Ω` (no steady state) |
//!
//! ```
//! use rsf_core::{Model, StateVariable};
//! use rsf_laws::{Aging, Slip};
//! // Two state variables with different laws (Slip for the short one, Aging for the long one).
//! let m = Model::new(0.6, 1.0, 0.01, 1e-3)
//!     .with_state(StateVariable::new(Slip, 0.008, 5.0))
//!     .with_state(StateVariable::new(Aging, 0.004, 50.0));
//! let mu = m.steady_state_friction(10.0).unwrap();
//! assert!((mu - (0.6 + (0.01 - 0.012) * 10f64.ln())).abs() < 1e-14);
//! ```
#![forbid(unsafe_code)]

mod aging_slip;
pub mod expr;
mod no_healing;
pub mod registry;
pub mod reshaped;
pub mod text_law;

pub use aging_slip::AgingSlip;
pub use no_healing::AgingNoHealing;

pub use registry::{LawEntry, LawParameter, Start};
use rsf_core::{DynStateLaw, Jet, LnArgs, Real, StateArgs, StateLaw};
use std::sync::Arc;

/// Dieterich's Aging law, `dθ/dt = 1 − Vθ/Dc`.
///
/// θ grows with elapsed time in stationary contact (healing in time). Steady state θ = Dc/V.
/// At constant V, θ relaxes exponentially in time with rate V/Dc.
///
/// Dieterich, J. H. (1979), Modeling of rock friction 1. Experimental results and constitutive
/// equations, J. Geophys. Res. 84, 2161–2168; Ruina (1983).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aging;

impl StateLaw for Aging {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        -(s.v * s.theta / s.dc) + 1.0
    }
    fn name(&self) -> String {
        "aging".into()
    }
    /// 1/θ − V/Dc: one exponential, no division.
    fn ln_theta_rate(&self, s: &LnArgs) -> f64 {
        (-s.z).exp() - s.v_dc
    }
    /// Hand-derived: ∂G/∂V = −θ/Dc, ∂G/∂θ = −V/Dc, ∂G/∂Dc = Ω/Dc (checked against the
    /// dual-number default).
    fn jet(&self, s: &StateArgs<f64>) -> Jet {
        let omega = s.v * s.theta / s.dc;
        Jet {
            rate: 1.0 - omega,
            d_v: -s.theta / s.dc,
            d_theta: -s.v / s.dc,
            d_stress_rate: 0.0,
            d_dc: omega / s.dc,
            d_b: 0.0,
        }
    }
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        Ok(dc / v)
    }
}

/// Ruina's Slip law, `dθ/dt = −(Vθ/Dc) ln(Vθ/Dc)`.
///
/// State evolves only with slip: with no slip there is no healing. At imposed constant V,
/// `ln(Vθ/Dc)` decays as `exp(−δ/Dc)` with slip δ. Steady state θ = Dc/V.
///
/// Ruina, A. (1983), Slip instability and state variable friction laws, J. Geophys. Res. 88,
/// 10359–10370.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Slip;

impl StateLaw for Slip {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        let omega = s.v * s.theta / s.dc;
        -(omega * omega.ln())
    }
    fn name(&self) -> String {
        "slip".into()
    }
    /// −(V/Dc) ln Ω with ln Ω = x + z − ln Dc: no transcendental call at all.
    fn ln_theta_rate(&self, s: &LnArgs) -> f64 {
        // −(V/Dc) ln Ω, V multiplied last (it arrives last)
        -s.v * (s.inv_dc * (s.x + s.z - s.ln_dc))
    }
    /// Hand-derived: with Ω = Vθ/Dc, ∂G/∂V = −(θ/Dc)(ln Ω + 1), ∂G/∂θ = −(V/Dc)(ln Ω + 1),
    /// ∂G/∂Dc = (Ω/Dc)(ln Ω + 1).
    fn jet(&self, s: &StateArgs<f64>) -> Jet {
        let omega = s.v * s.theta / s.dc;
        let l = omega.ln();
        Jet {
            rate: -omega * l,
            d_v: -(s.theta / s.dc) * (l + 1.0),
            d_theta: -(s.v / s.dc) * (l + 1.0),
            d_stress_rate: 0.0,
            d_dc: (omega / s.dc) * (l + 1.0),
            d_b: 0.0,
        }
    }
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        Ok(dc / v)
    }
}

/// Kato–Tullis composite law with cut-off velocity Vc (µm/s):
/// `dθ/dt = exp(−V/Vc) − (Vθ/Dc) ln(Vθ/Dc)`.
///
/// Time-dependent (Aging-like) healing that switches off above Vc, plus the Slip law's
/// slip-dependent evolution. Far above Vc it is the Slip law; near and below Vc its steady
/// state is not Dc/V but the root of `exp(−V/Vc) = Ω ln Ω` (Ω = Vθ/Dc > 1).
///
/// Kato, N. & Tullis, T. E. (2001), A composite rate- and state-dependent law for rock friction,
/// Geophys. Res. Lett. 28, 1103–1106.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KatoTullis {
    /// Cut-off velocity Vc, µm/s.
    pub vc: f64,
}

impl StateLaw for KatoTullis {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        let omega = s.v * s.theta / s.dc;
        (-(s.v / self.vc)).exp() - omega * omega.ln()
    }
    fn name(&self) -> String {
        "kato-tullis".into()
    }
    /// e^(−V/Vc − z) − (V/Dc) ln Ω: one exponential instead of three calls.
    fn ln_theta_rate(&self, s: &LnArgs) -> f64 {
        (-s.v / self.vc - s.z).exp() - s.v * (s.inv_dc * (s.x + s.z - s.ln_dc))
    }
    fn parameters(&self) -> Vec<(&'static str, f64)> {
        vec![("vc", self.vc)]
    }
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), String> {
        match name {
            "vc" => {
                self.vc = value;
                Ok(())
            }
            _ => Err(format!("law `kato-tullis` has no parameter `{name}`")),
        }
    }
    /// ∂/∂Vc = e^(−V/Vc) V/Vc², exact.
    fn parameter_derivative(&self, name: &str, s: &StateArgs<f64>) -> Option<f64> {
        (name == "vc").then(|| (-s.v / self.vc).exp() * s.v / (self.vc * self.vc))
    }
    fn validate(&self) -> Result<(), String> {
        if self.vc > 0.0 && self.vc.is_finite() {
            Ok(())
        } else {
            Err(format!("vc = {} must be positive and finite (µm/s)", self.vc))
        }
    }
    /// Solves `Ω ln Ω = q`, `q = exp(−V/Vc)`, by Newton from Ω = 1 + q (convex, monotone).
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        let q = (-v / self.vc).exp();
        let mut om = 1.0 + q;
        for _ in 0..100 {
            let h = om * om.ln() - q;
            let step = h / (om.ln() + 1.0);
            om -= step;
            if step.abs() <= 1e-16 * om {
                break;
            }
        }
        Ok(om * dc / v)
    }
}

/// Perrin–Rice–Zheng quadratic law, `dθ/dt = 1 − (Vθ/(2Dc))²`.
///
/// Aging-like healing with a symmetric response to steps up and down. PRZ define θ so that
/// the steady state is θ = 2Dc/V; the friction term is therefore `b ln(V0 θ/(2Dc))`
/// ([`theta_scale`](StateLaw::theta_scale) = 2), which gives the standard steady state.
///
/// Perrin, G., Rice, J. R. & Zheng, G. (1995), Self-healing slip pulse on a frictional surface,
/// J. Mech. Phys. Solids 43, 1461–1495.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Prz;

impl StateLaw for Prz {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        let half_omega = s.v * s.theta / (s.dc * 2.0);
        -(half_omega * half_omega) + 1.0
    }
    fn name(&self) -> String {
        "prz".into()
    }
    fn theta_scale(&self) -> f64 {
        2.0
    }
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        Ok(2.0 * dc / v)
    }
}

/// Nagata's law: the Aging law plus a shear-stress-rate term,
/// `dθ/dt = 1 − Vθ/Dc − (c/b) θ dτ/dt` (c dimensionless, τ in friction units).
///
/// A rise in shear stress weakens the contact population (reduces θ). Steady state θ = Dc/V.
/// The solver supplies `dτ/dt = k (V_lp − V)`.
///
/// Nagata, K., Nakatani, M. & Yoshida, S. (2012), A revised rate- and state-dependent friction
/// law obtained by constraining constitutive and evolution laws separately with laboratory data,
/// J. Geophys. Res. 117, B02314.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nagata {
    /// Stress-weakening coefficient c (dimensionless; Nagata et al. report c ≈ 2).
    pub c: f64,
}

impl StateLaw for Nagata {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        -(s.v * s.theta / s.dc) + 1.0 - s.theta * s.stress_rate * self.c / s.b
    }
    fn name(&self) -> String {
        "nagata".into()
    }
    /// 1/θ − V/Dc − (c/b) dτ/dt.
    fn ln_theta_rate(&self, s: &LnArgs) -> f64 {
        (-s.z).exp() - s.v_dc - s.stress_rate * self.c / s.b
    }
    fn parameters(&self) -> Vec<(&'static str, f64)> {
        vec![("c", self.c)]
    }
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), String> {
        match name {
            "c" => {
                self.c = value;
                Ok(())
            }
            _ => Err(format!("law `nagata` has no parameter `{name}`")),
        }
    }
    /// ∂/∂c = −θ (dτ/dt) / b, exact.
    fn parameter_derivative(&self, name: &str, s: &StateArgs<f64>) -> Option<f64> {
        (name == "c").then(|| -s.theta * s.stress_rate / s.b)
    }
    fn validate(&self) -> Result<(), String> {
        if self.c >= 0.0 && self.c.is_finite() {
            Ok(())
        } else {
            Err(format!("c = {} must be zero or positive and finite", self.c))
        }
    }
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        Ok(dc / v)
    }
}

/// The built-in laws: the one place each is listed — its name in files and on the command
/// line, its own parameters, its constructor, its id in the C ABI and its name in words. A new
/// variant fails to compile until every match on it (the CLI, Python, the C ABI, the report)
/// handles it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Law {
    /// [`Aging`].
    Aging,
    /// [`Slip`].
    Slip,
    /// [`KatoTullis`].
    KatoTullis,
    /// [`Prz`].
    Prz,
    /// [`Nagata`].
    Nagata,
    /// [`AgingSlip`].
    AgingSlip,
    /// [`AgingNoHealing`].
    AgingNoHealing,
}

rsf_core::vocabulary!(Law, "law", {
    Aging => "aging",
    Slip => "slip",
    KatoTullis => "kato-tullis",
    Prz => "prz",
    Nagata => "nagata",
    AgingSlip => "aging-slip",
    AgingNoHealing => "aging-no-healing",
});

impl Law {
    /// The name in prose (`Kato–Tullis`, `PRZ`).
    pub fn words(self) -> &'static str {
        match self {
            Law::Aging => "Aging",
            Law::Slip => "Slip",
            Law::KatoTullis => "Kato–Tullis",
            Law::Prz => "PRZ",
            Law::Nagata => "Nagata",
            Law::AgingSlip => "Aging–Slip",
            Law::AgingNoHealing => "Aging without healing",
        }
    }

    /// The law's own parameters: name, unit, physical range, fitting scale and start.
    pub fn specs(self) -> &'static [LawParameter] {
        match self {
            Law::Aging | Law::Slip | Law::Prz | Law::AgingNoHealing => &[],
            // µm/s: from far below any lab slip rate to far above; spans decades, so ln Vc;
            // starts at the record's slowest load point, where a cut-off first shows
            Law::KatoTullis => &[LawParameter {
                name: "vc",
                unit: "µm/s",
                lo: 1e-9,
                hi: 1e6,
                log: true,
                start: Start::SlowestLoadPointVelocity,
            }],
            // dimensionless; Nagata et al. (2012) report c ≈ 2; of either sign in a fit's
            // trial steps (the law itself refuses c < 0)
            Law::Nagata => {
                &[LawParameter { name: "c", unit: "", lo: -1e9, hi: 1e9, log: false, start: Start::Value(1.0) }]
            }
            // a share: 0 is the Slip law, 1 the Aging law
            Law::AgingSlip => {
                &[LawParameter { name: "w", unit: "", lo: 0.0, hi: 1.0, log: false, start: Start::Value(0.5) }]
            }
        }
    }

    /// The names of the law's own parameters (`vc`, µm/s; `c` and `w`, dimensionless).
    pub fn parameters(self) -> Vec<&'static str> {
        self.specs().iter().map(|p| p.name).collect()
    }

    /// Where a fit starts one of the law's own parameters without a record at hand (Vc
    /// 0.01 µm/s; Nagata's c 1; the aging share w ½).
    pub fn starting_value(self, parameter: &str) -> Option<f64> {
        self.specs().iter().find(|p| p.name == parameter).map(|p| p.start_value(None))
    }

    /// The law's id in the C ABI (`RsfStateParams.law`).
    pub fn c_id(self) -> i32 {
        match self {
            Law::Aging => 0,
            Law::Slip => 1,
            Law::KatoTullis => 2,
            Law::Prz => 3,
            Law::Nagata => 4,
            Law::AgingSlip => 5,
            Law::AgingNoHealing => 6,
        }
    }

    /// The law of a C ABI id.
    pub fn from_c_id(id: i32) -> Option<Law> {
        Law::ALL.iter().copied().find(|l| l.c_id() == id)
    }

    /// The law with its own parameters looked up by `param`; the error names a missing one.
    pub fn build(self, param: impl Fn(&'static str) -> Option<f64>) -> Result<Arc<dyn DynStateLaw>, String> {
        let need = |p: &'static str| param(p).ok_or_else(|| format!("law `{}` needs parameter `{p}`", self.name()));
        Ok(match self {
            Law::Aging => Arc::new(Aging),
            Law::Slip => Arc::new(Slip),
            Law::KatoTullis => Arc::new(KatoTullis { vc: need("vc")? }),
            Law::Prz => Arc::new(Prz),
            Law::Nagata => Arc::new(Nagata { c: need("c")? }),
            Law::AgingSlip => Arc::new(AgingSlip { w: need("w")? }),
            Law::AgingNoHealing => Arc::new(AgingNoHealing),
        })
    }

    /// The law with its parameters at their fit starting values ([`Law::starting_value`]).
    pub fn with_starting_values(self) -> Arc<dyn DynStateLaw> {
        match self.build(|p| self.starting_value(p)) {
            Ok(l) => l,
            Err(e) => unreachable!("every parameter of a built-in law has a starting value: {e}"),
        }
    }
}

/// A registered law (built in or registered by a program) by name, with its own parameters
/// looked up by `param` (e.g. `"vc"`). The error names the missing or unknown item.
pub fn law_by_name(name: &str, param: impl Fn(&str) -> Option<f64>) -> Result<Arc<dyn DynStateLaw>, String> {
    registry::find(name)?.build(param)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Every law's log-form rate equals the generic one (θ-rate at e^x, e^z over θ), with and
    /// without a stress rate and normal stress, far from and at steady state.
    #[test]
    fn log_form_rates_equal_the_generic_ones() {
        type Rates = Box<dyn Fn(&LnArgs) -> (f64, f64)>;
        let laws: Vec<(&str, Rates)> = vec![
            ("aging", Box::new(|s| (Aging.ln_theta_rate(s), Aging.theta_rate(&s.state_args())))),
            ("slip", Box::new(|s| (Slip.ln_theta_rate(s), Slip.theta_rate(&s.state_args())))),
            ("kato-tullis", {
                let l = KatoTullis { vc: 0.05 };
                Box::new(move |s| (l.ln_theta_rate(s), l.theta_rate(&s.state_args())))
            }),
            ("prz", Box::new(|s| (Prz.ln_theta_rate(s), Prz.theta_rate(&s.state_args())))),
            ("nagata", {
                let l = Nagata { c: 2.0 };
                Box::new(move |s| (l.ln_theta_rate(s), l.theta_rate(&s.state_args())))
            }),
            ("aging-slip", {
                let l = AgingSlip { w: 0.3 };
                Box::new(move |s| (l.ln_theta_rate(s), l.theta_rate(&s.state_args())))
            }),
            (
                "aging-no-healing",
                Box::new(|s| (AgingNoHealing.ln_theta_rate(s), AgingNoHealing.theta_rate(&s.state_args()))),
            ),
        ];
        for &(x, z, dc) in
            &[(0.3, 1.1, 2.07), (-20.0, 25.0, 8000.0), (5.0, -4.0, 0.1), (-3.0, 3.0 + 2.07f64.ln(), 2.07)]
        {
            for stress_rate in [0.0, 3e-3, -0.2] {
                let s =
                    LnArgs { stress_rate, normal_stress: 12.0, normal_stress_rate: 0.5, ..LnArgs::new(x, z, dc, 0.01) };
                for (name, f) in &laws {
                    let (ln_form, g) = f(&s);
                    let generic = g / f64::exp(z);
                    // the generic form loses digits near steady state (Ω ln Ω with Ω ≈ 1)
                    let scale = generic.abs().max(s.v / dc).max(f64::exp(-z));
                    assert!(
                        (ln_form - generic).abs() <= 1e-12 * scale,
                        "{name} at x {x}, z {z}, dc {dc}, τ' {stress_rate}: {ln_form:e} vs {generic:e}"
                    );
                }
            }
        }
    }

    fn all() -> Vec<Arc<dyn DynStateLaw>> {
        vec![
            Arc::new(Aging),
            Arc::new(Slip),
            Arc::new(KatoTullis { vc: 0.05 }),
            Arc::new(Prz),
            Arc::new(Nagata { c: 2.0 }),
            Arc::new(AgingSlip { w: 0.3 }),
        ]
    }

    /// Exact (dual-number) partials agree with central differences of the same law.
    #[test]
    fn jets_match_finite_differences() {
        for law in all() {
            for &(v, theta, sr) in &[(1.0, 3.0, 0.0), (0.01, 500.0, 1e-3), (30.0, 0.05, -0.2)] {
                let s = StateArgs { stress_rate: sr, ..StateArgs::new(v, theta, 10.0, 0.01) };
                let j = law.jet(&s);
                assert_relative_eq!(j.rate, law.rate(&s), max_relative = 1e-15);
                let fd = |f: &dyn Fn(f64) -> StateArgs<f64>, x: f64| {
                    let h = 1e-6 * x.abs().max(1e-3);
                    (law.rate(&f(x + h)) - law.rate(&f(x - h))) / (2.0 * h)
                };
                let dv = fd(&|x| StateArgs { v: x, ..s }, v);
                let dt = fd(&|x| StateArgs { theta: x, ..s }, theta);
                let ds = fd(&|x| StateArgs { stress_rate: x, ..s }, sr);
                let ddc = fd(&|x| StateArgs { dc: x, ..s }, 10.0);
                let db = fd(&|x| StateArgs { b: x, ..s }, 0.01);
                assert_relative_eq!(j.d_dc, ddc, max_relative = 1e-6, epsilon = 1e-9);
                assert_relative_eq!(j.d_b, db, max_relative = 1e-6, epsilon = 1e-9);
                assert_relative_eq!(j.d_v, dv, max_relative = 1e-6, epsilon = 1e-9);
                assert_relative_eq!(j.d_theta, dt, max_relative = 1e-6, epsilon = 1e-9);
                assert_relative_eq!(j.d_stress_rate, ds, max_relative = 1e-6, epsilon = 1e-9);
            }
        }
    }

    /// The hand-derived jets of Aging and Slip equal the dual-number default.
    #[test]
    fn hand_jets_equal_the_automatic_ones() {
        #[derive(Debug, Clone)]
        struct Auto<L: StateLaw>(L);
        impl<L: StateLaw> StateLaw for Auto<L> {
            fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
                self.0.theta_rate(s)
            }
        }
        for &(v, theta) in &[(1.0, 3.0), (1e-4, 7e3), (30.0, 0.01)] {
            let s = StateArgs::new(v, theta, 10.0, 0.01);
            for (h, a) in [
                (StateLaw::jet(&Aging, &s), StateLaw::jet(&Auto(Aging), &s)),
                (StateLaw::jet(&Slip, &s), StateLaw::jet(&Auto(Slip), &s)),
            ] {
                for (x, y) in [
                    (h.rate, a.rate),
                    (h.d_v, a.d_v),
                    (h.d_theta, a.d_theta),
                    (h.d_stress_rate, a.d_stress_rate),
                    (h.d_dc, a.d_dc),
                    (h.d_b, a.d_b),
                ] {
                    assert_relative_eq!(x, y, max_relative = 1e-14, epsilon = 1e-300);
                }
            }
        }
    }

    /// Every law's steady state is a zero of its own rate, and the closed forms agree with
    /// the trait's generic Newton solver.
    #[test]
    fn steady_states_are_roots() {
        for law in all() {
            for &v in &[1e-6, 1e-3, 0.05, 1.0, 300.0] {
                let th = law.steady_state_theta(v, 7.0).unwrap();
                let g = law.rate(&StateArgs::new(v, th, 7.0, 0.01));
                assert!(g.abs() < 1e-12, "{}: G = {g} at V = {v}", law.name());
            }
        }
        // the default Newton solver (trait default) finds the Kato–Tullis root too
        #[derive(Debug, Clone)]
        struct KtDefault(f64);
        impl StateLaw for KtDefault {
            fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
                KatoTullis { vc: self.0 }.theta_rate(s)
            }
        }
        for &v in &[1e-5, 1e-3, 0.02, 1.0] {
            let a = StateLaw::steady_state_theta(&KtDefault(0.01), v, 3.0).unwrap();
            let b = StateLaw::steady_state_theta(&KatoTullis { vc: 0.01 }, v, 3.0).unwrap();
            assert_relative_eq!(a, b, max_relative = 1e-12);
        }
    }

    #[test]
    fn names_round_trip_and_errors_name_the_problem() {
        for &l in Law::ALL {
            let law = law_by_name(l.name(), |_| Some(1.0)).unwrap();
            assert_eq!(law.name(), l.name());
            assert_eq!(l.name().parse::<Law>(), Ok(l));
            assert_eq!(Law::from_c_id(l.c_id()), Some(l));
            // the parameters the registry lists are the ones the law reports
            let own: Vec<&str> = law.parameters().iter().map(|(n, _)| *n).collect();
            assert_eq!(own, l.parameters());
            assert_eq!(l.with_starting_values().name(), l.name());
        }
        assert!(law_by_name("kato-tullis", |_| None).unwrap_err().contains("vc"));
        assert!(law_by_name("dieterich", |_| None).unwrap_err().contains("unknown law `dieterich`"));
        assert!(StateLaw::validate(&KatoTullis { vc: -1.0 }).is_err());
    }
}
