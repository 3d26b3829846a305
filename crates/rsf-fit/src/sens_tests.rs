//! Tests of the forward sensitivities (`sens.rs`): against central differences of tight solves.

use super::*;
use rsf_core::{Loading, Model, Segment, StateVariable};
use rsf_laws::{Aging, KatoTullis, Slip};

fn every(m: &Model) -> Vec<bool> {
    vec![true; n_params_of(m)]
}
fn params(m: &Model) -> Vec<f64> {
    m.parameter_vector()
}
fn rebuild(base: &Model, p: &[f64]) -> Model {
    base.with_parameter_vector(p).unwrap()
}

/// The largest error of ∂mu/∂p_j from `s` against central differences of tight solves of
/// `mk(model)`, relative to the column's largest value, for the parameters `js`.
fn worst_errors(base: &Model, mk: &dyn Fn(Model) -> Problem, s: &SensSolution, js: &[usize]) -> Vec<(usize, f64)> {
    let p = params(base);
    let np = s.n_params;
    js.iter()
        .filter(|&&j| p[j] != 0.0)
        .map(|&j| {
            let h = 1e-5 * p[j].abs();
            let (mut pp, mut pm) = (p.clone(), p.clone());
            pp[j] += h;
            pm[j] -= h;
            let fp = rsf_solvers::solve(&mk(rebuild(base, &pp)), &rsf_solvers::Dopri5::new(1e-12, 1e-15)).unwrap();
            let fm = rsf_solvers::solve(&mk(rebuild(base, &pm)), &rsf_solvers::Dopri5::new(1e-12, 1e-15)).unwrap();
            let scale = (0..s.mu.len()).map(|r| s.dmu[r * np + j].abs()).fold(0.0, f64::max).max(1e-9);
            let worst = (0..s.mu.len())
                .map(|r| ((fp.mu[r] - fm.mu[r]) / (2.0 * h) - s.dmu[r * np + j]).abs() / scale)
                .fold(0.0, f64::max);
            (j, worst)
        })
        .collect()
}

/// ∂mu/∂p from the sensitivity equations agrees with central differences of tight
/// solves, for 1, 2 and 3 states (mixed laws, a law parameter) over a step–hold protocol.
#[test]
fn sensitivities_match_finite_differences() {
    let models = vec![
        Model::new(0.6, 1.0, 0.011, 0.02).with_state(StateVariable::new(Slip, 0.014, 3.0)),
        // a rate-dependent direct effect, a + a₁ ln(V/V0): its column too
        Model::new(0.6, 1.0, 0.011, 0.02).with_state(StateVariable::new(Slip, 0.014, 3.0)).with_a_slope(4e-4),
        Model::new(0.6, 1.0, 0.011, 0.02)
            .with_state(StateVariable::new(Slip, 0.009, 3.0))
            .with_state(StateVariable::new(Aging, 0.005, 30.0))
            .with_slip_trend(1e-5),
        Model::new(0.6, 1.0, 0.011, 0.02)
            .with_state(StateVariable::new(Slip, 0.008, 3.0))
            .with_state(StateVariable::new(Aging, 0.004, 30.0))
            .with_state(StateVariable::new(KatoTullis { vc: 0.05 }, 0.003, 10.0)),
    ];
    for base in models {
        // a long stretch at steady state first: y is at rest there and only error control on
        // S keeps the sensitivity equations within the explicit method's stability limit
        let segs = vec![
            Segment::for_duration(1.0, 2000.0),
            Segment::for_duration(10.0, 3.0),
            Segment::for_duration(0.1, 60.0),
            Segment::for_duration(0.0, 100.0),
            Segment::for_duration(1.0, 20.0),
        ];
        let mk = |m: Model| Problem::new(m, Loading::Segments(segs.clone()), 1.0, 1.0);
        let s = solve_with_sensitivities(&mk(base.clone()), 1e-11, 1e-14, crate::fit::FIT_MAX_STEPS, &every(&base))
            .unwrap();
        let all: Vec<usize> = (0..s.n_params).collect();
        for (j, worst) in worst_errors(&base, &mk, &s, &all) {
            assert!(worst < 2e-4, "N = {}, parameter {j}: max rel error {worst:e}", base.n_states());
        }
    }
}

/// A law with two own parameters (a text law: power-law aging blended with the Slip law by
/// w), after a Kato–Tullis state with one: the layout holds the second parameter after the
/// fixed block, and every column, that one included, matches central differences of tight
/// solves, with the steady start's own sensitivity.
#[test]
fn a_laws_further_parameters_are_exact_too() {
    const BLEND: &str = "name = \"blend-sens\"\n\
        theta_rate = \"w*(1 - omega^n) - (1 - w)*omega*ln(omega)\"\n\
        [[parameter]]\nname = \"n\"\nrange = [0.2, 5.0]\nstart = 1.5\n\
        [[parameter]]\nname = \"w\"\nrange = [0.0, 1.0]\nstart = 0.4\n";
    let law = rsf_laws::text_law::parse(BLEND, "blend.toml").unwrap().with_starting_values().unwrap();
    let base = Model::new(0.6, 1.0, 0.011, 0.02)
        .with_state(StateVariable::new(rsf_laws::KatoTullis { vc: 0.05 }, 0.006, 3.0))
        .with_state(StateVariable::from_shared(law, 0.008, 20.0));
    assert_eq!(rsf_core::extra_law_parameters(&base), vec![(1, "w")]);
    assert_eq!(n_params_of(&base), n_params(2) + 1);
    assert_eq!(rsf_core::param_index(&base, "w2"), Some(n_params(2)));
    assert_eq!(rsf_core::param_index(&base, "n2"), Some(rsf_core::state_offset(1) + 2));
    let p = base.parameter_vector();
    assert_eq!(p[n_params(2)], 0.4);
    assert_eq!(base.with_parameter_vector(&p).unwrap().parameter_vector(), p);
    assert!(base.with_parameter_vector(&p[..n_params(2)]).is_err(), "a short vector is refused");
    let segs = vec![
        Segment::for_duration(1.0, 300.0),
        Segment::for_duration(10.0, 5.0),
        Segment::for_duration(0.1, 60.0),
        Segment::for_duration(0.0, 100.0),
        Segment::for_duration(1.0, 20.0),
    ];
    // v_init 0.5 µm/s: the start is steady at a rate other than v0, so ∂θ0/∂w is not zero
    let mk = |m: Model| Problem::new(m, Loading::Segments(segs.clone()), 0.5, 1.0);
    let s =
        solve_with_sensitivities(&mk(base.clone()), 1e-11, 1e-14, crate::fit::FIT_MAX_STEPS, &every(&base)).unwrap();
    assert_eq!(s.n_params, n_params(2) + 1);
    let all: Vec<usize> = (0..s.n_params).collect();
    let errs = worst_errors(&base, &mk, &s, &all);
    assert!(errs.iter().any(|&(j, _)| j == n_params(2)), "w's column is checked");
    for (j, worst) in errs {
        assert!(worst < 2e-4, "parameter {j}: max rel error {worst:e}");
    }
}

/// Only the wanted columns are carried (a baseline's a, b, Dc; a two-state fit's five): they
/// still match central differences, μ0's is exact without a column (it moves no state),
/// and a column neither wanted nor identically zero comes out NaN, never a silent zero.
#[test]
fn wanted_columns_alone_are_carried_and_exact() {
    let one = Model::new(0.6, 1.0, 0.011, 0.02).with_state(StateVariable::new(Slip, 0.014, 3.0));
    let two = Model::new(0.6, 1.0, 0.011, 0.02)
        .with_state(StateVariable::new(Slip, 0.009, 3.0))
        .with_state(StateVariable::new(Aging, 0.005, 30.0));
    let segs = vec![
        Segment::for_duration(1.0, 200.0),
        Segment::for_duration(10.0, 3.0),
        Segment::for_duration(0.0, 100.0),
        Segment::for_duration(1.0, 20.0),
    ];
    let mk = |m: Model| Problem::new(m, Loading::Segments(segs.clone()), 1.0, 1.0);
    for base in [one, two] {
        let n = base.n_states();
        let np = n_params(n);
        let mut wanted = vec![false; np];
        wanted[0] = true;
        wanted[1] = true;
        for i in 0..n {
            wanted[rsf_core::state_offset(i)] = true;
            wanted[rsf_core::state_offset(i) + 1] = true;
        }
        assert_eq!(carried(&base, false, &wanted).unwrap().len(), 1 + 2 * n, "a and (b, Dc) per state");
        let s = solve_with_sensitivities(&mk(base.clone()), 1e-11, 1e-14, crate::fit::FIT_MAX_STEPS, &wanted).unwrap();
        let js: Vec<usize> = (0..np).filter(|&j| wanted[j]).collect();
        for (j, worst) in worst_errors(&base, &mk, &s, &js) {
            assert!(worst < 2e-4, "N = {n}, parameter {j}: max rel error {worst:e}");
        }
        assert!((0..s.mu.len()).all(|r| s.dmu[r * np] == 1.0), "∂μ/∂μ0 = 1");
        // k (index 2) is neither wanted nor zero
        assert!((0..s.mu.len()).all(|r| s.dmu[r * np + 2].is_nan()));
    }
}

/// The same with a measured normal stress (ramps up and down, one during the hold) and
/// Linker–Dieterich α on both states: ∂mu/∂α_i and the others against central differences.
#[test]
fn sensitivities_follow_normal_stress_changes() {
    let mut base = Model::new(0.6, 1.0, 0.011, 0.02)
        .with_state(StateVariable::new(Slip, 0.009, 3.0).with_alpha(0.25))
        .with_state(StateVariable::new(Aging, 0.005, 30.0).with_alpha(0.1))
        .with_normal_stress(10.0);
    base.slip_trend = 1e-5;
    let segs = vec![
        Segment::for_duration(1.0, 200.0),
        Segment::for_duration(10.0, 3.0),
        Segment::for_duration(0.1, 60.0),
        Segment::for_duration(0.0, 100.0),
        Segment::for_duration(1.0, 40.0),
    ];
    let sn = rsf_core::NormalStressRecord {
        time: vec![0.0, 100.0, 102.0, 250.0, 300.0, 320.0, 403.0],
        sigma: vec![10.0, 10.0, 12.0, 12.0, 9.5, 9.5, 9.5],
    };
    let mk = |m: Model| {
        let mut p = Problem::new(m, Loading::Segments(segs.clone()), 1.0, 1.0);
        p.normal_stress = Some(sn.clone());
        p
    };
    let s =
        solve_with_sensitivities(&mk(base.clone()), 1e-11, 1e-14, crate::fit::FIT_MAX_STEPS, &every(&base)).unwrap();
    let np = s.n_params;
    let all: Vec<usize> = (0..np).collect();
    for (j, worst) in worst_errors(&base, &mk, &s, &all) {
        assert!(worst < 2e-4, "parameter {j}: max rel error {worst:e}");
    }
    // α matters: its column is far from zero
    let ja = rsf_core::state_offset(0) + 3;
    assert!((0..s.mu.len()).any(|r| s.dmu[r * np + ja].abs() > 1e-3));
}

/// Every column of the fixed block carried at once — one Kato–Tullis state under a measured
/// normal stress, with α, a slip trend and a rate-dependent direct effect: nine columns, the
/// block's whole width, and each against central differences.
#[test]
fn the_whole_fixed_block_is_carried() {
    let mut base = Model::new(0.6, 1.0, 0.011, 0.02)
        .with_state(StateVariable::new(KatoTullis { vc: 0.05 }, 0.014, 3.0).with_alpha(0.25))
        .with_normal_stress(10.0)
        .with_a_slope(3e-4);
    base.slip_trend = 1e-5;
    let segs =
        vec![Segment::for_duration(1.0, 200.0), Segment::for_duration(10.0, 3.0), Segment::for_duration(0.1, 60.0)];
    let sn = rsf_core::NormalStressRecord { time: vec![0.0, 100.0, 102.0, 263.0], sigma: vec![10.0, 10.0, 12.0, 12.0] };
    let mk = |m: Model| {
        let mut p = Problem::new(m, Loading::Segments(segs.clone()), 1.0, 1.0);
        p.normal_stress = Some(sn.clone());
        p
    };
    assert_eq!(carried(&base, true, &every(&base)).map(|c| c.len()), Some(9));
    let s =
        solve_with_sensitivities(&mk(base.clone()), 1e-11, 1e-14, crate::fit::FIT_MAX_STEPS, &every(&base)).unwrap();
    let all: Vec<usize> = (0..s.n_params).collect();
    for (j, worst) in worst_errors(&base, &mk, &s, &all) {
        assert!(worst < 2e-4, "parameter {j}: max rel error {worst:e}");
    }
}

/// A stiff machine (k = 10 /µm, Dc = 0.1 µm: the spring relaxes in a/(kV) ≈ 1e-4 s while
/// the state evolves over Dc/V = 0.01 s): the sensitivities follow `auto` into Rodas5P with
/// the augmented Jacobian, match finite differences, and need a fraction of the steps the
/// explicit method alone takes (for one and two states, with and without α columns).
#[test]
fn stiff_sensitivities_switch_to_the_implicit_method() {
    let one = Model::new(0.6, 1.0, 0.01, 10.0).with_state(StateVariable::new(Slip, 0.014, 0.1));
    let two = Model::new(0.6, 1.0, 0.01, 10.0)
        .with_state(StateVariable::new(Slip, 0.009, 0.1))
        .with_state(StateVariable::new(Aging, 0.005, 1.0));
    let segs = vec![
        Segment::for_duration(10.0, 5.0),
        Segment::for_duration(0.0, 100.0),
        Segment::for_duration(10.0, 5.0),
        Segment::for_duration(1.0, 5.0),
    ];
    // the second model also under normal-stress ramps (during sliding and in the hold), so
    // that the implicit stretches see a time-dependent augmented system (∂f/∂t)
    let two = two.with_normal_stress(10.0);
    let two = Model { states: two.states.iter().map(|s| s.clone().with_alpha(0.2)).collect(), ..two };
    let sn = rsf_core::NormalStressRecord {
        time: vec![0.0, 1.0, 3.0, 20.0, 40.0, 115.0],
        sigma: vec![10.0, 10.0, 11.0, 11.0, 10.5, 10.5],
    };
    for base in [one, two] {
        let ramps = base.normal_stress.is_some();
        let mk = |m: Model| {
            let mut p = Problem::new(m, Loading::Segments(segs.clone()), 10.0, 0.5);
            if ramps {
                p.normal_stress = Some(sn.clone());
            }
            p
        };
        let s =
            solve_with_sensitivities(&mk(base.clone()), 1e-9, 1e-13, crate::fit::FIT_MAX_STEPS, &every(&base)).unwrap();
        let explicit = rsf_solvers::solve(&mk(base.clone()), &Dopri5::new(1e-9, 1e-13)).unwrap();
        println!(
            "N = {}: sensitivities {:?}; forward dopri5 {} steps",
            base.n_states(),
            s.stats,
            explicit.stats.accepted
        );
        assert!(s.stats.to_implicit >= 2, "{:?}", s.stats);
        assert!(
            s.stats.accepted * 5 < explicit.stats.accepted,
            "{} steps with sensitivities vs {} forward explicit",
            s.stats.accepted,
            explicit.stats.accepted
        );
        let all: Vec<usize> = (0..s.n_params).collect();
        for (j, worst) in worst_errors(&base, &mk, &s, &all) {
            assert!(worst < 1e-4, "N = {}, parameter {j}: max rel error {worst:e}", base.n_states());
        }
    }
}

/// The case that exposed uncontrolled sensitivities (basalt velstep7 with k free): steady
/// sliding at 100 µm/s, a step to 300 µm/s, 1 kHz output. ∂mu/∂ln Dc must match finite
/// differences (it was off by orders of magnitude when S was outside error control).
#[test]
fn sensitivities_stay_accurate_through_fast_steady_sliding() {
    let base = Model::new(0.608, 100.0, 0.011, 0.0105).with_state(StateVariable::new(Slip, 0.012, 10.0));
    let segs = vec![Segment::for_duration(100.0, 1.95), Segment::for_duration(300.0, 2.0)];
    let mk = |m: Model| {
        let mut p = Problem::new(m, Loading::Segments(segs.clone()), 100.0, 1.0);
        p.output = rsf_solvers::OutputTimes::Times((0..3950).map(|i| i as f64 * 1e-3).collect());
        p
    };
    let s = solve_with_sensitivities(&mk(base.clone()), 1e-7, 1e-11, crate::fit::FIT_MAX_STEPS, &every(&base)).unwrap();
    for (j, worst) in worst_errors(&base, &mk, &s, &[1, 2, 4, 5]) {
        assert!(worst < 1e-3, "parameter {j}: max rel error {worst:e}");
    }
}
