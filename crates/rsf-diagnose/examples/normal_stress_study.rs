//! Recovery of the Linker–Dieterich α, and its diagnosis, on records made by the independent
//! generator `benches/normal_stress/make_records.py` (scipy, its own formulation): σ changes of
//! +10, +30 and −20 % (2 s ramps) with α ∈ {0, 0.1, 0.3, 0.5}, a velocity step and a hold,
//! white noise of 2e-4 in μ. For each record: a fit with `--fit-alpha` (Slip law, record
//! loading, k known), the relative errors of α, a, b and Dc, and `rsf diagnose`'s cause.
//!
//! ```sh
//! /tmp/wpvenv/bin/python benches/normal_stress/make_records.py /tmp/nsrec
//! cargo run --release -p rsf-diagnose --example normal_stress_study -- /tmp/nsrec [--jobs 2] [--no-diagnose]
//! ```

use rsf_diagnose::{DiagnoseOptions, diagnose};
use rsf_fit::data::{ReadOptions, read_record};
use rsf_fit::fit::{AlphaFit, FitOptions, LoadingMode, fit, prepare};
use rsf_fit::parallel::par_map;
use rsf_fit::segment::{SegmentOptions, detect};
use serde_json::{Value, json};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir =
        std::path::PathBuf::from(args.first().ok_or("usage: normal_stress_study DIR [--jobs N] [--no-diagnose]")?);
    let jobs: usize =
        args.iter().position(|a| a == "--jobs").and_then(|i| args.get(i + 1)).map_or(Ok(2), |j| j.parse())?;
    let with_diagnosis = !args.iter().any(|a| a == "--no-diagnose");
    let truth: Vec<Value> = serde_json::from_str(&std::fs::read_to_string(dir.join("truth.json"))?)?;
    // records in parallel (one diagnosis thread each), results in file order
    let mut results = par_map(&truth, jobs.max(1), |m| {
        let r = run(&dir, m, with_diagnosis).unwrap_or_else(|e| json!({"file": m["file"], "error": e}));
        eprintln!("{r}");
        r
    });
    results.sort_by(|a, b| a["file"].as_str().cmp(&b["file"].as_str()));
    println!("| record | α true | α fitted (95% CI) | a err | b err | Dc err | cause | ΔBIC | s |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for r in &results {
        if r.get("error").is_some() {
            println!("| {} | error: {} |", r["file"], r["error"]);
            continue;
        }
        println!(
            "| {} | {} | {:.3} [{:.3}, {:.3}] | {:+.1}% | {:+.1}% | {:+.1}% | {} | {} | {:.1} |",
            r["file"].as_str().unwrap_or(""),
            r["alpha_true"],
            r["alpha"].as_f64().unwrap_or(f64::NAN),
            r["alpha_ci"][0].as_f64().unwrap_or(f64::NAN),
            r["alpha_ci"][1].as_f64().unwrap_or(f64::NAN),
            100.0 * r["a_err"].as_f64().unwrap_or(f64::NAN),
            100.0 * r["b_err"].as_f64().unwrap_or(f64::NAN),
            100.0 * r["dc_err"].as_f64().unwrap_or(f64::NAN),
            r["cause"].as_str().unwrap_or("–"),
            r["gain_bic"].as_f64().map(|g| format!("{g:.0}")).unwrap_or_else(|| "–".into()),
            r["seconds"].as_f64().unwrap_or(f64::NAN)
        );
    }
    Ok(())
}

fn run(dir: &std::path::Path, m: &Value, with_diagnosis: bool) -> Result<Value, String> {
    let clock = std::time::Instant::now();
    let file = m["file"].as_str().ok_or("no file")?;
    let p = &m["params"];
    let f = |k: &str| p[k].as_f64().ok_or(format!("no {k}"));
    let read =
        ReadOptions { lp_col: "lp_um".into(), normal_col: Some("normal_stress_mpa".into()), ..ReadOptions::default() };
    let rec = read_record(&dir.join(file), &read).map_err(|e| e.to_string())?;
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let slip = rsf_laws::law_by_name("slip", |_| None).map_err(|e| e.to_string())?;
    let mut o = FitOptions::new(vec![slip], f("k")?);
    o.loading = LoadingMode::Record;
    o.alpha = AlphaFit::Shared;
    let prep = prepare(&rec, &segs, &o).map_err(|e| e.to_string())?;
    let r = fit(&prep, &o).map_err(|e| e.to_string())?;
    let rel = |x: f64, t: f64| (x - t) / t;
    let mut out = json!({
        "file": file,
        "alpha_true": f("alpha")?,
        "alpha": r.params.alpha.first(),
        "alpha_ci": r.ci95.get("alpha1"),
        "a_err": rel(r.params.a, f("a")?),
        "b_err": rel(r.params.b[0], f("b")?),
        "dc_err": rel(r.params.dc[0], f("dc")?),
        "rms": r.rms,
    });
    if with_diagnosis {
        let mut base =
            FitOptions::new(vec![rsf_laws::law_by_name("slip", |_| None).map_err(|e| e.to_string())?], f("k")?);
        base.loading = LoadingMode::Protocol;
        let d = diagnose(&rec, &segs, &DiagnoseOptions { threads: 1, ..DiagnoseOptions::new(base) })
            .map_err(|e| e.to_string())?;
        out["cause"] = json!(d.cause.as_str());
        out["gain_bic"] = json!(
            d.candidates.iter().find(|c| c.cause == rsf_diagnose::Cause::NormalStressCoupling).map(|c| c.delta_bic)
        );
        out["effect"] = json!(d.effect);
    }
    out["seconds"] = json!(clock.elapsed().as_secs_f64());
    Ok(out)
}
