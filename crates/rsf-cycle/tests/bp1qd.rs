//! BP1-QD on a coarse grid against the anchors of ../shared/notes/fault-sim.md (QDYN 2024-03,
//! RKF45 at 1e-7, the same geometry, 78 m cells): first event 196.64 yr, intervals 75.66,
//! 77.88, 78.36, 78.41 yr; nucleation 13.0–13.2 km; surface peak slip rate 4.14 m/s (first
//! 4.48); surface slip 2.47 m (first 2.84). At 156 m cells (N = 256, the CI size: 4 events in
//! about 3 s) the tolerances are the for onsets and intervals, a little wider for the
//! peak rate, which converges more slowly with cell size (N = 512 is within 0.2%: docs/faultsim.md).

use rsf_cycle::YEAR;
use rsf_cycle::run::{CycleProgress, RunOptions, run};

#[test]
fn bp1qd_coarse_matches_the_anchors() {
    let dir = std::env::temp_dir().join("rsf_cycle_bp1qd_test");
    // the library prints nothing; the observer sees every new event and each century
    let seen = std::sync::Arc::new(std::sync::Mutex::new(Vec::<CycleProgress>::new()));
    let log = seen.clone();
    let o = RunOptions {
        cells: 256,
        years: 600.0,
        max_events: Some(4),
        out: Some(dir.clone()),
        progress: Some(std::sync::Arc::new(move |p: &CycleProgress| log.lock().unwrap().push(*p))),
        ..RunOptions::default()
    };
    let r = run(&o).expect("BP1-QD run");
    let ev = &r.catalogue.events;
    assert!(ev.len() >= 4, "{} events", ev.len());
    let seen = seen.lock().unwrap();
    assert!(seen.len() >= 4 && seen.windows(2).all(|w| w[1].years >= w[0].years), "{} reports", seen.len());
    assert_eq!(seen.last().map(|p| p.events), Some(ev.len()));
    let on: Vec<f64> = ev.iter().map(|e| e.onset_s / YEAR).collect();
    println!("onsets {on:?}, steps {} ({} RHS) in {:.1} s", r.stats.accepted, r.stats.rhs_evals, r.wall_s);
    assert!((on[0] - 196.64).abs() < 0.5, "first event at {} yr", on[0]);
    for (k, anchor) in [(1, 75.66), (2, 77.88), (3, 78.36)] {
        let dt = on[k] - on[k - 1];
        assert!((dt / anchor - 1.0).abs() < 0.005, "interval {k}: {dt} yr against {anchor}");
    }
    for (i, e) in ev.iter().enumerate().take(4) {
        let (peak, slip) = if i == 0 { (4.48, 2.84) } else { (4.14, 2.47) };
        assert!((e.peak_v / peak - 1.0).abs() < 0.06, "event {i}: peak {} m/s", e.peak_v);
        assert!((e.surface_slip / slip - 1.0).abs() < 0.02, "event {i}: surface slip {} m", e.surface_slip);
        assert!((12.5e3..13.6e3).contains(&e.nucleation_depth_m), "event {i}: nucleation {} m", e.nucleation_depth_m);
    }
    // in the periodic regime the surface slips V_p T per cycle: what the plate delivers
    let t = (on[3] - on[2]) * YEAR;
    assert!((ev[3].surface_slip / (1e-9 * t) - 1.0).abs() < 0.01, "slip {} vs Vp T {}", ev[3].surface_slip, 1e-9 * t);
    // the files: the catalogue header and 12 stations
    let csv = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    assert!(csv.starts_with("onset_yr,peak_slip_rate_m_s,surface_slip_m,nucleation_depth_km\n"));
    assert_eq!(csv.lines().count(), ev.len() + 1);
    for z in ["000", "025", "050", "075", "100", "125", "150", "175", "200", "250", "300", "350"] {
        let s = std::fs::read_to_string(dir.join(format!("fltst_dp{z}"))).unwrap();
        assert!(s.lines().count() > 1000, "station {z}");
    }
}

#[test]
fn bad_options_are_refused() {
    for o in [
        RunOptions { cells: 2, ..RunOptions::default() },
        RunOptions { years: -1.0, ..RunOptions::default() },
        RunOptions { rtol: 0.0, ..RunOptions::default() },
    ] {
        assert!(run(&o).is_err());
    }
}
