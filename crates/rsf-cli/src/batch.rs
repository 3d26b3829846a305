//! `rsf batch`: a lab's archive, every record fitted and/or diagnosed in parallel, resumable,
//! one summary table and figure. The per-record work and the table are `rsf_batch`'s
//! (shared with Python's `fit_many`/`diagnose_many`); this file owns the files.
//!
//! Layout of `--out DIR`:
//! - `DIR/summary.csv`, `DIR/summary.parquet`, `DIR/summary.svg`: one row per record (the
//!   Parquet file with typed columns); parameters across conditions. `DIR/summary.set.json`
//!   lists the three with their SHA-256: they are one run's (`summary_set.rs`).
//! - `DIR/records/KEY.fit.json`, `KEY.diagnosis.json`, `KEY.html`: each record's results
//!   (KEY: the manifest's name, `/` → `__`).
//! - `DIR/records/KEY.row.json` and `KEY.stamp`: the record's summary row, and what it was
//!   computed from (SHA-256 of the record's bytes, the options, the job, rsf's version). The
//!   stamp is written last, after every output is complete: a record with a matching stamp is
//!   skipped on a re-run; an interrupted or failed one is run again, its earlier outputs
//!   removed first (a failed record leaves none).
//! - `DIR/.rsf-batch.lock` while a run works on DIR (`batch_lock.rs`).

use crate::args::BatchArgs;
use anyhow::{Context, Result, bail};
use rsf_batch::{
    Entry, Job, RecordOptions, Row, Status, folder_entries, read_manifest, read_manifest_allowing_outside, run_entry,
    summary_csv, summary_table,
};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The batch-wide options: the command line's, which a manifest's cells override.
fn defaults(a: &BatchArgs) -> Result<RecordOptions> {
    Ok(RecordOptions {
        stiffness: a.stiffness,
        time_col: a.time_col.clone(),
        lp_col: a.lp_col.clone(),
        mu_col: a.mu_col.clone(),
        shear_col: a.shear_col.clone(),
        normal_col: a.normal_col.clone(),
        normal_stress: a.normal_stress,
        disp_unit: a.disp_unit,
        time_unit: a.time_unit,
        t_min: None,
        t_max: None,
        law_file: None, // --law-file registers for the whole run
        law: a.law.as_deref().map(str::parse).transpose().map_err(anyhow::Error::msg)?,
        baseline: a.baseline.as_deref().map(str::parse).transpose().map_err(anyhow::Error::msg)?,
        loading: a.loading,
        fit_stiffness: a.fit_stiffness.then_some(true),
        fit_slip_trend: a.fit_slip_trend.then_some(true),
        fit_a_slope: a.fit_a_slope.then_some(true),
        drop_invalid: a.drop_invalid.then_some(true),
        accept_implausible: a.accept_implausible.then_some(true),
        seed: a.seed,
    })
}

/// A record's output files.
struct Paths {
    fit: PathBuf,
    diagnosis: PathBuf,
    report: PathBuf,
    row: PathBuf,
    stamp: PathBuf,
}

impl Paths {
    fn new(dir: &Path, name: &str) -> Paths {
        let key: String = name.replace(['/', '\\'], "__");
        let p = |ext: &str| dir.join(format!("{key}.{ext}"));
        Paths {
            fit: p("fit.json"),
            diagnosis: p("diagnosis.json"),
            report: p("html"),
            row: p("row.json"),
            stamp: p("stamp"),
        }
    }
}

/// What a record's results were computed from.
fn stamp(e: &Entry, o: &RecordOptions, job: Job) -> Result<String> {
    let mut h = Sha256::new();
    let mut f = std::fs::File::open(&e.path).with_context(|| format!("{}", e.path.display()))?;
    std::io::copy(&mut f, &mut h).with_context(|| format!("reading {}", e.path.display()))?;
    let record: String = h.finalize().iter().map(|b| format!("{b:02x}")).collect();
    let what = serde_json::json!({
        "rsf": env!("CARGO_PKG_VERSION"),
        "record_sha256": record,
        "options": o,
        "meta": e.meta,
        "job": job,
        // the laws programs registered (law files): the diagnosis tries each, and a fit may
        // name one, so an edited law file must run the record again
        "registered_laws": rsf_laws::registry::all()
            .iter()
            .filter(|l| l.builtin().is_none())
            .map(|l| serde_json::json!({ "name": l.name(), "source": l.source() }))
            .collect::<Vec<_>>(),
    });
    Ok(serde_json::to_string_pretty(&what)? + "\n")
}

/// The row of a complete earlier run of this record with this stamp, if there is one.
fn reuse(p: &Paths, stamp: &str, job: Job) -> Option<Row> {
    if std::fs::read_to_string(&p.stamp).ok()? != stamp {
        return None;
    }
    let row: Row = serde_json::from_str(&std::fs::read_to_string(&p.row).ok()?).ok()?;
    let complete = (!job.fit || p.fit.is_file()) && (!job.diagnose || (p.diagnosis.is_file() && p.report.is_file()));
    (row.status == Status::Ok && complete).then_some(row)
}

/// Runs one record (or reuses its earlier results); returns its row and whether it was reused.
fn one(e: &Entry, d: &RecordOptions, job: Job, dir: &Path, threads: usize, force: bool) -> (Row, bool) {
    let p = Paths::new(dir, &e.name);
    let o = e.options.or(d);
    // a FIFO or device would be read twice (the stamp, then the record): the stamp's read
    // drains it and the record's then waits for ever
    if std::fs::metadata(&e.path).is_ok_and(|m| !m.is_file()) {
        let mut row = Row::failed(
            &e.name,
            Status::ReadFailed,
            format!("{}: not a regular file (a pipe, device or folder): give rsf batch a file", e.path.display()),
        );
        row.meta = e.meta.clone();
        return (row, false);
    }
    let st = match stamp(e, &o, job) {
        Ok(s) => s,
        Err(err) => {
            let mut row = Row::failed(&e.name, Status::ReadFailed, format!("{err:#}"));
            row.meta = e.meta.clone();
            return (row, false);
        }
    };
    if !force {
        if let Some(row) = reuse(&p, &st, job) {
            return (row, true);
        }
    }
    // an earlier run's stamp goes first: an interrupted run must not leave new outputs under
    // an old stamp; then its outputs: a record that fails now must not leave them beside its
    // failed row
    let _ = std::fs::remove_file(&p.stamp);
    for old in [&p.fit, &p.diagnosis, &p.report] {
        let _ = std::fs::remove_file(old);
    }
    let out = run_entry(e, d, job, threads);
    let mut row = out.row;
    let write = || -> Result<()> {
        if let Some(f) = &out.fit {
            let v = serde_json::json!({ "data": e.path.display().to_string(), "fit": f });
            crate::output::write_bytes(&p.fit, serde_json::to_string_pretty(&v)? + "\n")?;
        }
        if let Some(dg) = &out.diagnosis {
            let mut v = serde_json::to_value(dg)?;
            v["data"] = serde_json::json!(e.path.display().to_string());
            crate::output::write_bytes(&p.diagnosis, serde_json::to_string_pretty(&v)? + "\n")?;
            crate::output::write_bytes(&p.report, rsf_report::diagnosis_html(dg, &e.name))?;
        }
        Ok(())
    };
    if row.status == Status::Ok {
        if let Err(err) = write() {
            row.status = Status::WriteFailed;
            row.error = format!("{err:#}");
        }
    }
    let saved = crate::output::write_bytes(&p.row, serde_json::to_string_pretty(&row).unwrap_or_default() + "\n");
    if row.status == Status::Ok && saved.is_ok() {
        if let Err(err) = crate::output::write_bytes(&p.stamp, &st) {
            eprintln!("rsf batch: {}: {err:#} (it will run again next time)", e.name);
        }
    }
    (row, false)
}

/// `rsf batch`.
pub fn run(a: &BatchArgs) -> Result<()> {
    if !a.fit && !a.diagnose {
        bail!("say what to do with each record: --fit, --diagnose or both");
    }
    let job = Job { fit: a.fit, diagnose: a.diagnose };
    let entries = if a.input.is_dir() {
        folder_entries(&a.input).map_err(anyhow::Error::msg)?
    } else if a.allow_outside {
        read_manifest_allowing_outside(&a.input).map_err(anyhow::Error::msg)?
    } else {
        read_manifest(&a.input).map_err(anyhow::Error::msg)?
    };
    // two records must not share their output files (`a/b.csv` and `a__b.csv`)
    let mut keys = std::collections::BTreeMap::new();
    for e in &entries {
        if let Some(other) = keys.insert(Paths::new(&a.out, &e.name).row, &e.name) {
            bail!("`{other}` and `{}` would share their output files in {}: rename one", e.name, a.out.display());
        }
    }
    let d = defaults(a)?;
    d.check().map_err(|(c, e)| anyhow::anyhow!("--{}: {e}", c.replace('_', "-")))?;
    let dir = a.out.join("records");
    let (summary, figure) = (a.out.join("summary.csv"), a.out.join("summary.svg"));
    let parquet = a.out.join("summary.parquet");
    let set = a.out.join(crate::summary_set::SET);
    // no output may be an input: a record listed under the output folder's names is refused
    let mut files = crate::output::Files::default();
    if !a.input.is_dir() {
        files = files.input("manifest", &a.input);
    }
    for e in &entries {
        files = files.input("record", &e.path);
    }
    files = files
        .output("summary", Some(&summary))
        .output("summary", Some(&parquet))
        .output("figure", Some(&figure))
        .output("summary set", Some(&set));
    // and each record's own outputs (a manifest may list one of an earlier run's)
    for e in &entries {
        let p = Paths::new(&dir, &e.name);
        for out in [&p.fit, &p.diagnosis, &p.report, &p.row, &p.stamp] {
            files = files.output("record", Some(out));
        }
    }
    files.check()?;
    let _lock = crate::batch_lock::lock(&a.out)?;
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    // what a killed run left half-written
    crate::batch_lock::sweep_partials(&a.out);
    crate::batch_lock::sweep_partials(&dir);
    // and a summary set it left half renamed
    crate::summary_set::clear_broken(&a.out)?;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs = if a.jobs == 0 { cores } else { a.jobs }.min(entries.len()).max(1);
    // the cores left over go to each record's own fits (the result does not depend on it)
    let inner = (cores / jobs).max(1);
    eprintln!(
        "rsf batch: {} records, {} at a time, {} to {}",
        entries.len(),
        jobs,
        match job {
            Job { fit: true, diagnose: true } => "fit and diagnose",
            Job { fit: true, diagnose: false } => "fit",
            Job { fit: false, .. } => "diagnose",
        },
        a.out.display()
    );
    let bar =
        indicatif::ProgressBar::with_draw_target(Some(entries.len() as u64), indicatif::ProgressDrawTarget::stderr());
    bar.set_style(
        indicatif::ProgressStyle::with_template("batch {bar:30} {pos}/{len} records, {elapsed} (eta {eta}) {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let results = rsf_fit::parallel::par_map(&entries, jobs, |e| {
        let r = one(e, &d, job, &dir, inner, a.force);
        bar.inc(1);
        bar.set_message(format!("{}: {}", e.name, if r.1 { "reused" } else { r.0.status.text() }));
        if r.0.status != Status::Ok {
            bar.suspend(|| eprintln!("rsf batch: {}: {}: {}", e.name, r.0.status.text(), r.0.error));
        }
        r
    });
    bar.finish_and_clear();
    let rows: Vec<Row> = results.iter().map(|r| r.0.clone()).collect();
    // one unit: the three written completely, then renamed, then the set file naming them
    let parquet_bytes = crate::summary_parquet::summary_parquet(&summary_table(&rows))?;
    let svg = crate::plot::batch(&rows)?;
    crate::summary_set::write(&a.out, summary_csv(&rows).as_bytes(), &parquet_bytes, svg.as_bytes(), rows.len())?;
    let reused = results.iter().filter(|r| r.1).count();
    let failed: Vec<&Row> = rows.iter().filter(|r| r.status != Status::Ok).collect();
    let mut text = format!(
        "{} records: {} ok ({} reused from an earlier run), {} failed\n",
        rows.len(),
        rows.len() - failed.len(),
        reused,
        failed.len()
    );
    for r in &failed {
        text += &format!("  {}: {}: {}\n", r.file, r.status.text(), r.error);
    }
    text += &format!("summary: {} (and {})\nfigure: {}\n", summary.display(), parquet.display(), figure.display());
    crate::write_stdout(&text)?;
    if !failed.is_empty() {
        bail!("{} of {} records failed (each named above and in {})", failed.len(), rows.len(), summary.display());
    }
    Ok(())
}
