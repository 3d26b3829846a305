//! Rodas4: a 6-stage, L-stable, stiffly accurate Rosenbrock method of order 4(3) with a
//! 3rd-order dense output, using the system's exact Jacobian (kept beside Rodas5P for
//! comparison; its stage order 1 costs order on Prothero–Robinson problems at tight tolerance).
//! Coefficients in `tableau/rodas4.rs`; the step loop is `rosenbrock.rs`, shared by the
//! Rosenbrock methods.

crate::ode::integrator!(
    /// Implicit (linearly implicit) Rodas4 with exact Jacobian.
    Rodas4,
    "rodas4",
    rosenbrock crate::tableau::rodas4::RODAS4
);
