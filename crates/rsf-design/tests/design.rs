//! `rsf design` on cases whose best next experiment is known: records made by Rodas4 at rtol
//! 1e-11 (not the predictions' explicit sensitivity solve), with white noise.
//!
//! - Aging vs Slip on small velocity steps only: the laws differ in how they heal at low slip
//!   rates and after large steps down, so the next segment must leave the 0.5-decade range:
//!   a large step down or a hold.
//! - A cut-off velocity Vc far below every slip rate the record reached: only a segment that
//!   brings the slip rate down towards Vc can show it — a hold long enough, or a step down to
//!   near Vc.
//! - A record that never changed the normal stress says nothing of α: only a change of σ can,
//!   when the machine can make one.

use rsf_core::{Model, StateVariable};
use rsf_design::{Design, DesignOptions, Primitive, design};
use rsf_diagnose::{DiagnoseOptions, Diagnosis};
use rsf_fit::fit::FitOptions;
use rsf_fit::segment::{SegmentOptions, detect};
use rsf_fit::synthetic::{Noise, record};
use rsf_laws::{Aging, KatoTullis, law_by_name};

/// 0.5-decade steps between 1 and √10 µm/s, about 6 Dc of slip each, 10 Hz.
fn small_steps() -> Vec<(f64, f64, f64)> {
    let up = 10f64.sqrt();
    vec![(1.0, 60.0, 0.1), (up, 20.0, 0.1), (1.0, 60.0, 0.1), (up, 20.0, 0.1), (1.0, 60.0, 0.1)]
}

fn run(truth: &Model, protocol: &[(f64, f64, f64)], sigma: f64, seed: u64) -> (Diagnosis, Design) {
    let rec = record(truth, 1.0, protocol, Noise { sigma, tau: 0.0 }, seed).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let fit = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], truth.stiffness);
    let dopts = DiagnoseOptions { threads: 2, ..DiagnoseOptions::new(fit) };
    let o = DesignOptions { threads: 2, max_time: 3600.0, max_hold: 3000.0, ..Default::default() };
    let (d, g) = design(&rec, &segs, &dopts, &o).unwrap();
    println!("cause {} ({:.1}); runner-up {:?}", d.cause, d.confidence, d.runner_up);
    for m in &g.models {
        println!("  model {:24} ΔBIC {:>8.1} draws {}", m.name, m.delta_bic, m.draws);
    }
    println!("  {}", g.summary);
    for r in g.proposals.iter().take(8) {
        println!(
            "  {:>2} {:>8.0} s score {:.2} lead {:>8.1}  {}",
            r.rank, r.machine_time_s, r.score, r.lead_pair_dchi2, r.description
        );
    }
    (d, g)
}

/// One problem of the whole protocol: the detected segments of `p` and the appended `next`,
/// run by `model` from the record's start; with the record's end and the loading's end in the
/// solver's time (s), the latter summed segment by segment as the solver does.
fn whole_protocol(
    model: Model,
    p: &rsf_fit::fit::Prepared,
    next: &[rsf_core::Segment],
) -> (rsf_solvers::Problem, f64, f64) {
    let mut all: Vec<rsf_core::Segment> =
        p.segments.iter().map(|s| rsf_core::Segment::for_duration(s.v, s.t1 - s.t0)).collect();
    let end = all.iter().fold(0.0, |t, s| t + s.duration().unwrap());
    all.extend_from_slice(next);
    let t_end = all.iter().fold(0.0, |t, s| t + s.duration().unwrap());
    (rsf_solvers::Problem::new(model, rsf_core::Loading::Segments(all), p.v_init, 1.0), end, t_end)
}

/// The friction of `model` at `times` (s after the record's end): one direct solve (Rodas4 at
/// rtol 1e-11, another path than the prediction's sensitivity solve) of the detected protocol
/// of `p` and the appended segments `next`.
fn direct_solve(model: Model, p: &rsf_fit::fit::Prepared, next: &[rsf_core::Segment], times: &[f64]) -> Vec<f64> {
    let (mut prob, end, _) = whole_protocol(model, p, next);
    prob.output = rsf_solvers::OutputTimes::Times(times.iter().map(|t| end + t).collect());
    rsf_solvers::solve(&prob, &rsf_solvers::Rodas4::new(1e-11, 1e-14)).unwrap().mu
}

#[test]
fn aging_against_slip_on_small_steps_asks_for_a_large_step_down_or_a_hold() {
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(Aging, 0.013, 10.0));
    let (_, g) = run(&truth, &small_steps()[..2], 1e-3, 3);
    assert!(g.models.iter().any(|m| m.name == "evolution_law"), "the other law must be credible");
    let best = &g.proposals[0];
    // the best proposal leaves the record's range: a step down of ≥ 1.5 decades or a hold
    let leaves = best.proposal.parts.iter().any(|p| match *p {
        Primitive::Step { v, .. } => v <= g.v_end / 10f64.powf(1.5) * 1.0001,
        Primitive::Hold { hold_s, .. } => hold_s >= 30.0,
        Primitive::NormalStress { .. } => false,
    });
    assert!(leaves, "{}", best.description);
    // and tells the laws apart better than the standard segment of the same time
    let std = g.standard.as_ref().unwrap();
    assert!(best.score >= std.score, "{} vs {}", best.score, std.score);
}

#[test]
fn a_cutoff_below_every_slip_rate_asks_for_a_long_hold() {
    let vc = 0.01;
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(KatoTullis { vc }, 0.013, 10.0));
    let (_, g) = run(&truth, &small_steps(), 2e-4, 4);
    assert!(g.models.iter().any(|m| m.name == "cutoff_velocity"), "the cut-off must be credible");
    let best = &g.proposals[0];
    let reaches = best.proposal.parts.iter().any(|p| match *p {
        Primitive::Step { v, .. } => v <= 3.0 * vc,
        Primitive::Hold { hold_s, .. } => hold_s >= 100.0,
        Primitive::NormalStress { .. } => false,
    });
    assert!(reaches, "{}", best.description);
}

/// The prediction of a proposal is the fitted model run through the record's protocol and on:
/// the same as one direct solve of the whole protocol (Rodas4, tight), and its derivatives are
/// those of central differences of the prediction itself.
#[test]
fn a_prediction_is_the_whole_protocol_solved_at_once_with_exact_derivatives() {
    use rsf_fit::fit::{fit, parameter_map, predict, prepare};
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(Aging, 0.013, 10.0));
    let rec = record(&truth, 1.0, &small_steps(), Noise { sigma: 2e-4, tau: 0.0 }, 5).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut o = FitOptions::new(vec![law_by_name("aging", |_| None).unwrap()], truth.stiffness);
    o.rtol = 1e-10;
    let p = prepare(&rec, &segs, &o).unwrap();
    let f = fit(&p, &o).unwrap();
    let map = parameter_map(&p, &o).unwrap();
    let next = [rsf_core::Segment::for_duration(0.0, 300.0), rsf_core::Segment::for_duration(1.0, 40.0)];
    let times: Vec<f64> = (1..=68).map(|i| 5.0 * i as f64).collect();
    let got = predict(&p, &map, &o, &f.theta, &next, &times, true).unwrap();
    // one direct solve of the detected protocol and the appended segments
    let pr = &f.params;
    let model = Model::new(pr.mu0, pr.v0, pr.a, pr.k).with_state(StateVariable::new(Aging, pr.b[0], pr.dc[0]));
    let direct = direct_solve(model, &p, &next, &times);
    let worst = got.mu.iter().zip(&direct).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-7, "prediction vs direct solve: {worst:e}");
    // the derivatives against central differences of the prediction
    let m = got.m;
    for k in 0..m {
        let h = 1e-5;
        let mut tp = f.theta.clone();
        tp[k] += h;
        let mut tm = f.theta.clone();
        tm[k] -= h;
        let up = predict(&p, &map, &o, &tp, &next, &times, false).unwrap().mu;
        let dn = predict(&p, &map, &o, &tm, &next, &times, false).unwrap().mu;
        for r in (0..times.len()).step_by(7) {
            let fd = (up[r] - dn[r]) / (2.0 * h);
            let an = got.jac[r * m + k];
            assert!((fd - an).abs() < 1e-4 * an.abs().max(1e-3), "param {k} row {r}: {an} vs {fd}");
        }
    }
}

/// The same record, options and seed give the same design with one thread or two; another seed
/// draws other parameters.
#[test]
fn the_design_does_not_depend_on_the_thread_count() {
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(Aging, 0.013, 10.0));
    let rec = record(&truth, 1.0, &small_steps()[..2], Noise { sigma: 1e-3, tau: 0.0 }, 3).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let fit = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], truth.stiffness);
    let d = rsf_diagnose::diagnose(&rec, &segs, &DiagnoseOptions { threads: 2, ..DiagnoseOptions::new(fit) }).unwrap();
    let o = DesignOptions { max_time: 3600.0, max_hold: 3000.0, ..Default::default() };
    let one = rsf_design::design_from(&rec, &segs, &d, &DesignOptions { threads: 1, ..o.clone() }).unwrap();
    let two = rsf_design::design_from(&rec, &segs, &d, &DesignOptions { threads: 2, ..o.clone() }).unwrap();
    let json = |g: &Design| serde_json::to_string(&g.proposals).unwrap();
    assert!(one.proposals.len() > 10);
    assert_eq!(json(&one), json(&two));
    let other = rsf_design::design_from(&rec, &segs, &d, &DesignOptions { seed: 2, ..o }).unwrap();
    assert_ne!(json(&one), json(&other));
}

/// A record at constant σ: with a machine that can change σ by 20 %, the best model with α is
/// credible and the best proposal changes σ; without, neither.
#[test]
fn a_record_at_constant_normal_stress_asks_for_a_change_of_it() {
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(rsf_laws::Slip, 0.013, 10.0));
    let rec = record(&truth, 1.0, &small_steps(), Noise { sigma: 2e-4, tau: 0.0 }, 6).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let fit = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], truth.stiffness);
    let d = rsf_diagnose::diagnose(&rec, &segs, &DiagnoseOptions { threads: 2, ..DiagnoseOptions::new(fit) }).unwrap();
    let o = DesignOptions { threads: 2, max_time: 3600.0, max_hold: 3000.0, ..Default::default() };
    let without = rsf_design::design_from(&rec, &segs, &d, &o).unwrap();
    assert!(!without.models.iter().any(|m| m.name == "normal_stress_coupling"));
    assert!(!without.proposals.iter().any(|r| r.proposal.changes_normal_stress()));
    // a machine whose σ range is below the smallest change proposed: no α model nothing tests
    let tiny = DesignOptions { max_sigma_change: 0.02, ..o.clone() };
    let t = rsf_design::design_from(&rec, &segs, &d, &tiny).unwrap();
    assert!(!t.models.iter().any(|m| m.name == "normal_stress_coupling"));
    assert!(t.notes.iter().any(|n| n.contains("no change of normal stress fits")), "{:?}", t.notes);
    let g = rsf_design::design_from(&rec, &segs, &d, &DesignOptions { max_sigma_change: 0.2, ..o }).unwrap();
    let alpha = g.models.iter().find(|m| m.name == "normal_stress_coupling").expect("α must be credible");
    assert_eq!(alpha.params.alpha, vec![rsf_design::ALPHA_PRIOR_MEAN]);
    assert!(alpha.draws > 0);
    let best = &g.proposals[0];
    println!("{}", best.description);
    assert!(best.proposal.changes_normal_stress(), "{}", best.description);
    assert!(best.normal_stress.iter().all(|s| (s - 1.0).abs() <= 0.2 + 1e-12));
    // the pair (baseline, α) is settled by it, and by no proposal that keeps σ: those leave it
    // at the criterion's floor for two models that predict alike (the truth's draws against
    // the rival's freedom, about the number of parameters)
    let pair = |r: &rsf_design::Ranked| {
        r.pairs.iter().find(|p| p.a == "baseline" && p.b == "normal_stress_coupling").map(|p| p.dchi2).unwrap()
    };
    assert!(pair(best) > rsf_design::SETTLE_DCHI2, "{}", pair(best));
    for r in g.proposals.iter().filter(|r| !r.proposal.changes_normal_stress()) {
        assert!(pair(r) < 0.25 * rsf_design::SETTLE_DCHI2, "{}: {}", r.description, pair(r));
    }
    // the protocol file carries the ramp and σ_ref
    let toml = rsf_design::protocol_toml(&g, 1).unwrap();
    assert!(toml.contains("normal_stress = 1.0") && toml.contains("normal_stress_rate"), "{toml}");
    // and a best model's rate-dependent direct effect, which `rsf simulate` reads back
    let mut bent = g.clone();
    bent.models[0].params.a_slope = 2e-4;
    let toml = rsf_design::protocol_toml(&bent, 1).unwrap();
    let p = rsf_solvers::protocol::parse(&toml, None, "design.toml").unwrap();
    assert_eq!(p.problem.model.a_slope, 2e-4, "{toml}");
}

/// Through a change of σ appended after a record at constant σ, a prediction with α is the whole
/// protocol solved at once (Rodas4, tight), and its derivative in α that of central differences.
#[test]
fn a_prediction_through_a_change_of_normal_stress_is_exact() {
    use rsf_fit::fit::{AlphaFit, fit, parameter_map, predict, prepare};
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(rsf_laws::Slip, 0.013, 10.0));
    let rec = record(&truth, 1.0, &small_steps(), Noise { sigma: 2e-4, tau: 0.0 }, 7).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut o = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], truth.stiffness);
    o.rtol = 1e-10;
    let p = prepare(&rec, &segs, &o).unwrap();
    let f = fit(&p, &o).unwrap();
    let names = parameter_map(&p, &o).unwrap().free_names();
    let oa = FitOptions { alpha: AlphaFit::Shared, ..o.clone() };
    let pa = prepare(&rec, &segs, &oa).unwrap();
    let map = parameter_map(&pa, &oa).unwrap();
    let alpha = 0.3;
    let theta: Vec<f64> =
        map.free_names().iter().map(|n| names.iter().position(|x| x == n).map_or(alpha, |i| f.theta[i])).collect();
    let ka = map.free_names().iter().position(|n| n == "alpha1").unwrap();
    // σ up 20 % over 1 s, slide, down to 0.9 over 1 s, slide (in units of the record's σ)
    let next = [
        rsf_core::Segment::for_duration(1.0, 1.0).with_normal_stress_rate(0.2),
        rsf_core::Segment::for_duration(1.0, 60.0),
        rsf_core::Segment::for_duration(1.0, 1.0).with_normal_stress_rate(-0.3),
        rsf_core::Segment::for_duration(1.0, 60.0),
    ];
    let times: Vec<f64> = (1..=122).map(|i| 0.25 * i as f64).chain((31..=61).map(|i| 2.0 * i as f64)).collect();
    let got = predict(&pa, &map, &oa, &theta, &next, &times, true).unwrap();
    let pr = &f.params;
    let mut model = Model::new(pr.mu0, pr.v0, pr.a, pr.k)
        .with_state(StateVariable::new(rsf_laws::Slip, pr.b[0], pr.dc[0]).with_alpha(alpha));
    model.normal_stress = Some(1.0);
    let direct = direct_solve(model, &pa, &next, &times);
    let worst = got.mu.iter().zip(&direct).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-7, "prediction vs direct solve: {worst:e}");
    // the change of σ shows: friction moves by more than 0.01 across the first ramp
    assert!((got.mu[3] - got.mu[0]).abs() > 0.01, "{} {}", got.mu[0], got.mu[3]);
    let h = 1e-5;
    let at = |a: f64| {
        let mut t = theta.clone();
        t[ka] = a;
        predict(&pa, &map, &oa, &t, &next, &times, false).unwrap().mu
    };
    let (up, dn) = (at(alpha + h), at(alpha - h));
    let m = got.m;
    let mut largest: f64 = 0.0;
    for r in 0..times.len() {
        let fd = (up[r] - dn[r]) / (2.0 * h);
        let an = got.jac[r * m + ka];
        largest = largest.max(an.abs());
        assert!((fd - an).abs() < 1e-4 * an.abs().max(1e-3), "row {r}: {an} vs {fd}");
    }
    assert!(largest > 0.01, "α must matter after the change of σ: {largest}");
}

/// A design from the diagnosis's JSON (its models refitted from their reported parameters) ranks
/// as the design from the diagnosis itself; the JSON of another record is refused.
#[test]
fn a_design_from_the_diagnosis_json_is_the_design_from_the_diagnosis() {
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(Aging, 0.013, 10.0));
    let rec = record(&truth, 1.0, &small_steps()[..2], Noise { sigma: 1e-3, tau: 0.0 }, 3).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let fit = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], truth.stiffness);
    let dopts = DiagnoseOptions { threads: 2, ..DiagnoseOptions::new(fit) };
    let d = rsf_diagnose::diagnose(&rec, &segs, &dopts).unwrap();
    let json = serde_json::to_string(&d).unwrap();
    let o = DesignOptions { threads: 2, max_time: 3600.0, max_hold: 3000.0, ..Default::default() };
    let live = rsf_design::design_from(&rec, &segs, &d, &o).unwrap();
    let back = rsf_design::design_from_json(&rec, &segs, &json, &dopts, &o).unwrap();
    let names = |g: &Design| g.models.iter().map(|m| m.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&live), names(&back));
    assert!(live.models.len() >= 2);
    for (a, b) in live.proposals.iter().zip(&back.proposals).take(5) {
        assert_eq!(a.description, b.description);
        assert!((a.score - b.score).abs() <= 0.01 * a.score, "{} vs {}", a.score, b.score);
    }
    // another record (another noise draw): refused, with the reason
    let other = record(&truth, 1.0, &small_steps()[..2], Noise { sigma: 1e-3, tau: 0.0 }, 4).unwrap();
    let osegs = detect(&other.time, &other.load_point, &SegmentOptions::default());
    let err = rsf_design::design_from_json(&other, &osegs, &json, &dopts, &o).unwrap_err().to_string();
    assert!(err.contains("not the record"), "{err}");
    // another baseline law: refused
    let aging = DiagnoseOptions::new(FitOptions::new(vec![law_by_name("aging", |_| None).unwrap()], truth.stiffness));
    let err = rsf_design::design_from_json(&rec, &segs, &json, &aging, &o).unwrap_err().to_string();
    assert!(err.contains("baseline"), "{err}");
    // another stiffness (the warm start would carry the diagnosis's): refused
    let soft =
        DiagnoseOptions::new(FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], 0.5 * truth.stiffness));
    let err = rsf_design::design_from_json(&rec, &segs, &json, &soft, &o).unwrap_err().to_string();
    assert!(err.contains("stiffness"), "{err}");
    // a cut JSON: refused
    let err = rsf_design::design_from_json(&rec, &segs, &json[..json.len() / 2], &dopts, &o).unwrap_err();
    assert!(err.to_string().contains("does not parse"), "{err}");
}

/// The largest slip rate of `model` through the appended segments `next` (after the detected
/// protocol of `p`), µm/s: one direct solve (Rodas4 at rtol 1e-10) watching every step.
fn direct_peak(model: Model, p: &rsf_fit::fit::Prepared, next: &[rsf_core::Segment]) -> f64 {
    let (mut prob, end, t_end) = whole_protocol(model, p, next);
    prob.output = rsf_solvers::OutputTimes::Times(vec![end, t_end]);
    prob.watch.peak_slip_rate = true;
    match rsf_solvers::solve(&prob, &rsf_solvers::Rodas4::new(1e-10, 1e-14)) {
        Ok(s) => s.peak_slip_rate[1],
        Err(rsf_solvers::SolveError::BlowUp { .. }) => f64::INFINITY,
        Err(e) => panic!("{e}"),
    }
}

/// A Slip-law sample on a machine three times as stiff as critical is stable through the record's
/// small steps but stick-slips on the reslide after a hold of 1000 s or more. The design ranks
/// the proposals in which a credible model runs away last, and the truth itself (solved
/// directly) stays stable through every other.
#[test]
fn a_hold_the_sample_would_stick_slip_after_is_not_proposed() {
    use rsf_fit::fit::prepare;
    let (a, b, dc) = (0.010, 0.013, 10.0);
    let k = 3.0 * (b - a) / dc;
    let truth = Model::new(0.6, 1.0, a, k).with_state(StateVariable::new(rsf_laws::Slip, b, dc));
    let rec = record(&truth, 1.0, &small_steps(), Noise { sigma: 2e-4, tau: 0.0 }, 8).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let fit = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], k);
    let dopts = DiagnoseOptions { threads: 2, ..DiagnoseOptions::new(fit.clone()) };
    let o = DesignOptions { threads: 2, max_time: 4.0 * 3600.0, max_hold: 1e4, ..Default::default() };
    let (_, g) = design(&rec, &segs, &dopts, &o).unwrap();
    let flagged: Vec<&rsf_design::Ranked> = g.proposals.iter().filter(|r| r.stick_slip).collect();
    for r in g.proposals.iter().take(3).chain(flagged.iter().copied().take(3)) {
        println!("{:>3} stick-slip {} peak {:.3e} µm/s  {}", r.rank, r.stick_slip, r.peak_slip_rate, r.description);
    }
    // the truth, solved directly, runs away on the reslide after a hold of 1000 s (the
    // baseline's reslide of 10 Dc at the record's last velocity)…
    let p = prepare(&rec, &segs, &fit).unwrap();
    let v_fast =
        |r: &rsf_design::Ranked| r.segments.iter().map(|s| s.0).chain(segs.iter().map(|s| s.v)).fold(0.0, f64::max);
    let hold = [rsf_core::Segment::for_duration(0.0, 1000.0), rsf_core::Segment::for_duration(1.0, 100.0)];
    let peak = direct_peak(truth.clone(), &p, &hold);
    assert!(peak > 10.0 * 10f64.sqrt(), "{peak}");
    // …and no proposal the truth runs away in ranks among the safe ones (those the fit itself
    // cannot be run through are left out, and said so)
    for r in g.proposals.iter().filter(|r| !r.stick_slip) {
        let peak = direct_peak(truth.clone(), &p, &r.proposal.protocol());
        assert!(peak < 10.0 * v_fast(r), "{}: the truth reaches {peak:.3e} µm/s", r.description);
    }
    assert!(g.notes.iter().any(|n| n.contains("left out")), "{:?}", g.notes);
    assert!(!flagged.is_empty(), "no proposal flagged");
    // flagged ones rank after every other, and the best is not one
    let first_flagged = flagged[0].rank;
    assert!(g.proposals[first_flagged - 1..].iter().all(|r| r.stick_slip));
    assert!(!g.proposals[0].stick_slip);
    assert!(g.notes.iter().any(|n| n.contains("runs away")), "{:?}", g.notes);
    // the filter is cautious: it follows the models' draws, which run away sooner than the truth
    assert!(flagged.iter().any(|r| r.kind == "hold"));
}

/// A prediction sampled at the very end of the appended segments is made whatever the
/// durations: the record's span plus the proposal's, summed apart, can exceed the loading's
/// end (the same durations summed in order) by an ulp, and such a last time was refused ("output
/// times … lie outside the loading"), which silently dropped the proposal: two of the 35 hold
/// lengths and reslides below.
#[test]
fn a_prediction_reaches_the_end_of_any_appended_segments() {
    use rsf_fit::fit::{fit, parameter_map, predict, prepare};
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(Aging, 0.013, 10.0));
    let rec = record(&truth, 1.0, &small_steps(), Noise { sigma: 2e-4, tau: 0.0 }, 9).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let o = FitOptions::new(vec![law_by_name("aging", |_| None).unwrap()], truth.stiffness);
    let p = prepare(&rec, &segs, &o).unwrap();
    let f = fit(&p, &o).unwrap();
    let map = parameter_map(&p, &o).unwrap();
    let mut refused = vec![];
    for hold in rsf_design::space::HOLD_TIMES {
        for slip in [3.0, 10.0, 30.0, 23.028002709052355, 76.76000903017452] {
            let reslide = slip / 1.13;
            let next = [rsf_core::Segment::for_duration(0.0, hold), rsf_core::Segment::for_duration(1.13, reslide)];
            let times = [0.5 * hold, hold + reslide];
            if let Err(e) = predict(&p, &map, &o, &f.theta, &next, &times, false) {
                refused.push(format!("hold {hold} s, reslide {reslide} s: {e}"));
            }
        }
    }
    assert!(refused.is_empty(), "{refused:#?}");
}
