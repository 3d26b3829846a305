//! Forward sensitivities: friction and its exact derivatives with respect to every model
//! parameter, at the output times, from one integration.
//!
//! The state y = (ln V, ln θ_i, δ) is augmented with S = ∂y/∂p (p in the layout of
//! [`rsf_core::n_params`]): dS/dt = J S + ∂f/∂p, S(0) = ∂y0/∂p. J and ∂f/∂p are exact
//! (`SpringSlider::sensitivity_jacobians`: both from one jet per law at every stage), so the
//! derivatives are those of
//! the model, not finite differences of a tolerance-limited solution. The augmented system is
//! integrated with the automatic stiffness switching of the forward solver's default method,
//! as [`AutoDopri5`] (Dopri5 while non-stiff: fits sample the model at every data point, where
//! its free interpolant beats Vern6's extra stage; Rodas5P where stiff, with the augmented
//! Jacobian below; systems above [`MAX_IMPLICIT_SENS_DIM`] stay with Dopri5), with error
//! control on y and, more
//! loosely (10 rtol, relative with a floor of 1), on S; dense output gives both at the sample
//! times.

use nalgebra::{SMatrix, SVector};
use rsf_core::{LawParameter, N_GLOBAL, PER_STATE, SpringSlider, extra_law_parameters, n_params, n_params_of};
use rsf_solvers::{AutoDopri5, Dopri5, OdeSystem, Problem, SolveError, StepStats, Tolerances, drive};

/// Friction and its parameter derivatives at the output times.
#[derive(Clone, Debug, Default)]
pub struct SensSolution {
    /// Output times, s.
    pub time: Vec<f64>,
    /// Friction (spring stress) at the output times.
    pub mu: Vec<f64>,
    /// ∂mu/∂p, row-major: `dmu[row * n_params + j]`.
    pub dmu: Vec<f64>,
    /// Number of parameters per row.
    pub n_params: usize,
    /// Integrator work.
    pub stats: StepStats,
}

/// Largest number of state variables for which sensitivities are compiled.
pub const MAX_SENS_STATES: usize = 8;

/// The augmented system over the `P` carried parameters `cols` (columns of the whole layout
/// of [`n_params_of`] entries, whose fixed block has `PF` = [`n_params`]): the wanted ones
/// whose sensitivity is not identically zero ([`carried`]). Every carried column costs a
/// D-vector of equations and enters the error norm.
struct SensOde<'a, const D: usize, const P: usize, const PF: usize, const DA: usize> {
    sys: SpringSlider<'a>,
    ln_v_max: f64,
    cols: [usize; P],
    /// The laws' own parameters of the D − 2 states (the first entries).
    law_parameters: [LawParameter; D],
    /// The laws' further own parameters, columns `PF..` of the layout
    /// ([`extra_law_parameters`]).
    extra: Vec<(usize, &'static str)>,
}

impl<const D: usize, const P: usize, const PF: usize, const DA: usize> SensOde<'_, D, P, PF, DA> {
    /// The augmented right-hand side, and the J of the y block it was made with.
    fn rhs_with_j(&self, t: f64, ya: &SVector<f64, DA>) -> (SVector<f64, DA>, SMatrix<f64, D, D>) {
        let mut out = SVector::<f64, DA>::zeros();
        let mut dy = [0.0; D];
        let mut j = SMatrix::<f64, D, D>::zeros();
        let mut fp_full = SMatrix::<f64, D, PF>::zeros();
        let y = &ya.as_slice()[..D];
        let lp = &self.law_parameters[..D - 2];
        if self.sys.sensitivity_jacobians(t, y, &mut dy, j.as_mut_slice(), fp_full.as_mut_slice(), lp).is_err() {
            out.fill(f64::NAN); // checked before integration; NaN rejects the step if it ever happens
            return (out, j);
        }
        let mut fp = SMatrix::<f64, D, P>::zeros();
        for (c, &col) in self.cols.iter().enumerate() {
            if col < PF {
                fp.set_column(c, &fp_full.column(col));
            } else {
                let (i, name) = self.extra[col - PF];
                let mut buf = [0.0; D];
                if self.sys.extra_parameter_column(t, y, i, name, &mut buf).is_err() {
                    out.fill(f64::NAN);
                    return (out, j);
                }
                fp.set_column(c, &SVector::<f64, D>::from(buf));
            }
        }
        out.as_mut_slice()[..D].copy_from_slice(&dy);
        let s = SMatrix::<f64, D, P>::from_column_slice(&ya.as_slice()[D..]);
        let ds = j * s + fp;
        out.as_mut_slice()[D..].copy_from_slice(ds.as_slice());
        (out, j)
    }
}

impl<const D: usize, const P: usize, const PF: usize, const DA: usize> OdeSystem<DA> for SensOde<'_, D, P, PF, DA> {
    fn rhs(&self, t: f64, ya: &SVector<f64, DA>) -> SVector<f64, DA> {
        self.rhs_with_j(t, ya).0
    }
    /// The augmented Jacobian for the implicit stretches of [`AutoDopri5`]: block lower triangular,
    /// J in the y block and in every S block on the diagonal, and the coupling
    /// ∂(J S_c + ∂f/∂p_c)/∂y below it. The coupling holds second derivatives of f, taken here by
    /// central differences of the exact first derivatives (relative step 1e-6: truncation
    /// ~1e-12, round-off ~1e-10 relative; a Rosenbrock step tolerates such Jacobian errors,
    /// which enter its local error multiplied by h).
    fn rhs_and_jacobian(&self, t: f64, ya: &SVector<f64, DA>) -> (SVector<f64, DA>, SMatrix<f64, DA, DA>) {
        let (f, j) = self.rhs_with_j(t, ya);
        let mut ja = SMatrix::<f64, DA, DA>::zeros();
        for blk in 0..=P {
            ja.fixed_view_mut::<D, D>(blk * D, blk * D).copy_from(&j);
        }
        for k in 0..D {
            let eps = 1e-6 * (1.0 + ya[k].abs());
            let (mut yp, mut ym) = (*ya, *ya);
            yp[k] += eps;
            ym[k] -= eps;
            let (fp, fm) = (self.rhs(t, &yp), self.rhs(t, &ym));
            for r in D..DA {
                ja[(r, k)] = (fp[r] - fm[r]) / (2.0 * eps);
            }
        }
        (f, ja)
    }
    /// ∂f/∂t of the augmented system under a normal-stress ramp: a central difference in t
    /// over the time in which σ changes by 1e-7 of itself (the spring-slider's own step), so
    /// the step follows the ramp, not the clock.
    fn time_derivative(&self, t: f64, ya: &SVector<f64, DA>) -> Option<SVector<f64, DA>> {
        self.sys.time_dependent().then(|| {
            let dt = self.sys.ramp_time_step(t);
            (self.rhs(t + dt, ya) - self.rhs(t - dt, ya)) / (2.0 * dt)
        })
    }
    /// ρ of the block lower-triangular augmented Jacobian is ρ(J): bound it by the y block's
    /// row sums (the coupling rows hold ∂J/∂y·S, which can be far larger without changing a
    /// single eigenvalue, and would keep the automatic method implicit for nothing).
    fn spectral_radius_bound(&self, jac: &SMatrix<f64, DA, DA>) -> f64 {
        (0..D).map(|r| (0..D).map(|c| jac[(r, c)].abs()).sum::<f64>()).fold(0.0, f64::max)
    }
    #[inline]
    fn error_scale(&self, i: usize, y0: f64, y1: f64, tol: &Tolerances) -> f64 {
        if i + 1 < D {
            tol.rtol + tol.atol
        } else if i + 1 == D {
            tol.atol + tol.rtol * y0.abs().max(y1.abs())
        } else {
            // sensitivities are error-controlled too (as CVODES' errconS): otherwise a state at
            // rest lets the step grow past the stability limit that S' = J S + ∂f/∂p shares
            // with y, and S explodes while y stays exact
            10.0 * tol.rtol * (1.0 + y0.abs().max(y1.abs()))
        }
    }
    fn check(&self, ya: &SVector<f64, DA>) -> Result<(), String> {
        if ya[0] > self.ln_v_max {
            Err(format!("slip rate {:.3e} µm/s exceeds the limit", ya[0].exp()))
        } else {
            Ok(())
        }
    }
}

/// The numbers of carried sensitivity columns compiled for `n` state variables (each size is one
/// instantiation of the augmented system; a set of wanted columns is padded up to the next
/// size). One and two states, the diagnosis's fits, get the small sizes: a baseline needs a, b
/// and Dc only (μ0 moves no state), an extension one or two more.
fn carried_sizes(n: usize) -> &'static [usize] {
    match n {
        1 => &[3, 4, 5, 7, 8, 9, 12],
        2 => &[5, 6, 7, 10, 12, 13, 16],
        3 => &[13, 17],
        4 => &[16, 21],
        5 => &[19, 25],
        6 => &[22, 29],
        7 => &[25, 33],
        _ => &[28, 37],
    }
}

/// Whether parameter `j`'s S column is identically zero for `model`: μ0 and the α at constant
/// normal stress (they move no state), the law-parameter slot of a law without one. A law's
/// further own parameters (after the fixed block) always move its state.
fn zero_column(model: &rsf_core::Model, alpha: bool, j: usize) -> bool {
    if j < N_GLOBAL {
        return j == 0 && !alpha;
    }
    if j >= n_params(model.n_states()) {
        return false;
    }
    let (i, k) = ((j - N_GLOBAL) / PER_STATE, (j - N_GLOBAL) % PER_STATE);
    (k == 3 && !alpha) || (k == 2 && model.states[i].law.parameters().is_empty())
}

/// The S columns a solve carries: the wanted ones that are not identically zero, padded up
/// to a compiled size by further columns of the fixed block in layout order (α last); `None`
/// when more are wanted than the largest compiled size.
fn carried(model: &rsf_core::Model, alpha: bool, wanted: &[bool]) -> Option<Vec<usize>> {
    let pf = n_params(model.n_states());
    let is_alpha = |j: usize| j >= N_GLOBAL && (j - N_GLOBAL) % PER_STATE == 3;
    let mut cols: Vec<usize> = (0..wanted.len()).filter(|&j| wanted[j] && !zero_column(model, alpha, j)).collect();
    let sizes = carried_sizes(model.n_states());
    let target = sizes.iter().copied().find(|&s| s >= cols.len())?;
    let pad: Vec<usize> = (0..pf)
        .filter(|&j| !is_alpha(j))
        .chain((0..pf).filter(|&j| is_alpha(j)))
        .filter(|j| !cols.contains(j))
        .collect();
    cols.extend(pad.into_iter().take(target - cols.len()));
    cols.sort_unstable();
    (cols.len() == target).then_some(cols)
}

/// Solves `problem` with [`AutoDopri5`] (Dopri5 above [`MAX_IMPLICIT_SENS_DIM`]) at `rtol` and
/// returns friction and ∂mu/∂p at the output times for the parameters `wanted` (indexed as
/// [`n_params`]; the others come out NaN unless their sensitivity is identically zero or came
/// with a padded column). Classic friction form, finite stiffness, 1–8 state variables;
/// `max_steps` is the integrator's step budget per piece of loading.
pub fn solve_with_sensitivities(
    problem: &Problem,
    rtol: f64,
    atol: f64,
    max_steps: u64,
    wanted: &[bool],
) -> Result<SensSolution, SolveError> {
    let pieces = problem.pieces()?;
    let alpha = rsf_core::normal_stress_varies(&pieces);
    let n = problem.model.n_states();
    if !(1..=MAX_SENS_STATES).contains(&n) {
        return Err(SolveError::Input(format!(
            "{n} state variables: parameter sensitivities are compiled for 1 to {MAX_SENS_STATES}"
        )));
    }
    let total = n_params_of(&problem.model);
    if wanted.len() != total {
        return Err(SolveError::Input(format!("{} wanted columns for {total} parameters", wanted.len())));
    }
    let Some(cols) = carried(&problem.model, alpha, wanted) else {
        let most = carried_sizes(n).last().copied().unwrap_or(0);
        return Err(SolveError::Input(format!(
            "sensitivities to {} parameters wanted with {n} state variable(s): at most {most} are compiled; \
             fix some of them",
            wanted.iter().filter(|&&w| w).count()
        )));
    };
    let a = (problem, &pieces[..], rtol, atol, max_steps, &cols[..]);
    // <D, carried P, full P, D (1 + P)>
    match (n, cols.len()) {
        (1, 3) => run::<3, 3, 9, 12>(a),
        (1, 4) => run::<3, 4, 9, 15>(a),
        (1, 5) => run::<3, 5, 9, 18>(a),
        (1, 7) => run::<3, 7, 9, 24>(a),
        (1, 8) => run::<3, 8, 9, 27>(a),
        (1, 9) => run::<3, 9, 9, 30>(a),
        (1, _) => run::<3, 12, 9, 39>(a),
        (2, 5) => run::<4, 5, 13, 24>(a),
        (2, 6) => run::<4, 6, 13, 28>(a),
        (2, 7) => run::<4, 7, 13, 32>(a),
        (2, 10) => run::<4, 10, 13, 44>(a),
        (2, 12) => run::<4, 12, 13, 52>(a),
        (2, 13) => run::<4, 13, 13, 56>(a),
        (2, _) => run::<4, 16, 13, 68>(a),
        (3, 13) => run::<5, 13, 17, 70>(a),
        (3, _) => run::<5, 17, 17, 90>(a),
        (4, 16) => run::<6, 16, 21, 102>(a),
        (4, _) => run::<6, 21, 21, 132>(a),
        (5, 19) => run::<7, 19, 25, 140>(a),
        (5, _) => run::<7, 25, 25, 182>(a),
        (6, 22) => run::<8, 22, 29, 184>(a),
        (6, _) => run::<8, 29, 29, 240>(a),
        (7, 25) => run::<9, 25, 33, 234>(a),
        (7, _) => run::<9, 33, 33, 306>(a),
        (8, 28) => run::<10, 28, 37, 290>(a),
        _ => run::<10, 37, 37, 380>(a),
    }
}

/// What a parameter's ∂y/∂p is in a solve.
#[derive(Clone, Copy)]
enum Column {
    /// Carried as the augmented system's S column of this index.
    Carried(usize),
    /// Identically zero ([`zero_column`]).
    Zero,
    /// Not wanted, hence not carried: its ∂mu/∂p is NaN.
    Missing,
}

type RunArgs<'a> = (&'a Problem, &'a [rsf_core::Piece], f64, f64, u64, &'a [usize]);

fn run<const D: usize, const P: usize, const PF: usize, const DA: usize>(
    (problem, pieces, rtol, atol, max_steps, carried): RunArgs,
) -> Result<SensSolution, SolveError> {
    debug_assert_eq!(DA, D * (1 + P));
    let model = &problem.model;
    debug_assert_eq!(PF, n_params(model.n_states()));
    let extra = extra_law_parameters(model);
    // the whole layout: the fixed block and the laws' further own parameters
    let pt = PF + extra.len();
    debug_assert_eq!(carried.len(), P);
    let mut cols = [0usize; P];
    cols.copy_from_slice(carried);
    let alpha = rsf_core::normal_stress_varies(pieces);
    model.validate()?;
    if let Some(w) = pieces.windows(2).find(|w| w[1].sigma0 != w[0].sigma_end()) {
        // the step map's own derivatives are not carried; a measured σ is continuous anyway
        return Err(SolveError::Input(format!(
            "parameter sensitivities across an instantaneous normal-stress step (t = {} s) are not supported; \
             give the step as a short ramp",
            w[1].t0
        )));
    }
    let t_out = rsf_solvers::output_times(problem, pieces)?;
    let y0 = SpringSlider::steady_state(model, problem.v_init)?;
    // sensitivity support (classic form, finite k, law parameters settable) at the start
    let probe = SpringSlider::for_piece(model, &pieces[0]);
    let mut fp = vec![0.0; D * PF];
    probe.parameter_jacobian(pieces[0].t0, &y0, &mut fp).map_err(SolveError::Input)?;
    let mut ya = SVector::<f64, DA>::zeros();
    ya.as_mut_slice()[..D].copy_from_slice(&y0);
    let mut s0 = vec![0.0; D * pt];
    SpringSlider::steady_state_sensitivity(model, problem.v_init, &mut s0).map_err(SolveError::Input)?;
    for (c, &j) in cols.iter().enumerate() {
        ya.as_mut_slice()[D + c * D..D + (c + 1) * D].copy_from_slice(&s0[j * D..(j + 1) * D]);
    }
    let rows = t_out.len();
    let mut sol = SensSolution {
        time: Vec::with_capacity(rows),
        mu: Vec::with_capacity(rows),
        dmu: Vec::with_capacity(rows * pt),
        n_params: pt,
        stats: StepStats::default(),
    };
    // the S column of each full-layout parameter: carried, identically zero, or not wanted
    let mut col_of = vec![Column::Missing; pt];
    for (j, c) in col_of.iter_mut().enumerate() {
        if zero_column(model, alpha, j) {
            *c = Column::Zero;
        }
    }
    for (c, &j) in cols.iter().enumerate() {
        col_of[j] = Column::Carried(c);
    }
    let (mut gy, mut gp) = ([0.0; D], [0.0; PF]);
    let ln_v_max = problem.max_slip_rate.ln();
    let mut stats = StepStats::default();
    // the friction and its gradients do not depend on the piece (σ cancels in τ/σ)
    let friction = SpringSlider::new(model, pieces[0].v);
    let mut record = |_: &rsf_core::Piece, t: f64, ya: &SVector<f64, DA>| {
        let y = &ya.as_slice()[..D];
        sol.time.push(t);
        sol.mu.push(friction.stress(y));
        let _ = friction.stress_gradients(y, &mut gy, &mut gp);
        for j in 0..pt {
            let through_y = match col_of[j] {
                Column::Carried(c) => {
                    let col = &ya.as_slice()[D + c * D..D + (c + 1) * D];
                    gy.iter().zip(col).map(|(a, b)| a * b).sum::<f64>()
                }
                Column::Zero => 0.0,
                Column::Missing => f64::NAN,
            };
            // μ depends on a law's further own parameters through the state alone
            sol.dmu.push(gp.get(j).copied().unwrap_or(0.0) + through_y);
        }
    };
    let mut law_parameters = [None; D];
    law_parameters[..D - 2].copy_from_slice(&rsf_core::law_parameters(model));
    let make = |sys| SensOde::<D, P, PF, DA> { sys, ln_v_max, cols, law_parameters, extra: extra.clone() };
    let msr = problem.max_slip_rate;
    if DA <= MAX_IMPLICIT_SENS_DIM {
        let alg = AutoDopri5 { max_steps, ..AutoDopri5::new(rtol, atol) };
        drive(model, pieces, &t_out, ya, &alg, make, msr, &mut stats, &mut record)?;
    } else {
        let alg = Dopri5 { max_steps, ..Dopri5::new(rtol, atol) };
        drive(model, pieces, &t_out, ya, &alg, make, msr, &mut stats, &mut record)?;
    }
    sol.stats = stats;
    Ok(sol)
}

/// The largest augmented system (N + 2)(1 + P) that follows [`AutoDopri5`] into its implicit
/// stretches: 52, i.e. up to two states with their α columns. The Rosenbrock stepper keeps the
/// augmented Jacobian and its LU as stack matrices (21 KB each at 52; 1.1 MB at eight states,
/// which would overflow a worker thread's stack), so larger systems stay explicit with
/// [`Dopri5`], AutoDopri5's explicit method.
pub const MAX_IMPLICIT_SENS_DIM: usize = 52;

#[cfg(test)]
#[path = "sens_tests.rs"]
mod tests;
