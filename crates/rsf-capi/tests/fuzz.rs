//! The C ABI's boundary under random input (proptest): any mix of finite, huge, tiny, zero,
//! negative, NaN and infinite values, any ids and versions. Asserts: no call panics (none
//! returns RSF_INTERNAL), and a call that returns RSF_OK wrote only finite numbers. The case
//! count is proptest's (`PROPTEST_CASES`, 256 by default); docs/fuzzing.md records a longer
//! campaign.

use proptest::prelude::*;
use rsf_capi::*;

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => -50.0f64..50.0,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(0.0),
        1 => Just(-0.0),
        1 => Just(f64::MAX),
        1 => Just(-f64::MAX),
        1 => Just(f64::MIN_POSITIVE),
        1 => Just(5e-324),
        1 => prop::num::f64::ANY,
        2 => 1e-12f64..1e12,
    ]
}

fn friction_params() -> impl Strategy<Value = RsfFrictionParams> {
    (prop_oneof![4 => Just(RSF_ABI_VERSION), 1 => any::<u32>()], -1i32..4, any_f64(), any_f64(), any_f64())
        .prop_map(|(version, form, f0, a, v0)| RsfFrictionParams { version, form, f0, a, v0 })
}

fn state_params() -> impl Strategy<Value = RsfStateParams> {
    (prop_oneof![4 => Just(RSF_ABI_VERSION), 1 => any::<u32>()], -1i32..5, any_f64(), any_f64(), any_f64())
        .prop_map(|(version, law, b, dc, vc)| RsfStateParams { version, law, b, dc, vc })
}

fn check(st: RsfStatus, outs: &[f64]) -> Result<(), TestCaseError> {
    prop_assert!(st != RsfStatus::RsfInternal, "a panic inside rsf");
    if st == RsfStatus::RsfOk {
        prop_assert!(outs.iter().all(|x| x.is_finite()), "RSF_OK with {outs:?}");
    }
    Ok(())
}

proptest! {
    #[test]
    fn single_element_calls(fp in friction_params(), sp in state_params(), x in any_f64(), z in any_f64(),
                            tau in any_f64(), sigma in any_f64(), eta in any_f64()) {
        let (mut f, mut d1, mut d2, mut psi, mut rate, mut lv, mut dpsi) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut it = 0i32;
        // SAFETY: every pointer is to a live local
        unsafe {
            check(rsf_friction(&fp, x, z, &mut f, &mut d1, &mut d2), &[f, d1, d2])?;
            check(rsf_psi(&sp, fp.v0, z, &mut psi), &[psi])?;
            check(rsf_state_term(&fp, &sp, z, &mut psi, &mut dpsi), &[psi, dpsi])?;
            check(rsf_ln_theta_rate(&sp, x, z, &mut rate), &[rate])?;
            check(rsf_solve_slip_rate(&fp, z, tau, sigma, eta, x, &mut lv, &mut it), &[lv])?;
        }
    }

    #[test]
    fn batch_calls(elems in prop::collection::vec((friction_params(), state_params(), any_f64(), any_f64(),
                                                    any_f64(), any_f64(), any_f64()), 0..6)) {
        let n = elems.len();
        let fp: Vec<_> = elems.iter().map(|e| e.0).collect();
        let sp: Vec<_> = elems.iter().map(|e| e.1).collect();
        let (x, z): (Vec<f64>, Vec<f64>) = elems.iter().map(|e| (e.2, e.3)).unzip();
        let tau: Vec<f64> = elems.iter().map(|e| e.4).collect();
        let sigma: Vec<f64> = elems.iter().map(|e| e.5).collect();
        let eta: Vec<f64> = elems.iter().map(|e| e.6).collect();
        let (mut f, mut d1, mut d2, mut r) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut lv = x.clone();
        // SAFETY: every array has n elements and the outputs are distinct vectors
        unsafe {
            let st = rsf_batch_rates(n, fp.as_ptr(), sp.as_ptr(), x.as_ptr(), z.as_ptr(), f.as_mut_ptr(),
                                     d1.as_mut_ptr(), d2.as_mut_ptr(), r.as_mut_ptr());
            check(st, &[f.clone(), d1.clone(), d2.clone(), r.clone()].concat())?;
            let st = rsf_batch_partials(n, fp.as_ptr(), sp.as_ptr(), x.as_ptr(), z.as_ptr(), f.as_mut_ptr(),
                                        d1.as_mut_ptr(), d2.as_mut_ptr(), r.as_mut_ptr());
            check(st, &[f.clone(), d1, d2, r].concat())?;
            let st = rsf_batch_solve_slip_rate(n, fp.as_ptr(), sp.as_ptr(), z.as_ptr(), tau.as_ptr(),
                                               sigma.as_ptr(), eta.as_ptr(), lv.as_mut_ptr());
            check(st, &lv)?;
        }
    }
}

fn valid_element() -> impl Strategy<Value = (RsfFrictionParams, RsfStateParams, f64, f64)> {
    (
        0i32..3,
        0i32..4,
        0.3f64..0.9,
        1e-4f64..0.05,
        prop_oneof![Just(1e-6), 1e-9f64..1e-3],
        -0.02f64..0.05,
        prop_oneof![Just(1e-5), 1e-6f64..1e-1],
        1e-9f64..1.0,
        -30.0f64..5.0,
        -10.0f64..20.0,
    )
        .prop_map(|(form, law, f0, a, v0, b, dc, vc, x, z)| {
            // the cut-off form reads vc as V2 and refuses a Kato–Tullis state
            let law = if form == 2 && law == 2 { 0 } else { law };
            (
                RsfFrictionParams { version: RSF_ABI_VERSION, form, f0, a, v0 },
                RsfStateParams { version: RSF_ABI_VERSION, law, b, dc, vc },
                x,
                z,
            )
        })
}

proptest! {
    /// The batch partials are the one-element calls, bit for bit, however the elements share
    /// or differ in their parameters (the batch call keeps the logs of shared V0 and Dc).
    #[test]
    fn batch_partials_are_the_single_calls(elems in prop::collection::vec(valid_element(), 1..8)) {
        let n = elems.len();
        let fp: Vec<_> = elems.iter().map(|e| e.0).collect();
        let sp: Vec<_> = elems.iter().map(|e| e.1).collect();
        let (x, z): (Vec<f64>, Vec<f64>) = elems.iter().map(|e| (e.2, e.3)).unzip();
        let (mut f, mut fx, mut fz, mut r) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        // SAFETY: every array has n elements and the outputs are distinct vectors
        let st = unsafe {
            rsf_batch_partials(n, fp.as_ptr(), sp.as_ptr(), x.as_ptr(), z.as_ptr(), f.as_mut_ptr(),
                               fx.as_mut_ptr(), fz.as_mut_ptr(), r.as_mut_ptr())
        };
        prop_assert_eq!(st, RsfStatus::RsfOk);
        for i in 0..n {
            let (mut psi, mut dpsi, mut f1, mut d1, mut d2, mut rate) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
            // SAFETY: every pointer is to a live local
            unsafe {
                prop_assert_eq!(rsf_state_term(&fp[i], &sp[i], z[i], &mut psi, &mut dpsi), RsfStatus::RsfOk);
                prop_assert_eq!(rsf_friction(&fp[i], x[i], psi, &mut f1, &mut d1, &mut d2), RsfStatus::RsfOk);
                prop_assert_eq!(rsf_ln_theta_rate(&sp[i], x[i], z[i], &mut rate), RsfStatus::RsfOk);
            }
            prop_assert_eq!(f[i].to_bits(), f1.to_bits());
            prop_assert_eq!(fx[i].to_bits(), d1.to_bits());
            prop_assert_eq!(fz[i].to_bits(), (d2 * dpsi).to_bits());
            prop_assert_eq!(r[i].to_bits(), rate.to_bits());
        }
    }
}
