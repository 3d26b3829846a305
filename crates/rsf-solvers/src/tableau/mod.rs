//! Coefficient tables of the built-in methods, each with its source. The steppers
//! (`rosenbrock.rs`, `erk.rs`) are written once against these tables.

pub(crate) mod rodas4;
pub(crate) mod rodas5p;
pub(crate) mod tsit5;
pub(crate) mod vern6;

/// A stiffly accurate Rosenbrock method of `S` stages in the increment form of Hairer &
/// Wanner (Solving ODEs II, IV.7, eq. 7.4'), for an autonomous system:
///
/// `(I/(hγ) − J) k_i = f(y0 + Σ_{j<i} a_ij k_j) + Σ_{j<i} (c_ij/h) k_j`,
///
/// `y1 = y0 + Σ_j a_sj k_j + k_s` (the last stage's argument plus its increment: stiffly
/// accurate), error estimate `k_s`, and the dense output of `R` rows
/// `y(θ) = (1−θ) y0 + θ (y1 + (1−θ)(K_1 + θ (K_2 + θ (… K_R))))`, `K_r = Σ_i h_ri k_i`.
pub(crate) struct RosenbrockTableau<const S: usize, const R: usize> {
    /// Diagonal γ.
    pub gamma: f64,
    /// Transformed a_ij (row i = stage i; strictly lower triangular).
    pub a: [[f64; S]; S],
    /// Transformed c_ij (strictly lower triangular).
    pub c: [[f64; S]; S],
    /// Dense-output rows h_ri.
    pub h: [[f64; S]; R],
    /// Order of the embedded estimate + 1: the step-size exponent is its inverse.
    pub err_order: f64,
}

impl<const S: usize, const R: usize> RosenbrockTableau<S, R> {
    /// The stage nodes c_i = Σ_j α_ij and the sums d_i = Σ_j γ_ij (diagonal included) of the
    /// original coefficients, for time-dependent systems: stage i is evaluated at t + c_i h and
    /// gets h d_i ∂f/∂t. Recovered from the transformed table (Γ⁻¹ = diag(1/γ) − C, α = A Γ)
    /// rather than typed in a second time.
    pub(crate) fn nodes(&self) -> ([f64; S], [f64; S]) {
        // Γ⁻¹ is lower triangular with 1/γ on the diagonal: invert by forward substitution
        let mut ginv = [[0.0; S]; S];
        for i in 0..S {
            for j in 0..i {
                ginv[i][j] = -self.c[i][j];
            }
            ginv[i][i] = 1.0 / self.gamma;
        }
        let mut g = [[0.0; S]; S];
        for col in 0..S {
            for i in col..S {
                let mut acc = if i == col { 1.0 } else { 0.0 };
                for k in col..i {
                    acc -= ginv[i][k] * g[k][col];
                }
                g[i][col] = acc / ginv[i][i];
            }
        }
        let mut c = [0.0; S];
        let mut d = [0.0; S];
        for i in 0..S {
            d[i] = g[i].iter().sum();
            // α = A Γ (A strictly lower triangular)
            c[i] = (0..S).map(|k| self.a[i][k] * g[k].iter().sum::<f64>()).sum();
        }
        (c, d)
    }
}

#[cfg(test)]
mod tests {
    /// Hairer & Wanner's RODAS4 nodes and γ sums (rodas.f: C2..C4, D1..D4), recovered from the
    /// transformed table; Rodas5P's last stages at c = 1 with d = 0 (stiffly accurate).
    #[test]
    fn nodes_match_the_published_values() {
        let (c, d) = super::rodas4::RODAS4.nodes();
        let c_ref = [0.0, 0.386, 0.21, 0.63, 1.0, 1.0];
        let d_ref = [0.25, -0.1043, 0.1035, -0.3620000000000023e-01, 0.0, 0.0];
        for i in 0..6 {
            assert!((c[i] - c_ref[i]).abs() < 1e-12, "c{}: {} vs {}", i + 1, c[i], c_ref[i]);
            assert!((d[i] - d_ref[i]).abs() < 1e-12, "d{}: {} vs {}", i + 1, d[i], d_ref[i]);
        }
        let (c, d) = super::rodas5p::RODAS5P.nodes();
        assert_eq!(c[0], 0.0);
        assert!((d[0] - super::rodas5p::RODAS5P.gamma).abs() < 1e-15);
        for i in 5..8 {
            assert!((c[i] - 1.0).abs() < 1e-12 && d[i].abs() < 1e-12, "stage {}: c {} d {}", i + 1, c[i], d[i]);
        }
        for i in 1..5 {
            assert!(c[i] > 0.0 && c[i] < 1.0, "c{} = {}", i + 1, c[i]);
        }
    }
}
