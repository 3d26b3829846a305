//! Cross-checks against the reference solutions in tests/data/reference: rsfmodel (odeint,
//! rtol 1e-12) and an independent tight Radau solution. Both integrators must agree with both
//! references to 1e-9 in friction on every well-posed case, and must report the two finite-time
//! blow-ups as errors at the reference blow-up time.

use rsf_core::{Loading, Model, Segment, StateVariable};
use rsf_solvers::{Method, OutputTimes, Problem, SolveError};
use rsf_tests::{data_dir, read_csv, reference_cases};
use serde_json::Value;

fn build(case: &Value) -> Problem {
    let f = |k: &str| case[k].as_f64().unwrap();
    let mut model = Model::new(f("mu0"), f("V0"), f("a"), f("k"));
    for i in 1..=case["n_states"].as_u64().unwrap() {
        let law_name = case[format!("law{i}")].as_str().unwrap();
        let c = case[format!("c{i}")].as_f64();
        let law = rsf_laws::law_by_name(law_name, |p| if p == "c" { c } else { None }).unwrap();
        model = model.with_state(StateVariable::from_shared(law, f(&format!("b{i}")), f(&format!("Dc{i}"))));
    }
    let sched: Vec<(f64, f64)> =
        case["schedule"].as_array().unwrap().iter().map(|r| (r[0].as_f64().unwrap(), r[1].as_f64().unwrap())).collect();
    let mut times = Vec::new();
    for g in case["grid"].as_array().unwrap() {
        let (a, b, dt) = (g[0].as_f64().unwrap(), g[1].as_f64().unwrap(), g[2].as_f64().unwrap());
        let n = ((b - a) / dt).round() as usize;
        times.extend((0..n).map(|i| a + i as f64 * dt));
    }
    let t_end = case["grid"].as_array().unwrap().last().unwrap()[1].as_f64().unwrap();
    times.push(t_end);
    let mut segs = Vec::new();
    for (i, &(t0, v)) in sched.iter().enumerate() {
        let t1 = sched.get(i + 1).map(|s| s.0).unwrap_or(t_end);
        segs.push(Segment::for_duration(v, t1 - t0));
    }
    let mut p = Problem::new(model, Loading::Segments(segs), sched[0].1, 1.0);
    p.output = OutputTimes::Times(times);
    p
}

struct Diff {
    mu: f64,
    v_rel: f64,
    theta_rel: f64,
    lp: f64,
}

fn compare(sol: &rsf_solvers::Solution, cols: &[Vec<f64>]) -> Diff {
    let mut d = Diff { mu: 0.0, v_rel: 0.0, theta_rel: 0.0, lp: 0.0 };
    for r in 0..sol.len() {
        if cols[2][r].is_nan() {
            continue;
        }
        assert!((sol.time[r] - cols[0][r]).abs() < 1e-9, "grid mismatch at row {r}");
        d.lp = d.lp.max((sol.load_point[r] - cols[1][r]).abs());
        d.mu = d.mu.max((sol.mu[r] - cols[2][r]).abs());
        d.v_rel = d.v_rel.max((sol.slip_rate[r] / cols[3][r] - 1.0).abs());
        for (i, th) in sol.theta.iter().enumerate() {
            d.theta_rel = d.theta_rel.max((th[r] / cols[4 + i][r] - 1.0).abs());
        }
    }
    d
}

#[test]
fn reference_cases_agree_to_1e_9_in_friction() {
    let cases = reference_cases();
    let rtol = 1e-11;
    for case in cases["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let problem = build(case);
        let tight = read_csv(&data_dir().join(format!("reference/tight_radau/{name}.csv"))).1;
        let peer = read_csv(&data_dir().join(format!("reference/rsfmodel/{name}.csv"))).1;
        let blowup = case["accuracy"]["reference_blowup_time_s"].as_f64();
        // every built-in method, the automatic one included
        for method in Method::NAMES.iter().map(|n| Method::from_name(n, rtol, 1e-14).unwrap()) {
            match (method.solve(&problem), blowup) {
                (Ok(sol), None) => {
                    assert_eq!(sol.len(), tight[0].len(), "{name}: row count");
                    let dt = compare(&sol, &tight);
                    let dp = compare(&sol, &peer);
                    println!(
                        "{name:28} {:7} vs radau: mu {:.1e} V {:.1e} theta {:.1e} | vs rsfmodel: mu {:.1e} | steps {} rhs {} jac {}",
                        sol.method,
                        dt.mu,
                        dt.v_rel,
                        dt.theta_rel,
                        dp.mu,
                        sol.stats.accepted,
                        sol.stats.rhs_evals,
                        sol.stats.jacobian_evals
                    );
                    assert!(
                        dt.mu < 1e-9 && dp.mu < 1e-9,
                        "{name} {}: mu differs by {:e} / {:e}",
                        sol.method,
                        dt.mu,
                        dp.mu
                    );
                    assert!(dt.v_rel < 1e-7 && dt.theta_rel < 1e-7, "{name}: V/theta differ");
                    assert!(dt.lp < 1e-9, "{name}: load point differs by {:e}", dt.lp);
                }
                (Err(SolveError::BlowUp { t, v, .. }), Some(tb)) => {
                    println!("{name:28} blow-up reported at t = {t:.7} s (reference {tb:.7} s), V = {v:.2e}");
                    assert!((t - tb).abs() < 1e-5, "{name}: blow-up at {t}, reference {tb}");
                }
                (Ok(_), Some(tb)) => panic!("{name}: blow-up at {tb} s not reported"),
                (Err(e), _) => panic!("{name}: unexpected error {e}"),
            }
        }
    }
}

/// A blow-up is an error whose message names its time, never rows of garbage.
#[test]
fn blowup_message_names_the_time() {
    let cases = reference_cases();
    let case = cases["cases"].as_array().unwrap().iter().find(|c| c["name"] == "b_slip_vstep_1_10").unwrap();
    for name in ["rodas4", "auto"] {
        let err = Method::from_name(name, 1e-8, 1e-12).unwrap().solve(&build(case)).unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("t = 11.355"), "{name}: {msg}");
        assert!(msg.contains("eta"), "{name}: {msg}");
    }
}
