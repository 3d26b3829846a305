//! The credible models of a design: the diagnosis's models within the window of the best, the
//! best with α when σ may change, each with its covariance (inflated for correlated noise) and
//! its draws.

use super::basis::Basis;
use super::result::DesignModel;
use super::{ALPHA_PRIOR_MEAN, ALPHA_PRIOR_SD, DesignOptions};
use nalgebra::DMatrix;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use rsf_diagnose::{AdequacyVerdict, Cause, noisy};
use rsf_fit::data::Record;
use rsf_fit::fit::{FitError, FitOptions, FitResult, ParamMap, Prepared, parameter_map, prepare};
use rsf_fit::segment::Segment;

/// Attempts per wanted draw before a model makes do with fewer.
const DRAW_ATTEMPTS: usize = 20;

/// A credible model, ready to predict.
pub(super) struct Credible {
    pub(super) info: DesignModel,
    pub(super) opts: FitOptions,
    pub(super) p: Prepared,
    pub(super) map: ParamMap,
    pub(super) theta: Vec<f64>,
    /// S with S Sᵀ = the inflated covariance of θ.
    pub(super) sqrt_cov: DMatrix<f64>,
    pub(super) draws: Vec<Vec<f64>>,
}

/// A credible model before its draws: options, parameters and their covariance (inflated for
/// correlated noise).
pub(super) struct Source {
    pub(super) info: DesignModel,
    pub(super) opts: FitOptions,
    pub(super) theta: Vec<f64>,
    pub(super) cov: DMatrix<f64>,
}

/// The credible models, best first: the model of the diagnosis's cause (the baseline for
/// `none`: a candidate that scores better but failed a check is not yet the answer), and each
/// candidate with a converged fit, no parameter at a bound, an effect the record resolves, and
/// a ΔBIC within the window of the best, its Occam penalty not counted. The other ways of the
/// cause named (the registry's other laws, the mixtures) are candidates too, and while the
/// model named is in doubt (its adequacy untested or failed) those of every cause.
///
/// The window assumes that the best model explains the record. When the adequacy test says it
/// does not (or the diagnosis is `unexplained`), a ΔBIC between wrong models decides nothing:
/// every candidate and law that passes the checks is kept as a rival, so that the design
/// proposes what tells them (and the remainder) apart. When the best model could not be tested,
/// it is not taken as the only credible one either: the next best is kept as its rival.
pub(super) fn credible<'a>(
    d: &Basis<'a>,
    base_opts: &FitOptions,
    o: &DesignOptions,
    notes: &mut Vec<String>,
) -> Vec<(DesignModel, &'a FitResult, FitOptions)> {
    let base_law = base_opts.laws[0].name();
    let entry = |name: String, cause: Cause, extension: String, delta_bic: f64, f: &FitResult| DesignModel {
        name,
        cause,
        extension,
        delta_bic,
        params: f.params.clone(),
        stderr_theta: vec![],
        draws: 0,
    };
    let mut all: Vec<(DesignModel, &FitResult, FitOptions, f64)> = vec![(
        entry("baseline".into(), Cause::None, format!("{base_law} law, one state"), 0.0, d.baseline),
        d.baseline,
        base_opts.clone(),
        0.0,
    )];
    let ln_n = (d.baseline.n.max(3) as f64).ln();
    // the other ways of the cause named (another law, a mixture) are rivals: the law is part
    // of the answer; those of the other causes only while the model named is in doubt (when it
    // explains the record, the design tells the causes apart); for `undecided`, the two causes
    // the record could not tell apart lie within the window of the best, and the design is
    // for telling them apart
    let in_doubt = d.adequacy != AdequacyVerdict::Adequate || matches!(d.cause, Cause::Unexplained | Cause::Undecided);
    for bm in &d.candidates {
        let c = &bm.score;
        if !in_doubt && c.name != c.cause.as_str() && c.cause != d.cause {
            continue;
        }
        if let Some(why) = &c.excluded {
            notes.push(format!("{} left out: {why}", c.name));
            continue;
        }
        let Some((f, oc)) = bm.fit else { continue };
        if !c.converged {
            notes.push(format!("{} left out: its fit did not converge", c.name));
            continue;
        }
        // the parameters it adds, from the two criteria: ΔBIC − ΔAIC = Δk (ln n − 2)
        let dk = ((c.delta_bic - c.delta_aic) / (ln_n - 2.0)).max(0.0);
        all.push((entry(c.name.clone(), c.cause, c.extension.clone(), c.delta_bic, f), f, oc.clone(), dk));
    }
    all.sort_by(|a, b| a.0.delta_bic.total_cmp(&b.0.delta_bic));
    // the model named: the cause's own (not another way of it), the baseline for `none`
    let named = |m: &DesignModel| m.cause == d.cause && (m.cause == Cause::None || m.name == d.cause.as_str());
    let wrong = d.adequacy == AdequacyVerdict::Inadequate || d.cause == Cause::Unexplained;
    let best = all.iter().map(|m| m.0.delta_bic).fold(f64::INFINITY, f64::min);
    // within the window of the best, Occam's penalty for the parameters it adds not counted
    // against it: an extension that gains nothing (the effect where the record never went)
    // stays credible while the best is the baseline
    let within = |m: &DesignModel, dk: f64| named(m) || m.delta_bic - best <= o.credible_dbic + dk * ln_n;
    let mut keep: Vec<bool> = all.iter().map(|(m, _, _, dk)| wrong || within(m, *dk)).collect();
    if wrong {
        notes.push(format!(
            "the model named does not explain the record (adequacy: {}): every candidate and law that fits is kept as a rival, {} models",
            d.adequacy.as_str(),
            all.len()
        ));
    } else if d.adequacy == AdequacyVerdict::Untestable && keep.iter().filter(|k| **k).count() < 2 {
        if let Some(i) = keep.iter().position(|k| !k) {
            keep[i] = true;
            notes.push(format!(
                "the model named could not be tested for adequacy: the next best, {} (ΔBIC {:.1}), is kept as its rival",
                all[i].0.name, all[i].0.delta_bic
            ));
        }
    }
    all.into_iter().zip(keep).filter(|(_, k)| *k).map(|((m, f, oc, _), _)| (m, f, oc)).collect()
}

/// A fitted model's source: its covariance inflated by n/n_eff (correlated residuals carry
/// n_eff samples' worth of information, not n). `None` when the fit has no covariance.
pub(super) fn source(info: DesignModel, fit: &FitResult, opts: FitOptions) -> Option<Source> {
    let m = fit.theta.len();
    if fit.cov_theta.len() != m * m {
        return None;
    }
    let nm = noisy(fit).model;
    let inflate = (fit.curve.data.len() as f64 / nm.n_effective.max(1.0)).max(1.0);
    let cov = DMatrix::from_row_slice(m, m, &fit.cov_theta) * inflate;
    Some(Source { info, opts, theta: fit.theta.clone(), cov })
}

/// The best model with Linker–Dieterich α, for a record that never changed σ: α is free, its
/// value drawn from the lab range ([`ALPHA_PRIOR_MEAN`] ± [`ALPHA_PRIOR_SD`]); the other
/// parameters and their covariance are the best model's (the record cannot tell the two
/// apart: without a change of σ, α does nothing).
pub(super) fn with_alpha(rec: &Record, segs: &[Segment], best: &Source) -> Result<Source, FitError> {
    let base_law = best.opts.laws[0].name();
    let opts = Cause::NormalStressCoupling
        .extend(&best.opts, &base_law)
        .ok_or_else(|| FitError::Setup("the best model already fits α".into()))?;
    let names_best = parameter_map(&prepare(rec, segs, &best.opts)?, &best.opts)?.free_names();
    let names = parameter_map(&prepare(rec, segs, &opts)?, &opts)?.free_names();
    let m = names.len();
    let at = |n: &String| names_best.iter().position(|x| x == n);
    let mut theta = vec![0.0; m];
    let mut cov = DMatrix::zeros(m, m);
    for (i, ni) in names.iter().enumerate() {
        match at(ni) {
            Some(bi) => {
                theta[i] = best.theta[bi];
                for (j, nj) in names.iter().enumerate() {
                    if let Some(bj) = at(nj) {
                        cov[(i, j)] = best.cov[(bi, bj)];
                    }
                }
            }
            None if ni == "alpha1" => {
                theta[i] = ALPHA_PRIOR_MEAN;
                cov[(i, i)] = ALPHA_PRIOR_SD * ALPHA_PRIOR_SD;
            }
            None => return Err(FitError::Setup(format!("internal: {ni} is neither α nor the best model's"))),
        }
    }
    let mut info = best.info.clone();
    info.params.alpha = vec![ALPHA_PRIOR_MEAN; info.params.b.len()];
    info.extension = format!(
        "{} with Linker–Dieterich α: the record never changed σ; α from the lab range {ALPHA_PRIOR_MEAN} ± {ALPHA_PRIOR_SD}",
        if info.name == "baseline" { "the baseline".to_string() } else { format!("the {} model", info.name) }
    );
    info.name = Cause::NormalStressCoupling.as_str().into();
    info.cause = Cause::NormalStressCoupling;
    Ok(Source { info, opts, theta, cov })
}

/// A model with its parameter map, covariance square root and draws.
pub(super) fn prepare_model(
    rec: &Record,
    segs: &[Segment],
    s: Source,
    o: &DesignOptions,
    index: u64,
) -> Result<Credible, FitError> {
    let Source { mut info, opts, theta, cov } = s;
    let p = prepare(rec, segs, &opts)?;
    let map = parameter_map(&p, &opts)?;
    let m = theta.len();
    if map.free_names().len() != m || cov.nrows() != m {
        return Err(FitError::Setup(format!("{}: its fit has no covariance", info.name)));
    }
    let cov = (&cov + cov.transpose()) * 0.5;
    let eig = cov.clone().symmetric_eigen();
    let sqrt_cov = &eig.eigenvectors * DMatrix::from_diagonal(&eig.eigenvalues.map(|l| l.max(0.0).sqrt()));
    let mut rng = ChaCha8Rng::seed_from_u64(o.seed.wrapping_mul(0x9E37_79B9).wrapping_add(index));
    // draws outside the physical bounds are drawn again (a truncated normal), up to
    // DRAW_ATTEMPTS per draw wanted: a parameter the record leaves unconstrained keeps the
    // draws that are physical
    let mut draws = vec![];
    for _ in 0..o.draws * DRAW_ATTEMPTS {
        if draws.len() == o.draws {
            break;
        }
        let z = nalgebra::DVector::from_fn(m, |_, _| StandardNormal.sample(&mut rng));
        let dz = &sqrt_cov * z;
        let th: Vec<f64> = theta.iter().zip(dz.iter()).map(|(a, b)| a + b).collect();
        if map.in_bounds(&th) {
            draws.push(th);
        }
    }
    info.stderr_theta = map.free_names().into_iter().zip((0..m).map(|k| cov[(k, k)].sqrt())).collect();
    info.draws = draws.len();
    Ok(Credible { info, opts, p, map, theta, sqrt_cov, draws })
}
