//! The event catalogue: an event starts when the fault-wide maximum slip rate first reaches
//! the threshold (1e-3 m/s in the SEAS benchmarks) and ends when it falls below it again.

use std::io::Write;

/// Seismic threshold of the SEAS benchmarks, m/s.
pub const SEISMIC_V: f64 = 1e-3;

/// One event.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Onset, s (interpolated in ln V between the two steps around the crossing).
    pub onset_s: f64,
    /// End, s (`None` while still running).
    pub end_s: Option<f64>,
    /// Peak of the fault-wide maximum slip rate, m/s (sampled at the integrator's steps).
    pub peak_v: f64,
    /// Slip at the surface (z = 0, extrapolated from the two shallowest cells) during the event, m.
    pub surface_slip: f64,
    /// Depth of the maximum slip rate at onset, m.
    pub nucleation_depth_m: f64,
    /// Depth where the peak slip rate was reached, m.
    pub peak_depth_m: f64,
}

/// Watches the fault-wide maximum slip rate step by step.
#[derive(Clone, Debug, Default)]
pub struct Catalogue {
    /// The events so far.
    pub events: Vec<Event>,
    prev: Option<(f64, f64)>,
    surface_at_onset: f64,
}

impl Catalogue {
    /// After an accepted step at `t`: `ln_v_max` and the depth of the maximum, the surface slip.
    pub fn observe(&mut self, t: f64, ln_v_max: f64, depth_of_max: f64, surface_slip: f64) {
        let thr = SEISMIC_V.ln();
        let open = self.events.last().is_some_and(|e| e.end_s.is_none());
        if !open && ln_v_max >= thr {
            let onset = match self.prev {
                Some((tp, lp)) if lp < thr && ln_v_max > lp => tp + (thr - lp) / (ln_v_max - lp) * (t - tp),
                _ => t,
            };
            self.surface_at_onset = surface_slip;
            self.events.push(Event {
                onset_s: onset,
                end_s: None,
                peak_v: ln_v_max.exp(),
                surface_slip: 0.0,
                nucleation_depth_m: depth_of_max,
                peak_depth_m: depth_of_max,
            });
        } else if open {
            let e = self.events.last_mut().expect("an open event");
            if ln_v_max.exp() > e.peak_v {
                (e.peak_v, e.peak_depth_m) = (ln_v_max.exp(), depth_of_max);
            }
            e.surface_slip = surface_slip - self.surface_at_onset;
            if ln_v_max < thr {
                e.end_s = Some(t);
            }
        }
        self.prev = Some((t, ln_v_max));
    }

    /// Whether an event is running.
    pub fn seismic(&self) -> bool {
        self.events.last().is_some_and(|e| e.end_s.is_none())
    }

    /// `events.csv`: `onset_yr,peak_slip_rate_m_s,surface_slip_m,nucleation_depth_km`.
    pub fn write_csv(&self, mut w: impl Write) -> std::io::Result<()> {
        writeln!(w, "onset_yr,peak_slip_rate_m_s,surface_slip_m,nucleation_depth_km")?;
        for e in &self.events {
            writeln!(
                w,
                "{:.4},{:.5},{:.5},{:.3}",
                e.onset_s / crate::YEAR,
                e.peak_v,
                e.surface_slip,
                e.nucleation_depth_m / 1e3
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn onset_is_interpolated_and_slip_accumulated() {
        let mut c = Catalogue::default();
        c.observe(0.0, (1e-9f64).ln(), 1e4, 0.0);
        c.observe(10.0, (1e-5f64).ln(), 1.3e4, 0.1);
        // crossing ln 1e-3 between 1e-5 (t = 10) and 1e-1 (t = 12): at t = 11
        c.observe(12.0, (1e-1f64).ln(), 1.2e4, 0.2);
        assert!(c.seismic());
        c.observe(20.0, (3.0f64).ln(), 0.0, 1.5);
        c.observe(200.0, (1e-6f64).ln(), 0.0, 2.6);
        assert!(!c.seismic());
        let e = &c.events[0];
        assert!((e.onset_s - 11.0).abs() < 1e-9, "{e:?}");
        assert!((e.peak_v - 3.0).abs() < 1e-12 && (e.surface_slip - 2.4).abs() < 1e-12);
        assert_eq!(e.nucleation_depth_m, 1.2e4);
        assert_eq!(e.peak_depth_m, 0.0);
        assert_eq!(e.end_s, Some(200.0));
    }
}
