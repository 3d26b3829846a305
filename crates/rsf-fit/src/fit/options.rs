//! Fit settings, the work budget and errors.

use rsf_core::DynStateLaw;
use rsf_solvers::SolveError;
use serde::Serialize;
use std::sync::Arc;

/// Step budget per piece for forward solves inside fits: a trial point that needs more (a
/// very stiff corner of parameter space) fails quickly and LM steps back.
pub const FIT_MAX_STEPS: u64 = 200_000;

/// What drives the forward model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadingMode {
    /// The measured load-point history (piecewise linear between samples).
    Record,
    /// The idealised protocol detected by segmentation (constant velocities).
    Protocol,
}

rsf_core::vocabulary!(LoadingMode, "loading", { Record => "record", Protocol => "protocol" });

/// How samples are weighted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Weighting {
    /// Each segment counts equally (weight ∝ 1/N_samples of the segment).
    EqualSegments,
    /// Every sample counts equally.
    Uniform,
}

rsf_core::vocabulary!(Weighting, "weights", { EqualSegments => "equal-segments" | "equal", Uniform => "uniform" });

/// Whether a record's normal stress drives the forward model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NormalStressMode {
    /// Drive σ(t) from the record's normal-stress column when it varies by more than
    /// [`NORMAL_STRESS_VARIES`] of its median; constant otherwise.
    Auto,
    /// Constant normal stress, whatever the record holds.
    Constant,
    /// Always drive σ(t) from the record's normal-stress column.
    Record,
}

rsf_core::vocabulary!(NormalStressMode, "normal-stress mode", {
    Auto => "auto",
    Record => "record",
    Constant => "constant",
});

/// A normal stress whose range is below this fraction of its median counts as constant in
/// [`NormalStressMode::Auto`]: servo noise and drift of a nominally constant σ stay well
/// below 2 %, while the normal-stress steps of lab protocols are 5–100 %.
pub const NORMAL_STRESS_VARIES: f64 = 0.02;

/// Which Linker–Dieterich coefficients a fit frees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AlphaFit {
    /// α fixed (at 0 unless given by `initial` or `fix`).
    Fixed,
    /// One α shared by all state variables.
    Shared,
    /// One α per state variable.
    PerState,
}

rsf_core::vocabulary!(AlphaFit, "alpha fit", { Fixed => "fixed", Shared => "shared", PerState => "per-state" });

/// How a fit's standard errors and 95 % intervals treat the residuals' noise.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Uncertainty {
    /// Under the noise model fitted to the fit's own residuals — white, AR(1) and power-law
    /// drift, in time (`rsf-noise`, the model the diagnosis scores with): the sandwich
    /// H⁻¹ JᵀW²ΣW²J H⁻¹. Lab residuals are correlated; intervals that assume otherwise are
    /// too narrow by the square root of the correlation length in samples.
    NoiseModel,
    /// Independent residuals of one σ, σ² from the residuals: H⁻¹ JᵀW⁴J H⁻¹ σ².
    White,
}

rsf_core::vocabulary!(Uncertainty, "uncertainty", { NoiseModel => "noise-model", White => "white" });

/// Fit settings.
#[derive(Clone, Debug)]
pub struct FitOptions {
    /// One law per state variable.
    pub laws: Vec<Arc<dyn DynStateLaw>>,
    /// Stiffness k, 1/µm (initial value when fitted).
    pub stiffness: f64,
    /// Fit k as well.
    pub fit_stiffness: bool,
    /// Fit a slip trend g (friction per µm of slip) as well.
    pub fit_slip_trend: bool,
    /// Fit the rate dependence a₁ of the direct effect (`a_slope`: ∂f/∂ln V = a + a₁ ln(V/V0))
    /// as well; it starts at 0 unless given in `initial`.
    pub fit_a_slope: bool,
    /// The slip rates (µm/s, low and high) over which the direct effect's local slope
    /// a + a₁ ln(V/V0) must stay at least [`DIRECT_SLOPE_FLOOR`](super::DIRECT_SLOPE_FLOOR) of a:
    /// a trial beyond is rejected before it is solved. `None`: no such check (a slope that
    /// nears zero on the model's path makes the solve stiff to a crawl, and past zero the
    /// model has no slip rate).
    pub a_slope_range: Option<(f64, f64)>,
    /// Constraints, e.g. `a-b=-0.003`, `dc=10`.
    pub fix: Vec<super::Constraint>,
    /// A friction offset per segment.
    pub mu0_per_segment: bool,
    /// Use only the first `window_um` µm of load-point travel of each segment (and the last of
    /// the first segment); holds are used whole.
    pub window_um: Option<f64>,
    /// Time windows (s, inclusive) whose samples are left out of the fit (the diagnosis leaves
    /// out samples whose model value its break-time uncertainty makes unreliable).
    pub exclude: Vec<(f64, f64)>,
    /// Sample weights.
    pub weighting: Weighting,
    /// How the standard errors and intervals treat the residuals' noise (default: under the
    /// fitted noise model).
    pub uncertainty: Uncertainty,
    /// What drives the model.
    pub loading: LoadingMode,
    /// Integrator tolerance.
    pub rtol: f64,
    /// LM iteration limit per start.
    pub max_iter: usize,
    /// Number of starting points (1: the data-derived guess only).
    pub starts: usize,
    /// Initial values overriding the data-derived guesses (`name`, value).
    pub initial: Vec<(super::ParamName, f64)>,
    /// How much work the fit may do (counted, so the result never depends on the machine).
    pub budget: Budget,
    /// Whether the record's normal stress drives the model.
    pub normal_stress: NormalStressMode,
    /// Which α are fitted.
    pub alpha: AlphaFit,
    /// Set from another thread to stop the fit (and MCMC, and a diagnosis) at its next model
    /// evaluation: every evaluation then fails, so the work winds down within one solve. The
    /// Python package sets it on KeyboardInterrupt.
    pub cancel: Option<Arc<std::sync::atomic::AtomicBool>>,
    /// Whether a large record is fitted on bin means carrying the same information, and what
    /// the result then describes ([`super::BinMeans`]; default: bin means above
    /// [`super::BIN_ABOVE`] samples, [`super::BIN_FRACTION`]).
    pub bins: super::BinMeans,
    /// How precisely the search runs: default LM's own tests with every solve at `rtol`.
    pub search: SearchPrecision,
    /// Threads on which the starts after the first run side by side (1: one after another on
    /// the caller's thread; 0: all cores). The result does not depend on it: each start's run
    /// is the one it has under the step allowance the starts before it leave. (Under a budget
    /// that stops the later starts, a run made beside the others at a wider allowance is made
    /// again at its own: the work done can then exceed the budget's steps, the work counted
    /// cannot.)
    pub threads: usize,
}

/// How precisely a fit's search runs. A diagnosis's many fits need each log-likelihood to a
/// hundredth, not the optimum to round-off: they stop when the Gauss–Newton step would gain
/// less than `lnl_tolerance`, and solve at a looser tolerance while far from the optimum
/// ([`crate::lm::Convergence`]). The result is always evaluated at the fit's `rtol`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SearchPrecision {
    /// Stop when the Gauss–Newton step's predicted gain is below this, in units of ln L.
    pub lnl_tolerance: Option<f64>,
    /// The integrator tolerance while the predicted gain exceeds `coarse_above` (ln L units).
    pub coarse_rtol: Option<f64>,
    /// See `coarse_rtol`.
    pub coarse_above: f64,
}

impl SearchPrecision {
    /// The LM tests for `max_iter` iterations, ln L counted in `scale`.
    pub fn convergence(&self, max_iter: usize, scale: crate::lm::LnlScale) -> crate::lm::Convergence {
        crate::lm::Convergence {
            max_iter,
            lnl_tolerance: self.lnl_tolerance,
            coarse_above: self.coarse_rtol.map(|_| self.coarse_above),
            scale,
        }
    }
}

impl FitOptions {
    /// Whether [`cancel`](Self::cancel) has been set.
    pub fn cancelled(&self) -> bool {
        self.cancel.as_ref().is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed))
    }
}

/// The work a fit may do, counted in integrator steps of its forward solves, never in wall
/// time: the same record and options give the same answer on any machine, at any load, with
/// any number of threads. Past the budget, evaluations fail and Levenberg–Marquardt returns the
/// best point it has, and the result says so ([`BudgetHit`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    /// Integrator steps of all forward solves of the fit (all starts together).
    pub steps: u64,
    /// Each start after the first may take at most this many times the steps of the first
    /// (a start that wanders into a stiff corner of parameter space must not hold the fit up).
    pub per_start_factor: f64,
    /// Opt-in wall-clock guard, s (off by default). When it is hit the result depends on the
    /// machine, and says so.
    pub wall_clock_guard: Option<f64>,
}

impl Budget {
    /// The default: 40 million integrator steps, about 30 s of fitting on one core of the
    /// 2-core reference machine (docs/BENCHMARKS.md), the wall-time budget this replaces.
    pub const DEFAULT_STEPS: u64 = 40_000_000;

    /// A budget of `steps` integrator steps, five times the first start's work for later
    /// starts, no wall-clock guard.
    pub fn steps(steps: u64) -> Self {
        Self { steps, per_start_factor: 5.0, wall_clock_guard: None }
    }

    /// This budget scaled by `f` (a diagnosis gives each candidate a share of the baseline's).
    pub fn scaled(self, f: f64) -> Self {
        Self { steps: ((self.steps as f64) * f).round() as u64, ..self }
    }
}

impl Default for Budget {
    fn default() -> Self {
        Self::steps(Self::DEFAULT_STEPS)
    }
}

/// Which budget stopped the best start before it converged.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BudgetHit {
    /// The integrator-step budget ([`Budget::steps`]): deterministic.
    StepBudget,
    /// The opt-in wall-clock guard: the result depends on the machine.
    WallClockGuard,
}

impl std::fmt::Display for BudgetHit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::StepBudget => "step budget exhausted",
            Self::WallClockGuard => "wall-clock guard hit",
        })
    }
}

impl FitOptions {
    /// Defaults for `n` states of `law` at stiffness `k`.
    pub fn new(laws: Vec<Arc<dyn DynStateLaw>>, k: f64) -> Self {
        Self {
            laws,
            stiffness: k,
            fit_stiffness: false,
            fit_slip_trend: false,
            fit_a_slope: false,
            a_slope_range: None,
            fix: vec![],
            mu0_per_segment: false,
            window_um: None,
            exclude: vec![],
            weighting: Weighting::EqualSegments,
            uncertainty: Uncertainty::NoiseModel,
            loading: LoadingMode::Record,
            rtol: 1e-7,
            max_iter: 100,
            starts: 5,
            initial: vec![],
            budget: Budget::default(),
            normal_stress: NormalStressMode::Auto,
            alpha: AlphaFit::Fixed,
            cancel: None,
            bins: super::BinMeans::Replace { above: super::BIN_ABOVE, fraction: super::BIN_FRACTION },
            search: SearchPrecision::default(),
            threads: 1,
        }
    }
}

/// A fit error, in words.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// Bad settings.
    #[error("{0}")]
    Setup(String),
    /// The model could not be evaluated at the starting point.
    #[error("the model cannot be evaluated at the starting point: {0}")]
    Start(SolveError),
}
