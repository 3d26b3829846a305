//! A law file on the command line (issue 39): `--law-file` registers it for every command,
//! `rsf laws` lists it, `rsf check-law` runs the conformance kit, `rsf fit` fits its own
//! parameter, a manifest's `law` column takes its name; bad files and names say what is wrong.
//! On the main before issue 39 every one of these failed ("unknown law", "unknown field `n`",
//! no such command).

use std::path::PathBuf;
use std::process::{Command, Output};

fn rsf(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rsf")).args(args).output().unwrap()
}
fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}
fn path(rel: &str) -> String {
    repo().join(rel).to_str().unwrap().to_string()
}
fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

#[test]
fn a_law_file_is_listed_checked_and_fitted() {
    let law = path("examples/laws/power_aging.toml");
    let o = rsf(&["--law-file", &law, "laws"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("power-aging") && text(&o).contains("range [0.2, 5]"), "{}", text(&o));

    let o = rsf(&["check-law", &law, "--steady-state-dc-over-v", "--cases", "32"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("parameter_derivative: passed"), "{}", text(&o));

    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("fit.json");
    let rec = path("tests/data/outside/power_aging.csv");
    let o = rsf(&[
        "--law-file",
        &law,
        "fit",
        &rec,
        "--law",
        "power-aging",
        "--stiffness",
        "0.02",
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let n = v["params"]["law_params"]["n1"].as_f64().unwrap();
    assert!((n - 1.5).abs() < 0.005, "n = {n}");
}

#[test]
fn a_wrong_law_file_or_name_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "name = \"bad\"\ntheta_rate = \"1 - omega^m\"\n").unwrap();
    let o = rsf(&["--law-file", bad.to_str().unwrap(), "laws"]);
    assert!(!o.status.success());
    assert!(text(&o).contains("bad.toml:2:25: unknown name `m`"), "{}", text(&o));
    let o = rsf(&["fit", &path("tests/data/outside/power_aging.csv"), "--law", "power-aging", "--stiffness", "0.02"]);
    assert!(!o.status.success());
    assert!(text(&o).contains("unknown law `power-aging`") && text(&o).contains("--law-file"), "{}", text(&o));
    // a law that fails the kit: a claimed steady state it does not have
    let off = dir.path().join("off.toml");
    std::fs::write(&off, "name = \"off\"\ntheta_rate = \"1.1 - omega\"\n").unwrap();
    let o = rsf(&["check-law", off.to_str().unwrap(), "--steady-state-dc-over-v", "--cases", "16"]);
    assert!(!o.status.success());
    assert!(text(&o).contains("fails `steady_state`"), "{}", text(&o));
}

#[test]
fn a_manifest_names_a_law_from_a_law_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(repo().join("tests/data/outside/power_aging.csv"), dir.path().join("pa.csv")).unwrap();
    let manifest = dir.path().join("manifest.csv");
    std::fs::write(&manifest, "file,stiffness,law\npa.csv,0.02,power-aging\n").unwrap();
    let out = dir.path().join("out");
    let law = path("examples/laws/power_aging.toml");
    let o = rsf(&["--law-file", &law, "batch", manifest.to_str().unwrap(), "--out", out.to_str().unwrap(), "--fit"]);
    assert!(o.status.success(), "{}", text(&o));
    let fit = std::fs::read_to_string(out.join("records/pa.csv.fit.json"))
        .or_else(|_| std::fs::read_to_string(out.join("records/pa.fit.json")))
        .unwrap_or_else(|_| {
            panic!("no fit json in {:?}", std::fs::read_dir(out.join("records")).unwrap().collect::<Vec<_>>())
        });
    assert!(fit.contains("\"n1\""), "{fit}");
    // without the file the manifest's law is an error naming the line and column
    let o = rsf(&["batch", manifest.to_str().unwrap(), "--out", dir.path().join("o2").to_str().unwrap(), "--fit"]);
    assert!(!o.status.success() || text(&o).contains("unknown law"), "{}", text(&o));
    // the manifest itself names the law file (relative to the manifest): no --law-file needed
    std::fs::copy(&law, dir.path().join("power.toml")).unwrap();
    std::fs::write(&manifest, "file,stiffness,law_file,law\npa.csv,0.02,power.toml,power-aging\n").unwrap();
    let out3 = dir.path().join("o3");
    let o = rsf(&["batch", manifest.to_str().unwrap(), "--out", out3.to_str().unwrap(), "--fit"]);
    assert!(o.status.success(), "{}", text(&o));
    let summary = std::fs::read_to_string(out3.join("summary.csv")).unwrap();
    assert!(summary.contains("power-aging"), "{summary}");
    // a law file that is not there: the manifest's line and column
    std::fs::write(&manifest, "file,stiffness,law_file,law\npa.csv,0.02,nowhere.toml,power-aging\n").unwrap();
    let o = rsf(&["batch", manifest.to_str().unwrap(), "--out", dir.path().join("o4").to_str().unwrap(), "--fit"]);
    assert!(!o.status.success());
    assert!(text(&o).contains("line 2, column `law_file`") && text(&o).contains("nowhere.toml"), "{}", text(&o));
}

/// `rsf diagnose --baseline` takes any registered law (issue 39; on the main before it,
/// "power-aging" was refused as a baseline: only slip or aging): with the truth's own law as
/// the baseline, nothing is missing from the model, and the diagnosis says so.
#[test]
fn a_law_files_law_is_a_baseline() {
    let law = path("examples/laws/power_aging.toml");
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("d.json");
    let rec = path("tests/data/outside/power_aging.csv");
    let args = ["diagnose", &rec, "--stiffness", "0.02", "--baseline", "power-aging", "--json", json.to_str().unwrap()];
    let o = rsf(&args);
    assert!(!o.status.success(), "without the law file the name is unknown");
    assert!(text(&o).contains("power-aging"), "{}", text(&o));
    let mut with_file = vec!["--law-file", law.as_str()];
    with_file.extend(args);
    let o = rsf(&with_file);
    assert!(o.status.success(), "{}", text(&o));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["baseline"]["params"]["laws"][0], "power-aging", "{}", v["baseline"]);
    let n = v["baseline"]["params"]["law_params"]["n1"].as_f64().unwrap();
    assert!((n - 1.5).abs() < 0.01, "n = {n}");
    assert_eq!(v["cause"], "none", "{}", v["reason"]);
}
