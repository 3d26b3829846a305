//! The per-element kernels over many elements at once, structure of arrays: one slice per
//! parameter and per variable, caller-owned outputs, no allocation, no coupling between
//! elements (the elastic interaction stays in the host). Elements are independent:
//! [`rates_parallel`] splits them into chunks over scoped threads (worth it from about 10^4
//! elements; a host with its own thread pool splits the slices the same way).

use crate::element::{SlipRateError, friction, ln_theta_rate, psi_term, solve_slip_rate};
use crate::{FrictionForm, StateLaw};

/// Per-element parameters of a one-state-variable fault, each slice of the same length.
#[derive(Clone, Copy, Debug)]
pub struct Elements<'a> {
    /// Reference friction f0 (μ0).
    pub f0: &'a [f64],
    /// Direct-effect parameter a.
    pub a: &'a [f64],
    /// Reference slip rate V0 (the host's velocity unit).
    pub v0: &'a [f64],
    /// Evolution-effect parameter b.
    pub b: &'a [f64],
    /// Characteristic slip distance Dc (the host's length unit).
    pub dc: &'a [f64],
}

/// Why a batch call refused its input or failed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BatchError {
    /// A slice's length differs from the number of elements (the named argument).
    Length(&'static str),
    /// Element `index` failed to solve.
    Element {
        /// Index of the element.
        index: usize,
        /// Why.
        error: SlipRateError,
    },
}

impl std::fmt::Display for BatchError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Length(name) => write!(f, "`{name}` has a different length from the element arrays"),
            Self::Element { index, error } => write!(f, "element {index}: {error}"),
        }
    }
}

impl std::error::Error for BatchError {}

impl Elements<'_> {
    /// Number of elements, after checking that every parameter slice has it.
    pub fn count(&self) -> Result<usize, BatchError> {
        let n = self.f0.len();
        for (name, s) in [("a", self.a), ("v0", self.v0), ("b", self.b), ("dc", self.dc)] {
            if s.len() != n {
                return Err(BatchError::Length(name));
            }
        }
        Ok(n)
    }
}

/// Every (name, length) equals `n`, or the first that does not is named.
fn same_lengths(n: usize, lens: &[(&'static str, usize)]) -> Result<(), BatchError> {
    match lens.iter().find(|(_, len)| *len != n) {
        Some((name, _)) => Err(BatchError::Length(name)),
        None => Ok(()),
    }
}

/// The lengths of `rates`' variable and output slices against the element count.
fn rate_lengths(n: usize, lens: [usize; 6]) -> Result<(), BatchError> {
    let names = ["ln_v", "ln_theta", "friction", "d_ln_v", "d_psi", "ln_theta_rate"];
    same_lengths(n, &std::array::from_fn::<_, 6, _>(|i| (names[i], lens[i])))
}

/// Friction, its partials and the state rate of every element: for element i at
/// `ln_v[i]`, `ln_theta[i]`, writes f, ∂f/∂ln V, ∂f/∂Ψ and d ln θ/dt into the output slices.
#[allow(clippy::too_many_arguments)]
pub fn rates<L: StateLaw>(
    form: FrictionForm,
    law: &L,
    p: &Elements,
    ln_v: &[f64],
    ln_theta: &[f64],
    friction_out: &mut [f64],
    d_ln_v: &mut [f64],
    d_psi: &mut [f64],
    ln_theta_rate_out: &mut [f64],
) -> Result<(), BatchError> {
    let n = p.count()?;
    rate_lengths(
        n,
        [ln_v.len(), ln_theta.len(), friction_out.len(), d_ln_v.len(), d_psi.len(), ln_theta_rate_out.len()],
    )?;
    for i in 0..n {
        let psi = psi_term(p.b[i], p.v0[i], p.dc[i], law.theta_scale(), ln_theta[i]);
        let f = friction(form, p.f0[i], p.a[i], p.v0[i], ln_v[i], psi);
        friction_out[i] = f.value;
        d_ln_v[i] = f.d_ln_v;
        d_psi[i] = f.d_psi;
        ln_theta_rate_out[i] = ln_theta_rate(law, ln_v[i], ln_theta[i], p.dc[i], p.b[i]);
    }
    Ok(())
}

/// [`rates`] over `threads` scoped threads, each on a contiguous chunk of the elements (the
/// result is the same as with one thread, element by element).
#[allow(clippy::too_many_arguments)]
pub fn rates_parallel<L: StateLaw>(
    form: FrictionForm,
    law: &L,
    p: &Elements,
    ln_v: &[f64],
    ln_theta: &[f64],
    friction_out: &mut [f64],
    d_ln_v: &mut [f64],
    d_psi: &mut [f64],
    ln_theta_rate_out: &mut [f64],
    threads: usize,
) -> Result<(), BatchError> {
    let n = p.count()?;
    rate_lengths(
        n,
        [ln_v.len(), ln_theta.len(), friction_out.len(), d_ln_v.len(), d_psi.len(), ln_theta_rate_out.len()],
    )?;
    let chunk = n.div_ceil(threads.max(1)).max(1);
    std::thread::scope(|s| {
        let outs = friction_out
            .chunks_mut(chunk)
            .zip(d_ln_v.chunks_mut(chunk))
            .zip(d_psi.chunks_mut(chunk))
            .zip(ln_theta_rate_out.chunks_mut(chunk));
        let handles: Vec<_> = outs
            .enumerate()
            .map(|(c, (((f, fx), fp), r))| {
                let r0 = c * chunk;
                let r1 = r0 + f.len();
                let sub = Elements {
                    f0: &p.f0[r0..r1],
                    a: &p.a[r0..r1],
                    v0: &p.v0[r0..r1],
                    b: &p.b[r0..r1],
                    dc: &p.dc[r0..r1],
                };
                let (x, z) = (&ln_v[r0..r1], &ln_theta[r0..r1]);
                s.spawn(move || rates(form, law, &sub, x, z, f, fx, fp, r))
            })
            .collect();
        handles.into_iter().try_for_each(|h| h.join().expect("a batch thread panicked"))
    })
}

/// The slip rate of every element from the quasi-dynamic balance `τ − ηV = σ f(V, θ)`:
/// `ln_v` holds the warm starts on entry and the roots on return. Returns the total number of
/// iterations; stops at the first element without a root and names it.
#[allow(clippy::too_many_arguments)]
pub fn solve_slip_rates<L: StateLaw>(
    form: FrictionForm,
    law: &L,
    p: &Elements,
    ln_theta: &[f64],
    tau: &[f64],
    sigma: &[f64],
    eta: &[f64],
    ln_v: &mut [f64],
) -> Result<u64, BatchError> {
    let n = p.count()?;
    same_lengths(
        n,
        &[
            ("ln_theta", ln_theta.len()),
            ("tau", tau.len()),
            ("sigma", sigma.len()),
            ("eta", eta.len()),
            ("ln_v", ln_v.len()),
        ],
    )?;
    let mut iterations = 0u64;
    for i in 0..n {
        let psi = psi_term(p.b[i], p.v0[i], p.dc[i], law.theta_scale(), ln_theta[i]);
        let r = solve_slip_rate(form, p.f0[i], p.a[i], p.v0[i], psi, tau[i], sigma[i], eta[i], ln_v[i])
            .map_err(|error| BatchError::Element { index: i, error })?;
        ln_v[i] = r.ln_v;
        iterations += r.iterations as u64;
    }
    Ok(iterations)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::{self, TestAging as Aging};

    /// The batch equals the per-element kernels, element by element, and names a bad length.
    #[test]
    fn batch_equals_the_kernels_and_checks_lengths() {
        let n = 5;
        let f0 = vec![0.6; n];
        let a: Vec<f64> = (0..n).map(|i| 0.01 + 0.002 * i as f64).collect();
        let (v0, b, dc) = (vec![1e-6; n], vec![0.015; n], vec![0.008; n]);
        let p = Elements { f0: &f0, a: &a, v0: &v0, b: &b, dc: &dc };
        let ln_v: Vec<f64> = (0..n).map(|i| -20.0 + 4.0 * i as f64).collect();
        let ln_theta: Vec<f64> = (0..n).map(|i| 15.0 - 3.0 * i as f64).collect();
        let (mut f, mut fx, mut fp, mut r) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let form = FrictionForm::Regularized;
        rates(form, &Aging, &p, &ln_v, &ln_theta, &mut f, &mut fx, &mut fp, &mut r).unwrap();
        for i in 0..n {
            let psi = element::psi_term(0.015, 1e-6, 0.008, 1.0, ln_theta[i]);
            let e = element::friction(form, 0.6, a[i], 1e-6, ln_v[i], psi);
            assert_eq!((f[i], fx[i], fp[i]), (e.value, e.d_ln_v, e.d_psi));
            assert_eq!(r[i], element::ln_theta_rate(&Aging, ln_v[i], ln_theta[i], 0.008, 0.015));
        }
        // the solve inverts the friction: τ from the rates, the slip rates back from τ
        let (sigma, eta) = (vec![50e6; n], vec![4.624e6; n]);
        let tau: Vec<f64> = (0..n).map(|i| sigma[i] * f[i] + eta[i] * ln_v[i].exp()).collect();
        let mut guess: Vec<f64> = ln_v.iter().map(|x| x + 0.01).collect();
        solve_slip_rates(form, &Aging, &p, &ln_theta, &tau, &sigma, &eta, &mut guess).unwrap();
        for i in 0..n {
            assert!((guess[i] - ln_v[i]).abs() < 1e-9);
        }
        // the parallel batch gives the same numbers, for any thread count
        for threads in [1, 2, 3, 8] {
            let (mut f2, mut fx2, mut fp2, mut r2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            rates_parallel(form, &Aging, &p, &ln_v, &ln_theta, &mut f2, &mut fx2, &mut fp2, &mut r2, threads).unwrap();
            assert_eq!((&f2, &fx2, &fp2, &r2), (&f, &fx, &fp, &r), "{threads} threads");
        }
        let short = vec![0.0; n - 1];
        assert_eq!(
            rates(form, &Aging, &p, &short, &ln_theta, &mut f, &mut fx, &mut fp, &mut r),
            Err(BatchError::Length("ln_v"))
        );
        let bad_tau = vec![-1.0; n];
        assert!(matches!(
            solve_slip_rates(form, &Aging, &p, &ln_theta, &bad_tau, &sigma, &eta, &mut guess),
            Err(BatchError::Element { index: 0, error: SlipRateError::NoRoot })
        ));
    }
}
