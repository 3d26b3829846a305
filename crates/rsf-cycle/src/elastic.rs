//! The elastic interaction of a 2-D antiplane fault in a half-space with a free surface.
//!
//! Uniform slip δ on the cell [z1, z2] of a vertical fault changes the shear stress at depth z
//! on the fault by `K(z) δ` with (a screw-dislocation pair and its image above the free surface)
//!
//! `K(z) = μ/(2π) [ 1/(z − z2) − 1/(z − z1) + 1/(z + z1) − 1/(z + z2) ]`,
//!
//! negative on the cell itself (slip unloads it). The fault below W_f creeps at exactly V_p, so
//! in terms of the slip deficit δ − V_p t it contributes nothing, and the stressing rate is
//! `dτ_i/dt = Σ_j K_ij (V_j − V_p)`. The N × N matrix is dense (faer) and the product one
//! BLAS-2 call per right-hand side.

use faer::{Accum, Mat, Par};

/// The dense kernel of `n` equal cells over [0, depth].
pub struct Kernel {
    k: Mat<f64>,
    x: Mat<f64>,
    y: Mat<f64>,
}

impl Kernel {
    /// The kernel for shear modulus `mu` (Pa) and `n` cells of size `depth / n` (m).
    pub fn new(mu: f64, depth: f64, n: usize) -> Self {
        let dz = depth / n as f64;
        let c = mu / (2.0 * std::f64::consts::PI);
        let k = Mat::from_fn(n, n, |i, j| {
            let z = (i as f64 + 0.5) * dz;
            let (z1, z2) = (j as f64 * dz, (j as f64 + 1.0) * dz);
            c * (1.0 / (z - z2) - 1.0 / (z - z1) + 1.0 / (z + z1) - 1.0 / (z + z2))
        });
        Self { k, x: Mat::zeros(n, 1), y: Mat::zeros(n, 1) }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.k.nrows()
    }

    /// Whether there are no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// `out = K (v − vp)`: the stressing rate, Pa/s, from the slip rates `v` (m/s).
    pub fn stressing_rate(&mut self, v: &[f64], vp: f64, out: &mut [f64]) {
        for (i, vi) in v.iter().enumerate() {
            self.x[(i, 0)] = vi - vp;
        }
        faer::linalg::matmul::matmul(self.y.as_mut(), Accum::Replace, self.k.as_ref(), self.x.as_ref(), 1.0, Par::Seq);
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.y[(i, 0)];
        }
    }

    /// One element of the matrix, Pa/m.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.k[(i, j)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform slip over the whole fault, with nothing below: the stress field of a surface-
    /// breaking screw dislocation pair, K·1 at depth z = μ/(2π)·(1/(z − W) − 1/(z + W))·… — and
    /// the mat-vec agrees with a plain loop.
    #[test]
    fn kernel_signs_and_matvec() {
        let (mu, w, n) = (32e9, 40e3, 64);
        let mut k = Kernel::new(mu, w, n);
        for i in 0..n {
            assert!(k.get(i, i) < 0.0, "self-stress must be negative");
            if i + 1 < n {
                assert!(k.get(i, i + 1) > 0.0, "a neighbour's slip loads");
            }
        }
        // uniform slip on [0, W] with its image: the dislocations at ±W only
        let z = (3.0 + 0.5) * w / n as f64;
        let sum: f64 = (0..n).map(|j| k.get(3, j)).sum();
        let exact = mu / (2.0 * std::f64::consts::PI) * (1.0 / (z - w) - 1.0 / (z + w));
        assert!((sum - exact).abs() < 1e-9 * exact.abs(), "{sum} vs {exact}");
        let v: Vec<f64> = (0..n).map(|i| 1e-9 * (1.0 + i as f64)).collect();
        let mut out = vec![0.0; n];
        k.stressing_rate(&v, 1e-9, &mut out);
        for i in [0, 17, 63] {
            let plain: f64 = (0..n).map(|j| k.get(i, j) * (v[j] - 1e-9)).sum();
            assert!((out[i] - plain).abs() < 1e-9 * plain.abs().max(1e-30), "{i}: {} vs {plain}", out[i]);
        }
    }
}
