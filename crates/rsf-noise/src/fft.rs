//! FFT plans reused. Planning a length computes its twiddle factors (a sine and
//! a cosine per sample), which for one transform of a 75,000-sample record costs more than the
//! transform itself, and the diagnosis fits the noise of residuals of the same lengths dozens
//! of times per record (every candidate, every null replicate). A plan of a length computes
//! the same transform whichever planner made it, so reusing one changes no bit.

use rustfft::{Fft, FftDirection, FftPlanner};
use std::sync::{Arc, Mutex};

/// The plans kept hold at most this many samples in all (16 bytes of twiddles per sample:
/// 8 MB): the lengths of one record's residuals, its pooled stretches and its doubled
/// synthesis. A plan that would pass it empties the store first.
const PLAN_SAMPLES_KEPT: usize = 1 << 19;

type Plans = Vec<(usize, FftDirection, Arc<dyn Fft<f64>>)>;

/// Shared by the threads (the parallel maps start new ones for every batch of jobs); a lookup
/// holds the lock, planning does not.
static PLANS: Mutex<Plans> = Mutex::new(Vec::new());

fn plans() -> std::sync::MutexGuard<'static, Plans> {
    // a store poisoned by a panic elsewhere holds whole plans only: still good
    PLANS.lock().unwrap_or_else(|e| e.into_inner())
}

/// The plan of a transform of `n` samples in `direction`, made once while the store has room.
pub(crate) fn plan(n: usize, direction: FftDirection) -> Arc<dyn Fft<f64>> {
    if let Some((_, _, f)) = plans().iter().find(|(m, d, _)| *m == n && *d == direction) {
        return Arc::clone(f);
    }
    let f = FftPlanner::new().plan_fft(n, direction);
    let mut store = plans();
    if store.iter().map(|(m, _, _)| m).sum::<usize>() + n > PLAN_SAMPLES_KEPT {
        store.clear();
    }
    if n <= PLAN_SAMPLES_KEPT {
        store.push((n, direction, Arc::clone(&f)));
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use rustfft::num_complex::Complex;

    /// A kept plan gives the transform of a fresh planner's bit for bit, and the store never
    /// holds more than its bound.
    #[test]
    fn a_kept_plan_transforms_as_a_fresh_one() {
        for &n in &[75_405usize, 1_000, 75_405, 300_000, 300_000, 7] {
            let x: Vec<Complex<f64>> = (0..n).map(|i| Complex::new((i as f64 * 0.37).sin(), 0.0)).collect();
            let (mut a, mut b) = (x.clone(), x);
            plan(n, FftDirection::Forward).process(&mut a);
            FftPlanner::new().plan_fft_forward(n).process(&mut b);
            assert!(
                a.iter().zip(&b).all(|(p, q)| p.re.to_bits() == q.re.to_bits() && p.im.to_bits() == q.im.to_bits())
            );
            let held: usize = plans().iter().map(|(m, _, _)| m).sum();
            assert!(held <= PLAN_SAMPLES_KEPT, "{held}");
        }
    }
}
