//! Running the spring-slider: the resolution options and one solve call shared by every figure.

use crate::PaperError;
use rsf_core::{Loading, Model, Segment};
use rsf_solvers::{Dopri5, Method, OutputTimes, Problem, Rodas4, Solution};

/// How finely the figures are computed.
#[derive(Clone, Copy, Debug)]
pub struct Resolution {
    /// The integrator and its tolerances.
    pub method: Method,
    /// Output samples per simulated run (before any resampling).
    pub samples: usize,
    /// At most this many points per curve kept for plots and CSV files.
    pub plot_points: usize,
}

impl Resolution {
    /// What the examples use: Rodas4 (L-stable: holds are stiff) at rtol 1e-10, atol 1e-13,
    /// 20 000 samples per run, 300 plotted points per curve.
    pub fn figure() -> Self {
        Self { method: Method::Rodas4(Rodas4::new(1e-10, 1e-13)), samples: 20_000, plot_points: 300 }
    }

    /// A cheaper setting for tests: Rodas4 at rtol 1e-9, 2 000 samples per run.
    pub fn quick() -> Self {
        Self { method: Method::Rodas4(Rodas4::new(1e-9, 1e-12)), samples: 2_000, plot_points: 200 }
    }

    /// [`quick`](Self::quick) with the explicit Dormand–Prince 5(4) method instead: an
    /// independent integrator to check the implicit one against.
    pub fn quick_explicit() -> Self {
        Self { method: Method::Dopri5(Dopri5::new(1e-9, 1e-12)), ..Self::quick() }
    }
}

/// Solves `model` started in steady state at `v_init` (µm/s) under the load-point `segments`,
/// with output at `times` (s, increasing, within the protocol).
pub fn run(
    model: &Model,
    v_init: f64,
    segments: Vec<Segment>,
    times: Vec<f64>,
    res: &Resolution,
) -> Result<Solution, PaperError> {
    let problem = Problem {
        model: model.clone(),
        loading: Loading::Segments(segments),
        v_init,
        initial_theta: None,
        output: OutputTimes::Times(times),
        max_slip_rate: 1e9,
        watch: Default::default(),
        normal_stress: None,
    };
    Ok(res.method.solve(&problem)?)
}
