//! Rodas5P: an 8-stage, L-stable, stiffly accurate Rosenbrock method of order 5(4) with a
//! 4th-order dense output (Steinebach 2023), using the system's exact Jacobian: the implicit
//! default of the automatic method.
//! Coefficients in `tableau/rodas5p.rs`; the step loop is `rosenbrock.rs`, shared by the
//! Rosenbrock methods.

crate::ode::integrator!(
    /// Implicit (linearly implicit) Rodas5P with exact Jacobian. For stiff problems: very stiff
    /// machines, tiny Dc, steps to fast slip rates, radiation-damped stick-slip, multi-state
    /// laws with widely separated Dc.
    Rodas5P,
    "rodas5p",
    rosenbrock crate::tableau::rodas5p::RODAS5P
);
