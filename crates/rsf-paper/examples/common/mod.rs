//! What every figure example shares: the output directory and writing the three files.
//!
//! `NAME.svg` is the figure, `NAME.csv` the plotted curves (long format) and `NAME.json` the
//! figure's numbers: the library's result without its sampled curves (arrays of more than
//! [`MAX_JSON_ARRAY`] numbers), which are in the CSV.

use serde::Serialize;
use serde_json::Value;
use std::path::PathBuf;

/// Longer arrays of numbers are curves: left out of the JSON.
pub const MAX_JSON_ARRAY: usize = 32;

/// The first command-line argument, or `docs/figures` of the workspace; created if missing.
pub fn out_dir() -> PathBuf {
    let dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/figures"));
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
    dir
}

/// Removes the sampled curves from a serialized result, and the objects they leave empty.
fn strip_curves(v: &mut Value) {
    fn emptied(v: &Value) -> bool {
        match v {
            Value::Object(m) => m.is_empty(),
            Value::Array(a) => !a.is_empty() && a.iter().all(emptied),
            _ => false,
        }
    }
    match v {
        Value::Object(m) => {
            m.retain(
                |_, x| !matches!(x, Value::Array(a) if a.len() > MAX_JSON_ARRAY && a.iter().all(Value::is_number)),
            );
            m.values_mut().for_each(strip_curves);
            m.retain(|_, x| !emptied(x));
        }
        Value::Array(a) => a.iter_mut().for_each(strip_curves),
        _ => {}
    }
}

/// Writes `NAME.svg`, `NAME.csv` and `NAME.json` into [`out_dir`] and lists them.
pub fn write_all(name: &str, svg: &str, csv: &str, result: &impl Serialize) {
    let dir = out_dir();
    let mut json = serde_json::to_value(result).expect("results serialize");
    strip_curves(&mut json);
    let json = serde_json::to_string_pretty(&json).expect("JSON values serialize") + "\n";
    for (ext, text) in [("svg", svg), ("csv", csv), ("json", json.as_str())] {
        let path = dir.join(format!("{name}.{ext}"));
        std::fs::write(&path, text).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
        println!("wrote {}", path.display());
    }
}
