//! Recovering known parameters from synthetic noisy records made by a different integrator
//! and tolerance (Rodas4 at 1e-11) than the fit uses (Dopri5 sensitivities at 1e-7): a and b
//! within 5%, Dc within 10%, for Aging, Slip, two-state and Kato–Tullis models over a protocol
//! of velocity steps and holds, with noise 2e-4 in friction.

use rsf_core::{Model, StateVariable};
use rsf_fit::fit::{FitOptions, fit, prepare};
use rsf_fit::segment::{SegmentOptions, detect};
use rsf_fit::synthetic::{Noise, SampledSegment, record};
use rsf_laws::{Aging, KatoTullis, Slip, law_by_name};

/// Steps 1 → 10 → 1 → 0.1 → 1 µm/s and holds of 100 and 1000 s; 10 Hz sliding, 1 Hz holds.
fn protocol() -> Vec<SampledSegment> {
    vec![
        (1.0, 50.0, 0.1),
        (10.0, 15.0, 0.1),
        (1.0, 100.0, 0.1),
        (0.0, 100.0, 1.0),
        (1.0, 60.0, 0.1),
        (0.1, 300.0, 0.1),
        (1.0, 60.0, 0.1),
        (0.0, 1000.0, 1.0),
        (1.0, 60.0, 0.1),
    ]
}

fn check(truth: &Model, laws: &[&str], seed: u64) -> rsf_fit::fit::FitResult {
    let rec = record(truth, 1.0, &protocol(), Noise { sigma: 2e-4, tau: 0.0 }, seed).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    assert_eq!(segs.len(), protocol().len(), "segments: {segs:#?}");
    let laws = laws.iter().map(|l| law_by_name(l, |_| Some(0.01)).unwrap()).collect();
    let opts = FitOptions::new(laws, truth.stiffness);
    let p = prepare(&rec, &segs, &opts).unwrap();
    let t = std::time::Instant::now();
    let r = fit(&p, &opts).unwrap();
    println!(
        "{:?}: a {:.5} b {:?} dc {:?} {:?} | rms {:.2e} | {} iterations, {:.2} s",
        laws_of(truth),
        r.params.a,
        r.params.b,
        r.params.dc,
        r.params.law_params,
        r.rms,
        r.iterations,
        t.elapsed().as_secs_f64()
    );
    let rel = |x: f64, y: f64| (x / y - 1.0).abs();
    assert!(rel(r.params.a, truth.a) < 0.05, "a {} vs {}", r.params.a, truth.a);
    for (i, s) in truth.states.iter().enumerate() {
        assert!(rel(r.params.b[i], s.b) < 0.05, "b{} {} vs {}", i + 1, r.params.b[i], s.b);
        assert!(rel(r.params.dc[i], s.dc) < 0.10, "dc{} {} vs {}", i + 1, r.params.dc[i], s.dc);
    }
    // the noise level is recovered and the intervals contain the truth
    assert!((r.rms / 2e-4 - 1.0).abs() < 0.1, "rms {}", r.rms);
    let ci = &r.ci95["a"];
    assert!(ci[0] < truth.a && truth.a < ci[1], "a CI {ci:?}");
    r
}

fn laws_of(m: &Model) -> Vec<String> {
    m.states.iter().map(|s| s.law.name()).collect()
}

#[test]
fn recovers_slip_law() {
    let m = Model::new(0.6, 1.0, 0.010, 0.005).with_state(StateVariable::new(Slip, 0.013, 8.0));
    check(&m, &["slip"], 1);
}

#[test]
fn recovers_aging_law() {
    let m = Model::new(0.6, 1.0, 0.010, 0.005).with_state(StateVariable::new(Aging, 0.013, 8.0));
    check(&m, &["aging"], 2);
}

#[test]
fn recovers_two_state_model() {
    let m = Model::new(0.6, 1.0, 0.010, 0.005)
        .with_state(StateVariable::new(Slip, 0.008, 4.0))
        .with_state(StateVariable::new(Aging, 0.006, 40.0));
    check(&m, &["slip", "aging"], 3);
}

#[test]
fn recovers_kato_tullis_with_its_cutoff() {
    let m = Model::new(0.6, 1.0, 0.010, 0.005).with_state(StateVariable::new(KatoTullis { vc: 0.03 }, 0.013, 8.0));
    let r = check(&m, &["kato-tullis"], 4);
    let vc = r.params.law_params["vc1"];
    assert!((vc / 0.03 - 1.0).abs() < 0.2, "vc {vc}");
}

/// Fit windows (the first X µm after each change, holds whole) keep the recovery, and use fewer
/// samples; per-segment weights and uniform weights agree on noise-only misfit.
#[test]
fn windows_and_weights_keep_the_recovery() {
    let m = Model::new(0.6, 1.0, 0.010, 0.005).with_state(StateVariable::new(Slip, 0.013, 8.0));
    let rec = record(&m, 1.0, &protocol(), Noise { sigma: 2e-4, tau: 0.0 }, 9).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut opts = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], 0.005);
    opts.window_um = Some(30.0);
    let p = prepare(&rec, &segs, &opts).unwrap();
    assert!(p.used.len() < rec.len() * 3 / 4, "window kept {} of {}", p.used.len(), rec.len());
    let r = fit(&p, &opts).unwrap();
    assert!((r.params.a / 0.010 - 1.0).abs() < 0.05 && (r.params.b[0] / 0.013 - 1.0).abs() < 0.05);
    assert!((r.params.dc[0] / 8.0 - 1.0).abs() < 0.10, "dc {}", r.params.dc[0]);
    opts.window_um = None;
    opts.weighting = rsf_fit::fit::Weighting::Uniform;
    let r2 = fit(&prepare(&rec, &segs, &opts).unwrap(), &opts).unwrap();
    assert!((r2.params.dc[0] / 8.0 - 1.0).abs() < 0.10);
}

/// A slip trend hidden in the record (g·slip, 3e-6 per µm: 0.0015 of friction over the
/// protocol's ~500 µm) is recovered with `fit_slip_trend`, and a, b, Dc stay right.
#[test]
fn recovers_a_slip_trend() {
    let m = Model::new(0.6, 1.0, 0.010, 0.005).with_state(StateVariable::new(Slip, 0.013, 8.0)).with_slip_trend(3e-6);
    let rec = record(&m, 1.0, &protocol(), Noise { sigma: 2e-4, tau: 0.0 }, 11).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut opts = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], 0.005);
    opts.fit_slip_trend = true;
    let r = fit(&prepare(&rec, &segs, &opts).unwrap(), &opts).unwrap();
    println!(
        "g {:.3e} ± {:.1e}, a {:.5} b {:.5} dc {:.3}",
        r.params.g, r.stderr["g"], r.params.a, r.params.b[0], r.params.dc[0]
    );
    assert!((r.params.g / 3e-6 - 1.0).abs() < 0.2, "g {}", r.params.g);
    assert!((r.params.a / 0.010 - 1.0).abs() < 0.05 && (r.params.dc[0] / 8.0 - 1.0).abs() < 0.1);
    // without the trend term the misfit is larger
    opts.fit_slip_trend = false;
    let r0 = fit(&prepare(&rec, &segs, &opts).unwrap(), &opts).unwrap();
    assert!(r0.rms > r.rms);
}

/// A rate-dependent direct effect, ∂f/∂ln V = a + a₁ ln(V/V0) with a₁ = 5.909e-4 (±35 % of a
/// over the record), made by the independent generator (`benches/detection/generate.py
/// --outside`, scipy Radau; record 23 of seed 38, `tests/data/outside/SOURCE.md`: Slip law,
/// a = 0.009463, b = 0.010837, Dc = 10.05 µm, steps 1 ↔ 0.01, 0.0316, 3.16 µm/s, white noise
/// 1.8e-4, encoder noise on the load point) is recovered with `fit_a_slope`: a₁ within 10 %,
/// a and b within 5 %, Dc within 10 %, its standard error stated; without a₁ the fit is
/// decisively worse.
#[test]
fn recovers_a_rate_dependent_direct_effect() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/outside/rate_a_short_steps.csv");
    let rec = rsf_fit::data::read_record(&path, &rsf_fit::data::ReadOptions::default()).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut opts = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], 0.011935249730937679);
    opts.loading = rsf_fit::fit::LoadingMode::Protocol;
    opts.fit_a_slope = true;
    let r = fit(&prepare(&rec, &segs, &opts).unwrap(), &opts).unwrap();
    let p = &r.params;
    println!(
        "a_slope {:.4e} ± {:.1e}, a {:.5} b {:.5} dc {:.3}, rms {:.3e}",
        p.a_slope, r.stderr["a_slope"], p.a, p.b[0], p.dc[0], r.rms
    );
    assert!((p.a_slope / 5.909e-4 - 1.0).abs() < 0.10, "a_slope {}", p.a_slope);
    assert!(r.stderr["a_slope"] > 0.0 && r.stderr["a_slope"] < 0.2 * p.a_slope);
    assert!((p.a / 0.009463 - 1.0).abs() < 0.05 && (p.b[0] / 0.010837 - 1.0).abs() < 0.05, "a {} b {}", p.a, p.b[0]);
    assert!((p.dc[0] / 10.05 - 1.0).abs() < 0.10, "dc {}", p.dc[0]);
    opts.fit_a_slope = false;
    let r0 = fit(&prepare(&rec, &segs, &opts).unwrap(), &opts).unwrap();
    println!("without a_slope: rms {:.3e}, BIC {:.1} vs {:.1}", r0.rms, r0.bic, r.bic);
    assert!(r0.bic - r.bic > 100.0, "BIC {} vs {}", r0.bic, r.bic);
}
