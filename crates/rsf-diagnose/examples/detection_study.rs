//! The lab-realistic detection study: `rsf diagnose` on records made by the independent
//! generator `benches/detection/generate.py` (scipy Radau, its own equations), each hiding one
//! cause or none. Writes one JSON line per record and the tables of docs/diagnose/detection.md.
//!
//! ```sh
//! /tmp/genvenv/bin/python benches/detection/generate.py --out /tmp/detection_records
//! cargo run --release -p rsf-diagnose --example detection_study -- /tmp/detection_records [--only CAUSE] [--jobs 2]
//! ```
//!
//! Records run in parallel (`--jobs`, default 2), each diagnosis on one thread: the results
//! do not depend on either.

use rsf_diagnose::{DiagnoseOptions, diagnose};
use rsf_fit::data::{ReadOptions, read_record};
use rsf_fit::fit::{FitOptions, LoadingMode};
use rsf_fit::segment::{SegmentOptions, detect};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::io::Write;
use std::sync::Mutex;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = std::path::PathBuf::from(
        args.first()
            .ok_or("usage: detection_study DIR [--only CAUSE] [--family FAMILY] [--law-file FILE] [--jobs N]")?,
    );
    let flag = |name: &str| args.iter().position(|a| a == name).and_then(|i| args.get(i + 1)).cloned();
    let only = flag("--only");
    let family = flag("--family");
    // a law file registered first: its law is a candidate of every diagnosis (docs/laws.md)
    let law_file = flag("--law-file");
    if let Some(f) = &law_file {
        rsf_laws::text_law::register_file(std::path::Path::new(f))?;
    }
    let jobs: usize = flag("--jobs").map_or(Ok(2), |j| j.parse())?;
    let manifest: Vec<Value> = serde_json::from_str(&std::fs::read_to_string(dir.join("manifest.json"))?)?;
    let todo: Vec<&Value> = manifest
        .iter()
        .filter(|m| only.as_deref().is_none_or(|c| m["cause"].as_str() == Some(c)))
        .filter(|m| family.as_deref().is_none_or(|f| m["family"].as_str() == Some(f)))
        .collect();
    let tag = [only.as_deref(), family.as_deref(), law_file.as_ref().map(|_| "law_file")]
        .into_iter()
        .flatten()
        .collect::<Vec<_>>()
        .join("_");
    let out_path = dir.join(format!("results_{}.jsonl", if tag.is_empty() { "all" } else { &tag }));
    let out = Mutex::new(std::fs::File::create(&out_path)?);
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results: Mutex<Vec<Value>> = Mutex::new(vec![]);
    std::thread::scope(|sc| {
        for _ in 0..jobs.max(1) {
            sc.spawn(|| {
                loop {
                    let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some(m) = todo.get(i) else { break };
                    let r = run(&dir, m);
                    eprintln!(
                        "{:>3}/{} {} {:22} {:18} → {:22} {:.1} s",
                        i + 1,
                        todo.len(),
                        m["file"].as_str().unwrap_or("?"),
                        m["cause"].as_str().unwrap_or("?"),
                        m["size"].as_str().unwrap_or(""),
                        r["found"].as_str().unwrap_or("?"),
                        r["seconds"].as_f64().unwrap_or(f64::NAN)
                    );
                    let mut f = out.lock().unwrap_or_else(|e| e.into_inner());
                    let _ = writeln!(f, "{r}");
                    results.lock().unwrap_or_else(|e| e.into_inner()).push(r);
                }
            });
        }
    });
    let mut results = results.into_inner().unwrap_or_else(|e| e.into_inner());
    results.sort_by(|a, b| a["file"].as_str().cmp(&b["file"].as_str()));
    println!("{}", tables(&results));
    Ok(())
}

fn run(dir: &std::path::Path, m: &Value) -> Value {
    let t = std::time::Instant::now();
    let file = m["file"].as_str().unwrap_or_default();
    let outcome = (|| -> Result<rsf_diagnose::Diagnosis, String> {
        let rec = read_record(&dir.join(file), &ReadOptions::default()).map_err(|e| e.to_string())?;
        let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
        let k = m["nominal_stiffness"].as_f64().ok_or("no nominal_stiffness")?;
        let mut fit = FitOptions::new(vec![rsf_laws::law_by_name("slip", |_| None).map_err(|e| e.to_string())?], k);
        fit.loading = LoadingMode::Protocol;
        diagnose(&rec, &segs, &DiagnoseOptions { threads: 1, ..DiagnoseOptions::new(fit) }).map_err(|e| e.to_string())
    })();
    let truth = m["cause"].as_str().unwrap_or_default();
    let mut r = json!({
        "file": file, "cause": truth, "size": m["size"], "features": m["features"], "effect_true": m["effect"],
        "family": m["family"], "truth_law": m["truth_law"],
        "seconds": t.elapsed().as_secs_f64(),
    });
    match outcome {
        Ok(d) => {
            r["found"] = json!(d.cause.as_str());
            r["partial"] = json!(d.partial.map(|c| c.as_str()));
            r["adequacy"] = json!(d.adequacy.verdict.as_str());
            r["event_adequacy"] = json!(d.adequacy.event_verdict.as_str());
            r["adequacy_excess"] = json!(d.adequacy.excess);
            r["adequacy_p"] = json!(d.adequacy.p_value);
            r["adequacy_windows"] = json!(d.adequacy.windows);
            r["adequacy_events"] = json!(d.adequacy.events_total);
            r["levels_p"] = json!(d.adequacy.levels.p_value);
            r["levels_excess"] = json!(d.adequacy.levels.excess);
            r["quiet_p_below"] = json!(d.adequacy.quiet.p_below);
            r["quiet_p_above"] = json!(d.adequacy.quiet.p_above);
            r["form"] = json!(d.adequacy.form);
            r["quiet_ratio"] = json!(d.adequacy.quiet.ratio);
            r["quiet_stretches"] = json!(d.adequacy.quiet.stretches.len());
            r["coherence"] = json!(d.adequacy.coherence.verdict.as_str());
            r["coherence_p"] = json!(d.adequacy.coherence.p_value);
            r["coherence_excess"] = json!(d.adequacy.coherence.excess);
            r["coherence_compared"] = json!(d.adequacy.coherence.compared);
            r["profiles"] = json!(d.adequacy.coherence.profiles);
            r["levels"] = json!(
                d.adequacy
                    .levels
                    .steps
                    .iter()
                    .map(|l| json!([l.segment, l.offset, l.noise, l.z, l.ln_v_ratio]))
                    .collect::<Vec<_>>()
            );
            r["law"] = json!(d.effect.law);
            // laws the record cannot tell from the one named (the evolution-law candidate's)
            r["equally_good_laws"] = json!(
                d.candidates
                    .iter()
                    .find(|c| c.cause == d.cause)
                    .map(|c| c.equally_good_laws.clone())
                    .unwrap_or_default()
            );
            r["secondary"] = json!(d.secondary.as_ref().map(|s| s.cause.as_str()));
            // `undecided`: the two causes the record does not tell apart
            r["undecided"] = json!(d.undecided.iter().map(|u| u.0.as_str()).collect::<Vec<_>>());
            // the lead of the cause chosen over its best credible rival, against its chance spread
            r["lead"] = json!(d.lead);
            r["unfitted_causes"] = json!(d.unfitted_causes.iter().map(|c| c.as_str()).collect::<Vec<_>>());
            r["effect"] = json!(d.effect);
            r["confidence"] = json!(d.confidence);
            r["reconstruction"] = json!(d.reconstruction.as_ref().map(|x| x.segment));
            r["spikes_removed"] = json!(d.spikes_removed.len());
            // each calibrated candidate's null: its gain and the replicates' moments
            r["nulls"] = json!(
                d.candidates
                    .iter()
                    .filter_map(|c| c.null.as_ref().map(|n| json!({
                        "cause": c.cause.as_str(),
                        "dk": c.fit.as_ref().map(|f| f.n_free.saturating_sub(d.baseline.n_free)),
                        "observed": n.gain_observed,
                        "mean": n.gain_mean,
                        "sd": n.gain_sd,
                        "replicates": n.replicates,
                        "p": n.false_alarm_probability,
                        "p_upper": n.false_alarm_upper,
                    })))
                    .collect::<Vec<_>>()
            );
            // every candidate: its score, held-out prediction and why it was set aside
            r["baseline_rms"] = json!(d.baseline.rms);
            r["noise_sigma"] = m["noise_sigma"].clone();
            r["candidates"] = json!(
                d.candidates
                    .iter()
                    .map(|c| json!({
                        "cause": c.cause.as_str(),
                        "law": c.effect.law,
                        "dbic": c.delta_bic,
                        "heldout_before": c.heldout_rms_before,
                        "heldout_after": c.heldout_rms_after,
                        "heldout_uninformative": c.heldout_uninformative,
                        "converged": c.converged,
                        "at_bound": c.at_bound,
                        "unresolved": c.unresolved,
                        "drift_share_after": c.drift_share_after,
                        "rms": c.fit.as_ref().map(|f| f.rms),
                        "adequacy_excess": c.adequacy_excess,
                        "unfitted_ways": c.unfitted_ways,
                    }))
                    .collect::<Vec<_>>()
            );
            r["false_alarm_probability"] = json!(
                d.candidates
                    .iter()
                    .find(|c| c.cause == d.cause)
                    .and_then(|c| c.null.as_ref())
                    .map(|n| n.false_alarm_probability)
            );
        }
        Err(e) => r["found"] = json!(format!("error: {e}")),
    }
    r
}

/// Markdown tables: per cause, found/total and the causes named instead; per cause × feature;
/// per cause × size.
fn tables(results: &[Value]) -> String {
    let s = |v: &Value, k: &str| v[k].as_str().unwrap_or_default().to_string();
    let mut out = String::new();
    // truths outside the one-step menu: per family, what was named (with the law) and the adequacy
    let mut by_family: BTreeMap<String, Vec<&Value>> = BTreeMap::new();
    for r in results.iter().filter(|r| r["family"].is_string()) {
        by_family.entry(s(r, "family")).or_default().push(r);
    }
    if !by_family.is_empty() {
        out += "| family | records | named (law; adequacy) |\n|---|---|---|\n";
        for (f, rs) in &by_family {
            let mut named: BTreeMap<String, usize> = BTreeMap::new();
            for r in rs {
                let law = r["law"].as_str().map(|l| format!(" {l}")).unwrap_or_default();
                *named.entry(format!("{}{law}; {}", s(r, "found"), s(r, "adequacy"))).or_default() += 1;
            }
            let w: Vec<String> = named.iter().map(|(k, n)| format!("{k} ×{n}")).collect();
            out += &format!("| {f} | {} | {} |\n", rs.len(), w.join(", "));
        }
        out += "\n";
    }
    out += &String::from("| hidden cause | records | named correctly | named instead |\n|---|---|---|---|\n");
    let mut by_cause: BTreeMap<String, Vec<&Value>> = BTreeMap::new();
    for r in results {
        by_cause.entry(s(r, "cause")).or_default().push(r);
    }
    for (c, rs) in &by_cause {
        let ok = rs.iter().filter(|r| s(r, "found") == *c).count();
        let mut wrong: BTreeMap<String, usize> = BTreeMap::new();
        for r in rs.iter().filter(|r| s(r, "found") != *c) {
            *wrong.entry(s(r, "found")).or_default() += 1;
        }
        let w: Vec<String> = wrong.iter().map(|(k, n)| format!("{k} ×{n}")).collect();
        out += &format!("| {c} | {} | {ok} | {} |\n", rs.len(), w.join(", "));
    }
    let features: std::collections::BTreeSet<String> = results
        .iter()
        .flat_map(|r| r["features"].as_array().cloned().unwrap_or_default())
        .filter_map(|f| f.as_str().map(str::to_string))
        .collect();
    out += "\nNamed correctly per cause and feature (correct/records; for `none`, records with no false cause):\n\n| cause |";
    for f in &features {
        out += &format!(" {f} |");
    }
    out += "\n|---|";
    out += &"---|".repeat(features.len());
    out += "\n";
    for (c, rs) in &by_cause {
        out += &format!("| {c} |");
        for f in &features {
            let with: Vec<&&Value> =
                rs.iter().filter(|r| r["features"].as_array().is_some_and(|a| a.iter().any(|x| x == f))).collect();
            let ok = with.iter().filter(|r| s(r, "found") == *c).count();
            out += &if with.is_empty() { " – |".to_string() } else { format!(" {ok}/{} |", with.len()) };
        }
        out += "\n";
    }
    out += "\nPer effect size:\n\n| cause | size | named correctly |\n|---|---|---|\n";
    for (c, rs) in &by_cause {
        let mut sizes: BTreeMap<String, (usize, usize)> = BTreeMap::new();
        for r in rs {
            let e = sizes.entry(s(r, "size")).or_default();
            e.1 += 1;
            e.0 += usize::from(s(r, "found") == *c);
        }
        for (z, (ok, n)) in sizes {
            out += &format!("| {c} | {z} | {ok}/{n} |\n");
        }
    }
    out
}
