//! Rodas4: a 6-stage, L-stable, stiffly accurate Rosenbrock method of order 4(3) with a
//! 3rd-order dense output, using the system's exact Jacobian (kept beside Rodas5P for
//! comparison; its stage order 1 costs order on Prothero–Robinson problems at tight tolerance).
//! Coefficients in `tableau/rodas4.rs`; the step loop is `rosenbrock.rs`, shared by the
//! Rosenbrock methods.

use crate::ode::{IntegrationError, OdeSystem, Reached, StepStats};
use crate::rosenbrock::integrate;
use crate::tableau::rodas4::RODAS4;
use nalgebra::SVector;

crate::ode::integrator!(
    /// Implicit (linearly implicit) Rodas4 with exact Jacobian.
    Rodas4,
    "rodas4",
    run
);

/// One piece with the shared Rosenbrock stepper.
fn run<const D: usize, S: OdeSystem<D>>(
    m: &Rodas4,
    sys: &S,
    piece: (f64, SVector<f64, D>, f64, f64),
    t_out: &[f64],
    out: &mut impl FnMut(f64, &SVector<f64, D>),
    stats: &mut StepStats,
) -> Result<Reached<D>, IntegrationError> {
    integrate(&RODAS4, (&m.tol, m.max_steps), sys, piece, t_out, out, stats, false)
}
