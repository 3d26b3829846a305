//! A null whose replicates collapse onto the baseline, on a record with nothing hidden.
//!
//! An Aging–Slip share w ≥ 0 sits at its boundary when the truth is the Slip law, so many of
//! its null replicates refit to w = 0 and gain nothing (0 to rounding), and the rest gain like
//! a χ²₁. Here the first four replicates all collapsed (gains 0 to 0.002): their moments made a
//! null of scale 0.0005 that put the record's gain of 10.3 at a false-alarm probability of 0,
//! the sequential test stopped there, and a Slip-law record was named an Aging share of
//! w = 0.00017 (a false alarm of the detection study). Thirty-two replicates gain 5.2 ± 10.5,
//! and five of them reach 10.3. The test now stops early on a gain beyond chance only when at
//! least two replicates gained.
//!
//! The record (`tests/data/detection/boundary_null_collapsed.csv`, record 80 of the 111-record
//! study's seed 2, made by the independent generator) hides nothing: one Slip-law state on bare
//! rock, steps 1 ↔ 0.0316–3.16 µm/s, holds of 10–300 s, load-point encoder noise of 0.063 µm,
//! white friction noise and five spikes. On the main before this test it was `evolution_law`
//! (aging-slip, 0 of 4 replicates, false-alarm probability 0).

mod common;

use common::diagnose_detection_record;
use rsf_diagnose::Cause;

#[test]
fn replicates_collapsed_at_a_boundary_do_not_name_a_cause() {
    let d = diagnose_detection_record("boundary_null_collapsed.csv", 0.012107083304195465);
    assert_eq!(d.cause, Cause::None, "{}", d.reason);
    let mixture = d.candidates.iter().find(|c| c.cause == Cause::EvolutionLaw).expect("the evolution law was tried");
    let null = mixture.null.as_ref().expect("its ΔBIC was decisive, so its null was drawn");
    assert!(null.replicates > 4, "{null:?}");
    assert!(null.false_alarm_probability > 0.01, "{null:?}");
}

/// A null heavy in its tail at a boundary, on a record with nothing hidden
/// (`tests/data/detection/boundary_null_heavy_tail.csv`, record 65 of the study's seed 2: Slip
/// law, variable sampling, time jitter, load-point encoder noise of 0.19 µm, six spikes).
///
/// The Aging–Slip share's replicates collapse onto the baseline on about half their draws and
/// gain 1–100 on the rest. Its gain on the record, 107.5, lay beyond all sixteen replicates,
/// whose moments taken with their zeros put it at 3.3e-4, and the share (w = 0.00057) was named.
/// The null is now a boundary mixture (the share that gained, matched by moments) with a bound
/// at the upper confidence limit of its scale; where the bound and the estimate fall on either
/// side of the level, the test draws on to 32 and 64 replicates. On the main before this test
/// the record was `evolution_law` (aging-slip, 16 replicates, false-alarm probability 3.3e-4).
#[test]
fn a_heavy_tailed_null_at_a_boundary_draws_on_and_names_nothing() {
    let d = diagnose_detection_record("boundary_null_heavy_tail.csv", 0.01271656672793578);
    assert_eq!(d.cause, Cause::None, "{}", d.reason);
    let share = d.candidates.iter().find(|c| c.cause == Cause::EvolutionLaw).expect("the evolution law was tried");
    let null = share.null.as_ref().expect("its ΔBIC was decisive, so its null was drawn");
    assert!(null.replicates > 16, "{null:?}");
    assert!(null.false_alarm_upper >= 0.01, "{null:?}");
    assert!(null.false_alarm_upper >= null.false_alarm_probability, "{null:?}");
}
