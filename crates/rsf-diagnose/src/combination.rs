//! A second cause on top of the one named: the winner combined with the other credible
//! candidates, each combination fitted from both optima and scored against the winner alone.

use super::candidate::Ctx;
use super::cause::effect_of;
use super::decide::{heldout_ok, ineligible, merge};
use super::evidence::{noisy, scores};
use super::heldout::heldout;
use super::{Candidate, DECISIVE, Secondary};
use rsf_fit::fit::{FitOptions, FitResult, Prepared, prepare};
use rsf_fit::parallel::par_map;

/// A second cause: the winner combined with the two best other credible candidates (further
/// ones explain less and cost as much), scored against the winner alone with the winner's n_eff.
pub(super) fn secondary(ctx: &Ctx, c1: &Candidate, decisive: &[&Candidate], level: f64) -> Option<Secondary> {
    let f1 = c1.fit.as_ref()?;
    let others: Vec<&Candidate> =
        decisive.iter().copied().filter(|c| ineligible(c, level).is_none() && c.cause != c1.cause).take(2).collect();
    let nf1 = noisy(f1);
    let o1 = c1.options.clone()?;
    let threads = ctx.opts.threads;
    // the combinations' fits on the whole record and their held-out tests, all side by side
    // (each held-out fit starts from the two training optima, never from a fit that saw the
    // held-out part)
    let jobs: Vec<(usize, bool)> = (0..others.len())
        .map(|i| (i, false))
        .chain((0..others.len()).filter(|_| ctx.opts.heldout).map(|i| (i, true)))
        .collect();
    enum Part {
        Full(Option<Box<(FitOptions, FitResult)>>),
        Heldout(Option<f64>),
    }
    let parts = par_map(&jobs, threads, |&(i, held_out)| {
        let c2 = others[i];
        let Some(o) = c2.cause.extend(&o1, &ctx.base_law) else {
            return if held_out { Part::Heldout(None) } else { Part::Full(None) };
        };
        let Ok(pc) = prepare(ctx.rec, ctx.segs, &o) else {
            return if held_out { Part::Heldout(None) } else { Part::Full(None) };
        };
        if held_out {
            let ho = match (&c1.heldout_fit, &c2.heldout_fit) {
                (Some(ft1), Some(ft2)) => {
                    let from = merge(&ft1.params, &ft2.params, c2.cause);
                    let train = |pt: &Prepared, ot: &FitOptions| ctx.fit_best(pt, ot, &from, 1);
                    heldout(&pc.record, &pc.segments, &o, &train, ctx.t_split).map(|h| h.0)
                }
                _ => None,
            };
            return Part::Heldout(ho);
        }
        // from both optima: the winner's, with the added extension's parameters from its own
        // fit (no second Vc profile, no second search for a soft machine)
        let from = c2.fit.as_ref().map_or_else(|| f1.params.clone(), |f2| merge(&f1.params, &f2.params, c2.cause));
        Part::Full(ctx.fit_best(&pc, &o, &from, 1).map(|f| Box::new((o, f))))
    });
    let (full, held): (Vec<Part>, Vec<Part>) = parts.into_iter().partition(|p| matches!(p, Part::Full(_)));
    let held: Vec<Option<f64>> = held.into_iter().map(|p| if let Part::Heldout(h) = p { h } else { None }).collect();
    let tries: Vec<Option<Secondary>> = full
        .into_iter()
        .enumerate()
        .map(|(i, p)| {
            let Part::Full(Some(b)) = p else { return None };
            let (o, f) = *b;
            let c2 = others[i];
            let (dbic, _) = scores(f1, &nf1, &f, &noisy(&f));
            Some(Secondary {
                cause: c2.cause,
                delta_bic: dbic,
                rms_ratio: f.rms / f1.rms,
                heldout_rms_before: c1.heldout_rms_after,
                heldout_rms_after: held.get(i).copied().flatten(),
                // a law left unnamed on its own is not named in a combination either
                effect: if [c1, c2].iter().any(|c| c.law_undecided) {
                    effect_of(&[c1.cause, c2.cause], &f).without_law()
                } else {
                    effect_of(&[c1.cause, c2.cause], &f)
                },
                fit: f,
                options: Some(o),
            })
        })
        .collect();
    tries
        .into_iter()
        .flatten()
        .filter(|s| {
            s.delta_bic < DECISIVE
                && heldout_ok(s.heldout_rms_before, s.heldout_rms_after)
                && s.fit.at_bound.iter().all(|n| f1.at_bound.contains(n))
                // a second cause the record cannot resolve is not named, as a first is not
                && ctx.unresolved(s.cause, &s.fit).is_none()
        })
        .min_by(|a, b| a.delta_bic.total_cmp(&b.delta_bic))
}
