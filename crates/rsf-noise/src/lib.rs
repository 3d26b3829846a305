//! The noise of a friction record's residuals: white noise, an AR(1) part and a power-law
//! (1/f-like) drift, fitted to the residuals' spectrum — in sample index for a uniformly
//! sampled record, in time for a variably sampled one — with its likelihood, whitening,
//! replicates, and the covariance it implies between samples.
//!
//! Used by the fit (its parameters' covariance under the noise, `rsf-fit`) and by the
//! diagnosis (every score, the null replicates, the adequacy test, `rsf-diagnose`): one model
//! of the noise for both.
//!
//! | file | what |
//! |---|---|
//! | `noise.rs` | the model in sample index: spectrum fit, likelihood, synthesis |
//! | `whittle.rs` | Whittle's likelihood of a three-part spectrum: periodogram, amplitudes, standard errors |
//! | `sampling.rs` | the model in time of a variably sampled record: its estimate from pooled spectra |
//! | `state_space.rs` | that model as a state-space process: exact likelihood, whitening, replicates |
//! | `timed.rs` | the model at a record's sample times: which of the two forms applies |
//! | `kernel.rs` | Σx, the model's covariance in time applied to a vector |
//! | `fft.rs` | FFT plans reused on a thread |

mod fft;
mod kernel;
mod noise;
mod sampling;
mod state_space;
mod timed;
mod whittle;

pub use noise::{NoiseModel, NoiseStderr, VariableSampling};
pub use state_space::whiten;
