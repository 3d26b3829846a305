//! How a right-hand side reaches the states' evolution laws.
//!
//! A model keeps its laws as trait objects (`Arc<dyn DynStateLaw>`), so that any law, the
//! user's own included, works everywhere. Calling one costs little in itself, but the call
//! sits on the integrator's critical path: every live floating-point register is spilled
//! around it and the law's few multiplications cannot be scheduled with the stage
//! arithmetic. When every state follows one known law, the solvers call it directly through
//! [`SameLaw`] instead; on the seed protocol (Slip law, Vern6, rtol 1e-8) that cut the solve
//! from 1.36 to 1.15 ms with the same steps and the same answer to the last bit.

use crate::law::{LnArgs, StateLaw};
use crate::model::Model;

/// The route from a right-hand side to state `i`'s d ln θ/dt ([`StateLaw::ln_theta_rate`]).
pub trait LawDispatch {
    /// d ln θ_i/dt, 1/s, of state `i` of `model` at `args`.
    fn ln_rate(&self, model: &Model, i: usize, args: &LnArgs) -> f64;
}

/// Through the model's trait objects: any law, one indirect call per state and evaluation.
#[derive(Clone, Copy, Debug, Default)]
pub struct DynLaws;

impl LawDispatch for DynLaws {
    #[inline(always)]
    fn ln_rate(&self, model: &Model, i: usize, args: &LnArgs) -> f64 {
        model.states[i].law.ln_rate(args)
    }
}

/// Every state follows the one law `L` with the same parameters: called directly, so that the
/// law inlines into the integrator's stage loop. Built only by [`SameLaw::of`], which checks
/// that the model's laws are all equal to it.
#[derive(Clone, Copy, Debug)]
pub struct SameLaw<L>(L);

impl<L: StateLaw + PartialEq> SameLaw<L> {
    /// `Some` when every state of `model` (at least one) has law `L` with equal parameters.
    pub fn of(model: &Model) -> Option<Self> {
        let first = model.states.first()?.law.as_any().downcast_ref::<L>()?;
        model.states.iter().all(|s| s.law.as_any().downcast_ref::<L>() == Some(first)).then(|| Self(first.clone()))
    }
}

impl<L: StateLaw> LawDispatch for SameLaw<L> {
    #[inline(always)]
    fn ln_rate(&self, _: &Model, _: usize, args: &LnArgs) -> f64 {
        self.0.ln_theta_rate(args)
    }
}
