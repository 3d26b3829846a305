//! Helpers shared by rsf's cross-crate tests: reference files and the shared data folder.

use std::path::{Path, PathBuf};

/// This crate's directory.
pub fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The bundled data directory `tests/data`.
pub fn data_dir() -> PathBuf {
    crate_dir().join("data")
}

/// `../shared/data/<name>` beside the checkout, if present. Tests that need unlicensed records
/// use this and print a clear SKIP line when it is absent (CI always has it).
pub fn shared_data(name: &str) -> Option<PathBuf> {
    let p = crate_dir().join("..").join("..").join("shared").join("data").join(name);
    if p.exists() { Some(p) } else { None }
}

/// A numeric CSV with a header row: (column names, columns).
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(|s| s.trim().to_string()).collect();
    let mut cols = vec![Vec::new(); header.len()];
    for line in lines.filter(|l| !l.trim().is_empty()) {
        for (c, v) in line.split(',').enumerate() {
            cols[c].push(v.trim().parse::<f64>().unwrap_or(f64::NAN));
        }
    }
    (header, cols)
}

/// `cases.json` of the reference set.
pub fn reference_cases() -> serde_json::Value {
    let p = data_dir().join("reference/rsfmodel/cases.json");
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}
