//! The report words a registered law's own parameters (issue 39): the power-law-aging record
//! of the independent generator, diagnosed with the law file registered, reads "the power-law
//! aging law (n = 1.50…) instead of the slip law". Its own test binary: the registry is one
//! per process.

use rsf_diagnose::{Cause, DiagnoseOptions, diagnose};
use rsf_fit::data::{ReadOptions, read_record};
use rsf_fit::fit::FitOptions;
use rsf_fit::segment::{SegmentOptions, detect};

#[test]
fn the_verdict_names_a_registered_laws_parameters() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    rsf_laws::text_law::register_file(&root.join("examples/laws/power_aging.toml")).unwrap();
    let rec = read_record(&root.join("tests/data/outside/power_aging.csv"), &ReadOptions::default()).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let fit = FitOptions::new(vec![rsf_laws::law_by_name("slip", |_| None).unwrap()], 0.02);
    let d = diagnose(&rec, &segs, &DiagnoseOptions::new(fit)).unwrap();
    assert_eq!(d.cause, Cause::EvolutionLaw, "{}", d.reason);
    let words = rsf_report::verdict(&d);
    assert!(words.contains("power-law aging law (n = 1.5"), "{words}");
}
