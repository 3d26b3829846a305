//! Diagnosis: what a fitted model gets wrong, which extension fixes it, and the gain.
//!
//! 1. Fit the baseline (one state variable, Slip or Aging law), with uniform weights.
//! 2. Read the baseline residuals (correlation, trends against slip and ln V), estimate the
//!    machine stiffness from reloading slopes, and refit every step and hold alone to test
//!    whether one Dc serves them all.
//! 3. Fit each candidate extension from the baseline optimum: the other law, a two-state
//!    mixture, or a law of the library — PRZ, Nagata (c fitted), the one-state Aging–Slip
//!    mixture (w fitted) — (`evolution_law`), a second state variable (`second_state_variable`), the Kato–Tullis
//!    cut-off (`cutoff_velocity`), a slip trend g·δ (`slip_trend`), a free stiffness
//!    (`stiffness`).
//! 4. Score each by ΔBIC under a noise model fitted to the residuals' spectrum (the `rsf-noise` crate:
//!    white, AR(1) and 1/f-like drift parts, Whittle's likelihood): each model is scored with
//!    its own fitted noise, so an extension gains only where its residuals become less like the
//!    record's noise, and slow drift does not pass for an effect. n_eff, the information for a
//!    slow effect, is n σ²/S(1/n): n (1 − ρ)/(1 + ρ) for AR(1), far less under drift.
//! 5. Held-out test: fit on the first part of the record, predict the rest, before and after;
//!    the extension starts from the baseline's training optimum, never from a fit that saw the
//!    held-out part.
//! 6. The cause is the best-scoring candidate with ΔBIC_eff below −10 ("very strong" evidence,
//!    Kass & Raftery 1995) that is credible (held-out misfit not more than 5% worse, no
//!    parameter run to a bound); else `none`. The winner combined with the next credible
//!    candidates may add a second cause. The runner-up and every score are reported.
//! 7. The model named (the baseline for `none`) must explain the record to its noise level
//!    where the protocol's events are (`adequacy.rs`: event windows against placebo windows of
//!    the same length); when it does not, the verdict is `unexplained`, with the best partial
//!    extension and where the misfit sits; likewise when it puts segments at the wrong level
//!    across the steps (`levels.rs`), or, where no quiet stretch leaves the events testable
//!    against the noise, when its misfits at the events agree with each other beyond what noise
//!    does (`coherence.rs`). Among laws the record cannot tell apart the simplest is named, and
//!    none when two are as simple.
//!
//! Independent fits run in parallel on all cores.

//!
//! | file | what |
//! |---|---|
//! | `cause.rs` | the closed vocabulary of causes and the extension each applies |
//! | `evidence.rs` | residual statistics, n_eff, reload-slope stiffness, ΔBIC/ΔAIC |
//! | `starts.rs` | fits of an extension from a nested optimum (and the Vc profile) |
//! | `heldout.rs` | the held-out test: split, training part, prediction |
//! | `timing.rs` | samples the protocol's break-time uncertainty cannot predict, left out |
//! | `reconstruction.rs` | a misfit from a wrong protocol break, told from physics |
//! | `null.rs` | the null calibration: false-alarm probability by parametric bootstrap |
//! | `events.rs` | per-event refits and the consistency of Dc between events |
//! | `decide.rs` | which decisive candidate is credible, the verdict in words, combinations' starts |
//! | `adequacy.rs` | whether the model named explains the events to the noise level (else `unexplained`) |
//! | `rule.rs` | the rule the adequacy tests share: their verdicts, the significance and size a misfit needs, where placebos may lie |
//! | `coherence.rs` | where the events cannot be tested against quiet stretches: whether the model's misfits at them agree with each other (part of the adequacy verdict) |
//! | `windows.rs` | event windows in log-time bins: bin means, break shifts, the spread Q and the profile both tests use |
//! | `levels.rs` | whether it puts each segment at the right level: the change of level across each step (part of the adequacy verdict) |
//! | `sensitivity.rs` | the named fit's own uncertainty as changes of its model, for the level test's null |
//! | `run.rs` | the diagnosis itself: [`diagnose`] |
//! | `result.rs` | [`Diagnosis`], [`Candidate`], [`Evidence`] and the rest of the output |

mod adequacy;
mod baseline;
mod candidate;
mod cause;
mod coherence;
mod combination;
mod decide;
pub mod events;
mod evidence;
mod form;
mod heldout;
mod lead;
mod levels;
mod null;
mod quiet;
mod reconstruction;
mod result;
mod rule;
mod run;
mod sensitivity;
mod starts;
mod timing;
mod windows;

pub use adequacy::{Adequacy, AdequacyTest, EventMisfit, MIN_WINDOWS, adequacy};
pub use candidate::cause_variants;
pub use cause::{Baseline, Cause, Effect, EffectEntry, EffectKey, EffectValue, effect_of};
pub use coherence::{Coherence, EventDirection, EventProfile, SIGN_PATTERNS};
pub use events::{EventFit, EventKind, event_windows, per_event_fits};
pub use evidence::{Noisy, noisy};
pub use form::{FormTest, Reshaping};
pub use lead::Lead;
pub use levels::{LevelMisfit, LevelTest, level_test};
pub use null::{FALSE_ALARM_LEVEL, NULL_EXTENSION, NULL_REPLICATES, NullCalibration};
pub use quiet::{QuietStretch, QuietTest, quiet_test};
pub use rsf_noise::{NoiseModel, NoiseStderr, VariableSampling};
pub use sensitivity::{FitEffect, fit_effect};

pub use reconstruction::{
    RECORD_MEDIAN_TOLERANCE, RESOLVED_SEGMENT_RATIO, Reconstruction, Remedy, SHORT_SEGMENT_SAMPLES,
    SUSPECT_SEGMENT_RATIO,
};
pub use result::{Alternative, Apart, Candidate, Diagnosis, Disagreement, Evidence, Gain, NoiseDrift, Secondary};
pub use rsf_noise::whiten;
pub use rule::{
    ADEQUACY_EXCESS, ADEQUACY_EXCESS_LARGE, ADEQUACY_LEVEL, ADEQUACY_LEVEL_LARGE, AdequacyVerdict, Family, PLACEBOS,
    WINDOW_DC, p_words,
};
pub use run::{diagnose, diagnosis_fit_options, without_spikes};
pub use starts::{VC_PROFILE_MARGIN, VC_PROFILE_PER_DECADE};
pub use timing::{TIMING_SIGMAS, TimingMask};

/// Two credible, decisive causes scoring within this ΔBIC of each other make the verdict
/// `undecided` ([`Cause::Undecided`]), and two equally simple laws within it leave the law
/// unnamed: the scale on which ΔBIC = −10 is decisive; nearer than that, neither is.
pub const UNDECIDED_DBIC: f64 = 10.0;

/// The residuals' drift is reported (`Diagnosis::noise_drift`, the verdict's text) when it holds
/// at least this share of their variance: 5% is where a drift's rms reaches a quarter of the
/// residual rms, visible in a residual plot.
pub const DRIFT_NOTE_SHARE: f64 = 0.05;

use rsf_fit::fit::FitOptions;

/// Decisive ΔBIC_eff (negative: the extension is better).
pub const DECISIVE: f64 = -10.0;

/// The default relative uncertainty (one standard deviation) of the nominal machine
/// stiffness ([`DiagnoseOptions::stiffness_uncertainty`]): labs calibrate their apparatus
/// stiffness to a few per cent from loading–unloading cycles, and it drifts with the sample's
/// compaction by as much. Set it from your own calibration (`rsf diagnose
/// --stiffness-uncertainty`).
pub const STIFFNESS_UNCERTAINTY: f64 = 0.02;
/// A fitted stiffness is a finding only outside this many standard deviations of the nominal
/// (outside its 95 % interval): inside it, the fit has found the calibration's own error, which
/// the record can measure far more precisely than the lab did (a k free in a 20,000-sample
/// record has a standard error of 0.1 % or less, so any calibration error is "decisive").
pub const STIFFNESS_SIGMAS: f64 = 2.0;

/// Progress callback: (jobs done, jobs in all, what finished).
pub use rsf_fit::progress::Progress;

/// Diagnosis settings.
#[derive(Clone)]
pub struct DiagnoseOptions {
    /// Baseline fit settings (one state variable). The diagnosis always fits with uniform
    /// weights, whatever `fit.weighting` says: model comparison needs the likelihood of the
    /// noise, and lab noise has one σ throughout.
    pub fit: FitOptions,
    /// Run the held-out test.
    pub heldout: bool,
    /// Refit the baseline law step by step and hold by hold (parameter consistency).
    pub per_segment: bool,
    /// Try the winning extension combined with each other decisive one.
    pub combinations: bool,
    /// Threads for the independent fits (0: all cores). The result does not depend on it.
    pub threads: usize,
    /// Bootstrap replicates of the null calibration (0: no calibration; a decisive, credible
    /// candidate is then named on ΔBIC alone), drawn on to [`NULL_EXTENSION`] times as
    /// many where they leave the verdict open.
    pub null_replicates: usize,
    /// A cause is named only when its false-alarm probability is below this, also at the upper
    /// confidence limit of the null's scale ([`NullCalibration::false_alarm_upper`]).
    pub false_alarm_level: f64,
    /// Leave out the samples that a noisy load point's break-time uncertainty makes
    /// unpredictable ([`TimingMask`]).
    pub timing_mask: bool,
    /// Seed of the bootstrap noise (the diagnosis is a deterministic function of the record,
    /// the options and this seed).
    pub seed: u64,
    /// Relative uncertainty (one standard deviation) of the nominal stiffness `fit.stiffness`:
    /// a fitted k within [`STIFFNESS_SIGMAS`] of it is the nominal. Default
    /// [`STIFFNESS_UNCERTAINTY`].
    pub stiffness_uncertainty: f64,
    /// Called as fits finish.
    pub progress: Option<Progress>,
    /// Print each stage's and job's wall time on stderr (profiling only; `rsf diagnose
    /// --stage-times`). Results do not depend on it.
    pub stage_times: bool,
}

/// The diagnosis's solver tolerance: friction to about 1e-6 of itself (6e-7 at μ 0.6), a
/// hundredth of lab noise (1e-4), so that no ΔBIC moves by more than rounding; 1e-7 (`rsf fit`'s
/// default) costs a quarter more integrator steps for no change in any verdict or score shown
/// (docs/BENCHMARKS.md).
pub const DIAGNOSE_RTOL: f64 = 1e-6;
/// A diagnosis's fits search their optimum on bin means of a record of more than this many used
/// samples (each result is then evaluated on every sample, `BinMeans::Search`).
pub const SEARCH_BINS_ABOVE: usize = 5_000;
/// The bins' span as a fraction of the time since their segment's start.
pub const SEARCH_BIN_FRACTION: f64 = 0.003;

/// A diagnosis's fit stops when its Gauss–Newton step would gain less than this in ln L (white
/// noise, every sample): 1e-4 keeps every ΔBIC of the detection records within 0.2 of the fit
/// run to LM's own relative reduction of 1e-10. A looser 1e-2 moved a misfitting baseline's
/// noise-model ΔBIC by 13 (its correlated noise model weighs a step's edge far more than white
/// noise does), at a fifth less work.
pub const DIAGNOSE_LNL_TOLERANCE: f64 = 1e-4;
/// While its step would gain more than [`DIAGNOSE_COARSE_ABOVE`] in ln L, a diagnosis's fit
/// solves at this tolerance: far from the optimum a direction is all the search needs. A
/// hundred times [`DIAGNOSE_RTOL`]: 1e-3 took as much work again (more, shorter LM steps).
pub const DIAGNOSE_COARSE_RTOL: f64 = 1e-4;
/// See [`DIAGNOSE_COARSE_RTOL`]: far above the coarse solves' own error in ln L, so the fine
/// phase starts near the optimum.
pub const DIAGNOSE_COARSE_ABOVE: f64 = 100.0;

/// The diagnosis's search precision ([`DIAGNOSE_LNL_TOLERANCE`], [`DIAGNOSE_COARSE_RTOL`]).
pub const DIAGNOSE_SEARCH: rsf_fit::fit::SearchPrecision = rsf_fit::fit::SearchPrecision {
    lnl_tolerance: Some(DIAGNOSE_LNL_TOLERANCE),
    coarse_rtol: Some(DIAGNOSE_COARSE_RTOL),
    coarse_above: DIAGNOSE_COARSE_ABOVE,
};

impl DiagnoseOptions {
    /// Everything on: held-out test, per-segment refits, combinations, the null calibration
    /// (16 replicates, 1% level, seed 1), all cores, no progress.
    /// Defaults around `fit`, whose solver tolerance and bins become the diagnosis's own
    /// ([`DIAGNOSE_RTOL`]; the search on bin means of [`SEARCH_BINS_ABOVE`] and
    /// [`SEARCH_BIN_FRACTION`]), with white-noise uncertainties for its fits: set `fit.rtol` or `fit.bins`
    /// afterwards to change them.
    pub fn new(fit: FitOptions) -> Self {
        let bins = rsf_fit::fit::BinMeans::Search { above: SEARCH_BINS_ABOVE, fraction: SEARCH_BIN_FRACTION };
        Self {
            // its many fits need no noise-model covariance: the scores use the noise model
            // directly, and `rsf design` inflates the white form by n/n_eff
            fit: FitOptions {
                rtol: DIAGNOSE_RTOL,
                bins,
                search: DIAGNOSE_SEARCH,
                uncertainty: rsf_fit::fit::Uncertainty::White,
                ..fit
            },
            heldout: true,
            per_segment: true,
            combinations: true,
            threads: 0,
            null_replicates: NULL_REPLICATES,
            false_alarm_level: FALSE_ALARM_LEVEL,
            seed: 1,
            stiffness_uncertainty: STIFFNESS_UNCERTAINTY,
            timing_mask: true,
            progress: None,
            stage_times: false,
        }
    }
}

impl std::fmt::Debug for DiagnoseOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DiagnoseOptions")
            .field("fit", &self.fit)
            .field("heldout", &self.heldout)
            .field("per_segment", &self.per_segment)
            .field("combinations", &self.combinations)
            .field("threads", &self.threads)
            .field("null_replicates", &self.null_replicates)
            .field("false_alarm_level", &self.false_alarm_level)
            .field("seed", &self.seed)
            .field("stiffness_uncertainty", &self.stiffness_uncertainty)
            .finish_non_exhaustive()
    }
}
