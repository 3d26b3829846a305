//! # rsf-solvers — integrators and the forward solver
//!
//! A [`Problem`] (model + loading + output times), an algorithm ([`Auto`], the default, which
//! runs [`Vern6`] while the problem is non-stiff and [`Rodas5P`] where it is stiff; or any of
//! them alone, or [`Dopri5`] / [`Rodas4`] for comparison — all implementing [`Integrator`]) and
//! a [`Solution`] are separate values: swap the algorithm without touching the problem.
//!
//! The integrators are hand-written (docs/solvers.md says why): the systems have 3–10
//! unknowns, so a stack-allocated, monomorphised stepper is the fastest possible; every
//! load-point velocity discontinuity is a hard stop; output comes from dense output, never
//! from shortened steps; failures carry the time and values reached.
//!
//! [`protocol`] reads the TOML protocol files of `rsf simulate`.
//!
//! A velocity step 1 → 10 µm/s (Slip law, the parameters of Bhattacharya et al. 2022) under
//! both integrators: friction jumps by about a ln 10, then decays over a few Dc of slip to the
//! new steady state μ_ss(V) = μ0 + (a − b) ln(V/V0).
//!
//! ```
//! use rsf_core::{Loading, Model, Segment, StateVariable};
//! use rsf_laws::Slip;
//! use rsf_solvers::{Dopri5, Problem, Rodas4, solve};
//!
//! let (a, b) = (0.013, 0.016);
//! let model = Model::new(0.6, 1.0, a, 0.065).with_state(StateVariable::new(Slip, b, 2.07)); // k 1/µm, Dc µm
//! let loading = Loading::Segments(vec![
//!     Segment::for_displacement(1.0, 10.0),  // 10 µm at 1 µm/s
//!     Segment::for_displacement(10.0, 60.0), // 60 µm at 10 µm/s
//! ]);
//! let problem = Problem::new(model.clone(), loading, 1.0, 0.01); // start in steady state at 1 µm/s, output every 0.01 s
//! let explicit = solve(&problem, &Dopri5::new(1e-9, 1e-12)).unwrap();
//! let implicit = solve(&problem, &Rodas4::new(1e-9, 1e-12)).unwrap();
//!
//! let peak = explicit.mu.iter().cloned().fold(f64::MIN, f64::max);
//! assert!(peak - 0.6 > 0.5 * a * 10f64.ln()); // the direct effect, reduced by the finite stiffness
//! let mu_end = *explicit.mu.last().unwrap();
//! let mu_ss = model.steady_state_friction(10.0).unwrap(); // 0.6 + (a − b) ln 10
//! assert!((mu_end - mu_ss).abs() < 1e-6);
//! assert!((mu_end - implicit.mu.last().unwrap()).abs() < 1e-8);
//! ```
#![forbid(unsafe_code)]

mod auto;
mod dopri5;
mod erk;
mod large;
mod lu;
mod ode;
pub mod protocol;
mod record;
mod rodas4;
mod rodas5p;
mod rosenbrock;
mod route;
mod run_away;
mod solution;
mod solve;
mod tableau;
mod tsit5;
mod vern6;
mod watch;

pub use auto::{Auto, AutoDopri5};
pub use dopri5::Dopri5;
pub use large::{Flow, LargeSystem, LargeTsit5};
pub use ode::{Integrated, IntegrationError, Integrator, OdeSystem, StepStats, Tolerances};
pub use rodas4::Rodas4;
pub use rodas5p::Rodas5P;
pub use run_away::RunAway;
pub use solution::Solution;
pub use solve::{
    MAX_SLIP_RATE, MAX_STATES, OutputTimes, Problem, SolveError, drive, output_times, solve, solve_friction,
};
pub use tsit5::Tsit5;
pub use vern6::Vern6;
pub use watch::{SlipEvent, WatchOptions};

/// The built-in methods, for run-time selection (e.g. from a protocol file).
#[derive(Clone, Copy, Debug)]
pub enum Method {
    /// [`Auto`]: Vern6 while non-stiff, Rodas5P where stiff (the default).
    Auto(Auto),
    /// [`Tsit5`].
    Tsit5(Tsit5),
    /// [`Vern6`].
    Vern6(Vern6),
    /// [`Dopri5`].
    Dopri5(Dopri5),
    /// [`Rodas5P`].
    Rodas5P(Rodas5P),
    /// [`Rodas4`].
    Rodas4(Rodas4),
}

impl Method {
    /// The names [`from_name`](Self::from_name) accepts, besides the aliases `explicit` (Tsit5)
    /// and `implicit` (Rodas5P).
    pub const NAMES: [&'static str; 6] = ["auto", "tsit5", "vern6", "dopri5", "rodas5p", "rodas4"];

    /// A method by name with tolerances; `None` for an unknown name.
    pub fn from_name(name: &str, rtol: f64, atol: f64) -> Option<Self> {
        Some(match name {
            "auto" => Self::Auto(Auto::new(rtol, atol)),
            "tsit5" | "explicit" => Self::Tsit5(Tsit5::new(rtol, atol)),
            "vern6" => Self::Vern6(Vern6::new(rtol, atol)),
            "dopri5" => Self::Dopri5(Dopri5::new(rtol, atol)),
            "rodas5p" | "implicit" => Self::Rodas5P(Rodas5P::new(rtol, atol)),
            "rodas4" => Self::Rodas4(Rodas4::new(rtol, atol)),
            _ => return None,
        })
    }
    /// Its name.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Auto(m) => m.name(),
            Self::Tsit5(m) => m.name(),
            Self::Vern6(m) => m.name(),
            Self::Dopri5(m) => m.name(),
            Self::Rodas5P(m) => m.name(),
            Self::Rodas4(m) => m.name(),
        }
    }
    /// Its tolerances.
    pub fn tolerances(&self) -> Tolerances {
        match self {
            Self::Auto(m) => m.tol,
            Self::Tsit5(m) => m.tol,
            Self::Vern6(m) => m.tol,
            Self::Dopri5(m) => m.tol,
            Self::Rodas5P(m) => m.tol,
            Self::Rodas4(m) => m.tol,
        }
    }
    /// Solves `problem` with this method.
    pub fn solve(&self, problem: &Problem) -> Result<Solution, SolveError> {
        match self {
            Self::Auto(m) => solve(problem, m),
            Self::Tsit5(m) => solve(problem, m),
            Self::Vern6(m) => solve(problem, m),
            Self::Dopri5(m) => solve(problem, m),
            Self::Rodas5P(m) => solve(problem, m),
            Self::Rodas4(m) => solve(problem, m),
        }
    }
}
