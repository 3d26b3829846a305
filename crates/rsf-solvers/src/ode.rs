//! What integrators and problems share: the [`OdeSystem`] and [`Integrator`] traits.

use nalgebra::{SMatrix, SVector};
use serde::Serialize;
use thiserror::Error;

/// An ODE system `dy/dt = f(t, y)` of fixed dimension `D`. Most systems are autonomous (the
/// spring-slider at constant normal stress: time enters only through the piece boundaries at
/// which the caller restarts the integrator) and ignore `t`; a normal-stress ramp makes the
/// spring-slider depend on it.
pub trait OdeSystem<const D: usize> {
    /// `f(t, y)`.
    fn rhs(&self, t: f64, y: &SVector<f64, D>) -> SVector<f64, D>;

    /// `f(t, y)` and the exact Jacobian `∂f/∂y` (required by implicit methods only).
    fn rhs_and_jacobian(&self, t: f64, y: &SVector<f64, D>) -> (SVector<f64, D>, SMatrix<f64, D, D>);

    /// `∂f/∂t` for a system that depends on time (used by the Rosenbrock methods); `None`, the
    /// default, declares the system autonomous.
    fn time_derivative(&self, t: f64, y: &SVector<f64, D>) -> Option<SVector<f64, D>> {
        let _ = (t, y);
        None
    }

    /// An upper bound on the spectral radius ρ(J) of `jac` = ∂f/∂y, for the automatic
    /// method's test whether an explicit step would be stable. Default: the largest row sum
    /// of |J| (exact enough for the small dense systems here); a system whose Jacobian has
    /// structure (block triangular) can bound it tighter.
    fn spectral_radius_bound(&self, jac: &SMatrix<f64, D, D>) -> f64 {
        jac.row_iter().map(|r| r.abs().sum()).fold(0.0, f64::max)
    }

    /// The error scale of component `i`: an error equal to the scale is just acceptable.
    /// Default: `atol + rtol·max(|y0_i|, |y1_i|)` (Hairer & Wanner).
    fn error_scale(&self, i: usize, y0: f64, y1: f64, tol: &Tolerances) -> f64 {
        let _ = i;
        tol.atol + tol.rtol * y0.abs().max(y1.abs())
    }

    /// Called after each accepted step; an `Err` stops the integration with that message
    /// (e.g. a slip rate beyond any physical meaning).
    fn check(&self, y: &SVector<f64, D>) -> Result<(), String> {
        let _ = y;
        Ok(())
    }

    /// Called after each accepted step ending at time `t` with state `y` (the integrators call
    /// this, not [`check`](Self::check)); the default is `check(y)`. A system that watches
    /// every step (peak slip rates, events) overrides it.
    fn accepted(&self, t: f64, y: &SVector<f64, D>) -> Result<(), String> {
        let _ = t;
        self.check(y)
    }
}

/// Relative and absolute tolerances.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
}

impl Tolerances {
    /// Refuses tolerances that no step control can meet, saying what is allowed: 0 < rtol < 1,
    /// and atol > 0 (µm of slip: with atol = 0 the slip's error has no scale where slip is zero,
    /// at the start of every run).
    pub fn check(&self) -> Result<(), String> {
        use rsf_record::short_num;
        if !(self.rtol > 0.0 && self.rtol < 1.0) {
            return Err(format!("rtol = {} must satisfy 0 < rtol < 1 (e.g. 1e-9)", short_num(self.rtol)));
        }
        if !(self.atol > 0.0 && self.atol.is_finite()) {
            return Err(format!(
                "atol = {} must be positive and finite (µm of slip, e.g. 1e-12: the slip's error needs a scale where slip is zero)",
                short_num(self.atol)
            ));
        }
        Ok(())
    }
}

/// Work counters returned with every solution.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct StepStats {
    /// Accepted steps.
    pub accepted: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
    /// Jacobian evaluations.
    pub jacobian_evals: u64,
    /// LU decompositions.
    pub lu_decompositions: u64,
    /// Switches of the automatic method from explicit to implicit (stiffness detected).
    pub to_implicit: u64,
    /// …and back (the stretch became non-stiff).
    pub to_explicit: u64,
}

impl std::ops::AddAssign for StepStats {
    fn add_assign(&mut self, o: Self) {
        self.accepted += o.accepted;
        self.rejected += o.rejected;
        self.rhs_evals += o.rhs_evals;
        self.jacobian_evals += o.jacobian_evals;
        self.lu_decompositions += o.lu_decompositions;
        self.to_implicit += o.to_implicit;
        self.to_explicit += o.to_explicit;
    }
}

/// Why an integration stopped early. Every variant carries the time reached.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum IntegrationError {
    /// The step size fell below what floating point can resolve at `t`.
    #[error("step size underflow at t = {t} s (h = {h:e} s)")]
    StepSizeUnderflow {
        /// Time, s.
        t: f64,
        /// Step size, s.
        h: f64,
    },
    /// The step budget ran out.
    #[error(
        "more than {steps} steps at t = {t} s without reaching the end; the problem may be stiff (try the implicit method)"
    )]
    TooManySteps {
        /// Time, s.
        t: f64,
        /// Step budget.
        steps: u64,
    },
    /// The system's [`OdeSystem::check`] stopped the integration.
    #[error("stopped at t = {t} s: {reason}")]
    Stopped {
        /// Time, s.
        t: f64,
        /// The system's message.
        reason: String,
    },
    /// The Jacobian matrix `I/(hγ) − J` was singular.
    #[error("singular iteration matrix at t = {t} s")]
    Singular {
        /// Time, s.
        t: f64,
    },
}

/// End state of one call to [`Integrator::integrate`].
#[derive(Clone, Copy, Debug)]
pub struct Integrated<const D: usize> {
    /// State at the end time.
    pub y: SVector<f64, D>,
    /// Suggested first step for a following piece, s.
    pub h_next: f64,
}

/// How a stepper left a piece: at its end, or early at an accepted step because the automatic
/// method should change stepper there.
pub(crate) enum Reached<const D: usize> {
    /// The end of the piece.
    End(Integrated<D>),
    /// An accepted step at `t` with state `y` and proposed next step `h`.
    Switch {
        /// Time, s.
        t: f64,
        /// State.
        y: SVector<f64, D>,
        /// Proposed next step, s.
        h: f64,
    },
}

/// Declares a built-in method: the struct (tolerances and step budget), `new(rtol, atol)` and
/// its [`Integrator`] implementation, which hands each piece to a stepper: `explicit` (the
/// shared explicit stepper with the type's own [`ExplicitPair`](crate::erk::ExplicitPair)
/// coefficients), `rosenbrock TABLEAU`, or a function `run(&self, sys, (t0, y0, t1, h0), t_out,
/// out, stats)` returning [`Reached`].
macro_rules! integrator {
    ($(#[$doc:meta])* $ty:ident, $name:expr, explicit) => {
        $crate::ode::integrator!(@define $(#[$doc])* $ty, $name, |m, sys, piece, t_out, out, stats|
            $crate::erk::integrate::<$ty, D, S>((&m.tol, m.max_steps), sys, piece, t_out, out, stats, false));
    };
    ($(#[$doc:meta])* $ty:ident, $name:expr, rosenbrock $tab:path) => {
        $crate::ode::integrator!(@define $(#[$doc])* $ty, $name, |m, sys, piece, t_out, out, stats|
            $crate::rosenbrock::integrate(&$tab, (&m.tol, m.max_steps), sys, piece, t_out, out, stats, false));
    };
    ($(#[$doc:meta])* $ty:ident, $name:expr, $run:path) => {
        $crate::ode::integrator!(@define $(#[$doc])* $ty, $name, |m, sys, piece, t_out, out, stats|
            $run(m, sys, piece, t_out, out, stats));
    };
    (@define $(#[$doc:meta])* $ty:ident, $name:expr,
        |$m:ident, $sys:ident, $piece:ident, $t_out:ident, $out:ident, $stats:ident| $call:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug)]
        pub struct $ty {
            /// Tolerances.
            pub tol: $crate::ode::Tolerances,
            /// Step budget per [`integrate`]($crate::Integrator::integrate) call.
            pub max_steps: u64,
        }

        impl $ty {
            /// With relative and absolute tolerances.
            pub fn new(rtol: f64, atol: f64) -> Self {
                Self { tol: $crate::ode::Tolerances { rtol, atol }, max_steps: 2_000_000 }
            }
        }

        impl $crate::ode::Integrator for $ty {
            fn name(&self) -> &'static str {
                $name
            }
            fn tolerances(&self) -> $crate::ode::Tolerances {
                self.tol
            }
            fn integrate<const D: usize, S: $crate::ode::OdeSystem<D>>(
                &self,
                $sys: &S,
                t0: f64,
                y0: nalgebra::SVector<f64, D>,
                t1: f64,
                h0: f64,
                $t_out: &[f64],
                $out: &mut impl FnMut(f64, &nalgebra::SVector<f64, D>),
                $stats: &mut $crate::ode::StepStats,
            ) -> Result<$crate::ode::Integrated<D>, $crate::ode::IntegrationError> {
                let ($m, $piece) = (self, (t0, y0, t1, h0));
                match $call? {
                    $crate::ode::Reached::End(i) => Ok(i),
                    $crate::ode::Reached::Switch { .. } => unreachable!("only the automatic method switches"),
                }
            }
        }
    };
}
pub(crate) use integrator;

/// A time-stepping method. The same problem runs unchanged under any integrator.
///
/// Implementations: [`Auto`](crate::Auto) (the default: Vern6 while non-stiff, Rodas5P where
/// stiff), [`Vern6`](crate::Vern6), [`Tsit5`](crate::Tsit5) and [`Dopri5`](crate::Dopri5) (explicit), and
/// [`Rodas5P`](crate::Rodas5P) and [`Rodas4`](crate::Rodas4) (implicit, exact Jacobian).
pub trait Integrator {
    /// Method name for output, e.g. `"dopri5"`.
    fn name(&self) -> &'static str;

    /// Tolerances in use.
    fn tolerances(&self) -> Tolerances;

    /// Integrates from `(t0, y0)` to `t1` (`t1 > t0`), landing on `t1` exactly. For every time
    /// in `t_out` (sorted, within `(t0, t1]`) calls `out(t, y(t))` from the method's dense
    /// output, never by shortening steps. `h0 > 0` proposes a first step (e.g. the last step
    /// of the previous piece); `h0 <= 0` lets the method choose.
    #[allow(clippy::too_many_arguments)]
    fn integrate<const D: usize, S: OdeSystem<D>>(
        &self,
        sys: &S,
        t0: f64,
        y0: SVector<f64, D>,
        t1: f64,
        h0: f64,
        t_out: &[f64],
        out: &mut impl FnMut(f64, &SVector<f64, D>),
        stats: &mut StepStats,
    ) -> Result<Integrated<D>, IntegrationError>;
}

/// Mean square of `err_i / scale_i` over the components (Hairer & Wanner II, IV.4). The scales
/// depend on `y0` and `y1` only, so their reciprocals can be formed before the error itself is
/// known (off the latency chain of an explicit step).
#[inline(always)]
pub(crate) fn mean_square_error<const D: usize, S: OdeSystem<D>>(
    sys: &S,
    err: &SVector<f64, D>,
    y0: &SVector<f64, D>,
    y1: &SVector<f64, D>,
    tol: &Tolerances,
) -> f64 {
    let mut s = 0.0;
    for i in 0..D {
        let e = err[i] * (1.0 / sys.error_scale(i, y0[i], y1[i], tol));
        s += e * e;
    }
    s * (1.0 / D as f64)
}

/// RMS error norm of `err` against the component scales; a non-finite norm gives +∞.
#[inline]
pub(crate) fn error_norm<const D: usize, S: OdeSystem<D>>(
    sys: &S,
    err: &SVector<f64, D>,
    y0: &SVector<f64, D>,
    y1: &SVector<f64, D>,
    tol: &Tolerances,
) -> f64 {
    let n = mean_square_error(sys, err, y0, y1, tol).sqrt();
    if n.is_finite() { n } else { f64::INFINITY }
}

/// Hairer's starting step size heuristic (Solving ODEs I, II.4), one extra RHS evaluation.
pub(crate) fn initial_step<const D: usize, S: OdeSystem<D>>(
    sys: &S,
    t0: f64,
    y0: &SVector<f64, D>,
    f0: &SVector<f64, D>,
    span: f64,
    order: i32,
    tol: &Tolerances,
    stats: &mut StepStats,
) -> f64 {
    let mut dnf = 0.0;
    let mut dny = 0.0;
    for i in 0..D {
        let sk = sys.error_scale(i, y0[i], y0[i], tol);
        dnf += (f0[i] / sk).powi(2);
        dny += (y0[i] / sk).powi(2);
    }
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 { 1e-6 } else { (dny / dnf).sqrt() * 0.01 };
    // ‖y0‖ means nothing for log variables (ln V = 0 at V = 1 µm/s): keep the first guess
    // from collapsing to round-off so that the curvature estimate below can set the step —
    // round-off of t0 itself: a record whose clock starts at 10⁶ s resolves no step below
    // ~4e-9 s (found by rsf-testkit's `time_shift`)
    h = h.max(1e-9 * span).max(1e3 * h_min(t0)).min(span);
    let y1 = y0 + f0 * h;
    let f1 = sys.rhs(t0 + h, &y1);
    stats.rhs_evals += 1;
    let mut der2 = 0.0;
    for i in 0..D {
        let sk = sys.error_scale(i, y0[i], y0[i], tol);
        der2 += ((f1[i] - f0[i]) / sk).powi(2);
    }
    let der2 = der2.sqrt() / h;
    let der12 = der2.max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 { (h * 1e-3).max(1e-6) } else { (0.01 / der12).powf(1.0 / (order as f64 + 1.0)) };
    (100.0 * h).min(h1).max(MIN_STEPS_RESOLVED * h_min(t0)).min(span)
}

/// The first step is at least this many times the smallest step `t0` resolves.
const MIN_STEPS_RESOLVED: f64 = 10.0;

/// Clips a proposed step `h` at time `t` so that the integration lands exactly on `t1`;
/// returns the step and whether it is the last one, or an underflow error.
#[inline]
pub(crate) fn clip_step(t: f64, h: f64, t1: f64, span: f64) -> Result<(f64, bool), IntegrationError> {
    let last = t + h >= t1 - 1e-12 * span.max(h);
    let h = if last { t1 - t } else { h };
    if h < h_min(t) {
        return Err(IntegrationError::StepSizeUnderflow { t, h });
    }
    Ok((h, last))
}

/// Emits every requested output time in `(t, t_new]` after an accepted step: `y1` itself at
/// `t_new`, the dense output `interp(s)` (s = (t_out − t)/h) in between. `interp` is built
/// only when an output time lies strictly inside the step.
#[inline]
pub(crate) fn emit_dense<const D: usize, F: Fn(f64) -> SVector<f64, D>>(
    t_out: &[f64],
    next: &mut usize,
    (t, h, t_new): (f64, f64, f64),
    y1: &SVector<f64, D>,
    interp: impl FnOnce() -> F,
    out: &mut impl FnMut(f64, &SVector<f64, D>),
) {
    // times strictly inside the step come from the interpolant, built only if there are any
    // (Vern6's costs a stage); a time on the step's end is y1 itself. The per-row loop is the
    // whole cost of a solve with an output row per data sample, so it stays branch-light.
    // most steps hold no output time: one comparison decides that before any search
    if t_out.get(*next).is_none_or(|&to| to > t_new) {
        return;
    }
    let inside = t_out[*next..].partition_point(|&to| to < t_new);
    if inside > 0 {
        let f = interp();
        for &to in &t_out[*next..*next + inside] {
            out(to, &f((to - t) / h));
        }
        *next += inside;
    }
    if *next < t_out.len() && t_out[*next] == t_new {
        out(t_new, y1);
        *next += 1;
    }
}

/// Smallest step allowed at time `t`.
#[inline]
pub(crate) fn h_min(t: f64) -> f64 {
    16.0 * f64::EPSILON * t.abs().max(1e-3)
}

#[cfg(test)]
#[path = "ode_tests.rs"]
mod tests;
