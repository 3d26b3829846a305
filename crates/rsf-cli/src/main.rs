//! `rsf` — rate-and-state friction from the command line.
//!
//! Every output goes through `output` (temporary file, renamed when complete; an output that
//! is an input refused before work starts); every record through the one reader
//! (`rsf_record`, via `rsf_fit::data`).

mod batch;
mod fit;
mod output;
mod plot;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Parser)]
#[command(name = "rsf", version, about = "Rate-and-state friction: simulate lab friction experiments")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// How to read a measured record (a plain comment: as a doc comment, clap would apply it as the
// about text of every subcommand that flattens it, once subcommands are deferred).
#[derive(clap::Args, Clone, Debug)]
struct DataArgs {
    /// Time column (s unless --time-unit).
    #[arg(long, default_value = "time_s")]
    time_col: String,
    /// Load-point displacement column (µm unless --disp-unit).
    #[arg(long, default_value = "load_point_um")]
    lp_col: String,
    /// Friction column.
    #[arg(long, default_value = "mu")]
    mu_col: String,
    /// Shear-stress column; friction = shear / normal stress (needs --normal-stress or --normal-col).
    #[arg(long)]
    shear_col: Option<String>,
    /// Normal-stress column (MPa): divides --shear-col into friction; with a friction column, a
    /// varying normal stress drives the model (see --normal-stress-mode).
    #[arg(long)]
    normal_col: Option<String>,
    /// Whether the record's normal stress (--normal-col) drives the model: auto (when it varies
    /// by more than 2% of its median), record (always) or constant (never).
    #[arg(long, default_value = "auto")]
    normal_stress_mode: String,
    /// Constant normal stress, same units as the shear column.
    #[arg(long)]
    normal_stress: Option<f64>,
    /// Unit of the load-point column: um, mm or m.
    #[arg(long, default_value = "um")]
    disp_unit: String,
    /// Unit of the time column: s or ms.
    #[arg(long, default_value = "s")]
    time_unit: String,
    /// Use only rows with time >= this (s).
    #[arg(long)]
    t_min: Option<f64>,
    /// Use only rows with time <= this (s).
    #[arg(long)]
    t_max: Option<f64>,
    /// Rows whose time repeats the previous row's: `error` (refuse the record) or `drop` (keep
    /// the first of each run, report the count).
    #[arg(long, default_value = "error")]
    duplicate_times: String,
    /// Drop rows with an over-range value (|value| >= 1e30, |friction| >= 10), an instrument's
    /// no-reading value (-999999, -99999), NaN or infinity, and report the count (default: such a
    /// row is an error naming its line and column).
    #[arg(long)]
    drop_invalid: bool,
}

impl DataArgs {
    fn normal_stress_mode(&self) -> Result<rsf_fit::fit::NormalStressMode> {
        use rsf_fit::fit::NormalStressMode as M;
        Ok(match self.normal_stress_mode.as_str() {
            "auto" => M::Auto,
            "record" => M::Record,
            "constant" => M::Constant,
            other => anyhow::bail!("--normal-stress-mode `{other}`: use auto, record or constant"),
        })
    }

    fn read(&self, path: &std::path::Path) -> Result<rsf_fit::data::Record> {
        use rsf_fit::data::{DispUnit, ReadOptions, TimeUnit};
        let opts = ReadOptions {
            time_col: self.time_col.clone(),
            lp_col: self.lp_col.clone(),
            mu_col: self.mu_col.clone(),
            shear_col: self.shear_col.clone(),
            normal_col: self.normal_col.clone(),
            normal_stress: self.normal_stress,
            disp_unit: DispUnit::parse(&self.disp_unit)
                .with_context(|| format!("--disp-unit `{}`: use um, mm or m", self.disp_unit))?,
            time_unit: TimeUnit::parse(&self.time_unit)
                .with_context(|| format!("--time-unit `{}`: use s or ms", self.time_unit))?,
            t_min: self.t_min,
            t_max: self.t_max,
            duplicate_times: match self.duplicate_times.as_str() {
                "error" => rsf_fit::data::DuplicateTimes::Error,
                "drop" => rsf_fit::data::DuplicateTimes::Drop,
                other => anyhow::bail!("--duplicate-times `{other}`: use error or drop"),
            },
            invalid: if self.drop_invalid {
                rsf_fit::data::InvalidRows::Drop
            } else {
                rsf_fit::data::InvalidRows::Error
            },
        };
        let rec = rsf_fit::data::read_record(path, &opts)?;
        if rec.dropped_duplicate_times > 0 {
            eprintln!("rsf: dropped {} rows whose time repeated the previous row's", rec.dropped_duplicate_times);
        }
        for w in &rec.warnings {
            eprintln!("rsf: {}: {w}", path.display());
        }
        Ok(rec)
    }
}

// each subcommand's arguments are built only when it runs: building all of them (about two
// hundred, with their help) took 0.1 ms of a 2.4 ms `rsf simulate`
#[derive(Subcommand)]
#[command(defer = true)]
enum Command {
    /// Diagnose a record: fit a baseline, try extensions (other law, second state variable,
    /// cut-off velocity, slip trend, stiffness), name the cause and measure the gain.
    Diagnose(Box<DiagnoseArgs>),
    /// Fit a rate-and-state model to a measured record (Levenberg-Marquardt with exact
    /// sensitivities; optional MCMC uncertainties).
    Fit(Box<FitArgs>),
    /// Fit and/or diagnose every record of a manifest or a folder, in parallel.
    #[command(long_about = BATCH_HELP)]
    Batch(Box<BatchArgs>),
    /// Detect the loading protocol (segments of constant load-point velocity) of a record.
    Segments {
        /// The record (CSV or whitespace/tab-separated text with a header).
        data: PathBuf,
        #[command(flatten)]
        read: DataArgs,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
        /// Velocity ratio below which neighbouring segments are one.
        #[arg(long, default_value_t = 1.3)]
        min_ratio: f64,
        /// Shortest segment (s); shorter pieces (servo oscillation, noise bursts) join a neighbour.
        #[arg(long, default_value_t = 0.3)]
        min_duration: f64,
    },
    /// Simulate a spring-slider protocol described in a TOML file.
    #[command(long_about = SIMULATE_HELP)]
    Simulate {
        /// Protocol file (TOML; schema below and in docs/protocol.md).
        protocol: PathBuf,
        /// Write the CSV here instead of standard output.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Also write an SVG plot of friction and slip rate against time.
        #[arg(long)]
        plot: Option<PathBuf>,
        /// Override the protocol's solver method: auto (Vern6 while non-stiff, Rodas5P where stiff), vern6, tsit5, dopri5, rodas5p or rodas4 ("explicit" = tsit5, "implicit" = rodas5p).
        #[arg(long)]
        method: Option<String>,
        /// Override the protocol's relative tolerance (solver.rtol).
        #[arg(long)]
        rtol: Option<f64>,
        /// Override the protocol's absolute tolerance (solver.atol).
        #[arg(long)]
        atol: Option<f64>,
    },
}

#[derive(clap::Args, Debug)]
struct DiagnoseArgs {
    /// The record.
    data: PathBuf,
    #[command(flatten)]
    read: DataArgs,
    /// Nominal machine stiffness k, 1/µm.
    #[arg(long)]
    stiffness: f64,
    /// Baseline evolution law: slip or aging.
    #[arg(long, default_value = "slip")]
    baseline: String,
    /// Forward-model loading: record or protocol.
    #[arg(long, default_value = "protocol")]
    loading: String,
    /// Skip the held-out test.
    #[arg(long)]
    no_heldout: bool,
    /// Seed of the null calibration's noise replicates. The diagnosis is a deterministic function
    /// of the record, the options and this seed: the same on any machine, at any load, with any
    /// number of threads.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Noise replicates of the null calibration (parametric bootstrap under the baseline); 0
    /// names a cause on ΔBIC alone.
    #[arg(long, default_value_t = rsf_fit::diagnose::NULL_REPLICATES)]
    null_replicates: usize,
    /// A cause is named only when its gain would arise by chance under the baseline with
    /// probability below this.
    #[arg(long, default_value_t = rsf_fit::diagnose::FALSE_ALARM_LEVEL)]
    false_alarm_level: f64,
    /// Threads for the independent fits (0: all cores; the result does not depend on it).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Opt-in wall-clock guard per fit, s: a fit that runs longer stops with its best point and
    /// says so (the result then depends on the machine). Off by default: fits are bounded by a
    /// count of integrator steps instead.
    #[arg(long)]
    wall_clock_guard: Option<f64>,
    /// Write the diagnosis as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write a self-contained HTML report here.
    #[arg(long)]
    report: Option<PathBuf>,
}

#[derive(clap::Args, Debug)]
struct BatchArgs {
    /// The manifest (CSV) or a folder of records (.csv, .txt, .tsv, .dat; options from the
    /// command line).
    input: PathBuf,
    /// Output folder: summary.csv, summary.svg and records/ (created when missing).
    #[arg(long)]
    out: PathBuf,
    /// Fit each record (as `rsf fit`, law --law).
    #[arg(long)]
    fit: bool,
    /// Diagnose each record (as `rsf diagnose`).
    #[arg(long)]
    diagnose: bool,
    /// Nominal machine stiffness k, 1/µm, for records whose manifest row gives none.
    #[arg(long)]
    stiffness: Option<f64>,
    /// Time column (default time_s).
    #[arg(long)]
    time_col: Option<String>,
    /// Load-point displacement column (default load_point_um).
    #[arg(long)]
    lp_col: Option<String>,
    /// Friction column (default mu).
    #[arg(long)]
    mu_col: Option<String>,
    /// Shear-stress column (friction = shear / normal stress).
    #[arg(long)]
    shear_col: Option<String>,
    /// Normal-stress column, MPa.
    #[arg(long)]
    normal_col: Option<String>,
    /// Constant normal stress, MPa.
    #[arg(long)]
    normal_stress: Option<f64>,
    /// Unit of the load-point column: um, mm or m.
    #[arg(long)]
    disp_unit: Option<String>,
    /// Unit of the time column: s or ms.
    #[arg(long)]
    time_unit: Option<String>,
    /// Evolution law of the fit: aging, slip, kato-tullis, prz, nagata (default slip).
    #[arg(long)]
    law: Option<String>,
    /// Baseline law of the diagnosis: slip or aging (default slip).
    #[arg(long)]
    baseline: Option<String>,
    /// Forward-model loading: record or protocol (default: record for --fit, protocol for
    /// --diagnose).
    #[arg(long)]
    loading: Option<String>,
    /// Fit the stiffness too.
    #[arg(long)]
    fit_stiffness: bool,
    /// Fit a slip trend g too.
    #[arg(long)]
    fit_slip_trend: bool,
    /// Drop over-range, sentinel and non-finite rows (reported) instead of refusing the record.
    #[arg(long)]
    drop_invalid: bool,
    /// Seed of the diagnoses' null calibration (default 1).
    #[arg(long)]
    seed: Option<u64>,
    /// Records run at a time (0: one per core). The results do not depend on it.
    #[arg(long, default_value_t = 0)]
    jobs: usize,
    /// Run every record again, even those whose outputs are complete and unchanged.
    #[arg(long)]
    force: bool,
}

#[derive(clap::Args, Debug)]
struct FitArgs {
    /// The record (CSV or whitespace/tab-separated text with a header).
    data: PathBuf,
    #[command(flatten)]
    read: DataArgs,
    /// Evolution law of every state variable: aging, slip, kato-tullis, prz, nagata.
    #[arg(long, default_value = "slip")]
    law: String,
    /// Laws per state, comma-separated (overrides --law and --states), e.g. slip,aging.
    #[arg(long)]
    laws: Option<String>,
    /// Number of state variables (1 to 3).
    #[arg(long, default_value_t = 1)]
    states: usize,
    /// Machine stiffness k = stiffness / normal stress, 1/µm (initial value with --fit-stiffness).
    #[arg(long)]
    stiffness: f64,
    /// Fit the stiffness too.
    #[arg(long)]
    fit_stiffness: bool,
    /// Fit a slip trend g (a friction term g·slip: gouge growth, wear, slip hardening) too.
    #[arg(long)]
    fit_slip_trend: bool,
    /// Fit the Linker–Dieterich normal-stress coupling α: `shared` (one α for all states, the
    /// default when the flag is given without a value) or `per-state`.
    #[arg(long, num_args = 0..=1, default_missing_value = "shared")]
    fit_alpha: Option<String>,
    /// Constraint NAME=VALUE or NAME-NAME=VALUE (repeatable), e.g. a-b=-0.003, dc=10, vc1=0.01.
    #[arg(long)]
    fix: Vec<String>,
    /// Initial value NAME=VALUE (repeatable), overriding the data-derived guess.
    #[arg(long)]
    initial: Vec<String>,
    /// A friction offset per segment (mu0 per segment).
    #[arg(long)]
    mu0_per_segment: bool,
    /// Fit only the first X µm of load-point travel of each segment (holds whole).
    #[arg(long)]
    window_um: Option<f64>,
    /// Sample weights: equal (each segment counts equally) or uniform.
    #[arg(long, default_value = "equal")]
    weights: String,
    /// Forward-model loading: record (measured load-point history) or protocol (detected segments).
    #[arg(long, default_value = "record")]
    loading: String,
    /// Integrator relative tolerance.
    #[arg(long, default_value_t = 1e-7)]
    rtol: f64,
    /// Fit every sample even of a large record (by default a record of more than 100,000 used
    /// samples is fitted on bin means carrying the same information: docs/fit.md).
    #[arg(long)]
    every_sample: bool,
    /// Number of starting points for LM.
    #[arg(long, default_value_t = rsf_fit::batch::FIT_STARTS)]
    starts: usize,
    /// Also refit each velocity step and each hold-and-reslide on its own (the consistency check across step sizes and hold times; the same refits as `rsf diagnose`)
    #[arg(long)]
    per_segment: bool,
    /// Run MCMC with this many samples in total (after the LM fit).
    #[arg(long)]
    mcmc: Option<usize>,
    /// MCMC chains (run in parallel).
    #[arg(long, default_value_t = 4)]
    chains: usize,
    /// Random seed (MCMC).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Segmentation: velocity ratio below which neighbouring segments are one.
    #[arg(long, default_value_t = 1.3)]
    min_ratio: f64,
    /// Use these segments instead of detecting them: a JSON array of {"t0", "t1", "v"} (as printed
    /// by `rsf segments --json`, possibly edited).
    #[arg(long)]
    segments: Option<PathBuf>,
    /// Write the result as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write an SVG of data, model and residuals here.
    #[arg(long)]
    plot: Option<PathBuf>,
}

const BATCH_HELP: &str = "Fit and/or diagnose every record of a manifest or a folder, in parallel.

The manifest is a CSV file; its columns (any order; an empty cell takes the command line's value):
  file            the record, relative to the manifest (required)
  stiffness       nominal machine stiffness k, 1/µm
  time_col, lp_col, mu_col, shear_col, normal_col, normal_stress, disp_unit, time_unit,
  t_min, t_max, law, baseline, loading, fit_stiffness, fit_slip_trend, drop_invalid, seed
                  as the options of `rsf fit` / `rsf diagnose`
  meta_...        anything else the lab records (sample, humidity): carried into the summary
Any other column is refused, so a misspelt option is never ignored.

Output (--out DIR): DIR/summary.csv (one row per record: file, status, error, conditions,
parameters with standard errors, cause, delta_bic, effect, ...), DIR/summary.svg (a, b, Dc
against load-point velocity, normal stress and hold time), DIR/records/ (per-record JSON and
HTML). A re-run skips records whose outputs are complete and whose record bytes, options and
rsf version are unchanged (--force runs all). One failing record is reported and the rest go
on; the exit status is 1 when any failed.";

const SIMULATE_HELP: &str = "Simulate a spring-slider protocol described in a TOML file.

Output CSV columns: time_s,load_point_um,mu,slip_rate_um_s,slip_um,theta_1_s[,theta_2_s,...]
[,peak_slip_rate_um_s][,normal_stress_mpa when the normal stress varies].
t = 0, load point 0 and slip 0 at the start of the first segment; samples at t = 0, dt, 2dt, ...
and at the end of the last segment (for a record: at the record's own times).

Protocol schema (units: µm, s, µm/s; k in 1/µm):

[model]
mu0 = 0.65          # steady-state friction at v0
v0 = 1.0            # reference slip rate, µm/s
a = 0.013           # direct effect
stiffness = 0.065   # k = machine stiffness / normal stress, 1/µm; inf imposes V = V_lp
eta = 0.0           # optional radiation damping, friction per µm/s (default 0)
normal_stress = 10.0 # optional σ_ref, MPa: the initial normal stress and the σ k is stated at
                    # (required when a segment changes the normal stress)
form = \"classic\"    # optional: \"classic\" mu0 + a ln(V/V0) + ... or \"regularized\" (asinh)

[[model.state]]     # one table per state variable, N >= 1; laws may differ
law = \"slip\"        # \"aging\" | \"slip\" | \"kato-tullis\" | \"prz\" | \"nagata\"
b = 0.016
dc = 2.07           # µm
vc = 1e-3           # µm/s, kato-tullis only
c = 2.0             # nagata only
alpha = 0.0         # optional Linker–Dieterich coupling: dθ/dt gains −(α θ/(b σ)) dσ/dt

[loading]
v_init = 3.0        # µm/s; the system starts in steady state at this slip rate

[[loading.segment]] # in order; v and exactly one of duration (s) / displacement (µm)
v = 0.003           # µm/s; 0 = hold (a hold needs a duration)
duration = 500.0
# normal_stress = 12.0      # MPa: step σ at this segment's start (τ continuous, θ ← θ (σ⁻/σ⁺)^(α/b))
# normal_stress_rate = 0.1  # MPa/s: ramp σ through this segment
# or, instead of segments, a measured load-point record:
# record = \"run.csv\"            # relative to the protocol file; piecewise linear
# time_column = \"time_s\"        # optional column names
# load_point_column = \"load_point_um\"
# friction_column = \"mu\"        # optional measured friction: plotted, and its misfit reported
# normal_stress_column = \"sn\"   # optional measured normal stress (MPa) driving σ(t)

[output]
dt = 0.02           # s; optional for a record (default: the record's own times)
# peak_slip_rate = true   # add the largest slip rate since the previous row (from every step)
# event_slip_rate = 1e3   # µm/s: catalogue events with V above it into OUT_events.csv

[solver]
method = \"auto\"     # \"auto\" (Vern6, switching to Rodas5P where stiff) | \"vern6\" | \"tsit5\" | \"dopri5\" | \"rodas5p\" | \"rodas4\"
rtol = 1e-9         # relative error per step in V and theta
atol = 1e-12        # absolute error in slip, µm
max_slip_rate = 1e9 # µm/s; beyond it the run stops with a blow-up error

# [initial]         # optional: start off steady state instead of at loading.v_init
# v = 0.9e-3        # µm/s
# theta = [8e6]     # s, one per state variable";

fn main() -> std::process::ExitCode {
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
fn write_stdout(text: &str) -> Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => Ok(r?),
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Fit(args) => fit::run(&args),
        Command::Diagnose(args) => fit::diagnose(&args),
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
