//! Benchmark of fitting: an LM fit of a 100,000-sample, 10-segment synthetic record (Slip law,
//! one state, k fixed), MCMC throughput on the same protocol, and the peer approach —
//! finite-difference least squares over scipy's ODE solvers (benches/scipy_fit.py) — on the
//! same record in the same run.
//!
//! ```text
//! cargo run --release -p rsf-fit --example bench_fit [-- --no-scipy]
//! ```

use rsf_core::{Model, StateVariable};
use rsf_fit::fit::{FitOptions, LoadingMode, fit, initial_guess, prepare};
use rsf_fit::mcmc::{self, McmcOptions};
use rsf_fit::segment::{SegmentOptions, detect};
use rsf_fit::synthetic::{Noise, SampledSegment, record};
use rsf_laws::{Slip, law_by_name};
use std::time::Instant;

/// The same protocol sampled like a lab record: 10 Hz while sliding, 1 Hz in holds.
fn lab_protocol() -> Vec<SampledSegment> {
    protocol(1.0).into_iter().map(|(v, d, _)| (v, d, if v == 0.0 { 1.0 } else { 0.1 })).collect()
}

fn protocol(n_samples: f64) -> Vec<SampledSegment> {
    let segs = [
        (1.0, 50.0),
        (10.0, 15.0),
        (1.0, 100.0),
        (0.0, 100.0),
        (1.0, 60.0),
        (0.1, 300.0),
        (1.0, 60.0),
        (0.0, 1000.0),
        (1.0, 60.0),
        (3.0, 20.0),
    ];
    let total: f64 = segs.iter().map(|s| s.1).sum();
    let dt = total / n_samples;
    segs.iter().map(|&(v, d)| (v, d, dt)).collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Reading speed: CSV files of 1 and 5 million rows (time_s,load_point_um,mu).
fn ingest() {
    use std::io::Write;
    for rows in [1_000_000usize, 5_000_000] {
        let path = std::env::temp_dir().join(format!("rsf_ingest_{rows}.csv"));
        let mut w = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
        writeln!(w, "time_s,load_point_um,mu").unwrap();
        for i in 0..rows {
            let t = i as f64 * 0.01;
            writeln!(w, "{:.4},{:.4},{:.6}", 1000.0 + t, 5000.0 + 3.0 * t, 0.6 + 1e-3 * (t * 0.1).sin()).unwrap();
        }
        drop(w);
        let size = std::fs::metadata(&path).unwrap().len() as f64 / 1e6;
        let mut times = vec![];
        for _ in 0..3 {
            let t = Instant::now();
            let r = rsf_fit::data::read_record(&path, &rsf_fit::data::ReadOptions::default()).unwrap();
            times.push(t.elapsed().as_secs_f64());
            assert_eq!(r.len(), rows);
        }
        let t = median(times);
        println!(
            "| read CSV ({size:.0} MB), streaming | {} rows | {:.3} s | **{:.3} s per million rows**; kept: 3 × 8 bytes per row |",
            rows,
            t,
            t / (rows as f64 / 1e6)
        );
        let _ = std::fs::remove_file(&path);
    }
}

fn main() {
    let scipy = !std::env::args().any(|a| a == "--no-scipy");
    let truth = Model::new(0.6, 1.0, 0.010, 0.005).with_state(StateVariable::new(Slip, 0.013, 8.0));
    println!("| what | record | median wall | result |\n|---|---|---|---|");
    ingest();
    let mut rust_fit_s = 0.0;
    let mut rust_one_start_s = 0.0;
    let mut big = None;
    for (n, label) in
        [(1.0e5, "100k samples"), (1.765e4, "10 Hz (17.6k samples)"), (0.0, "10 Hz sliding, 1 Hz holds (7.8k samples)")]
    {
        let proto = if n > 0.0 { protocol(n) } else { lab_protocol() };
        let rec = record(&truth, 1.0, &proto, Noise { sigma: 2e-4, tau: 0.0 }, 1).unwrap();
        let label = format!("{label}: {} rows", rec.len());
        for loading in [LoadingMode::Record, LoadingMode::Protocol] {
            let mut opts = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], 0.005);
            opts.loading = loading;
            if n == 1.0e5 && loading == LoadingMode::Record {
                // one start, as the peer uses
                let mut o1 = opts.clone();
                o1.starts = 1;
                let t = Instant::now();
                let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
                let r = fit(&prepare(&rec, &segs, &o1).unwrap(), &o1).unwrap();
                rust_one_start_s = t.elapsed().as_secs_f64();
                println!(
                    "| LM fit, 1 start, loading Record | {label} | {:.3} s | a {:.5}, b {:.5}, Dc {:.3}, {} iterations |",
                    rust_one_start_s, r.params.a, r.params.b[0], r.params.dc[0], r.iterations
                );
            }
            let mut times = vec![];
            let mut last = None;
            for _ in 0..5 {
                let t = Instant::now();
                let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
                let p = prepare(&rec, &segs, &opts).unwrap();
                let r = fit(&p, &opts).unwrap();
                times.push(t.elapsed().as_secs_f64());
                last = Some(r);
            }
            let r = last.unwrap();
            let t = median(times);
            if n == 1.0e5 && loading == LoadingMode::Record {
                rust_fit_s = t;
            }
            println!(
                "| LM fit (segmentation + {} starts), loading {:?} | {label}, {} segments | {:.3} s | a {:.5}, b {:.5}, Dc {:.3}, rms {:.2e}, {} iterations |",
                r.starts,
                loading,
                r.segments.len(),
                t,
                r.params.a,
                r.params.b[0],
                r.params.dc[0],
                r.rms,
                r.iterations
            );
        }
        // MCMC throughput: 2 chains on the 2 cores
        let mut opts = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], 0.005);
        opts.loading = LoadingMode::Protocol;
        let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
        let p = prepare(&rec, &segs, &opts).unwrap();
        let r = fit(&p, &opts).unwrap();
        let m = McmcOptions { samples: 8000, chains: 2, seed: 1, ..Default::default() };
        let mc = mcmc::run(&p, &opts, &r, &m).unwrap();
        println!(
            "| MCMC, 2 chains (2 cores), rtol {:.0e} | {label}, 10 segments | {:.2} s | **{:.0} forward simulations/s**, acceptance {:.2}, R-hat(a) {:.3} |",
            m.rtol, mc.wall_s, mc.simulations_per_s, mc.acceptance, mc.params["a"].rhat
        );
        if n == 1.0e5 {
            big = Some((rec, p, proto));
        }
    }
    if !scipy {
        return;
    }
    // the peer: finite-difference least squares over scipy solve_ivp, same record and start
    let (rec, p, proto) = big.unwrap();
    let (mu0, a, b, dc) = initial_guess(&p);
    let dir = std::env::temp_dir();
    let csv = dir.join("rsf_bench_fit.csv");
    let mut text = String::from("time_s,load_point_um,mu\n");
    for i in 0..rec.len() {
        text += &format!("{:?},{:?},{:?}\n", rec.time[i], rec.load_point[i], rec.mu[i]);
    }
    std::fs::write(&csv, text).unwrap();
    let segs: Vec<String> = proto.iter().map(|(v, d, _)| format!("{{\"v\": {v:?}, \"duration\": {d:?}}}")).collect();
    let setup = format!(
        "{{\"law\": \"slip\", \"k\": 0.005, \"v_init\": 1.0, \"v0\": 1.0, \"segments\": [{}], \"initial\": {{\"mu0\": {mu0:?}, \"a\": {a:?}, \"b\": {b:?}, \"dc\": {dc:?}}}, \"rtol\": 1e-7}}",
        segs.join(", ")
    );
    let json = dir.join("rsf_bench_fit.json");
    std::fs::write(&json, setup).unwrap();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/../../benches/scipy_fit.py");
    for method in ["DOP853", "LSODA"] {
        let out = std::process::Command::new("python3")
            .args([script, csv.to_str().unwrap(), json.to_str().unwrap(), "--repeats", "1", "--method", method])
            .output();
        match out {
            Ok(o) if o.status.success() => {
                let v = String::from_utf8_lossy(&o.stdout).to_string();
                let f = |k: &str| -> String {
                    let i = v.find(&format!("\"{k}\": ")).map(|i| i + k.len() + 4).unwrap_or(0);
                    v[i..].split([',', '}']).next().unwrap_or("").trim().to_string()
                };
                let t: f64 = f("wall_s_median").parse().unwrap_or(f64::NAN);
                println!(
                    "| peer: scipy least_squares (2-point FD) over solve_ivp({method}), 1 start | 100k samples, 10 segments | {t:.2} s | {} ODE solves, a {}, dc {}, rms {}; **rsf 1 start is {:.1}× faster, rsf with 5 starts {:.1}×** |",
                    f("n_ode_solves"),
                    f("a"),
                    f("dc"),
                    f("rms"),
                    t / rust_one_start_s,
                    t / rust_fit_s
                );
            }
            Ok(o) => println!(
                "| peer {method} | failed | | {} |",
                String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or("")
            ),
            Err(e) => println!("| peer {method} | python3 not runnable: {e} | | |"),
        }
    }
}
