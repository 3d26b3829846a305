//! The automatic method: Vern6 while the problem is non-stiff, Rodas5P where it is stiff.
//!
//! Lab spring-sliders are mostly non-stiff (in log variables the Jacobian is V times a fixed
//! matrix, so its time scales follow slip, not time), but long holds on stiff machines,
//! radiation-damped stick-slip and the approach to a blow-up are not. The explicit stepper
//! watches h·ρ(J) through Hairer's free estimate ‖k7 − k6‖/‖y1 − y6‖ and hands over after
//! `STIFF_STEPS` stiff steps in a row; the implicit stepper, which has J anyway, hands back
//! after `NONSTIFF_STEPS` steps that an explicit method could take stably. The two counts are
//! the hysteresis that keeps it from flipping. Every piece (load-point segment) starts
//! explicit; the switches are counted in [`StepStats`].

use crate::dopri5::Dopri5;
use crate::erk::{self, ExplicitPair};
use crate::ode::{IntegrationError, OdeSystem, Reached, StepStats, Tolerances};
use crate::rosenbrock;
use crate::tableau::rodas5p::RODAS5P;
use crate::vern6::Vern6;
use nalgebra::SVector;

crate::ode::integrator!(
    /// Automatic stiffness switching between [`Vern6`](crate::Vern6) and
    /// [`Rodas5P`](crate::Rodas5P): the default. The step budget counts both steppers' steps.
    Auto,
    "auto",
    run
);

crate::ode::integrator!(
    /// The same switching with [`Dopri5`](crate::Dopri5) as the explicit method: for solves
    /// whose output rows outnumber the steps (fits, whose forward model is sampled at every
    /// data point), where an interpolant that costs nothing beats Vern6's extra stage per step
    /// (on `bench_fit`, MCMC at 100k rows ran 2.3× faster than with Vern6).
    AutoDopri5,
    "auto-dopri5",
    run
);

/// A switching method: its explicit partner, tolerances and step budget.
trait Switching {
    type Explicit: ExplicitPair;
    fn settings(&self) -> (&Tolerances, u64);
}

impl Switching for Auto {
    type Explicit = Vern6;
    fn settings(&self) -> (&Tolerances, u64) {
        (&self.tol, self.max_steps)
    }
}

impl Switching for AutoDopri5 {
    type Explicit = Dopri5;
    fn settings(&self) -> (&Tolerances, u64) {
        (&self.tol, self.max_steps)
    }
}

fn run<M: Switching, const D: usize, S: OdeSystem<D>>(
    m: &M,
    sys: &S,
    piece: (f64, SVector<f64, D>, f64, f64),
    t_out: &[f64],
    out: &mut impl FnMut(f64, &SVector<f64, D>),
    stats: &mut StepStats,
) -> Result<Reached<D>, IntegrationError> {
    switching::<M::Explicit, D, S>(m.settings(), sys, piece, t_out, out, stats)
}

/// One piece: the explicit pair `E` until it finds the problem stiff, Rodas5P until it finds
/// it non-stiff, …
fn switching<E: ExplicitPair, const D: usize, S: OdeSystem<D>>(
    (tol, max_steps): (&Tolerances, u64),
    sys: &S,
    (t0, y0, t1, h0): (f64, SVector<f64, D>, f64, f64),
    t_out: &[f64],
    out: &mut impl FnMut(f64, &SVector<f64, D>),
    stats: &mut StepStats,
) -> Result<Reached<D>, IntegrationError> {
    let used = |s: &StepStats| s.accepted + s.rejected;
    let start = used(stats);
    let (mut t, mut y, mut h, mut explicit) = (t0, y0, h0, true);
    loop {
        let budget = max_steps.saturating_sub(used(stats) - start).max(1);
        let rest = &t_out[t_out.partition_point(|&x| x <= t)..];
        let piece = (t, y, t1, h);
        let reached = if explicit {
            erk::integrate::<E, D, S>((tol, budget), sys, piece, rest, out, stats, true)
        } else {
            rosenbrock::integrate(&RODAS5P, (tol, budget), sys, piece, rest, out, stats, true)
        };
        match reached.map_err(|e| match e {
            // the budget is the whole call's, not the last stepper's
            IntegrationError::TooManySteps { t, .. } => IntegrationError::TooManySteps { t, steps: max_steps },
            e => e,
        })? {
            Reached::End(i) => return Ok(Reached::End(i)),
            Reached::Switch { t: ts, y: ys, h: hs } => {
                if explicit {
                    stats.to_implicit += 1;
                } else {
                    stats.to_explicit += 1;
                }
                (t, y, h, explicit) = (ts, ys, hs, !explicit);
            }
        }
    }
}
