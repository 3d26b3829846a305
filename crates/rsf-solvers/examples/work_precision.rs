//! Work–precision data of rsf's integrators on four cases, for `benches/work_precision/run.sh`
//! (which adds scipy's solvers on the same cases and draws the diagrams).
//!
//! ```sh
//! cargo run --release -p rsf-solvers --example work_precision -- OUTDIR [--repeats 5]
//! ```
//!
//! Writes, per case, `OUTDIR/<case>.json` (the model and protocol, read by `peers.py`) and
//! `OUTDIR/<case>_rsf.json` (for every method and rtol: median wall time of the whole protocol
//! on one core, steps, and μ at the end of every segment). The cases:
//!
//! * `seed`: the 71-segment protocol of `bench_protocol` (steps of 0.5–3.5 decades, holds of
//!   10–10⁴ s), Slip law, Bhattacharya et al. (2022) Table 1;
//! * `hold`: sliding at 10 µm/s, a 10⁴ s hold and a reslide on a very stiff machine (k = 10
//!   /µm, Dc = 0.1 µm): the spring relaxes in a/(kV) ≈ 1e-4 s, the state in Dc/V = 0.01 s, so
//!   the sliding is stiff;
//! * `stickslip`: radiation-damped stick-slip (k far below critical, η = 1e-3 per µm/s);
//! * `two_state`: a Slip-law and an Aging-law state with Dc 1 and 50 µm, steps and a hold.

use rsf_core::{Loading, Model, Segment, StateVariable};
use rsf_laws::{Aging, Slip};
use rsf_solvers::{Auto, Dopri5, Integrator, OutputTimes, Problem, Rodas4, Rodas5P, Solution, Tsit5, Vern6, solve};
use std::fmt::Write as _;
use std::time::Instant;

#[path = "common/seed_protocol.rs"]
mod seed_protocol;
use seed_protocol::seed_protocol;

struct Case {
    name: &'static str,
    model: Model,
    /// (law name, b, dc) of each state, for the JSON the peers read.
    states: Vec<(&'static str, f64, f64)>,
    v_init: f64,
    segments: Vec<(f64, f64)>,
}

fn cases() -> Vec<Case> {
    let with = |m: Model, st: &[(&'static str, f64, f64)]| {
        st.iter().fold(m, |m, &(law, b, dc)| match law {
            "slip" => m.with_state(StateVariable::new(Slip, b, dc)),
            _ => m.with_state(StateVariable::new(Aging, b, dc)),
        })
    };
    let seed_states = vec![("slip", 0.016, 2.07)];
    let hold_states = vec![("slip", 0.016, 0.1)];
    let ss_states = vec![("slip", 0.016, 2.07)];
    let two_states = vec![("slip", 0.008, 1.0), ("aging", 0.004, 50.0)];
    vec![
        Case {
            name: "seed",
            model: with(Model::new(0.6, 1.0, 0.013, 0.065), &seed_states),
            states: seed_states,
            v_init: 3.0,
            segments: seed_protocol(),
        },
        Case {
            name: "hold",
            model: with(Model::new(0.6, 1.0, 0.013, 10.0), &hold_states),
            states: hold_states,
            v_init: 10.0,
            segments: vec![(10.0, 2.0), (0.0, 1e4), (10.0, 2.0)],
        },
        Case {
            name: "stickslip",
            model: with(Model::new(0.6, 1.0, 0.01, 3e-4), &ss_states).with_eta(1e-3),
            states: ss_states,
            v_init: 3.0,
            segments: vec![(1.0, 300.0), (0.0, 100.0), (1.0, 300.0)],
        },
        Case {
            name: "two_state",
            model: with(Model::new(0.6, 1.0, 0.01, 0.01), &two_states),
            states: two_states,
            v_init: 1.0,
            segments: vec![(10.0, 50.0), (1.0, 300.0), (0.1, 1000.0), (0.0, 1000.0), (1.0, 300.0)],
        },
    ]
}

fn problem(c: &Case) -> Problem {
    let segs = c.segments.iter().map(|&(v, d)| Segment::for_duration(v, d)).collect();
    let mut p = Problem::new(c.model.clone(), Loading::Segments(segs), c.v_init, 1.0);
    p.output = OutputTimes::PieceEnds;
    p
}

/// Median wall time and the solution (μ at the end of every segment) of `repeats` solves.
fn timed<I: Integrator>(p: &Problem, alg: &I, repeats: usize) -> Result<(f64, Solution), String> {
    let mut times = Vec::new();
    let mut sol = None;
    for _ in 0..repeats {
        let t = Instant::now();
        let s = solve(p, alg).map_err(|e| e.to_string())?;
        times.push(t.elapsed().as_secs_f64());
        sol = Some(s);
    }
    times.sort_by(f64::total_cmp);
    Ok((times[times.len() / 2], sol.ok_or("no repeats")?))
}

fn floats(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(", ")
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = std::path::PathBuf::from(args.first().ok_or("usage: work_precision OUTDIR [--repeats N]")?);
    let repeats: usize =
        args.iter().position(|a| a == "--repeats").and_then(|i| args.get(i + 1)).map_or(Ok(5), |r| r.parse())?;
    std::fs::create_dir_all(&out)?;
    let rtols = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];
    for c in cases() {
        let m = &c.model;
        let states: Vec<String> =
            c.states.iter().map(|(l, b, dc)| format!("{{\"law\": \"{l}\", \"b\": {b:?}, \"dc\": {dc:?}}}")).collect();
        let segs: Vec<String> =
            c.segments.iter().map(|(v, d)| format!("{{\"v\": {v:?}, \"duration\": {d:?}}}")).collect();
        std::fs::write(
            out.join(format!("{}.json", c.name)),
            format!(
                "{{\"name\": \"{}\", \"model\": {{\"mu0\": {:?}, \"v0\": {:?}, \"a\": {:?}, \"k\": {:?}, \"eta\": {:?}, \"states\": [{}]}}, \"v_init\": {:?}, \"segments\": [{}]}}\n",
                c.name,
                m.mu0,
                m.v0,
                m.a,
                m.stiffness,
                m.eta,
                states.join(", "),
                c.v_init,
                segs.join(", ")
            ),
        )?;
        if c.name == "seed" {
            // the protocol file of the `rsf simulate` process benchmark (run.sh)
            let mut t = format!(
                "# {} segments of the seed-like protocol (written by the work_precision example)\n[model]\nmu0 = {:?}\nv0 = {:?}\na = {:?}\nstiffness = {:?}\n\n[[model.state]]\nlaw = \"slip\"\nb = {:?}\ndc = {:?}\n\n[loading]\nv_init = {:?}\n",
                c.segments.len(),
                m.mu0,
                m.v0,
                m.a,
                m.stiffness,
                c.states[0].1,
                c.states[0].2,
                c.v_init
            );
            for (v, d) in &c.segments {
                write!(t, "\n[[loading.segment]]\nv = {v:?}\nduration = {d:?}\n")?;
            }
            t.push_str("\n[output]\ndt = 50.0\n\n[solver]\nmethod = \"auto\"\nrtol = 1e-8\natol = 1e-12\n");
            std::fs::write(out.join("seed.toml"), t)?;
        }
        let p = problem(&c);
        let n = c.segments.len();
        let mut runs = vec![];
        for &rtol in &rtols {
            // atol is the slip's (µm); ln V and ln θ are controlled by rtol alone
            let atol = 1e-12;
            let results = [
                ("auto", timed(&p, &Auto::new(rtol, atol), repeats)),
                ("tsit5", timed(&p, &Tsit5::new(rtol, atol), repeats)),
                ("vern6", timed(&p, &Vern6::new(rtol, atol), repeats)),
                ("dopri5", timed(&p, &Dopri5::new(rtol, atol), repeats)),
                ("rodas5p", timed(&p, &Rodas5P::new(rtol, atol), repeats)),
                ("rodas4", timed(&p, &Rodas4::new(rtol, atol), repeats)),
            ];
            for (name, r) in results {
                let mut s = String::new();
                match r {
                    Ok((t, sol)) => {
                        let mu = &sol.mu[sol.mu.len().saturating_sub(n)..];
                        let st = sol.stats;
                        write!(
                            s,
                            "{{\"solver\": \"rsf {name}\", \"method\": \"{name}\", \"rtol\": {rtol:?}, \"wall_s\": {t:?}, \"steps\": {}, \"rejected\": {}, \"rhs_evals\": {}, \"jacobians\": {}, \"to_implicit\": {}, \"to_explicit\": {}, \"mu\": [{}]}}",
                            st.accepted,
                            st.rejected,
                            st.rhs_evals,
                            st.jacobian_evals,
                            st.to_implicit,
                            st.to_explicit,
                            floats(mu)
                        )?;
                        eprintln!(
                            "{:10} {name:8} rtol {rtol:.0e}: {:9.3} ms, {} steps, switches {}/{}",
                            c.name,
                            t * 1e3,
                            st.accepted,
                            st.to_implicit,
                            st.to_explicit
                        );
                    }
                    Err(e) => {
                        write!(
                            s,
                            "{{\"solver\": \"rsf {name}\", \"method\": \"{name}\", \"rtol\": {rtol:?}, \"error\": {:?}}}",
                            e
                        )?;
                        eprintln!("{:10} {name:8} rtol {rtol:.0e}: failed: {e}", c.name);
                    }
                }
                runs.push(s);
            }
        }
        std::fs::write(
            out.join(format!("{}_rsf.json", c.name)),
            format!("{{\"case\": \"{}\", \"runs\": [\n{}\n]}}\n", c.name, runs.join(",\n")),
        )?;
    }
    Ok(())
}
