//! The law passes rsf's conformance kit, and a fit started at n = 1 recovers the exponent of a
//! record made with n = 1.6.

use my_rsf_law::PowerAging;
use rsf_testkit::{Claims, Outcome, Property, assert_conforms};

#[test]
fn power_aging_conforms() {
    for n in [0.5, 1.0, 1.6, 3.0] {
        let report = assert_conforms(&PowerAging { n }, &Claims::new().steady_state_dc_over_v().cases(64));
        let exact = report.outcomes.iter().find(|(p, _)| *p == Property::ParameterDerivative).unwrap();
        assert_eq!(exact.1, Outcome::Passed(64), "{report}");
    }
}

#[test]
fn a_fit_recovers_n() {
    use rsf_core::{Loading, Model, Segment, StateVariable};
    use rsf_fit::fit::{FitOptions, fit, prepare};
    use rsf_fit::segment::{SegmentOptions, detect};
    use rsf_solvers::{Problem, Rodas4, solve};
    my_rsf_law::register().unwrap();
    let truth = Model::new(0.6, 1.0, 0.008, 0.02).with_state(StateVariable::new(PowerAging { n: 1.6 }, 0.011, 5.0));
    // the record starts in steady state at its first load-point velocity, as a fit assumes
    let loading = Loading::Segments(vec![
        Segment::for_displacement(1.0, 30.0),
        Segment::for_displacement(10.0, 100.0),
        Segment::for_displacement(1.0, 50.0),
        Segment::for_duration(0.0, 100.0),
        Segment::for_displacement(1.0, 60.0),
    ]);
    let sol = solve(&Problem::new(truth, loading, 1.0, 0.1), &Rodas4::new(1e-10, 1e-13)).unwrap();
    let law = rsf_laws::law_by_name(my_rsf_law::NAME, |_| Some(1.0)).unwrap();
    let rec = rsf_fit::data::Record {
        time: sol.time.clone(),
        load_point: sol.load_point.clone(),
        mu: sol.mu.clone(),
        ..Default::default()
    };
    let opts = FitOptions::new(vec![law], 0.02);
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let f = fit(&prepare(&rec, &segs, &opts).unwrap(), &opts).unwrap();
    let n = f.params.law_params["n1"];
    assert!((n - 1.6).abs() < 1e-4, "n = {n}, rms {:e}, {:?}", f.rms, f.params);
}
