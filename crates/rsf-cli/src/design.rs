//! `rsf design`: diagnose the record, then rank the next segments by how well they would tell
//! the credible causes apart.

use crate::args::DesignArgs;
use anyhow::{Context, Result, bail};
use rsf_design::{DesignOptions, protocol_toml};
use rsf_diagnose::DiagnoseOptions;
use rsf_fit::segment::{SegmentOptions, detect};
use std::time::Instant;

/// `LOW,HIGH` (µm/s), both positive, LOW ≤ HIGH.
fn v_range(s: &str) -> Result<(f64, f64)> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [lo, hi] = parts[..] else { bail!("--v-range `{s}`: expected LOW,HIGH in µm/s, e.g. 0.001,300") };
    let (lo, hi): (f64, f64) = match (lo.parse(), hi.parse()) {
        (Ok(a), Ok(b)) => (a, b),
        _ => bail!("--v-range `{s}`: LOW and HIGH must be numbers (µm/s)"),
    };
    if !(lo > 0.0 && hi >= lo && hi.is_finite()) {
        bail!("--v-range `{s}`: needs 0 < LOW ≤ HIGH");
    }
    Ok((lo, hi))
}

pub fn run(a: &DesignArgs) -> Result<()> {
    let start = Instant::now();
    let r = &a.d;
    let mut files = crate::output::Files::default().input("record", &r.data);
    if let Some(f) = &a.from {
        files = files.input("--from", f);
    }
    files
        .output("--json", a.json.as_deref())
        .output("--protocol", a.protocol.as_deref())
        .output("--plot", a.plot.as_deref())
        .output("--report", a.report.as_deref())
        .output("--diagnosis-json", a.diagnosis_json.as_deref())
        .check()?;
    let dopts = crate::fit::diagnose_options(r)?;
    for (name, x) in [("--max-time", a.max_time), ("--max-slip", a.max_slip)] {
        if !(x > 0.0 && x.is_finite()) {
            bail!("{name} {x} must be positive and finite");
        }
    }
    if !(a.max_hold >= 0.0 && a.max_hold.is_finite()) {
        bail!("--max-hold {} must be zero or positive (s)", a.max_hold);
    }
    if !(a.max_sigma_change >= 0.0 && a.max_sigma_change < 1.0) {
        bail!("--max-sigma-change {} must be a fraction of the record's normal stress in [0, 1)", a.max_sigma_change);
    }
    if !(a.credible >= 0.0) {
        bail!("--credible {} must not be negative", a.credible);
    }
    let o = DesignOptions {
        credible_dbic: a.credible,
        v_range: v_range(&a.v_range)?,
        max_hold: a.max_hold,
        max_time: a.max_time,
        max_slip: a.max_slip,
        max_sigma_change: a.max_sigma_change,
        draws: a.draws,
        sequences: !a.no_sequences,
        seed: r.seed,
        threads: r.threads,
        progress: None,
    };
    let rec = r.read.read(&r.data)?;
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let (design, diagnosis, cause_line, t_diag) = match &a.from {
        Some(from) => {
            let bytes = std::fs::read(from).with_context(|| format!("reading {}", from.display()))?;
            let text = String::from_utf8(bytes).map_err(|e| {
                anyhow::anyhow!(
                    "{}: not UTF-8 text (byte {}): not a diagnosis JSON",
                    from.display(),
                    e.utf8_error().valid_up_to()
                )
            })?;
            let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| {
                anyhow::anyhow!("{}: line {}, column {}: not JSON: {e}", from.display(), e.line(), e.column())
            })?;
            let word = |k: &str| v.get(k).and_then(serde_json::Value::as_str).unwrap_or("?").to_string();
            let line = format!("cause: {} ({}) [from {}]\n", word("cause"), word("reason"), from.display());
            eprintln!(
                "rsf design: {} samples, {} segments; refitting the models of {}…",
                rec.len(),
                segs.len(),
                from.display()
            );
            let design = rsf_design::Rebuilt::from_json(&rec, &segs, &text, &dopts)
                .map_err(|e| anyhow::anyhow!("{}: {e}", from.display()))
                .and_then(|rb| {
                    let t = start.elapsed().as_secs_f64();
                    eprintln!("rsf design: models refitted in {t:.1} s; scoring the proposals…");
                    let (bar, progress) = crate::fit::progress_bar("design {bar:30} {pos}/{len} proposals, {elapsed}");
                    let o = DesignOptions { progress: Some(progress), ..o };
                    let mut d = rsf_design::design_basis(&rec, &segs, &rb.basis(), &o)?;
                    bar.finish_and_clear();
                    d.notes.splice(0..0, rb.notes.iter().cloned());
                    Ok((d, t))
                })?;
            (design.0, None, line, design.1)
        }
        None => {
            eprintln!("rsf design: {} samples, {} segments; diagnosing first…", rec.len(), segs.len());
            let (bar, progress) = crate::fit::progress_bar("diagnose {bar:30} {pos}/{len} fits, {elapsed} {msg}");
            let dopts = DiagnoseOptions { progress: Some(progress), ..dopts };
            let d = rsf_diagnose::diagnose(&rec, &segs, &dopts)?;
            bar.finish_and_clear();
            let t_diag = start.elapsed().as_secs_f64();
            eprintln!("rsf design: diagnosis in {t_diag:.1} s (cause: {}); scoring the proposals…", d.cause);
            let (bar, progress) = crate::fit::progress_bar("design {bar:30} {pos}/{len} proposals, {elapsed}");
            let design = rsf_design::design_from(&rec, &segs, &d, &DesignOptions { progress: Some(progress), ..o })?;
            bar.finish_and_clear();
            let line = format!("cause: {} ({})\n", d.cause, d.reason);
            (design, Some(d), line, t_diag)
        }
    };
    let wall = start.elapsed().as_secs_f64();
    let mut out = cause_line;
    out += "credible models:";
    for m in &design.models {
        out += &format!(" {} (ΔBIC {:.1}, {} draws);", m.name, m.delta_bic, m.draws);
    }
    out.pop();
    out += "\n";
    for n in &design.notes {
        out += &format!("note: {n}\n");
    }
    out += &format!("{}\n", design.summary);
    if !design.proposals.is_empty() {
        out += &format!(
            "{:>3}  {:>9} {:>9} {:>6} {:>9} {:>8} {:>9}  proposal\n",
            "#", "time_s", "slip_um", "score", "lead_Δχ²", "score/h", "peak_V"
        );
        let row = |label: String, r: &rsf_design::Ranked| {
            format!(
                "{label:>3}  {:>9.0} {:>9.1} {:>6.2} {:>9.1} {:>8.2} {:>9.3e}  {}{}\n",
                r.machine_time_s,
                r.slip_um,
                r.score,
                r.lead_pair_dchi2,
                r.score_per_hour,
                r.peak_slip_rate,
                if r.stick_slip { "[stick-slip] " } else { "" },
                r.description
            )
        };
        for r in design.proposals.iter().take(a.top) {
            out += &row(r.rank.to_string(), r);
        }
        // the standard segments of the same time, the best of them marked
        for s in &design.standards {
            let best = design.standard.as_ref().is_some_and(|b| b.standard == s.standard);
            out += &row(if best { "std*".into() } else { "std".into() }, s);
        }
    }
    crate::write_stdout(&out)?;
    let first = if a.from.is_some() { "refits" } else { "diagnosis" };
    eprintln!("rsf design: {wall:.1} s ({t_diag:.1} s {first}, {:.1} s design)", wall - t_diag);
    if let Some(j) = &a.json {
        let mut v = serde_json::to_value(&design)?;
        v["data"] = serde_json::json!(r.data.display().to_string());
        crate::output::write_bytes(j, serde_json::to_string_pretty(&v)? + "\n")?;
    }
    if let (Some(j), Some(d)) = (&a.diagnosis_json, &diagnosis) {
        let mut v = serde_json::to_value(d)?;
        v["data"] = serde_json::json!(r.data.display().to_string());
        crate::output::write_bytes(j, serde_json::to_string_pretty(&v)? + "\n")?;
    }
    if let Some(p) = &a.protocol {
        match protocol_toml(&design, 1) {
            Some(t) => crate::output::write_bytes(p, t)?,
            None => bail!("--protocol: there is no proposal to write ({})", design.summary),
        }
    }
    if let Some(p) = &a.plot {
        match rsf_report::design_svg(&design) {
            Ok(svg) => crate::output::write_bytes(p, svg)?,
            Err(e) => bail!("--plot: {e}"),
        }
    }
    if let Some(page) = &a.report {
        let name = r.data.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
        crate::output::write_bytes(page, rsf_report::design_html(&design, &name))?;
    }
    Ok(())
}
