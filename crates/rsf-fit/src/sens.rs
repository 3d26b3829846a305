//! Forward sensitivities: friction and its exact derivatives with respect to every model
//! parameter, at the output times, from one integration.
//!
//! The state y = (ln V, ln θ_i, δ) is augmented with S = ∂y/∂p (p in the layout of
//! [`rsf_core::n_params`]): dS/dt = J S + ∂f/∂p, S(0) = ∂y0/∂p. J and ∂f/∂p are exact
//! (`SpringSlider::jacobian`, `SpringSlider::parameter_jacobian`), so the derivatives are those of
//! the model, not finite differences of a tolerance-limited solution. The augmented system is
//! integrated with the automatic stiffness switching of the forward solver's default method,
//! as [`AutoDopri5`] (Dopri5 while non-stiff: fits sample the model at every data point, where
//! its free interpolant beats Vern6's extra stage; Rodas5P where stiff, with the augmented
//! Jacobian below; systems above [`MAX_IMPLICIT_SENS_DIM`] stay with Dopri5), with error
//! control on y and, more
//! loosely (10 rtol, relative with a floor of 1), on S; dense output gives both at the sample
//! times.

use nalgebra::{SMatrix, SVector};
use rsf_core::{N_GLOBAL, PER_STATE, SpringSlider, n_params};
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

/// The augmented system over the `P` active parameters `cols` (columns of the full layout of
/// `PF` = [`n_params`] entries). At constant normal stress the α columns are left out: their
/// sensitivities are identically zero, and carrying them would only cost work and dilute the
/// error norm.
struct SensOde<'a, const D: usize, const P: usize, const PF: usize, const DA: usize> {
    sys: SpringSlider<'a>,
    ln_v_max: f64,
    cols: [usize; P],
}

impl<const D: usize, const P: usize, const PF: usize, const DA: usize> OdeSystem<DA> for SensOde<'_, D, P, PF, DA> {
    fn rhs(&self, t: f64, ya: &SVector<f64, DA>) -> SVector<f64, DA> {
        let mut out = SVector::<f64, DA>::zeros();
        let mut dy = [0.0; D];
        let mut j = SMatrix::<f64, D, D>::zeros();
        self.sys.jacobian(t, &ya.as_slice()[..D], &mut dy, j.as_mut_slice());
        let mut fp_full = SMatrix::<f64, D, PF>::zeros();
        if self.sys.parameter_jacobian(t, &ya.as_slice()[..D], fp_full.as_mut_slice()).is_err() {
            out.fill(f64::NAN); // checked before integration; NaN rejects the step if it ever happens
            return out;
        }
        let fp = SMatrix::<f64, D, P>::from_fn(|r, c| fp_full[(r, self.cols[c])]);
        out.as_mut_slice()[..D].copy_from_slice(&dy);
        let s = SMatrix::<f64, D, P>::from_column_slice(&ya.as_slice()[D..]);
        let ds = j * s + fp;
        out.as_mut_slice()[D..].copy_from_slice(ds.as_slice());
        out
    }
    /// The augmented Jacobian for the implicit stretches of [`AutoDopri5`]: block lower triangular,
    /// J in the y block and in every S block on the diagonal, and the coupling
    /// ∂(J S_c + ∂f/∂p_c)/∂y below it. The coupling holds second derivatives of f, taken here by
    /// central differences of the exact first derivatives (relative step 1e-6: truncation
    /// ~1e-12, round-off ~1e-10 relative; a Rosenbrock step tolerates such Jacobian errors,
    /// which enter its local error multiplied by h).
    fn rhs_and_jacobian(&self, t: f64, ya: &SVector<f64, DA>) -> (SVector<f64, DA>, SMatrix<f64, DA, DA>) {
        let f = self.rhs(t, ya);
        let mut ja = SMatrix::<f64, DA, DA>::zeros();
        let mut dy = [0.0; D];
        let mut j = SMatrix::<f64, D, D>::zeros();
        self.sys.jacobian(t, &ya.as_slice()[..D], &mut dy, j.as_mut_slice());
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

/// Solves `problem` with [`AutoDopri5`] (Dopri5 above [`MAX_IMPLICIT_SENS_DIM`]) at `rtol` and returns friction and ∂mu/∂p at the
/// output times. Classic friction form, finite stiffness, 1–8 state variables; `max_steps` is
/// the integrator's step budget per piece of loading.
pub fn solve_with_sensitivities(
    problem: &Problem,
    rtol: f64,
    atol: f64,
    max_steps: u64,
) -> Result<SensSolution, SolveError> {
    let pieces = problem.pieces()?;
    let alpha = rsf_core::normal_stress_varies(&pieces);
    match problem.model.n_states() {
        // <D, active P, full P, D (1 + P)>: α columns active only when σ varies
        1 if alpha => run::<3, 8, 8, 27>(problem, &pieces, rtol, atol, max_steps),
        1 => run::<3, 7, 8, 24>(problem, &pieces, rtol, atol, max_steps),
        2 if alpha => run::<4, 12, 12, 52>(problem, &pieces, rtol, atol, max_steps),
        2 => run::<4, 10, 12, 44>(problem, &pieces, rtol, atol, max_steps),
        3 if alpha => run::<5, 16, 16, 85>(problem, &pieces, rtol, atol, max_steps),
        3 => run::<5, 13, 16, 70>(problem, &pieces, rtol, atol, max_steps),
        4 if alpha => run::<6, 20, 20, 126>(problem, &pieces, rtol, atol, max_steps),
        4 => run::<6, 16, 20, 102>(problem, &pieces, rtol, atol, max_steps),
        5 if alpha => run::<7, 24, 24, 175>(problem, &pieces, rtol, atol, max_steps),
        5 => run::<7, 19, 24, 140>(problem, &pieces, rtol, atol, max_steps),
        6 if alpha => run::<8, 28, 28, 232>(problem, &pieces, rtol, atol, max_steps),
        6 => run::<8, 22, 28, 184>(problem, &pieces, rtol, atol, max_steps),
        7 if alpha => run::<9, 32, 32, 297>(problem, &pieces, rtol, atol, max_steps),
        7 => run::<9, 25, 32, 234>(problem, &pieces, rtol, atol, max_steps),
        8 if alpha => run::<10, 36, 36, 370>(problem, &pieces, rtol, atol, max_steps),
        8 => run::<10, 28, 36, 290>(problem, &pieces, rtol, atol, max_steps),
        n => Err(SolveError::Input(format!(
            "{n} state variables: parameter sensitivities are compiled for 1 to {MAX_SENS_STATES}"
        ))),
    }
}

fn run<const D: usize, const P: usize, const PF: usize, const DA: usize>(
    problem: &Problem,
    pieces: &[rsf_core::Piece],
    rtol: f64,
    atol: f64,
    max_steps: u64,
) -> Result<SensSolution, SolveError> {
    debug_assert_eq!(DA, D * (1 + P));
    let model = &problem.model;
    debug_assert_eq!(PF, n_params(model.n_states()));
    // the active columns: all, or all but the α of each state
    let mut cols = [0usize; P];
    let mut k = 0;
    for j in 0..PF {
        let is_alpha = j >= N_GLOBAL && (j - N_GLOBAL) % PER_STATE == 3;
        if P == PF || !is_alpha {
            cols[k] = j;
            k += 1;
        }
    }
    debug_assert_eq!(k, P);
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
    let mut s0 = vec![0.0; D * PF];
    SpringSlider::steady_state_sensitivity(model, problem.v_init, &mut s0).map_err(SolveError::Input)?;
    for (c, &j) in cols.iter().enumerate() {
        ya.as_mut_slice()[D + c * D..D + (c + 1) * D].copy_from_slice(&s0[j * D..(j + 1) * D]);
    }
    let rows = t_out.len();
    let mut sol = SensSolution {
        time: Vec::with_capacity(rows),
        mu: Vec::with_capacity(rows),
        dmu: Vec::with_capacity(rows * PF),
        n_params: PF,
        stats: StepStats::default(),
    };
    // the S column of each full-layout parameter (None: identically zero)
    let mut col_of = [None; PF];
    for (c, &j) in cols.iter().enumerate() {
        col_of[j] = Some(c);
    }
    let (mut gy, mut gp) = ([0.0; D], [0.0; PF]);
    let ln_v_max = problem.max_slip_rate.ln();
    let mut stats = StepStats::default();
    let mut record = |piece: &rsf_core::Piece, t: f64, ya: &SVector<f64, DA>| {
        let sys = SpringSlider::for_piece(model, piece);
        let y = &ya.as_slice()[..D];
        sol.time.push(t);
        sol.mu.push(sys.stress(y));
        let _ = sys.stress_gradients(y, &mut gy, &mut gp);
        for j in 0..PF {
            let through_y = col_of[j].map_or(0.0, |c| {
                let col = &ya.as_slice()[D + c * D..D + (c + 1) * D];
                gy.iter().zip(col).map(|(a, b)| a * b).sum::<f64>()
            });
            sol.dmu.push(gp[j] + through_y);
        }
    };
    let make = |sys| SensOde::<D, P, PF, DA> { sys, ln_v_max, cols };
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
mod tests {
    use super::*;
    use rsf_core::{Loading, Model, Segment, StateVariable};
    use rsf_laws::{Aging, KatoTullis, Slip};

    fn params(m: &Model) -> Vec<f64> {
        m.parameter_vector()
    }
    fn rebuild(base: &Model, p: &[f64]) -> Model {
        base.with_parameter_vector(p).unwrap()
    }

    /// The largest error of ∂mu/∂p_j from `s` against central differences of tight solves of
    /// `mk(model)`, relative to the column's largest value, for the parameters `js`.
    fn worst_errors(base: &Model, mk: &dyn Fn(Model) -> Problem, s: &SensSolution, js: &[usize]) -> Vec<(usize, f64)> {
        let p = params(base);
        let np = s.n_params;
        js.iter()
            .filter(|&&j| p[j] != 0.0)
            .map(|&j| {
                let h = 1e-5 * p[j].abs();
                let (mut pp, mut pm) = (p.clone(), p.clone());
                pp[j] += h;
                pm[j] -= h;
                let fp = rsf_solvers::solve(&mk(rebuild(base, &pp)), &rsf_solvers::Dopri5::new(1e-12, 1e-15)).unwrap();
                let fm = rsf_solvers::solve(&mk(rebuild(base, &pm)), &rsf_solvers::Dopri5::new(1e-12, 1e-15)).unwrap();
                let scale = (0..s.mu.len()).map(|r| s.dmu[r * np + j].abs()).fold(0.0, f64::max).max(1e-9);
                let worst = (0..s.mu.len())
                    .map(|r| ((fp.mu[r] - fm.mu[r]) / (2.0 * h) - s.dmu[r * np + j]).abs() / scale)
                    .fold(0.0, f64::max);
                (j, worst)
            })
            .collect()
    }

    /// ∂mu/∂p from the sensitivity equations agrees with central differences of tight
    /// solves, for 1, 2 and 3 states (mixed laws, a law parameter) over a step–hold protocol.
    #[test]
    fn sensitivities_match_finite_differences() {
        let models = vec![
            Model::new(0.6, 1.0, 0.011, 0.02).with_state(StateVariable::new(Slip, 0.014, 3.0)),
            Model::new(0.6, 1.0, 0.011, 0.02)
                .with_state(StateVariable::new(Slip, 0.009, 3.0))
                .with_state(StateVariable::new(Aging, 0.005, 30.0))
                .with_slip_trend(1e-5),
            Model::new(0.6, 1.0, 0.011, 0.02)
                .with_state(StateVariable::new(Slip, 0.008, 3.0))
                .with_state(StateVariable::new(Aging, 0.004, 30.0))
                .with_state(StateVariable::new(KatoTullis { vc: 0.05 }, 0.003, 10.0)),
        ];
        for base in models {
            // a long stretch at steady state first: y is at rest there and only error control on
            // S keeps the sensitivity equations within the explicit method's stability limit
            let segs = vec![
                Segment::for_duration(1.0, 2000.0),
                Segment::for_duration(10.0, 3.0),
                Segment::for_duration(0.1, 60.0),
                Segment::for_duration(0.0, 100.0),
                Segment::for_duration(1.0, 20.0),
            ];
            let mk = |m: Model| Problem::new(m, Loading::Segments(segs.clone()), 1.0, 1.0);
            let s = solve_with_sensitivities(&mk(base.clone()), 1e-11, 1e-14, crate::fit::FIT_MAX_STEPS).unwrap();
            let all: Vec<usize> = (0..s.n_params).collect();
            for (j, worst) in worst_errors(&base, &mk, &s, &all) {
                assert!(worst < 2e-4, "N = {}, parameter {j}: max rel error {worst:e}", base.n_states());
            }
        }
    }

    /// The same with a measured normal stress (ramps up and down, one during the hold) and
    /// Linker–Dieterich α on both states: ∂mu/∂α_i and the others against central differences.
    #[test]
    fn sensitivities_follow_normal_stress_changes() {
        let mut base = Model::new(0.6, 1.0, 0.011, 0.02)
            .with_state(StateVariable::new(Slip, 0.009, 3.0).with_alpha(0.25))
            .with_state(StateVariable::new(Aging, 0.005, 30.0).with_alpha(0.1))
            .with_normal_stress(10.0);
        base.slip_trend = 1e-5;
        let segs = vec![
            Segment::for_duration(1.0, 200.0),
            Segment::for_duration(10.0, 3.0),
            Segment::for_duration(0.1, 60.0),
            Segment::for_duration(0.0, 100.0),
            Segment::for_duration(1.0, 40.0),
        ];
        let sn = rsf_core::NormalStressRecord {
            time: vec![0.0, 100.0, 102.0, 250.0, 300.0, 320.0, 403.0],
            sigma: vec![10.0, 10.0, 12.0, 12.0, 9.5, 9.5, 9.5],
        };
        let mk = |m: Model| {
            let mut p = Problem::new(m, Loading::Segments(segs.clone()), 1.0, 1.0);
            p.normal_stress = Some(sn.clone());
            p
        };
        let s = solve_with_sensitivities(&mk(base.clone()), 1e-11, 1e-14, crate::fit::FIT_MAX_STEPS).unwrap();
        let np = s.n_params;
        let all: Vec<usize> = (0..np).collect();
        for (j, worst) in worst_errors(&base, &mk, &s, &all) {
            assert!(worst < 2e-4, "parameter {j}: max rel error {worst:e}");
        }
        // α matters: its column is far from zero
        let ja = rsf_core::state_offset(0) + 3;
        assert!((0..s.mu.len()).any(|r| s.dmu[r * np + ja].abs() > 1e-3));
    }

    /// A stiff machine (k = 10 /µm, Dc = 0.1 µm: the spring relaxes in a/(kV) ≈ 1e-4 s while
    /// the state evolves over Dc/V = 0.01 s): the sensitivities follow `auto` into Rodas5P with
    /// the augmented Jacobian, match finite differences, and need a fraction of the steps the
    /// explicit method alone takes (for one and two states, with and without α columns).
    #[test]
    fn stiff_sensitivities_switch_to_the_implicit_method() {
        let one = Model::new(0.6, 1.0, 0.01, 10.0).with_state(StateVariable::new(Slip, 0.014, 0.1));
        let two = Model::new(0.6, 1.0, 0.01, 10.0)
            .with_state(StateVariable::new(Slip, 0.009, 0.1))
            .with_state(StateVariable::new(Aging, 0.005, 1.0));
        let segs = vec![
            Segment::for_duration(10.0, 5.0),
            Segment::for_duration(0.0, 100.0),
            Segment::for_duration(10.0, 5.0),
            Segment::for_duration(1.0, 5.0),
        ];
        // the second model also under normal-stress ramps (during sliding and in the hold), so
        // that the implicit stretches see a time-dependent augmented system (∂f/∂t)
        let two = two.with_normal_stress(10.0);
        let two = Model { states: two.states.iter().map(|s| s.clone().with_alpha(0.2)).collect(), ..two };
        let sn = rsf_core::NormalStressRecord {
            time: vec![0.0, 1.0, 3.0, 20.0, 40.0, 115.0],
            sigma: vec![10.0, 10.0, 11.0, 11.0, 10.5, 10.5],
        };
        for base in [one, two] {
            let ramps = base.normal_stress.is_some();
            let mk = |m: Model| {
                let mut p = Problem::new(m, Loading::Segments(segs.clone()), 10.0, 0.5);
                if ramps {
                    p.normal_stress = Some(sn.clone());
                }
                p
            };
            let s = solve_with_sensitivities(&mk(base.clone()), 1e-9, 1e-13, crate::fit::FIT_MAX_STEPS).unwrap();
            let explicit = rsf_solvers::solve(&mk(base.clone()), &Dopri5::new(1e-9, 1e-13)).unwrap();
            println!(
                "N = {}: sensitivities {:?}; forward dopri5 {} steps",
                base.n_states(),
                s.stats,
                explicit.stats.accepted
            );
            assert!(s.stats.to_implicit >= 2, "{:?}", s.stats);
            assert!(
                s.stats.accepted * 5 < explicit.stats.accepted,
                "{} steps with sensitivities vs {} forward explicit",
                s.stats.accepted,
                explicit.stats.accepted
            );
            let all: Vec<usize> = (0..s.n_params).collect();
            for (j, worst) in worst_errors(&base, &mk, &s, &all) {
                assert!(worst < 1e-4, "N = {}, parameter {j}: max rel error {worst:e}", base.n_states());
            }
        }
    }

    /// The case that exposed uncontrolled sensitivities (basalt velstep7 with k free): steady
    /// sliding at 100 µm/s, a step to 300 µm/s, 1 kHz output. ∂mu/∂ln Dc must match finite
    /// differences (it was off by orders of magnitude when S was outside error control).
    #[test]
    fn sensitivities_stay_accurate_through_fast_steady_sliding() {
        let base = Model::new(0.608, 100.0, 0.011, 0.0105).with_state(StateVariable::new(Slip, 0.012, 10.0));
        let segs = vec![Segment::for_duration(100.0, 1.95), Segment::for_duration(300.0, 2.0)];
        let mk = |m: Model| {
            let mut p = Problem::new(m, Loading::Segments(segs.clone()), 100.0, 1.0);
            p.output = rsf_solvers::OutputTimes::Times((0..3950).map(|i| i as f64 * 1e-3).collect());
            p
        };
        let s = solve_with_sensitivities(&mk(base.clone()), 1e-7, 1e-11, crate::fit::FIT_MAX_STEPS).unwrap();
        for (j, worst) in worst_errors(&base, &mk, &s, &[1, 2, 4, 5]) {
            assert!(worst < 1e-3, "parameter {j}: max rel error {worst:e}");
        }
    }
}
