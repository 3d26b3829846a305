//! Small numerical tools shared by the figures: sampling grids, interpolation, the running
//! mean in slip, extrema and straight-line fits.

use serde::Serialize;

/// `n ≥ 2` points geometrically spaced from `lo` to `hi` (both > 0, included).
pub fn log_grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let (l0, l1) = (lo.ln(), hi.ln());
    let mut g: Vec<f64> = (0..n).map(|i| (l0 + (l1 - l0) * i as f64 / (n - 1) as f64).exp()).collect();
    // exact end points (exp∘ln is not the identity in floating point)
    g[0] = lo;
    g[n - 1] = hi;
    g
}

/// `n ≥ 2` points evenly spaced from `lo` to `hi` (included).
pub fn lin_grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let mut g: Vec<f64> = (0..n).map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64).collect();
    g[n - 1] = hi;
    g
}

/// Output times on `[0, t_end]` that resolve both the fast start of a transient and its long
/// tail: `n` evenly spaced times merged with `n` geometrically spaced ones from `t_fast` to
/// `t_end`, sorted, without duplicates, starting at 0.
pub fn transient_times(t_fast: f64, t_end: f64, n: usize) -> Vec<f64> {
    let mut t = lin_grid(0.0, t_end, n);
    t.extend(log_grid(t_fast, t_end, n));
    t.sort_by(f64::total_cmp);
    t.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * b.abs().max(1e-300));
    t
}

/// Linear interpolation of `y(x)` at `xq`, for `x` strictly increasing; `xq` outside
/// `[x_0, x_last]` is clamped to the end values.
pub fn interp(x: &[f64], y: &[f64], xq: f64) -> f64 {
    let n = x.len();
    if xq <= x[0] {
        return y[0];
    }
    if xq >= x[n - 1] {
        return y[n - 1];
    }
    let i = x.partition_point(|&v| v <= xq); // x[i-1] <= xq < x[i]
    let w = (xq - x[i - 1]) / (x[i] - x[i - 1]);
    y[i - 1] + w * (y[i] - y[i - 1])
}

/// Centred running mean of `y` sampled on the evenly spaced grid `x` over a window of total
/// width `width` (same unit as `x`); near the ends the window is truncated to the samples
/// available. This is the smoothing the paper applies to its records (0.2 µm of slip after
/// decreases, 0.4 µm after increases).
pub fn running_mean(x: &[f64], y: &[f64], width: f64) -> Vec<f64> {
    let n = y.len();
    if n < 2 {
        return y.to_vec();
    }
    let h = (x[n - 1] - x[0]) / (n - 1) as f64;
    let half = (0.5 * width / h).round() as usize;
    // prefix sums: the mean of y[lo..hi] is (c[hi] − c[lo]) / (hi − lo)
    let mut c = vec![0.0; n + 1];
    for i in 0..n {
        c[i + 1] = c[i] + y[i];
    }
    (0..n)
        .map(|i| {
            let lo = i.saturating_sub(half);
            let hi = (i + half + 1).min(n);
            (c[hi] - c[lo]) / (hi - lo) as f64
        })
        .collect()
}

/// An extremum of sampled data, refined by the parabola through the extreme sample and its
/// two neighbours (exact for a quadratic, error O(h³) for smooth data).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Extremum {
    /// Index of the extreme sample.
    pub index: usize,
    /// Abscissa of the refined extremum.
    pub x: f64,
    /// Refined extreme value.
    pub y: f64,
}

/// The minimum (`sign = 1`) or maximum (`sign = −1`) of `y(x)` over `x` strictly increasing.
pub fn extremum(x: &[f64], y: &[f64], sign: f64) -> Extremum {
    let i = (0..y.len()).min_by(|&i, &j| (sign * y[i]).total_cmp(&(sign * y[j]))).expect("non-empty data");
    if i == 0 || i + 1 == y.len() {
        return Extremum { index: i, x: x[i], y: y[i] };
    }
    let (x0, x1, x2) = (x[i - 1], x[i], x[i + 1]);
    let (y0, y1, y2) = (y[i - 1], y[i], y[i + 1]);
    // Newton divided differences: y = y0 + d1 (x − x0) + d2 (x − x0)(x − x1)
    let d1 = (y1 - y0) / (x1 - x0);
    let d2 = ((y2 - y1) / (x2 - x1) - d1) / (x2 - x0);
    if d2 * sign <= 0.0 {
        return Extremum { index: i, x: x1, y: y1 };
    }
    let xe = (0.5 * (x0 + x1 - d1 / d2)).clamp(x0, x2);
    Extremum { index: i, x: xe, y: y0 + d1 * (xe - x0) + d2 * (xe - x0) * (xe - x1) }
}

/// A least-squares straight line `y = intercept + slope x` with its coefficient of
/// determination R².
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LineFit {
    /// Slope, units of y per unit of x.
    pub slope: f64,
    /// Intercept.
    pub intercept: f64,
    /// Coefficient of determination.
    pub r2: f64,
}

/// Least-squares line through `(x_i, y_i)` (at least two distinct x).
pub fn line_fit(x: &[f64], y: &[f64]) -> LineFit {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    let syy: f64 = y.iter().map(|b| (b - my).powi(2)).sum();
    let slope = sxy / sxx;
    LineFit { slope, intercept: my - slope * mx, r2: if syy > 0.0 { sxy * sxy / (sxx * syy) } else { 1.0 } }
}

/// Indices of at most `n ≥ 2` of `len` samples, evenly spread over the index, the first and last
/// always kept (all of them when `len <= n`). Thinning picks samples, it never interpolates.
pub fn thin_indices(len: usize, n: usize) -> Vec<usize> {
    if len <= n || n < 2 {
        return (0..len).collect();
    }
    (0..n).map(|i| (i * (len - 1) + (n - 1) / 2) / (n - 1)).collect()
}

/// `v[i]` for every `i` of `idx`.
pub fn pick(v: &[f64], idx: &[usize]) -> Vec<f64> {
    idx.iter().map(|&i| v[i]).collect()
}

/// A curve `y(x)` for plots and CSV files.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Curve {
    /// Abscissae.
    pub x: Vec<f64>,
    /// Ordinates.
    pub y: Vec<f64>,
}

impl Curve {
    /// A curve from its columns.
    pub fn new(x: Vec<f64>, y: Vec<f64>) -> Self {
        debug_assert_eq!(x.len(), y.len());
        Self { x, y }
    }

    /// At most `n` samples kept, evenly spread over the index (see [`thin_indices`]): for
    /// curves that are already sampled evenly in the plotted coordinate.
    pub fn thinned(&self, n: usize) -> Self {
        let idx = thin_indices(self.x.len(), n);
        Self { x: pick(&self.x, &idx), y: pick(&self.y, &idx) }
    }

    /// The points as `(x, y)` pairs.
    pub fn points(&self) -> Vec<(f64, f64)> {
        self.x.iter().copied().zip(self.y.iter().copied()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extremum_is_exact_for_a_parabola() {
        let x = lin_grid(0.0, 1.0, 11);
        let y: Vec<f64> = x.iter().map(|v| 2.0 + 3.0 * (v - 0.437).powi(2)).collect();
        let e = extremum(&x, &y, 1.0);
        assert!((e.x - 0.437).abs() < 1e-12 && (e.y - 2.0).abs() < 1e-12, "{e:?}");
        let e = extremum(&x, &y.iter().map(|v| -v).collect::<Vec<_>>(), -1.0);
        assert!((e.x - 0.437).abs() < 1e-12 && (e.y + 2.0).abs() < 1e-12, "{e:?}");
    }

    #[test]
    fn running_mean_keeps_lines_and_interp_is_linear() {
        let x = lin_grid(0.0, 10.0, 101);
        let y: Vec<f64> = x.iter().map(|v| 1.0 + 2.0 * v).collect();
        let s = running_mean(&x, &y, 1.0);
        // a centred mean of a line is the line away from the ends
        for i in 5..96 {
            assert!((s[i] - y[i]).abs() < 1e-12);
        }
        assert!((interp(&x, &y, 3.33) - 7.66).abs() < 1e-12);
        let f = line_fit(&x, &y);
        assert!((f.slope - 2.0).abs() < 1e-12 && (f.intercept - 1.0).abs() < 1e-12 && (f.r2 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn grids_and_thinning() {
        let g = log_grid(1e-3, 10.0, 5);
        assert_eq!((g[0], g[4]), (1e-3, 10.0));
        assert!((g[1] - 1e-2).abs() < 1e-15);
        let t = transient_times(1e-3, 10.0, 11);
        assert_eq!(t[0], 0.0);
        assert!(t.windows(2).all(|w| w[1] > w[0]));
        let c = Curve::new(lin_grid(0.0, 1.0, 1001), lin_grid(0.0, 1.0, 1001)).thinned(11);
        assert_eq!(c.x.len(), 11);
        assert_eq!((c.x[0], c.x[10]), (0.0, 1.0));
    }
}
