//! Benchmark of `rsf diagnose`: a full diagnosis (baseline, five candidates with held-out
//! tests, per-event refits, combinations) of a 50,000-sample step-and-hold record, for a record
//! with nothing hidden and for one with each effect, on all cores of this machine.
//!
//! ```text
//! cargo run --release -p rsf-diagnose --example bench_diagnose [-- CAUSE]
//! ```

use rsf_core::{Model, StateVariable};
use rsf_diagnose::{DiagnoseOptions, diagnose};
use rsf_fit::fit::{FitOptions, LoadingMode};
use rsf_fit::segment::{SegmentOptions, detect};
use rsf_fit::synthetic::{Noise, record, step_hold_protocol};
use rsf_laws::{Aging, KatoTullis, Slip, law_by_name};
use std::time::Instant;

fn main() {
    // the lab-like protocol sampled ~8.5× denser: 50,000 samples
    let base = step_hold_protocol();
    let n0: f64 = base.iter().map(|&(_, d, dt)| (d / dt).round()).sum();
    let scale = n0 / 50_000.0;
    let protocol: Vec<_> = base.iter().map(|&(v, d, dt)| (v, d, dt * scale)).collect();
    let m = || Model::new(0.6, 1.0, 0.010, 0.005);
    let cases: Vec<(&str, Model)> = vec![
        ("none", m().with_state(StateVariable::new(Slip, 0.013, 8.0))),
        ("evolution_law", m().with_state(StateVariable::new(Aging, 0.013, 8.0))),
        (
            "second_state_variable",
            m().with_state(StateVariable::new(Slip, 0.010, 5.0)).with_state(StateVariable::new(Slip, 0.004, 60.0)),
        ),
        ("cutoff_velocity", m().with_state(StateVariable::new(KatoTullis { vc: 0.02 }, 0.013, 8.0))),
        ("slip_trend", m().with_state(StateVariable::new(Slip, 0.013, 8.0)).with_slip_trend(3e-6)),
        ("stiffness", Model::new(0.6, 1.0, 0.010, 0.008).with_state(StateVariable::new(Slip, 0.013, 8.0))),
    ];
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!("| hidden | samples | cause found | median wall (3 runs, {threads} threads) |\n|---|---|---|---|");
    let mut all = vec![];
    // `bench_diagnose CAUSE` runs one case only
    let only = std::env::args().nth(1);
    for (i, (name, truth)) in cases.iter().enumerate() {
        if only.as_deref().is_some_and(|o| o != *name) {
            continue;
        }
        let rec = record(truth, 1.0, &protocol, Noise { sigma: 2e-4, tau: 3.0 }, 100 + i as u64).unwrap();
        let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
        let mut times = vec![];
        let mut cause = String::new();
        for _ in 0..std::env::var("RUNS").ok().and_then(|r| r.parse().ok()).unwrap_or(3) {
            let mut fit = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], 0.005);
            fit.loading = LoadingMode::Protocol;
            let t = Instant::now();
            let stage_times = std::env::args().any(|a| a == "--stage-times");
            let d = diagnose(&rec, &segs, &DiagnoseOptions { stage_times, ..DiagnoseOptions::new(fit) }).unwrap();
            times.push(t.elapsed().as_secs_f64());
            cause = d.cause.to_string();
            if stage_times {
                for c in &d.candidates {
                    if let Some(f) = &c.fit {
                        eprintln!(
                            "   {:24} steps {:>10} (fit {:>10}) iterations {:>3} starts {} {}{}",
                            c.cause,
                            c.steps,
                            f.steps,
                            f.iterations,
                            f.starts,
                            f.stop_reason,
                            f.budget_hit.map_or(String::new(), |b| format!(" ({b})"))
                        );
                    }
                }
            }
        }
        times.sort_by(f64::total_cmp);
        all.push(times[times.len() / 2]);
        println!("| {name} | {} | {cause} | {:.1} s |", rec.len(), times[times.len() / 2]);
    }
    all.sort_by(f64::total_cmp);
    println!("\nslowest median {:.1} s (target < 30 s)", all[all.len() - 1]);
}
