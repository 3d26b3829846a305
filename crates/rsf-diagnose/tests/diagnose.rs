//! Hidden effects must be found: synthetic records with one effect each (made by Rodas4 at
//! rtol 1e-11, a different path from the fits), realistic protocol (steps and holds up to
//! 3000 s, 10 Hz sliding, 1 Hz holds), noise 2e-4 white or correlated; `none` records must give
//! `none`.

use rsf_core::{Model, StateVariable};
use rsf_diagnose::{DiagnoseOptions, diagnose};
use rsf_fit::fit::{FitOptions, LoadingMode};
use rsf_fit::segment::{SegmentOptions, detect};
use rsf_fit::synthetic::{Noise, SampledSegment, record};
use rsf_laws::{Aging, KatoTullis, Slip, law_by_name};

fn protocol() -> Vec<SampledSegment> {
    rsf_fit::synthetic::step_hold_protocol()
}

fn run(truth: &Model, k_nominal: f64, tau: f64, seed: u64) -> rsf_diagnose::Diagnosis {
    let rec = record(truth, 1.0, &protocol(), Noise { sigma: 2e-4, tau }, seed).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut fit = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], k_nominal);
    fit.loading = LoadingMode::Protocol;
    let d = diagnose(&rec, &segs, &DiagnoseOptions::new(fit)).unwrap();
    println!(
        "cause {} ({:.1}); runner-up {:?}; lag1 {:.2} n_eff {:.0}; {}",
        d.cause, d.confidence, d.runner_up, d.evidence.residual_lag1, d.evidence.n_effective, d.reason
    );
    let b = &d.baseline;
    println!(
        "   baseline a {:.5} b {:?} dc {:?} rms {:.2e} iters {} {}",
        b.params.a, b.params.b, b.params.dc, b.rms, b.iterations, b.stop_reason
    );
    for s in &b.segments {
        println!("      seg {} {:?} {:.1}-{:.1} v {:.4} n {} rms {:.2e}", s.index, s.kind, s.t0, s.t1, s.v, s.n, s.rms);
    }
    let e = &d.evidence;
    println!(
        "   per-event Dc χ²/dof {:?}, d lnDc/d ln step {:?}, d lnDc/d ln hold {:?}; residual vs ln V {:?} (t {:?}); k reload {:?}",
        e.dc_consistency_chi2,
        e.dc_vs_ln_step,
        e.dc_vs_ln_hold,
        e.residual_vs_ln_v,
        e.residual_vs_ln_v_t,
        e.k_reload_slope
    );
    for ev in &d.per_segment {
        println!(
            "      {} t {:.0} {:.2}→{:.2} hold {:?}: a {:.5} b {:.5} dc {:.2} ±{:.3}",
            ev.event, ev.t, ev.v_before, ev.v_after, ev.hold_s, ev.a, ev.b[0], ev.dc[0], ev.ln_dc_stderr
        );
    }
    if let Some(s) = &d.secondary {
        println!("   secondary {} ΔBIC {:.1} {:?}", s.cause, s.delta_bic, s.effect);
    }
    for c in &d.candidates {
        println!(
            "   {:24} ΔBIC {:>9.1} rms ratio {:.4} held-out {:?} → {:?} {:?}",
            c.cause, c.delta_bic, c.rms_ratio, c.heldout_rms_before, c.heldout_rms_after, c.effect
        );
    }
    d
}

fn base() -> Model {
    Model::new(0.6, 1.0, 0.010, 0.005)
}

fn effect(d: &rsf_diagnose::Diagnosis, key: &str) -> f64 {
    d.effect.number(key).unwrap_or_else(|| panic!("effect {key}: {:?}", d.effect))
}

#[test]
fn nothing_hidden_gives_none_with_white_or_correlated_noise() {
    let m = base().with_state(StateVariable::new(Slip, 0.013, 8.0));
    for (tau, seed) in [(0.0, 1), (3.0, 2)] {
        // AR(1) noise with a 3 s correlation time must not pass for an effect either
        let d = run(&m, 0.005, tau, seed);
        assert_eq!(d.cause.as_str(), "none");
        assert!(d.secondary.is_none());
        // one Dc serves every step and hold: the per-event refits scatter as their errors say
        assert_eq!(d.per_segment.len(), 7);
        let chi2 = d.evidence.dc_consistency_chi2.unwrap();
        assert!(chi2 < 4.0, "per-event Dc χ²/dof {chi2}");
    }
}

#[test]
fn finds_an_aging_law_behind_a_slip_baseline() {
    let d = run(&base().with_state(StateVariable::new(Aging, 0.013, 8.0)), 0.005, 0.0, 3);
    assert_eq!(d.cause.as_str(), "evolution_law");
    assert_eq!(d.effect.law.as_deref(), Some("aging"));
    // the signature in the per-event refits: a Slip law refitted step by step needs a longer Dc
    // for up-steps than for down-steps (Aging heals by time, fast after an up-step in slip
    // terms), and the spread is far beyond the errors
    let e = &d.evidence;
    assert!(e.dc_consistency_chi2.unwrap() > 100.0, "{e:?}");
    assert!(e.dc_vs_ln_step.unwrap() > 0.1, "{e:?}");
}

/// A subtle evolution effect: a tenth of b heals by time (an Aging state sharing Dc with the
/// Slip state). The mixture extension names it and recovers the share.
#[test]
fn finds_a_small_share_of_time_dependent_healing() {
    let m = base().with_state(StateVariable::new(Slip, 0.0117, 8.0)).with_state(StateVariable::new(Aging, 0.0013, 8.0));
    let d = run(&m, 0.005, 3.0, 9);
    assert_eq!(d.cause.as_str(), "evolution_law");
    assert_eq!(d.effect.law.as_deref(), Some("slip+aging"));
    let share = effect(&d, "b_other_fraction");
    assert!((share / 0.1 - 1.0).abs() < 0.2, "Aging share {share}");
}

#[test]
fn finds_a_second_state_variable() {
    let m = base().with_state(StateVariable::new(Slip, 0.010, 5.0)).with_state(StateVariable::new(Slip, 0.004, 60.0));
    let d = run(&m, 0.005, 0.0, 4);
    assert_eq!(d.cause.as_str(), "second_state_variable");
    assert!((effect(&d, "dc2") / 60.0 - 1.0).abs() < 0.2 && (effect(&d, "b2") / 0.004 - 1.0).abs() < 0.2);
}

#[test]
fn finds_a_cutoff_velocity() {
    let d = run(&base().with_state(StateVariable::new(KatoTullis { vc: 0.02 }, 0.013, 8.0)), 0.005, 0.0, 5);
    assert_eq!(d.cause.as_str(), "cutoff_velocity");
    assert!((effect(&d, "vc") / 0.02 - 1.0).abs() < 0.2);
}

#[test]
fn finds_a_slip_trend_in_correlated_noise() {
    let m = base().with_state(StateVariable::new(Slip, 0.013, 8.0)).with_slip_trend(3e-6);
    let d = run(&m, 0.005, 3.0, 6);
    assert_eq!(d.cause.as_str(), "slip_trend");
    assert!((effect(&d, "g") / 3e-6 - 1.0).abs() < 0.2);
}

#[test]
fn finds_a_wrong_nominal_stiffness() {
    let d = run(&Model::new(0.6, 1.0, 0.010, 0.008).with_state(StateVariable::new(Slip, 0.013, 8.0)), 0.005, 0.0, 7);
    assert_eq!(d.cause.as_str(), "stiffness");
    assert!((effect(&d, "k") / 0.008 - 1.0).abs() < 0.2);
}

/// Two effects at once (a second state variable and a slip trend): the stronger is named, the
/// other found on top of it, both parameters recovered.
#[test]
fn finds_two_causes_at_once() {
    let m = base()
        .with_state(StateVariable::new(Slip, 0.010, 5.0))
        .with_state(StateVariable::new(Slip, 0.004, 60.0))
        .with_slip_trend(3e-6);
    let d = run(&m, 0.005, 0.0, 8);
    let s = d.secondary.as_ref().expect("a second cause");
    let mut causes = [d.cause.as_str(), s.cause.as_str()];
    causes.sort();
    assert_eq!(causes, ["second_state_variable", "slip_trend"]);
    let g = s.effect.g.unwrap();
    let dc2 = s.effect.dc2.unwrap();
    assert!((g / 3e-6 - 1.0).abs() < 0.2, "g {g}");
    assert!((dc2 / 60.0 - 1.0).abs() < 0.2, "dc2 {dc2}");
}
