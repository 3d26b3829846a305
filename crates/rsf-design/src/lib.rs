//! Experiment design: the next protocol segment, appended at the record's end, that best tells
//! the credible models of a diagnosis apart (`rsf design`).
//!
//! 1. The credible models: the model of the diagnosis's cause (the baseline for `none`), and
//!    every candidate extension of the diagnosis whose
//!    ΔBIC lies within [`DesignOptions::credible_dbic`] of the best, Occam's penalty for the
//!    parameters it adds (Δk ln n) not counted against it: while the best is the baseline, an
//!    extension that gains nothing because the record never went where its effect lives stays
//!    credible. A candidate with a parameter at a bound or an effect below resolution is left
//!    out.
//! 2. The proposals ([`space`]): velocity steps up and down of 0.5–3.5 decades with their slip,
//!    slide–hold–reslide with holds on a log grid and the reslide distance, normal-stress
//!    changes when the machine can make them, and sequences of two of the best of these,
//!    within the lab's constraints.
//! 3. The criterion (`criterion.rs`): for each ordered pair of models (truth i, rival j), the
//!    expected lack of fit of j when i is true, over the new samples under the record's noise
//!    model, after j re-adjusts its parameters within what the record allows:
//!    Δ_ij = E_θi[ rᵀ (Σ + J_j C_j J_jᵀ)⁻¹ r ], r = f_i(θ_i) − f_j(θ̂_j), θ_i drawn from i's
//!    covariance (Atkinson & Fedorov's T-optimality, 1975, with the rival's freedom limited by
//!    its posterior from the record, as Box & Hill 1967 and Buzzi-Ferraris & Forzatti 1984).
//!    A pair's value is the mean of both directions; a proposal's score is the number of pairs
//!    it is expected to settle, Σ (1 − exp(−D_ij / [`SETTLE_DCHI2`])).
//! 4. The stick-slip screen: a proposal in which a model, at its fit or a draw, slips faster
//!    than [`STICK_SLIP_FACTOR`] × the fastest load point (in a step or a hold) ranks last.
//! 5. The ranking: by score, near-ties (within [`SCORE_TIE`] pairs) to the shorter machine
//!    time. The score adds, once a cause with parameters of its own is named, how much the
//!    proposal shrinks their uncertainty (D_s-optimality, at most one pair: [`EFFECT_HALVING`]).
//! 6. The yardsticks ([`standard`]): the lab's standard segments of the best proposal's machine
//!    time within the same limits, scored the same way.
//!
//! When the adequacy test says the model named does not explain the record, every candidate
//! and every other law the diagnosis fitted is a rival (`models.rs`): the design proposes what
//! tells them apart instead of stopping at one credible model.
//!
//! Σ is the noise model fitted to the best credible model's residuals (white, AR(1) and drift
//! in time), applied by a Kalman filter at the new sample times; the covariances are the fits',
//! inflated by n/n_eff for correlated noise.
//!
//! | file | what |
//! |---|---|
//! | `space.rs` | proposals: primitives, sequences, sampling plan, constraints |
//! | `standard.rs` | the lab's standard segments a design is compared with |
//! | `criterion.rs` | the expected discrimination of one proposal between the models |
//! | `basis.rs` | what a design starts from: a diagnosis, or its JSON rebuilt ([`Rebuilt`]) |
//! | `models.rs` | the credible models, their covariances and draws |
//! | `run.rs` | the search, the ranking: [`design`] |
//! | `protocol.rs` | a proposal as a TOML protocol for `rsf simulate` |
//! | `result.rs` | [`Design`], [`Ranked`], [`DesignModel`], predicted curves |

mod basis;
mod criterion;
mod models;
mod protocol;
mod result;
mod run;
pub mod space;
pub mod standard;

pub use basis::{Basis, BasisModel, CandidateScore, REBUILD_LNL_TOLERANCE, Rebuilt};
pub use protocol::protocol_toml;
pub use result::{Design, DesignModel, EffectGain, EffectStderr, PairScore, PredictedCurve, Ranked};
pub use run::{design, design_basis, design_from, design_from_json};
pub use space::{Primitive, Proposal};
pub use standard::StandardKind;

/// A pair of models is settled by a proposal when its expected Δχ² reaches about this: the
/// 2Δln L an extension of two parameters needs for ΔBIC −10 at n ≈ 10⁵ samples
/// (10 + 2 ln 10⁵ ≈ 33), with margin for the realised Δχ², which scatters about its expectation.
pub const SETTLE_DCHI2: f64 = 40.0;

/// Scores within this many pairs of the best are a tie, broken by machine time: a twentieth of
/// one pair settled is no difference worth more machine time, while a relative tie (1 % of a
/// score of 15 pairs is 0.15 pair) let proposals that leave a pair a sixth unsettled win on time.
pub const SCORE_TIE: f64 = 0.05;

/// The effect term of the score: a proposal that halves every standard error of the named
/// effect's parameters (a gain of ln 2 nats per parameter) counts 1 − e⁻¹ = 0.63 of a pair
/// settled, and the term never exceeds one pair. The score counts the questions a segment
/// answers; "how large is the effect" is one more question once its cause is credible, worth
/// at most as much as telling one pair of models apart, so that telling causes apart still
/// leads while they are open, and measuring the effect decides between proposals that settle
/// the same pairs (or when one credible model is left).
pub const EFFECT_HALVING: f64 = std::f64::consts::LN_2;

/// Default ΔBIC window of the credible models: ΔBIC −10 is decisive ([`rsf_diagnose::DECISIVE`]);
/// a model within that of the best is not decided against.
pub const CREDIBLE_DBIC: f64 = 10.0;

/// The Linker–Dieterich α of a record that never changed σ is not measured by it: the design
/// draws it from the range lab measurements report (α ≈ 0.2–0.3 in Linker & Dieterich 1992,
/// values from near 0 to about 0.5 in later studies), as a normal of this mean…
pub const ALPHA_PRIOR_MEAN: f64 = 0.25;
/// …and this standard deviation, truncated at α ≥ 0.
pub const ALPHA_PRIOR_SD: f64 = 0.12;

/// A proposal in which a credible model (at its fit or at any draw) slips faster than this
/// many times the fastest load-point velocity of the record and the proposal, in a step or a
/// hold, runs away: the sample may stick-slip, the machine loses control of it, and the models
/// cannot be compared on it. Such proposals rank after every other. A stable slider's peak after
/// a hold or a step up stays within a few times the load point; the study's generator
/// (benches/design) calls the same rate stick-slip.
///
/// The slip a change of σ forces is not judged: the spring must shed or take up shear stress as
/// σ ramps, and the credible models' slip rate there reaches 10²–10⁶ times the load point in runs
/// whose true model stays stable (seed 3 of the study), so no threshold tells a run-away from it.
pub const STICK_SLIP_FACTOR: f64 = 10.0;

/// Default draws from each model's parameter covariance.
pub const DRAWS: usize = 12;

/// Design settings: the lab's constraints and the search's.
#[derive(Clone)]
pub struct DesignOptions {
    /// Models within this ΔBIC of the best are credible.
    pub credible_dbic: f64,
    /// Load-point velocities the machine can drive, µm/s.
    pub v_range: (f64, f64),
    /// Longest hold, s.
    pub max_hold: f64,
    /// Longest proposal, s of machine time.
    pub max_time: f64,
    /// Most load-point displacement of a proposal, µm.
    pub max_slip: f64,
    /// Largest normal-stress change the machine can make, as a fraction of the record's σ
    /// (0: none). When positive and the record's σ is constant, normal-stress changes are
    /// proposed and the best model with Linker–Dieterich α (drawn from the lab range,
    /// [`ALPHA_PRIOR_MEAN`] ± [`ALPHA_PRIOR_SD`]) is a credible model.
    pub max_sigma_change: f64,
    /// Draws from each model's covariance (0: the fitted parameters only).
    pub draws: usize,
    /// Try sequences of two primitives.
    pub sequences: bool,
    /// Seed of the draws (the design is a deterministic function of the record, the options and
    /// this seed).
    pub seed: u64,
    /// Threads (0: all cores). The result does not depend on it.
    pub threads: usize,
    /// Called as proposals are scored: (done, all, what).
    pub progress: Option<rsf_fit::progress::Progress>,
}

impl Default for DesignOptions {
    /// A lab's usual range: 0.001–300 µm/s, holds up to 10⁴ s, 4 h and 1 mm per proposal, no
    /// normal-stress changes.
    fn default() -> Self {
        Self {
            credible_dbic: CREDIBLE_DBIC,
            v_range: (1e-3, 300.0),
            max_hold: 1e4,
            max_time: 4.0 * 3600.0,
            max_slip: 1000.0,
            max_sigma_change: 0.0,
            draws: DRAWS,
            sequences: true,
            seed: 1,
            threads: 0,
            progress: None,
        }
    }
}

impl std::fmt::Debug for DesignOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DesignOptions")
            .field("credible_dbic", &self.credible_dbic)
            .field("v_range", &self.v_range)
            .field("max_hold", &self.max_hold)
            .field("max_time", &self.max_time)
            .field("max_slip", &self.max_slip)
            .field("max_sigma_change", &self.max_sigma_change)
            .field("draws", &self.draws)
            .field("sequences", &self.sequences)
            .field("seed", &self.seed)
            .field("threads", &self.threads)
            .finish_non_exhaustive()
    }
}
