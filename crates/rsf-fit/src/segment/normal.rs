//! Normal-stress changes in a record, reported beside the load-point segments.

use rsf_core::NormalStressRecord;
use serde::Serialize;

/// A change of normal stress counts as an event when it moves σ by more than this fraction of
/// the record's median σ: the servo noise of a nominally constant σ stays well below it, lab
/// normal-stress steps (5–100 %) far above.
pub const NORMAL_STRESS_EVENT: f64 = 0.01;

/// A change of normal stress between `t0` and `t1` (s): a step (over one sampling interval) or
/// a ramp.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NormalStressEvent {
    /// Start, s.
    pub t0: f64,
    /// End, s.
    pub t1: f64,
    /// σ before, MPa.
    pub from: f64,
    /// σ after, MPa.
    pub to: f64,
}

/// Servo noise and the kHz bursts of a σ record are averaged over this window (s) before
/// changes are looked for: lab σ changes take seconds, the noise is sample-to-sample.
pub const NORMAL_STRESS_SMOOTHING_S: f64 = 1.0;

/// A servo that raises σ in stages pauses between them; pauses shorter than this (s) do not
/// split one change into several.
pub const NORMAL_STRESS_PAUSE_S: f64 = 10.0;

/// The normal-stress changes of a record (`time`, `sigma` of equal length). σ is averaged over
/// [`NORMAL_STRESS_SMOOTHING_S`], simplified to a polyline (tolerance a quarter of the event
/// threshold), and runs of pieces moving σ the same way — across pauses shorter than
/// [`NORMAL_STRESS_PAUSE_S`] — are one change, reported when it moves σ by more than
/// [`NORMAL_STRESS_EVENT`] of the median.
pub fn normal_stress_events(time: &[f64], sigma: &[f64]) -> Vec<NormalStressEvent> {
    let n = time.len();
    if sigma.len() != n || n < 3 {
        return vec![];
    }
    let mut sorted = sigma.to_vec();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[n / 2];
    // centred moving average over the time window (prefix sums: O(n))
    let mut prefix = vec![0.0; n + 1];
    for i in 0..n {
        prefix[i + 1] = prefix[i] + sigma[i];
    }
    let half = 0.5 * NORMAL_STRESS_SMOOTHING_S;
    let smooth: Vec<f64> = (0..n)
        .map(|i| {
            let lo = time.partition_point(|&t| t < time[i] - half);
            let hi = time.partition_point(|&t| t <= time[i] + half);
            (prefix[hi] - prefix[lo]) / (hi - lo) as f64
        })
        .collect();
    let h = NormalStressRecord { time: time.to_vec(), sigma: smooth };
    if h.validate().is_err() {
        return vec![];
    }
    let threshold = NORMAL_STRESS_EVENT * median;
    let poly = h.simplified(0.25 * threshold);
    let mut out: Vec<NormalStressEvent> = vec![];
    // (start, end, σ at start, σ at end, direction) of the run being built
    let mut run: Option<(f64, f64, f64, f64, f64)> = None;
    let close = |run: &mut Option<(f64, f64, f64, f64, f64)>, out: &mut Vec<NormalStressEvent>| {
        if let Some((t0, t1, from, to, _)) = run.take() {
            if (to - from).abs() > threshold {
                out.push(NormalStressEvent { t0, t1, from, to });
            }
        }
    };
    for i in 0..poly.time.len() - 1 {
        let (t0, t1, from, to) = (poly.time[i], poly.time[i + 1], poly.sigma[i], poly.sigma[i + 1]);
        let moving = (to - from).abs() > 0.25 * threshold;
        let dir = (to - from).signum();
        match (&mut run, moving) {
            (Some(r), true) if r.4 == dir => {
                r.1 = t1;
                r.3 = to;
            }
            (Some(r), false) if t1 - t0 < NORMAL_STRESS_PAUSE_S => {
                let _ = r; // a pause inside a staged change
            }
            _ => {
                close(&mut run, &mut out);
                if moving {
                    run = Some((t0, t1, from, to, dir));
                }
            }
        }
    }
    close(&mut run, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_and_ramps_are_found_and_noise_is_not() {
        let time: Vec<f64> = (0..3000).map(|i| i as f64 * 0.1).collect();
        let sigma: Vec<f64> = time
            .iter()
            .enumerate()
            .map(|(i, &t)| {
                let base = if t < 100.0 {
                    10.0
                } else if t < 102.0 {
                    10.0 + 1.5 * (t - 100.0)
                } else if t < 200.0 {
                    13.0
                } else {
                    10.0
                };
                base + 2e-3 * (((i * 7919) % 17) as f64 / 17.0 - 0.5)
            })
            .collect();
        let e = normal_stress_events(&time, &sigma);
        assert_eq!(e.len(), 2, "{e:?}");
        // the 1 s averaging widens each change by up to half a second on either side
        assert!((e[0].t0 - 100.0).abs() < 0.7 && (e[0].t1 - 102.0).abs() < 0.7, "{e:?}");
        assert!((e[0].to - 13.0).abs() < 0.05 && (e[1].to - 10.0).abs() < 0.05, "{e:?}");
        assert!((e[1].t0 - 200.0).abs() < 0.7 && (e[1].t1 - 200.0).abs() < 0.7, "{e:?}");
        let flat: Vec<f64> = sigma.iter().map(|_| 10.0).collect();
        assert!(normal_stress_events(&time, &flat).is_empty());
    }
}
