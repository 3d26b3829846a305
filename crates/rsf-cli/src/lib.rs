//! `rsf` — rate-and-state friction from the command line, as a library so that a crate adding
//! laws can be the same CLI with its laws registered ([`main`]).
//!
//! Every output goes through `output` (temporary file, renamed when complete; an output that
//! is an input refused before work starts); every record through the one reader
//! (`rsf_record`, via `rsf_fit::data`).
#![forbid(unsafe_code)]

mod args;
mod batch;
mod batch_lock;
mod design;
mod fit;
mod laws;
mod output;
mod plot;
mod summary_parquet;
mod summary_set;

use anyhow::{Context, Result};
use args::{Cli, Command};
use clap::Parser;
use std::time::Instant;

/// The `rsf` command line: parses the process's arguments, runs the command, prints an error
/// and returns failure if it fails. A crate that registers its own laws first
/// ([`rsf_laws::registry::register`]) and then calls this is the `rsf` CLI with those laws
/// (examples/custom-law's `rsf-power`).
pub fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            use std::io::Write;
            // eprintln! would panic on a closed stderr
            let _ = writeln!(std::io::stderr(), "error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// Writes to standard output and flushes it; a closed pipe (`rsf … | head`) is not an error.
/// When an output file is standard output (`--json -`, `--json /dev/stdout`), the text goes to
/// standard error instead, so that the file arrives whole.
fn write_stdout(text: &str) -> Result<()> {
    use std::io::Write;
    if output::stdout_taken() {
        let _ = std::io::stderr().write_all(text.as_bytes());
        return Ok(());
    }
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => Ok(r?),
    }
}

fn run(cli: Cli) -> Result<()> {
    for f in &cli.law_file {
        rsf_laws::text_law::register_file(f).map_err(anyhow::Error::msg)?;
    }
    match cli.command {
        Command::Laws => write_stdout(&laws::list()),
        Command::CheckLaw { law, cases, steady_state_dc_over_v } => {
            write_stdout(&laws::check_law(&law, cases, steady_state_dc_over_v)?)
        }
        Command::Fit(args) => fit::run(&args),
        Command::Diagnose(args) => fit::diagnose(&args),
        Command::Design(args) => design::run(&args),
        Command::Batch(args) => batch::run(&args),
        Command::Segments { data, read, json, min_ratio, min_duration } => {
            output::Files::default().input("record", &data).check()?;
            let rec = read.read(&data)?;
            let opts = rsf_fit::segment::SegmentOptions { min_ratio, min_duration, ..Default::default() };
            let segs = rsf_fit::segment::detect(&rec.time, &rec.load_point, &opts);
            let sn_events = rsf_fit::segment::normal_stress_events(&rec.time, &rec.normal_stress);
            let text = if json {
                // the segments array as before (it feeds `--segments`); σ changes on stderr
                if !sn_events.is_empty() {
                    eprintln!("normal-stress changes: {}", serde_json::to_string(&sn_events)?);
                }
                serde_json::to_string_pretty(&segs)? + "\n"
            } else {
                let mut t = format!(
                    "{:>3} {:>10} {:>12} {:>12} {:>10} {:>12} {:>12} {:>8}\n",
                    "#", "kind", "t_start_s", "t_end_s", "dur_s", "lp_start_um", "v_um_s", "samples"
                );
                for (k, s) in segs.iter().enumerate() {
                    t += &format!(
                        "{:>3} {:>10} {:>12.3} {:>12.3} {:>10.3} {:>12.3} {:>12.5} {:>8}\n",
                        k + 1,
                        s.kind.name(),
                        s.t0,
                        s.t1,
                        s.t1 - s.t0,
                        s.lp0,
                        s.v,
                        s.i1 + 1 - s.i0
                    );
                }
                if !sn_events.is_empty() {
                    t += &format!(
                        "\nnormal-stress changes:\n{:>3} {:>12} {:>12} {:>10} {:>10}\n",
                        "#", "t_start_s", "t_end_s", "from_mpa", "to_mpa"
                    );
                    for (k, e) in sn_events.iter().enumerate() {
                        t += &format!("{:>3} {:>12.3} {:>12.3} {:>10.4} {:>10.4}\n", k + 1, e.t0, e.t1, e.from, e.to);
                    }
                }
                t
            };
            write_stdout(&text)
        }
        Command::Simulate { protocol, output, plot, method, rtol, atol } => {
            let mut p = rsf_solvers::protocol::load(&protocol)?;
            // the catalogue goes beside a CSV file (OUT_events.csv); with output to a device or
            // a pipe (`-o /dev/null`), or none, to stderr
            let events_path = match (&output, p.problem.watch.event_slip_rate) {
                (Some(path), Some(_)) if !std::fs::metadata(path).is_ok_and(|m| !m.is_file()) => {
                    Some(path.with_file_name(format!(
                        "{}_events.csv",
                        path.file_stem().map(|s| s.to_string_lossy()).unwrap_or_default()
                    )))
                }
                _ => None,
            };
            let mut files = output::Files::default().input("protocol", &protocol);
            if let Some(r) = &p.record {
                files = files.input("record the protocol reads", r);
            }
            files
                .output("-o", output.as_deref())
                .output("--plot", plot.as_deref())
                .output("events", events_path.as_deref())
                .check()?;
            if method.is_some() || rtol.is_some() || atol.is_some() {
                let tol = p.method.tolerances();
                let name = method.clone().unwrap_or_else(|| p.method.name().into());
                p.method = rsf_solvers::Method::from_name(&name, rtol.unwrap_or(tol.rtol), atol.unwrap_or(tol.atol))
                    .with_context(|| {
                        format!("unknown --method `{name}`; use one of {}", rsf_solvers::Method::NAMES.join(", "))
                    })?;
            }
            let start = Instant::now();
            let sol = p.method.solve(&p.problem).with_context(|| format!("simulating {}", protocol.display()))?;
            let solve_s = start.elapsed().as_secs_f64();
            let start = Instant::now();
            match &output {
                Some(path) => output::write_file(path, |w| sol.write_csv(w))?,
                // a closed pipe (`rsf simulate p.toml | head`) ends the output quietly
                None => match sol.write_csv(std::io::stdout().lock()) {
                    Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {}
                    r => r.context("writing CSV to stdout")?,
                },
            }
            let write_s = start.elapsed().as_secs_f64();
            if let Some(v) = p.problem.watch.event_slip_rate {
                match &events_path {
                    Some(ev) => {
                        output::write_file(ev, |w| sol.write_events_csv(w))?;
                        eprintln!("rsf simulate: {} events (V ≥ {v} µm/s) in {}", sol.events.len(), ev.display());
                    }
                    None => {
                        eprintln!("rsf simulate: {} events (V ≥ {v} µm/s):", sol.events.len());
                        sol.write_events_csv(std::io::stderr().lock()).context("writing events")?;
                    }
                }
            }
            if let Some(path) = &plot {
                plot::simulation(&sol, p.measured_friction.as_deref(), path, &protocol.display().to_string())
                    .with_context(|| format!("writing plot {}", path.display()))?;
            }
            if let Some(mu) = &p.measured_friction {
                if mu.len() == sol.len() {
                    let rms =
                        (mu.iter().zip(&sol.mu).map(|(a, b)| (a - b).powi(2)).sum::<f64>() / mu.len() as f64).sqrt();
                    eprintln!("rsf simulate: rms misfit to the measured friction column: {rms:.3e}");
                }
            }
            let s = sol.stats;
            // one write: stderr is unbuffered, and each piece of a formatted message would be
            // a system call of its own
            let summary = format!(
                "rsf simulate: {} rows, {} states, method {} | {} steps ({} rejected), {} RHS, {} Jacobians | solve {:.3} ms, write {:.3} ms\n",
                sol.len(),
                sol.theta.len(),
                sol.method,
                s.accepted,
                s.rejected,
                s.rhs_evals,
                s.jacobian_evals,
                solve_s * 1e3,
                write_s * 1e3
            );
            eprint!("{summary}");
            Ok(())
        }
    }
}
