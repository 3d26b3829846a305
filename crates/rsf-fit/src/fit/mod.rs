//! Fitting a rate-and-state model to a measured record.
//!
//! Parameters live in the layout of [`rsf_core::n_params`] (`mu0, a, k, g, a_slope, b_i, dc_i, q_i, alpha_i`) plus,
//! optionally, one friction offset per segment after the first (`mu0` per segment). Positive
//! quantities (a, k, Dc, Vc) are fitted as logarithms, so they cannot leave their domain; `b`,
//! `mu0`, offsets and Nagata's `c` are fitted directly. Linear constraints `X=c`, `X-Y=c` and
//! `X+Y=c` remove Y (or X) from the free set and express it through the other.

//!
//! | file | what |
//! |---|---|
//! | `options.rs` | [`FitOptions`], loading and weighting modes, the work budget, errors |
//! | `bins.rs` | large records fitted on bin means with the same information |
//! | `prepare.rs` | samples and weights of a record ([`prepare`]), data-derived starting values |
//! | `param_name.rs` | [`ParamName`], parsed once at the edge, and each name's scale and physical range |
//! | `params.rs` | the parameter map: layout, log transforms, constraints, physical bounds |
//! | `forward.rs` | the forward model and its sensitivities at the used samples |
//! | `lsq.rs` | starting points and Levenberg–Marquardt under the work budget: [`fit`] |
//! | `covariance.rs` | covariance, standard errors and 95% intervals at the optimum |
//! | `result.rs` | [`FitResult`], [`Params`], the segment table and the fitted curve |

mod bins;
mod covariance;
mod forward;
mod lsq;
mod options;
mod param_name;
mod params;
mod prepare;
mod result;

pub use bins::{BIN_ABOVE, BIN_FRACTION, BinMeans, Binning};
pub use covariance::covariance_under;
pub use forward::{Prediction, model_curve, predict, record_span};
pub use lsq::fit;
pub use options::{
    AlphaFit, Budget, BudgetHit, FIT_MAX_STEPS, FitError, FitOptions, LoadingMode, NORMAL_STRESS_VARIES,
    NormalStressMode, SearchPrecision, Uncertainty, Weighting,
};
pub use param_name::ParamName;
pub use params::{Constraint, DIRECT_SLOPE_FLOOR, ParamMap, parameter_map};
pub use prepare::{NORMAL_STRESS_TOLERANCE, Prepared, driving_normal_stress, initial_guess, prepare};
pub use result::{Curve, Estimate, FitResult, NoiseSummary, Params, SegmentRow};
