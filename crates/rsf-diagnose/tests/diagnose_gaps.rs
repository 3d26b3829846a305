//! A uniformly sampled record with a noisy load point: the samples its breaks' timing cannot
//! predict are left out (`timing.rs`), seconds after each break, and the residuals' noise
//! model must read those gaps as gaps. In sample index (Whittle's likelihood, replicates drawn
//! per sample) the residuals on the two sides of a gap were neighbours: the real noise, which
//! decorrelated across the gap's seconds, jumped there, a model that bent across the jumps won
//! likelihood, and the null replicates, drawn per sample, never had such jumps.
//!
//! The record (`tests/data/detection/slip_truth_masked_gaps.csv`, record 39 of the 111-record
//! study's fresh seed 3, made by the independent generator) is a Slip-law truth with nothing
//! hidden: gouge, a staircase 1–300 µm/s and holds, AR(1) friction noise (τ 3.7 s), encoder
//! noise of 0.12 µm on the load point, spikes, time jitter. On the main before this test it
//! was named `cutoff_velocity` (ΔBIC −109, its gain 2Δln L 118 against 4 null replicates'
//! 0.08 ± 0.16, false-alarm probability 1e-161), with three more candidates decisive; the same
//! friction with the load point's true lines was `none`.

mod common;

use common::diagnose_detection_record;
use rsf_diagnose::Cause;

#[test]
fn gaps_left_by_the_timing_mask_are_gaps_in_time() {
    let d = diagnose_detection_record("slip_truth_masked_gaps.csv", 0.0031904591269690096);
    // the break-timing mask left samples out, and the noise model is the one in time
    assert!(d.timing.as_ref().is_some_and(|t| t.samples > 0), "{:?}", d.timing);
    let noise = d.evidence.noise.as_ref().expect("a noise model");
    assert!(noise.sampling.is_some(), "the residuals' noise model is in sample index");
    assert_eq!(d.cause, Cause::None, "{}", d.reason);
    assert!(d.adequacy.misfits().is_empty(), "{:?}", d.adequacy.misfits());
    let decisive: Vec<_> =
        d.candidates.iter().filter(|c| c.delta_bic < rsf_diagnose::DECISIVE).map(|c| c.cause).collect();
    assert!(decisive.is_empty(), "decisive on a Slip truth: {decisive:?}");
}
