//! The diagnosis's shortcuts against the full computation (issue 22): its fits search their
//! optimum on bin means (`BinMeans::Search`) at the diagnosis's solver tolerance
//! (`DIAGNOSE_RTOL`), solve coarsely while far from the optimum and stop when a Gauss–Newton
//! step would gain less than 1e-4 in ln L (`DIAGNOSE_SEARCH`), and each result is evaluated on
//! every sample by one plain solve, its covariance from the bins; the full computation fits
//! every sample at `rsf fit`'s 1e-7 to LM's own stopping tests. On three records of the detection study, made by the
//! independent generator (`benches/detection/generate.py`: a second state under AR(1) noise in
//! time on variable sampling, a cut-off only a 10⁴ s hold reaches, and issue 21's 1/f-drift
//! gouge record with nothing hidden), both name the same cause, and every candidate's ΔBIC
//! agrees within `DBIC_TOLERANCE`.

use rsf_diagnose::{DiagnoseOptions, Diagnosis, diagnose};
use rsf_fit::data::{ReadOptions, read_record};
use rsf_fit::fit::{BinMeans, FitOptions, LoadingMode, SearchPrecision};
use rsf_fit::segment::{SegmentOptions, detect};
use rsf_laws::law_by_name;

/// ΔBIC may differ by this much plus `DBIC_RELATIVE` of itself: the optima differ by a small
/// fraction of a standard error (`tests/bins.rs`), which moves a log-likelihood by far less
/// than 1; a decision turns on ΔBIC beyond −10 (`DECISIVE`).
const DBIC_TOLERANCE: f64 = 1.0;
const DBIC_RELATIVE: f64 = 2e-3;

fn both(file: &str, k: f64) -> (Diagnosis, Diagnosis) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/detection").join(file);
    let rec = read_record(&path, &ReadOptions::default()).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut fit = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], k);
    fit.loading = LoadingMode::Protocol;
    let short = DiagnoseOptions::new(fit);
    assert!(matches!(short.fit.bins, BinMeans::Search { .. }), "the diagnosis searches on bins by default");
    assert!(short.fit.search.lnl_tolerance.is_some() && short.fit.search.coarse_rtol.is_some());
    let mut full = short.clone();
    full.fit.bins = BinMeans::Off;
    full.fit.rtol = 1e-7;
    full.fit.search = SearchPrecision::default();
    (diagnose(&rec, &segs, &short).unwrap(), diagnose(&rec, &segs, &full).unwrap())
}

fn same(file: &str, k: f64) {
    let (s, f) = both(file, k);
    println!("{file}: shortcut {} / full {}", s.cause, f.cause);
    assert_eq!(s.cause, f.cause, "shortcut: {}\nfull: {}", s.reason, f.reason);
    for cf in &f.candidates {
        let cs = s.candidates.iter().find(|c| c.cause == cf.cause).expect("the same candidates");
        let d = (cs.delta_bic - cf.delta_bic).abs();
        println!("  {:<24} ΔBIC {:>12.2} full {:>12.2}", cf.cause.as_str(), cs.delta_bic, cf.delta_bic);
        assert!(
            d <= DBIC_TOLERANCE + DBIC_RELATIVE * cf.delta_bic.abs(),
            "{}: ΔBIC {} vs {}",
            cf.cause,
            cs.delta_bic,
            cf.delta_bic
        );
    }
    let (ns, nf) = (s.evidence.noise.as_ref().unwrap(), f.evidence.noise.as_ref().unwrap());
    assert!((ns.n_effective / nf.n_effective - 1.0).abs() < 0.05, "n_eff {} vs {}", ns.n_effective, nf.n_effective);
}

#[test]
fn second_state_on_variable_sampling_as_the_full_computation() {
    same("rec_049.csv", 0.03486150845858375);
}

#[test]
fn cutoff_in_a_long_hold_as_the_full_computation() {
    same("rec_082.csv", 0.0525811245151848);
}

#[test]
fn drift_with_nothing_hidden_as_the_full_computation() {
    same("drift_gouge.csv", 0.004);
}
