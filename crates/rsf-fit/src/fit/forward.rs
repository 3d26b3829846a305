//! The forward model at the used samples: friction, and its exact derivatives with respect to
//! the free parameters from one forward-sensitivity solve.

use super::params::within_bounds;
use super::{FIT_MAX_STEPS, FitOptions, LoadingMode, ParamMap, Prepared};
use crate::sens::solve_with_sensitivities;
use rsf_core::{LoadRecord, Loading, Model, Segment};
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
    let problem = forward_problem(p, opts, model);
    let seg_of = |r: usize| p.seg_of[r];
    with_sensitivities(&problem, map, theta, &full, rtol, &seg_of)
}

/// One forward-sensitivity solve of `problem`, mapped to the free parameters θ: friction with
/// its segment offset (`seg_of(r)`: the segment of output row r) and ∂friction/∂θ.
fn with_sensitivities(
    problem: &Problem,
    map: &ParamMap,
    theta: &[f64],
    full: &[f64],
    rtol: f64,
    seg_of: &dyn Fn(usize) -> usize,
) -> Result<Evaluated, SolveError> {
    let np = map.np;
    let m = map.free.len();
    let dfull = map.jac(theta);
    // the sensitivities the free parameters reach (a fixed k, g or Vc costs nothing)
    let wanted: Vec<bool> = (0..np).map(|j| dfull[j * m..(j + 1) * m].iter().any(|&d| d != 0.0)).collect();
    let s = solve_with_sensitivities(problem, rtol, rtol * 1e-4, FIT_MAX_STEPS, &wanted)?;
    let steps = s.stats.accepted + s.stats.rejected;
    let mut model_mu = s.mu;
    let mut raw_j = vec![0.0; model_mu.len() * m];
    // ∂p_j/∂θ_k is sparse (each model parameter follows one or two free ones; a segment's
    // friction offset is one free parameter of its own): its non-zero entries, per j
    let nonzero = |j: usize| -> Vec<(usize, f64)> {
        dfull[j * m..(j + 1) * m].iter().copied().enumerate().filter(|&(_, d)| d != 0.0).collect()
    };
    let chain: Vec<(usize, Vec<(usize, f64)>)> = (0..np).filter(|&j| wanted[j]).map(|j| (j, nonzero(j))).collect();
    let offsets: Vec<Vec<(usize, f64)>> = (np..map.slots.len()).map(nonzero).collect();
    // the chain rule row by row: ∂mu/∂θ_k = Σ_j ∂mu/∂p_j ∂p_j/∂θ_k (+ the segment offset's),
    // summed over j in layout order for each k
    for r in 0..model_mu.len() {
        let row = &mut raw_j[r * m..(r + 1) * m];
        let seg = seg_of(r);
        let off_idx = if seg > 0 && map.slots.len() > np { Some(seg - 1) } else { None };
        if let Some(oi) = off_idx {
            model_mu[r] += full[np + oi];
        }
        let dmu = &s.dmu[r * np..(r + 1) * np];
        for (j, entries) in &chain {
            for &(k, d) in entries {
                row[k] += dmu[*j] * d;
            }
        }
        if let Some(oi) = off_idx {
            for &(k, d) in &offsets[oi] {
                row[k] += d;
            }
        }
    }
    Ok(Evaluated { model_mu, raw_j, steps })
}

/// Where [`predict`]'s appended segments start in its solver's time, s: the sum of the record's
/// segment durations (a run's times, such as a blow-up's, are counted from the record's start).
pub fn record_span(p: &Prepared) -> f64 {
    p.segments.iter().map(|s| (s.t1 - s.t0).max(1e-9)).sum()
}

/// A fitted model run on past the record: friction at new sample times after the next
/// protocol segments are appended to the record's own (the forward model of `rsf design`).
#[derive(Clone, Debug)]
pub struct Prediction {
    /// Friction at the new times (the last segment's friction offset included).
    pub mu: Vec<f64>,
    /// ∂friction/∂θ (free parameters in fit order, transformed scale), row-major n × m; empty
    /// unless asked for.
    pub jac: Vec<f64>,
    /// Free parameters.
    pub m: usize,
    /// The largest slip rate since the previous new time (the first: since the record's end),
    /// µm/s, from every integrator step; empty when the derivatives were asked for.
    pub peak_slip_rate: Vec<f64>,
}

/// Runs the model of `map` at θ (free parameters, transformed scale, as
/// [`super::FitResult::theta`]) from the record's start through its protocol (the segments of
/// `p`, whatever loading the fit used) and on through `next`, and samples it at `times`
/// (s after the end of the record's last segment). With `jac`, also ∂friction/∂θ, from one
/// forward-sensitivity solve. σ stays at its last value after the record unless `next`
/// changes it, which it may only when the record's σ is constant (`next` then gives σ in units
/// of the record's). Without `jac`, also the peak slip rate between the new times
/// ([`Prediction::peak_slip_rate`]).
pub fn predict(
    p: &Prepared,
    map: &ParamMap,
    opts: &FitOptions,
    theta: &[f64],
    next: &[Segment],
    times: &[f64],
    jac: bool,
) -> Result<Prediction, SolveError> {
    let full = map.full(theta);
    within_bounds(map, &full).map_err(SolveError::Input)?;
    let mut model = map.model(opts, &full, p.v_init).map_err(SolveError::Input)?;
    if p.segments.is_empty() || p.record.time.is_empty() {
        return Err(SolveError::Input("the record has no segments".into()));
    }
    let t0 = p.record.time[0];
    let mut segs: Vec<Segment> =
        p.segments.iter().map(|s| Segment::for_duration(s.v, (s.t1 - s.t0).max(1e-9))).collect();
    let end = record_span(p);
    segs.extend_from_slice(next);
    // the loading's end as the solver sums it, segment by segment in order (the record's span
    // plus the appended durations, summed apart, may exceed it by an ulp, and a last output
    // time past it is refused)
    let t_end = segs.iter().fold(0.0, |t, s| t + s.duration().unwrap_or(0.0));
    let out: Vec<f64> = times.iter().map(|t| (end + t).clamp(end, t_end)).collect();
    // σ_ref: the record's first σ, or 1 when σ is constant (the appended segments' σ changes
    // are then in units of the record's σ: only ratios of σ enter the model)
    if p.normal_stress.is_some() || next.iter().any(Segment::changes_normal_stress) {
        model.normal_stress = Some(p.sigma_ref);
    }
    let mut problem = Problem::new(model, Loading::Segments(segs), p.v_init, 1.0);
    problem.output = OutputTimes::Times(out);
    problem.normal_stress = p.normal_stress.as_ref().map(|h| {
        // held at its last value through the appended segments
        let mut h = h.shifted(-t0);
        if let (Some(&tl), Some(&sl)) = (h.time.last(), h.sigma.last()) {
            if t_end + 1.0 > tl {
                h.time.push(t_end + 1.0);
                h.sigma.push(sl);
            }
        }
        h
    });
    let last_seg = p.segments.len() - 1;
    if jac {
        let e = with_sensitivities(&problem, map, theta, &full, opts.rtol, &|_| last_seg)?;
        return Ok(Prediction { mu: e.model_mu, jac: e.raw_j, m: map.free.len(), peak_slip_rate: vec![] });
    }
    let alg = rsf_solvers::AutoDopri5 {
        max_steps: FIT_MAX_STEPS,
        ..rsf_solvers::AutoDopri5::new(opts.rtol, opts.rtol * 1e-4)
    };
    // a row more at the record's end (unless the first new time is there), so that the first
    // new time's peak covers only the appended segments
    let extra = usize::from(times.first().is_none_or(|&t| t > 0.0));
    if let OutputTimes::Times(t) = &mut problem.output {
        if extra == 1 {
            t.insert(0, end);
        }
    }
    problem.watch.peak_slip_rate = true;
    let s = rsf_solvers::solve(&problem, &alg)?;
    let mut peak_slip_rate = s.peak_slip_rate[extra..].to_vec();
    if extra == 0 {
        peak_slip_rate[0] = s.slip_rate[0];
    }
    let mut mu = s.mu[extra..].to_vec();
    let np = map.np;
    if last_seg > 0 && map.slots.len() > np {
        for x in &mut mu {
            *x += full[np + last_seg - 1];
        }
    }
    Ok(Prediction { mu, jac: vec![], m: map.free.len(), peak_slip_rate })
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
    let np = map.np;
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

/// The model at the used samples without sensitivities: friction (with its segment offsets)
/// and slip rate from one solve, and the integrator steps taken.
pub(super) struct AtSamples {
    pub(super) mu: Vec<f64>,
    pub(super) slip_rate: Vec<f64>,
    pub(super) steps: u64,
}

/// [`AtSamples`] for the full parameter vector.
pub(super) fn model_at_samples(
    p: &Prepared,
    map: &ParamMap,
    opts: &FitOptions,
    full: &[f64],
) -> Result<AtSamples, SolveError> {
    let model = map.model(opts, full, p.v_init).map_err(SolveError::Input)?;
    let alg = rsf_solvers::AutoDopri5 {
        max_steps: FIT_MAX_STEPS,
        ..rsf_solvers::AutoDopri5::new(opts.rtol, opts.rtol * 1e-4)
    };
    let s = rsf_solvers::solve(&forward_problem(p, opts, model), &alg)?;
    let np = map.np;
    let mut mu = s.mu;
    if map.slots.len() > np {
        for (r, &seg) in p.seg_of.iter().enumerate() {
            if seg > 0 {
                mu[r] += full[np + seg - 1];
            }
        }
    }
    Ok(AtSamples { mu, slip_rate: s.slip_rate, steps: s.stats.accepted + s.stats.rejected })
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
