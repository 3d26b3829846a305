//! # rsf-paper — the simulations of Bhattacharya et al. (2022)
//!
//! Bhattacharya, Rubin, Tullis, Beeler & Okazaki (2022), "The evolution of rock friction is more
//! sensitive to slip than elapsed time, even at near-zero slip rates", PNAS.
//!
//! One pure function per figure runs the simulations and returns a [`serde::Serialize`] struct
//! of the numbers; the examples of this crate (`examples/NAME.rs`) draw them with [`plot`],
//! write them with [`csv`] and print the headline numbers. The library does no file I/O.
//!
//! | function | example | what |
//! |---|---|---|
//! | [`fig1_steps`] | `fig1_steps` | normalised friction after steps against slip (Fig. 1B/C) |
//! | [`fig2_minima`] | `fig2_minima` | friction minima after step decreases (Fig. 2B–E) |
//! | [`fig3_holds`] | `fig3_holds` | holds from three V_i against V_i·t (Fig. 3A/B) |
//! | [`aging_hold_flattening`] | `aging_hold_flattening` | relaxation rate in long holds |
//! | [`peak_vs_hold`] | `peak_vs_hold` | slide–hold–slide peak against hold time |
//! | [`hold_slip_rate`] | `hold_slip_rate` | slip rate at the end of a 10⁴ s hold |
//!
//! Units: friction is shear stress over normal stress (dimensionless), slip and Dc in µm,
//! slip rates in µm/s, stiffness k in 1/µm, time in s. The machine is a spring of
//! k = 0.065 1/µm; parameters are those of the paper's Table 1 ([`params`]). Every run starts
//! in steady state; integration is by Rodas4 (holds are stiff) at the tolerances of
//! [`Resolution`].
//!
//! The slip rate at the end of a 10⁴ s hold from 0.032 µm/s: the hold-fitted Slip law reaches
//! the experiments' ~2·10⁻⁵ µm/s, and every law stays below the frozen-state bound
//! a / (k t + a/V_i) (state only grows during a hold):
//!
//! ```
//! use rsf_paper::{Resolution, hold_slip_rate};
//!
//! let fig = hold_slip_rate(&Resolution::quick()).unwrap();
//! let slip = &fig.laws[0];
//! assert_eq!(slip.params.law, "slip");
//! let ratio = slip.v_end / fig.lab_v_end; // both µm/s
//! assert!((0.5..2.0).contains(&ratio), "Slip law: {} µm/s", slip.v_end);
//! for law in &fig.laws {
//!     assert!(law.v_end < law.v_frozen_state);
//! }
//! ```
#![forbid(unsafe_code)]

pub mod csv;
mod holds;
pub mod numerics;
pub mod params;
/// The figures' chart module: the workspace's one, [`rsf_plot`].
pub use rsf_plot as plot;
mod shs;
mod sim;
mod steps;

pub use holds::{
    FIG3_HOLD, FLATTENING_T, Fig3, Flattening, HOLD_VI, HoldCurve, HoldSlipRate, HoldSlipRates, Relaxation,
    aging_hold_flattening, fig3_holds, hold_slip_rate,
};
pub use shs::{LONG_HOLD, PeakFamily, PeakVsHold, RESLIDE, SHS_V, Shs, hold_times, peak_vs_hold};
pub use sim::{Resolution, run};
pub use steps::{
    Fig1, Fig2, LOAD_POINT_AFTER_STEP, MinimaFamily, MinimumPoint, NORMALISATION_SLIP, NormalisedStep,
    SMOOTHING_DECREASE, SMOOTHING_INCREASE, STEP_SIZES, StepFamily, V_HIGH, fig1_steps, fig2_minima,
};

use thiserror::Error;

/// Why a figure could not be computed.
#[derive(Debug, Error)]
pub enum PaperError {
    /// A forward solve failed.
    #[error(transparent)]
    Solve(#[from] rsf_solvers::SolveError),
    /// A model parameter is invalid.
    #[error(transparent)]
    Model(#[from] rsf_core::ModelError),
    /// A simulated protocol is too short for the measurement taken from it.
    #[error("{0}")]
    Protocol(String),
    /// Drawing failed.
    #[error(transparent)]
    Plot(#[from] rsf_plot::PlotError),
}
