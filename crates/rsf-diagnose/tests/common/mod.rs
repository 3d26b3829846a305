//! What the tests on the detection study's records share: a record of
//! `tests/data/detection/` (made by the independent generator; SOURCE.md there) diagnosed as
//! the study diagnoses it — a Slip-law baseline at the nominal stiffness, the protocol's
//! loading, two threads.

use rsf_diagnose::{DiagnoseOptions, Diagnosis, diagnose};
use rsf_fit::data::{ReadOptions, read_record};
use rsf_fit::fit::{FitOptions, LoadingMode};
use rsf_fit::segment::{SegmentOptions, detect};

/// The diagnosis of `tests/data/detection/<file>` with a Slip-law baseline at the nominal
/// stiffness `k` (1/µm), its cause and reason printed.
pub fn diagnose_detection_record(file: &str, k: f64) -> Diagnosis {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/detection").join(file);
    let rec = read_record(&path, &ReadOptions::default()).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut fit = FitOptions::new(vec![rsf_laws::law_by_name("slip", |_| None).unwrap()], k);
    fit.loading = LoadingMode::Protocol;
    let d = diagnose(&rec, &segs, &DiagnoseOptions { threads: 2, ..DiagnoseOptions::new(fit) }).unwrap();
    println!("{file}: {}: {}", d.cause, d.reason);
    d
}
