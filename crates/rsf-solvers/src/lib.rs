//! # rsf-solvers — integrators and the forward solver
//!
//! A [`Problem`] (model + loading + output times), an algorithm ([`Dopri5`] explicit or
//! [`Rodas4`] implicit, both implementing [`Integrator`]) and a [`Solution`] are separate
//! values: swap the algorithm without touching the problem.
//!
//! The integrators are hand-written (docs/solvers.md says why): the systems have 3–10
//! unknowns, so a stack-allocated, monomorphised stepper is the fastest possible; every
//! load-point velocity discontinuity is a hard stop; output comes from dense output, never
//! from shortened steps; failures carry the time and values reached.
//!
//! [`protocol`] reads the TOML protocol files of `rsf simulate`.

mod dopri5;
mod ode;
pub mod protocol;
mod rodas4;
mod solve;

pub use dopri5::Dopri5;
pub use ode::{Integrated, IntegrationError, Integrator, OdeSystem, StepStats, Tolerances};
pub use rodas4::Rodas4;
pub use solve::{MAX_STATES, OutputTimes, Problem, Solution, SolveError, drive, output_times, solve, solve_friction};

/// The two built-in methods, for run-time selection (e.g. from a protocol file).
#[derive(Clone, Copy, Debug)]
pub enum Method {
    /// [`Dopri5`].
    Explicit(Dopri5),
    /// [`Rodas4`].
    Implicit(Rodas4),
}

impl Method {
    /// `"explicit"` or `"implicit"` with tolerances.
    pub fn from_name(name: &str, rtol: f64, atol: f64) -> Option<Self> {
        match name {
            "explicit" | "dopri5" => Some(Self::Explicit(Dopri5::new(rtol, atol))),
            "implicit" | "rodas4" => Some(Self::Implicit(Rodas4::new(rtol, atol))),
            _ => None,
        }
    }
    /// Solves `problem` with this method.
    pub fn solve(&self, problem: &Problem) -> Result<Solution, SolveError> {
        match self {
            Self::Explicit(m) => solve(problem, m),
            Self::Implicit(m) => solve(problem, m),
        }
    }
}
