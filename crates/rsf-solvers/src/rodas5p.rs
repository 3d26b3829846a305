//! Rodas5P: an 8-stage, L-stable, stiffly accurate Rosenbrock method of order 5(4) with a
//! 4th-order dense output (Steinebach 2023), using the system's exact Jacobian: the implicit
//! default of the automatic method.
//! Coefficients in `tableau/rodas5p.rs`; the step loop is `rosenbrock.rs`, shared by the
//! Rosenbrock methods.

use crate::ode::{IntegrationError, OdeSystem, Reached, StepStats};
use crate::rosenbrock::integrate;
use crate::tableau::rodas5p::RODAS5P;
use nalgebra::SVector;

crate::ode::integrator!(
    /// Implicit (linearly implicit) Rodas5P with exact Jacobian. For stiff problems: very stiff
    /// machines, tiny Dc, steps to fast slip rates, radiation-damped stick-slip, multi-state
    /// laws with widely separated Dc.
    Rodas5P,
    "rodas5p",
    run
);

/// One piece with the shared Rosenbrock stepper.
fn run<const D: usize, S: OdeSystem<D>>(
    m: &Rodas5P,
    sys: &S,
    piece: (f64, SVector<f64, D>, f64, f64),
    t_out: &[f64],
    out: &mut impl FnMut(f64, &SVector<f64, D>),
    stats: &mut StepStats,
) -> Result<Reached<D>, IntegrationError> {
    integrate(&RODAS5P, (&m.tol, m.max_steps), sys, piece, t_out, out, stats, false)
}
