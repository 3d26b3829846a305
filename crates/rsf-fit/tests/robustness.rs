//! Impossible or degenerate fits end promptly with a clear error or a bounded answer — never a
//! hang or a panic.

use rsf_core::{Model, StateVariable};
use rsf_fit::data::Record;
use rsf_fit::fit::{FitOptions, fit, prepare};
use rsf_fit::segment::{SegmentOptions, detect};
use rsf_fit::synthetic::{Noise, record};
use rsf_laws::{Slip, law_by_name};
use std::time::Instant;

fn opts() -> FitOptions {
    FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], 0.005)
}

#[test]
fn a_record_without_a_velocity_change_is_an_error() {
    let m = Model::new(0.6, 1.0, 0.01, 0.005).with_state(StateVariable::new(Slip, 0.012, 5.0));
    let rec = record(&m, 1.0, &[(1.0, 100.0, 0.1)], Noise { sigma: 2e-4, tau: 0.0 }, 1).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let e = prepare(&rec, &segs, &opts()).unwrap_err().to_string();
    assert!(e.contains("cannot be told apart"), "{e}");
}

#[test]
fn friction_with_no_rate_dependence_ends_promptly() {
    // steps in the load point, but friction is pure noise around a constant
    let m = Model::new(0.6, 1.0, 0.01, 0.005).with_state(StateVariable::new(Slip, 0.012, 5.0));
    let mut rec: Record =
        record(&m, 1.0, &[(1.0, 50.0, 0.1), (10.0, 10.0, 0.1), (1.0, 50.0, 0.1)], Noise { sigma: 0.0, tau: 0.0 }, 1)
            .unwrap();
    for (i, mu) in rec.mu.iter_mut().enumerate() {
        *mu = 0.6 + 2e-4 * ((i as f64 * 12.9898).sin() * 43758.5453).fract();
    }
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let p = prepare(&rec, &segs, &opts()).unwrap();
    let t = Instant::now();
    let r = fit(&p, &opts());
    let s = t.elapsed().as_secs_f64();
    assert!(s < 20.0, "took {s} s");
    if let Ok(r) = r {
        // whatever it found lies inside the physical bounds, and the misfit is the noise
        assert!(r.params.a > 0.0 && r.params.a <= 1.0 && r.params.dc[0] <= 1e7);
        assert!(r.rms < 1e-3);
    }
}

/// Every parameter fixed (the model at a known point, e.g. a generator's truth): the fit
/// evaluates it — rms and curve, nothing free — instead of panicking on a Jacobian of no
/// columns.
#[test]
fn a_fit_with_every_parameter_fixed_evaluates_the_model() {
    let m = Model::new(0.6, 1.0, 0.01, 0.005).with_state(StateVariable::new(Slip, 0.012, 5.0));
    let rec =
        record(&m, 1.0, &[(1.0, 60.0, 0.1), (10.0, 20.0, 0.05), (1.0, 60.0, 0.1)], Noise { sigma: 2e-4, tau: 0.0 }, 3)
            .unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut o = opts();
    o.fix = [("mu0", 0.6), ("a", 0.01), ("b1", 0.012), ("dc1", 5.0)]
        .into_iter()
        .map(|(n, v)| rsf_fit::fit::Constraint::fixed(n, v))
        .collect();
    let r = fit(&prepare(&rec, &segs, &o).unwrap(), &o).unwrap();
    assert!(r.stderr.is_empty(), "free: {:?}", r.stderr.keys());
    assert_eq!((r.params.a, r.params.b[0], r.params.dc[0]), (0.01, 0.012, 5.0));
    // the truth's residual is the noise
    assert!(r.rms > 1.7e-4 && r.rms < 2.3e-4, "rms {}", r.rms);
    assert_eq!(r.curve.model.len(), r.curve.data.len());
}
