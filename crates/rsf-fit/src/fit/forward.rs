//! The forward model at the used samples: friction, and its exact derivatives with respect to
//! the free parameters from one forward-sensitivity solve.

use super::params::within_bounds;
use super::{FIT_MAX_STEPS, FitOptions, LoadingMode, ParamMap, Prepared};
use crate::sens::solve_with_sensitivities;
use rsf_core::{LoadRecord, Loading, Model, n_params};
use rsf_solvers::{OutputTimes, Problem, SolveError};

/// The model at θ: friction at the used samples, ∂friction/∂θ, and the integrator steps taken.
pub(super) struct Evaluated {
    pub(super) model_mu: Vec<f64>,
    /// ∂model/∂θ, row-major n × m.
    pub(super) raw_j: Vec<f64>,
    pub(super) steps: u64,
}

pub(super) fn evaluate(
    p: &Prepared,
    map: &ParamMap,
    opts: &FitOptions,
    theta: &[f64],
    rtol: f64,
) -> Result<Evaluated, SolveError> {
    let full = map.full(theta);
    within_bounds(map, &full).map_err(SolveError::Input)?;
    let model = map.model(opts, &full, p.v_init).map_err(SolveError::Input)?;
    let np = n_params(map.n_states);
    let problem = forward_problem(p, opts, model);
    let m = map.free.len();
    let dfull = map.jac(theta);
    // the sensitivities the free parameters reach (a fixed k, g or Vc costs nothing)
    let wanted: Vec<bool> = (0..np).map(|j| dfull[j * m..(j + 1) * m].iter().any(|&d| d != 0.0)).collect();
    let s = solve_with_sensitivities(&problem, rtol, rtol * 1e-4, FIT_MAX_STEPS, &wanted)?;
    let steps = s.stats.accepted + s.stats.rejected;
    let mut model_mu = s.mu;
    let mut raw_j = vec![0.0; model_mu.len() * m];
    for r in 0..model_mu.len() {
        let seg = p.seg_of[r];
        let off_idx = if seg > 0 && map.slots.len() > np { Some(np + seg - 1) } else { None };
        if let Some(oi) = off_idx {
            model_mu[r] += full[oi];
        }
        for k in 0..m {
            let mut acc = 0.0;
            for j in (0..np).filter(|&j| wanted[j]) {
                acc += s.dmu[r * np + j] * dfull[j * m + k];
            }
            if let Some(oi) = off_idx {
                acc += dfull[oi * m + k];
            }
            raw_j[r * m + k] = acc;
        }
    }
    Ok(Evaluated { model_mu, raw_j, steps })
}

/// Model friction at the used samples for free parameters θ (no sensitivities): the forward
/// model of MCMC and of predictions.
pub fn model_curve(
    p: &Prepared,
    map: &ParamMap,
    opts: &FitOptions,
    theta: &[f64],
    rtol: f64,
) -> Result<Vec<f64>, SolveError> {
    let full = map.full(theta);
    within_bounds(map, &full).map_err(SolveError::Input)?;
    let model = map.model(opts, &full, p.v_init).map_err(SolveError::Input)?;
    let np = n_params(map.n_states);
    let problem = forward_problem(p, opts, model);
    let alg = rsf_solvers::AutoDopri5 { max_steps: FIT_MAX_STEPS, ..rsf_solvers::AutoDopri5::new(rtol, rtol * 1e-4) };
    let (mut mu, _) = rsf_solvers::solve_friction(&problem, &alg)?;
    if map.slots.len() > np {
        for (r, &seg) in p.seg_of.iter().enumerate() {
            if seg > 0 {
                mu[r] += full[np + seg - 1];
            }
        }
    }
    Ok(mu)
}

/// Model slip rate at the used samples for the full parameter vector (for residuals against
/// log V): one forward solve.
pub(super) fn model_slip_rate(
    p: &Prepared,
    map: &ParamMap,
    opts: &FitOptions,
    full: &[f64],
) -> Result<Vec<f64>, SolveError> {
    let model = map.model(opts, full, p.v_init).map_err(SolveError::Input)?;
    let alg = rsf_solvers::AutoDopri5 {
        max_steps: FIT_MAX_STEPS,
        ..rsf_solvers::AutoDopri5::new(opts.rtol, opts.rtol * 1e-4)
    };
    Ok(rsf_solvers::solve(&forward_problem(p, opts, model), &alg)?.slip_rate)
}

/// The forward problem of a fit for `model`: loading and output at the used samples.
fn forward_problem(p: &Prepared, opts: &FitOptions, mut model: Model) -> Problem {
    let times: Vec<f64> = p.used.iter().map(|&i| p.record.time[i]).collect();
    let t0 = p.record.time[0];
    if p.normal_stress.is_some() {
        model.normal_stress = Some(p.sigma_ref);
    }
    let (loading, out) = match opts.loading {
        LoadingMode::Record => (
            Loading::Record(LoadRecord { time: p.record.time.clone(), load_point: p.record.load_point.clone() }),
            times,
        ),
        LoadingMode::Protocol => {
            let durations: Vec<f64> = p.segments.iter().map(|s| (s.t1 - s.t0).max(1e-9)).collect();
            // the summed durations may fall an ulp short of the last sample's time
            let end: f64 = durations.iter().sum();
            let segs =
                p.segments.iter().zip(&durations).map(|(s, &d)| rsf_core::Segment::for_duration(s.v, d)).collect();
            (Loading::Segments(segs), times.iter().map(|t| (t - t0).clamp(0.0, end)).collect())
        }
    };
    let shift = match opts.loading {
        LoadingMode::Record => 0.0,
        LoadingMode::Protocol => -t0,
    };
    let mut problem = Problem::new(model, loading, p.v_init, 1.0);
    problem.output = OutputTimes::Times(out);
    problem.normal_stress = p.normal_stress.as_ref().map(|h| h.shifted(shift));
    problem
}
