//! Watching every accepted step, not only the output rows: the largest slip rate between two
//! output samples and a catalogue of slip events. An output grid of 0.05 s can miss a 3 ms
//! event entirely; the integrator's steps cannot, so both are taken from them.

use serde::Serialize;
use std::cell::{Cell, RefCell};

/// What to watch (both off by default).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WatchOptions {
    /// Record, for every output row, the largest slip rate since the previous row.
    pub peak_slip_rate: bool,
    /// Catalogue slip events: an event starts when V first reaches this slip rate (µm/s) and
    /// ends when it falls below it again.
    pub event_slip_rate: Option<f64>,
}

/// One slip event.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SlipEvent {
    /// Onset, s: where ln V crosses the threshold, interpolated between the two steps around it.
    pub onset_s: f64,
    /// End, s (`None` if the run ended inside the event).
    pub end_s: Option<f64>,
    /// Largest slip rate in the event, µm/s (at the integrator's steps).
    pub peak_slip_rate: f64,
    /// When it was reached, s.
    pub peak_time_s: f64,
    /// Slip from onset to end, µm.
    pub slip_um: f64,
}

/// The watcher the spring-slider system reports its accepted steps to.
#[derive(Debug)]
pub(crate) struct StepWatch {
    threshold: Option<f64>,
    /// The last accepted step's end (t, ln V), not yet merged: output rows before it do not
    /// see it.
    pending: Cell<Option<(f64, f64)>>,
    /// Largest ln V over the merged steps since the last output row.
    max_ln_v: Cell<f64>,
    prev: Cell<Option<(f64, f64)>>,
    prev_rate: Cell<Option<(f64, f64, f64)>>,
    slip_at_onset: Cell<f64>,
    events: RefCell<Vec<SlipEvent>>,
}

impl StepWatch {
    pub(crate) fn new(opts: &WatchOptions) -> Self {
        Self {
            threshold: opts.event_slip_rate.map(f64::ln),
            pending: Cell::new(None),
            max_ln_v: Cell::new(f64::NEG_INFINITY),
            prev: Cell::new(None),
            prev_rate: Cell::new(None),
            slip_at_onset: Cell::new(0.0),
            events: RefCell::new(Vec::new()),
        }
    }

    /// After an accepted step ending at `t` with `ln_v`, its rate `dln_v` (1/s) and slip
    /// `slip` (µm). A maximum of ln V inside the step (the rate changes sign from + to −) is
    /// located on the cubic Hermite interpolant of the two ends: step ends alone can miss most
    /// of a peak that the integrator crosses in one or two long steps.
    pub(crate) fn step(&self, t: f64, ln_v: f64, dln_v: f64, slip: f64) {
        let mut top = (t, ln_v);
        if let Some((tp, lp, dp)) = self.prev_rate.replace(Some((t, ln_v, dln_v))) {
            if dp > 0.0 && dln_v <= 0.0 {
                if let Some(m) = hermite_max((tp, lp, dp), (t, ln_v, dln_v)) {
                    if m.1 > top.1 {
                        top = m;
                    }
                }
            }
        }
        if let Some((_, lp)) = self.pending.replace(Some((t, top.1))) {
            self.max_ln_v.set(self.max_ln_v.get().max(lp));
        }
        if let Some(thr) = self.threshold {
            let mut ev = self.events.borrow_mut();
            let open = ev.last().is_some_and(|e| e.end_s.is_none());
            if !open && ln_v >= thr {
                let onset = match self.prev.get() {
                    Some((tp, lp)) if lp < thr && ln_v > lp => tp + (thr - lp) / (ln_v - lp) * (t - tp),
                    _ => t,
                };
                self.slip_at_onset.set(slip);
                ev.push(SlipEvent {
                    onset_s: onset,
                    end_s: None,
                    peak_slip_rate: ln_v.exp(),
                    peak_time_s: t,
                    slip_um: 0.0,
                });
            } else if open {
                let e = ev.last_mut().expect("an open event");
                if top.1.exp() > e.peak_slip_rate {
                    (e.peak_slip_rate, e.peak_time_s) = (top.1.exp(), top.0);
                }
                e.slip_um = slip - self.slip_at_onset.get();
                if ln_v < thr {
                    e.end_s = Some(t);
                }
            }
        }
        self.prev.set(Some((t, ln_v)));
    }

    /// The largest slip rate (µm/s) over the steps since the previous row and the row itself
    /// (at `t`, `ln_v`); starts the next interval.
    pub(crate) fn row(&self, t: f64, ln_v: f64) -> f64 {
        if let Some((tp, lp)) = self.pending.get() {
            if tp <= t {
                self.max_ln_v.set(self.max_ln_v.get().max(lp));
                self.pending.set(None);
            }
        }
        let m = self.max_ln_v.get().max(ln_v);
        self.max_ln_v.set(f64::NEG_INFINITY);
        m.exp()
    }

    pub(crate) fn into_events(self) -> Vec<SlipEvent> {
        self.events.into_inner()
    }
}

/// The maximum (t, y) of the cubic Hermite interpolant through (t0, y0, y0') and (t1, y1, y1')
/// inside (t0, t1), if it has one there.
fn hermite_max((t0, y0, d0): (f64, f64, f64), (t1, y1, d1): (f64, f64, f64)) -> Option<(f64, f64)> {
    let h = t1 - t0;
    if !(h > 0.0) {
        return None;
    }
    let (m0, m1) = (h * d0, h * d1);
    let p = |s: f64| {
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * y0 + (s3 - 2.0 * s2 + s) * m0 + (-2.0 * s3 + 3.0 * s2) * y1 + (s3 - s2) * m1
    };
    // p'(s) = a s² + b s + c
    let (a, b, c) = (6.0 * y0 + 3.0 * m0 - 6.0 * y1 + 3.0 * m1, -6.0 * y0 - 4.0 * m0 + 6.0 * y1 - 2.0 * m1, m0);
    let roots: Vec<f64> = if a.abs() < 1e-300 {
        vec![-c / b]
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            return None;
        }
        let q = -0.5 * (b + b.signum() * disc.sqrt());
        vec![q / a, c / q]
    };
    roots
        .into_iter()
        .filter(|s| s.is_finite() && *s > 0.0 && *s < 1.0)
        .map(|s| (t0 + s * h, p(s)))
        .max_by(|x, y| x.1.total_cmp(&y.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_see_the_steps_between_them_and_events_are_catalogued() {
        let w = StepWatch::new(&WatchOptions { peak_slip_rate: true, event_slip_rate: Some(1e3) });
        w.step(1.0, 0.0, 1.0, 0.0);
        assert_eq!(w.row(1.0, 0.0), 1.0);
        // a spike between rows 1 and 3: the row at 3 reports it
        w.step(2.0, (1e4f64).ln(), 1.0, 5.0);
        w.step(3.0, (2e4f64).ln(), 1.0, 20.0);
        w.step(4.0, 0.0, 1.0, 30.0);
        // a row at 3.5 sees the steps at 2 and 3, not the one at 4
        assert!((w.row(3.5, (10.0f64).ln()) - 2e4).abs() < 1e-6);
        assert!((w.row(4.0, 0.0) - 1.0).abs() < 1e-12);
        let ev = w.into_events();
        assert_eq!(ev.len(), 1);
        // ln V crosses ln 1e3 between t = 1 (ln V 0) and t = 2 (ln 1e4): at 1 + 3/4
        assert!((ev[0].onset_s - 1.75).abs() < 1e-12, "{ev:?}");
        assert_eq!((ev[0].end_s, ev[0].peak_time_s), (Some(4.0), 3.0));
        assert!((ev[0].slip_um - 25.0).abs() < 1e-12);
    }

    /// A parabola's top between two steps is found from the ends' values and slopes.
    #[test]
    fn a_peak_inside_a_step_is_located() {
        // y = 1 − (t − 0.3)²: y(0) = 0.91, y'(0) = 0.6, y(1) = 0.51, y'(1) = −1.4
        let (t, y) = hermite_max((0.0, 0.91, 0.6), (1.0, 0.51, -1.4)).unwrap();
        assert!((t - 0.3).abs() < 1e-12 && (y - 1.0).abs() < 1e-12, "{t} {y}");
        assert!(hermite_max((0.0, 0.0, -1.0), (1.0, -1.0, -1.0)).is_none());
    }
}
