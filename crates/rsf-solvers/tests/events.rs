//! Event-aware output: a radiation-damped stick-slip cycle whose events (seconds long) fall
//! between output samples 2000 s apart. The step watcher still catalogues every event and
//! reports the peak slip rate between rows. The spring-slider is the BP1-like one of
//! ../shared/notes/fault-sim.md (regularized friction, aging law, η = ρc_s/2, k = k_c/2, start
//! at V = 0.9 V_p, θ = Dc/V_p) in µm and s: QDYN's and the C-ABI host's first onset 5.9824 yr,
//! period 14.1784 yr (years of 365 days), peak 0.8321 m/s.

use rsf_core::{FrictionForm, Loading, Model, Segment, StateVariable};
use rsf_laws::Aging;
use rsf_solvers::{Auto, Problem, WatchOptions, solve};

const YEAR: f64 = 3.1536e7;

#[test]
fn events_between_samples_are_caught() {
    let sigma = 50e6;
    let k = 0.5 * (0.015 - 0.010) / 0.008 * 1e-6; // k_c / 2 per σ, per µm
    let eta = 2670.0 * 3464.0 / 2.0 / sigma * 1e-6;
    let model = Model { form: FrictionForm::Regularized, ..Model::new(0.6, 1.0, 0.010, k) }
        .with_eta(eta)
        .with_state(StateVariable::new(Aging, 0.015, 8000.0));
    let mut p = Problem::new(model, Loading::Segments(vec![Segment::for_duration(1e-3, 60.0 * YEAR)]), 0.9e-3, 2000.0);
    p.initial_theta = Some(vec![8e6]);
    p.watch = WatchOptions { peak_slip_rate: true, event_slip_rate: Some(1e3) };
    let sol = solve(&p, &Auto::new(1e-10, 1e-9)).unwrap();
    // the rows alone miss every event
    let sampled = sol.slip_rate.iter().cloned().fold(0.0, f64::max);
    assert!(sampled < 1e3, "a row fell inside an event ({sampled} µm/s): choose another dt");
    let ev = &sol.events;
    assert_eq!(ev.len(), 4, "{ev:?}");
    assert!((ev[0].onset_s / YEAR - 5.9824).abs() < 1e-3, "{:?}", ev[0]);
    let period = (ev[2].onset_s - ev[1].onset_s) / YEAR;
    assert!((period - 14.1784).abs() < 1e-3, "period {period}");
    for e in ev {
        assert!(e.end_s.is_some_and(|t| t > e.onset_s && t - e.onset_s < 1e3), "{e:?}");
    }
    // the first event (from the perturbed start) is smaller; the periodic ones peak at 0.8321
    // m/s, alike, and slip less in the event than the V_p × period = 0.447 m of a whole cycle
    assert!(ev[0].peak_slip_rate < 0.7 * ev[1].peak_slip_rate, "{:?}", ev[0]);
    for e in &ev[1..] {
        assert!((e.peak_slip_rate / 8.321e5 - 1.0).abs() < 5e-3, "{e:?}");
        assert!(e.slip_um < 1e-3 * period * YEAR && (e.slip_um / ev[1].slip_um - 1.0).abs() < 1e-3, "{e:?}");
    }
    // the peak column carries them: its maximum is the events' peak, row by row ≥ the row's V
    assert_eq!(sol.peak_slip_rate.len(), sol.len());
    let col = sol.peak_slip_rate.iter().cloned().fold(0.0, f64::max);
    let top = ev.iter().map(|e| e.peak_slip_rate).fold(0.0, f64::max);
    assert!((col / top - 1.0).abs() < 1e-12, "{col} vs {top}");
    assert!(sol.peak_slip_rate.iter().zip(&sol.slip_rate).all(|(p, v)| p >= &(v * (1.0 - 1e-12))));
    let mut csv = Vec::new();
    sol.write_events_csv(&mut csv).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    assert!(csv.starts_with("onset_s,end_s,peak_slip_rate_um_s,peak_time_s,slip_um\n") && csv.lines().count() == 5);
}
