//! Benchmark: the reference paper's whole protocol — 16 velocity-step decreases and 13
//! increases of 0.5–3.5 orders of magnitude between 3 and 0.001 µm/s, then holds of 10 … 10^4 s
//! from 1, 0.3 and 0.03 µm/s with reslides — under both integrators at rtol 1e-8.
//!
//! ```text
//! cargo run --release -p rsf-solvers --example bench_protocol [-- --repeats 21 --no-scipy]
//! ```
//!
//! Reports median wall time (one core), steps and RHS/Jacobian evaluations, the accuracy
//! against a tight-tolerance run, the cost of a million output rows (solve with dense output
//! and CSV writing, separately), and — when python3 with scipy is installed — the same
//! protocol under scipy's `solve_ivp(method="Radau")` (benches/scipy_protocol.py) measured in
//! the same run, with the ratio.

use rsf_core::{Loading, Model, Segment, StateVariable};
use rsf_laws::{Aging, Slip};
use rsf_solvers::{Auto, Dopri5, Integrator, OutputTimes, Problem, Rodas4, Rodas5P, Solution, Tsit5, Vern6, solve};
use std::time::Instant;

#[path = "common/seed_protocol.rs"]
mod seed_protocol;
use seed_protocol::seed_protocol;

/// Load-point slip per velocity segment, µm (≈ 10 Dc for the Slip-law fit).
const SLIDE: f64 = 20.0;

/// The protocol as (v, duration) segments, starting at steady state at 3 µm/s.
fn protocol() -> Vec<(f64, f64)> {
    seed_protocol()
}

fn model(law: &str) -> Model {
    let m = Model::new(0.6, 1.0, 0.0, 0.065);
    match law {
        "slip" => Model { a: 0.013, ..m }.with_state(StateVariable::new(Slip, 0.016, 2.07)),
        _ => Model { a: 0.022, ..m }.with_state(StateVariable::new(Aging, 0.018, 0.99)),
    }
}

fn problem(law: &str, output: OutputTimes) -> Problem {
    let segs = protocol().into_iter().map(|(v, d)| Segment::for_duration(v, d)).collect();
    let mut p = Problem::new(model(law), Loading::Segments(segs), 3.0, 1.0);
    p.output = output;
    p
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

fn timed<I: Integrator>(p: &Problem, alg: &I, repeats: usize) -> (f64, Solution) {
    let mut times = Vec::new();
    let mut sol = None;
    for _ in 0..repeats {
        let t = Instant::now();
        let s = solve(p, alg).expect("benchmark solve failed");
        times.push(t.elapsed().as_secs_f64());
        sol = Some(s);
    }
    (median(times), sol.unwrap())
}

/// One table row: law, method, tolerance, time, work, accuracy.
fn row(law: &str, rtol: f64, t: f64, s: &Solution, n_segments: usize, err: f64) {
    println!(
        "| {law} | {} | {rtol:.0e} | {:.3} ms | {:.1} µs | {} ({}) | {} | {} | {err:.1e} |",
        s.method,
        t * 1e3,
        t * 1e6 / n_segments as f64,
        s.stats.accepted,
        s.stats.rejected,
        s.stats.rhs_evals,
        s.stats.jacobian_evals
    );
}

fn max_dmu(a: &Solution, b: &Solution) -> f64 {
    a.mu.iter().zip(&b.mu).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let repeats = args.iter().position(|a| a == "--repeats").map(|i| args[i + 1].parse().unwrap()).unwrap_or(21);
    let scipy = !args.iter().any(|a| a == "--no-scipy");
    let segs = protocol();
    let dec = segs.windows(2).filter(|w| w[1].0 < w[0].0 && w[1].0 > 0.0 && w[0].0 > 0.0).count() + 1;
    let inc = segs.windows(2).filter(|w| w[1].0 > w[0].0 && w[0].0 > 0.0).count();
    let holds = segs.iter().filter(|s| s.0 == 0.0).count();
    let total_t: f64 = segs.iter().map(|s| s.1).sum();
    println!(
        "protocol: {} segments ({dec} step decreases, {inc} increases, {holds} holds with reslides), {:.0} s, {} µm per velocity segment",
        segs.len(),
        total_t,
        SLIDE
    );
    println!("one core, release build, median of {repeats} solves; output only at segment ends (71 rows)\n");
    println!(
        "| law | integrator | rtol | median wall | per segment | steps (rejected) | RHS evals | Jacobians | max abs Δμ vs tight |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let mut rust_radau_ref = None;
    for law in ["slip", "aging"] {
        let p = problem(law, OutputTimes::PieceEnds);
        let tight = solve(&p, &Rodas4::new(1e-13, 1e-15)).unwrap();
        let tight2 = solve(&p, &Dopri5::new(1e-13, 1e-15)).unwrap();
        let tight_err = max_dmu(&tight, &tight2);
        for rtol in [1e-8] {
            let (te, e) = timed(&p, &Dopri5::new(rtol, 1e-11), repeats);
            let (ti, i) = timed(&p, &Rodas4::new(rtol, 1e-11), repeats);
            let (tt, ts) = timed(&p, &Tsit5::new(rtol, 1e-11), repeats);
            let (tv, vs) = timed(&p, &Vern6::new(rtol, 1e-11), repeats);
            let (tp, ps) = timed(&p, &Rodas5P::new(rtol, 1e-11), repeats);
            let (ta, au) = timed(&p, &Auto::new(rtol, 1e-11), repeats);
            for (t, s) in [(ta, &au), (tv, &vs), (tt, &ts), (te, &e), (tp, &ps), (ti, &i)] {
                row(law, rtol, t, s, segs.len(), max_dmu(s, &tight));
            }
            if law == "slip" {
                rust_radau_ref = Some((ta, ti, au.mu[au.len() - 1]));
            }
        }
        // Rodas4's error estimate is conservative: at rtol 1e-7 it matches dopri5's 1e-8 accuracy
        let (t, s) = timed(&p, &Rodas4::new(1e-7, 1e-10), repeats);
        row(law, 1e-7, t, &s, segs.len(), max_dmu(&s, &tight));
        println!("| {law} | (tight: rodas4 vs dopri5 at 1e-13) | | | | | | | {tight_err:.1e} |");
    }

    // output cost: a million rows
    let p = problem("slip", OutputTimes::PieceEnds);
    let t_end: f64 = total_t;
    let dt = t_end / 1.0e6;
    let p_out = problem("slip", OutputTimes::Every(dt));
    let alg = Dopri5::new(1e-8, 1e-11);
    let (t_plain, _) = timed(&p, &alg, 5);
    let (t_dense, sol) = timed(&p_out, &alg, 5);
    let path = std::env::temp_dir().join("rsf_bench_1M.csv");
    let mut tw = Vec::new();
    for _ in 0..3 {
        let t = Instant::now();
        sol.write_csv(std::fs::File::create(&path).unwrap()).unwrap();
        tw.push(t.elapsed().as_secs_f64());
    }
    let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    let _ = std::fs::remove_file(&path);
    println!(
        "\noutput: {} rows by dense output: solve {:.1} ms (vs {:.2} ms with segment-end output only); CSV writing {:.0} ms ({:.0} MB)",
        sol.len(),
        t_dense * 1e3,
        t_plain * 1e3,
        median(tw) * 1e3,
        size as f64 / 1e6
    );

    // scipy Radau on the same equations, tolerance and protocol, in the same run (the protocol
    // file is written even with --no-scipy: benches/work_precision/paired.sh reads it)
    let json = format!(
        "{{\"model\": {{\"mu0\": 0.6, \"v0\": 1.0, \"a\": 0.013, \"k\": 0.065, \"states\": [{{\"law\": \"slip\", \"b\": 0.016, \"dc\": 2.07}}]}}, \"v_init\": 3.0, \"segments\": [{}], \"rtol\": 1e-8, \"atol\": 1e-11}}",
        segs.iter().map(|(v, d)| format!("{{\"v\": {v:?}, \"duration\": {d:?}}}")).collect::<Vec<_>>().join(", ")
    );
    let jpath = std::env::temp_dir().join("rsf_bench_protocol.json");
    std::fs::write(&jpath, json).unwrap();
    if !scipy {
        return;
    }
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/../../benches/scipy_protocol.py");
    let out = std::process::Command::new("python3").args([script, jpath.to_str().unwrap(), "--repeats", "3"]).output();
    match out {
        Ok(o) if o.status.success() => {
            let text = String::from_utf8_lossy(&o.stdout);
            let field = |k: &str| -> f64 {
                let i = text.find(&format!("\"{k}\": ")).unwrap() + k.len() + 4;
                text[i..].split([',', '}']).next().unwrap().trim().parse().unwrap()
            };
            let (te, ti, mu_rust) = rust_radau_ref.unwrap();
            let ts = field("wall_s_median");
            let mu_py = {
                let i = text.find("\"end\": {\"mu\": ").unwrap() + 14;
                text[i..].split(',').next().unwrap().parse::<f64>().unwrap()
            };
            println!(
                "\nscipy solve_ivp(Radau), same equations/tolerance/protocol, median of 3: {:.1} ms ({} RHS, {} Jacobians, {} LU)\n\
                 ratio scipy Radau / rsf auto = {:.0}x, / rsf rodas4 = {:.0}x; end friction differs by {:.1e}",
                ts * 1e3,
                field("nfev"),
                field("njev"),
                field("nlu"),
                ts / te,
                ts / ti,
                (mu_py - mu_rust).abs()
            );
        }
        Ok(o) => {
            println!("\nscipy comparison skipped: {}", String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or(""))
        }
        Err(e) => println!("\nscipy comparison skipped: python3 not runnable ({e})"),
    }
}
