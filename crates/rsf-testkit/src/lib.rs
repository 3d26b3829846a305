//! # rsf-testkit — the conformance kit for state-evolution laws
//!
//! One call checks a [`StateLaw`] with property tests (proptest), the same checks rsf's
//! built-in laws pass, and says which property failed on which (shrunk) input:
//!
//! | property | what must hold |
//! |---|---|
//! | `finite` | dθ/dt, its log form and its partial derivatives are finite over the documented ranges |
//! | `log_form` | [`StateLaw::ln_theta_rate`] equals dθ/dt / θ |
//! | `jacobian` | [`StateLaw::jet`] equals the dual-number derivatives of `theta_rate` and central differences |
//! | `steady_state` | [`StateLaw::steady_state_theta`] is an attracting root of dθ/dt = 0 (and θ = s·Dc/V where claimed); for a law that claims none, it refuses and dθ/dt < 0 |
//! | `time_scaling` | dθ/dt is unchanged when time is rescaled: V → V/c, θ → cθ, rates → /c, the law's velocities → /c |
//! | `unit_scaling` | dθ/dt is unchanged when lengths are rescaled (µm ↔ m): V, Dc and the law's lengths and velocities × s |
//! | `vi_t_identity` | holds and steps of an N-state model (the law mixed with Aging and Slip, N = 1–3) from V_i and V_i·10^u trace the same Δμ against V_i·t (Bhattacharya et al. 2022, Eqs. 9–11); for laws without a velocity scale |
//! | `time_shift` | a model driven by a load-point record gives the same friction when the record's clock starts at 10⁶ s |
//! | `integrators_agree` | the explicit (Dopri5) and implicit (Rodas4, which uses the Jacobian) integrators agree |
//! | `parameter_round_trip` | each parameter `parameters()` lists can be set by `set_parameter` (a fit sets it by name) and reads back |
//! | `parameter_derivative` | an exact ∂(dθ/dt)/∂q ([`StateLaw::parameter_derivative`]) equals central differences |
//!
//! ```
//! use rsf_core::{Real, StateArgs, StateLaw};
//! use rsf_testkit::{Claims, check};
//!
//! /// dθ/dt = 1 − (Vθ/Dc)^p: a law with its own exponent.
//! #[derive(Debug, Clone)]
//! struct Power { p: f64 }
//! impl StateLaw for Power {
//!     fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
//!         -(s.v * s.theta / s.dc).powf(self.p) + 1.0
//!     }
//! }
//! let report = check(&Power { p: 2.0 }, &Claims::new().steady_state_dc_over_v().cases(32)).unwrap();
//! assert!(report.to_string().contains("vi_t_identity: passed"));
//! ```
//!
//! In a law's own tests, [`assert_conforms`] panics with the failure's text. Runs are
//! deterministic: the kit sets proptest's case count, random-number generator and seed itself
//! and writes no regression files.
//!
//! Why own this rather than ask each author for their tests: the properties are what rsf's
//! solvers, fitters and diagnosis rely on (a wrong Jacobian silently costs Rodas4 its order; a
//! wrong steady state starts every fit off-steady), and they are the same for every law.
#![forbid(unsafe_code)]

mod pointwise;
pub mod registered;
mod solver;

use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestError, TestRng, TestRunner};
use rsf_core::StateLaw;
use std::fmt;

pub use registered::check_entry;

/// Inputs per property by default (solver-level properties use an eighth of it, at least 8).
pub const DEFAULT_CASES: u32 = 256;

/// The ranges a law is promised to be finite and correct over. Defaults cover lab and natural
/// faults: V 1e-9–1e4 µm/s, Ω = Vθ/Dc 1e-6–1e6, Dc 0.1–1e4 µm, b 1e-4–0.1, dτ/dt ±1 /s,
/// σ 1–200 MPa, dσ/dt ±10 MPa/s.
#[derive(Clone, Debug, PartialEq)]
pub struct Ranges {
    /// Slip rate V, µm/s (sampled log-uniformly).
    pub v: (f64, f64),
    /// Ω = Vθ/Dc (sampled log-uniformly; θ follows).
    pub omega: (f64, f64),
    /// Dc, µm (log-uniform).
    pub dc: (f64, f64),
    /// b (log-uniform).
    pub b: (f64, f64),
    /// Shear-stress rate over normal stress, 1/s (uniform).
    pub stress_rate: (f64, f64),
    /// Normal stress, MPa (log-uniform).
    pub normal_stress: (f64, f64),
    /// Normal-stress rate, MPa/s (uniform).
    pub normal_stress_rate: (f64, f64),
}

impl Default for Ranges {
    fn default() -> Self {
        Ranges {
            v: (1e-9, 1e4),
            omega: (1e-6, 1e6),
            dc: (0.1, 1e4),
            b: (1e-4, 0.1),
            stress_rate: (-1.0, 1.0),
            normal_stress: (1.0, 200.0),
            normal_stress_rate: (-10.0, 10.0),
        }
    }
}

/// What a law claims about itself beyond what every law must satisfy.
#[derive(Clone, Debug, PartialEq)]
pub struct Claims {
    /// The steady state is θ = s·Dc/V, s = [`StateLaw::theta_scale`] (Aging, Slip, PRZ,
    /// Nagata; not Kato–Tullis).
    pub steady_state_dc_over_v: bool,
    /// The law has no steady state (the Aging law without healing): `steady_state` then checks
    /// that [`StateLaw::steady_state_theta`] refuses and that θ only decays, and the solver
    /// properties start every state at θ = Dc/V_i instead of steady state.
    pub no_steady_state: bool,
    /// The law's own parameters that are velocities, µm/s (Kato–Tullis's `vc`), set through
    /// [`StateLaw::set_parameter`] when time or length is rescaled. A law with one has a
    /// velocity scale of its own: the V_i·t identity is not expected of it.
    pub velocity_parameters: Vec<&'static str>,
    /// The law's own parameters that are lengths, µm.
    pub length_parameters: Vec<&'static str>,
    /// Where the law is promised to work.
    pub ranges: Ranges,
    /// Inputs per pointwise property.
    pub cases: u32,
    /// The law's [`jet`](StateLaw::jet) is central differences of its rate, not dual numbers
    /// (a Python function): `jacobian` checks it against the kit's own central differences
    /// alone.
    pub derivatives_by_differences: bool,
}

impl Default for Claims {
    fn default() -> Self {
        Self::new()
    }
}

impl Claims {
    /// No claim beyond what every law must satisfy; default ranges and cases.
    pub fn new() -> Self {
        Claims {
            steady_state_dc_over_v: false,
            no_steady_state: false,
            velocity_parameters: vec![],
            length_parameters: vec![],
            ranges: Ranges::default(),
            cases: DEFAULT_CASES,
            derivatives_by_differences: false,
        }
    }
    /// Says the law has no steady state (θ decays at every V > 0).
    pub fn no_steady_state(mut self) -> Self {
        self.no_steady_state = true;
        self
    }
    /// Says the law's derivatives are central differences of its rate (a Python function).
    pub fn derivatives_by_differences(mut self) -> Self {
        self.derivatives_by_differences = true;
        self
    }
    /// Claims θ_ss = s·Dc/V.
    pub fn steady_state_dc_over_v(mut self) -> Self {
        self.steady_state_dc_over_v = true;
        self
    }
    /// Names a parameter of the law that is a velocity (µm/s).
    pub fn velocity_parameter(mut self, name: &'static str) -> Self {
        self.velocity_parameters.push(name);
        self
    }
    /// Names a parameter of the law that is a length (µm).
    pub fn length_parameter(mut self, name: &'static str) -> Self {
        self.length_parameters.push(name);
        self
    }
    /// Ranges other than the default.
    pub fn ranges(mut self, ranges: Ranges) -> Self {
        self.ranges = ranges;
        self
    }
    /// Inputs per pointwise property.
    pub fn cases(mut self, cases: u32) -> Self {
        self.cases = cases.max(1);
        self
    }
    /// Whether the law claims no velocity scale of its own (the V_i·t identity applies).
    pub fn scale_free(&self) -> bool {
        self.velocity_parameters.is_empty()
    }
}

/// The properties the kit checks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    /// Finite values over the ranges.
    Finite,
    /// The log-form rate equals the rate over θ.
    LogForm,
    /// The Jacobian equals dual numbers and central differences.
    Jacobian,
    /// The steady state is an attracting root.
    SteadyState,
    /// Invariance under a change of time unit.
    TimeScaling,
    /// Invariance under a change of length unit.
    UnitScaling,
    /// Bhattacharya et al.'s V_i·t identity for N-state models.
    ViTIdentity,
    /// A shifted clock changes nothing.
    TimeShift,
    /// Explicit and implicit integrators agree.
    IntegratorsAgree,
    /// Each listed parameter can be set and reads back.
    ParameterRoundTrip,
    /// An exact parameter derivative equals central differences.
    ParameterDerivative,
}

impl Property {
    /// Every property, in the order checked.
    pub const ALL: [Property; 11] = [
        Property::Finite,
        Property::LogForm,
        Property::Jacobian,
        Property::SteadyState,
        Property::TimeScaling,
        Property::UnitScaling,
        Property::ViTIdentity,
        Property::TimeShift,
        Property::IntegratorsAgree,
        Property::ParameterRoundTrip,
        Property::ParameterDerivative,
    ];

    /// The property's name.
    pub fn text(&self) -> &'static str {
        match self {
            Property::Finite => "finite",
            Property::LogForm => "log_form",
            Property::Jacobian => "jacobian",
            Property::SteadyState => "steady_state",
            Property::TimeScaling => "time_scaling",
            Property::UnitScaling => "unit_scaling",
            Property::ViTIdentity => "vi_t_identity",
            Property::TimeShift => "time_shift",
            Property::IntegratorsAgree => "integrators_agree",
            Property::ParameterRoundTrip => "parameter_round_trip",
            Property::ParameterDerivative => "parameter_derivative",
        }
    }
}

/// How one property came out.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// Held on this many inputs.
    Passed(u32),
    /// Not applicable to this law, and why.
    Skipped(&'static str),
}

/// Every property checked and its outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// The law's name.
    pub law: String,
    /// Outcome per property.
    pub outcomes: Vec<(Property, Outcome)>,
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "law `{}` conforms:", self.law)?;
        for (p, o) in &self.outcomes {
            match o {
                Outcome::Passed(n) => writeln!(f, "  {}: passed ({n} inputs)", p.text())?,
                Outcome::Skipped(why) => writeln!(f, "  {}: skipped ({why})", p.text())?,
            }
        }
        Ok(())
    }
}

/// The first property that failed: which, why, and the smallest input proptest found.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// The law's name.
    pub law: String,
    /// The property.
    pub property: Property,
    /// What went wrong.
    pub reason: String,
    /// The shrunk input that shows it.
    pub input: String,
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "law `{}` fails `{}`: {}\n  minimal input: {}",
            self.law,
            self.property.text(),
            self.reason,
            self.input
        )
    }
}

impl std::error::Error for Failure {}

/// Checks `law` against every property; the first failure stops the check.
pub fn check<L: StateLaw>(law: &L, claims: &Claims) -> Result<Report, Failure> {
    let name = law.name();
    let mut outcomes = vec![];
    for p in Property::ALL {
        let outcome = match p {
            Property::Finite
            | Property::LogForm
            | Property::Jacobian
            | Property::SteadyState
            | Property::TimeScaling
            | Property::UnitScaling
            | Property::ParameterRoundTrip
            | Property::ParameterDerivative => pointwise::run(p, law, claims),
            Property::ViTIdentity | Property::TimeShift | Property::IntegratorsAgree => solver::run(p, law, claims),
        };
        match outcome {
            Ok(o) => outcomes.push((p, o)),
            Err((reason, input)) => return Err(Failure { law: name, property: p, reason, input }),
        }
    }
    Ok(Report { law: name, outcomes })
}

/// [`check`], panicking with the failure's text: for a law's own `#[test]`.
pub fn assert_conforms<L: StateLaw>(law: &L, claims: &Claims) -> Report {
    check(law, claims).unwrap_or_else(|f| panic!("{f}"))
}

/// Runs one property over `cases` inputs of `strategy`, deterministically; the error carries
/// the reason and the shrunk input.
pub(crate) fn run_cases<S>(
    cases: u32,
    strategy: &S,
    test: impl Fn(S::Value) -> Result<(), String>,
) -> Result<Outcome, (String, String)>
where
    S: proptest::strategy::Strategy,
    S::Value: fmt::Debug,
{
    let config = Config { cases, failure_persistence: None, max_shrink_iters: 256, ..Config::default() };
    let rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
    let mut runner = TestRunner::new_with_rng(config, rng);
    match runner.run(strategy, |v| test(v).map_err(TestCaseError::fail)) {
        Ok(()) => Ok(Outcome::Passed(cases)),
        Err(TestError::Fail(reason, input)) => Err((reason.message().to_string(), format!("{input:?}"))),
        Err(TestError::Abort(reason)) => Err((format!("aborted: {}", reason.message()), String::new())),
    }
}
