//! Dormand–Prince 5(4) with Hairer's 4th-order dense output: the coefficients and the dense
//! output; the step loop is `erk.rs`, shared with Tsit5.
//!
//! Hand-written rather than taken from a crate: the state is 3–10 numbers, so per-step
//! overhead dominates and a stack-allocated, monomorphised stepper is several times faster
//! than general-purpose libraries (see docs/solvers.md); it also lets us stop exactly on every
//! load-point discontinuity and report failures with their time and values.
//!
//! Coefficients: Dormand & Prince (1980); dense output and controller: Hairer, Nørsett &
//! Wanner, Solving ODEs I, 2nd ed., II.5–II.6 (code DOPRI5).

use crate::erk::{ExplicitPair, Slopes};
use crate::ode::{OdeSystem, StepStats};
use nalgebra::SVector;

crate::ode::integrator!(
    /// Explicit Dormand–Prince 5(4) with dense output, for non-stiff problems (kept beside
    /// [`Tsit5`](crate::Tsit5) for comparison).
    Dopri5,
    "dopri5",
    explicit
);

/// Hairer's threshold for the 5(4) pairs (code DOPRI5): the border of their stability region
/// on the negative real axis is near −3.3.
pub(crate) const STIFF_H_RHO_54: f64 = 3.25;

const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

impl ExplicitPair for Dopri5 {
    const STAGES: usize = 7;
    const A: &'static [&'static [f64]] = &[
        &[A21],
        &[A31, A32],
        &[A41, A42, A43],
        &[A51, A52, A53, A54],
        &[A61, A62, A63, A64, A65],
        &[A71, 0.0, A73, A74, A75, A76],
    ];
    const E: &'static [f64] = &[E1, 0.0, E3, E4, E5, E6, E7];
    const EMBEDDED_ORDER: i32 = 4;
    const STIFF_H_RHO: f64 = STIFF_H_RHO_54;

    fn dense<const D: usize, S: OdeSystem<D>>(
        k: &mut Slopes<D>,
        (_, y0, y1, h): (f64, &SVector<f64, D>, &SVector<f64, D>, f64),
        _: &S,
        _: &mut StepStats,
    ) -> impl Fn(f64) -> SVector<f64, D> {
        let ydiff = y1 - y0;
        let bspl = k[0] * h - ydiff;
        let r4 = ydiff - k[6] * h - bspl;
        let r5 = (k[0] * D1 + k[2] * D3 + k[3] * D4 + k[4] * D5 + k[5] * D6 + k[6] * D7) * h;
        let y0 = *y0;
        move |s: f64| {
            let s1 = 1.0 - s;
            y0 + (ydiff + (bspl + (r4 + r5 * s1) * s) * s1) * s
        }
    }
}
