//! A diagnosis names no cause from a fit that did not converge (issue 40: "the diagnosis does
//! not act on `converged`"). The Penn State p655 step 23 → 229 µm/s (`../shared/data`,
//! unlicensed, not bundled: the test prints SKIP without it): its stiffness candidate scores
//! best (ΔBIC −1,590, k 2.6× the calibrated 1e-3) from a fit stopped at LM's iteration limit.
//! On the main before the
//! change the record was `stiffness`; then the stiffness was set aside, saying why, and the
//! record was `second_state_variable`. Scored under a noise model in time (the break-timing
//! mask's gaps are gaps), the stiffness no longer scores best (ΔBIC −82.5 against the second
//! state's −140.6) and the record is `unexplained` with the second state as its best partial
//! extension; the stiffness, still unconverged, is named nowhere.

use std::path::Path;
use std::process::Command;

#[test]
fn a_candidate_whose_fit_did_not_converge_is_not_named() {
    let rec =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/psu-xlook-examples/p655intact100_reduced.csv");
    if !rec.exists() {
        println!("SKIP: {} not found (../shared beside the checkout)", rec.display());
        return;
    }
    let d = tempfile::tempdir().unwrap();
    let json = d.path().join("d.json");
    let o = Command::new(env!("CARGO_BIN_EXE_rsf"))
        .arg("diagnose")
        .arg(&rec)
        .args(["--lp-col", "lp_disp_um", "--t-min", "3870", "--t-max", "3878.9", "--stiffness", "1e-3", "--json"])
        .arg(&json)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let stiffness = v["candidates"].as_array().unwrap().iter().find(|c| c["cause"] == "stiffness").unwrap();
    assert_eq!(stiffness["converged"], false, "the premise: the stiffness fit does not converge");
    assert_ne!(v["cause"], "stiffness");
    assert_ne!(v["partial"], "stiffness");
    let reason = v["reason"].as_str().unwrap();
    // where it scores better than the cause named, the reason says why it was set aside
    let best = v["candidates"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["delta_bic"].as_f64().unwrap())
        .fold(f64::INFINITY, f64::min);
    if stiffness["delta_bic"].as_f64().unwrap() <= best {
        assert!(reason.contains("stiffness: the fit did not converge"), "{reason}");
    }
    // the cause named (or the partial extension given) comes from a fit that did
    assert_eq!(v["extended"]["converged"], true);
}
