//! # rsf-core — the rate-and-state friction model
//!
//! Units throughout: slip and displacement in µm, time in s, slip rate in µm/s, state θ in s,
//! stiffness `k` in friction per µm (machine stiffness divided by normal stress, 1/µm),
//! radiation damping `eta` in friction per (µm/s). Friction is shear stress divided by normal
//! stress (dimensionless).
//!
//! The model is
//!
//! ```text
//! mu = mu0 + a ln(V/V0) + Σ_i b_i ln(V0 θ_i / (s_i Dc_i))          (classic form)
//! dθ_i/dt = G_i(V, θ_i, …)                                           (one StateLaw per state)
//! dτ/dt  = k (V_lp(t) − V),   τ = mu(V, θ) + eta V                   (spring-slider, Eqs. 3–8)
//! ```
//!
//! where `s_i` is the law's θ scale (1 for every law but Perrin–Rice–Zheng, which uses 2).
//!
//! * [`StateLaw`] — the plugin trait for evolution laws (one required method).
//! * [`Model`] — friction parameters, state variables and the machine.
//! * [`SpringSlider`] — the ODE right-hand side and its exact Jacobian in the variables
//!   `y = (ln V, ln θ_1, …, ln θ_N, slip)`.
//! * [`Loading`] — a protocol of constant-velocity segments or a measured load-point record,
//!   both reduced to pieces of constant load-point velocity so that solvers restart exactly at
//!   every velocity discontinuity.
//! * [`nondim`] — the non-dimensional form of Bhattacharya et al. (2022) Eqs. 9–12.
//!
//! ```
//! use rsf_core::{Model, StateLaw, StateArgs, Real, StateVariable};
//!
//! // The Aging law written as a user would write it in their own crate.
//! #[derive(Debug, Clone)]
//! struct MyAging;
//! impl StateLaw for MyAging {
//!     fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
//!         -(s.v * s.theta / s.dc) + 1.0
//!     }
//! }
//! let model = Model::new(0.6, 1.0, 0.01, 1e-3)
//!     .with_state(StateVariable::new(MyAging, 0.015, 10.0));
//! model.validate().unwrap();
//! // Steady state at V: θ = Dc / V, so mu_ss = mu0 + (a − b) ln(V/V0).
//! let mu = model.steady_state_friction(10.0).unwrap();
//! assert!((mu - (0.6 + (0.01 - 0.015) * 10f64.ln())).abs() < 1e-14);
//! ```
#![forbid(unsafe_code)]

pub mod batch;
pub mod element;
mod friction;
mod law;
mod loading;
mod model;
pub mod nondim;
pub mod vocabulary;
#[doc(hidden)]
pub use serde as __serde;
mod system;

pub use friction::{FrictionForm, asinh_exp_and_slope};
pub use law::{DynStateLaw, Jet, LnArgs, Real, StateArgs, StateLaw};
pub use loading::{LoadRecord, Loading, NormalStressRecord, Piece, Segment, SegmentEnd, normal_stress_varies};
pub use model::{Model, ModelError, StateVariable};
pub use system::{
    DynLaws, LawDispatch, LawParameter, N_GLOBAL, PER_STATE, SameLaw, SpringSlider, extra_law_parameters,
    law_parameters, n_params, n_params_of, param_index, state_offset,
};
