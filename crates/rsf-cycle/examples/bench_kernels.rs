//! Throughput of the per-element kernels (`rsf_core::element`) over many independent elements,
//! as a fault code calls them: friction with its partials plus one state rate in log form, for
//! the aging and slip laws, and the warm-started slip-rate solve.
//!
//! ```sh
//! cargo run --release -p rsf-cycle --example bench_kernels
//! ```

use rsf_core::FrictionForm;
use rsf_core::element::{friction, ln_theta_rate, psi_term, solve_slip_rate};
use rsf_laws::{Aging, Slip};
use std::hint::black_box;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let n = 100_000;
    let (f0, a, v0, b, dc, sigma, eta): (f64, f64, f64, f64, f64, f64, f64) =
        (0.6, 0.01, 1e-6, 0.015, 0.008, 50e6, 4.624e6);
    // heterogeneous elements: ln V from −30 to 0, ln θ around steady state
    let x: Vec<f64> = (0..n).map(|i| -30.0 + 30.0 * i as f64 / n as f64).collect();
    let z: Vec<f64> = x.iter().enumerate().map(|(i, &x)| (dc).ln() - x + 0.3 * ((i % 7) as f64 - 3.0)).collect();
    let mut out = vec![0.0; n];
    for form in [FrictionForm::Regularized, FrictionForm::Classic] {
        for law in ["aging", "slip"] {
            let mut times = vec![];
            for _ in 0..21 {
                let t = Instant::now();
                for i in 0..n {
                    let psi = psi_term(b, v0, dc, 1.0, z[i]);
                    let f = friction(form, f0, a, v0, x[i], psi);
                    let r = if law == "aging" {
                        ln_theta_rate(&Aging, x[i], z[i], dc, b)
                    } else {
                        ln_theta_rate(&Slip, x[i], z[i], dc, b)
                    };
                    out[i] = f.value + f.d_ln_v + f.d_psi * r;
                }
                black_box(&out);
                times.push(t.elapsed().as_secs_f64());
            }
            println!(
                "{form:?} friction + partials + {law} state rate: {:.2} ns per element (median of 21 sweeps over {n})",
                median(times) * 1e9 / n as f64
            );
        }
    }
    // the slip-rate solve, warm (the previous ln V perturbed by 1e-3) and cold
    let form = FrictionForm::Regularized;
    let tau: Vec<f64> = (0..n)
        .map(|i| sigma * friction(form, f0, a, v0, x[i], psi_term(b, v0, dc, 1.0, z[i])).value + eta * x[i].exp())
        .collect();
    for (name, shift) in [("warm (guess 1e-3 off)", 1e-3), ("cold (guess 5 off)", 5.0)] {
        let (mut times, mut iters) = (vec![], 0u64);
        for _ in 0..11 {
            iters = 0;
            let t = Instant::now();
            for i in 0..n {
                let psi = psi_term(b, v0, dc, 1.0, z[i]);
                let r = solve_slip_rate(form, f0, a, v0, psi, tau[i], sigma, eta, x[i] + shift).unwrap();
                iters += r.iterations as u64;
                out[i] = r.ln_v;
            }
            black_box(&out);
            times.push(t.elapsed().as_secs_f64());
        }
        println!(
            "slip-rate solve, {name}: {:.0} ns per element, {:.1} iterations on average",
            median(times) * 1e9 / n as f64,
            iters as f64 / n as f64
        );
    }
}
