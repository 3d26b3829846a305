//! Which route the forward solver takes to a model's laws (see `rsf_core::LawDispatch`): the
//! direct call for the built-in laws the lab fits use most, the trait objects otherwise.

use rsf_core::{Model, SameLaw};
use rsf_laws::{Aging, Slip};

/// Models with more states than this keep the trait objects: each direct route is another
/// compiled copy of every integrator for every dimension it covers, and one- and two-state
/// models are the lab's fits.
pub(crate) const DIRECT_MAX_STATES: usize = 2;

/// The route to a model's laws.
pub(crate) enum LawRoute {
    /// Every state follows the Slip law.
    Slip(SameLaw<Slip>),
    /// Every state follows the Aging law.
    Aging(SameLaw<Aging>),
    /// Anything else: the trait objects.
    Dyn,
}

/// The route for `model` (direct only up to [`DIRECT_MAX_STATES`] states).
pub(crate) fn law_route(model: &Model) -> LawRoute {
    if model.states.len() > DIRECT_MAX_STATES {
        LawRoute::Dyn
    } else if let Some(l) = SameLaw::<Slip>::of(model) {
        LawRoute::Slip(l)
    } else if let Some(l) = SameLaw::<Aging>::of(model) {
        LawRoute::Aging(l)
    } else {
        LawRoute::Dyn
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsf_core::StateVariable;

    fn name(m: &Model) -> &'static str {
        match law_route(m) {
            LawRoute::Slip(_) => "slip",
            LawRoute::Aging(_) => "aging",
            LawRoute::Dyn => "dyn",
        }
    }

    #[test]
    fn the_solver_calls_slip_and_aging_directly_and_everything_else_through_trait_objects() {
        let m = Model::new(0.6, 1.0, 0.011, 0.02);
        let slip = m.clone().with_state(StateVariable::new(Slip, 0.01, 3.0));
        assert_eq!(name(&slip), "slip");
        assert_eq!(name(&slip.clone().with_state(StateVariable::new(Slip, 0.004, 30.0))), "slip");
        let aging = m.clone().with_state(StateVariable::new(Aging, 0.01, 3.0));
        assert_eq!(name(&aging), "aging");
        assert_eq!(name(&slip.clone().with_state(StateVariable::new(Aging, 0.004, 30.0))), "dyn");
        let kt = m.clone().with_state(StateVariable::new(rsf_laws::KatoTullis { vc: 1e-3 }, 0.01, 3.0));
        assert_eq!(name(&kt), "dyn");
        let three = (0..3).fold(m, |m, i| m.with_state(StateVariable::new(Slip, 0.004, 3.0 + i as f64)));
        assert_eq!(name(&three), "dyn", "more than DIRECT_MAX_STATES states");
    }
}
