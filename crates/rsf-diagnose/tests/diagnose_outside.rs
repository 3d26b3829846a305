//! Truths outside the one-step menu (issue 38), on records of the independent generator
//! (`benches/detection/generate.py --outside-tests`, scipy Radau; tests/data/outside/SOURCE.md):
//! a law of the library is named as the law, with its own parameter measured; a law no library
//! has is `unexplained`, never a confident wrong cause. Each record: one state, a = 0.008,
//! b = 0.011, Dc = 5 µm, white noise 1.5e-4 (PRZ: plus AR(1) of 1e-4, τ = 2 s); steps of
//! 0.5–2 decades and holds.
//!
//! On the main before issue 38 the PRZ, Nagata and one-state-mixture records could not be named
//! with their law (no such candidate) and the power-law-aging record was named
//! `cutoff_velocity` (a confident wrong cause); `Cause::Unexplained` did not exist.

use rsf_diagnose::{AdequacyVerdict, Cause, DiagnoseOptions, Diagnosis, diagnose};
use rsf_fit::data::{ReadOptions, read_record};
use rsf_fit::fit::FitOptions;
use rsf_fit::segment::{SegmentOptions, detect};

fn diagnosed(name: &str, k: f64) -> Diagnosis {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../tests/data/outside/{name}.csv"));
    let rec = read_record(&path, &ReadOptions::default()).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let fit = FitOptions::new(vec![rsf_laws::law_by_name("slip", |_| None).unwrap()], k);
    let d = diagnose(&rec, &segs, &DiagnoseOptions::new(fit)).unwrap();
    println!("{name}: {} — {}", d.cause, d.reason);
    d
}

/// The diagnosis of `tests/data/outside/{name}.csv` with protocol loading, as `rsf diagnose`
/// and the study have it.
fn diagnosed_with_protocol(name: &str, k: f64) -> Diagnosis {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../tests/data/outside/{name}.csv"));
    let rec = read_record(&path, &ReadOptions::default()).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut fit = FitOptions::new(vec![rsf_laws::law_by_name("slip", |_| None).unwrap()], k);
    fit.loading = rsf_fit::fit::LoadingMode::Protocol;
    let d = diagnose(&rec, &segs, &DiagnoseOptions::new(fit)).unwrap();
    println!("{name}: {}", d.reason);
    d
}

/// PRZ truth with steps and holds of 10–100 s: the evolution law, named as PRZ, and the PRZ
/// model explains the events to the noise level. (Before: `none`, its misfit read as drift.)
#[test]
fn a_prz_truth_is_named_as_prz() {
    let d = diagnosed("prz_holds", 0.02);
    assert_eq!(d.cause, Cause::EvolutionLaw);
    assert_eq!(d.effect.law.as_deref(), Some("prz"));
    assert_eq!(d.adequacy.verdict, AdequacyVerdict::Adequate);
}

/// One state healing by 0.3 Aging + 0.7 Slip, holds to 10⁴ s: the one-state mixture with its
/// aging share w measured (truth 0.3). (Before: a cut-off velocity, a mimic.)
#[test]
fn a_one_state_mixture_is_named_with_its_share() {
    let d = diagnosed("mix1_holds", 0.02);
    assert_eq!(d.cause, Cause::EvolutionLaw);
    assert_eq!(d.effect.law.as_deref(), Some("aging-slip"));
    let w = d.effect.w.unwrap();
    assert!((w - 0.3).abs() < 0.03, "w = {w}");
}

/// Nagata's law with c = 2: named as Nagata's, c measured.
#[test]
fn a_nagata_truth_is_named_with_its_c() {
    let d = diagnosed("nagata", 0.01);
    assert_eq!(d.cause, Cause::EvolutionLaw);
    assert_eq!(d.effect.law.as_deref(), Some("nagata"));
    let c = d.effect.c.unwrap();
    assert!((c - 2.0).abs() < 0.2, "c = {c}");
}

/// Power-law aging dθ/dt = 1 − Ω^1.5, a law no library has: not a confident wrong cause. The
/// best extension (a cut-off) still misfits where the events are, so the verdict is
/// `unexplained`, with the cut-off as the best partial extension and its events named.
#[test]
fn a_law_outside_the_library_is_unexplained() {
    let d = diagnosed("power_aging", 0.02);
    assert_eq!(d.cause, Cause::Unexplained);
    assert_eq!(d.adequacy.verdict, AdequacyVerdict::Inadequate);
    assert!(d.partial.is_some(), "the best partial extension is reported");
    assert!(d.gain.is_some() && d.extended.is_some());
    assert!(!d.adequacy.events.is_empty() && d.adequacy.events[0].ratio > 2.0);
    assert!(d.reason.starts_with("not explained"), "{}", d.reason);
}

/// A rate-dependent direct effect a + a1 ln(V/V0) (a law no library has), steps of 0.5–2
/// decades each ~5 Dc long: too short for the adequacy test's quiet placebos (untestable). The
/// evolution law (the Aging–Slip law) scores best on the whole record but predicts the
/// held-out part worse than the baseline; the cut-off that scores next is set aside by
/// nothing. The record's parts disagree, so no cause is named: `unexplained`, the cut-off as the
/// best partial extension, the disagreement in the JSON. (Record 23 of the `--outside` study,
/// `tests/data/outside/SOURCE.md`. Before: `cutoff_velocity`, a confident wrong cause.)
#[test]
fn parts_of_an_untestable_record_that_disagree_name_no_cause() {
    let d = diagnosed_with_protocol("rate_a_short_steps", 0.011935249730937679);
    assert_eq!(d.adequacy.verdict, AdequacyVerdict::Untestable);
    assert_eq!(d.cause, Cause::Unexplained, "{}", d.reason);
    assert_eq!(d.partial, Some(Cause::CutoffVelocity));
    let dis = d.disagreement.as_ref().expect("the disagreement is reported");
    assert_eq!(dis.better, Cause::EvolutionLaw);
    assert!(dis.heldout_rms_after.unwrap() > dis.heldout_rms_before.unwrap());
    assert!(d.reason.starts_with("not explained"), "{}", d.reason);
}

/// A rate-dependent direct effect (local slope a + a1 ln(V/V0), spanning ±15 % of a over the
/// record), steps 1 ↔ 0.00316, 0.1, 0.316 and 3.16 µm/s. The best extension, a cut-off
/// (Vc = 7.6e-4 µm/s), passes the one event window that can be tested (excess 0.1); the level
/// test sees what it misses: the truth's steady state bends in ln V, and the model puts the
/// 3.16 µm/s segment 4e-4 too low — four times its noise band — a change of level 3.3 times
/// the noise's and the fit's own uncertainty in variance (`levels.rs`; p = 0.01). The level
/// test is reported beside the verdict, not part of it yet (its false-alarm rate is still to be
/// measured on sets it was not shaped on), so the verdict is still the cut-off; this pins what the level
/// test sees. (Record 48 of the `--outside` study, `tests/data/outside/SOURCE.md`. On the main
/// before, no level test existed.)
#[test]
fn a_steady_state_bent_in_ln_v_shows_in_the_levels() {
    let d = diagnosed_with_protocol("rate_a_levels", 0.012256148243476378);
    assert_eq!(d.adequacy.verdict, AdequacyVerdict::Adequate, "the event window passes");
    let levels = &d.adequacy.levels;
    assert_eq!(levels.steps.len(), 4);
    assert!(levels.p_value < 0.05 && levels.excess > 2.0, "p {} excess {}", levels.p_value, levels.excess);
    // the worst step is the one into the fastest segment, its model level too low (the
    // residual's level too high)
    let worst = &levels.steps[0];
    assert!((worst.ln_v_ratio.exp() - 3.16).abs() < 0.05, "{}", worst.ln_v_ratio.exp());
    assert!(worst.offset > 3.0 * worst.noise, "{} vs {}", worst.offset, worst.noise);
}
