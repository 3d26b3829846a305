//! `rsf design` on cases whose best next experiment is known: records made by Rodas4 at rtol
//! 1e-11 (not the predictions' explicit sensitivity solve), with white noise.
//!
//! - Aging vs Slip on small velocity steps only: the laws differ in how they heal at low slip
//!   rates and after large steps down, so the next segment must leave the 0.5-decade range:
//!   a large step down or a hold.
//! - A cut-off velocity Vc far below every slip rate the record reached: only a segment that
//!   brings the slip rate down towards Vc can show it — a hold long enough, or a step down to
//!   near Vc.

use rsf_core::{Model, StateVariable};
use rsf_fit::design::{Design, DesignOptions, Primitive, design};
use rsf_fit::diagnose::{DiagnoseOptions, Diagnosis};
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

#[test]
fn aging_against_slip_on_small_steps_asks_for_a_large_step_down_or_a_hold() {
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(Aging, 0.013, 10.0));
    let (_, g) = run(&truth, &small_steps()[..2], 1e-3, 3);
    assert!(g.models.iter().any(|m| m.name == "evolution_law"), "the other law must be credible");
    let best = &g.proposals[0];
    // the best proposal leaves the record's range: a step down of ≥ 1.5 decades or a hold
    let leaves = best.proposal.parts.iter().any(|p| match *p {
        Primitive::Step { v, .. } => v <= 1.0 / 10f64.powf(1.5) * 1.0001,
        Primitive::Hold { hold_s, .. } => hold_s >= 30.0,
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
    });
    assert!(reaches, "{}", best.description);
}
