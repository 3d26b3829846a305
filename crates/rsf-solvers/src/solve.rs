//! Problem → algorithm → solution for the spring-slider.

use crate::Solution;
use crate::ode::{IntegrationError, Integrator, OdeSystem, StepStats, Tolerances};
use crate::route::{DIRECT_MAX_STATES, LawRoute, law_route};
use crate::run_away::{RunAway, blow_up_reason};
use crate::watch::{StepWatch, WatchOptions};
use nalgebra::{SMatrix, SVector};
use rsf_core::{
    DynLaws, LawDispatch, Loading, Model, ModelError, NormalStressRecord, Piece, SpringSlider, normal_stress_varies,
};
use thiserror::Error;

/// Largest number of state variables the solver is compiled for.
pub const MAX_STATES: usize = 8;

/// Calls `$f::<D, …>` with the stack dimension D = N + 2 of the problem's N state variables.
macro_rules! by_dimension {
    ($problem:expr, $f:ident::<$i:ident>($($arg:expr),*)) => {{
        let n = $problem.model.n_states();
        match n {
            1 => $f::<3, $i>($($arg),*),
            2 => $f::<4, $i>($($arg),*),
            3 => $f::<5, $i>($($arg),*),
            4 => $f::<6, $i>($($arg),*),
            5 => $f::<7, $i>($($arg),*),
            6 => $f::<8, $i>($($arg),*),
            7 => $f::<9, $i>($($arg),*),
            8 => $f::<10, $i>($($arg),*),
            0 => Err(SolveError::Model(ModelError::NoState)),
            _ => Err(SolveError::Input(format!("{n} state variables: this build supports at most {MAX_STATES}"))),
        }
    }};
}

/// Evaluates `$body` with `$laws` bound to the route to the model's laws that `law_route`
/// picks ([`LawDispatch`]). `$d` is the const dimension: the direct branches are compiled only
/// for the dimensions they can serve (N ≤ `DIRECT_MAX_STATES`).
macro_rules! with_laws {
    ($d:expr, $model:expr, $laws:ident => $body:expr) => {{
        if $d <= DIRECT_MAX_STATES + 2 {
            match law_route($model) {
                LawRoute::Slip($laws) => $body,
                LawRoute::Aging($laws) => $body,
                LawRoute::Dyn => {
                    let $laws = DynLaws;
                    $body
                }
            }
        } else {
            let $laws = DynLaws;
            $body
        }
    }};
}

/// Where output samples are taken.
#[derive(Clone, Debug, PartialEq)]
pub enum OutputTimes {
    /// `t = 0, dt, 2dt, …` and the end of the last segment (s).
    Every(f64),
    /// At every piece boundary (segment ends; for a record, the ends of its merged pieces of
    /// constant load-point velocity).
    PieceEnds,
    /// At these times (s, sorted, within the loading's time span).
    Times(Vec<f64>),
}

/// The default slip rate beyond which a run stops with a blow-up error, µm/s (1 km/s: no
/// quasi-static lab model means anything there).
pub const MAX_SLIP_RATE: f64 = 1e9;

/// A forward problem: model, loading, initial steady state and output times. It holds no
/// solution state, so solving it twice gives the same answer.
#[derive(Clone, Debug)]
pub struct Problem {
    /// The friction model and machine.
    pub model: Model,
    /// How the load point moves.
    pub loading: Loading,
    /// The system starts at this slip rate, µm/s — in steady state unless `initial_theta`.
    pub v_init: f64,
    /// θ_i (s) to start from instead of the steady state at `v_init` (off-steady initial
    /// conditions: a perturbed start, or a cycle model's own state); `None`: steady state.
    pub initial_theta: Option<Vec<f64>>,
    /// Output sampling.
    pub output: OutputTimes,
    /// Slip rate (µm/s) beyond which the run stops with a blow-up error. Default
    /// [`MAX_SLIP_RATE`].
    pub max_slip_rate: f64,
    /// What to take from every integrator step besides the output rows: the peak slip rate
    /// between rows and an event catalogue ([`WatchOptions`]); off by default.
    pub watch: WatchOptions,
    /// A measured normal-stress history (MPa, piecewise linear, spanning the loading) that
    /// drives σ(t); `None`: σ follows the protocol segments, or stays at the model's σ_ref.
    pub normal_stress: Option<NormalStressRecord>,
}

impl Problem {
    /// A problem sampled every `dt` seconds.
    pub fn new(model: Model, loading: Loading, v_init: f64, dt: f64) -> Self {
        Self {
            model,
            loading,
            v_init,
            initial_theta: None,
            output: OutputTimes::Every(dt),
            max_slip_rate: MAX_SLIP_RATE,
            watch: WatchOptions::default(),
            normal_stress: None,
        }
    }

    /// The pieces of constant load-point velocity and normal-stress rate the solvers restart
    /// at; the error names the bad segment or sample, or a varying σ with no σ_ref.
    pub fn pieces(&self) -> Result<Vec<Piece>, SolveError> {
        let pieces = self
            .loading
            .pieces_with(self.model.sigma_ref(), self.normal_stress.as_ref())
            .map_err(SolveError::Loading)?;
        if self.model.normal_stress.is_none() && normal_stress_varies(&pieces) {
            return Err(SolveError::Input(
                "the normal stress changes, so the model needs `normal_stress` (σ_ref, MPa: the stress at which \
                 `stiffness` = K/σ is stated)"
                    .into(),
            ));
        }
        Ok(pieces)
    }
}

/// The state vector (ln V, ln θ_i, slip) a problem starts from: steady state at `v_init`, or
/// `v_init` with the given `initial_theta`.
/// With `initial_theta` no steady state is computed, so a law without one (the Aging law
/// without healing) can start from its given θ.
pub fn initial_state(problem: &Problem) -> Result<Vec<f64>, SolveError> {
    let Some(theta) = &problem.initial_theta else {
        return Ok(SpringSlider::steady_state(&problem.model, problem.v_init)?);
    };
    let n = problem.model.states.len();
    if theta.len() != n {
        return Err(SolveError::Input(format!("initial theta has {} values for {n} state variables", theta.len())));
    }
    let v = problem.v_init;
    if !(v > 0.0 && v.is_finite()) {
        return Err(SolveError::Input(format!("initial slip rate {v} must be positive and finite (µm/s)")));
    }
    let mut y = Vec::with_capacity(n + 2);
    y.push(v.ln());
    for (i, &th) in theta.iter().enumerate() {
        if !(th > 0.0 && th.is_finite()) {
            return Err(SolveError::Input(format!("initial theta {} = {th} must be positive and finite (s)", i + 1)));
        }
        y.push(th.ln());
    }
    y.push(0.0);
    Ok(y)
}

/// Why a forward solve failed. Messages name the parameter, or the time and values reached.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SolveError {
    /// A model parameter is invalid.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The loading history is invalid.
    #[error("loading: {0}")]
    Loading(String),
    /// Another input is invalid.
    #[error("{0}")]
    Input(String),
    /// The slip rate diverged: a quasi-static instability.
    #[error("slip rate blew up at t = {t:.6} s (V = {v:.3e} µm/s, mu = {mu:.6}) {at}: {}", blow_up_reason(*k, *kc))]
    BlowUp {
        /// Time, s.
        t: f64,
        /// Slip rate at stop, µm/s.
        v: f64,
        /// Friction at stop.
        mu: f64,
        /// Stiffness, 1/µm.
        k: f64,
        /// Critical stiffness estimate, 1/µm.
        kc: f64,
        /// Where, and what the protocol did there.
        at: Box<RunAway>,
    },
    /// The integrator failed.
    #[error("integration failed in piece {piece} (V_lp = {v_lp} µm/s, V = {v:.3e} µm/s): {source}")]
    Integration {
        /// 1-based piece (segment or record interval) index.
        piece: usize,
        /// Load-point velocity, µm/s.
        v_lp: f64,
        /// Slip rate at the start of the failing piece, µm/s.
        v: f64,
        /// The integrator's error.
        source: IntegrationError,
    },
}

/// The spring-slider as an [`OdeSystem`] of dimension `D = N + 2`.
struct SliderOde<'a, const D: usize, L> {
    sys: SpringSlider<'a>,
    ln_v_max: f64,
    watch: Option<&'a StepWatch>,
    laws: &'a L,
}

impl<const D: usize, L: LawDispatch> OdeSystem<D> for SliderOde<'_, D, L> {
    #[inline]
    fn rhs(&self, t: f64, y: &SVector<f64, D>) -> SVector<f64, D> {
        let mut dy = SVector::<f64, D>::zeros();
        self.sys.rhs_with(self.laws, t, y.as_slice(), dy.as_mut_slice());
        dy
    }
    fn rhs_and_jacobian(&self, t: f64, y: &SVector<f64, D>) -> (SVector<f64, D>, SMatrix<f64, D, D>) {
        let mut dy = SVector::<f64, D>::zeros();
        let mut j = SMatrix::<f64, D, D>::zeros();
        self.sys.jacobian(t, y.as_slice(), dy.as_mut_slice(), j.as_mut_slice());
        (dy, j)
    }
    fn time_derivative(&self, t: f64, y: &SVector<f64, D>) -> Option<SVector<f64, D>> {
        self.sys.time_dependent().then(|| {
            let mut ft = SVector::<f64, D>::zeros();
            self.sys.time_derivative(t, y.as_slice(), ft.as_mut_slice());
            ft
        })
    }
    /// ln V and ln θ are controlled absolutely (an error ε is a relative error ε in V or θ)
    /// to `atol + rtol`; slip relatively to `atol + rtol |δ|`.
    #[inline]
    fn error_scale(&self, i: usize, y0: f64, y1: f64, tol: &Tolerances) -> f64 {
        if i + 1 < D { tol.rtol + tol.atol } else { tol.atol + tol.rtol * y0.abs().max(y1.abs()) }
    }
    #[inline]
    fn check(&self, y: &SVector<f64, D>) -> Result<(), String> {
        if y[0] > self.ln_v_max { Err(format!("slip rate {:.3e} µm/s exceeds the limit", y[0].exp())) } else { Ok(()) }
    }
    #[inline]
    fn accepted(&self, t: f64, y: &SVector<f64, D>) -> Result<(), String> {
        if let Some(w) = self.watch {
            // one right-hand side per accepted step, only when watching
            w.step(t, y[0], self.rhs(t, y)[0], y[D - 1]);
        }
        self.check(y)
    }
}

/// Solves `problem` with the integrator `alg`.
///
/// ```
/// use rsf_core::{Loading, Model, Segment, StateVariable};
/// use rsf_laws::Slip;
/// use rsf_solvers::{solve, Dopri5, Problem, Rodas4};
///
/// let model = Model::new(0.6, 1.0, 0.013, 0.065).with_state(StateVariable::new(Slip, 0.016, 2.07));
/// let loading = Loading::Segments(vec![Segment::for_duration(1.0, 5.0), Segment::for_duration(0.0, 100.0)]);
/// let problem = Problem::new(model, loading, 1.0, 0.5);
/// let explicit = solve(&problem, &Dopri5::new(1e-9, 1e-12)).unwrap();
/// let implicit = solve(&problem, &Rodas4::new(1e-9, 1e-12)).unwrap();
/// let end = explicit.len() - 1;
/// assert!((explicit.mu[end] - implicit.mu[end]).abs() < 1e-8);
/// assert!(explicit.slip_rate[end] < 1e-2); // the hold relaxes V by orders of magnitude
/// ```
pub fn solve<I: Integrator>(problem: &Problem, alg: &I) -> Result<Solution, SolveError> {
    by_dimension!(problem, solve_dim::<I>(problem, alg))
}

/// The output times of `problem` over its `pieces`.
pub fn output_times(problem: &Problem, pieces: &[Piece]) -> Result<Vec<f64>, SolveError> {
    let t0 = pieces[0].t0;
    let t_end = pieces[pieces.len() - 1].t1;
    match &problem.output {
        OutputTimes::Every(dt) => {
            if !(*dt > 0.0 && dt.is_finite()) {
                return Err(SolveError::Input(format!("output dt = {dt} must be positive and finite")));
            }
            let span = t_end - t0;
            let count = (span / dt * (1.0 + 1e-12)).floor() as usize;
            if count > 50_000_000 {
                return Err(SolveError::Input(format!(
                    "output dt = {dt} s gives {count} rows over {span} s; choose a larger dt"
                )));
            }
            let mut ts: Vec<f64> = (0..=count).map(|i| t0 + i as f64 * dt).collect();
            let last = *ts.last().unwrap();
            if (t_end - last).abs() <= 1e-9 * dt {
                *ts.last_mut().unwrap() = t_end;
            } else if last < t_end {
                ts.push(t_end);
            } else {
                ts.pop();
                ts.push(t_end);
            }
            Ok(ts)
        }
        OutputTimes::PieceEnds => {
            let mut ts = vec![t0];
            ts.extend(pieces.iter().map(|p| p.t1));
            Ok(ts)
        }
        OutputTimes::Times(ts) => {
            for (i, w) in ts.windows(2).enumerate() {
                if !(w[1] > w[0]) {
                    return Err(SolveError::Input(format!("output time {} ({} s) does not increase", i + 1, w[1])));
                }
            }
            if let (Some(&a), Some(&b)) = (ts.first(), ts.last()) {
                if a < t0 || b > t_end {
                    return Err(SolveError::Input(format!(
                        "output times [{a}, {b}] s lie outside the loading [{t0}, {t_end}] s"
                    )));
                }
            }
            Ok(ts.clone())
        }
    }
}

/// Every check a solve makes before it integrates — model, tolerances, initial slip rate,
/// loading, output times, imposed-velocity restrictions, the blow-up limit — for [`solve`] and
/// [`solve_friction`] alike; returns the pieces and output times.
fn checked(problem: &Problem, tol: &Tolerances) -> Result<(Vec<Piece>, Vec<f64>), SolveError> {
    let model = &problem.model;
    model.validate()?;
    tol.check().map_err(SolveError::Input)?;
    if !(problem.v_init > 0.0 && problem.v_init.is_finite()) {
        return Err(SolveError::Input(format!("v_init = {} must be positive and finite (µm/s)", problem.v_init)));
    }
    let pieces = problem.pieces()?;
    let t_out = output_times(problem, &pieces)?;
    if model.imposed_velocity() {
        if let Some((i, p)) = pieces.iter().enumerate().find(|(_, p)| !(p.v > 0.0)) {
            return Err(SolveError::Loading(format!(
                "piece {}: with infinite stiffness the slip rate equals V_lp, which must be positive (got {})",
                i + 1,
                p.v
            )));
        }
        let y = SpringSlider::steady_state(model, problem.v_init)?;
        for (i, s) in model.states.iter().enumerate() {
            let j = s.law.jet(&rsf_core::StateArgs::new(problem.v_init, y[1 + i].exp(), s.dc, s.b));
            if j.d_stress_rate != 0.0 {
                return Err(SolveError::Input(format!(
                    "state {} ({}) depends on the stress rate, which is undefined with infinite stiffness",
                    i + 1,
                    s.law.name()
                )));
            }
        }
    }
    if !(problem.max_slip_rate > problem.v_init) {
        return Err(SolveError::Input(format!(
            "max_slip_rate = {} must exceed v_init = {}",
            problem.max_slip_rate, problem.v_init
        )));
    }
    Ok((pieces, t_out))
}

fn solve_dim<const D: usize, I: Integrator>(problem: &Problem, alg: &I) -> Result<Solution, SolveError> {
    let model = &problem.model;
    let tol = alg.tolerances();
    let (pieces, t_out) = checked(problem, &tol)?;

    let n = D - 2;
    let rows = t_out.len();
    let mut sol = Solution {
        time: Vec::with_capacity(rows),
        load_point: Vec::with_capacity(rows),
        mu: Vec::with_capacity(rows),
        slip_rate: Vec::with_capacity(rows),
        slip: Vec::with_capacity(rows),
        theta: vec![Vec::with_capacity(rows); n],
        stats: StepStats::default(),
        method: alg.name().to_string(),
        tolerances: Some(tol),
        peak_slip_rate: Vec::new(),
        events: Vec::new(),
        normal_stress: Vec::new(),
    };
    let sigma_varies = normal_stress_varies(&pieces);
    let y = SVector::<f64, D>::from_column_slice(&initial_state(problem)?);
    let watching = problem.watch.peak_slip_rate || problem.watch.event_slip_rate.is_some();
    let watch = watching.then(|| StepWatch::new(&problem.watch));

    // τ/σ does not depend on the load point or σ: one system evaluates every row's friction
    let friction = SpringSlider::new(model, 1.0);
    let record = |sol: &mut Solution, sys: &SpringSlider, piece: &Piece, t: f64, y: &SVector<f64, D>| {
        sol.time.push(t);
        sol.load_point.push(piece.load_point(t));
        sol.mu.push(sys.stress(y.as_slice()));
        sol.slip_rate.push(y[0].exp());
        sol.slip.push(y[D - 1]);
        for i in 0..n {
            sol.theta[i].push(y[1 + i].exp());
        }
        if sigma_varies {
            sol.normal_stress.push(piece.normal_stress(t));
        }
    };

    let stats = with_laws!(D, model, laws => {
        drive_slider::<D, I, _>(problem, &pieces, &t_out, y, alg, watch.as_ref(), &laws, |piece, t, y| {
            record(&mut sol, &friction, piece, t, y);
            if let (Some(w), true) = (&watch, problem.watch.peak_slip_rate) {
                sol.peak_slip_rate.push(w.row(t, y[0]));
            }
        })
    })?;
    sol.stats = stats;
    if let Some(w) = watch {
        sol.events = w.into_events();
    }
    Ok(sol)
}

/// Integrates `y0` across the `pieces`, restarting the integrator exactly at every boundary
/// (applying a normal-stress step there to the first N + 2 components), and calling `record(piece, t, y)` at every time of `t_out` (sorted, within
/// the pieces' span; a time on a boundary is recorded once). `make` wraps the spring-slider of
/// each piece into the system actually integrated (e.g. augmented with sensitivities, whose
/// first N + 2 components must be the spring-slider's). Returns the end state; a failure is
/// reported as a blow-up (with time, slip rate and friction) or as the failing piece.
#[allow(clippy::too_many_arguments)]
pub fn drive<'m, const D: usize, I: Integrator, S: OdeSystem<D>>(
    model: &'m Model,
    pieces: &[Piece],
    t_out: &[f64],
    y0: SVector<f64, D>,
    alg: &I,
    make: impl Fn(SpringSlider<'m>) -> S,
    max_slip_rate: f64,
    stats: &mut StepStats,
    mut record: impl FnMut(&Piece, f64, &SVector<f64, D>),
) -> Result<SVector<f64, D>, SolveError> {
    let mut y = y0;
    let mut oi = 0; // next output index
    let mut h = 0.0;
    for (pi, piece) in pieces.iter().enumerate() {
        let sys = SpringSlider::for_piece(model, piece);
        if model.imposed_velocity() {
            y[0] = piece.v.ln();
        }
        if pi > 0 {
            let sigma_minus = pieces[pi - 1].sigma_end();
            if piece.sigma0 != sigma_minus {
                // times on the step belong to the piece ending there (recorded before the step)
                while oi < t_out.len() && t_out[oi] <= piece.t0 {
                    record(&pieces[pi - 1], t_out[oi], &y);
                    oi += 1;
                }
                let n2 = model.n_states() + 2;
                sys.normal_stress_step(&mut y.as_mut_slice()[..n2], sigma_minus, piece.sigma0)
                    .map_err(|e| SolveError::Input(format!("piece {} (t = {} s): {e}", pi + 1, piece.t0)))?;
                h = 0.0; // the step is a discontinuity: let the method choose a new first step
            }
        }
        // times on the start of the first piece; later boundaries belong to the piece ending there
        while oi < t_out.len() && t_out[oi] <= piece.t0 {
            record(piece, t_out[oi], &y);
            oi += 1;
        }
        let start = oi;
        while oi < t_out.len() && t_out[oi] <= piece.t1 {
            oi += 1;
        }
        let ode = make(sys);
        let v_start = y[0].exp();
        let mut last: Option<SVector<f64, D>> = None;
        let res = alg.integrate(
            &ode,
            piece.t0,
            y,
            piece.t1,
            h,
            &t_out[start..oi],
            &mut |t, yy| {
                record(piece, t, yy);
                last = Some(*yy);
            },
            stats,
        );
        match res {
            Ok(r) => {
                y = r.y;
                h = r.h_next;
            }
            Err(e) => {
                let t_fail = match &e {
                    IntegrationError::StepSizeUnderflow { t, .. }
                    | IntegrationError::TooManySteps { t, .. }
                    | IntegrationError::Stopped { t, .. }
                    | IntegrationError::Singular { t } => *t,
                };
                let stopped = matches!(e, IntegrationError::Stopped { .. });
                let blew_up = stopped
                    || (matches!(e, IntegrationError::StepSizeUnderflow { .. })
                        && last.map(|yy| yy[0] > y[0] + 2.0).unwrap_or(true));
                if blew_up && !model.imposed_velocity() {
                    let yy = last.unwrap_or(y);
                    let before = pi.checked_sub(1).map(|i| &pieces[i]);
                    let at = RunAway {
                        piece: pi + 1,
                        t0: piece.t0,
                        v_lp: (before.map(|b| b.v), piece.v),
                        sigma: (before.map(|b| b.sigma_end()), piece.sigma0),
                        states: model
                            .states
                            .iter()
                            .enumerate()
                            .map(|(i, st)| (st.law.name(), yy[1 + i].exp()))
                            .collect(),
                    };
                    return Err(SolveError::BlowUp {
                        t: t_fail,
                        v: yy[0].exp().max(if stopped { max_slip_rate } else { 0.0 }),
                        mu: sys.stress(yy.as_slice()),
                        k: model.stiffness,
                        kc: model.critical_stiffness_estimate(),
                        at: Box::new(at),
                    });
                }
                return Err(SolveError::Integration { piece: pi + 1, v_lp: piece.v, v: v_start, source: e });
            }
        }
    }
    Ok(y)
}

/// [`drive`] for the plain spring-slider of `problem`.
#[allow(clippy::too_many_arguments)]
fn drive_slider<const D: usize, I: Integrator, L: LawDispatch>(
    problem: &Problem,
    pieces: &[Piece],
    t_out: &[f64],
    y: SVector<f64, D>,
    alg: &I,
    watch: Option<&StepWatch>,
    laws: &L,
    record: impl FnMut(&Piece, f64, &SVector<f64, D>),
) -> Result<StepStats, SolveError> {
    let ln_v_max = problem.max_slip_rate.ln();
    let mut stats = StepStats::default();
    drive(
        &problem.model,
        pieces,
        t_out,
        y,
        alg,
        |sys| SliderOde::<D, L> { sys, ln_v_max, watch, laws },
        problem.max_slip_rate,
        &mut stats,
        record,
    )?;
    Ok(stats)
}

/// Friction only (the spring stress at the output times): the lean path for likelihoods and
/// misfits, which need nothing else. Same integration and the same friction values as
/// [`solve`].
pub fn solve_friction<I: Integrator>(problem: &Problem, alg: &I) -> Result<(Vec<f64>, StepStats), SolveError> {
    by_dimension!(problem, friction_dim::<I>(problem, alg))
}

fn friction_dim<const D: usize, I: Integrator>(
    problem: &Problem,
    alg: &I,
) -> Result<(Vec<f64>, StepStats), SolveError> {
    let model = &problem.model;
    let (pieces, t_out) = checked(problem, &alg.tolerances())?;
    let y = SVector::<f64, D>::from_column_slice(&initial_state(problem)?);
    // τ/σ = f + ηV + gδ with the logarithms of V0 and s_i Dc_i taken once (SpringSlider::stress)
    let friction = SpringSlider::new(model, 1.0);
    let mut mu = Vec::with_capacity(t_out.len());
    let stats = with_laws!(D, model, laws => {
        drive_slider::<D, I, _>(problem, &pieces, &t_out, y, alg, None, &laws, |_, _, y| {
            mu.push(friction.stress(y.as_slice()))
        })
    })?;
    Ok((mu, stats))
}
