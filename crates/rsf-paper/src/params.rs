//! The parameters of the paper's Table 1 and the machine.
//!
//! Friction is shear stress over normal stress (dimensionless); `a`, `b` are dimensionless,
//! `Dc` in µm, slip rates in µm/s, the stiffness `k` (machine stiffness over normal stress) in
//! 1/µm.

use rsf_core::{Model, StateVariable};
use serde::Serialize;

/// Machine stiffness over normal stress of the experiments, k = 0.065 1/µm (Table 1).
pub const STIFFNESS: f64 = 0.065;
/// Reference friction μ0 at V0. Arbitrary: every result here is a friction difference.
pub const MU0: f64 = 0.6;
/// Reference slip rate V0, µm/s.
pub const V0: f64 = 1.0;

/// One single-state parameter set of Table 1: law name (as in `rsf_laws::law_by_name`), `a`,
/// `b` and `Dc` (µm).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LawParams {
    /// `"slip"` or `"aging"`.
    pub law: &'static str,
    /// Direct-effect coefficient a.
    pub a: f64,
    /// Evolution-effect coefficient b.
    pub b: f64,
    /// Characteristic slip distance Dc, µm.
    pub dc: f64,
}

/// Slip law fitted to the velocity steps.
pub const SLIP_STEPS: LawParams = LawParams { law: "slip", a: 0.013, b: 0.016, dc: 2.07 };
/// Aging law fitted to the velocity steps.
pub const AGING_STEPS: LawParams = LawParams { law: "aging", a: 0.022, b: 0.018, dc: 0.99 };
/// Aging law fitted to the velocity steps with a − b = −0.003 held fixed.
pub const AGING_STEPS_FIXED: LawParams = LawParams { law: "aging", a: 0.014, b: 0.017, dc: 10.05 };
/// Slip law fitted to the holds from V_i = 0.032, 0.32 and 1.0 µm/s (`(V_i, parameters)`;
/// b = a + 0.003).
pub const SLIP_HOLDS: [(f64, LawParams); 3] = [
    (0.032, LawParams { law: "slip", a: 0.014, b: 0.017, dc: 1.99 }),
    (0.32, LawParams { law: "slip", a: 0.015, b: 0.018, dc: 2.10 }),
    (1.0, LawParams { law: "slip", a: 0.015, b: 0.018, dc: 3.43 }),
];

impl LawParams {
    /// The spring-slider model: μ0 = [`MU0`], V0 = [`V0`], k = [`STIFFNESS`], one state
    /// variable of this law.
    ///
    /// # Panics
    /// If `law` is not a built-in law without parameters of its own (a programming error:
    /// every set of this module is valid).
    pub fn model(&self) -> Model {
        let law = rsf_laws::law_by_name(self.law, |_| None).expect("a built-in law without extra parameters");
        Model::new(MU0, V0, self.a, STIFFNESS).with_state(StateVariable::from_shared(law, self.b, self.dc))
    }

    /// A legend label, e.g. `Slip (a=0.013, b=0.016, Dc=2.07 µm)`.
    pub fn label(&self) -> String {
        format!("{} (a={}, b={}, Dc={} µm)", self.name(), self.a, self.b, self.dc)
    }

    /// The law's name with a capital, e.g. `Aging`.
    pub fn name(&self) -> String {
        let mut name = self.law.to_string();
        name[..1].make_ascii_uppercase();
        name
    }
}
