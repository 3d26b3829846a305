//! # rsf-fit — fitting rate-and-state models to measured records
//!
//! Units as in `rsf-core`: time s, load point, slip and Dc µm, velocities µm/s, stiffness k in
//! 1/µm, friction dimensionless.
//!
//! | module | what |
//! |---|---|
//! | [`data`] | reading delimited text records (column names, units, xlook exports) into a [`data::Record`] |
//! | [`segment`] | the loading protocol detected from the load-point record: segments of constant velocity |
//! | [`fit`] | parameters, constraints, starting points, Levenberg–Marquardt, covariance: [`fit::fit`] |
//! | [`sens`] | friction and its exact parameter derivatives from one forward-sensitivity integration |
//! | [`lm`] | the Levenberg–Marquardt minimiser |
//! | [`mcmc`] | posterior sampling by adaptive Metropolis, chains in parallel |
//! | [`parallel`] | an order-keeping parallel map (results independent of thread count) |
//! | [`synthetic`] | records made by the model with known parameters and noise, for tests |
//!
//! What a fitted model gets wrong is `rsf-diagnose`'s, the next experiment `rsf-design`'s, the
//! HTML report `rsf-report`'s and a lab's archive `rsf-batch`'s: a law author who fits
//! depends on this crate alone.
//!
//! A synthetic velocity-step record (Slip law, a = 0.010, b = 0.013, Dc = 8 µm, steps
//! 1 → 10 → 1 µm/s sampled at 10 Hz, noise 2·10⁻⁴ in friction), its protocol detected from the
//! load point alone, and a fit that recovers the parameters:
//!
//! ```
//! use rsf_core::{Model, StateVariable};
//! use rsf_fit::fit::{FitOptions, fit, prepare};
//! use rsf_fit::segment::{SegmentOptions, detect};
//! use rsf_fit::synthetic::{Noise, record};
//! use rsf_laws::Slip;
//!
//! let truth = Model::new(0.6, 1.0, 0.010, 0.005).with_state(StateVariable::new(Slip, 0.013, 8.0));
//! // (load-point velocity µm/s, duration s, sampling interval s) per segment
//! let protocol = [(1.0, 50.0, 0.1), (10.0, 15.0, 0.1), (1.0, 100.0, 0.1)];
//! let rec = record(&truth, 1.0, &protocol, Noise { sigma: 2e-4, tau: 0.0 }, 7).unwrap();
//!
//! let segments = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
//! assert_eq!(segments.len(), 3);
//!
//! let opts = FitOptions::new(vec![std::sync::Arc::new(Slip)], 0.005); // k = 0.005 1/µm, known
//! let result = fit(&prepare(&rec, &segments, &opts).unwrap(), &opts).unwrap();
//! let p = &result.params;
//! assert!((p.a / 0.010 - 1.0).abs() < 0.05 && (p.b[0] / 0.013 - 1.0).abs() < 0.05);
//! assert!((p.dc[0] / 8.0 - 1.0).abs() < 0.10);
//! assert!((result.rms / 2e-4 - 1.0).abs() < 0.1); // the misfit is the noise
//! let ci = result.ci95["a"];
//! assert!(ci[0] < 0.010 && 0.010 < ci[1]);
//! ```
#![forbid(unsafe_code)]

pub mod data;
pub mod fit;
pub mod lm;
pub mod mcmc;
pub mod parallel;
pub mod progress;
pub mod segment;
pub mod sens;
pub mod synthetic;
