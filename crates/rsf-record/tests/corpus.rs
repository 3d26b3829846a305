//! The regression corpus (`tests/corpus/`): lab export variants that must read to the same 20
//! rows, and reproducers of the broken files of issue 20 that must be refused (or, a cut last
//! line, dropped with a warning), each with its expected outcome in `expected.json`. The files
//! are made by `tests/corpus/README.md`'s script, not by this crate.

use rsf_record::{Column, Spec, read_path};
use std::path::PathBuf;

#[test]
fn every_corpus_file_gives_its_expected_outcome() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/corpus");
    let expected: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("expected.json")).unwrap()).unwrap();
    let mut reference: Option<Vec<Vec<f64>>> = None;
    for (file, want) in expected.as_object().unwrap() {
        let names: Vec<String> = match want.get("columns") {
            Some(c) => c.as_array().unwrap().iter().map(|n| n.as_str().unwrap().to_string()).collect(),
            None => vec!["time_s".into(), "lp_um".into(), "mu".into()],
        };
        let spec = Spec::timed(vec![Column::new(&names[0]), Column::new(&names[1]), Column::friction(&names[2])]);
        let mut rows = vec![];
        let got = read_path(&dir.join(file), &spec, |_, v| {
            rows.push(v.to_vec());
            Ok(())
        });
        match (got, want.get("error").and_then(|e| e.as_str())) {
            (Err(e), Some(msg)) => assert!(e.to_string().contains(msg), "{file}: `{e}` lacks `{msg}`"),
            (Ok(_), Some(msg)) => panic!("{file}: accepted, expected `{msg}`"),
            (Err(e), None) => panic!("{file}: {e}"),
            (Ok(summary), None) => {
                assert_eq!(rows.len() as u64, want["rows"].as_u64().unwrap(), "{file}");
                if let Some(w) = want.get("warning").and_then(|w| w.as_str()) {
                    assert!(summary.warnings.iter().any(|x| x.contains(w)), "{file}: {:?}", summary.warnings);
                } else {
                    assert!(summary.warnings.is_empty(), "{file}: {:?}", summary.warnings);
                }
                // every variant reads to the same numbers as the first
                let r = reference.get_or_insert_with(|| rows.clone());
                assert_eq!(rows[..], r[..rows.len()], "{file}");
            }
        }
    }
}
