//! What a fit returns.

use super::{BudgetHit, LoadingMode, ParamName, Uncertainty, Weighting};
use crate::lm::StopReason;
use crate::segment::SegmentKind;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A parameter's value with its uncertainty.
#[derive(Clone, Debug, Serialize)]
pub struct Estimate {
    /// Best-fit value.
    pub value: f64,
    /// Standard error (linearised).
    pub stderr: f64,
    /// 95% interval (asymmetric for log-fitted parameters).
    pub ci95: [f64; 2],
}

/// One segment of the fitted record with its misfit.
#[derive(Clone, Debug, Serialize)]
pub struct SegmentRow {
    /// 1-based index.
    pub index: usize,
    /// Kind.
    pub kind: SegmentKind,
    /// Start and end time, s.
    pub t0: f64,
    /// End time, s.
    pub t1: f64,
    /// Load-point velocity, µm/s.
    pub v: f64,
    /// Samples used in the fit.
    pub n: usize,
    /// RMS misfit of the used samples.
    pub rms: f64,
}

/// Fitted model parameters in physical units (read back from a diagnosis's JSON by
/// `rsf design --from`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Params {
    /// Steady-state friction at v0.
    pub mu0: f64,
    /// Reference slip rate (= the initial load-point velocity), µm/s.
    pub v0: f64,
    /// Direct effect.
    pub a: f64,
    /// b_i.
    pub b: Vec<f64>,
    /// Dc_i, µm.
    pub dc: Vec<f64>,
    /// Stiffness, 1/µm.
    pub k: f64,
    /// Slip trend g, friction per µm of slip (0 unless fitted or fixed).
    pub g: f64,
    /// Rate dependence a₁ of the direct effect, ∂f/∂ln V = a + a₁ ln(V/V0) (0 unless fitted
    /// or fixed).
    #[serde(default, skip_serializing_if = "is_zero_f64")]
    pub a_slope: f64,
    /// Laws, per state.
    pub laws: Vec<String>,
    /// Law-specific parameters by name (e.g. `vc1`).
    pub law_params: BTreeMap<String, f64>,
    /// Per-segment friction offsets (segment 2 onward), when fitted.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mu0_offsets: Vec<f64>,
    /// Linker–Dieterich α_i per state, when the normal stress drives the model or α is fitted
    /// (empty otherwise).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub alpha: Vec<f64>,
    /// σ_ref, MPa, the normal stress k is stated at, when the normal stress drives the model.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_stress: Option<f64>,
}

impl Params {
    /// These parameters as `FitOptions::initial` starting values (`mu0`, `a`, `k`, `g`, `b1`,
    /// `dc1`, …, law parameters such as `vc1`): to restart a related fit from an optimum.
    pub fn as_initial(&self) -> Vec<(ParamName, f64)> {
        let mut v = vec![
            (ParamName::Mu0, self.mu0),
            (ParamName::A, self.a),
            (ParamName::K, self.k),
            (ParamName::G, self.g),
            (ParamName::ASlope, self.a_slope),
        ];
        for (i, (b, dc)) in self.b.iter().zip(&self.dc).enumerate() {
            v.push((ParamName::B(i + 1), *b));
            v.push((ParamName::Dc(i + 1), *dc));
        }
        // law parameters are stored by their written names (`vc1`), which always parse
        v.extend(self.law_params.iter().filter_map(|(n, x)| Some((ParamName::parse(n)?, *x))));
        v.extend(self.alpha.iter().enumerate().map(|(i, x)| (ParamName::Alpha(i + 1), *x)));
        v.extend(self.mu0_offsets.iter().enumerate().map(|(k, x)| (ParamName::Mu0Seg(k + 2), *x)));
        v
    }
}

/// The noise the fit's uncertainties were stated under ([`Uncertainty::NoiseModel`]): the
/// model fitted to the fit's residuals, in short, and the white-noise standard errors beside
/// the ones reported, for comparison.
#[derive(Clone, Debug, Serialize)]
pub struct NoiseSummary {
    /// White part, standard deviation per sample.
    pub white_sd: f64,
    /// AR(1) part, standard deviation (0 without one).
    pub ar1_sd: f64,
    /// AR(1) correlation time, s.
    pub ar1_tau_s: f64,
    /// Power-law drift: its share of the residual variance.
    pub drift_share: f64,
    /// Power-law exponent β of the drift (S ∝ f^−β).
    pub drift_beta: f64,
    /// Effective independent samples for a slowly varying effect.
    pub n_effective: f64,
    /// Whether the model was fitted in time (a variably sampled record) rather than in sample
    /// index.
    pub in_time: bool,
    /// The standard errors the white-noise form gives, by name.
    pub stderr_white: BTreeMap<String, f64>,
    /// The 95 % intervals the white-noise form gives, by name.
    pub ci95_white: BTreeMap<String, [f64; 2]>,
}

/// The result of a fit.
#[derive(Clone, Debug, Serialize)]
pub struct FitResult {
    /// Parameters.
    pub params: Params,
    /// Free parameters with standard errors and 95% intervals.
    pub ci95: BTreeMap<String, [f64; 2]>,
    /// Standard errors of the free parameters.
    pub stderr: BTreeMap<String, f64>,
    /// How `stderr` and `ci95` treat the residuals' noise.
    pub uncertainty: Uncertainty,
    /// The noise model they were computed under (absent for [`Uncertainty::White`], or when
    /// the residuals were too few to fit one: then the white form is reported).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise: Option<NoiseSummary>,
    /// Constraints applied.
    pub constraints: Vec<String>,
    /// Free parameters that ended at a physical bound: the data do not constrain them there.
    pub at_bound: Vec<String>,
    /// RMS misfit (unweighted) over the used samples.
    pub rms: f64,
    /// Samples used.
    pub n: usize,
    /// Number of free parameters.
    pub n_free: usize,
    /// Gaussian log-likelihood at the optimum, σ estimated, of the weighted model (noise σ/w_r
    /// at sample r; the usual one for uniform weights).
    pub log_likelihood: f64,
    /// Akaike information criterion (free parameters + σ).
    pub aic: f64,
    /// Bayesian information criterion.
    pub bic: f64,
    /// Segment table.
    pub segments: Vec<SegmentRow>,
    /// LM iterations of the best start.
    pub iterations: usize,
    /// Why LM stopped on the best start.
    pub stop_reason: StopReason,
    /// Whether the best start reached an optimum: LM stopped for a reason other than its
    /// iteration limit ([`StopReason::at_optimum`]) and no budget stopped it. A fit that did
    /// not is still returned (its numbers are the best point found), and says so here,
    /// in [`Self::convergence_text`], on the CLI and in a batch's status.
    pub converged: bool,
    /// A budget that stopped the best start before it converged (absent when none did).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub budget_hit: Option<BudgetHit>,
    /// Integrator steps of all the fit's forward solves (the work the budget counts).
    pub steps: u64,
    /// Starts tried.
    pub starts: usize,
    /// Starts whose search failed (a forward solve that ran away at their first point, or a
    /// budget before it).
    pub starts_failed: usize,
    /// Loading used by the forward model.
    pub loading: LoadingMode,
    /// Weighting.
    pub weighting: Weighting,
    /// Times, data, model and residual of the used samples (for plots and diagnosis); of the
    /// bin means when the record was binned.
    #[serde(skip)]
    pub curve: Curve,
    /// The bin means the fit was made on, when the record was large enough to be binned
    /// ([`super::Binning`]); `n`, `rms`, the likelihood and the segment table are the samples'.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bins: Option<usize>,
    /// Free-parameter names in fit order, transformed scale (`ln` for log-fitted).
    #[serde(skip)]
    pub theta: Vec<f64>,
    /// Covariance of θ.
    #[serde(skip)]
    pub cov_theta: Vec<f64>,
}

impl FitResult {
    /// Whether an optional global parameter — the slip trend `g` or the direct effect's rate
    /// dependence `a_slope`, 0 unless asked for — belongs in a summary of this fit: it was
    /// fitted (it has a standard error) or set to a value other than 0. Other names: always.
    pub fn reports(&self, name: &ParamName) -> bool {
        let (key, value) = match name {
            ParamName::G => ("g", self.params.g),
            ParamName::ASlope => ("a_slope", self.params.a_slope),
            ParamName::Mu0
            | ParamName::A
            | ParamName::K
            | ParamName::B(_)
            | ParamName::Dc(_)
            | ParamName::Alpha(_)
            | ParamName::Law(..)
            | ParamName::Mu0Seg(_) => return true,
        };
        value != 0.0 || self.stderr.contains_key(key)
    }

    /// Why the fit is not at an optimum, in words (`None` when it converged).
    pub fn convergence_text(&self) -> Option<String> {
        if self.converged {
            return None;
        }
        let why = match self.budget_hit {
            Some(b) => format!("{b} on its best start"),
            None => format!("its best start stopped at the {}", self.stop_reason),
        };
        Some(format!(
            "the fit did not converge: {why} ({} of {} starts failed); its numbers are the best point found, not an optimum",
            self.starts_failed, self.starts
        ))
    }
}

/// Samples used by a fit with data and model.
#[derive(Clone, Debug, Default)]
pub struct Curve {
    /// Time, s.
    pub time: Vec<f64>,
    /// Load point, µm.
    pub load_point: Vec<f64>,
    /// Measured friction.
    pub data: Vec<f64>,
    /// Model friction.
    pub model: Vec<f64>,
    /// Segment index (0-based) of each sample.
    pub segment: Vec<usize>,
    /// Model slip rate V at each sample, µm/s (empty if the extra forward solve failed).
    pub slip_rate: Vec<f64>,
}

/// Whether a parameter that is 0 unless asked for was left out (serde's `skip_serializing_if`).
fn is_zero_f64(x: &f64) -> bool {
    *x == 0.0
}
