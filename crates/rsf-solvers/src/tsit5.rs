//! Tsitouras 5(4): the explicit default of the automatic method. Coefficients in
//! `tableau/tsit5.rs`; the step loop is `erk.rs`, shared with Dopri5.
//!
//! Chosen over Dopri5 because its error coefficients are smaller for the same order (the
//! pair satisfies only the first column simplifying assumption, which frees parameters to
//! minimise the principal error), so it takes fewer steps at the same tolerance; the measured
//! gain on rsf's problems is in docs/BENCHMARKS.md.

use crate::erk::{ExplicitPair, Slopes};
use crate::ode::{OdeSystem, StepStats};
use crate::tableau::tsit5::{A, E, R};
use nalgebra::SVector;

crate::ode::integrator!(
    /// Explicit Tsitouras 5(4) with its free 4th-order dense output, for non-stiff problems.
    Tsit5,
    "tsit5",
    explicit
);

impl ExplicitPair for Tsit5 {
    const STAGES: usize = 7;
    const A: &'static [&'static [f64]] = &A;
    const E: &'static [f64] = &E;
    const EMBEDDED_ORDER: i32 = 4;
    const STIFF_H_RHO: f64 = crate::dopri5::STIFF_H_RHO_54;

    fn dense<const D: usize, S: OdeSystem<D>>(
        k: &mut Slopes<D>,
        (_, y0, _, h): (f64, &SVector<f64, D>, &SVector<f64, D>, f64),
        _: &S,
        _: &mut StepStats,
    ) -> impl Fn(f64) -> SVector<f64, D> {
        let (k, y0): ([SVector<f64, D>; 7], _) = (std::array::from_fn(|i| k[i]), *y0);
        move |s: f64| {
            let mut acc = SVector::<f64, D>::zeros();
            for (ki, r) in k.iter().zip(&R) {
                acc += ki * (s * (r[0] + s * (r[1] + s * (r[2] + s * r[3]))));
            }
            y0 + acc * h
        }
    }
}
