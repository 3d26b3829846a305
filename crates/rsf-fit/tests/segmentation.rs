//! Exact segmentation of lab-like load-point records: breaks at the sample where the load point
//! starts or stops moving, holds of exactly zero velocity (in the middle and at the end of a
//! record), holds of 10–10⁴ s, 1 Hz holds beside 10 Hz sliding and 100 Hz bursts after each
//! change, time jitter, non-zero start times, and load-point encoder noise of 0.05–0.2 µm.
//!
//! On the main branch before the exact break refinement, 13 of the 60 clean records below were
//! segmented wrongly (a hold ending one or two samples late and called a `step-down` at
//! 1e-7–1e-4 µm/s, or a ramp segment left between a 1 Hz hold and a 100 Hz reslide).

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use rsf_fit::segment::{SegmentKind, SegmentOptions, detect};

/// Load point at time t of a protocol of (v µm/s, duration s) from x = 0 at t = 0.
fn lp_at(proto: &[(f64, f64)], t: f64) -> f64 {
    let (mut tc, mut xc) = (0.0, 0.0);
    for &(v, d) in proto {
        if t <= tc + d {
            return xc + v * (t - tc);
        }
        tc += d;
        xc += v * d;
    }
    xc
}

/// A bare-rock protocol: 1 µm/s, steps down 0.5–3.5 decades or up 0.5–1.5, each followed by 40 µm at 1 µm/s,
/// then holds of 10–10⁴ s each followed by a 40 µm reslide (the record ends in a reslide).
fn protocol(rng: &mut ChaCha8Rng) -> Vec<(f64, f64)> {
    let mut proto = vec![(1.0, 60.0)];
    for _ in 0..rng.random_range(1..4) {
        // down by 0.5–3.5 decades, or up by 0.5–1.5
        let v: f64 = if rng.random_bool(0.6) {
            10f64.powf(-rng.random_range(0.5..3.5))
        } else {
            10f64.powf(rng.random_range(0.5..1.5))
        };
        // at least 20 µm and 4 s (40 samples at 10 Hz) of sliding
        proto.push((v, (20.0 / v).clamp(4.0, 3000.0)));
        proto.push((1.0, 40.0));
    }
    for _ in 0..rng.random_range(1..4) {
        proto.push((0.0, 10f64.powf(rng.random_range(1.0..4.0))));
        proto.push((1.0, 40.0));
    }
    proto
}

/// A gouge staircase on a soft machine: 1, 3, 10, 30, 100, 300 µm/s for 5–7 Dc each (Dc 10–60
/// µm: the 300 µm/s step lasts 0.2–1.4 s, 4–28 samples at 20 Hz), 10 µm/s, then holds of 3–300
/// s each followed by 5 Dc at 10 µm/s.
fn gouge_staircase(rng: &mut ChaCha8Rng) -> Vec<(f64, f64)> {
    let dc = 10f64.powf(rng.random_range(1.0..1.78));
    let mut proto: Vec<(f64, f64)> =
        [1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 10.0].iter().map(|&v| (v, rng.random_range(5.0..7.0) * dc / v)).collect();
    for h in [3.0, 10.0, 30.0, 100.0, 300.0] {
        if rng.random_bool(0.6) {
            proto.push((0.0, h));
            proto.push((10.0, 5.0 * dc / 10.0));
        }
    }
    proto
}

/// A bare-rock record sampled at 1 Hz with short changes: 1 µm/s, a step up by half a decade to
/// a decade for 10–20 s (10–20 samples), back to 1 µm/s, a slow step down, and holds of 10, 30
/// and 100 s between 50 s of sliding.
fn short_rock_steps(rng: &mut ChaCha8Rng) -> Vec<(f64, f64)> {
    let up = 10f64.powf(rng.random_range(0.5..1.0));
    vec![
        (1.0, 50.0),
        (0.1, 300.0),
        (1.0, 50.0),
        (up, rng.random_range(10.0f64..20.0).round()),
        (1.0, 60.0),
        (0.001, 1500.0),
        (1.0, 50.0),
        (0.0, 10.0),
        (1.0, 50.0),
        (0.0, 30.0),
        (1.0, 50.0),
        (0.0, 100.0),
        (1.0, 50.0),
    ]
}

/// Samples `proto` every `dt.0` s while sliding and `dt.1` s in holds, optionally 100 Hz for 5 s after each change,
/// optionally ±1% time jitter; start time t0; Gaussian encoder noise `enc` µm.
fn sample(
    proto: &[(f64, f64)],
    rng: &mut ChaCha8Rng,
    burst: bool,
    jitter: bool,
    t0: f64,
    enc: f64,
    (dt_moving, dt_hold): (f64, f64),
) -> (Vec<f64>, Vec<f64>) {
    let ends: Vec<f64> = proto
        .iter()
        .scan(0.0, |s, p| {
            *s += p.1;
            Some(*s)
        })
        .collect();
    let total = ends[ends.len() - 1];
    let (mut t, mut x) = (vec![], vec![]);
    let mut tt = 0.0;
    while tt <= total {
        t.push(t0 + tt);
        let z: f64 = StandardNormal.sample(rng);
        x.push(lp_at(proto, tt) + enc * z);
        let k = ends.iter().position(|&e| tt < e).unwrap_or(ends.len() - 1);
        let since = if k == 0 { f64::INFINITY } else { tt - ends[k - 1] };
        let dt = if burst && since < 5.0 {
            0.01
        } else if proto[k].0 == 0.0 {
            dt_hold
        } else {
            dt_moving
        };
        tt += dt * if jitter { 1.0 + rng.random_range(-0.01..0.01) } else { 1.0 };
    }
    (t, x)
}

/// Segments `n` random records with encoder noise `enc` and checks kinds, velocities and breaks:
/// exact on a clean record, within 4σ/|Δv| + one sample interval with noise.
fn check(enc: f64, n: usize, seed: u64) {
    check_protocols(protocol, (0.1, 1.0), true, enc, n, seed);
}

/// `check` for records of `make` sampled every `dt.0` s while moving and `dt.1` s in holds, with 100 Hz bursts
/// after changes on every other record when `bursts`.
fn check_protocols(
    make: fn(&mut ChaCha8Rng) -> Vec<(f64, f64)>,
    dt: (f64, f64),
    bursts: bool,
    enc: f64,
    n: usize,
    seed: u64,
) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut failures = vec![];
    for case in 0..n {
        let proto = make(&mut rng);
        let (burst, jitter) = (bursts && case % 2 == 1, case % 4 == 2);
        let t0 = if case % 3 == 0 { 12345.678 } else { 0.0 };
        let (t, x) = sample(&proto, &mut rng, burst, jitter, t0, enc, dt);
        let segs = detect(&t, &x, &SegmentOptions::default());
        let breaks: Vec<f64> = proto
            .iter()
            .scan(0.0, |s, p| {
                *s += p.1;
                Some(*s)
            })
            .collect();
        let mut ok = segs.len() == proto.len();
        for (k, (s, p)) in segs.iter().zip(&proto).enumerate() {
            // holds are exactly zero; moving velocities exact (clean) or within 5% (noisy)
            let v_ok = if p.0 == 0.0 {
                s.v == 0.0 && (k == 0 || s.kind == SegmentKind::Hold)
            } else if enc == 0.0 {
                (s.v / p.0 - 1.0).abs() < 1e-6
            } else {
                (s.v / p.0 - 1.0).abs() < 0.05
            };
            ok &= v_ok;
            if k > 0 {
                let dv = (p.0 - proto[k - 1].0).abs();
                let tol = if enc == 0.0 { 1e-6 } else { 4.0 * enc / dv + 0.1 };
                ok &= (s.t0 - t0 - breaks[k - 1]).abs() < tol;
                // the break lies between the segment's first sample and the one before
                ok &= t[s.i0 - 1] <= s.t0 && s.t0 <= t[s.i0];
            }
        }
        if !ok {
            failures.push(format!("case {case} (burst {burst}, jitter {jitter}): {proto:?}\n{segs:#?}"));
        }
    }
    assert!(failures.is_empty(), "{} of {n} records segmented wrongly:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn clean_load_points_are_segmented_exactly() {
    check(0.0, 60, 1);
}

#[test]
fn encoder_noise_of_005_um() {
    check(0.05, 40, 2);
}

#[test]
fn encoder_noise_of_02_um() {
    check(0.2, 40, 3);
}

/// Short changes (issue 9's false alarms): a 300 µm/s step of a few samples in a gouge
/// staircase, a 3–10 µm/s step of 10–20 samples at 1 Hz and a 10 s hold at 1 Hz were merged
/// with their neighbours into one segment of an average velocity no protocol had. On the main branch before the
/// misfit split (segment/split.rs), 16 of 40 clean staircases, 12 of 40 with encoder noise and
/// 40 of 40 of the 1 Hz rock records failed.
#[test]
fn short_fast_steps_clean() {
    check_protocols(gouge_staircase, (0.05, 0.05), false, 0.0, 40, 4);
}

#[test]
fn short_steps_and_holds_at_1_hz() {
    check_protocols(short_rock_steps, (1.0, 1.0), false, 0.0, 40, 5);
}

#[test]
fn short_fast_steps_with_encoder_noise() {
    check_protocols(gouge_staircase, (0.05, 0.05), false, 0.15, 40, 6);
}

/// The failing record of issue 9: 10 Hz throughout, the record ends with a 3000 s hold and a
/// 40 µm reslide at 1 µm/s; the hold must end at the exact sample, with zero velocity.
#[test]
fn a_long_hold_at_the_end_of_a_record() {
    let proto = [
        (1.0, 60.0),
        (10.0, 10.0),
        (1.0, 80.0),
        (0.1, 300.0),
        (1.0, 60.0),
        (0.0, 100.0),
        (1.0, 60.0),
        (0.0, 1000.0),
        (1.0, 60.0),
        (0.0, 3000.0),
        (1.0, 40.0),
    ];
    let total: f64 = proto.iter().map(|p| p.1).sum();
    let n = (total / 0.1).round() as usize;
    let t: Vec<f64> = (0..=n).map(|i| 1000.0 + total * i as f64 / n as f64).collect();
    let x: Vec<f64> = t.iter().map(|&ti| lp_at(&proto, ti - 1000.0)).collect();
    let segs = detect(&t, &x, &SegmentOptions::default());
    assert_eq!(segs.len(), proto.len(), "{segs:#?}");
    let last_hold = &segs[9];
    assert_eq!(last_hold.kind, SegmentKind::Hold);
    assert_eq!(last_hold.v, 0.0);
    assert!((last_hold.t0 - 2730.0).abs() < 1e-6 && (last_hold.t1 - 5730.0).abs() < 1e-6, "{last_hold:?}");
    assert!((segs[10].t0 - 5730.0).abs() < 1e-6 && (segs[10].v - 1.0).abs() < 1e-9, "{:?}", segs[10]);
}

/// With encoder noise the best split is good only to the samples within σ_x/|Δv| of a break — a
/// sample or more — while the two segments' lines, each fitted on hundreds of samples, cross
/// within a fraction of that; every break misplaced by δt misplaces the friction's transient by
/// k·|Δv|·δt. Breaks of 40 records (0.2 µm encoder noise, 10 Hz sliding, 1 Hz holds, breaks
/// between samples) are placed to within a fifth of σ_x/|Δv| at the median and within half of
/// it at the 95th percentile. On the main before the crossing (the split's sample interval, the
/// crossing clamped into it) the median was 0.37 and the 95th percentile 1.8 (now 0.08 and 0.40, at most 0.74).
#[test]
fn noisy_breaks_are_placed_where_the_lines_cross() {
    let (enc, n) = (0.2, 40);
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut z = vec![];
    for _ in 0..n {
        let proto = protocol(&mut rng);
        let (t, x) = sample(&proto, &mut rng, false, false, 0.0, enc, (0.1, 1.0));
        let segs = detect(&t, &x, &SegmentOptions::default());
        assert_eq!(segs.len(), proto.len(), "{proto:?}\n{segs:#?}");
        let mut end = 0.0;
        for (k, s) in segs.iter().enumerate().skip(1) {
            end += proto[k - 1].1;
            let dv = (proto[k].0 - proto[k - 1].0).abs();
            z.push((s.t0 - end).abs() / (enc / dv));
            assert!(t[s.i0 - 1] <= s.t0 && s.t0 <= t[s.i0], "{s:?}");
        }
    }
    z.sort_by(f64::total_cmp);
    let (median, p95) = (z[z.len() / 2], z[z.len() * 95 / 100]);
    eprintln!(
        "{} breaks: |error| / (σ_x/|Δv|) median {median:.3}, 95th percentile {p95:.3}, max {:.3}",
        z.len(),
        z[z.len() - 1]
    );
    assert!(median < 0.2 && p95 < 0.5, "median {median}, 95th percentile {p95}");
}
