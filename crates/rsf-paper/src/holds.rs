//! Holds (load point stopped, V_lp = 0, finite stiffness): the paper's Fig. 3, the flattening
//! of Aging-law relaxation, and the slip rate reached at the end of a long hold.
//!
//! During a hold the spring unloads as the slider creeps: dμ/dt = −k V (Eq. 3 with V_lp = 0),
//! so the relaxation rate per e-fold of time, `−dμ/d ln t = k V t`, is read exactly from the
//! slip rate without differentiating friction numerically.
//!
//! For laws whose state evolution depends on V and θ only through `Vθ/Dc` (Aging, Slip), the
//! non-dimensional form (Eqs. 9–12, `rsf_core::nondim`) has V_i only in `T = V_i t/Dc`: a hold
//! from any V_i traces the same `Δμ = μ − μ_ss(V_i)` against `V_i t`.

use crate::PaperError;
use crate::numerics::{interp, log_grid, pick, thin_indices};
use crate::params::{AGING_STEPS, AGING_STEPS_FIXED, LawParams, SLIP_HOLDS, SLIP_STEPS};
use crate::sim::{Resolution, run};
use crate::steps::V_HIGH;
use rsf_core::Segment;
use rsf_solvers::Solution;
use serde::Serialize;

/// Smallest `V_i t` sampled in a hold, µm (1 Å of load-point-equivalent travel).
const VI_T_MIN: f64 = 1e-4;

/// Samples per decade of time for a resolution.
fn per_decade(res: &Resolution) -> usize {
    (res.samples / 40).clamp(10, 250)
}

/// The values `V_i t = 10^(−4 + j/n)` µm (j = 0, 1, …) below `max`, preceded by 0 and followed
/// by `max`. The grid depends on `n` only, so holds from different V_i are sampled at exactly
/// the same `V_i t` (bit for bit) over their common range.
fn vi_t_grid(max: f64, n: usize) -> Vec<f64> {
    let mut g = vec![0.0];
    g.extend((0..).map(|j| VI_T_MIN * 10f64.powf(j as f64 / n as f64)).take_while(|&x| x < max * (1.0 - 1e-12)));
    g.push(max);
    g
}

/// A hold of `duration` s from steady sliding at `v_i` µm/s, sampled at `V_i t` on
/// [`vi_t_grid`] (times `t = V_i t / V_i`).
fn hold_run(
    p: &LawParams,
    v_i: f64,
    v_lp: f64,
    duration: f64,
    res: &Resolution,
) -> Result<(Vec<f64>, Solution), PaperError> {
    let g = vi_t_grid(v_i * duration, per_decade(res));
    let mut times: Vec<f64> = g.iter().map(|x| x / v_i).collect();
    *times.last_mut().expect("a non-empty grid") = duration;
    Ok((g, run(&p.model(), v_i, vec![Segment::for_duration(v_lp, duration)], times, res)?))
}

/// One hold (or step) of Fig. 3 against `V_i t`.
#[derive(Clone, Debug, Serialize)]
pub struct HoldCurve {
    /// The parameters.
    pub params: LawParams,
    /// Slip rate before the hold, µm/s.
    pub v_i: f64,
    /// Load-point rate: 0 for a hold, V_f for a step decrease, µm/s.
    pub v_lp: f64,
    /// `V_i t`, µm.
    pub vi_t: Vec<f64>,
    /// Δμ = μ − μ_ss(V_i).
    pub delta_mu: Vec<f64>,
    /// Slip rate V, µm/s.
    pub slip_rate: Vec<f64>,
}

impl HoldCurve {
    fn new(p: &LawParams, v_i: f64, v_lp: f64, g: Vec<f64>, sol: &Solution) -> Result<Self, PaperError> {
        let mu_i = p.model().steady_state_friction(v_i)?;
        Ok(Self {
            params: *p,
            v_i,
            v_lp,
            vi_t: g,
            delta_mu: sol.mu.iter().map(|m| m - mu_i).collect(),
            slip_rate: sol.slip_rate.clone(),
        })
    }

    /// At most `n` samples, evenly spread over the (logarithmic) grid.
    fn thinned(self, n: usize) -> Self {
        let idx = thin_indices(self.vi_t.len(), n);
        Self {
            vi_t: pick(&self.vi_t, &idx),
            delta_mu: pick(&self.delta_mu, &idx),
            slip_rate: pick(&self.slip_rate, &idx),
            ..self
        }
    }
}

/// Fig. 3: holds from three V_i, and step decreases, against `V_i t`.
#[derive(Clone, Debug, Serialize)]
pub struct Fig3 {
    /// Hold duration, s.
    pub hold_duration: f64,
    /// Holds: for each law, V_i = 1, 0.32, 0.032 µm/s.
    pub holds: Vec<HoldCurve>,
    /// Per law (same order as the laws of `holds`): the largest |Δμ| difference between the
    /// holds from different V_i at the same `V_i t`, over their common range.
    pub collapse: Vec<(LawParams, f64)>,
    /// Slip law: the hold from [`V_HIGH`] and step decreases from it by 1, 2 and 3 orders of
    /// magnitude, first the hold.
    pub steps: Vec<HoldCurve>,
}

/// Initial slip rates of the Fig. 3 holds, µm/s (those of Table 1's hold fits).
pub const HOLD_VI: [f64; 3] = [1.0, 0.32, 0.032];
/// Duration of the Fig. 3 holds, s.
pub const FIG3_HOLD: f64 = 3000.0;

/// Fig. 3A/B: 3000 s holds from V_i = 1, 0.32 and 0.032 µm/s for the step-fitted Slip and
/// Aging laws, Δμ = μ − μ_ss(V_i) against `V_i t` (they collapse onto one curve per law), and
/// step decreases from 3 µm/s to 3·10^−1, 3·10^−2, 3·10^−3 µm/s (Slip law), which follow the
/// hold from 3 µm/s while V ≫ V_f.
///
/// Run by `cargo run --release -p rsf-paper --example fig3_holds`.
pub fn fig3_holds(res: &Resolution) -> Result<Fig3, PaperError> {
    let mut holds = Vec::new();
    let mut collapse = Vec::new();
    for p in [SLIP_STEPS, AGING_STEPS] {
        let curves = HOLD_VI
            .iter()
            .map(|&v_i| {
                let (g, sol) = hold_run(&p, v_i, 0.0, FIG3_HOLD, res)?;
                HoldCurve::new(&p, v_i, 0.0, g, &sol)
            })
            .collect::<Result<Vec<_>, PaperError>>()?;
        // the grids coincide on their common range (vi_t_grid): compare at equal V_i t
        let mut worst = 0f64;
        for (i, c) in curves.iter().enumerate() {
            for d in &curves[i + 1..] {
                for k in (0..c.vi_t.len().min(d.vi_t.len())).filter(|&k| c.vi_t[k] == d.vi_t[k]) {
                    worst = worst.max((c.delta_mu[k] - d.delta_mu[k]).abs());
                }
            }
        }
        collapse.push((p, worst));
        holds.extend(curves.into_iter().map(|c| c.thinned(res.plot_points)));
    }
    let mut steps = Vec::new();
    for v_lp in [0.0, 0.3, 0.03, 0.003] {
        let (g, sol) = hold_run(&SLIP_STEPS, V_HIGH, v_lp, FIG3_HOLD, res)?;
        steps.push(HoldCurve::new(&SLIP_STEPS, V_HIGH, v_lp, g, &sol)?.thinned(res.plot_points));
    }
    Ok(Fig3 { hold_duration: FIG3_HOLD, holds, collapse, steps })
}

/// Relaxation during one long hold, against `T = V_i t / Dc`.
#[derive(Clone, Debug, Serialize)]
pub struct Relaxation {
    /// The parameters.
    pub params: LawParams,
    /// `V_i t / Dc`.
    pub t_nd: Vec<f64>,
    /// Δμ = μ − μ_ss(V_i).
    pub delta_mu: Vec<f64>,
    /// Relaxation rate per e-fold of time, `−dμ/d ln t = k V t`.
    pub rate: Vec<f64>,
    /// `(T, −dμ/d ln t)` at T = 0.5, 2, 20, 200.
    pub rate_at: Vec<(f64, f64)>,
    /// `rate(T = 20) / rate(T = 0.5)`: about 1 for log-linear relaxation.
    pub flattening_ratio: f64,
}

/// `aging_hold_flattening`: a 10⁴ s hold from V_i = 1 µm/s.
#[derive(Clone, Debug, Serialize)]
pub struct Flattening {
    /// Slip rate before the hold, µm/s.
    pub v_i: f64,
    /// Hold duration, s.
    pub hold_duration: f64,
    /// Aging law with a − b = −0.003 (a = 0.014, b = 0.017, Dc = 10.05 µm), the Slip law with
    /// the same a, b and Dc, and the Slip law fitted to the holds from 1 µm/s.
    pub laws: Vec<Relaxation>,
}

/// Values of `T = V_i t / Dc` at which relaxation rates are reported.
pub const FLATTENING_T: [f64; 4] = [0.5, 2.0, 20.0, 200.0];

/// Relaxation rate `−dμ/d ln t = k V t` during a 10⁴ s hold from V_i = 1 µm/s against
/// `T = V_i t/Dc` for the Aging law with a − b = −0.003 and Dc = 10.05 µm, the Slip law with
/// the same parameters and the hold-fitted Slip law. Aging relaxation flattens once T exceeds
/// a few (θ then grows like elapsed time and heals the contact as fast as the slider creeps);
/// Slip-law relaxation stays close to log-linear.
///
/// Run by `cargo run --release -p rsf-paper --example aging_hold_flattening`.
pub fn aging_hold_flattening(res: &Resolution) -> Result<Flattening, PaperError> {
    let (v_i, duration) = (1.0, 1e4);
    let slip_same = LawParams { law: "slip", ..AGING_STEPS_FIXED };
    let mut laws = Vec::new();
    for p in [AGING_STEPS_FIXED, slip_same, SLIP_HOLDS[2].1] {
        let (g, sol) = hold_run(&p, v_i, 0.0, duration, res)?;
        let mu_i = p.model().steady_state_friction(v_i)?;
        let k = p.model().stiffness;
        let t_nd: Vec<f64> = g.iter().map(|x| x / p.dc).collect();
        let rate: Vec<f64> = sol.time.iter().zip(&sol.slip_rate).map(|(t, v)| k * v * t).collect();
        // interpolate in ln T (the grid is logarithmic); skip the t = 0 sample
        let ln_t: Vec<f64> = t_nd[1..].iter().map(|x| x.ln()).collect();
        let rate_at: Vec<(f64, f64)> = FLATTENING_T.iter().map(|&x| (x, interp(&ln_t, &rate[1..], x.ln()))).collect();
        let idx = thin_indices(g.len(), res.plot_points);
        let delta_mu: Vec<f64> = sol.mu.iter().map(|m| m - mu_i).collect();
        laws.push(Relaxation {
            params: p,
            flattening_ratio: rate_at[2].1 / rate_at[0].1,
            rate_at,
            t_nd: pick(&t_nd, &idx),
            delta_mu: pick(&delta_mu, &idx),
            rate: pick(&rate, &idx),
        });
    }
    Ok(Flattening { v_i, hold_duration: duration, laws })
}

/// The slip rate during one long hold.
#[derive(Clone, Debug, Serialize)]
pub struct HoldSlipRate {
    /// The parameters.
    pub params: LawParams,
    /// Time since the hold began, s (log-spaced, t > 0).
    pub time: Vec<f64>,
    /// Slip rate, µm/s.
    pub slip_rate: Vec<f64>,
    /// Slip rate at the end of the hold, µm/s.
    pub v_end: f64,
    /// The frozen-state bound `a / (k t + a/V_i)` at the end of the hold, µm/s: the exact slip
    /// rate if state did not evolve, and an upper bound whenever state grows during the hold
    /// (Slip and Aging laws below steady state).
    pub v_frozen_state: f64,
    /// `(a − b)/(k t)` at the end, µm/s: the Aging law's asymptote for a > b (θ ≈ t, friction
    /// then decays as −(a−b) ln t); `None` when a ≤ b or the law is not Aging.
    pub v_aging_asymptote: Option<f64>,
}

/// `hold_slip_rate`: 10⁴ s holds from V_i = 0.032 µm/s.
#[derive(Clone, Debug, Serialize)]
pub struct HoldSlipRates {
    /// Slip rate before the hold, µm/s.
    pub v_i: f64,
    /// Hold duration, s.
    pub hold_duration: f64,
    /// The slip rate the experiments reach at the end of such a hold, µm/s (about 0.02 nm/s).
    pub lab_v_end: f64,
    /// Slip law fitted to the holds from 0.032 µm/s, step-fitted Aging law, Aging law with
    /// a − b = −0.003.
    pub laws: Vec<HoldSlipRate>,
}

/// Slip rate at the end of a 10⁴ s hold from V_i = 0.032 µm/s (the lab reaches about
/// 2·10⁻⁵ µm/s) for the hold-fitted Slip law and the two step-fitted Aging laws, with the
/// slip rate against time through the hold.
///
/// Run by `cargo run --release -p rsf-paper --example hold_slip_rate`.
pub fn hold_slip_rate(res: &Resolution) -> Result<HoldSlipRates, PaperError> {
    let (v_i, duration) = (SLIP_HOLDS[0].0, 1e4);
    let mut laws = Vec::new();
    for p in [SLIP_HOLDS[0].1, AGING_STEPS, AGING_STEPS_FIXED] {
        let times = log_grid(1e-3, duration, per_decade(res) * 7);
        let sol = run(&p.model(), v_i, vec![Segment::for_duration(0.0, duration)], times, res)?;
        let idx = thin_indices(sol.len(), res.plot_points);
        let v_end = *sol.slip_rate.last().expect("non-empty solution");
        let k = p.model().stiffness;
        laws.push(HoldSlipRate {
            params: p,
            time: pick(&sol.time, &idx),
            slip_rate: pick(&sol.slip_rate, &idx),
            v_end,
            v_frozen_state: p.a / (k * duration + p.a / v_i),
            v_aging_asymptote: (p.law == "aging" && p.a > p.b).then(|| (p.a - p.b) / (k * duration)),
        });
    }
    Ok(HoldSlipRates { v_i, hold_duration: duration, lab_v_end: 2e-5, laws })
}
