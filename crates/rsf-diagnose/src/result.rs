//! What a diagnosis returns.

use super::{Cause, Effect, EventFit, NullCalibration, Reconstruction, TimingMask};
use rsf_fit::fit::{FitOptions, FitResult};
use serde::Serialize;

/// Numbers from the baseline residuals that point at causes.
#[derive(Clone, Debug, Serialize)]
pub struct Evidence {
    /// Lag-one autocorrelation of the baseline residuals.
    pub residual_lag1: f64,
    /// Effective number of independent samples for a slow effect under the fitted noise
    /// model, n σ²/S(1/n): n (1 − ρ)/(1 + ρ) for AR(1) noise, far less under 1/f drift.
    pub n_effective: f64,
    /// The baseline residuals' noise model, fitted to their spectrum: white, AR(1) and drift
    /// parts with standard errors, the drift's share of the variance, and the binned
    /// periodogram with the model's power (the report's residual-spectrum figure).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise: Option<super::NoiseModel>,
    /// Slope of the residuals against load-point displacement (friction per µm) and its t value.
    pub residual_trend_per_um: f64,
    /// t statistic of that slope with n_eff.
    pub residual_trend_t: f64,
    /// Largest per-segment rms over the median per-segment rms.
    pub segment_rms_ratio: f64,
    /// Baseline misfit over the noise estimated from sample-to-sample differences.
    pub misfit_over_noise: f64,
    /// Slope of the baseline residuals against ln V (model slip rate): a law that heals too
    /// fast or too slowly at low slip rates leaves residuals that trend with ln V.
    pub residual_vs_ln_v: Option<f64>,
    /// Its t value with n_eff.
    pub residual_vs_ln_v_t: Option<f64>,
    /// Per-event refits: spread of ln Dc between events in units of its standard error
    /// (reduced χ²; ≈ 1 when one Dc serves every step and hold).
    pub dc_consistency_chi2: Option<f64>,
    /// Slope of ln Dc against ln(V_after/V_before) over the velocity steps (the Aging law fitted
    /// with one Dc to Slip-law steps, or the reverse, gives Dc that depends on step direction).
    pub dc_vs_ln_step: Option<f64>,
    /// Slope of ln Dc against ln(hold duration) over the holds.
    pub dc_vs_ln_hold: Option<f64>,
    /// Machine stiffness (1/µm) from the elastic reloading slope at up-steps and reslides
    /// (median over events; the reload-slope method): a nominal k far from it points at
    /// `stiffness`.
    pub k_reload_slope: Option<f64>,
}

/// One candidate extension and its score.
#[derive(Clone, Debug, Serialize)]
pub struct Candidate {
    /// The cause this candidate extension stands for.
    pub cause: Cause,
    /// What was changed.
    pub extension: String,
    /// ΔBIC with n_eff (negative: better than the baseline).
    pub delta_bic: f64,
    /// ΔAIC with n_eff.
    pub delta_aic: f64,
    /// rms(extended) / rms(baseline).
    pub rms_ratio: f64,
    /// Held-out rms of the baseline and of this extension.
    pub heldout_rms_before: Option<f64>,
    /// Held-out rms of the extension.
    pub heldout_rms_after: Option<f64>,
    /// ΔBIC of the extension over the baseline on the held-out test's training part alone:
    /// not decisive means the training part holds no evidence of the effect (e.g. a cut-off
    /// that only the last, longest hold reaches), and the held-out prediction then tests an
    /// unconstrained parameter, not overfitting.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub heldout_training_gain: Option<f64>,
    /// The held-out test cannot judge this candidate: its training part is blind to the effect
    /// by construction (a cut-off whose fitted Vc lies far below every slip rate of the training
    /// part) and shows no decisive gain, or it never saw a change of σ that the held-out part
    /// holds; while the full record shows ten times the decisive gain. Its worse prediction
    /// then does not set it aside (the null calibration judges it, at a stricter level).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub heldout_uninformative: bool,
    /// Share of the extended fit's residual variance in slow drift (its own noise model): a
    /// slip trend that leaves drift behind is not told from the drift's slowest part.
    pub drift_share_after: f64,
    /// The effect's parameters (e.g. `b2`, `dc2`; `vc`; `g`; `k`; `law`).
    pub effect: Effect,
    /// Other laws (one state, fitted the same way) that explain the record as well as the one
    /// named: ΔBIC within the decisive threshold of the best. The record cannot tell them apart
    /// (e.g. PRZ and power-law aging at n = 2 with Dc doubled, which are the same model); the one
    /// named is the simplest, and these have more free parameters. With
    /// [`Candidate::law_undecided`], the laws as simple as each other instead, the one fitted first.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub equally_good_laws: Vec<String>,
    /// Set when another law the record cannot tell from the one fitted has as few free
    /// parameters: no law is named (`effect` carries none; `equally_good_laws` lists those as
    /// simple, the one fitted and shown first). Otherwise the law named is the
    /// one of fewest free parameters among those the record cannot tell apart (PRZ before
    /// power-law aging with its exponent free).
    pub law_undecided: bool,
    /// The cause's other ways (the evolution law's other laws of the registry and mixtures),
    /// each fitted like the one chosen and scored against the baseline: the rivals a design
    /// keeps when the model named does not explain the record (`rsf design`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub alternatives: Vec<Alternative>,
    /// The cause's ways that could not be fitted from any start (their model could not be
    /// evaluated from the baseline's optimum nor from the steadier starts, or every start
    /// failed): not among its ways, named so that their absence is seen (e.g.
    /// `evolution law: PRZ law instead of slip`). Empty when every way was fitted.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub unfitted_ways: Vec<String>,
    /// The adequacy test's excess for this extension's fit (1: its event windows look like
    /// noise; `diagnose/adequacy.rs`); NaN where untestable.
    pub adequacy_excess: f64,
    /// Integrator steps of the candidate's fits (its work; deterministic, unlike wall time).
    pub steps: u64,
    /// Its gain against the null distribution under the baseline (decisive, credible
    /// candidates only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub null: Option<NullCalibration>,
    /// Free parameters of its fit that ended at a physical bound (such a candidate is not
    /// named: the data do not constrain it).
    pub at_bound: Vec<String>,
    /// Set when the effect, though decisive, is below what the record or the lab's nominal
    /// values resolve: a fitted stiffness within [`super::STIFFNESS_SIGMAS`] stated uncertainties
    /// of the nominal, or an added state with Dc shorter than the slip between two samples at the
    /// fastest rate. Such a candidate is not named.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unresolved: Option<String>,
    /// Whether its fit reached an optimum (LM's tests, not its iteration limit or a budget); one
    /// that did not is not named.
    pub converged: bool,
    /// The fit; in JSON its parameters, `params` (what `rsf design --from` refits from).
    #[serde(rename = "params", serialize_with = "params_of", skip_serializing_if = "Option::is_none")]
    pub fit: Option<FitResult>,
    /// Its held-out training fit (the start of a combination's held-out fit).
    #[serde(skip)]
    pub heldout_fit: Option<FitResult>,
    /// The options it was fitted with (the base of combinations).
    #[serde(skip)]
    pub options: Option<FitOptions>,
}

/// Another way of a candidate's cause (another law, or a mixture), fitted the same way.
#[derive(Clone, Debug, Serialize)]
pub struct Alternative {
    /// What was changed.
    pub extension: String,
    /// ΔBIC with n_eff against the baseline.
    pub delta_bic: f64,
    /// ΔAIC with n_eff against the baseline.
    pub delta_aic: f64,
    /// Whether its fit reached an optimum.
    pub converged: bool,
    /// The fit; in JSON its parameters, `params`.
    #[serde(rename = "params", serialize_with = "params_of_fit")]
    pub fit: FitResult,
    /// The options it was fitted with.
    #[serde(skip)]
    pub options: FitOptions,
}

fn params_of_fit<S: serde::Serializer>(fit: &FitResult, s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&fit.params, s)
}

/// A candidate's fit in JSON: its parameters.
fn params_of<S: serde::Serializer>(fit: &Option<FitResult>, s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&fit.as_ref().map(|f| &f.params), s)
}

/// The gain of the chosen extension.
#[derive(Clone, Debug, Serialize)]
pub struct Gain {
    /// ΔBIC with n_eff.
    pub delta_bic: f64,
    /// ΔAIC with n_eff.
    pub delta_aic: f64,
    /// rms ratio.
    pub rms_ratio: f64,
    /// Held-out rms before.
    pub heldout_rms_before: Option<f64>,
    /// Held-out rms after.
    pub heldout_rms_after: Option<f64>,
}

/// A second cause found on top of the first.
#[derive(Clone, Debug, Serialize)]
pub struct Secondary {
    /// The second cause.
    pub cause: Cause,
    /// ΔBIC_eff of the combined model against the first extension alone.
    pub delta_bic: f64,
    /// rms(combined) / rms(first extension).
    pub rms_ratio: f64,
    /// Held-out rms of the first extension and of the combination.
    pub heldout_rms_before: Option<f64>,
    /// Held-out rms of the combination.
    pub heldout_rms_after: Option<f64>,
    /// Effect parameters of the combined fit.
    pub effect: Effect,
    /// The combined fit.
    pub fit: FitResult,
    /// The options it was fitted with (the level and quiet tests' fit effect).
    #[serde(skip)]
    pub options: Option<FitOptions>,
}

/// The diagnosis.
#[derive(Clone, Debug, Serialize)]
pub struct Diagnosis {
    /// What the baseline gets wrong (`none` when no extension earns its parameters).
    pub cause: Cause,
    /// The decisive statistic: ΔBIC_eff of the chosen extension (or of the best candidate for `none`).
    pub confidence: f64,
    /// Human-readable reason.
    pub reason: String,
    /// Residual evidence.
    pub evidence: Evidence,
    /// Baseline fit.
    pub baseline: FitResult,
    /// Extended fit (absent for `none`).
    pub extended: Option<FitResult>,
    /// Gain of the extension.
    pub gain: Option<Gain>,
    /// Effect parameters of the chosen extension (for `unexplained`, of the best partial one).
    pub effect: Effect,
    /// For `unexplained`: the extension that helps most though its model still misfits; for
    /// `undecided`: the better-scoring of the two (its fit is `extended`, its gain `gain`, its
    /// parameters `effect`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub partial: Option<Cause>,
    /// The adequacy test of the model named (the baseline for `none`; the best partial
    /// extension's, or the baseline's, for `unexplained`): whether it explains the record's
    /// events to the noise level, and where it does not.
    pub adequacy: super::Adequacy,
    /// For `unexplained` on a record whose adequacy could not be tested: the candidate that
    /// scored better than the one chosen on the whole record but predicted its held-out part
    /// worse than the baseline ([`Disagreement`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub disagreement: Option<Disagreement>,
    /// Runner-up cause and its ΔBIC_eff.
    pub runner_up: Option<(Cause, f64)>,
    /// For `undecided`: the two causes the record does not tell apart (both decisive and
    /// credible, within [`super::UNDECIDED_DBIC`], or, the model chosen untestable, with a lead that
    /// does not hold by [`Diagnosis::lead`], or a rival set aside only because its fit did not
    /// converge that scores better than the one chosen), the one chosen first (whose fit, gain
    /// and effect the diagnosis gives), with their ΔBIC. Empty otherwise.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub undecided: Vec<(Cause, f64)>,
    /// For `undecided`: why the record does not tell the two apart ([`Apart`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub apart: Option<Apart>,
    /// The lead of the cause chosen over the best other credible, decisive candidate against
    /// its chance spread (`lead.rs`), when there is one: where the model chosen could not be tested
    /// against the noise, a lead that does not hold at the false-alarm level leaves the verdict
    /// `undecided` between the two.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lead: Option<super::Lead>,
    /// The candidate causes none of whose ways could be fitted from any start: not among
    /// `candidates`, named so that their absence is seen (a cause some of whose ways failed
    /// lists them in its [`Candidate::unfitted_ways`]). Empty when every cause was fitted.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub unfitted_causes: Vec<Cause>,
    /// Slow drift in the residuals of the model named (the baseline's for `none`), when the
    /// noise model finds one holding at least
    /// [`super::DRIFT_NOTE_SHARE`] of their variance: a property of the record (gouge layer,
    /// temperature, servo or sensor drift) that the cause, if any, is named despite.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise_drift: Option<NoiseDrift>,
    /// All candidates.
    pub candidates: Vec<Candidate>,
    /// A second cause that decisively improves on the first extension, when one does.
    pub secondary: Option<Secondary>,
    /// Per-event refits of the baseline law.
    pub per_segment: Vec<EventFit>,
    /// Held-out split time, s.
    pub heldout_split_t: f64,
    /// A protocol-reconstruction problem found before physics was blamed (the diagnosis then
    /// used record loading).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reconstruction: Option<Reconstruction>,
    /// Samples left out because the protocol's break times are uncertain (a noisy load point).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub timing: Option<TimingMask>,
    /// Times (s) of isolated single-sample spikes left out of every fit
    /// ([`rsf_fit::data::isolated_spikes`]).
    pub spikes_removed: Vec<f64>,
    /// The loading the diagnosis used.
    pub loading: rsf_fit::fit::LoadingMode,
    /// The baseline's fit options as the diagnosis settled them (uniform weights, its loading,
    /// any samples left out): each candidate's `options` is this with its extension applied.
    #[serde(skip)]
    pub baseline_options: Option<FitOptions>,
}

/// Why a record is `undecided` between two causes ([`Diagnosis::undecided`]): decided once, in
/// the diagnosis, and put in words by each edge (the reason, the report).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Apart {
    /// Both decisive and credible, within [`super::UNDECIDED_DBIC`] of each other.
    Margin,
    /// Further apart, but the model chosen could not be tested against the noise and its lead
    /// does not hold at the false-alarm level ([`Diagnosis::lead`]).
    Lead,
    /// The second, set aside only because its fit did not converge, scores better than the one
    /// chosen even at a point short of its optimum.
    Unconverged,
    /// The second's law, reshaped (the form test, [`super::FormTest`]), explains the record
    /// decisively better than the model chosen, by no more than the record's noise gives it: a
    /// model without the cause chosen does as well as the model with it.
    Form,
}

rsf_core::vocabulary!(Apart, "undecided reason", {
    Margin => "margin",
    Lead => "lead",
    Unconverged => "unconverged",
    Form => "form",
});

/// How much slow drift a record's residuals carry (the noise model's power-law part).
#[derive(Clone, Debug, Serialize)]
pub struct NoiseDrift {
    /// Its rms, friction units.
    pub rms: f64,
    /// Its share of the residual variance.
    pub share: f64,
    /// The spectral exponent β of S ∝ f^(−β).
    pub beta: f64,
}

impl NoiseDrift {
    /// The drift in words, for the diagnosis's reason: counted as noise, or — when the quiet
    /// test finds it to be misfit (`misfit`, `quiet.rs`) — said to be misfit.
    pub fn words(&self, misfit: bool) -> String {
        let (what, how) = if misfit {
            ("a slow part", "which their noise model reads as drift but the quiet stretches show to be misfit")
        } else {
            ("slow drift", "counted as noise")
        };
        format!(
            "the residuals carry {what} (spectrum ∝ f^-{:.1}, rms {:.1e}, {:.0}% of their variance), {how}",
            self.beta,
            self.rms,
            100.0 * self.share
        )
    }
}

/// Two extensions that disagree about the record: `better` scores better on the whole record
/// but predicts the held-out part worse than the baseline (or cannot be fitted to the training
/// part), while the one chosen predicts it no worse than the baseline does. A record whose
/// adequacy cannot be tested gets no cause named then (`unexplained`): a model that explained the
/// record would do both, and the better-scoring one fitting the whole record better and
/// predicting worse is what a model missing something does (`diagnose/decide.rs`,
/// `disagreement`).
#[derive(Clone, Debug, Serialize)]
pub struct Disagreement {
    /// The better-scoring cause.
    pub better: Cause,
    /// Its extension, in words.
    pub extension: String,
    /// Its ΔBIC on the whole record.
    pub delta_bic: f64,
    /// The baseline's held-out rms.
    pub heldout_rms_before: Option<f64>,
    /// Its held-out rms (absent when its training fit failed).
    pub heldout_rms_after: Option<f64>,
}
