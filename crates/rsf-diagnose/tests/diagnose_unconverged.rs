//! A better-scoring rival whose fit did not converge: its ΔBIC, at the best point found, is an
//! upper bound on its optimum's, so the cause chosen over it is beaten on the record, and the
//! diagnosis names neither (`undecided`).
//!
//! The record (`tests/data/detection/unconverged_rival_slip_trend.csv`, record 54 of the
//! 111-record study's seed 5, made by the independent generator) hides a slip trend of
//! g = 1e-7 /µm under one Slip-law state on a gouge staircase (1–300 µm/s, holds of 3–300 s;
//! time jitter, a nonzero start time, four spikes; 13,962 samples). The trend's fit exhausted
//! its step budget at ΔBIC −33.4 (g 7.2e-8, the truth's order) and was set aside as not
//! converged; the second state stopped at its iteration limit at −28.9; and a Slip–Aging
//! mixture whose aging state holds 0.3 % of b was named at −12.6 (false-alarm probability
//! 3.4e-9, its bound 3.5e-4). On the main before this test the record was `evolution_law`
//! (slip+aging): a confident wrong cause.

mod common;

use common::diagnose_detection_record;
use rsf_diagnose::Cause;

#[test]
fn a_cause_beaten_by_a_rival_that_did_not_converge_is_not_named() {
    let d = diagnose_detection_record("unconverged_rival_slip_trend.csv", 0.004560632516018635);
    assert_ne!(d.cause, Cause::EvolutionLaw, "{}", d.reason);
    let trend = d.candidates.iter().find(|c| c.cause == Cause::SlipTrend).expect("the slip trend was tried");
    if trend.converged {
        // a fit that reaches the trend's optimum names the truth
        assert_eq!(d.cause, Cause::SlipTrend, "{}", d.reason);
        return;
    }
    assert_eq!(d.cause, Cause::Undecided, "{}", d.reason);
    let (chosen, rival) = (d.undecided[0], d.undecided[1]);
    assert_eq!(rival.0, Cause::SlipTrend, "{:?}", d.undecided);
    assert!(rival.1 < chosen.1, "{:?}", d.undecided);
    assert!(d.reason.contains("did not converge"), "{}", d.reason);
    assert_eq!(d.apart, Some(rsf_diagnose::Apart::Unconverged));
    assert_eq!(serde_json::to_value(&d).unwrap()["apart"], "unconverged");
}
