//! The seed-like protocol of the solver benchmarks (`bench_protocol`, `work_precision`), shared
//! by `#[path]`: from steady state at 3 µm/s, 16 step decreases and 13 increases of 0.5–3.5
//! decades (3 → V_f → 3 and 1 → V_f → 1), then holds of 10–10⁴ s from 1, 0.3 and 0.03 µm/s, each
//! with a reslide; every velocity segment lasts 20 µm of load-point travel. 71 segments.

/// The protocol as (v µm/s, duration s) segments.
pub fn seed_protocol() -> Vec<(f64, f64)> {
    let mut s: Vec<(f64, f64)> = Vec::new();
    let slide = |s: &mut Vec<(f64, f64)>, v: f64| s.push((v, 20.0 / v));
    let grid = [1.0, 0.3, 0.1, 0.03, 0.01, 0.003, 0.001];
    for &vf in &grid {
        slide(&mut s, vf);
        slide(&mut s, 3.0);
    }
    slide(&mut s, 1.0);
    for &vf in &grid[1..] {
        slide(&mut s, vf);
        slide(&mut s, 1.0);
    }
    for (i, &vi) in [1.0, 0.3, 0.03].iter().enumerate() {
        if i > 0 {
            slide(&mut s, vi);
        }
        for th in [10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0] {
            s.push((0.0, th));
            slide(&mut s, vi);
        }
    }
    s
}
