//! Coefficient tables of the built-in methods, each with its source. The steppers
//! (`rosenbrock.rs`, `erk.rs`) are written once against these tables.

pub(crate) mod rodas4;
pub(crate) mod rodas5p;
pub(crate) mod tsit5;

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
