//! The direct route to a law (`SameLaw`, chosen by the solver when every state follows Slip or
//! every state Aging) gives the same solution, bit for bit, as the trait-object route that any
//! other law takes; and it is chosen only when it applies.

use rsf_core::{DynLaws, LawDispatch, LnArgs, Model, Real, SameLaw, StateArgs, StateLaw, StateVariable};
use rsf_laws::{Aging, KatoTullis, Slip};
use rsf_solvers::{Integrator, Rodas5P, Solution, Tsit5, Vern6, solve};
use rsf_tests::problem;

/// A user's law that behaves exactly like `L` but is not `L`, so the solver cannot recognise
/// it and calls it through the trait object.
#[derive(Clone, Debug, PartialEq)]
struct Opaque<L>(L);

impl<L: StateLaw> StateLaw for Opaque<L> {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        self.0.theta_rate(s)
    }
    fn ln_theta_rate(&self, s: &LnArgs) -> f64 {
        self.0.ln_theta_rate(s)
    }
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        self.0.steady_state_theta(v, dc)
    }
    fn jet(&self, s: &StateArgs<f64>) -> rsf_core::Jet {
        self.0.jet(s)
    }
    fn theta_scale(&self) -> f64 {
        self.0.theta_scale()
    }
}

fn model<L: StateLaw>(law: impl Fn() -> L, states: usize) -> Model {
    let mut m = Model::new(0.6, 1.0, 0.011, 0.02);
    for i in 0..states {
        m = m.with_state(StateVariable::new(law(), 0.014 / states as f64, 3.0 * (1 + 4 * i) as f64));
    }
    m
}

fn solve_both(direct: Model, opaque: Model, alg: &impl Integrator) -> (Solution, Solution) {
    let segs = [(10.0, 2.0), (0.1, 50.0), (0.0, 300.0), (1.0, 30.0), (0.01, 200.0)];
    (solve(&problem(direct, 1.0, &segs, 5.0), alg).unwrap(), solve(&problem(opaque, 1.0, &segs, 5.0), alg).unwrap())
}

fn assert_identical(a: &Solution, b: &Solution, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    assert_eq!(a.stats, b.stats, "{what}: the two routes took different steps");
    for (name, x, y) in [
        ("mu", &a.mu, &b.mu),
        ("slip_rate", &a.slip_rate, &b.slip_rate),
        ("slip", &a.slip, &b.slip),
        ("theta_1", &a.theta[0], &b.theta[0]),
    ] {
        for (r, (p, q)) in x.iter().zip(y).enumerate() {
            assert!(p.to_bits() == q.to_bits(), "{what}: {name} differs at row {r}: {p:e} vs {q:e}");
        }
    }
}

#[test]
fn the_direct_route_is_chosen_only_when_every_state_has_the_same_known_law() {
    assert!(SameLaw::<Slip>::of(&model(|| Slip, 1)).is_some());
    assert!(SameLaw::<Slip>::of(&model(|| Slip, 2)).is_some());
    assert!(SameLaw::<Aging>::of(&model(|| Slip, 1)).is_none());
    assert!(SameLaw::<Slip>::of(&model(|| Opaque(Slip), 1)).is_none());
    let mixed = model(|| Slip, 1).with_state(StateVariable::new(Aging, 0.005, 40.0));
    assert!(SameLaw::<Slip>::of(&mixed).is_none() && SameLaw::<Aging>::of(&mixed).is_none());
    // parameters count: two Kato–Tullis states with different cut-off velocities are not one law
    let kt = |vc| KatoTullis { vc };
    let same = Model::new(0.6, 1.0, 0.011, 0.02)
        .with_state(StateVariable::new(kt(1e-3), 0.007, 3.0))
        .with_state(StateVariable::new(kt(1e-3), 0.007, 30.0));
    let differ = Model::new(0.6, 1.0, 0.011, 0.02)
        .with_state(StateVariable::new(kt(1e-3), 0.007, 3.0))
        .with_state(StateVariable::new(kt(1e-2), 0.007, 30.0));
    assert!(SameLaw::<KatoTullis>::of(&same).is_some());
    assert!(SameLaw::<KatoTullis>::of(&differ).is_none());
    assert!(SameLaw::<Slip>::of(&Model::new(0.6, 1.0, 0.011, 0.02)).is_none(), "no state");
}

#[test]
fn both_routes_reach_the_law_with_the_same_arguments() {
    let m = model(|| Slip, 2);
    let args = LnArgs {
        x: 0.3,
        v: 0.3f64.exp(),
        v_dc: 0.3f64.exp() / 3.0,
        z: 1.2,
        dc: 3.0,
        inv_dc: 1.0 / 3.0,
        ln_dc: 3f64.ln(),
        b: 0.007,
        stress_rate: 0.0,
        normal_stress: 0.0,
        normal_stress_rate: 0.0,
    };
    let direct = SameLaw::<Slip>::of(&m).unwrap();
    for i in 0..2 {
        assert_eq!(direct.ln_rate(&m, i, &args).to_bits(), DynLaws.ln_rate(&m, i, &args).to_bits());
    }
}

#[test]
fn direct_and_trait_object_routes_give_identical_solutions() {
    for states in [1, 2] {
        let (a, b) = solve_both(model(|| Slip, states), model(|| Opaque(Slip), states), &Vern6::new(1e-9, 1e-12));
        assert_identical(&a, &b, &format!("slip, {states} states, vern6"));
        let (a, b) = solve_both(model(|| Aging, states), model(|| Opaque(Aging), states), &Tsit5::new(1e-9, 1e-12));
        assert_identical(&a, &b, &format!("aging, {states} states, tsit5"));
    }
    // the implicit method's right-hand sides go the same way (its Jacobian always through the
    // trait objects)
    let (a, b) = solve_both(model(|| Slip, 1), model(|| Opaque(Slip), 1), &Rodas5P::new(1e-9, 1e-12));
    assert_identical(&a, &b, "slip, rodas5p");
}
