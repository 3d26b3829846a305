//! One candidate extension: fitting it from the baseline (with the stiffness's softer
//! starts), choosing among its ways, scoring it, and its held-out test. Its null calibration is
//! in `null.rs`, a second cause on top of the first in `combination.rs`.

use super::cause::{Cause, builtin, effect_of, library_laws, other_law};
use super::decide::BLIND_DECISIVE;
use super::evidence::{Noisy, Scored, best_lls, noisy, scores, scores_of};
use super::heldout::heldout;
use super::starts::fit_from;
use super::{Alternative, Candidate, DECISIVE, DiagnoseOptions, Evidence, STIFFNESS_SIGMAS};
use rsf_fit::data::Record;
use rsf_fit::fit::{Budget, FitOptions, FitResult, Params, Prepared, prepare};
use rsf_fit::segment::Segment;
use rsf_laws::Law;
use rsf_noise::NoiseModel;

/// A cut-off's healing term e^(−V/Vc) is e^(−10) ≈ 5e-5 of its full size at V = 10 Vc: a
/// training part whose slip rates all stay above this multiple of the fitted Vc cannot see it.
const TRAINING_BLIND_FACTOR: f64 = 10.0;

/// A candidate's held-out training fit may do this many times the work of the baseline's
/// training fit, and at least `HELDOUT_MIN_STEPS` integrator steps. (On the 60–75k-row records
/// of docs/BENCHMARKS.md the candidates' training fits took 0.1–4.3 times the baseline's
/// training fit, 7,000–280,000 steps: the cap stops only a runaway.) Known before any
/// candidate is fitted, so that each held-out test runs beside its candidate's fit.
const HELDOUT_WORK_FACTOR: f64 = 20.0;
const HELDOUT_MIN_STEPS: u64 = 1_000_000;

/// An extension fitted to the whole record: which way (`extension`, options `o`), the fit and
/// its residuals' noise.
pub(super) struct FullFit {
    pub(super) extension: String,
    pub(super) o: FitOptions,
    pub(super) f: FitResult,
    pub(super) nf: Noisy,
    /// ΔBIC and ΔAIC against the baseline, every fit scored under the same noise models
    /// ([`rescore`]).
    pub(super) score: (f64, f64),
    /// The noise of each of `others`, in their order.
    pub(super) others_noise: Vec<Noisy>,
    /// Other one-law ways of the cause that explain the record as well (see
    /// [`Candidate::equally_good_laws`]).
    pub(super) alike: Vec<String>,
    /// Whether one of `alike` is as simple as the way chosen (see
    /// [`Candidate::law_undecided`]).
    pub(super) undecided: bool,
    /// The cause's other ways, fitted the same way (see [`Candidate::alternatives`]).
    pub(super) others: Vec<Alternative>,
    /// The ways that could not be fitted from any start (see [`Candidate::unfitted_ways`]).
    pub(super) unfitted: Vec<String>,
}

impl FullFit {
    /// Replaces the fit by `f`, with its noise; [`rescore`] scores it.
    pub(super) fn replace(&mut self, f: FitResult) {
        self.nf = noisy(&f);
        self.f = f;
    }
}

/// Scores every cause's fits — the way each chose and its other ways — and the baseline
/// `base` (noise `bn`) under the best of all the noise models fitted to any of them
/// ([`best_lls`]), so that the candidates' ΔBIC compare with one another on one footing.
pub(super) fn rescore<'a>(base: &FitResult, bn: &Noisy, fulls: impl Iterator<Item = &'a mut FullFit>) {
    let mut fulls: Vec<&mut FullFit> = fulls.collect();
    let scored = {
        let rulers: Vec<&NoiseModel> = std::iter::once(&bn.model)
            .chain(
                fulls
                    .iter()
                    .flat_map(|ff| std::iter::once(&ff.nf.model).chain(ff.others_noise.iter().map(|n| &n.model))),
            )
            .collect();
        let all: Vec<(&FitResult, Scored)> = std::iter::once((base, Scored::of(bn)))
            .chain(fulls.iter().flat_map(|ff| {
                std::iter::once((&ff.f, Scored::of(&ff.nf)))
                    .chain(ff.others.iter().zip(&ff.others_noise).map(|(a, n)| (&a.fit, Scored::of(n))))
            }))
            .collect();
        best_lls(&all, &rulers)
    };
    let sb = scored[0];
    let mut next = scored[1..].iter();
    for ff in fulls.iter_mut() {
        let Some(&se) = next.next() else { return };
        ff.score = scores_of(base, sb, &ff.f, se);
        for a in ff.others.iter_mut() {
            let Some(&se) = next.next() else { return };
            (a.delta_bic, a.delta_aic) = scores_of(base, sb, &a.fit, se);
        }
    }
}

/// A free stiffness fitted from the nominal k that stays above this fraction of it has not
/// moved off the nominal (a stiff nominal leaves no gradient in k): softer starts are tried.
const K_STUCK_FRACTION: f64 = 0.8;
/// The softer starting stiffnesses, as divisors of the nominal: series compliance of gouge and
/// assembly only ever softens a machine, by up to an order of magnitude in lab rigs.
const K_SOFTER_STARTS: [f64; 2] = [4.0, 16.0];
/// The reload-slope k is a further start when it differs from the nominal by more than this
/// in ln k (22%): closer, the nominal start already covers it.
const K_RELOAD_LN_DIFF: f64 = 0.2;
/// What the candidates share: the record, the baseline and its evidence.
pub(super) struct Ctx<'a> {
    pub(super) rec: &'a Record,
    pub(super) segs: &'a [Segment],
    pub(super) opts: &'a DiagnoseOptions,
    /// Baseline options (uniform weights, the loading the diagnosis settled on).
    pub(super) base_opts: FitOptions,
    /// Candidate options: a third of the baseline's budget each.
    pub(super) cand_opts: FitOptions,
    pub(super) base_law: String,
    pub(super) p: Prepared,
    pub(super) base: FitResult,
    /// The baseline residuals' fitted noise and their likelihood under it.
    pub(super) base_noise: Noisy,
    pub(super) ev: Evidence,
    /// The baseline's slip rates, µm/s (the span of the Vc profile).
    pub(super) v_range: (f64, f64),
    pub(super) t_split: f64,
    /// The record's σ drives the model and first changes in the held-out part: the held-out
    /// test cannot judge the candidates (`heldout::sigma_first_changes_after`).
    pub(super) sigma_held_out: bool,
    /// The baseline's held-out rms and training fit.
    pub(super) ho_base: Option<(f64, FitResult)>,
    /// The noise fitted to the baseline's training residuals (the extensions' training gains
    /// are scored against it).
    pub(super) ho_base_noise: Option<Noisy>,
    /// Load-point noise about the protocol, µm, when it matters for the break times: the null
    /// replicates then re-segment their own noisy load point.
    pub(super) lp_noise: Option<f64>,
    /// Load-point noise about the protocol's lines, µm (the adequacy test's break-time
    /// uncertainty).
    pub(super) load_point_sigma: f64,
}

impl Ctx<'_> {
    /// Fits the model `o` on `pc` from the nested optimum `from`; a free stiffness also from the
    /// reload-slope k and softer machines (a stiff nominal k leaves no gradient in k, and series
    /// compliance of gouge and assembly only ever softens a machine).
    pub(super) fn fit_best(&self, pc: &Prepared, o: &FitOptions, from: &Params, threads: usize) -> Option<FitResult> {
        let first = fit_from(pc, o, from, self.v_range, threads);
        // only when the fit from the nominal k did not soften the machine: then the nominal may
        // sit where k has no gradient
        let stuck = first.as_ref().is_none_or(|f| f.params.k > K_STUCK_FRACTION * from.k);
        // (a start that already has a fitted k, e.g. a combination's, is not at the nominal)
        let at_nominal = from.k == self.base_opts.stiffness;
        if !(o.fit_stiffness && !self.base_opts.fit_stiffness && stuck && at_nominal) {
            return first;
        }
        let mut ks: Vec<f64> = K_SOFTER_STARTS.iter().map(|d| from.k / d).collect();
        ks.extend(self.ev.k_reload_slope.filter(|k| (k / from.k).ln().abs() > K_RELOAD_LN_DIFF));
        ks.into_iter()
            .filter_map(|k| fit_from(pc, o, &Params { k, ..from.clone() }, self.v_range, threads))
            .chain(first)
            .max_by(|a, b| a.log_likelihood.total_cmp(&b.log_likelihood))
    }

    /// The ways to apply `cause`: its extension, and for the evolution law also a mixture (a
    /// state of each law sharing one Dc: healing partly by time, partly by slip).
    pub(super) fn variants(&self, cause: Cause) -> Vec<(String, FitOptions)> {
        cause_variants(cause, &self.cand_opts, &self.base_law)
    }

    /// The best-scoring variant of `cause` fitted to `pc` from `from` (scored against `base`),
    /// with its residuals' fitted noise. A mixture of laws starts from `from` and also from the
    /// other law's optimum with its healing shared half and half: a mixture nests both pure
    /// laws, and when the truth is one (a share of time-dependent healing), the other law's
    /// optimum can lie far closer to it than the baseline's (a Slip-law baseline's a, b and
    /// Dc bend to mimic the holds).
    pub(super) fn fit_cause(
        &self,
        pc_of: &dyn Fn(&FitOptions) -> Option<Prepared>,
        cause: Cause,
        from: &Params,
        base: &FitResult,
        bn: &Noisy,
        threads: usize,
        only: Option<&str>,
    ) -> Option<FullFit> {
        let mut single: Option<Params> = None;
        let mut fitted = vec![];
        let mut unfitted = vec![];
        for (ext, o) in self.variants(cause) {
            // a law of the library is refitted only when it is the way asked for; the classic
            // ways (the other law, the two-state mixture) always
            let library = o.laws.len() == 1
                && o.laws[0].name() != self.base_law
                && o.laws[0].name() != other_law(&self.base_law).name();
            if library && only.is_some_and(|e| e != ext) {
                continue;
            }
            let Some(pc) = pc_of(&o) else {
                unfitted.push(ext);
                continue;
            };
            let mixture = o.laws.len() == 2 && o.laws[0].name() != o.laws[1].name();
            let mut starts = vec![from.clone()];
            if mixture {
                starts.extend(single.as_ref().map(shared_healing));
            }
            // a mixture has both states healing (b of one sign); b of opposite signs is a
            // difference of laws, not a share of time-dependent healing
            let fits: Vec<FitResult> = starts.iter().filter_map(|s| self.fit_best(&pc, &o, s, threads)).collect();
            if fits.is_empty() {
                unfitted.push(ext);
                continue;
            }
            let best = fits
                .into_iter()
                .filter(|f| !mixture || f.params.b[0] * f.params.b[1] > 0.0)
                .max_by(|a, b| a.log_likelihood.total_cmp(&b.log_likelihood));
            let Some(f) = best else { continue };
            if cause == Cause::EvolutionLaw && o.laws.len() == 1 && o.laws[0].name() == other_law(&self.base_law).name()
            {
                single = Some(f.params.clone());
            }
            let en = noisy(&f);
            fitted.push((ext, o, pc, f, en));
        }
        // every way scored under the best of the noise models fitted to any of them and to the
        // baseline (`best_lls`): a comparison of laws is not decided by whose noise estimate
        // landed nearer its maximum
        let rulers: Vec<&NoiseModel> = std::iter::once(&bn.model).chain(fitted.iter().map(|w| &w.4.model)).collect();
        let all: Vec<(&FitResult, Scored)> =
            std::iter::once((base, Scored::of(bn))).chain(fitted.iter().map(|w| (&w.3, Scored::of(&w.4)))).collect();
        let s = best_lls(&all, &rulers);
        let pooled: Vec<(f64, f64)> =
            fitted.iter().zip(&s[1..]).map(|(w, &se)| scores_of(base, s[0], &w.3, se)).collect();
        let mut fitted: Vec<_> = fitted.into_iter().zip(pooled).map(|(w, s)| (s.0, s, w)).collect();
        let best = fitted.iter().enumerate().min_by(|a, b| a.1.0.total_cmp(&b.1.0)).map(|(i, _)| i)?;
        let one_law = |o: &FitOptions| (o.laws.len() == 1).then(|| o.laws[0].name());
        let best_score = fitted[best].0;
        // the one-law ways that the record cannot tell from the best: within the decisive
        // threshold of its score (e.g. PRZ and power-law aging at n = 2, the same model)
        let tied: Vec<usize> = match one_law(&fitted[best].2.1) {
            Some(_) => (0..fitted.len())
                .filter(|&i| one_law(&fitted[i].2.1).is_some() && fitted[i].0 - best_score < -DECISIVE)
                .collect(),
            None => vec![best],
        };
        // of those, the one with the fewest free parameters is named (the best-scoring of them):
        // a law the record cannot tell from a freer one is the simpler claim
        let free = |i: usize| fitted[i].2.3.n_free;
        let chosen =
            tied.iter().copied().min_by(|&a, &b| free(a).cmp(&free(b)).then(fitted[a].0.total_cmp(&fitted[b].0)));
        let chosen = chosen.unwrap_or(best);
        // as simple a law as it that the record cannot tell from it: no law is named, and the
        // laws listed are those as simple (the freer ones stay among the alternatives)
        let undecided = tied.iter().any(|&i| i != chosen && free(i) == free(chosen));
        let alike: Vec<String> = tied
            .iter()
            .filter(|&&i| i != chosen && (!undecided || free(i) == free(chosen)))
            .filter_map(|&i| one_law(&fitted[i].2.1))
            .collect();
        let (_, score, (extension, o, _, f, nf)) = fitted.swap_remove(chosen);
        // the other ways, in the order fitted, each scored against the baseline, with its noise
        let (others, others_noise) = fitted
            .into_iter()
            .map(|(_, (delta_bic, delta_aic), (extension, options, _, fit, nf))| {
                (Alternative { extension, delta_bic, delta_aic, converged: fit.converged, fit, options }, nf)
            })
            .unzip();
        Some(FullFit { extension, o, f, nf, score, others_noise, alike, undecided, others, unfitted })
    }

    /// Whether the held-out test's training part is blind to `cause` as fitted in `f`: a cut-off
    /// acts through e^(−V/Vc), which is below e^(−10) wherever V > 10 Vc; when every modelled
    /// slip rate of the training part stays above that and the training fit gained nothing
    /// decisive, the training part holds no evidence of Vc by construction.
    pub(super) fn training_blind(&self, cause: Cause, f: &FitResult, training_gain: Option<f64>) -> bool {
        if cause != Cause::CutoffVelocity || training_gain.is_none_or(|g| g < DECISIVE) {
            return false;
        }
        let (Some((_, ft_base)), Some(vc)) = (&self.ho_base, f.params.law_params.get("vc1")) else {
            return false;
        };
        let v = &ft_base.curve.slip_rate;
        let v_min = v.iter().copied().fold(f64::INFINITY, f64::min);
        !v.is_empty() && v_min > TRAINING_BLIND_FACTOR * vc
    }

    /// The options of `cause`'s extension when it has one way only: its held-out test can then
    /// run beside its fit on the whole record (the evolution law's two ways wait for the fit to
    /// say which one to test).
    pub(super) fn single_variant(&self, cause: Cause) -> Option<FitOptions> {
        let mut v = self.variants(cause);
        (v.len() == 1).then(|| v.remove(0).1)
    }

    /// The extension `cause` fitted to the whole record from the baseline optimum: its best way.
    pub(super) fn full_fit(&self, cause: Cause) -> Option<FullFit> {
        let pc_of = |o: &FitOptions| prepare(self.rec, self.segs, o).ok();
        self.fit_cause(&pc_of, cause, &self.base.params, &self.base, &self.base_noise, self.opts.threads, None)
    }

    /// The fit on the whole record continued from the held-out test's training optimum `ft`
    /// when that point, which saw only the record's first part, fits the whole record better
    /// than the full fit's own optimum: the full fit stopped in a worse basin (a cut-off whose
    /// Vc profile settled a decade below the truth, record 91 of the 111-record study's seed 2).
    /// The continued fit replaces it only when its likelihood is higher. `None`: nothing better.
    pub(super) fn continued_from_training(&self, full: &FullFit, ft: &FitResult) -> Option<FitResult> {
        let whole = super::heldout::whole_rms(self.rec, self.segs, &full.o, ft, self.t_split)?;
        if !(whole < full.f.rms) {
            return None;
        }
        let pc = prepare(self.rec, self.segs, &full.o).ok()?;
        self.fit_best(&pc, &full.o, &ft.params, 1).filter(|f| f.log_likelihood > full.f.log_likelihood)
    }

    /// The held-out test of the extension `o`: its training fit, from the baseline's training
    /// optimum, under a work cap ([`HELDOUT_WORK_FACTOR`] times the baseline's training fit, at
    /// least [`HELDOUT_MIN_STEPS`]: a training fit wandering into a stiff corner must not
    /// dominate the run).
    pub(super) fn heldout_fit(&self, o: &FitOptions) -> Option<(f64, FitResult)> {
        let (_, ft_base) = self.ho_base.as_ref()?;
        let cap = ((HELDOUT_WORK_FACTOR * ft_base.steps as f64) as u64).max(HELDOUT_MIN_STEPS).min(o.budget.steps);
        let pc = prepare(self.rec, self.segs, o).ok()?;
        heldout(
            &pc.record,
            &pc.segments,
            o,
            &|pt: &Prepared, ot: &FitOptions| {
                let ot = FitOptions { budget: Budget { steps: cap, ..ot.budget }, ..ot.clone() };
                self.fit_best(pt, &ot, &ft_base.params, self.opts.threads)
            },
            self.t_split,
        )
    }

    /// The candidate `cause` from its fit on the whole record and its held-out test.
    pub(super) fn candidate(&self, cause: Cause, full: FullFit, ho: Option<(f64, FitResult)>) -> Candidate {
        let FullFit { extension, o, f, nf, score, alike, undecided, others, unfitted, .. } = full;
        // the laws the record cannot tell apart are named together, none of them alone
        let (extension, alike) = match o.laws.as_slice() {
            [law] if undecided => {
                let laws: Vec<String> = std::iter::once(law.name()).chain(alike).collect();
                (format!("a law other than {} ({})", self.base_law, laws.join(" or ")), laws)
            }
            _ => (extension, alike),
        };
        let (dbic, daic) = score;
        // parameters at a bound that the baseline did not already have there
        let at_bound = f.at_bound.iter().filter(|n| !self.base.at_bound.contains(n)).cloned().collect();
        // the extension's gain on the training part alone
        let training_gain = match (&self.ho_base, &self.ho_base_noise, &ho) {
            (Some((_, ft_base)), Some(nt_base), Some((_, ft))) => Some(scores(ft_base, nt_base, ft, &noisy(ft)).0),
            _ => None,
        };
        Candidate {
            cause,
            extension,
            delta_bic: dbic,
            delta_aic: daic,
            rms_ratio: f.rms / self.base.rms,
            heldout_rms_before: self.ho_base.as_ref().map(|h| h.0),
            heldout_rms_after: ho.as_ref().map(|h| h.0),
            heldout_training_gain: training_gain,
            heldout_uninformative: dbic < BLIND_DECISIVE
                && (self.sigma_held_out || self.training_blind(cause, &f, training_gain)),
            drift_share_after: nf.model.drift_share,
            // a law the record cannot tell from another as simple is not named, nor its parameters
            effect: if undecided { effect_of(&[cause], &f).without_law() } else { effect_of(&[cause], &f) },
            equally_good_laws: alike,
            law_undecided: undecided,
            alternatives: others,
            unfitted_ways: unfitted,
            adequacy_excess: super::adequacy::adequacy(&f, &self.p.segments, self.load_point_sigma, None, None).excess,
            steps: f.steps + ho.as_ref().map_or(0, |h| h.1.steps),
            null: None,
            at_bound,
            unresolved: self.unresolved(cause, &f),
            converged: f.converged,
            fit: Some(f),
            heldout_fit: ho.map(|h| h.1),
            options: Some(o),
        }
    }

    /// Why a decisive effect is no finding: a stiffness within [`STIFFNESS_SIGMAS`] stated
    /// uncertainties of the nominal, or an added state whose Dc is shorter than the slip between two samples at the
    /// fastest load-point rate (the record cannot resolve it: such a state only reshapes the
    /// first sample after a step).
    pub(super) fn unresolved(&self, cause: Cause, f: &FitResult) -> Option<String> {
        let nominal = self.base_opts.stiffness;
        match cause {
            Cause::Stiffness
                if (f.params.k / nominal).ln().abs() < STIFFNESS_SIGMAS * self.opts.stiffness_uncertainty =>
            {
                Some(format!(
                    "k = {:.4e} is {:.1} % from the nominal {nominal:.4e}, inside the nominal's stated uncertainty \
                     ({} × {:.1} %)",
                    f.params.k,
                    100.0 * (f.params.k / nominal - 1.0),
                    STIFFNESS_SIGMAS,
                    100.0 * self.opts.stiffness_uncertainty
                ))
            }
            Cause::SecondStateVariable => {
                let res = self.slip_per_sample();
                let dc = f.params.dc.iter().copied().fold(f64::INFINITY, f64::min);
                (dc < res && self.base.params.dc.iter().all(|&d| d >= res)).then(|| {
                    format!(
                        "added state's Dc = {dc:.3e} µm is shorter than the slip between two samples at the fastest \
                         rate ({res:.3e} µm): the record cannot resolve it"
                    )
                })
            }
            Cause::Stiffness
            | Cause::None
            | Cause::Unexplained
            | Cause::Undecided
            | Cause::EvolutionLaw
            | Cause::CutoffVelocity
            | Cause::SlipTrend
            | Cause::NormalStressCoupling => None,
        }
    }

    /// The load-point slip between two samples at the fastest segment's rate, µm (its median
    /// sampling interval × its velocity).
    fn slip_per_sample(&self) -> f64 {
        let t = &self.p.record.time;
        let Some(s) = self.p.segments.iter().filter(|s| s.i1 > s.i0).max_by(|a, b| a.v.total_cmp(&b.v)) else {
            return 0.0;
        };
        let mut d: Vec<f64> = t[s.i0..=s.i1].windows(2).map(|w| w[1] - w[0]).filter(|d| *d > 0.0).collect();
        d.sort_by(f64::total_cmp);
        d.get(d.len() / 2).map_or(0.0, |dt| s.v * dt)
    }
}

/// A mixture's start from the other law's optimum `p` (one state): the baseline's law and the
/// other law each with half of its healing b, sharing its Dc (the mixture's states are in the
/// order of `cause_variants`: the baseline's law first).
fn shared_healing(p: &Params) -> Params {
    let (b, dc) = (p.b[0], p.dc[0]);
    Params { b: vec![0.5 * b, 0.5 * b], dc: vec![dc, dc], ..p.clone() }
}

/// The ways to apply `cause` to the options `o` of a baseline of `base_law`: its extension, and
/// for the evolution law also a mixture (a state of each law sharing one Dc: healing partly by
/// time, partly by slip); each with its words.
pub fn cause_variants(cause: Cause, o: &FitOptions, base_law: &str) -> Vec<(String, FitOptions)> {
    let mut tries = vec![];
    if let Some(e) = cause.extend(o, base_law) {
        tries.push((cause.describe(base_law), e));
    }
    if cause == Cause::EvolutionLaw {
        let other = other_law(base_law);
        let mut om = o.clone();
        om.laws.push(builtin(other));
        om.fix.push(rsf_fit::fit::Constraint::difference("dc1", "dc2", 0.0));
        tries.push((format!("a mixture: {base_law} and {other} states sharing Dc"), om));
        // the law library: each law for every state of the baseline (one, in a diagnosis)
        for law in library_laws() {
            if law.name() == base_law {
                continue; // the baseline itself (a diagnosis of a library law as baseline)
            }
            let start = library_start(law.builtin(), base_law);
            let Ok(l) = law.build(|p| {
                start.iter().find(|s| s.0 == p).map(|s| s.1).or(law.parameter(p).map(|q| q.start_value(None)))
            }) else {
                continue;
            };
            let mut ol = o.clone();
            if ol.laws.iter().any(|x| x.name() != base_law) {
                continue;
            }
            ol.laws = ol.laws.iter().map(|_| l.clone()).collect();
            tries.push((format!("{} law instead of {base_law}", law.words()), ol));
        }
    }
    tries
}

/// Where a library law's own parameters start from the baseline optimum: the one-state
/// Aging–Slip mixture next to the baseline's own law (w = 0.1 from Slip, 0.9 from Aging; at
/// w = 0 or 1 exactly, every step that leaves the bound would be rejected), the others at
/// their registry starts.
fn library_start(builtin: Option<Law>, base_law: &str) -> Vec<(&'static str, f64)> {
    match builtin {
        Some(Law::AgingSlip) if base_law == Law::Aging.name() => vec![("w", 1.0 - MIXTURE_START_OFF_BOUND)],
        Some(Law::AgingSlip) => vec![("w", MIXTURE_START_OFF_BOUND)],
        Some(Law::Aging | Law::Slip | Law::KatoTullis | Law::Prz | Law::Nagata | Law::AgingNoHealing) | None => vec![],
    }
}

/// The one-state mixture's start this far inside its range from the baseline's own law.
const MIXTURE_START_OFF_BOUND: f64 = 0.1;
