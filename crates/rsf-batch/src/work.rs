//! One record's work: read, segment, fit and/or diagnose; a failure (or a panic) becomes the
//! record's status, never the batch's end.

use super::manifest::{Entry, RecordOptions};
use super::row::{Param, Row, Status};
use rsf_diagnose::{DiagnoseOptions, Diagnosis, diagnose};
use rsf_fit::data::{DispUnit, InvalidRows, ReadOptions, Record, TimeUnit, read_record};
use rsf_fit::fit::{FitOptions, FitResult, LoadingMode, ParamName, fit, prepare};
use rsf_fit::segment::{Segment, SegmentKind, SegmentOptions, detect};
use serde::{Deserialize, Serialize};

/// Starting points of a fit: `rsf fit`'s default (`--starts`), so that a batch fit is the
/// single-record fit.
pub const FIT_STARTS: usize = 4;

/// What to do with each record.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Job {
    /// Fit the law given (`law`, default slip), as `rsf fit`.
    pub fit: bool,
    /// Diagnose, as `rsf diagnose`.
    pub diagnose: bool,
}

/// A record's results: its summary row and, when they were computed, the fit and diagnosis.
pub struct Outcome {
    /// The summary row.
    pub row: Row,
    /// The fit.
    pub fit: Option<FitResult>,
    /// The diagnosis.
    pub diagnosis: Option<Diagnosis>,
}

/// The record's options with the batch-wide `defaults` filled in.
fn read_options(o: &RecordOptions) -> ReadOptions {
    ReadOptions {
        time_col: o.time_col.clone().unwrap_or_else(|| "time_s".into()),
        lp_col: o.lp_col.clone().unwrap_or_else(|| "load_point_um".into()),
        mu_col: o.mu_col.clone().unwrap_or_else(|| "mu".into()),
        shear_col: o.shear_col.clone(),
        normal_col: o.normal_col.clone(),
        normal_stress: o.normal_stress,
        disp_unit: o.disp_unit.unwrap_or(DispUnit::Um),
        time_unit: o.time_unit.unwrap_or(TimeUnit::S),
        t_min: o.t_min,
        t_max: o.t_max,
        invalid: if o.drop_invalid == Some(true) { InvalidRows::Drop } else { InvalidRows::Error },
        accept_implausible: o.accept_implausible == Some(true),
        ..ReadOptions::default()
    }
}

/// The protocol's conditions: slide velocities, longest hold, median normal stress.
fn conditions(row: &mut Row, rec: &Record, segs: &[Segment], o: &RecordOptions) {
    row.samples = Some(rec.len());
    row.duration_s = Some(rec.time[rec.len() - 1] - rec.time[0]);
    let slides: Vec<f64> = segs.iter().filter(|s| s.v > 0.0).map(|s| s.v).collect();
    row.v_lp_min_um_s = slides.iter().copied().reduce(f64::min);
    row.v_lp_max_um_s = slides.iter().copied().reduce(f64::max);
    row.longest_hold_s = segs.iter().filter(|s| s.kind == SegmentKind::Hold).map(|s| s.t1 - s.t0).reduce(f64::max);
    row.normal_stress_mpa = if rec.normal_stress.is_empty() {
        o.normal_stress
    } else {
        let mut s = rec.normal_stress.clone();
        let mid = s.len() / 2;
        s.select_nth_unstable_by(mid, f64::total_cmp);
        Some(s[mid])
    };
}

/// A fit's parameters for the row, named as `rsf fit` names them.
fn params_of(f: &FitResult) -> Vec<Param> {
    f.params
        .as_initial()
        .into_iter()
        .filter(|(n, _)| f.reports(n))
        .filter(|(n, _)| !matches!(n, ParamName::Mu0Seg(_)))
        .map(|(n, value)| {
            let name = n.text();
            Param { stderr: f.stderr.get(&name).copied(), name, value }
        })
        .collect()
}

fn stiffness(o: &RecordOptions) -> Result<f64, String> {
    o.stiffness.ok_or_else(|| "no stiffness: give a `stiffness` column or a batch-wide --stiffness".to_string())
}

fn fit_options(o: &RecordOptions) -> Result<FitOptions, String> {
    let l = o.law.clone().unwrap_or_else(|| rsf_laws::Law::Slip.into()).with_starting_values()?;
    let mut fo = FitOptions::new(vec![l], stiffness(o)?);
    fo.loading = o.loading.unwrap_or(LoadingMode::Record);
    fo.fit_stiffness = o.fit_stiffness == Some(true);
    fo.fit_slip_trend = o.fit_slip_trend == Some(true);
    fo.fit_a_slope = o.fit_a_slope == Some(true);
    fo.starts = FIT_STARTS;
    Ok(fo)
}

fn diagnose_options(o: &RecordOptions, threads: usize) -> Result<DiagnoseOptions, String> {
    let law = o.baseline.clone().unwrap_or_default().law()?;
    let mut fo = FitOptions::new(vec![law], stiffness(o)?);
    fo.loading = o.loading.unwrap_or(LoadingMode::Protocol);
    Ok(DiagnoseOptions { threads, seed: o.seed.unwrap_or(1), ..DiagnoseOptions::new(fo) })
}

/// Runs `job` on one record with the options `entry.options.or(defaults)`, on `threads`
/// threads (0: all cores; the result does not depend on it). Never panics: a panic inside
/// becomes [`Status::Crashed`] with its message.
pub fn run_entry(entry: &Entry, defaults: &RecordOptions, job: Job, threads: usize) -> Outcome {
    let work = std::panic::AssertUnwindSafe(|| work(entry, defaults, job, threads));
    match std::panic::catch_unwind(work) {
        Ok(out) => out,
        Err(p) => {
            let msg = p
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".into());
            let mut row = Row::failed(&entry.name, Status::Crashed, format!("rsf panicked (please report): {msg}"));
            row.meta = entry.meta.clone();
            Outcome { row, fit: None, diagnosis: None }
        }
    }
}

fn work(entry: &Entry, defaults: &RecordOptions, job: Job, threads: usize) -> Outcome {
    let o = entry.options.or(defaults);
    let fail = |status: Status, e: String| {
        let mut row = Row::failed(&entry.name, status, e);
        row.meta = entry.meta.clone();
        Outcome { row, fit: None, diagnosis: None }
    };
    if let Err((_, e)) = o.check() {
        return fail(Status::OptionsInvalid, e);
    }
    let (fo, dopt) = match (
        job.fit.then(|| fit_options(&o)).transpose(),
        job.diagnose.then(|| diagnose_options(&o, threads)).transpose(),
    ) {
        (Ok(f), Ok(d)) => (f, d),
        (Err(e), _) | (_, Err(e)) => return fail(Status::OptionsInvalid, e),
    };
    let rec = match read_record(&entry.path, &read_options(&o)) {
        Ok(r) => r,
        Err(e) => return fail(Status::ReadFailed, e.to_string()),
    };
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut row = Row::failed(&entry.name, Status::Ok, String::new());
    row.meta = entry.meta.clone();
    conditions(&mut row, &rec, &segs, &o);
    let mut out = Outcome { row, fit: None, diagnosis: None };
    if let Some(fo) = fo {
        match prepare(&rec, &segs, &fo).and_then(|p| fit(&p, &fo)) {
            Ok(f) => {
                out.row.laws = Some(f.params.laws.join("+"));
                out.row.rms = Some(f.rms);
                out.row.params = params_of(&f);
                if let Some(why) = f.convergence_text() {
                    out.row.status = Status::NotConverged;
                    out.row.error = why;
                }
                out.fit = Some(f);
            }
            Err(e) => {
                out.row.status = Status::FitFailed;
                out.row.error = e.to_string();
                return out;
            }
        }
    }
    if let Some(dopt) = dopt {
        match diagnose(&rec, &segs, &dopt) {
            Ok(d) => {
                if out.fit.is_none() {
                    out.row.laws = Some(d.baseline.params.laws.join("+"));
                    out.row.rms = Some(d.baseline.rms);
                    out.row.params = params_of(&d.baseline);
                }
                out.row.cause = Some(d.cause.to_string());
                out.row.delta_bic = d.gain.as_ref().map(|g| g.delta_bic);
                out.row.rms_ratio = d.gain.as_ref().map(|g| g.rms_ratio);
                out.row.effect = (!d.effect.is_empty()).then(|| serde_json::to_string(&d.effect).unwrap_or_default());
                out.row.runner_up = d.runner_up.as_ref().map(|(c, _)| c.to_string());
                out.row.partial = d.partial.map(|c| c.to_string());
                out.row.adequacy = Some(d.adequacy.verdict.as_str().to_string());
                out.row.adequacy_excess = Some(d.adequacy.excess).filter(|x| x.is_finite());
                out.row.events_tested = Some(d.adequacy.windows);
                out.row.events = Some(d.adequacy.events_total);
                out.row.drift_rms = d.noise_drift.as_ref().map(|n| n.rms);
                out.row.quiet_wander = Some(d.adequacy.quiet.ratio).filter(|x| x.is_finite());
                out.row.form_delta_bic = d.adequacy.form.as_ref().map(|f| f.delta_bic);
                out.row.lead_z = d.lead.map(|l| l.z).filter(|z| z.is_finite());
                out.diagnosis = Some(d);
            }
            Err(e) => {
                out.row.status = Status::DiagnoseFailed;
                out.row.error = e.to_string();
            }
        }
    }
    out
}
