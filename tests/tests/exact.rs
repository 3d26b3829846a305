//! Exact solutions: imposed slip rate (infinite stiffness) and steady states.

use rsf_core::StateVariable;
use rsf_tests::{both, model1, problem};

const LAWS: [&str; 5] = ["aging", "slip", "kato-tullis", "prz", "nagata"];

/// Slip law at imposed V after a step from steady state at V_i:
/// ln(Vθ/Dc) = ln(V_f/V_i) exp(−δ/Dc), δ the slip since the step.
#[test]
fn slip_law_decays_exponentially_in_slip() {
    for &(vi, vf) in &[(3.0, 0.003), (1.0, 10.0), (0.1, 0.0316)] {
        let dc = 2.07;
        let m = model1("slip", 0.013, 0.016, dc, f64::INFINITY, 0.0);
        let t_end = 15.0 * dc / vf;
        let p = problem(m, vi, &[(vf, t_end)], t_end / 400.0);
        for sol in [both(&p, 1e-10).0, both(&p, 1e-10).1] {
            let mut worst: f64 = 0.0;
            for r in 0..sol.len() {
                let ln_omega = (sol.slip_rate[r] * sol.theta[0][r] / dc).ln();
                let exact = (vf / vi).ln() * (-sol.slip[r] / dc).exp();
                worst = worst.max((ln_omega - exact).abs());
                assert!((sol.slip[r] - vf * sol.time[r]).abs() < 1e-9 * (1.0 + sol.slip[r]));
            }
            assert!(worst < 1e-8, "{vi}->{vf} {}: max |ln Ω − exact| = {worst:e}", sol.method);
        }
    }
}

/// Aging law at constant V: θ(t) = Dc/V + (θ0 − Dc/V) exp(−V t/Dc), exponential in time.
/// PRZ at constant V: u = Vθ/(2Dc) = tanh(V t/(2Dc) + atanh(u0)).
#[test]
fn aging_and_prz_relax_as_their_closed_forms() {
    let dc = 5.0;
    for &(vi, vf) in &[(1.0, 0.01), (1.0, 30.0)] {
        let t_end = 12.0 * dc / vf;
        let aging = problem(model1("aging", 0.01, 0.012, dc, f64::INFINITY, 0.0), vi, &[(vf, t_end)], t_end / 300.0);
        let (e, i) = both(&aging, 1e-10);
        for sol in [e, i] {
            for r in 0..sol.len() {
                let t = sol.time[r];
                let exact = dc / vf + (dc / vi - dc / vf) * (-vf * t / dc).exp();
                let rel = (sol.theta[0][r] / exact - 1.0).abs();
                assert!(rel < 1e-8, "aging {vi}->{vf} {} t={t}: rel err {rel:e}", sol.method);
            }
        }
        if vf < vi {
            let prz = problem(model1("prz", 0.01, 0.012, dc, f64::INFINITY, 0.0), vi, &[(vf, t_end)], t_end / 300.0);
            let (e, i) = both(&prz, 1e-10);
            let u0: f64 = vf / vi;
            for sol in [e, i] {
                for r in 0..sol.len() {
                    let t = sol.time[r];
                    let exact = (vf * t / (2.0 * dc) + u0.atanh()).tanh();
                    let u = vf * sol.theta[0][r] / (2.0 * dc);
                    assert!((u - exact).abs() < 1e-8, "prz {} t={t}: {u} vs {exact}", sol.method);
                }
            }
        }
    }
}

/// mu_ss(V) = mu0 + (a − Σ b_i) ln(V/V0) for every law (Kato–Tullis far above Vc), also for
/// several state variables with mixed laws; Kato–Tullis near and below Vc uses its own steady
/// state exp(−V/Vc) = Ω ln Ω.
#[test]
fn steady_state_friction_for_every_law() {
    for law in LAWS {
        let m = model1(law, 0.011, 0.015, 4.0, 0.01, if law == "nagata" { 2.0 } else { 1e-6 });
        for &v in &[1e-3, 0.1, 1.0, 30.0] {
            let mu = m.steady_state_friction(v).unwrap();
            let expect = 0.6 + (0.011 - 0.015) * v.ln();
            assert!((mu - expect).abs() < 1e-12, "{law} at {v}: {mu} vs {expect}");
        }
    }
    // mixed laws, three states
    let mut m = model1("slip", 0.011, 0.006, 4.0, 0.01, 0.0);
    for (law, b, dc) in [("prz", 0.004, 30.0), ("aging", 0.003, 300.0)] {
        m = m.with_state(StateVariable::from_shared(rsf_laws::law_by_name(law, |_| None).unwrap(), b, dc));
    }
    let mu = m.steady_state_friction(0.2).unwrap();
    assert!((mu - (0.6 + (0.011 - 0.013) * 0.2f64.ln())).abs() < 1e-12);
    // Kato–Tullis near Vc: its own steady state, which is stronger than the Slip law's
    let kt = model1("kato-tullis", 0.011, 0.015, 4.0, 0.01, 0.1);
    for &v in &[0.01, 0.1, 0.3] {
        let th = kt.steady_state_thetas(v).unwrap()[0];
        let om = v * th / 4.0;
        assert!(((-v / 0.1f64).exp() - om * om.ln()).abs() < 1e-14);
        let mu = kt.steady_state_friction(v).unwrap();
        assert!((mu - (0.6 + (0.011 - 0.015) * v.ln() + 0.015 * om.ln())).abs() < 1e-12);
        assert!(om > 1.0);
    }
}

/// A simulation started at v_init starts exactly on its steady state and stays there when
/// loaded at v_init; after a long slide at another velocity every law reaches its steady state.
#[test]
fn simulations_start_on_and_reach_steady_state() {
    for law in LAWS {
        let extra = if law == "nagata" { 2.0 } else { 0.05 };
        let m = model1(law, 0.013, 0.016, 2.0, 0.065, extra);
        let mu_i = m.steady_state_friction(1.0).unwrap();
        let p = problem(m.clone(), 1.0, &[(1.0, 200.0)], 1.0);
        let (e, i) = both(&p, 1e-10);
        for sol in [&e, &i] {
            // the rows' friction is the same formula with its constants gathered (a linear form
            // in ln V, ln θ): equal to the last few bits
            assert!(
                (sol.mu[0] - mu_i).abs() <= 4.0 * f64::EPSILON * mu_i.abs(),
                "{law}: first row {} is not the steady state {mu_i}",
                sol.mu[0]
            );
            let drift = sol.mu.iter().map(|x| (x - mu_i).abs()).fold(0.0, f64::max);
            assert!(drift < 1e-11, "{law} {}: drift {drift:e} while loaded at v_init", sol.method);
        }
        let vf = 0.3;
        let p = problem(m.clone(), 1.0, &[(vf, 300.0 / vf)], 10.0);
        let (e, i) = both(&p, 1e-10);
        let expect = m.steady_state_friction(vf).unwrap();
        for sol in [&e, &i] {
            let end = *sol.mu.last().unwrap();
            assert!((end - expect).abs() < 1e-9, "{law} {}: {end} vs steady {expect}", sol.method);
            assert!((sol.slip_rate.last().unwrap() / vf - 1.0).abs() < 1e-7);
        }
    }
}
