//! What a design returns.

use super::space::Proposal;
use super::standard::StandardKind;
use rsf_diagnose::{Cause, NoiseModel};
use rsf_fit::fit::Params;
use serde::Serialize;

/// One credible model.
#[derive(Clone, Debug, Serialize)]
pub struct DesignModel {
    /// `baseline`, or the cause the extension stands for.
    pub name: String,
    /// The cause (`none` for the baseline).
    pub cause: Cause,
    /// The extension in words.
    pub extension: String,
    /// Its ΔBIC against the baseline in the diagnosis.
    pub delta_bic: f64,
    /// Its fitted parameters.
    pub params: Params,
    /// Its free parameters' standard errors as used by the design (the fit's, inflated by
    /// √(n/n_eff) for correlated noise), in fit order, transformed scale (ln for log-fitted).
    pub stderr_theta: Vec<(String, f64)>,
    /// Draws from its covariance that were inside the physical bounds and solved.
    pub draws: usize,
}

/// The expected discrimination of one pair of models by a proposal.
#[derive(Clone, Debug, Serialize)]
pub struct PairScore {
    /// One model.
    pub a: String,
    /// The other.
    pub b: String,
    /// The expected Δχ² between them: the mean of the rival's expected lack of fit with each
    /// one true.
    pub dchi2: f64,
}

/// A scored proposal.
#[derive(Clone, Debug, Serialize)]
pub struct Ranked {
    /// 1-based rank (0 for an unranked comparison, the standard segment).
    pub rank: usize,
    /// `step`, `hold`, `normal_stress` or `sequence`.
    pub kind: &'static str,
    /// In words.
    pub description: String,
    /// The proposal.
    pub proposal: Proposal,
    /// Its protocol segments: (load-point velocity µm/s, duration s).
    pub segments: Vec<(f64, f64)>,
    /// The normal stress at the end of each segment over the record's (1: unchanged); a change
    /// is a linear ramp through its segment.
    #[serde(rename = "normal_stress_ratio")]
    pub normal_stress: Vec<f64>,
    /// Machine time, s.
    pub machine_time_s: f64,
    /// Load-point displacement, µm.
    pub slip_um: f64,
    /// Samples the lab would record at the record's own sampling intervals.
    pub samples: usize,
    /// Pairs expected to be settled: Σ (1 − exp(−Δχ²/[`super::SETTLE_DCHI2`])) over the pairs.
    pub score: f64,
    /// The score per hour of machine time.
    pub score_per_hour: f64,
    /// The expected Δχ² of the closest pair of the diagnosis (the best model and its
    /// runner-up).
    pub lead_pair_dchi2: f64,
    /// Every pair.
    pub pairs: Vec<PairScore>,
    /// The largest slip rate a credible model reaches in it, at its fit or at a draw, µm/s.
    pub peak_slip_rate: f64,
    /// Whether a credible model, at its fit or a draw, runs away in a step or hold of it
    /// (stick-slip: faster than [`super::STICK_SLIP_FACTOR`] × the fastest load point). Such
    /// proposals rank after all others.
    pub stick_slip: bool,
    /// How much it is expected to measure the named effect (absent when the diagnosis named no
    /// effect with parameters of its own).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub effect: Option<EffectGain>,
    /// Which standard segment this is (absent for a design's own proposal).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub standard: Option<StandardKind>,
}

/// What a proposal is expected to do to the named effect's parameters (those its model adds to
/// the baseline: Dc₂ and b₂, Vc, α, k, g, a law's own parameters).
#[derive(Clone, Debug, Serialize)]
pub struct EffectGain {
    /// The model whose effect it is.
    pub model: String,
    /// ½ ln(det C_E / det C'_E): the information the proposal adds on them, nats.
    pub gain_nats: f64,
    /// Its part of the score: 1 − exp(−(gain per parameter)/ln 2), so that halving every
    /// standard error counts 0.63 of a pair settled ([`super::EFFECT_HALVING`]).
    pub score: f64,
    /// Each parameter with its standard error now and expected after the proposal.
    pub parameters: Vec<EffectStderr>,
}

/// One effect parameter's uncertainty, in its own units (log-fitted parameters by the delta
/// method: value × the standard error of its logarithm).
#[derive(Clone, Debug, Serialize)]
pub struct EffectStderr {
    /// The parameter (`dc2`, `vc1`, `alpha1`, …).
    pub name: String,
    /// Its fitted value.
    pub value: f64,
    /// Its standard error from the record (inflated for correlated noise, as the design uses it).
    pub stderr_now: f64,
    /// Its expected standard error once the proposal's data are added.
    pub stderr_expected: f64,
}

/// A model's predicted friction through the best proposal.
#[derive(Clone, Debug, Serialize)]
pub struct PredictedCurve {
    /// The model.
    pub model: String,
    /// Time after the record's end, s.
    pub time: Vec<f64>,
    /// Friction at the fitted parameters.
    pub mu: Vec<f64>,
    /// Its spread over the draws (sd; 0 without draws).
    pub mu_sd: Vec<f64>,
}

/// The design.
#[derive(Clone, Debug, Serialize)]
pub struct Design {
    /// The diagnosis's cause (`none` when none was named).
    pub cause: Cause,
    /// The credible models, best first.
    pub models: Vec<DesignModel>,
    /// The record's load-point velocity at its end, µm/s (where every proposal starts).
    pub v_end: f64,
    /// The sampling intervals assumed, s: while sliding and in holds (the record's own).
    pub dt_slide_s: f64,
    /// The sampling interval in holds, s.
    pub dt_hold_s: f64,
    /// The noise model of the best model's residuals that the criterion uses.
    pub noise: NoiseModel,
    /// Every proposal scored, best first.
    pub proposals: Vec<Ranked>,
    /// The best-scoring of [`Self::standards`].
    pub standard: Option<Ranked>,
    /// The standard segments of the best proposal's machine time within the same limits (a
    /// hold and reslide, a decade down and back, a decade up and back), scored the same way.
    pub standards: Vec<Ranked>,
    /// The models' predictions through the best proposal.
    pub curves: Vec<PredictedCurve>,
    /// What the design concludes, in words.
    pub summary: String,
    /// Notes on what limits it (a record that does not end in steady sliding, few credible
    /// models, draws that failed).
    pub notes: Vec<String>,
}
