//! Whittle's likelihood for a spectrum that is a sum of three shapes (white, AR(1), a power
//! law) with non-negative amplitudes: the periodogram, the likelihood of binned ordinates, the
//! amplitudes by scoring, their standard errors, and the small linear algebra they need. Shared
//! by the noise model in sample index (`noise.rs`) and in time (`sampling.rs`).

use rustfft::num_complex::Complex;

/// Whittle scoring iterations per grid point (converged to < 1e-6 in the amplitudes well before).
const SCORING_ITERATIONS: usize = 12;
/// The share of a stretch tapered at each end before its periodogram (a Tukey window of 20 %:
/// its variance inflation is 1.1, its sidelobes fall as 1/f³).
pub(super) const TAPER_SHARE: f64 = 0.1;

/// The AR(1) spectrum of unit variance at `f` cycles per sample (0 for φ = 0).
pub(super) fn ar1_shape(f: f64, phi: f64) -> f64 {
    if phi > 0.0 { (1.0 - phi * phi) / (1.0 - 2.0 * phi * (std::f64::consts::TAU * f).cos() + phi * phi) } else { 0.0 }
}

/// |DFT|²/n at the frequencies j/n, j = 1..=n/2.
pub(super) fn periodogram(r: &[f64]) -> Vec<f64> {
    let n = r.len();
    let mean = r.iter().sum::<f64>() / n as f64;
    let mut buf: Vec<Complex<f64>> = r.iter().map(|x| Complex::new(x - mean, 0.0)).collect();
    super::fft::plan(n, rustfft::FftDirection::Forward).process(&mut buf);
    (1..=n / 2).map(|j| buf[j].norm_sqr() / n as f64).collect()
}

/// −Whittle log-likelihood of binned power under amplitudes `a` of the basis.
pub(super) fn whittle(b: &[(f64, f64, f64)], x: &[[f64; 3]], a: &[f64; 3]) -> f64 {
    b.iter()
        .zip(x)
        .map(|(&(_, ibar, m), xb)| {
            let s = (a[0] * xb[0] + a[1] * xb[1] + a[2] * xb[2]).max(1e-300);
            m * (s.ln() + ibar / s)
        })
        .sum()
}

/// The non-negative amplitudes that maximise the Whittle likelihood for one shape, by scoring
/// over each subset of the three parts; returns them and −log-likelihood plus the BIC
/// penalty of the parts used (`penalty` per parameter: an AR or drift part costs two, its
/// amplitude and its shape), so that a part is kept only when the spectrum needs it — a chance
/// excess in the few lowest ordinates must not become a drift.
pub(super) fn amplitudes(
    b: &[(f64, f64, f64)],
    x: &[[f64; 3]],
    var: f64,
    has_ar: bool,
    penalty: f64,
) -> ([f64; 3], f64) {
    let white = ([var, 0.0, 0.0], whittle(b, x, &[var, 0.0, 0.0]) + penalty);
    match amplitudes_where(b, x, var, &|mask| has_ar || mask & 2 == 0, penalty) {
        Some(best) if best.1 < white.1 => best,
        _ => white,
    }
}

/// [`amplitudes`] over the subsets of parts `allowed` admits (a bit mask: 1 white, 2 AR, 4
/// drift); `None` when none of them has a solution.
pub(super) fn amplitudes_where(
    b: &[(f64, f64, f64)],
    x: &[[f64; 3]],
    var: f64,
    allowed: &dyn Fn(u8) -> bool,
    penalty: f64,
) -> Option<([f64; 3], f64)> {
    let cost = |a: &[f64; 3]| {
        let k = 1 + 2 * usize::from(a[1] > 0.0) + 2 * usize::from(a[2] > 0.0);
        whittle(b, x, a) + penalty * k as f64
    };
    let mut best: Option<([f64; 3], f64)> = None;
    for mask in 1u8..8 {
        if !allowed(mask) {
            continue;
        }
        let on: Vec<usize> = (0..3).filter(|k| mask & (1 << k) != 0).collect();
        let mut a = [0.0; 3];
        for &k in &on {
            a[k] = var / on.len() as f64;
        }
        let mut ok = true;
        for _ in 0..SCORING_ITERATIONS {
            // weighted normal equations: Σ m/S² x xᵀ a = Σ m/S² x Ī
            let mut h = [[0.0; 3]; 3];
            let mut g = [0.0; 3];
            for (&(_, ibar, m), xb) in b.iter().zip(x) {
                let s = (a[0] * xb[0] + a[1] * xb[1] + a[2] * xb[2]).max(1e-300);
                let w = m / (s * s);
                for &i in &on {
                    g[i] += w * xb[i] * ibar;
                    for &j in &on {
                        h[i][j] += w * xb[i] * xb[j];
                    }
                }
            }
            let Some(sol) = solve_small(&h, &g, &on) else {
                ok = false;
                break;
            };
            if on.iter().any(|&k| !(sol[k] > 0.0)) {
                ok = false;
                break;
            }
            a = sol;
        }
        if ok {
            let v = cost(&a);
            if best.is_none_or(|(_, bv)| v < bv) {
                best = Some((a, v));
            }
        }
    }
    best
}

/// Standard errors of the amplitudes `a` from their Fisher information Σ m x_i x_j / S² (NaN
/// for a part not used).
pub(super) fn amplitude_stderr(b: &[(f64, f64, f64)], x: &[[f64; 3]], a: &[f64; 3]) -> [f64; 3] {
    let mut info = [[0.0; 3]; 3];
    for (&(_, _, m), xb) in b.iter().zip(x) {
        let s = (a[0] * xb[0] + a[1] * xb[1] + a[2] * xb[2]).max(1e-300);
        for i in 0..3 {
            for j in 0..3 {
                info[i][j] += m * xb[i] * xb[j] / (s * s);
            }
        }
    }
    let on: Vec<usize> = (0..3).filter(|&k| a[k] > 0.0).collect();
    let mut se = [f64::NAN; 3];
    for &k in &on {
        let mut e = [0.0; 3];
        e[k] = 1.0;
        if let Some(c) = solve_small(&info, &e, &on) {
            se[k] = c[k].max(0.0).sqrt();
        }
    }
    se
}

/// Σ_{j=1}^{n/2} j^(−β) · 2/n: the share of a power-law part of unit amplitude (at the lowest
/// of n Fourier frequencies) in the variance — exact for the first terms, the integral beyond.
pub(super) fn power_law_variance(n: f64, beta: f64) -> f64 {
    const EXACT_TERMS: usize = 2000;
    let half = (n / 2.0).floor();
    let exact = (half as usize).min(EXACT_TERMS);
    let mut sum: f64 = (1..=exact).map(|j| (j as f64).powf(-beta)).sum();
    if half > exact as f64 {
        let (lo, hi) = (exact as f64 + 0.5, half + 0.5);
        sum += if (beta - 1.0).abs() < 1e-12 {
            (hi / lo).ln()
        } else {
            (hi.powf(1.0 - beta) - lo.powf(1.0 - beta)) / (1.0 - beta)
        };
    }
    sum * 2.0 / n
}

/// Solves the rows/columns `on` of h a = g (at most 3×3) by Gaussian elimination.
pub(super) fn solve_small(h: &[[f64; 3]; 3], g: &[f64; 3], on: &[usize]) -> Option<[f64; 3]> {
    let k = on.len();
    let mut m = [[0.0; 4]; 3];
    for (r, &i) in on.iter().enumerate() {
        for (c, &j) in on.iter().enumerate() {
            m[r][c] = h[i][j];
        }
        m[r][3] = g[i];
    }
    for c in 0..k {
        let p = (c..k).max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs()))?;
        m.swap(c, p);
        if !(m[c][c].abs() > 1e-300) {
            return None;
        }
        for r in 0..k {
            if r != c {
                let f = m[r][c] / m[c][c];
                for cc in c..4 {
                    m[r][cc] -= f * m[c][cc];
                }
            }
        }
    }
    let mut out = [0.0; 3];
    for (r, &i) in on.iter().enumerate() {
        out[i] = m[r][3] / m[r][r];
    }
    Some(out)
}

/// Standard error of a grid parameter from the profile likelihood's curvature at the best
/// point (NaN at the grid's edge or where the curvature is not positive).
pub(super) fn grid_stderr(grid: &[f64], nll: &[f64], i: usize) -> f64 {
    if i == 0 || i + 1 >= grid.len() {
        return f64::NAN;
    }
    let (x0, x1, x2) = (grid[i - 1], grid[i], grid[i + 1]);
    let (y0, y1, y2) = (nll[i - 1], nll[i], nll[i + 1]);
    // second derivative of a parabola through three unevenly spaced points
    let d2 = 2.0 * ((y2 - y1) / (x2 - x1) - (y1 - y0) / (x1 - x0)) / (x2 - x0);
    if d2 > 0.0 { (1.0 / d2).sqrt() } else { f64::NAN }
}

/// The periodogram of `x` (mean removed) after a split cosine bell taper of
/// [`TAPER_SHARE`] at each end, normalised by Σw² so that white noise keeps its level; and the
/// worth of one ordinate in independent ordinates, (Σw²)²/(n Σw⁴). The taper keeps a short
/// stretch's lowest ordinates from the leakage of the steep spectrum below them (a rectangular
/// window's sidelobes fall as 1/f² only; in a 8 s burst of OU noise with τ = 3 s they read as
/// drift).
pub(super) fn tapered_periodogram(x: &[f64]) -> (Vec<f64>, f64) {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let edge = ((n as f64 * TAPER_SHARE).round() as usize).max(1);
    let w = |i: usize| -> f64 {
        let k = i.min(n - 1 - i);
        if k >= edge { 1.0 } else { 0.5 * (1.0 - (std::f64::consts::PI * (k as f64 + 0.5) / edge as f64).cos()) }
    };
    let (s2, s4) = (0..n).fold((0.0, 0.0), |(a, b), i| (a + w(i).powi(2), b + w(i).powi(4)));
    let y: Vec<f64> = x.iter().enumerate().map(|(i, v)| (v - mean) * w(i)).collect();
    let p = periodogram(&y).into_iter().map(|v| v * n as f64 / s2).collect();
    (p, s2 * s2 / (n as f64 * s4))
}
