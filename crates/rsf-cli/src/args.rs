//! The command line: the subcommands, their arguments and long help texts (clap derive), and
//! how a record's column options become the reader's options.

use anyhow::Result;
use clap::{Parser, Subcommand};
use rsf_fit::data::{DispUnit, DuplicateTimes, TimeUnit};
use rsf_fit::fit::{AlphaFit, LoadingMode, NormalStressMode, Uncertainty, Weighting};
use std::path::PathBuf;

/// clap's parser for a closed vocabulary: the type's own `FromStr`, shared with Python and the
/// manifests; its error lists the names.
fn word<T: std::str::FromStr<Err = String>>(s: &str) -> Result<T, String> {
    s.parse()
}

#[derive(Parser)]
#[command(name = "rsf", version, about = "Rate-and-state friction: simulate lab friction experiments")]
pub(crate) struct Cli {
    /// A law file (TOML: the rate as an expression, its parameters; docs/laws.md) to register
    /// before the command runs; its law is then a name for --law, --laws, protocols and
    /// manifests, and a candidate of every diagnosis. Repeat for several.
    #[arg(long = "law-file", global = true, value_name = "FILE")]
    pub(crate) law_file: Vec<PathBuf>,
    #[command(subcommand)]
    pub(crate) command: Command,
}

// How to read a measured record (a plain comment: as a doc comment, clap would apply it as the
// about text of every subcommand that flattens it, once subcommands are deferred).
#[derive(clap::Args, Clone, Debug)]
pub(crate) struct DataArgs {
    /// Time column (s unless --time-unit).
    #[arg(long, default_value = "time_s")]
    pub(crate) time_col: String,
    /// Load-point displacement column (µm unless --disp-unit).
    #[arg(long, default_value = "load_point_um")]
    pub(crate) lp_col: String,
    /// Friction column.
    #[arg(long, default_value = "mu")]
    pub(crate) mu_col: String,
    /// Shear-stress column; friction = shear / normal stress (needs --normal-stress or --normal-col).
    #[arg(long)]
    pub(crate) shear_col: Option<String>,
    /// Normal-stress column (MPa): divides --shear-col into friction; with a friction column, a
    /// varying normal stress drives the model (see --normal-stress-mode).
    #[arg(long)]
    pub(crate) normal_col: Option<String>,
    /// Whether the record's normal stress (--normal-col) drives the model: auto (when it varies
    /// by more than 2% of its median), record (always) or constant (never).
    #[arg(long, default_value = "auto", value_parser = word::<NormalStressMode>)]
    pub(crate) normal_stress_mode: NormalStressMode,
    /// Constant normal stress, same units as the shear column.
    #[arg(long)]
    pub(crate) normal_stress: Option<f64>,
    /// Unit of the load-point column: um, mm or m.
    #[arg(long, default_value = "um", value_parser = word::<DispUnit>)]
    pub(crate) disp_unit: DispUnit,
    /// Unit of the time column: s or ms.
    #[arg(long, default_value = "s", value_parser = word::<TimeUnit>)]
    pub(crate) time_unit: TimeUnit,
    /// Use only rows with time >= this (s).
    #[arg(long)]
    pub(crate) t_min: Option<f64>,
    /// Use only rows with time <= this (s).
    #[arg(long)]
    pub(crate) t_max: Option<f64>,
    /// Rows whose time repeats the previous row's: `error` (refuse the record) or `drop` (keep
    /// the first of each run, report the count).
    #[arg(long, default_value = "error", value_parser = word::<DuplicateTimes>)]
    pub(crate) duplicate_times: DuplicateTimes,
    /// Drop rows with an over-range value (|value| >= 1e30, |friction| >= 10), an instrument's
    /// no-reading value (-999999, -99999), NaN or infinity, and report the count (default: such a
    /// row is an error naming its line and column).
    #[arg(long)]
    pub(crate) drop_invalid: bool,
    /// Read a record that does not look like a friction experiment (friction outside 0.05–2 or
    /// negative, the friction and load-point columns swapped, the load point backwards or at an
    /// implausible speed) instead of refusing it; each finding is reported as a warning.
    #[arg(long)]
    pub(crate) accept_implausible: bool,
}

impl DataArgs {
    pub(crate) fn read(&self, path: &std::path::Path) -> Result<rsf_fit::data::Record> {
        use rsf_fit::data::ReadOptions;
        let opts = ReadOptions {
            time_col: self.time_col.clone(),
            lp_col: self.lp_col.clone(),
            mu_col: self.mu_col.clone(),
            shear_col: self.shear_col.clone(),
            normal_col: self.normal_col.clone(),
            normal_stress: self.normal_stress,
            disp_unit: self.disp_unit,
            time_unit: self.time_unit,
            t_min: self.t_min,
            t_max: self.t_max,
            duplicate_times: self.duplicate_times,
            invalid: if self.drop_invalid {
                rsf_fit::data::InvalidRows::Drop
            } else {
                rsf_fit::data::InvalidRows::Error
            },
            accept_implausible: self.accept_implausible,
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
pub(crate) enum Command {
    /// Diagnose a record: fit a baseline, try extensions (other law, second state variable,
    /// cut-off velocity, slip trend, stiffness), name the cause and measure the gain.
    Diagnose(Box<DiagnoseArgs>),
    /// Design the next experiment: diagnose the record, then rank velocity steps, holds and
    /// sequences of two, appended at its end, by how well they would tell the credible causes
    /// apart (docs/design.md).
    Design(Box<DesignArgs>),
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
    /// Check a law file (or a registered law by name) with the conformance kit: the rate and
    /// its derivatives are finite and exact, the steady state is an attracting root, time and
    /// length units rescale, the V_i·t identity holds for a law without a velocity scale, the
    /// integrators agree, and each parameter can be set and has an exact derivative
    /// (docs/laws.md). A parameter whose unit is µm/s or µm is rescaled with the units.
    CheckLaw {
        /// The law file (TOML), or the name of a law already registered.
        law: String,
        /// Random cases per property (256 when not given).
        #[arg(long)]
        cases: Option<u32>,
        /// Also check the claim that the steady state is θ = s·Dc/V (s: the law's theta_scale).
        #[arg(long)]
        steady_state_dc_over_v: bool,
    },
    /// List the laws rsf knows — built in and registered by --law-file — with their
    /// parameters' units, ranges and starts.
    Laws,
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
pub(crate) struct DiagnoseArgs {
    #[command(flatten)]
    pub(crate) d: DiagnosisArgs,
    /// Write the diagnosis as JSON here.
    #[arg(long)]
    pub(crate) json: Option<PathBuf>,
    /// Write a self-contained HTML report here.
    #[arg(long)]
    pub(crate) report: Option<PathBuf>,
}

// The diagnosis's own options, shared by `rsf diagnose` and `rsf design` (a plain comment: a
// doc comment would become the about text of both)
#[derive(clap::Args, Debug)]
pub(crate) struct DiagnosisArgs {
    /// The record.
    pub(crate) data: PathBuf,
    #[command(flatten)]
    pub(crate) read: DataArgs,
    /// Nominal machine stiffness k, 1/µm.
    #[arg(long)]
    pub(crate) stiffness: f64,
    /// Relative uncertainty (one standard deviation) of the nominal stiffness, from your
    /// machine's calibration: a fitted k within two of them of the nominal is not named as a
    /// cause.
    #[arg(long, default_value_t = rsf_diagnose::STIFFNESS_UNCERTAINTY)]
    pub(crate) stiffness_uncertainty: f64,
    /// Baseline evolution law: any law `rsf laws` lists (slip, aging, a law file's law…).
    #[arg(long, default_value = "slip")]
    pub(crate) baseline: String,
    /// Forward-model loading: record or protocol.
    #[arg(long, default_value = "protocol", value_parser = word::<LoadingMode>)]
    pub(crate) loading: LoadingMode,
    /// Skip the held-out test.
    #[arg(long)]
    pub(crate) no_heldout: bool,
    /// Print each stage's and job's wall time on stderr (profiling; the result is the same).
    #[arg(long)]
    pub(crate) stage_times: bool,
    /// Seed of every random draw (the null calibration's noise replicates; `rsf design`'s
    /// parameter draws). The result is a deterministic function of the record, the options and
    /// this seed: the same on any machine, at any load, with any number of threads.
    #[arg(long, default_value_t = 1)]
    pub(crate) seed: u64,
    /// Noise replicates of the null calibration (parametric bootstrap under the baseline),
    /// drawn on to four times as many where they leave the verdict open; 0 names a cause on
    /// ΔBIC alone.
    #[arg(long, default_value_t = rsf_diagnose::NULL_REPLICATES)]
    pub(crate) null_replicates: usize,
    /// A cause is named only when its gain would arise by chance under the baseline with
    /// probability below this, also at the 95 % upper limit of the null's scale.
    #[arg(long, default_value_t = rsf_diagnose::FALSE_ALARM_LEVEL)]
    pub(crate) false_alarm_level: f64,
    /// Threads for the independent fits (0: all cores; the result does not depend on it).
    #[arg(long, default_value_t = 0)]
    pub(crate) threads: usize,
    /// Opt-in wall-clock guard per fit, s: a fit that runs longer stops with its best point and
    /// says so (the result then depends on the machine). Off by default: fits are bounded by a
    /// count of integrator steps instead.
    #[arg(long)]
    pub(crate) wall_clock_guard: Option<f64>,
}

#[derive(clap::Args, Debug)]
pub(crate) struct DesignArgs {
    #[command(flatten)]
    pub(crate) d: DiagnosisArgs,
    /// Load-point velocities the machine can drive, µm/s: LOW,HIGH.
    #[arg(long, default_value = "0.001,300")]
    pub(crate) v_range: String,
    /// Longest hold, s.
    #[arg(long, default_value_t = 1e4)]
    pub(crate) max_hold: f64,
    /// Longest proposal, s of machine time.
    #[arg(long, default_value_t = 14400.0)]
    pub(crate) max_time: f64,
    /// Most load-point displacement of a proposal, µm.
    #[arg(long, default_value_t = 1000.0)]
    pub(crate) max_slip: f64,
    /// Largest normal-stress change the machine can make, as a fraction of the record's σ
    /// (0.2: ±20 %). When positive and the record's σ is constant, σ changes are proposed and
    /// the best model with Linker–Dieterich α (from the lab range) is a credible model.
    #[arg(long, default_value_t = 0.0)]
    pub(crate) max_sigma_change: f64,
    /// Models within this ΔBIC of the best are credible (besides those that fit at least as
    /// well as the baseline).
    #[arg(long, default_value_t = rsf_design::CREDIBLE_DBIC)]
    pub(crate) credible: f64,
    /// Draws from each model's parameter covariance (0: the fitted parameters only).
    #[arg(long, default_value_t = rsf_design::DRAWS)]
    pub(crate) draws: usize,
    /// Single steps and holds only, no sequences of two.
    #[arg(long)]
    pub(crate) no_sequences: bool,
    /// Proposals to print.
    #[arg(long, default_value_t = 5)]
    pub(crate) top: usize,
    /// Write the ranking, the models and the best proposal's predictions as JSON here.
    #[arg(long)]
    pub(crate) json: Option<PathBuf>,
    /// Write the best proposal as a TOML protocol for `rsf simulate` here.
    #[arg(long)]
    pub(crate) protocol: Option<PathBuf>,
    /// Write the figure (the models' predictions through the best proposal) as SVG here.
    #[arg(long)]
    pub(crate) plot: Option<PathBuf>,
    /// Write a self-contained HTML page (summary, figure, ranking) here.
    #[arg(long)]
    pub(crate) report: Option<PathBuf>,
    /// Also write the diagnosis it starts from as JSON here.
    #[arg(long, conflicts_with = "from")]
    pub(crate) diagnosis_json: Option<PathBuf>,
    /// Design from this diagnosis (`rsf diagnose --json` of the same record, with the same
    /// column, baseline and loading options) instead of diagnosing again: its models are
    /// refitted from their reported parameters, one warm start each.
    #[arg(long, value_name = "DIAGNOSIS_JSON")]
    pub(crate) from: Option<PathBuf>,
}

#[derive(clap::Args, Debug)]
pub(crate) struct BatchArgs {
    /// The manifest (CSV) or a folder of records (.csv, .txt, .tsv, .dat; options from the
    /// command line).
    pub(crate) input: PathBuf,
    /// Output folder: summary.csv, summary.parquet, summary.svg and records/ (created when missing).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Fit each record (as `rsf fit`, law --law).
    #[arg(long)]
    pub(crate) fit: bool,
    /// Diagnose each record (as `rsf diagnose`).
    #[arg(long)]
    pub(crate) diagnose: bool,
    /// Read records outside the manifest's folder too (an absolute path, `../`, a link out);
    /// refused by default.
    #[arg(long)]
    pub(crate) allow_outside: bool,
    /// Nominal machine stiffness k, 1/µm, for records whose manifest row gives none.
    #[arg(long)]
    pub(crate) stiffness: Option<f64>,
    /// Time column (default time_s).
    #[arg(long)]
    pub(crate) time_col: Option<String>,
    /// Load-point displacement column (default load_point_um).
    #[arg(long)]
    pub(crate) lp_col: Option<String>,
    /// Friction column (default mu).
    #[arg(long)]
    pub(crate) mu_col: Option<String>,
    /// Shear-stress column (friction = shear / normal stress).
    #[arg(long)]
    pub(crate) shear_col: Option<String>,
    /// Normal-stress column, MPa.
    #[arg(long)]
    pub(crate) normal_col: Option<String>,
    /// Constant normal stress, MPa.
    #[arg(long)]
    pub(crate) normal_stress: Option<f64>,
    /// Unit of the load-point column: um, mm or m.
    #[arg(long, value_parser = word::<DispUnit>)]
    pub(crate) disp_unit: Option<DispUnit>,
    /// Unit of the time column: s or ms.
    #[arg(long, value_parser = word::<TimeUnit>)]
    pub(crate) time_unit: Option<TimeUnit>,
    /// Evolution law of the fit: aging, slip, kato-tullis, prz, nagata, aging-slip or a law
    /// registered by --law-file (default slip).
    #[arg(long)]
    pub(crate) law: Option<String>,
    /// Baseline law of the diagnosis: any law `rsf laws` lists (default slip).
    #[arg(long)]
    pub(crate) baseline: Option<String>,
    /// Forward-model loading: record or protocol (default: record for --fit, protocol for
    /// --diagnose).
    #[arg(long, value_parser = word::<LoadingMode>)]
    pub(crate) loading: Option<LoadingMode>,
    /// Fit the stiffness too.
    #[arg(long)]
    pub(crate) fit_stiffness: bool,
    /// Fit a slip trend g too.
    #[arg(long)]
    pub(crate) fit_slip_trend: bool,
    /// Fit a rate-dependent direct effect a₁ too (--fit: ∂f/∂ln V = a + a_slope·ln(V/V0)).
    #[arg(long)]
    pub(crate) fit_a_slope: bool,
    /// Drop over-range, sentinel and non-finite rows (reported) instead of refusing the record.
    #[arg(long)]
    pub(crate) drop_invalid: bool,
    /// Read records that do not look like friction experiments (friction outside 0.05–2 or
    /// negative, columns swapped, the load point backwards or at an implausible speed) instead
    /// of refusing them; each finding is reported as a warning.
    #[arg(long)]
    pub(crate) accept_implausible: bool,
    /// Seed of the diagnoses' null calibration (default 1).
    #[arg(long)]
    pub(crate) seed: Option<u64>,
    /// Records run at a time (0: one per core). The results do not depend on it.
    #[arg(long, default_value_t = 0)]
    pub(crate) jobs: usize,
    /// Run every record again, even those whose outputs are complete and unchanged.
    #[arg(long)]
    pub(crate) force: bool,
}

#[derive(clap::Args, Debug)]
pub(crate) struct FitArgs {
    /// The record (CSV or whitespace/tab-separated text with a header).
    pub(crate) data: PathBuf,
    #[command(flatten)]
    pub(crate) read: DataArgs,
    /// Evolution law of every state variable: aging, slip, kato-tullis, prz, nagata,
    /// aging-slip or a law registered by --law-file.
    #[arg(long, default_value = "slip")]
    pub(crate) law: String,
    /// Laws per state, comma-separated (overrides --law and --states), e.g. slip,aging.
    #[arg(long)]
    pub(crate) laws: Option<String>,
    /// Number of state variables (1 to 3).
    #[arg(long, default_value_t = 1)]
    pub(crate) states: usize,
    /// Machine stiffness k = stiffness / normal stress, 1/µm (initial value with --fit-stiffness).
    #[arg(long)]
    pub(crate) stiffness: f64,
    /// Fit the stiffness too.
    #[arg(long)]
    pub(crate) fit_stiffness: bool,
    /// Fit a slip trend g (a friction term g·slip: gouge growth, wear, slip hardening) too.
    #[arg(long)]
    pub(crate) fit_slip_trend: bool,
    /// Fit a rate-dependent direct effect too: ∂f/∂ln V = a + a_slope·ln(V/V0) (the parameter
    /// `a_slope`, a₁; a steady state bent in ln V, up- and down-steps that jump unlike).
    #[arg(long)]
    pub(crate) fit_a_slope: bool,
    /// Fit the Linker–Dieterich normal-stress coupling α: `shared` (one α for all states, the
    /// default when the flag is given without a value) or `per-state`.
    #[arg(long, num_args = 0..=1, default_missing_value = "shared", value_parser = word::<AlphaFit>)]
    pub(crate) fit_alpha: Option<AlphaFit>,
    /// Constraint NAME=VALUE or NAME-NAME=VALUE (repeatable), e.g. a-b=-0.003, dc=10, vc1=0.01.
    #[arg(long, value_parser = word::<rsf_fit::fit::Constraint>)]
    pub(crate) fix: Vec<rsf_fit::fit::Constraint>,
    /// Initial value NAME=VALUE (repeatable), overriding the data-derived guess.
    #[arg(long)]
    pub(crate) initial: Vec<String>,
    /// A friction offset per segment (mu0 per segment).
    #[arg(long)]
    pub(crate) mu0_per_segment: bool,
    /// Fit only the first X µm of load-point travel of each segment (holds whole).
    #[arg(long)]
    pub(crate) window_um: Option<f64>,
    /// Sample weights: equal (each segment counts equally) or uniform.
    #[arg(long, default_value = "equal", value_parser = word::<Weighting>)]
    pub(crate) weights: Weighting,
    /// Forward-model loading: record (measured load-point history) or protocol (detected segments).
    #[arg(long, default_value = "record", value_parser = word::<LoadingMode>)]
    pub(crate) loading: LoadingMode,
    /// Standard errors and intervals: noise-model (under the white, AR(1) and drift noise fitted
    /// to the residuals) or white (independent residuals).
    #[arg(long, default_value = "noise-model", value_parser = word::<Uncertainty>)]
    pub(crate) uncertainty: Uncertainty,
    /// Integrator relative tolerance.
    #[arg(long, default_value_t = 1e-7)]
    pub(crate) rtol: f64,
    /// Fit every sample even of a large record (by default a record of more than 100,000 used
    /// samples is fitted on bin means carrying the same information: docs/fit.md).
    #[arg(long)]
    pub(crate) every_sample: bool,
    /// Number of starting points for LM.
    #[arg(long, default_value_t = rsf_batch::FIT_STARTS)]
    pub(crate) starts: usize,
    /// LM iterations per start; a fit whose best start reaches the limit is reported as not
    /// converged (exit status 1, outputs written with "converged": false).
    #[arg(long, default_value_t = 100)]
    pub(crate) max_iter: usize,
    /// Also refit each velocity step and each hold-and-reslide on its own (the consistency check across step sizes and hold times; the same refits as `rsf diagnose`)
    #[arg(long)]
    pub(crate) per_segment: bool,
    /// Run MCMC with this many samples in total (after the LM fit).
    #[arg(long)]
    pub(crate) mcmc: Option<usize>,
    /// MCMC chains (run in parallel).
    #[arg(long, default_value_t = 4)]
    pub(crate) chains: usize,
    /// Threads for the starts after the first (0: all cores; the result does not depend on it).
    #[arg(long, default_value_t = 0)]
    pub(crate) threads: usize,
    /// Random seed (MCMC).
    #[arg(long, default_value_t = 1)]
    pub(crate) seed: u64,
    /// Segmentation: velocity ratio below which neighbouring segments are one.
    #[arg(long, default_value_t = 1.3)]
    pub(crate) min_ratio: f64,
    /// Use these segments instead of detecting them: a JSON array of {"t0", "t1", "v"} (as printed
    /// by `rsf segments --json`, possibly edited).
    #[arg(long)]
    pub(crate) segments: Option<PathBuf>,
    /// Write the result as JSON here.
    #[arg(long)]
    pub(crate) json: Option<PathBuf>,
    /// Write an SVG of data, model and residuals here.
    #[arg(long)]
    pub(crate) plot: Option<PathBuf>,
}

const BATCH_HELP: &str = "Fit and/or diagnose every record of a manifest or a folder, in parallel.

The manifest is a CSV file; its columns (any order; an empty cell takes the command line's value):
  file            the record, relative to the manifest (required)
  stiffness       nominal machine stiffness k, 1/µm
  time_col, lp_col, mu_col, shear_col, normal_col, normal_stress, disp_unit, time_unit,
  t_min, t_max, law, baseline, loading, fit_stiffness, fit_slip_trend, fit_a_slope,
  drop_invalid, accept_implausible, seed
                  as the options of `rsf fit` / `rsf diagnose`
  meta_...        anything else the lab records (sample, humidity): carried into the summary
Any other column is refused, so a misspelt option is never ignored.

Output (--out DIR): DIR/summary.csv (one row per record: file, status, error, conditions,
parameters with standard errors, cause, delta_bic, effect, ...), DIR/summary.parquet (the
same table with typed columns), DIR/summary.svg (a, b, Dc
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
