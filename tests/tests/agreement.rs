//! Solver against solver: the explicit (Dopri5) and implicit (Rodas4) integrators agree on
//! every law and protocol to within their tolerances, and every solution satisfies the spring
//! identity τ(t) − τ(0) = k (x_lp(t) − δ(t)) (an exact invariant of the equations).

use rsf_core::{FrictionForm, StateVariable};
use rsf_solvers::{Dopri5, Rodas4, SolveError, solve};
use rsf_tests::{model1, problem};

/// Steps up and down, a 300 s hold and a reslide.
const PROTOCOL: [(f64, f64); 5] = [(10.0, 2.0), (0.1, 50.0), (0.0, 300.0), (1.0, 30.0), (0.01, 200.0)];

fn cases() -> Vec<(String, rsf_core::Model)> {
    let mut v: Vec<(String, rsf_core::Model)> = ["aging", "slip", "kato-tullis", "prz", "nagata"]
        .iter()
        .map(|law| (law.to_string(), model1(law, 0.011, 0.014, 3.0, 0.02, if *law == "nagata" { 2.0 } else { 0.05 })))
        .collect();
    let two = model1("slip", 0.011, 0.008, 3.0, 0.02, 0.0).with_state(StateVariable::from_shared(
        rsf_laws::law_by_name("aging", |_| None).unwrap(),
        0.005,
        40.0,
    ));
    v.push(("slip+aging".into(), two));
    v.push((
        "slip regularized".into(),
        model1("slip", 0.011, 0.014, 3.0, 0.02, 0.0).with_form(FrictionForm::Regularized),
    ));
    v.push(("aging damped".into(), model1("aging", 0.011, 0.014, 3.0, 0.02, 0.0).with_eta(0.05)));
    v
}

#[test]
fn explicit_and_implicit_agree_within_tolerance() {
    for (name, m) in cases() {
        let k = m.stiffness;
        let p = problem(m, 1.0, &PROTOCOL, 0.5);
        for (rtol, bound) in [(1e-7, 1e-5), (1e-10, 1e-8)] {
            let e = solve(&p, &Dopri5::new(rtol, rtol * 1e-3)).unwrap();
            let i = solve(&p, &Rodas4::new(rtol, rtol * 1e-3)).unwrap();
            let dmu = e.mu.iter().zip(&i.mu).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            let dv = e.slip_rate.iter().zip(&i.slip_rate).map(|(a, b)| (a / b - 1.0).abs()).fold(0.0, f64::max);
            println!(
                "{name:18} rtol {rtol:.0e}: max |Δμ| {dmu:.1e}, max rel ΔV {dv:.1e} | steps dopri5 {} rodas4 {}",
                e.stats.accepted, i.stats.accepted
            );
            assert!(dmu < bound, "{name} rtol {rtol}: Δμ = {dmu:e}");
            assert!(dv < 1e3 * bound, "{name} rtol {rtol}: ΔV/V = {dv:e}");
            for sol in [&e, &i] {
                for r in 0..sol.len() {
                    let lhs = sol.mu[r] - sol.mu[0];
                    let rhs = k * (sol.load_point[r] - sol.slip[r]);
                    assert!(
                        (lhs - rhs).abs() < 10.0 * bound,
                        "{name} {}: spring identity off by {:e}",
                        sol.method,
                        lhs - rhs
                    );
                }
            }
        }
    }
}

/// With k below critical stiffness the quasi-static system blows up (reported as an error);
/// radiation damping turns the blow-up into repeated stick-slip events that both integrators
/// follow, with long-term average slip rate equal to the load-point rate.
#[test]
fn radiation_damping_gives_stick_slip_instead_of_blow_up() {
    // a − b = −0.005, Dc = 10 µm: k_c = 5e-4 /µm; k = 2e-4. η = 5e-7 per µm/s is G/(2 c_s σ)
    // for G = 30 GPa, c_s = 3 km/s, σ = 10 MPa.
    let m = model1("aging", 0.01, 0.015, 10.0, 2e-4, 0.0);
    let p = problem(m.clone(), 0.5, &[(1.0, 4000.0)], 0.1);
    match solve(&p, &Rodas4::new(1e-8, 1e-11)) {
        Err(SolveError::BlowUp { t, .. }) => assert!(t > 0.0 && t < 4000.0),
        Err(e) => panic!("expected a blow-up, got {e}"),
        Ok(_) => panic!("expected a blow-up, got a solution"),
    }
    let p = problem(m.with_eta(5e-7), 0.5, &[(1.0, 4000.0)], 0.1);
    let e = solve(&p, &Dopri5::new(1e-9, 1e-12)).unwrap();
    let i = solve(&p, &Rodas4::new(1e-9, 1e-12)).unwrap();
    let events = |v: &[f64]| v.windows(2).filter(|w| w[0] < 100.0 && w[1] >= 100.0).count();
    let (ne, ni) = (events(&e.slip_rate), events(&i.slip_rate));
    println!(
        "stick-slip: {ne} events (dopri5), {ni} (rodas4); peak V {:.3e} µm/s",
        i.slip_rate.iter().fold(0.0f64, |a, &b| a.max(b))
    );
    assert!(ne >= 3 && ne == ni, "events {ne} vs {ni}");
    let vmax = i.slip_rate.iter().fold(0.0f64, |a, &b| a.max(b));
    assert!(vmax > 1e3 && vmax < 1e7, "peak V {vmax}");
    // average slip rate over the run ≈ load-point rate (elastic strain is bounded)
    let avg = i.slip.last().unwrap() / i.time.last().unwrap();
    assert!((avg - 1.0).abs() < 0.2, "average slip rate {avg}");
}

/// The lean friction-only path gives exactly the friction column of the full solve.
#[test]
fn friction_only_path_equals_the_full_solution() {
    for (name, m) in cases() {
        let p = problem(m, 1.0, &PROTOCOL, 0.5);
        let full = solve(&p, &Dopri5::new(1e-9, 1e-12)).unwrap();
        let (mu, stats) = rsf_solvers::solve_friction(&p, &Dopri5::new(1e-9, 1e-12)).unwrap();
        assert_eq!(stats, full.stats, "{name}");
        let d = mu.iter().zip(&full.mu).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(d < 1e-13, "{name}: {d:e}");
    }
}
