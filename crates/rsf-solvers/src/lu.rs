//! LU factorisation with partial pivoting of a small dense matrix on the stack (the iteration
//! matrix `I/(hγ) − J` of the Rosenbrock methods, 3×3 … 10×10): our own because a generic
//! linear-algebra call costs more than the factorisation itself at these sizes.

use nalgebra::{SMatrix, SVector};

/// LU factorisation with partial pivoting of a small dense matrix, in place.
pub(crate) struct Lu<const D: usize> {
    m: SMatrix<f64, D, D>,
    piv: [usize; D],
}

impl<const D: usize> Lu<D> {
    pub(crate) fn new(mut m: SMatrix<f64, D, D>) -> Option<Self> {
        let mut piv = [0usize; D];
        for k in 0..D {
            let mut p = k;
            let mut best = m[(k, k)].abs();
            for i in k + 1..D {
                if m[(i, k)].abs() > best {
                    best = m[(i, k)].abs();
                    p = i;
                }
            }
            if best == 0.0 || !best.is_finite() {
                return None;
            }
            piv[k] = p;
            if p != k {
                m.swap_rows(p, k);
            }
            let inv = 1.0 / m[(k, k)];
            for i in k + 1..D {
                let l = m[(i, k)] * inv;
                m[(i, k)] = l;
                for j in k + 1..D {
                    m[(i, j)] -= l * m[(k, j)];
                }
            }
        }
        Some(Self { m, piv })
    }

    #[inline]
    pub(crate) fn solve(&self, mut b: SVector<f64, D>) -> SVector<f64, D> {
        for k in 0..D {
            b.swap_rows(k, self.piv[k]);
        }
        for i in 0..D {
            let mut s = b[i];
            for j in 0..i {
                s -= self.m[(i, j)] * b[j];
            }
            b[i] = s;
        }
        for i in (0..D).rev() {
            let mut s = b[i];
            for j in i + 1..D {
                s -= self.m[(i, j)] * b[j];
            }
            b[i] = s / self.m[(i, i)];
        }
        b
    }
}
