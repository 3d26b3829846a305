//! A law the user registers is a candidate of the diagnosis (issues 38 and 39): on the
//! power-law-aging record of the independent generator (n = 1.5; tests/data/outside/SOURCE.md),
//! with the law file registered the diagnosis names `evolution_law` with `power-aging` and n
//! measured, and the named model explains the events. Without it, no law on the menu is that
//! law (tests/diagnose_outside.rs). Its own test binary: the registry is one per process.

use rsf_diagnose::{AdequacyVerdict, Cause, DiagnoseOptions, diagnose};
use rsf_fit::data::{ReadOptions, read_record};
use rsf_fit::fit::FitOptions;
use rsf_fit::segment::{SegmentOptions, detect};

#[test]
fn a_registered_law_is_named_when_it_is_the_truth() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let name = rsf_laws::text_law::register_file(&root.join("examples/laws/power_aging.toml")).unwrap();
    assert_eq!(name, "power-aging");
    let rec = read_record(&root.join("tests/data/outside/power_aging.csv"), &ReadOptions::default()).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let fit = FitOptions::new(vec![rsf_laws::law_by_name("slip", |_| None).unwrap()], 0.02);
    let d = diagnose(&rec, &segs, &DiagnoseOptions::new(fit)).unwrap();
    println!("{} — {}", d.cause, d.reason);
    assert_eq!(d.cause, Cause::EvolutionLaw, "{}", d.reason);
    assert_eq!(d.effect.law.as_deref(), Some("power-aging"));
    let n = d.effect.law_parameters["n"];
    assert!((n - 1.5).abs() < 0.01, "n = {n}");
    assert_eq!(d.adequacy.verdict, AdequacyVerdict::Adequate);
    // the JSON carries n under its own name
    let json = serde_json::to_value(&d).unwrap();
    assert_eq!(json["effect"]["law"], "power-aging");
    assert!((json["effect"]["n"].as_f64().unwrap() - n).abs() < 1e-12);
}
