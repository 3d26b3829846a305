//! Starting points and Levenberg–Marquardt under the work budget: [`fit`].

use super::covariance::{covariance, covariance_under, intervals};
use super::forward::{AtSamples, Evaluated, evaluate, model_at_samples};
use super::params::within_bounds;
use super::{
    AlphaFit, BudgetHit, Curve, FitError, FitOptions, FitResult, NoiseSummary, ParamMap, ParamName, Params, Prepared,
    SegmentRow, Uncertainty, parameter_map,
};
use crate::lm::{self, Eval};
use rsf_core::state_offset;
use rsf_noise::NoiseModel;
use rsf_solvers::SolveError;
use std::cell::{Cell, RefCell};
use std::collections::BTreeMap;

/// Fits the model to the prepared record: Levenberg–Marquardt from several starting points
/// (the best optimum wins), under the work budget of `opts.budget`. Under
/// [`BinMeans::Search`](super::BinMeans::Search) the optimum is sought on bin means and the
/// result evaluated on every sample of `p`.
pub fn fit(p: &Prepared, opts: &FitOptions) -> Result<FitResult, FitError> {
    match opts.bins.search_points(p) {
        Some(pb) => {
            let s = search(&pb, opts)?;
            report(p, Some(&pb), opts, s)
        }
        None => {
            let s = search(p, opts)?;
            report(p, None, opts, s)
        }
    }
}

/// The optimum of a [`search`]: where it is, on which parameter map, and the work it took.
struct Searched {
    map: ParamMap,
    best: lm::LmResult,
    /// The budget that stopped the best start, if one did.
    best_hit: Option<BudgetHit>,
    /// Integrator steps of the whole search.
    steps: u64,
    starts: usize,
    /// Starts whose search failed (a forward solve that ran away, a budget before the first
    /// evaluation).
    starts_failed: usize,
    /// The best start's evaluation at its optimum, when it kept one.
    at_best: Option<AtBest>,
}

/// One start's Levenberg–Marquardt run under its allowance of integrator steps.
struct StartRun {
    result: Result<lm::LmResult, SolveError>,
    /// Integrator steps it took.
    steps: u64,
    /// The budget that stopped it, if one did.
    hit: Option<BudgetHit>,
    /// The steps it was allowed.
    allowance: u64,
    /// Its evaluation at full accuracy of the smallest sum of squares (the point it stopped
    /// at, [`AtBest`]).
    at_best: Option<AtBest>,
}

impl StartRun {
    /// What is left in a slot whose run has been taken.
    fn placeholder() -> Self {
        Self { result: Err(SolveError::Input("taken".into())), steps: 0, hit: None, allowance: 0, at_best: None }
    }
}

/// A search's evaluation at full accuracy (`opts.rtol`) with the smallest sum of squares, and
/// where it was made. Levenberg–Marquardt accepts a step only when it lowers the sum of
/// squares of full-accuracy evaluations, so this is the evaluation at the point the search
/// stops at: [`report`] takes its curve and Jacobian instead of solving the same problem again
/// (one sensitivity solve per fit; the Vc profile's grid points are fits of eight iterations).
/// It is used only when its point is bit for bit the optimum's, so the result is the same.
struct AtBest {
    theta: Vec<f64>,
    ssr: f64,
    eval: Evaluated,
}

/// Levenberg–Marquardt from several starting points on the points of `p`. The later starts
/// run side by side on `opts.threads` threads; each result is still the one its start gives
/// under the allowance the starts before it leave, so the fit does not depend on the threads.
fn search(p: &Prepared, opts: &FitOptions) -> Result<Searched, FitError> {
    let map = parameter_map(p, opts)?;
    let m = map.free.len();
    let bounds = map.theta_bounds();
    let data: Vec<f64> = p.used.iter().map(|&i| p.record.mu[i]).collect();
    // work counted in integrator steps: `used` before the starts (a nested one-state fit)
    let used = Cell::new(0u64);
    let clock = std::time::Instant::now();
    // one start under its own allowance of integrator steps: its result, the steps it took and
    // the budget that stopped it, if one did (a pure function of the start and the allowance)
    let run_start = |start: &[f64], allowance: u64, convergence: &lm::Convergence| -> StartRun {
        let used = Cell::new(0u64);
        let hit = Cell::new(None::<BudgetHit>);
        let at_best = RefCell::new(None::<AtBest>);
        let objective = |theta: &[f64], accuracy: lm::Accuracy| -> Result<Eval, SolveError> {
            if opts.cancelled() {
                return Err(SolveError::Input("cancelled".into()));
            }
            if used.get() >= allowance {
                hit.set(Some(BudgetHit::StepBudget));
                return Err(SolveError::Input("the fit's step budget is exhausted".into()));
            }
            if opts.budget.wall_clock_guard.is_some_and(|g| clock.elapsed().as_secs_f64() > g) {
                hit.set(Some(BudgetHit::WallClockGuard));
                return Err(SolveError::Input("the fit's wall-clock guard was hit".into()));
            }
            let rtol = match accuracy {
                lm::Accuracy::Fine => opts.rtol,
                lm::Accuracy::Coarse => opts.search.coarse_rtol.unwrap_or(opts.rtol),
            };
            let mut e = evaluate(p, &map, opts, theta, rtol)?;
            used.set(used.get() + e.steps);
            let r: Vec<f64> = e.model_mu.iter().zip(&data).zip(&p.weights).map(|((mo, d), w)| w * (mo - d)).collect();
            // kept when it is the smallest sum of squares at full accuracy so far (summed as
            // the search sums it, so the same value decides)
            let ssr = (accuracy == lm::Accuracy::Fine).then(|| r.iter().map(|x| x * x).sum::<f64>());
            let keep = ssr.filter(|s| at_best.borrow().as_ref().is_none_or(|b| *s < b.ssr));
            let mut j = if keep.is_some() { e.raw_j.clone() } else { std::mem::take(&mut e.raw_j) };
            for (row, w) in j.chunks_mut(m.max(1)).zip(&p.weights) {
                row.iter_mut().for_each(|x| *x *= w);
            }
            if let Some(ssr) = keep {
                *at_best.borrow_mut() = Some(AtBest { theta: theta.to_vec(), ssr, eval: e });
            }
            Ok(Eval { r, j })
        };
        let result = lm::minimize_in(start, &bounds, &objective, convergence);
        StartRun { result, steps: used.get(), hit: hit.get(), allowance, at_best: at_best.into_inner() }
    };
    // starting points: the data-derived guess, then Dc and a scaled
    let theta0 = map.theta_of(&map.base);
    let mut starts = vec![theta0.clone()];
    let scale = |name: &str, f: f64| {
        let mut t = theta0.clone();
        for (k, n) in map.free_names().iter().enumerate() {
            if n.starts_with(name) {
                t[k] = if map.is_log(k) { t[k] + f.ln() } else { t[k] * f };
            }
        }
        t
    };
    // several states: start from the one-state optimum, the extra states small and slower, with
    // either sign of b (a strengthening second state is as plausible as a weakening one)
    if opts.laws.len() > 1 && opts.starts > 1 {
        let mut o1 = opts.clone();
        o1.laws.truncate(1);
        // constraints and starting values of the first state and the globals only
        o1.fix.retain(|c| c.max_state() <= 1);
        o1.initial.retain(|(n, _)| n.state().is_none_or(|i| i <= 1));
        // a caller that gives the first state's start (diagnosis: the baseline optimum) spares
        // the nested one-state fit
        let given = |n: ParamName| opts.initial.iter().any(|(x, _)| *x == n);
        let r1 = if given(ParamName::B(1)) && given(ParamName::Dc(1)) && given(ParamName::A) && given(ParamName::Mu0) {
            let f = |i: usize| map.base[i];
            Ok(Params {
                mu0: f(0),
                v0: p.v_init,
                a: f(1),
                b: vec![f(state_offset(0))],
                dc: vec![f(state_offset(0) + 1)],
                k: f(2),
                g: f(3),
                a_slope: f(4),
                laws: vec![],
                law_params: BTreeMap::new(),
                mu0_offsets: vec![],
                alpha: vec![],
                normal_stress: None,
            })
        } else {
            fit(p, &o1).map(|r| {
                used.set(used.get() + r.steps);
                r.params
            })
        };
        if let Ok(r1) = r1 {
            for sign in [1.0, -1.0] {
                let mut full = map.base.clone();
                full[0] = r1.mu0;
                full[1] = r1.a;
                full[2] = r1.k;
                full[3] = r1.g;
                full[4] = r1.a_slope;
                full[state_offset(0)] = r1.b[0];
                full[state_offset(0) + 1] = r1.dc[0];
                for i in 1..opts.laws.len() {
                    full[state_offset(i)] = sign * 0.2 * r1.b[0].abs();
                    full[state_offset(i) + 1] = r1.dc[0] * 10f64.powi(i as i32);
                }
                starts.insert(0, map.theta_of(&full));
            }
        }
    }
    // b of either sign: velocity-strengthening evolution (b < 0) looks like a slow rise after
    // an up-step, which a positive-b start can mistake for a vanishing Dc
    for (name, f) in [("dc", 3.0), ("b", -1.0), ("dc", 0.3), ("a", 1.5), ("dc", 10.0), ("a", 0.7)] {
        starts.push(scale(name, f));
    }
    starts.truncate(opts.starts.max(1) + if opts.laws.len() > 1 { 2 } else { 0 });
    // ln L of the samples the points stand for (bin means leave out their bins' scatter)
    let scale = lm::LnlScale {
        samples: Some(p.samples() as f64),
        ssr_offset: (0..p.used.len()).map(|r| p.weights[r].powi(2) / p.count(r) * p.within(r)).sum(),
    };
    let convergence = opts.search.convergence(opts.max_iter, scale);
    let budget = opts.budget.steps;
    let mut best: Option<lm::LmResult> = None;
    let mut at_best = None;
    // the budget that stopped the best start, if one did: not converged, and said so
    let mut best_hit = None;
    let mut first_err = None;
    let mut failed = 0usize;
    let mut before = used.get();
    // the starts in order, each under the allowance the ones before it leave. Until one start
    // has converged within the budget, each may use all that is left; after the first that
    // has, each later one at most `per_start_factor` times that start's work (a start that
    // wanders into a stiff corner must not hold the fit up). A start that ran away at once is
    // no measure of the work a fit takes: its few steps would starve every later start.
    // `later`: (the share, the index of the start it was measured on, the later starts' runs
    // made side by side)
    let mut later: Option<(u64, usize, Vec<StartRun>)> = None;
    for (i, s) in starts.iter().enumerate() {
        if before >= budget {
            break;
        }
        let share = later.as_ref().map_or(u64::MAX, |(share, _, _)| *share);
        let allowance = (budget - before).min(share);
        let ahead = later.as_mut().and_then(|(_, at, runs)| runs.get_mut(i.checked_sub(*at + 1)?));
        let run = match ahead {
            // run beside the others at the largest allowance any later start can have: the
            // same run as under its own allowance when that is the same, or when it finished
            // below its own without a budget stopping it
            Some(r) if r.allowance == allowance || (r.hit.is_none() && r.steps < allowance) => {
                std::mem::replace(r, StartRun::placeholder())
            }
            _ => run_start(s, allowance, &convergence),
        };
        before += run.steps;
        if later.is_none() && run.result.is_ok() && run.hit.is_none() {
            // the later starts' share, and (with threads) their runs side by side
            let share = (opts.budget.per_start_factor * run.steps.max(1) as f64) as u64;
            let widest = budget.saturating_sub(before).min(share);
            let threads = match opts.threads {
                0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
                t => t,
            };
            let rest = &starts[i + 1..];
            let runs = if threads > 1 && rest.len() > 1 && widest > 0 {
                crate::parallel::par_map(rest, threads, |s| run_start(s, widest, &convergence))
            } else {
                vec![]
            };
            later = Some((share, i, runs));
        }
        match run.result {
            Ok(r) => {
                if best.as_ref().is_none_or(|b| r.ssr < b.ssr) {
                    best_hit = run.hit;
                    best = Some(r);
                    at_best = run.at_best;
                }
            }
            Err(e) => {
                failed += 1;
                first_err.get_or_insert(e);
            }
        }
        if run.hit == Some(BudgetHit::WallClockGuard) {
            break;
        }
    }
    let Some(best) = best else {
        return Err(FitError::Start(
            first_err
                .unwrap_or_else(|| SolveError::Input("the step budget ran out before the first evaluation".into())),
        ));
    };
    Ok(Searched { map, best, best_hit, steps: before, starts: starts.len(), starts_failed: failed, at_best })
}

/// The fit's result at the optimum `s`, evaluated on the points of `p`: curve, residuals,
/// covariance, likelihood. When the search ran on the bin means `searched` of `p`, the
/// covariance is theirs (they carry the samples' information, `bins.rs`) and the curve and
/// residuals come from one plain solve at the samples: their sensitivities would cost m + 1
/// times the output of the curve for nothing the result needs. The Jacobian (and, on every
/// sample, the curve) is the search's own evaluation at the optimum ([`AtBest`]) when it kept
/// one.
fn report(p: &Prepared, searched: Option<&Prepared>, opts: &FitOptions, s: Searched) -> Result<FitResult, FitError> {
    let Searched { map, best, best_hit, steps, starts, starts_failed, at_best } = s;
    // the search's own evaluation at the optimum, or the same solve again
    let at_optimum = |on: &Prepared| match at_best.filter(|b| b.theta == best.theta) {
        Some(b) => Ok(b.eval),
        None => evaluate(on, &map, opts, &best.theta, opts.rtol),
    };
    let m = map.free.len();
    let data: Vec<f64> = p.used.iter().map(|&i| p.record.mu[i]).collect();
    let full = map.full(&best.theta);
    // the curve (and slip rate) at the samples, and the Jacobian for the covariance on the
    // points that carry it
    let (model_mu, slip_rate, raw_j, points, steps) = match searched {
        Some(pb) => {
            let eb = at_optimum(pb).map_err(FitError::Start)?;
            // (where the plain solver fails, the sensitivity solver's curve serves)
            let c = model_at_samples(p, &map, opts, &full).or_else(|_| {
                evaluate(p, &map, opts, &best.theta, opts.rtol).map(|e| AtSamples {
                    mu: e.model_mu,
                    slip_rate: vec![],
                    steps: e.steps,
                })
            });
            let c = c.map_err(FitError::Start)?;
            // σ² from the samples' residuals (below), the Jacobian of the bins with their counts
            (c.mu, c.slip_rate, eb.raw_j, pb, steps + eb.steps + c.steps)
        }
        None => {
            let e = at_optimum(p).map_err(FitError::Start)?;
            let v = model_at_samples(p, &map, opts, &full).map(|c| c.slip_rate).unwrap_or_default();
            (e.model_mu, v, e.raw_j, p, steps + e.steps)
        }
    };
    let resid: Vec<f64> = model_mu.iter().zip(&data).map(|(a, b)| a - b).collect();
    // per sample: a bin mean stands for its count, and the scatter inside it is added back
    let n = p.samples();
    let ssr_raw: f64 = resid.iter().enumerate().map(|(r, x)| p.count(r) * x * x + p.within(r)).sum();
    // σ² from the unweighted residuals
    let s2 = ssr_raw / (n as f64 - m as f64).max(1.0);
    let counts = points.binning.as_ref().map(|b| &b.counts[..]);
    let white = covariance(&raw_j, &points.weights, counts, m, s2);
    let (white_ci95, white_stderr) = intervals(&map, &best.theta, &white);
    let noise = match opts.uncertainty {
        Uncertainty::White => None,
        // residuals of bin means only (the samples are never evaluated): their noise is not the
        // samples' (a bin's white part is σ²/c), and a model fitted to them mistakes that for
        // drift; the white form is stated, and said (`--every-sample` gives the other)
        Uncertainty::NoiseModel if p.binning.is_some() => None,
        Uncertainty::NoiseModel => residual_noise(p, &resid),
    };
    let (cov, ci95, stderr, noise) = match noise {
        Some(model) => {
            let times: Vec<f64> = points.used.iter().map(|&i| points.record.time[i]).collect();
            let cov = covariance_under(&raw_j, &points.weights, counts, &times, m, &model);
            let (ci95, stderr) = intervals(&map, &best.theta, &cov);
            let summary = NoiseSummary {
                white_sd: model.white_variance.sqrt(),
                ar1_sd: model.ar1_variance.sqrt(),
                ar1_tau_s: model.ar1_tau_s,
                drift_share: model.drift_share,
                drift_beta: model.drift_beta,
                n_effective: model.n_effective,
                in_time: model.sampling.is_some(),
                stderr_white: white_stderr,
                ci95_white: white_ci95,
            };
            (cov, ci95, stderr, Some(summary))
        }
        None => (white, white_ci95, white_stderr, None),
    };
    // within 0.1 % of a bound, or on it (a bound at 0, such as α's, is reached exactly by the
    // search, which ends a step on the bound it meets: `lm::minimize_in`)
    let boxes = map.theta_bounds();
    let at_bound: Vec<String> = map
        .free
        .iter()
        .enumerate()
        .filter(|&(k, &i)| {
            let mut f2 = full.clone();
            f2[i] *= 0.999;
            let mut f3 = full.clone();
            f3[i] *= 1.001;
            let on = best.theta[k] <= boxes[k].0 || best.theta[k] >= boxes[k].1;
            on || within_bounds(&map, &f2).is_err() || within_bounds(&map, &f3).is_err()
        })
        .map(|(_, &i)| map.names[i].clone())
        .collect();
    // the likelihood of what the fit minimises: noise σ/w_r at sample r (w normalised to mean
    // square 1; uniform weights give the usual Gaussian likelihood), so that models compared by
    // AIC/BIC are compared on the objective they were fitted to
    let ssr_w: f64 = resid
        .iter()
        .zip(&p.weights)
        .enumerate()
        .map(|(r, (x, w))| (w * x).powi(2) + w * w / p.count(r) * p.within(r))
        .sum();
    let sum_ln_w: f64 = match &p.binning {
        Some(b) => b.sum_ln_w,
        None => p.weights.iter().map(|w| w.ln()).sum(),
    };
    let ll = sum_ln_w - 0.5 * n as f64 * ((2.0 * std::f64::consts::PI * ssr_w / n as f64).ln() + 1.0);
    let kf = (m + 1) as f64;
    let np = map.np;
    let params = Params {
        mu0: full[0],
        v0: p.v_init,
        a: full[1],
        b: (0..map.n_states).map(|i| full[state_offset(i)]).collect(),
        dc: (0..map.n_states).map(|i| full[state_offset(i) + 1]).collect(),
        k: full[2],
        g: full[3],
        a_slope: full[4],
        laws: opts.laws.iter().map(|l| l.name()).collect(),
        law_params: map.law_parameter_values(opts, &full),
        mu0_offsets: full[np..].to_vec(),
        alpha: if p.normal_stress.is_some() || opts.alpha != AlphaFit::Fixed {
            (0..map.n_states).map(|i| full[state_offset(i) + 3]).collect()
        } else {
            vec![]
        },
        normal_stress: p.normal_stress.as_ref().map(|_| p.sigma_ref),
    };
    let mut rows: Vec<SegmentRow> = p
        .segments
        .iter()
        .enumerate()
        .map(|(k, s)| SegmentRow { index: k + 1, kind: s.kind, t0: s.t0, t1: s.t1, v: s.v, n: 0, rms: 0.0 })
        .collect();
    for (r, &sg) in p.seg_of.iter().enumerate() {
        rows[sg].n += p.count(r) as usize;
        rows[sg].rms += p.count(r) * resid[r] * resid[r] + p.within(r);
    }
    rows.iter_mut().for_each(|r| r.rms = if r.n > 0 { (r.rms / r.n as f64).sqrt() } else { 0.0 });
    let curve = Curve {
        time: p.used.iter().map(|&i| p.record.time[i]).collect(),
        load_point: p.used.iter().map(|&i| p.record.load_point[i]).collect(),
        data,
        model: model_mu,
        segment: p.seg_of.clone(),
        slip_rate,
    };
    Ok(FitResult {
        params,
        ci95,
        stderr,
        uncertainty: if noise.is_some() { Uncertainty::NoiseModel } else { Uncertainty::White },
        noise,
        constraints: map.constraints.clone(),
        at_bound,
        rms: (ssr_raw / n as f64).sqrt(),
        n,
        n_free: m,
        log_likelihood: ll,
        aic: 2.0 * kf - 2.0 * ll,
        bic: kf * (n as f64).ln() - 2.0 * ll,
        segments: rows,
        iterations: best.iterations,
        stop_reason: best.reason,
        converged: best_hit.is_none() && best.reason.at_optimum(),
        budget_hit: best_hit,
        steps,
        starts,
        starts_failed,
        loading: opts.loading,
        weighting: opts.weighting,
        curve,
        bins: p.binning.as_ref().map(|_| p.used.len()),
        theta: best.theta.clone(),
        cov_theta: cov.as_slice().to_vec(),
    })
}

/// The noise model of a fit's residuals at their samples' times (`rsf-noise`), or `None` when
/// they are too few to fit one ([`MIN_NOISE_POINTS`]).
fn residual_noise(p: &Prepared, resid: &[f64]) -> Option<NoiseModel> {
    if resid.len() < MIN_NOISE_POINTS || resid.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let times: Vec<f64> = p.used.iter().map(|&i| p.record.time[i]).collect();
    Some(NoiseModel::fit_at(resid, &times).0)
}

/// Fewer residuals than this give no noise model (its spectrum needs a few dozen Fourier
/// ordinates per part): the white form is reported.
const MIN_NOISE_POINTS: usize = 64;

#[cfg(test)]
#[path = "lsq_tests.rs"]
mod tests;
