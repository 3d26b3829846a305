//! Slide–hold–slide: peak friction on reslide against hold time.
//!
//! Steady sliding at V_i, a hold (V_lp = 0) of t_h seconds, then reslide at V_i. The peak on
//! reslide minus the pre-hold steady friction, `Δμ_pk = μ_pk − μ_ss(V_i)`, grows about
//! linearly in ln t_h. At the peak dμ/dt = k (V_i − V) = 0, i.e. V = V_i.

use crate::PaperError;
use crate::numerics::{Curve, extremum, interp, lin_grid, line_fit, log_grid, pick, thin_indices};
use crate::params::{AGING_STEPS, AGING_STEPS_FIXED, LawParams, SLIP_STEPS};
use crate::sim::{Resolution, run};
use rsf_core::Segment;
use serde::Serialize;

/// Slip rate before and after every hold, µm/s.
pub const SHS_V: f64 = 1.0;
/// Hold times, s: 10 values log-spaced from 10 to 10⁴ s.
pub fn hold_times() -> Vec<f64> {
    log_grid(10.0, 1e4, 10)
}
/// Load-point displacement of the reslide, µm.
pub const RESLIDE: f64 = 30.0;
/// Holds at least this long (s) define the long-hold slope.
pub const LONG_HOLD: f64 = 300.0;

/// One slide–hold–slide.
#[derive(Clone, Debug, Serialize)]
pub struct Shs {
    /// Hold time, s.
    pub hold: f64,
    /// Δμ at the end of the hold (negative: relaxation).
    pub relaxed: f64,
    /// Δμ_pk = μ_pk − μ_ss(V_i).
    pub peak: f64,
    /// Load-point displacement from reslide onset to the peak, µm.
    pub peak_load_point: f64,
    /// Slip rate at the peak, µm/s (V_i in theory).
    pub v_at_peak: f64,
    /// Δμ against load-point displacement since reslide onset, µm (half the plotted points of
    /// other curves: there are 30 of them).
    pub reslide: Curve,
}

/// Peak friction against hold time for one parameter set.
#[derive(Clone, Debug, Serialize)]
pub struct PeakFamily {
    /// The parameters.
    pub params: LawParams,
    /// One entry per hold time.
    pub holds: Vec<Shs>,
    /// d Δμ_pk / d ln t_h fitted over holds ≥ [`LONG_HOLD`] s.
    pub slope_long: f64,
    /// d Δμ_pk / d ln t_h fitted over all holds.
    pub slope_all: f64,
    /// `slope_long / b`.
    pub slope_over_b: f64,
}

/// `peak_vs_hold`: slide–hold–slide at 1 µm/s.
#[derive(Clone, Debug, Serialize)]
pub struct PeakVsHold {
    /// Slip rate before and after the holds, µm/s.
    pub v: f64,
    /// Step-fitted Aging, Aging with a − b = −0.003, step-fitted Slip.
    pub families: Vec<PeakFamily>,
}

/// Slide–hold–slide at V_i = 1 µm/s with holds of 10 … 10⁴ s (10 log-spaced), reslide at V_i
/// for 30 µm: Δμ_pk = μ_pk − μ_ss(V_i) against ln t_h and its slope, for both step-fitted
/// Aging laws and the step-fitted Slip law. The Aging law heals in time (θ ≈ t in a long
/// hold), so its slope approaches b; the Slip law heals only by the slip of the hold.
///
/// Run by `cargo run --release -p rsf-paper --example peak_vs_hold`.
pub fn peak_vs_hold(res: &Resolution) -> Result<PeakVsHold, PaperError> {
    let v = SHS_V;
    let pre = 1.0; // s of steady sliding before the hold (the run starts in steady state)
    let reslide_time = RESLIDE / v;
    let mut families = Vec::new();
    for p in [AGING_STEPS, AGING_STEPS_FIXED, SLIP_STEPS] {
        let model = p.model();
        let mu_i = model.steady_state_friction(v)?;
        let mut holds = Vec::new();
        for t_h in hold_times() {
            let t_r = pre + t_h; // reslide onset
            let n = res.samples / 2;
            let mut times = vec![0.0, pre, t_r];
            times.extend(lin_grid(t_r, t_r + reslide_time, n).into_iter().skip(1));
            times.dedup();
            let segs = vec![
                Segment::for_duration(v, pre),
                Segment::for_duration(0.0, t_h),
                Segment::for_duration(v, reslide_time),
            ];
            let sol = run(&model, v, segs, times, res)?;
            let r = 2..sol.len(); // reslide samples, from its onset
            let e = extremum(&sol.time[r.clone()], &sol.mu[r.clone()], -1.0);
            let lp: Vec<f64> = sol.load_point[r.clone()].iter().map(|x| x - sol.load_point[2]).collect();
            let idx = thin_indices(lp.len(), res.plot_points / 2);
            let dmu: Vec<f64> = sol.mu[r.clone()].iter().map(|m| m - mu_i).collect();
            holds.push(Shs {
                hold: t_h,
                relaxed: sol.mu[2] - mu_i,
                peak: e.y - mu_i,
                peak_load_point: (e.x - t_r) * v,
                v_at_peak: interp(&sol.time[r.clone()], &sol.slip_rate[r], e.x),
                reslide: Curve::new(pick(&lp, &idx), pick(&dmu, &idx)),
            });
        }
        let fit = |min_hold: f64| {
            let (x, y): (Vec<f64>, Vec<f64>) =
                holds.iter().filter(|s| s.hold >= min_hold).map(|s| (s.hold.ln(), s.peak)).unzip();
            line_fit(&x, &y).slope
        };
        let slope_long = fit(LONG_HOLD);
        families.push(PeakFamily { params: p, slope_all: fit(0.0), slope_over_b: slope_long / p.b, slope_long, holds });
    }
    Ok(PeakVsHold { v, families })
}
