//! SEAS BP1-QD with rsf-cycle.
//!
//! ```sh
//! cargo run --release -p rsf-cycle --example bp1qd -- --cells 512 --years 3000 --out target/bp1qd
//! cargo run --release -p rsf-cycle --example bp1qd -- --cells 512 --years 1000 --law slip --out target/bp1qd_slip
//! # two state variables: b = 0.010 + 0.005, Dc = 8 mm and 80 mm
//! cargo run --release -p rsf-cycle --example bp1qd -- --cells 512 --years 1000 --second-state 0.005,0.08 --out target/bp1qd_2state
//! ```
//!
//! Writes `OUT/events.csv` (`onset_yr,peak_slip_rate_m_s,surface_slip_m,nucleation_depth_km`) and
//! the 12 station files `OUT/fltst_dpXXX`, and prints the catalogue with the recurrence
//! intervals, the integrator's work and the time per step and per dense mat-vec.

use rsf_cycle::elastic::Kernel;
use rsf_cycle::run::{CycleProgress, ProgressFn, RunOptions, run_with};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let flag = |name: &str| args.iter().position(|a| a == name).and_then(|i| args.get(i + 1)).cloned();
    let line: ProgressFn = std::sync::Arc::new(|p: &CycleProgress| {
        eprintln!(
            "t = {:8.2} yr  max V = {:9.3e} m/s  events {}  steps {}",
            p.years, p.max_slip_rate, p.events, p.steps
        )
    });
    let mut o = RunOptions { progress: Some(line), ..RunOptions::default() };
    if let Some(n) = flag("--cells") {
        o.cells = n.parse()?;
    }
    if let Some(y) = flag("--years") {
        o.years = y.parse()?;
    }
    if let Some(r) = flag("--rtol") {
        o.rtol = r.parse()?;
    }
    if let Some(m) = flag("--max-events") {
        o.max_events = Some(m.parse()?);
    }
    o.out = Some(flag("--out").unwrap_or_else(|| "target/bp1qd".into()).into());
    let mut p = rsf_cycle::params::Bp1::default();
    if let Some(b0) = flag("--b0") {
        p.b0 = b0.parse()?;
    }
    match flag("--law").as_deref() {
        None | Some("aging") => {}
        Some("slip") => p.law = rsf_cycle::params::EvolutionLaw::Slip,
        Some(other) => return Err(format!("--law {other}: use aging (the benchmark's) or slip").into()),
    }
    // --second-state B,DC[,LAW]: a second state variable (b0 stays the first state's b)
    if let Some(s) = flag("--second-state") {
        let parts: Vec<&str> = s.split(',').collect();
        let law = match parts.get(2).copied() {
            None | Some("aging") => rsf_cycle::params::EvolutionLaw::Aging,
            Some("slip") => rsf_cycle::params::EvolutionLaw::Slip,
            Some(other) => return Err(format!("--second-state law {other}: use aging or slip").into()),
        };
        let (b, dc) = match (parts.first().map(|x| x.parse::<f64>()), parts.get(1).map(|x| x.parse::<f64>())) {
            (Some(Ok(b)), Some(Ok(dc))) if dc > 0.0 => (b, dc),
            _ => return Err(format!("--second-state {s}: give B,DC[,LAW] with Dc > 0 (m)").into()),
        };
        p.second = Some(rsf_cycle::params::SecondState { law, b, dc });
    }
    eprintln!("BP1-QD: {} cells of {:.1} m, {} yr, rtol {:e}", o.cells, 40e3 / o.cells as f64, o.years, o.rtol);
    let r = run_with(p, &o)?;
    println!("| # | onset (yr) | interval (yr) | peak V (m/s) | peak at (km) | surface slip (m) | nucleation (km) |");
    println!("|---|---|---|---|---|---|---|");
    let mut prev: Option<f64> = None;
    for (i, e) in r.catalogue.events.iter().enumerate() {
        let on = e.onset_s / rsf_cycle::YEAR;
        println!(
            "| {} | {on:.2} | {} | {:.3} | {:.2} | {:.3} | {:.2} |",
            i + 1,
            prev.map_or("–".into(), |p| format!("{:.2}", on - p)),
            e.peak_v,
            e.peak_depth_m / 1e3,
            e.surface_slip,
            e.nucleation_depth_m / 1e3
        );
        prev = Some(on);
    }
    let s = r.stats;
    println!(
        "\n{:.1} yr in {:.1} s wall: {} steps ({} rejected), {} RHS, {:.1} µs per step, {:.1} µs per RHS",
        r.t_end / rsf_cycle::YEAR,
        r.wall_s,
        s.accepted,
        s.rejected,
        s.rhs_evals,
        r.wall_s * 1e6 / (s.accepted + s.rejected) as f64,
        r.wall_s * 1e6 / s.rhs_evals as f64
    );
    // the dense mat-vec alone, for the record
    let mut k = Kernel::new(rsf_cycle::params::Bp1::default().mu(), 40e3, o.cells);
    let v = vec![2e-9; o.cells];
    let mut out = vec![0.0; o.cells];
    let reps = 2000;
    let t = Instant::now();
    for _ in 0..reps {
        k.stressing_rate(&v, 1e-9, &mut out);
    }
    println!(
        "dense mat-vec (faer, N = {}): {:.1} µs per product",
        o.cells,
        t.elapsed().as_secs_f64() * 1e6 / reps as f64
    );
    Ok(())
}
