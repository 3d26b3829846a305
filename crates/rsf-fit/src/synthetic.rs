//! Synthetic lab records for tests and demonstrations: a model run through a protocol by the
//! implicit integrator at a tight tolerance (a different path from the fitter's explicit
//! sensitivity solve), sampled like a lab record and given white or time-correlated noise.

use crate::data::Record;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use rsf_core::{Loading, Model, Segment};
use rsf_solvers::{OutputTimes, Problem, Rodas4, SolveError, solve};

/// Noise added to friction.
#[derive(Clone, Copy, Debug)]
pub struct Noise {
    /// Standard deviation.
    pub sigma: f64,
    /// Correlation time, s (0: white; else AR(1) with φ = exp(−Δt/τ)).
    pub tau: f64,
}

/// A protocol segment with its sampling interval: (v µm/s, duration s, dt s).
pub type SampledSegment = (f64, f64, f64);

/// Runs `model` from steady state at `v_init` through `protocol`, samples it at each segment's
/// interval, and adds `noise` with `seed`. The load point is exact (piecewise linear).
pub fn record(
    model: &Model,
    v_init: f64,
    protocol: &[SampledSegment],
    noise: Noise,
    seed: u64,
) -> Result<Record, SolveError> {
    let mut times = vec![0.0];
    let mut t = 0.0;
    for &(_, d, dt) in protocol {
        let n = (d / dt).round().max(1.0) as usize;
        for i in 1..=n {
            times.push(t + d * i as f64 / n as f64);
        }
        t += d;
    }
    let segs = protocol.iter().map(|&(v, d, _)| Segment::for_duration(v, d)).collect();
    let mut p = Problem::new(model.clone(), Loading::Segments(segs), v_init, 1.0);
    p.output = OutputTimes::Times(times);
    let sol = solve(&p, &Rodas4::new(1e-11, 1e-14))?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut e = 0.0;
    let mut mu = Vec::with_capacity(sol.len());
    for r in 0..sol.len() {
        let z: f64 = StandardNormal.sample(&mut rng);
        e = if noise.tau > 0.0 && r > 0 {
            let phi = (-(sol.time[r] - sol.time[r - 1]) / noise.tau).exp();
            phi * e + (1.0 - phi * phi).sqrt() * noise.sigma * z
        } else {
            noise.sigma * z
        };
        mu.push(sol.mu[r] + e);
    }
    Ok(Record {
        time: sol.time,
        load_point: sol.load_point,
        mu,
        source: format!("synthetic (seed {seed})"),
        normal_stress: vec![],
        dropped_duplicate_times: 0,
        dropped_invalid: 0,
        warnings: vec![],
    })
}

/// A lab-like protocol for diagnosis tests and studies: steps 1 → 10 → 1 → 0.1 → 1 µm/s and
/// holds of 100, 1000 and 3000 s with reslides; 10 Hz sliding, 2 Hz at 0.1 µm/s, 1–0.2 Hz in holds.
pub fn step_hold_protocol() -> Vec<SampledSegment> {
    vec![
        (1.0, 60.0, 0.1),
        (10.0, 10.0, 0.1),
        (1.0, 80.0, 0.1),
        (0.1, 300.0, 0.5),
        (1.0, 60.0, 0.1),
        (0.0, 100.0, 1.0),
        (1.0, 60.0, 0.1),
        (0.0, 1000.0, 2.0),
        (1.0, 60.0, 0.1),
        (0.0, 3000.0, 5.0),
        (1.0, 80.0, 0.1),
    ]
}
