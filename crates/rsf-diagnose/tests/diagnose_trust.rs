//! A diagnosis you can trust: the same JSON for any thread count, a cut-off far below every
//! starting value found by the Vc profile, and a protocol-reconstruction error reported as such
//! instead of blamed on physics. Records are made by Rodas4 at rtol 1e-11 (a different path
//! from the fits' Dopri5 sensitivity solves), with models different from the baseline.

use rsf_core::{Model, StateVariable};
use rsf_diagnose::{Cause, DiagnoseOptions, Diagnosis, diagnose};
use rsf_fit::fit::{FitOptions, LoadingMode};
use rsf_fit::segment::{SegmentKind, SegmentOptions, detect};
use rsf_fit::synthetic::{Noise, SampledSegment, record};
use rsf_laws::{KatoTullis, Slip, law_by_name};

fn options(k: f64, loading: LoadingMode) -> DiagnoseOptions {
    let mut fit = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], k);
    fit.loading = loading;
    DiagnoseOptions::new(fit)
}

/// The diagnosis of a record of `tests/data/detection` at nominal stiffness `k`, protocol
/// loading (as `rsf diagnose` has it).
fn diagnosed_record(file: &str, k: f64) -> Diagnosis {
    use rsf_fit::data::{ReadOptions, read_record};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/detection").join(file);
    let rec = read_record(&path, &ReadOptions::default()).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    diagnose(&rec, &segs, &options(k, LoadingMode::Protocol)).unwrap()
}

fn base() -> Model {
    Model::new(0.6, 1.0, 0.010, 0.005)
}

/// Steps and one hold: small enough for a quick test, with a slip trend to find.
fn short_protocol() -> Vec<SampledSegment> {
    vec![(1.0, 40.0, 0.1), (10.0, 8.0, 0.1), (1.0, 60.0, 0.1), (0.0, 300.0, 1.0), (1.0, 60.0, 0.1)]
}

/// The JSON of a diagnosis — every number, the cause, the candidates, the null calibration —
/// is identical on 1 and 2 threads: budgets are counted in integrator steps, results land in
/// fixed slots, and the bootstrap seeds are derived from the replicate number.
#[test]
fn same_json_for_one_and_two_threads() {
    let m = base().with_state(StateVariable::new(Slip, 0.013, 8.0)).with_slip_trend(4e-6);
    let rec = record(&m, 1.0, &short_protocol(), Noise { sigma: 2e-4, tau: 1.0 }, 11).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut o = options(0.005, LoadingMode::Protocol);
    o.null_replicates = 6;
    let run = |threads: usize| {
        let d = diagnose(&rec, &segs, &DiagnoseOptions { threads, ..o.clone() }).unwrap();
        serde_json::to_string(&d).unwrap()
    };
    let (one, two) = (run(1), run(2));
    assert!(one.contains("\"null\""), "the null calibration ran: {one}");
    assert_eq!(one, two);
}

/// A Kato–Tullis cut-off of 5e-6 µm/s on bare rock in a stiff machine (k = 0.1 /µm) lives only
/// at the end of a 10⁴ s hold (where V falls to ~1e-5 µm/s) and in its reslide peak; the
/// profile over the baseline's slip rates finds it within a factor 2.
#[test]
fn a_cutoff_below_every_starting_value_is_found() {
    let proto: Vec<SampledSegment> = vec![
        (1.0, 60.0, 0.1),
        (10.0, 10.0, 0.1),
        (1.0, 80.0, 0.1),
        (0.0, 100.0, 1.0),
        (1.0, 60.0, 0.1),
        (0.0, 10_000.0, 10.0),
        (1.0, 80.0, 0.1),
    ];
    let m = Model::new(0.6, 1.0, 0.006, 0.1).with_state(StateVariable::new(KatoTullis { vc: 5e-6 }, 0.009, 5.0));
    let rec = record(&m, 1.0, &proto, Noise { sigma: 2e-4, tau: 0.0 }, 21).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let d = diagnose(&rec, &segs, &options(0.1, LoadingMode::Protocol)).unwrap();
    println!("{}\n{:?}", d.reason, d.candidates.iter().map(|c| (c.cause, c.delta_bic, &c.effect)).collect::<Vec<_>>());
    assert_eq!(d.cause, Cause::CutoffVelocity, "{}", d.reason);
    let vc = d.effect.vc.unwrap();
    assert!((vc / 5e-6).ln().abs() < 2f64.ln(), "Vc {vc}");
}

/// The lab-realistic failure of the detection study: record 82 (`tests/data/detection`, made by
/// the independent generator `benches/detection/generate.py`: bare rock, rock steps down to
/// 3e-4 µm/s, holds of 30–10⁴ s, a cut-off of 3e-6 µm/s that only the second half of the last
/// hold reaches, time jitter and load-point encoder noise). The held-out split falls inside that
/// hold: the training part holds no evidence of Vc, and its fit predicts the rest 4× worse. The
/// previous rule called that overfitting and named a mixture of laws; the cut-off must be named.
#[test]
fn a_cutoff_only_the_last_hold_reaches_survives_the_held_out_test() {
    let d = diagnosed_record("rec_082.csv", 0.0525811245151848);
    let c = d.candidates.iter().find(|c| c.cause == Cause::CutoffVelocity).unwrap();
    println!("{}\n{:?} {:?} {:?}", d.reason, c.heldout_rms_before, c.heldout_rms_after, c.heldout_training_gain);
    // the situation the old rule vetoed: a worse held-out prediction …
    assert!(c.heldout_rms_after.unwrap() > 1.05 * c.heldout_rms_before.unwrap());
    // … from a training part without evidence of the effect
    assert!(c.heldout_training_gain.unwrap() > rsf_diagnose::DECISIVE);
    assert_eq!(d.cause, Cause::CutoffVelocity, "{}", d.reason);
    let vc = d.effect.vc.unwrap();
    assert!((vc / 3e-6).ln().abs() < 2f64.ln(), "Vc {vc}");
}

/// A hidden cut-off made visible by a 10⁴ s hold (tests/data/design/cutoff_after_long_hold.csv,
/// the design study's first cut-off case with its designed segment): the baseline's parameters
/// with any cut-off heal so much in the hold that the reslide runs away at every Vc of the
/// profile. The cut-off candidate must still be fitted (from steadier starts, then from the
/// best cut-off fit), not vanish — the diagnosis then named `none`.
#[test]
fn a_cutoff_whose_profile_start_runs_away_after_a_long_hold_is_still_fitted() {
    use rsf_fit::data::{ReadOptions, read_record};
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/design/cutoff_after_long_hold.csv");
    let rec = read_record(&path, &ReadOptions::default()).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let d = diagnose(&rec, &segs, &options(0.0026919553456917138, LoadingMode::Protocol)).unwrap();
    assert!(d.candidates.iter().any(|c| c.cause == Cause::CutoffVelocity), "no cut-off candidate: {}", d.reason);
    assert_eq!(d.cause, Cause::CutoffVelocity, "{}", d.reason);
    let vc = d.effect.vc.unwrap();
    assert!((vc / 1.2115e-3).ln().abs() < 2f64.ln(), "Vc {vc}");
}

/// An Aging/Slip record with a normal-stress drop of 5 % over 1 s at its end (the design
/// study's `evolution_law_018` with its designed segment): the drop forces fast slip, which
/// every cold start of the Slip-law baseline turns into a run-away. The baseline is then fitted
/// on the record before that segment first and continued from there; before, the diagnosis
/// failed with the blow-up.
#[test]
fn a_baseline_whose_cold_starts_run_away_late_is_continued_from_the_record_before() {
    use rsf_diagnose::{diagnosis_fit_options, without_spikes};
    use rsf_fit::data::{ReadOptions, read_record};
    use rsf_fit::fit::{FitError, fit, prepare};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/design/sigma_drop_aging.csv");
    let ro = ReadOptions { normal_col: Some("normal_stress_mpa".into()), ..ReadOptions::default() };
    let rec = read_record(&path, &ro).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let o = options(0.0004622440548290379, LoadingMode::Protocol);
    // what the diagnosis meets: cold starts that run away at the drop of σ — every one of them
    // while a start that ran away set the later starts' budget; since a start that ran away no
    // longer starves the others (issue 40), a later start may get through
    let fo = diagnosis_fit_options(&o);
    let (clean, csegs, _) = without_spikes(&rec, &segs);
    match fit(&prepare(&clean, &csegs, &fo).unwrap(), &fo) {
        Err(FitError::Start(rsf_solvers::SolveError::BlowUp { .. })) => {}
        Ok(f) => assert!(f.starts_failed >= 1, "no start ran away: {} of {}", f.starts_failed, f.starts),
        Err(e) => panic!("{e}"),
    }
    let d = diagnose(&rec, &segs, &o).unwrap();
    assert_eq!(d.cause, Cause::EvolutionLaw, "{}", d.reason);
}

/// A record from the design study, read with its normal stress when it has one.
fn study_record(name: &str, sigma: bool) -> (rsf_fit::data::Record, Vec<rsf_fit::segment::Segment>) {
    use rsf_fit::data::{ReadOptions, read_record};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/design").join(name);
    let ro = ReadOptions { normal_col: sigma.then(|| "normal_stress_mpa".into()), ..ReadOptions::default() };
    let rec = read_record(&path, &ro).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    (rec, segs)
}

/// A designed drop of σ at the end of a steps-only record of an Aging/Slip mixture (the design
/// study's seed-2 `evolution_law_017` with its designed segment). The held-out part holds the
/// record's only change of σ, which the training part never saw: the mixture's training fit
/// predicts a run-away at the drop, and the true law was set aside as "could not be fitted to
/// the held-out training part" — the diagnosis named `none`. Such a held-out test cannot judge
/// the candidates; the null calibration does, at the stricter level.
#[test]
fn a_change_of_sigma_only_the_held_out_part_holds_does_not_judge() {
    let (rec, segs) = study_record("sigma_drop_in_heldout.csv", true);
    let d = diagnose(&rec, &segs, &options(0.0008699461187032379, LoadingMode::Protocol)).unwrap();
    assert_eq!(d.cause, Cause::EvolutionLaw, "{}", d.reason);
    let c = d.candidates.iter().find(|c| c.cause == Cause::EvolutionLaw).unwrap();
    assert!(c.heldout_uninformative && c.heldout_rms_after.is_none(), "{:?}", c.heldout_rms_after);
    let null = c.null.as_ref().expect("the null calibration judged it");
    assert!(null.false_alarm_probability < 1e-3, "{}", null.false_alarm_probability);
}

/// A designed drop of σ by 20 % over 1 s at the end of a steps-only record of an Aging/Slip
/// mixture (the design study's seed-3 `evolution_law_004`). Every start of the Slip-law
/// baseline, and the optimum of the record before the drop, ran away at the drop, and the
/// diagnosis stopped with that error. Grown to its size in quarters, each fit starting from the
/// one before, the drop is followed, and the mixture is named with its true share.
#[test]
fn a_drop_of_sigma_no_start_survives_is_grown_in_steps() {
    let (rec, segs) = study_record("sigma_drop_20pct.csv", true);
    let d = diagnose(&rec, &segs, &options(0.000675, LoadingMode::Protocol)).unwrap();
    names_the_half_and_half_mixture(&d, 20.887, 0.1);
}

/// An Aging/Slip mixture (half each, sharing Dc = 5.92 µm) after a designed 300 s hold (the
/// design study's seed-1 `evolution_law_026`). From the Slip-law baseline's optimum the
/// mixture's fit stalled, and a cut-off velocity (Vc = 13 µm/s) mimicking the hold's healing
/// scored best: the diagnosis named `cutoff_velocity`. Started also from the Aging law's
/// optimum, the mixture finds the truth and wins.
#[test]
fn a_mixture_starts_from_the_other_laws_optimum_too() {
    let (rec, segs) = study_record("mixture_after_hold.csv", false);
    let d = diagnose(&rec, &segs, &options(0.0024923571954179654, LoadingMode::Protocol)).unwrap();
    names_the_half_and_half_mixture(&d, 5.9165, 0.05);
}

/// `d` names the evolution law: an Aging/Slip mixture sharing Dc, with half its healing each
/// (±0.05) and Dc within `dc_tol` of `dc` µm.
fn names_the_half_and_half_mixture(d: &rsf_diagnose::Diagnosis, dc: f64, dc_tol: f64) {
    assert_eq!(d.cause, Cause::EvolutionLaw, "{}", d.reason);
    let p = &d.extended.as_ref().unwrap().params;
    assert_eq!(p.laws, ["slip", "aging"]);
    let share = p.b[1] / (p.b[0] + p.b[1]);
    assert!((share - 0.5).abs() < 0.05, "aging share {share}");
    assert!((p.dc[0] / dc - 1.0).abs() < dc_tol, "dc {}", p.dc[0]);
}

/// A plain Slip-law record whose reconstructed protocol ends the last hold 0.3 s late (the
/// reslide then starts late in the model): under protocol loading the reslide misfits far
/// above every other segment. The diagnosis reports the protocol problem at that break,
/// continues with record loading, and names no physical cause.
#[test]
fn a_reconstruction_error_is_not_blamed_on_physics() {
    let proto: Vec<SampledSegment> = vec![
        (1.0, 60.0, 0.1),
        (10.0, 10.0, 0.1),
        (1.0, 80.0, 0.1),
        (0.0, 100.0, 0.1),
        (1.0, 60.0, 0.1),
        (0.0, 3000.0, 0.1),
        (1.0, 40.0, 0.1),
    ];
    let m = base().with_state(StateVariable::new(Slip, 0.013, 8.0));
    let rec = record(&m, 1.0, &proto, Noise { sigma: 2e-4, tau: 0.0 }, 31).unwrap();
    let mut segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    assert_eq!(segs.len(), proto.len());
    // the old failure: the hold ends three samples late
    let (h, r) = (segs.len() - 2, segs.len() - 1);
    assert_eq!(segs[h].kind, SegmentKind::Hold);
    segs[h].i1 += 3;
    segs[r].i0 += 3;
    segs[r].t0 += 0.3;
    segs[h].t1 = segs[r].t0;
    segs[r].lp0 += 0.3 * segs[r].v;
    let d = diagnose(&rec, &segs, &options(0.005, LoadingMode::Protocol)).unwrap();
    println!("{}", d.reason);
    let rc = d.reconstruction.as_ref().expect("a reconstruction problem is reported");
    println!("{}", rc.message);
    assert!((rc.t - segs[r].t0).abs() < 1e-9, "at the late break: {rc:?}");
    assert_eq!(d.loading, LoadingMode::Record);
    assert_eq!(d.cause, Cause::None, "{}", d.reason);
}

/// Isolated 10–20σ spikes (electrical glitches) are left out, counted, and never become a cause.
#[test]
fn spikes_never_become_a_cause() {
    let m = base().with_state(StateVariable::new(Slip, 0.013, 8.0));
    let mut rec = record(&m, 1.0, &short_protocol(), Noise { sigma: 2e-4, tau: 0.0 }, 41).unwrap();
    let at = [150, 400, 700, 1000, 1500, 1900];
    for (k, &i) in at.iter().enumerate() {
        rec.mu[i] += if k % 2 == 0 { 1.0 } else { -1.0 } * (10.0 + 2.0 * k as f64) * 2e-4;
    }
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let d = diagnose(&rec, &segs, &options(0.005, LoadingMode::Protocol)).unwrap();
    let times: Vec<f64> = at.iter().map(|&i| rec.time[i]).collect();
    assert_eq!(d.spikes_removed, times);
    assert_eq!(d.cause, Cause::None, "{}", d.reason);
}

/// Issue 21's false alarm, made by the independent generator (`benches/detection/generate.py
/// --issue21`): a plain one-state Slip-law gouge record (a > b, staircase 1 → 300 µm/s, holds of
/// 3–300 s at 10 µm/s, 28,403 rows) with white (1.5e-4), AR(1) (5e-5, τ = 1 s) and 1/f noise
/// (rms 1.5e-4). With white + AR(1) noise the diagnosis named a second state variable (ΔBIC −40.6
/// with n_eff = 11,832 from the lag-one correlation, false-alarm probability 1.8e-51). The
/// spectral noise model finds the drift, and nothing is named.
#[test]
fn one_over_f_drift_is_noise_not_a_cause() {
    let d = diagnosed_record("drift_gouge.csv", 0.004);
    println!("{}", d.reason);
    assert_eq!(d.cause, Cause::None, "{}", d.reason);
    let m = d.evidence.noise.as_ref().unwrap();
    // the injected drift: rms 1.5e-4 of 1/f noise, about half the residual variance
    let drift = d.noise_drift.as_ref().expect("the drift is reported");
    assert!((drift.rms / 1.5e-4 - 1.0).abs() < 0.3, "drift rms {}", drift.rms);
    assert!((m.drift_beta - 1.0).abs() <= 0.3, "β {}", m.drift_beta);
    assert!(m.n_effective < 0.01 * d.baseline.n as f64, "n_eff {}", m.n_effective);
    assert!(d.reason.contains("slow drift"), "{}", d.reason);
    // real drift wanders inside the quiet stretches of sliding as much as its model says
    let q = &d.adequacy.quiet;
    assert!(q.stretches.len() >= 3 && q.p_below > 0.05 && q.p_above > 0.05 && !q.inadequate(), "{q:?}");
}

/// Issue 21's variable-sampling case, made by the independent generator (record 49 of the
/// 111-record study): a second state variable (b2 1.2e-3, Dc2 105 µm) under AR(1) noise in
/// time (τ = 3.3 s) sampled at 100 Hz after each change and ≤ 1 Hz in holds. Read in sample
/// index, that noise is φ ≈ 0.997 in the bursts and ≈ 0.4 in the holds; the index spectrum took
/// it for 1/f drift (β 1.6, all of the variance, n_eff 2) and nothing was named. The noise
/// model in time (`diagnose/sampling.rs`) finds the AR(1) part with its τ and variance, and the
/// second state is named (ΔBIC −100, P(false) 5e-14).
#[test]
fn ar1_noise_in_time_on_variable_sampling_is_not_drift() {
    let d = diagnosed_record("rec_049.csv", 0.03486150845858375);
    println!("{}", d.reason);
    let m = d.evidence.noise.as_ref().unwrap();
    println!("{:?}", (m.white_variance, m.ar1_variance, m.ar1_tau_s, m.drift_share, m.n_effective, &m.sampling));
    assert!(m.sampling.is_some(), "the record is variably sampled");
    assert!(m.drift_share < 0.2, "drift share {}", m.drift_share);
    assert!((m.ar1_tau_s / 3.3).ln().abs() < 2f64.ln(), "τ {}", m.ar1_tau_s);
    // the AR(1) part as generated (σ 1.08e-4): the baseline's residuals also hold the second
    // state's misfit, which the model reads as a little drift
    assert!((m.ar1_variance / 1.0785e-4f64.powi(2) - 1.0).abs() < 0.3, "AR(1) variance {}", m.ar1_variance);
    assert_eq!(d.cause, Cause::SecondStateVariable, "{}", d.reason);
}

/// The adequacy test's false alarm on record 97 of the 111-record study (independent
/// generator; nothing hidden: a one-state Slip-law gouge staircase 1 → 300 µm/s with holds,
/// white noise 1.36e-4 only, 10 Hz, every break a sample). The baseline fit is the truth (rms
/// equal to the noise), yet the test judged it inadequate (excess 3.9, p = 0.005): its placebos
/// started between samples, so they lacked the single sample at the start that every event
/// window has, and a 0.43 s window at 300 µm/s held four samples. Placebos at the event's
/// sampling phase and windows of at least ten samples make it `none`, adequate.
#[test]
fn a_true_baseline_on_a_sampled_break_is_adequate() {
    assert_named_adequate("rec_097.csv", 0.00599549780660686, Cause::None);
}

/// The test record `file` (nominal stiffness `k`, 1/µm) is named `cause`, its model adequate.
fn assert_named_adequate(file: &str, k: f64, cause: Cause) {
    let d = diagnosed_record(file, k);
    println!("{}", d.reason);
    assert_eq!(d.cause, cause, "{}", d.reason);
    assert_eq!(d.adequacy.verdict, rsf_diagnose::AdequacyVerdict::Adequate, "{}", d.reason);
}

/// A true model judged inadequate for its break times (record 2 of the 60–75k-row speed set,
/// `generate.py --drift --seed 22 --rows-scale 5`: independent generator; an Aging share of
/// 0.75 in a two-state gouge, the staircase 1 → 300 µm/s and holds of 3–300 s at 10 µm/s;
/// encoder noise 0.19 µm, 1/f noise, time jitter, spikes; 66,885 rows at 100 Hz). The
/// slip + aging mixture is named and its fit is the truth within 1 %, yet the adequacy test
/// judged it inadequate (excess 5.1, p < 0.001, worst at three reslides: 5.9×, 5.4×, 4.8×), so
/// the verdict was `unexplained`. The noisy load point leaves each reslide's time uncertain by
/// 3σ_x/Δv = 0.057 s; the protocol read them 0.03 s off, which misplaces the spring's loading
/// (k·V = 0.047/s) by 10× the noise in the first samples — far from linear in the shift the
/// test took out. The test now takes the break shift within that uncertainty that fits best,
/// in the event window and in its placebos alike.
#[test]
fn a_true_mixture_with_uncertain_break_times_is_adequate() {
    assert_named_adequate("gouge_encoder_holds.csv", 0.004698618005311877, Cause::EvolutionLaw);
}

/// A cut-off of Vc = 1e-4 µm/s that only the 10⁴ s hold reaches (record 91 of the 111-record
/// study's seed 2, `tests/data/detection/cutoff_missed_by_its_profile.csv`): the full fit's Vc
/// profile settled a decade low (ΔBIC +2352, worse than the baseline), while the held-out
/// test's training fit predicted the rest of the record to the noise. The full fit is continued
/// from the training optimum, which fits the whole record better, and the cut-off is named with
/// its Vc. (Fails on the main before: the Aging–Slip law, aging share 0.078, was named.)
#[test]
fn a_full_fit_its_training_fit_beats_is_continued_from_there() {
    let d = diagnosed_record("cutoff_missed_by_its_profile.csv", 0.045822454546905984);
    assert_eq!(d.cause, Cause::CutoffVelocity, "{}", d.reason);
    let vc = d.effect.vc.unwrap();
    assert!((vc / 1e-4 - 1.0).abs() < 0.05, "Vc {vc}");
}
