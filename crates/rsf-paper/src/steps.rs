//! Velocity steps (the paper's Figs. 1 and 2).
//!
//! A run starts in steady state at `v_from` (µm/s) and at t = 0 the load point switches to
//! `v_to`. Friction is stress over normal stress; slip is measured from the step onset (µm).
//! Both figures use the step-fitted parameters of Table 1 and k = 0.065 1/µm.

use crate::PaperError;
use crate::numerics::{Curve, LineFit, extremum, interp, lin_grid, line_fit, running_mean, transient_times};
use crate::params::{AGING_STEPS, AGING_STEPS_FIXED, LawParams, SLIP_STEPS};
use crate::sim::{Resolution, run};
use rsf_core::Segment;
use rsf_solvers::Solution;
use serde::Serialize;

/// The high slip rate of every step: decreases start from it and increases end at it, µm/s.
pub const V_HIGH: f64 = 3.0;
/// Step sizes, log10(V_high/V_low): 0.5, 1, …, 3.5 orders of magnitude.
pub const STEP_SIZES: [f64; 7] = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5];
/// Load-point displacement simulated after each step, µm.
pub const LOAD_POINT_AFTER_STEP: f64 = 25.0;
/// Post-extremum slip over which Fig. 1 normalises friction, µm.
pub const NORMALISATION_SLIP: f64 = 4.0;
/// Width of the running mean in slip applied after decreases (as the paper does), µm.
pub const SMOOTHING_DECREASE: f64 = 0.2;
/// Width of the running mean in slip applied after increases, µm.
pub const SMOOTHING_INCREASE: f64 = 0.4;
/// Spacing of the even slip grid the curves are resampled on before smoothing, µm.
const SLIP_SPACING: f64 = 0.005;

/// One step simulated from steady state at `v_from` to load-point rate `v_to` (µm/s), followed
/// for [`LOAD_POINT_AFTER_STEP`] µm of load point.
fn step_run(p: &LawParams, v_from: f64, v_to: f64, res: &Resolution) -> Result<Solution, PaperError> {
    let t_end = LOAD_POINT_AFTER_STEP / v_to;
    // resolve the first nanometre of slip at the faster rate as well as the long tail
    let times = transient_times(1e-3 / v_from.max(v_to), t_end, res.samples / 2);
    run(&p.model(), v_from, vec![Segment::for_duration(v_to, t_end)], times, res)
}

/// Friction against slip from step onset on an even grid of [`SLIP_SPACING`] µm.
fn friction_vs_slip(sol: &Solution) -> Curve {
    let end = *sol.slip.last().expect("non-empty solution");
    let x = lin_grid(0.0, end, (end / SLIP_SPACING).round() as usize + 1);
    let y = x.iter().map(|&s| interp(&sol.slip, &sol.mu, s)).collect();
    Curve::new(x, y)
}

/// The centred running mean over `width` µm of slip of a step record `f` (friction on the even
/// grid of [`friction_vs_slip`], slip 0 at the step onset), as applied to a lab record that
/// includes the steady sliding before the step: the record is extended to negative slip with
/// the steady-state friction `mu_before` = μ_ss(V_from) the run starts from, so that windows
/// near the onset are full rather than truncated at slip 0. Returned on the grid of `f` (slip ≥ 0).
fn smooth_with_steady_sliding_before(f: &Curve, mu_before: f64, width: f64) -> Curve {
    let h = f.x[1] - f.x[0];
    // a whole window of steady sliding: more than the half window a centred mean reaches back
    let pad = (width / h).ceil() as usize;
    let x: Vec<f64> = (1..=pad).rev().map(|j| -(j as f64) * h).chain(f.x.iter().copied()).collect();
    let y: Vec<f64> = std::iter::repeat_n(mu_before, pad).chain(f.y.iter().copied()).collect();
    let smooth = running_mean(&x, &y, width);
    Curve::new(f.x.clone(), smooth[pad..].to_vec())
}

/// One step of Fig. 1: friction normalised between its extremum and 4 µm of slip later.
#[derive(Clone, Debug, Serialize)]
pub struct NormalisedStep {
    /// Step size log10(V_high/V_low).
    pub log10_size: f64,
    /// Slip rate before the step, µm/s.
    pub v_from: f64,
    /// Load-point rate after the step, µm/s.
    pub v_to: f64,
    /// Slip from step onset to the extremum of the smoothed friction, µm.
    pub slip_to_extremum: f64,
    /// Post-extremum slip at which the normalised friction first reaches 1/2, µm.
    pub half_recovery_slip: f64,
    /// Normalised friction `(μ(δ_e + s) − μ_e)/(μ(δ_e + 4 µm) − μ_e)` against the slip `s`
    /// since the extremum, µm (smoothed friction μ, extremum at slip δ_e).
    pub curve: Curve,
}

/// Fig. 1 steps of one law and direction.
#[derive(Clone, Debug, Serialize)]
pub struct StepFamily {
    /// The parameters.
    pub params: LawParams,
    /// `"decrease"` or `"increase"`.
    pub direction: &'static str,
    /// One entry per step size of [`STEP_SIZES`].
    pub steps: Vec<NormalisedStep>,
    /// max/min over step sizes of the half-recovery slip: 1 when the evolution distance does
    /// not depend on the step size.
    pub half_recovery_spread: f64,
}

/// Fig. 1B/C: normalised friction after velocity-step decreases and increases.
#[derive(Clone, Debug, Serialize)]
pub struct Fig1 {
    /// High slip rate, µm/s: decreases go from it to V_HIGH·10^(−size), increases from
    /// V_HIGH·10^(−size) back to it.
    pub v_high: f64,
    /// Running-mean widths in slip (decrease, increase), µm.
    pub smoothing: (f64, f64),
    /// Normalisation slip, µm.
    pub normalisation_slip: f64,
    /// Slip and Aging (step-fitted) decreases, then increases.
    pub families: Vec<StepFamily>,
}

/// Normalises one smoothed step record (friction on an even slip grid) at its extremum.
fn normalise(f: &Curve, decrease: bool, log10_size: f64, v_from: f64, v_to: f64) -> Result<NormalisedStep, PaperError> {
    let sign = if decrease { 1.0 } else { -1.0 };
    let e = extremum(&f.x, &f.y, sign);
    let (s_e, mu_e) = (f.x[e.index], f.y[e.index]);
    let end = *f.x.last().expect("non-empty curve");
    let span = (end - s_e).min(1.5 * NORMALISATION_SLIP);
    if span < NORMALISATION_SLIP {
        return Err(PaperError::Protocol(format!(
            "step of 10^{log10_size}: only {:.2} µm of slip after the extremum",
            end - s_e
        )));
    }
    let mu_4 = interp(&f.x, &f.y, s_e + NORMALISATION_SLIP);
    let n = (span / SLIP_SPACING).round() as usize + 1;
    let x = lin_grid(0.0, span, n);
    let y: Vec<f64> = x.iter().map(|&s| (interp(&f.x, &f.y, s_e + s) - mu_e) / (mu_4 - mu_e)).collect();
    let k = y.iter().position(|&v| v >= 0.5).expect("normalised friction reaches 1 at 4 µm");
    let half = x[k - 1] + (0.5 - y[k - 1]) / (y[k] - y[k - 1]) * (x[k] - x[k - 1]);
    Ok(NormalisedStep {
        log10_size,
        v_from,
        v_to,
        slip_to_extremum: s_e,
        half_recovery_slip: half,
        curve: Curve::new(x, y),
    })
}

/// Fig. 1B/C: velocity-step decreases from 3 µm/s by 10^0.5 … 10^3.5 and increases of the same
/// sizes back up to 3 µm/s, for the step-fitted Slip and Aging laws; friction smoothed by a
/// centred running mean over 0.2 µm (0.4 µm for increases) of slip, with steady sliding at
/// μ_ss(V_from) before the step (as in a lab record), and normalised by its change from the
/// extremum to 4 µm of slip past it, against slip since the extremum.
///
/// Run by `cargo run --release -p rsf-paper --example fig1_steps`.
pub fn fig1_steps(res: &Resolution) -> Result<Fig1, PaperError> {
    let mut families = Vec::new();
    for decrease in [true, false] {
        for p in [SLIP_STEPS, AGING_STEPS] {
            let mut steps = Vec::new();
            for &m in &STEP_SIZES {
                let v_low = V_HIGH * 10f64.powf(-m);
                let (v_from, v_to) = if decrease { (V_HIGH, v_low) } else { (v_low, V_HIGH) };
                let mu_from = p.model().steady_state_friction(v_from)?;
                let raw = friction_vs_slip(&step_run(&p, v_from, v_to, res)?);
                let width = if decrease { SMOOTHING_DECREASE } else { SMOOTHING_INCREASE };
                let smooth = smooth_with_steady_sliding_before(&raw, mu_from, width);
                let mut s = normalise(&smooth, decrease, m, v_from, v_to)?;
                s.curve = s.curve.thinned(res.plot_points);
                steps.push(s);
            }
            let (lo, hi) = steps.iter().fold((f64::INFINITY, 0f64), |(lo, hi), s| {
                (lo.min(s.half_recovery_slip), hi.max(s.half_recovery_slip))
            });
            families.push(StepFamily {
                params: p,
                direction: if decrease { "decrease" } else { "increase" },
                steps,
                half_recovery_spread: hi / lo,
            });
        }
    }
    Ok(Fig1 {
        v_high: V_HIGH,
        smoothing: (SMOOTHING_DECREASE, SMOOTHING_INCREASE),
        normalisation_slip: NORMALISATION_SLIP,
        families,
    })
}

/// The friction minimum after one velocity-step decrease.
#[derive(Clone, Debug, Serialize)]
pub struct MinimumPoint {
    /// Step size log10(V_i/V_f).
    pub log10_size: f64,
    /// Load-point rate after the step V_f, µm/s.
    pub v_f: f64,
    /// Δμ_min = min μ − μ_ss(V_i).
    pub delta_mu_min: f64,
    /// −a ln(V_i/V_f): the direct effect alone, the minimum if state did not evolve.
    pub direct_effect: f64,
    /// Slip from step onset to the minimum, µm.
    pub slip_to_min: f64,
    /// Time from step onset to the minimum, s.
    pub time_to_min: f64,
    /// Slip rate at the minimum, µm/s. Exactly V_f in theory (dμ/dt = k (V_f − V) = 0 there).
    pub v_at_min: f64,
}

/// Fig. 2 minima for one parameter set.
#[derive(Clone, Debug, Serialize)]
pub struct MinimaFamily {
    /// The parameters.
    pub params: LawParams,
    /// One point per step size of [`STEP_SIZES`].
    pub points: Vec<MinimumPoint>,
    /// Straight line Δμ_min against log10(V_i/V_f) (slope per decade).
    pub fit: LineFit,
    /// The slope per e-fold of step size, `fit.slope / ln 10`.
    pub slope_per_efold: f64,
    /// Ratio of the last to the first half-decade increment of Δμ_min: 1 for a straight line,
    /// small when the minima shallow for large steps.
    pub increment_ratio: f64,
    /// Δμ = μ − μ_ss(V_i) against slip from step onset (µm), one curve per step size.
    pub curves: Vec<Curve>,
}

/// Fig. 2: friction minima after velocity-step decreases.
#[derive(Clone, Debug, Serialize)]
pub struct Fig2 {
    /// Slip rate before every step, µm/s.
    pub v_i: f64,
    /// Slip law, Aging law and Aging law with a − b = −0.003 (all step-fitted).
    pub families: Vec<MinimaFamily>,
}

/// Fig. 2B–E: Δμ_min = min μ − μ_ss(V_i) after decreases from V_i = 3 µm/s by 10^0.5 … 10^3.5
/// against log10 step size (with a straight-line fit), the slip from step onset to the minimum,
/// and the friction curves against slip, for the step-fitted Slip law and both step-fitted
/// Aging laws.
///
/// Run by `cargo run --release -p rsf-paper --example fig2_minima`.
pub fn fig2_minima(res: &Resolution) -> Result<Fig2, PaperError> {
    let mut families = Vec::new();
    for p in [SLIP_STEPS, AGING_STEPS, AGING_STEPS_FIXED] {
        let mu_i = p.model().steady_state_friction(V_HIGH)?;
        let mut points = Vec::new();
        let mut curves = Vec::new();
        for &m in &STEP_SIZES {
            let v_f = V_HIGH * 10f64.powf(-m);
            let sol = step_run(&p, V_HIGH, v_f, res)?;
            let e = extremum(&sol.time, &sol.mu, 1.0);
            points.push(MinimumPoint {
                log10_size: m,
                v_f,
                delta_mu_min: e.y - mu_i,
                direct_effect: -p.a * (V_HIGH / v_f).ln(),
                slip_to_min: interp(&sol.time, &sol.slip, e.x),
                time_to_min: e.x,
                v_at_min: interp(&sol.time, &sol.slip_rate, e.x),
            });
            let f = friction_vs_slip(&sol);
            curves.push(Curve::new(f.x, f.y.iter().map(|mu| mu - mu_i).collect()).thinned(res.plot_points));
        }
        let x: Vec<f64> = points.iter().map(|q| q.log10_size).collect();
        let y: Vec<f64> = points.iter().map(|q| q.delta_mu_min).collect();
        let fit = line_fit(&x, &y);
        let n = y.len();
        families.push(MinimaFamily {
            params: p,
            slope_per_efold: fit.slope / std::f64::consts::LN_10,
            increment_ratio: (y[n - 2] - y[n - 1]) / (y[0] - y[1]),
            fit,
            points,
            curves,
        });
    }
    Ok(Fig2 { v_i: V_HIGH, families })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The padding is the state the run starts from: friction at slip 0 is μ_ss(V_from).
    #[test]
    fn step_runs_start_at_the_steady_state_the_smoothing_pads_with() {
        for p in [SLIP_STEPS, AGING_STEPS] {
            let v_from = V_HIGH * 10f64.powf(-3.5);
            let raw = friction_vs_slip(&step_run(&p, v_from, V_HIGH, &Resolution::quick()).unwrap());
            let mu_from = p.model().steady_state_friction(v_from).unwrap();
            assert!((raw.y[0] - mu_from).abs() < 1e-12, "{}: μ(0) − μ_ss(V_from) = {}", p.law, raw.y[0] - mu_from);
        }
    }

    /// A record that jumps by 1 at the onset: with steady sliding before the step the centred
    /// mean is ≈ 1/2 at the onset and ramps linearly to 1 half a window later (a mean truncated
    /// at slip 0 would be 1 throughout); beyond half a window the padding changes nothing.
    #[test]
    fn smoothing_sees_the_steady_sliding_before_the_step() {
        let width = 0.4;
        let x = lin_grid(0.0, 2.0, 401);
        let h = x[1];
        let f = Curve::new(x.clone(), vec![1.0; x.len()]);
        let s = smooth_with_steady_sliding_before(&f, 0.0, width);
        assert_eq!(s.x, x);
        let half = (0.5 * width / h).round() as usize;
        for (i, (&xi, &yi)) in s.x.iter().zip(&s.y).enumerate() {
            let expected = if i < half { (half + 1 + i) as f64 / (2 * half + 1) as f64 } else { 1.0 };
            assert!((yi - expected).abs() < 1e-12, "slip {xi}: {yi} vs {expected}");
        }
        let y: Vec<f64> = x.iter().map(|v| (3.0 * v).sin()).collect();
        let padded = smooth_with_steady_sliding_before(&Curve::new(x.clone(), y.clone()), 0.0, width);
        let truncated = running_mean(&x, &y, width);
        assert!((half..x.len()).all(|i| (padded.y[i] - truncated[i]).abs() < 1e-12));
    }
}
