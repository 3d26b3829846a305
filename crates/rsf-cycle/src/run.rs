//! One BP1-QD simulation: integrate the fault, watch events and record stations after every
//! accepted step, and write the catalogue and station files.

use crate::events::Catalogue;
use crate::fault::{Fault, shear_stress, slip_index};
use crate::params::Bp1;
use crate::stations::{Stations, at_depth};
use rsf_solvers::{Flow, LargeTsit5, StepStats};
use std::path::PathBuf;
use std::time::Instant;

/// Where a simulation stands, for a progress observer ([`RunOptions::progress`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CycleProgress {
    /// Simulated time, years.
    pub years: f64,
    /// The largest slip rate on the fault now, m/s.
    pub max_slip_rate: f64,
    /// Events begun so far.
    pub events: usize,
    /// Accepted steps so far.
    pub steps: u64,
}

/// A progress observer: called at every new event and every 100 simulated years. The library
/// prints nothing; the caller decides (the `bp1qd` example prints a line on stderr).
pub type ProgressFn = std::sync::Arc<dyn Fn(&CycleProgress) + Send + Sync>;

/// What to simulate.
#[derive(Clone)]
pub struct RunOptions {
    /// Cells over [0, W_f] (512: 78 m, the resolution of the anchors).
    pub cells: usize,
    /// Simulated time, years.
    pub years: f64,
    /// Relative tolerance on ln V and ln θ (absolute on their logs) and on slip.
    pub rtol: f64,
    /// Absolute tolerance on slip, m.
    pub atol: f64,
    /// Where to write `events.csv` and the station files (nothing written when `None`).
    pub out: Option<PathBuf>,
    /// Stop after this many events (the CI check); `None` runs to `years`.
    pub max_events: Option<usize>,
    /// Called with the progress at every new event and every 100 simulated years.
    pub progress: Option<ProgressFn>,
}

impl std::fmt::Debug for RunOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunOptions")
            .field("cells", &self.cells)
            .field("years", &self.years)
            .field("rtol", &self.rtol)
            .field("atol", &self.atol)
            .field("out", &self.out)
            .field("max_events", &self.max_events)
            .field("progress", &self.progress.as_ref().map(|_| "observer"))
            .finish()
    }
}

impl Default for RunOptions {
    fn default() -> Self {
        Self { cells: 512, years: 3000.0, rtol: 1e-7, atol: 1e-6, out: None, max_events: None, progress: None }
    }
}

/// What a simulation returns.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// The event catalogue.
    pub catalogue: Catalogue,
    /// Integrator work.
    pub stats: StepStats,
    /// Time reached, s.
    pub t_end: f64,
    /// Wall time of the integration, s (reported, never used in a decision).
    pub wall_s: f64,
}

/// Runs BP1-QD with the benchmark's parameters.
pub fn run(opts: &RunOptions) -> Result<RunResult, String> {
    run_with(Bp1::default(), opts)
}

/// Runs the benchmark geometry with parameters `p`.
pub fn run_with(p: Bp1, opts: &RunOptions) -> Result<RunResult, String> {
    if opts.cells < 4 || !(opts.years > 0.0) || !(opts.rtol > 0.0) {
        return Err(format!(
            "need at least 4 cells, positive years and rtol (got {}, {}, {})",
            opts.cells, opts.years, opts.rtol
        ));
    }
    let mut fault = Fault::new(p, opts.cells);
    let n = fault.cells();
    let dz = fault.dz;
    let mut y = fault.initial_state();
    let mut cat = Catalogue::default();
    let mut st = Stations::new();
    let mut stats = StepStats::default();
    let alg = LargeTsit5::new(opts.rtol, opts.atol);
    let t1 = opts.years * crate::YEAR;
    let clock = Instant::now();
    let mut next_report = 0.0;
    // what the observer needs of the fault while the integrator holds it for the right-hand side
    let (p_obs, a_obs) = (fault.p.clone(), fault.a.clone());
    let slip = |y: &[f64], i: usize| y[slip_index(&p_obs, n, i)];
    let depth = |i: usize| (i as f64 + 0.5) * dz;
    let t_end = alg
        .integrate(
            &mut fault,
            0.0,
            &mut y,
            t1,
            0.0,
            |t, y, s| {
                let (mut imax, mut xmax) = (0, f64::NEG_INFINITY);
                for (i, &x) in y[..n].iter().enumerate() {
                    if x > xmax {
                        (imax, xmax) = (i, x);
                    }
                }
                let surface = at_depth(0.0, dz, n, |i| slip(y, i));
                let before = cat.events.len();
                cat.observe(t, xmax, depth(imax), surface);
                if st.due(t, cat.seismic()) {
                    st.record(t, |z| {
                        (
                            at_depth(z, dz, n, |i| slip(y, i)),
                            at_depth(z, dz, n, |i| y[i]),
                            at_depth(z, dz, n, |i| shear_stress(&p_obs, &a_obs, y, i)),
                            at_depth(z, dz, n, |i| y[n + i]),
                        )
                    });
                }
                if let Some(report) = opts.progress.as_ref().filter(|_| cat.events.len() > before || t >= next_report) {
                    report(&CycleProgress {
                        years: t / crate::YEAR,
                        max_slip_rate: xmax.exp(),
                        events: cat.events.len(),
                        steps: s.accepted,
                    });
                    next_report = t + 100.0 * crate::YEAR;
                }
                let done =
                    opts.max_events.is_some_and(|m| cat.events.iter().filter(|e| e.end_s.is_some()).count() >= m);
                if done { Flow::Stop } else { Flow::Continue }
            },
            &mut stats,
        )
        .map_err(|e| e.to_string())?;
    let wall_s = clock.elapsed().as_secs_f64();
    if let Some(dir) = &opts.out {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let f = std::fs::File::create(dir.join("events.csv")).map_err(|e| e.to_string())?;
        cat.write_csv(std::io::BufWriter::new(f)).map_err(|e| e.to_string())?;
        let header =
            format!("SEAS BP1-QD by rsf-cycle: {n} cells of {dz:.1} m, Tsit5 (max norm) at rtol {:e}", opts.rtol);
        st.write(dir, &header).map_err(|e| e.to_string())?;
    }
    Ok(RunResult { catalogue: cat, stats, t_end, wall_s })
}
