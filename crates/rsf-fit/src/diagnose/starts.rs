//! Fits of an extension from the optimum of a nested model, and the profile of a threshold
//! parameter (the cut-off velocity Vc) over the whole range of slip rates the record reaches.

use super::parallel::par_map;
use crate::fit::{FitOptions, FitResult, ParamName, Params, Prepared, fit, parameter_map};

/// Grid points per decade of the Vc profile: the cut-off's effect switches on over about half
/// a decade of V/Vc (exp(−V/Vc) goes from 0.05 to 0.7 between V = 3 Vc and V = 0.3 Vc).
pub const VC_PROFILE_PER_DECADE: f64 = 2.0;

/// The profile reaches this factor below the slowest and above the fastest model slip rate of
/// the baseline: below every slip rate the cut-off is invisible, above every one it is a
/// constant healing term, and the optimum lies in between.
pub const VC_PROFILE_MARGIN: f64 = 3.0;

/// Levenberg–Marquardt iterations per profile point: from the baseline optimum, with Vc fixed,
/// the other parameters move little; the best points are then refined with Vc free.
const VC_PROFILE_ITERATIONS: usize = 8;

/// `from`'s parameters as starting values for the model `o` on `p`, keeping only the names that
/// model knows (a law parameter or a per-segment offset of the nested model may not be there).
pub(super) fn initial_for(p: &Prepared, o: &FitOptions, from: &Params) -> Option<Vec<(ParamName, f64)>> {
    let map = parameter_map(p, &FitOptions { initial: vec![], fix: vec![], ..o.clone() }).ok()?;
    let free = map.free_names();
    Some(
        from.as_initial()
            .into_iter()
            .filter(|(n, _)| {
                free.iter().any(|x| *x == n.text())
                    || match n {
                        ParamName::Mu0 | ParamName::A | ParamName::K | ParamName::G => true,
                        ParamName::B(i) | ParamName::Dc(i) => *i <= o.laws.len(),
                        ParamName::Alpha(_) | ParamName::Law(..) | ParamName::Mu0Seg(_) => false,
                    }
            })
            .collect(),
    )
}

/// The range of model slip rates (µm/s) of a fit, from its curve.
pub(super) fn slip_rate_range(f: &FitResult) -> Option<(f64, f64)> {
    let v = f.curve.slip_rate.iter().copied().filter(|v| *v > 0.0 && v.is_finite());
    let (lo, hi) = v.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    (lo.is_finite() && hi > 0.0).then_some((lo, hi))
}

/// Fits `o` starting from `from` (an optimum of a nested model). A cut-off velocity new to the
/// model is first profiled on a log grid spanning `v_range` (the baseline's slip rates), with
/// the other parameters fitted at each Vc; the two best grid points then start free fits and the
/// better one wins. A local search from one starting Vc misses a cut-off far below it (where
/// the gradient in Vc vanishes) — e.g. 3e-6 µm/s that only the end of a 10⁴ s hold reaches.
pub(super) fn fit_from(
    p: &Prepared,
    o: &FitOptions,
    from: &Params,
    v_range: (f64, f64),
    threads: usize,
) -> Option<FitResult> {
    let mut o = o.clone();
    o.initial = initial_for(p, &o, from)?;
    let names = parameter_map(p, &FitOptions { initial: vec![], ..o.clone() }).ok()?.free_names();
    if names.iter().any(|x| x == "vc1") && !from.law_params.contains_key("vc1") {
        return profile_vc(p, &o, v_range, threads);
    }
    fit(p, &o).ok()
}

fn profile_vc(p: &Prepared, o: &FitOptions, (vlo, vhi): (f64, f64), threads: usize) -> Option<FitResult> {
    let (l0, l1) = ((vlo / VC_PROFILE_MARGIN).log10(), (vhi * VC_PROFILE_MARGIN).log10());
    let n = ((l1 - l0) * VC_PROFILE_PER_DECADE).ceil().max(1.0) as usize;
    let grid: Vec<f64> = (0..=n).map(|i| 10f64.powf(l0 + (l1 - l0) * i as f64 / n as f64)).collect();
    // each profile point gets an equal share of a third of the candidate's budget
    let point_budget = o.budget.scaled(1.0 / (3.0 * grid.len() as f64));
    let profile = par_map(&grid, threads, |&vc| {
        let mut oc = o.clone();
        oc.fix.push(crate::fit::Constraint::fixed("vc1", vc));
        oc.starts = 1;
        oc.max_iter = VC_PROFILE_ITERATIONS;
        oc.budget = point_budget;
        fit(p, &oc).ok().map(|f| (vc, f.log_likelihood))
    });
    let mut pts: Vec<(f64, f64)> = profile.into_iter().flatten().collect();
    // best first; ties by grid order (deterministic)
    pts.sort_by(|a, b| b.1.total_cmp(&a.1));
    let refined = par_map(&pts[..pts.len().min(2)], threads, |&(vc, _)| {
        let mut oc = o.clone();
        let vc1 = ParamName::Law("vc".into(), 1);
        oc.initial.retain(|(n, _)| *n != vc1);
        oc.initial.push((vc1, vc));
        oc.starts = 1;
        oc.budget = o.budget.scaled(1.0 / 3.0);
        fit(p, &oc).ok()
    });
    refined.into_iter().flatten().max_by(|a, b| a.log_likelihood.total_cmp(&b.log_likelihood))
}
