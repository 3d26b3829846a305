//! # rsf-cycle — earthquake cycles on rsf's per-element kernels
//!
//! A 2-D antiplane quasi-dynamic simulator of the SCEC SEAS benchmark BP1-QD (Erickson & Jiang
//! 2018): a vertical strike-slip fault in a homogeneous half-space with a free surface,
//! regularized rate-and-state friction with the aging law for 0 ≤ z < W_f, steady creep at the
//! plate rate V_p below, radiation damping η = ρ c_s / 2. It is built only on the public
//! per-element kernels of [`rsf_core::element`] and the large-system integrator
//! [`rsf_solvers::LargeTsit5`] — what a fault-simulation author would use.
//!
//! | file | concern |
//! |---|---|
//! | `params.rs` | the BP1-QD parameters and the a(z) profile, SI units |
//! | `elastic.rs` | the half-space kernel (image method) as a dense faer matrix, and its mat-vec |
//! | `fault.rs` | the fault as a [`LargeSystem`](rsf_solvers::LargeSystem): unknowns ln V, ln θ, slip per cell |
//! | `events.rs` | the event catalogue (onset at max V ≥ 1e-3 m/s) and `events.csv` |
//! | `stations.rs` | the SEAS on-fault station files `fltst_dpXXX` |
//! | `run.rs` | one simulation: integrate, observe, write |
//!
//! Units: m, s, Pa (stresses in MPa only in the station files); years of 3.1536e7 s.
#![forbid(unsafe_code)]

pub mod elastic;
pub mod events;
pub mod fault;
pub mod params;
pub mod run;
pub mod stations;

/// Seconds per year (365 days, the SEAS convention).
pub const YEAR: f64 = 365.0 * 86_400.0;
