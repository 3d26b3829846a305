//! A mesh (`rsf_mesh_*`): parameters checked once, evaluations in V and θ. Checked against the
//! batch call in log variables (every form and law, V > 0), against QDYN's closed forms written
//! out here (the host's own arithmetic), and for its two policies outside V > 0, θ > 0.

use rsf_capi::{
    RSF_ABI_VERSION, RsfDomain, RsfFrictionParams, RsfLaw, RsfMesh, RsfStateParams, RsfStatus, rsf_batch_partials,
    rsf_last_error, rsf_mesh_free, rsf_mesh_friction, rsf_mesh_new, rsf_mesh_partials, rsf_mesh_state_rate,
};
use std::ffi::CStr;

fn fp(form: i32, f0: f64, a: f64, v0: f64) -> RsfFrictionParams {
    RsfFrictionParams { version: RSF_ABI_VERSION, form, f0, a, v0 }
}

fn sp(law: RsfLaw, b: f64, dc: f64, vc: f64) -> RsfStateParams {
    RsfStateParams { version: RSF_ABI_VERSION, law: law as i32, b, dc, vc }
}

fn last_error() -> String {
    // SAFETY: rsf_last_error returns a valid C string owned by the library
    unsafe { CStr::from_ptr(rsf_last_error()) }.to_string_lossy().into_owned()
}

/// A mesh owned by the test, freed on drop.
struct Mesh(*mut RsfMesh, usize);

impl Mesh {
    fn new(fp: &[RsfFrictionParams], sp: &[RsfStateParams], domain: RsfDomain) -> Result<Mesh, (RsfStatus, String)> {
        let mut m = std::ptr::null_mut();
        // SAFETY: slices of fp.len() values and one out pointer
        let st = unsafe { rsf_mesh_new(fp.len(), fp.as_ptr(), sp.as_ptr(), domain as i32, &mut m) };
        if st == RsfStatus::RsfOk { Ok(Mesh(m, fp.len())) } else { Err((st, last_error())) }
    }

    /// (status, μ, ∂μ/∂V, ∂μ/∂θ, dθ/dt) at (v, θ); the statuses of the three calls must agree
    /// in success, the first failure is returned.
    #[allow(clippy::type_complexity)]
    fn eval(&self, v: &[f64], theta: &[f64]) -> Result<(Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>), (RsfStatus, String)> {
        let n = self.1;
        let (mut mu, mut dv, mut dth, mut rate) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        // SAFETY: n values in every array, a live mesh
        let sts = unsafe {
            [
                rsf_mesh_friction(self.0, n, v.as_ptr(), theta.as_ptr(), mu.as_mut_ptr()),
                rsf_mesh_partials(self.0, n, v.as_ptr(), theta.as_ptr(), dv.as_mut_ptr(), dth.as_mut_ptr()),
                rsf_mesh_state_rate(self.0, n, v.as_ptr(), theta.as_ptr(), rate.as_mut_ptr()),
            ]
        };
        match sts.iter().find(|s| **s != RsfStatus::RsfOk) {
            Some(&st) => Err((st, last_error())),
            None => Ok((mu, dv, dth, rate)),
        }
    }
}

impl Drop for Mesh {
    fn drop(&mut self) {
        // SAFETY: made by rsf_mesh_new, freed once
        unsafe { rsf_mesh_free(self.0) }
    }
}

fn close(x: f64, y: f64, rel: f64) -> bool {
    (x - y).abs() <= rel * x.abs().max(y.abs()) + 1e-300
}

/// Every form (classic, regularized, cut-off) with every law of the ABI, at V from 1e-12 to 10
/// and θ over six decades around steady state: the mesh's outputs equal the batch call's in log
/// variables (∂f/∂ln V / V, ∂f/∂ln θ / θ, θ d ln θ/dt) to 1e-12 relative (the friction to
/// 1e-13 absolute).
#[test]
fn a_mesh_equals_the_batch_call_in_log_variables() {
    let laws = [
        (RsfLaw::RsfLawAging, 0.0),
        (RsfLaw::RsfLawSlip, 0.0),
        (RsfLaw::RsfLawPrz, 0.0),
        (RsfLaw::RsfLawAgingNoHealing, 0.0),
    ];
    let (mut fps, mut sps, mut v, mut theta) = (vec![], vec![], vec![], vec![]);
    for form in 0..3 {
        for &(law, _) in &laws {
            for &vv in &[1e-12, 1e-9, 3e-6, 1e-3, 0.5, 10.0] {
                for &om in &[1e-3, 0.7, 1.0, 40.0, 1e3] {
                    let (a, b, dc) = (0.011, 0.015, 8e-3);
                    // QDYN: the cut-off form's V1 in v0, V2 in vc
                    fps.push(fp(form, 0.6, a, if form == 2 { 1e-7 } else { 1e-6 }));
                    sps.push(sp(law, b, dc, if form == 2 { 1e-4 } else { 0.0 }));
                    v.push(vv);
                    theta.push(om * dc / vv);
                }
            }
        }
    }
    // Kato–Tullis under the two core forms (its vc is its own)
    for form in 0..2 {
        fps.push(fp(form, 0.6, 0.01, 1e-6));
        sps.push(sp(RsfLaw::RsfLawKatoTullis, 0.014, 1e-2, 1e-5));
        v.push(2e-5);
        theta.push(300.0);
    }
    let n = fps.len();
    // mixed forms and laws: the per-element path
    let m = Mesh::new(&fps, &sps, RsfDomain::RsfDomainRefuse).unwrap();
    let (mu, dv, dth, rate) = m.eval(&v, &theta).unwrap();
    // each form and law on its own: the uniform path (one loop per form and law) gives the
    // same numbers, bit for bit
    let per = 6 * 5;
    for g in 0..(3 * laws.len()) {
        let r = g * per..(g + 1) * per;
        let u = Mesh::new(&fps[r.clone()], &sps[r.clone()], RsfDomain::RsfDomainRefuse).unwrap();
        let (umu, udv, udth, urate) = u.eval(&v[r.clone()], &theta[r.clone()]).unwrap();
        assert_eq!(
            (&umu[..], &udv[..], &udth[..], &urate[..]),
            (&mu[r.clone()], &dv[r.clone()], &dth[r.clone()], &rate[r])
        );
    }
    let (ln_v, ln_th): (Vec<f64>, Vec<f64>) = v.iter().zip(&theta).map(|(a, b)| (a.ln(), b.ln())).unzip();
    let (mut f, mut fx, mut fz, mut r) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    // SAFETY: n values each
    let st = unsafe {
        rsf_batch_partials(
            n,
            fps.as_ptr(),
            sps.as_ptr(),
            ln_v.as_ptr(),
            ln_th.as_ptr(),
            f.as_mut_ptr(),
            fx.as_mut_ptr(),
            fz.as_mut_ptr(),
            r.as_mut_ptr(),
        )
    };
    assert_eq!(st, RsfStatus::RsfOk, "{}", last_error());
    for i in 0..n {
        let what = format!("element {i}: form {} law {} V {:e} θ {:e}", fps[i].form, sps[i].law, v[i], theta[i]);
        assert!((mu[i] - f[i]).abs() <= 1e-13, "{what}: μ {} vs {}", mu[i], f[i]);
        assert!(close(dv[i], fx[i] / v[i], 1e-12), "{what}: ∂μ/∂V {} vs {}", dv[i], fx[i] / v[i]);
        assert!(close(dth[i], fz[i] / theta[i], 1e-12), "{what}: ∂μ/∂θ {} vs {}", dth[i], fz[i] / theta[i]);
        let want = theta[i] * r[i];
        // the rate near steady state is a difference of nearly equal terms: compare on the
        // scale of its terms (1 and Ω for the aging law)
        let scale = 1.0 + v[i] * theta[i] / sps[i].dc;
        assert!((rate[i] - want).abs() <= 1e-12 * scale, "{what}: dθ/dt {} vs {want}", rate[i]);
    }
}

/// QDYN's own formulas (src/friction.f90 of QDYN e06edb1, written out here as the host writes
/// them) and the mesh's agree to rounding for the classic, cut-off and regularized forms.
#[test]
fn a_mesh_is_the_hosts_own_closed_forms() {
    let (a, b, dc, mu_star, v_star, v1, v2) = (0.001, 0.0015, 1e-5, 0.6, 1e-6, 1e-3, 1e-1);
    let vs = [1e-11, 1e-6, 3e-3, 2.0];
    let ths = [1e-4, 10.0, 1e5];
    for form in 0..3 {
        let mut fps = vec![];
        let (mut v, mut th) = (vec![], vec![]);
        for &vv in &vs {
            for &t in &ths {
                fps.push(fp(form, mu_star, a, if form == 2 { v1 } else { v_star }));
                v.push(vv);
                th.push(t);
            }
        }
        let sps = vec![sp(RsfLaw::RsfLawAging, b, dc, if form == 2 { v2 } else { 0.0 }); fps.len()];
        let m = Mesh::new(&fps, &sps, RsfDomain::RsfDomainRefuse).unwrap();
        let (mu, dv, dth, rate) = m.eval(&v, &th).unwrap();
        for i in 0..fps.len() {
            let (vv, t) = (v[i], th[i]);
            let (qmu, qdv, qdth) = match form {
                0 => (mu_star - a * (v_star / vv).ln() + b * (t / (dc / v_star)).ln(), a / vv, b / t),
                1 => {
                    let z = ((mu_star + b * (t / (dc / v_star)).ln()) / a).exp() / (2.0 * v_star);
                    let dmu_dv = a / (1.0 / (z * z) + vv * vv).sqrt();
                    (a * (vv / (2.0 * v_star) * (2.0 * v_star * z)).asinh(), dmu_dv, dmu_dv * (b * vv) / (a * t))
                }
                _ => (
                    mu_star - a * (v1 / vv + 1.0).ln() + b * (t / (dc / v2) + 1.0).ln(),
                    a * v1 / vv / (v1 + vv),
                    b * v2 / (v2 * t + dc),
                ),
            };
            let what = format!("form {form} V {vv:e} θ {t:e}");
            assert!((mu[i] - qmu).abs() <= 1e-13, "{what}: μ {} vs QDYN's {qmu}", mu[i]);
            assert!(close(dv[i], qdv, 1e-12), "{what}: ∂μ/∂V {} vs QDYN's {qdv}", dv[i]);
            assert!(close(dth[i], qdth, 1e-12), "{what}: ∂μ/∂θ {} vs QDYN's {qdth}", dth[i]);
            assert_eq!(rate[i], 1.0 - vv * t / dc, "{what}: the aging rate");
        }
    }
}

/// Outside V > 0: refused, naming the element, V and θ, with `RSF_DOMAIN_REFUSE`; with
/// `RSF_DOMAIN_CONTINUE`, the closed forms at the signed values — QDYN's own numbers — and NaN
/// where the formula is undefined, with success.
#[test]
fn outside_v_positive_refuse_or_continue() {
    let (a, b, dc) = (0.01, 0.015, 1e-5);
    let fps = [fp(0, 0.6, a, 1e-6), fp(0, 0.6, a, 1e-6), fp(1, 0.6, a, 1e-6), fp(0, 0.6, a, 1e-6)];
    let sps = [
        sp(RsfLaw::RsfLawAging, b, dc, 0.0),
        sp(RsfLaw::RsfLawAging, b, dc, 0.0),
        sp(RsfLaw::RsfLawAging, b, dc, 0.0),
        sp(RsfLaw::RsfLawSlip, b, dc, 0.0),
    ];
    let v = [1e-6, -2.58e-10, -1e-3, -1e-9];
    let th = [10.0, 2e4, 10.0, 10.0];
    let refuse = Mesh::new(&fps, &sps, RsfDomain::RsfDomainRefuse).unwrap();
    let (st, msg) = refuse.eval(&v, &th).unwrap_err();
    assert_eq!(st, RsfStatus::RsfBadInput);
    assert!(msg.contains("element 1") && msg.contains("-2.58e-10") && msg.contains("V > 0"), "{msg}");

    let cont = Mesh::new(&fps, &sps, RsfDomain::RsfDomainContinue).unwrap();
    let (mu, dv, dth, rate) = cont.eval(&v, &th).unwrap();
    // element 1, classic and aging: QDYN's a/V, b/θ, 1 − Vθ/Dc; μ = NaN (ln of a negative V)
    assert!(mu[1].is_nan());
    assert_eq!(dv[1], a / v[1]);
    assert_eq!(dth[1], b / th[1]);
    assert_eq!(rate[1], 1.0 - v[1] * th[1] / dc);
    // element 2, regularized: odd in V, so μ(−V) = −μ(V), ∂μ/∂V even
    let pos = Mesh::new(&fps[2..3], &sps[2..3], RsfDomain::RsfDomainRefuse).unwrap();
    let (mu_p, dv_p, dth_p, _) = pos.eval(&[1e-3], &[10.0]).unwrap();
    assert_eq!(mu[2], -mu_p[0]);
    assert_eq!(dv[2], dv_p[0]);
    assert_eq!(dth[2], -dth_p[0]);
    // element 3, slip law: −Ω ln Ω is undefined for Ω < 0
    assert!(rate[3].is_nan());
    assert_eq!(dv[3], a / v[3]);
    // the element inside the domain is untouched by its neighbours
    assert_eq!(rate[0], 1.0 - v[0] * th[0] / dc);
}

/// Inside the domain a result that overflows is still refused, under either policy; so are a
/// size other than the mesh's, a null mesh, an unknown policy and bad parameters at set-up
/// (naming the element, leaving the out pointer null).
#[test]
fn refusals_name_what_is_wrong() {
    let fps = [fp(0, 0.6, 0.01, 1e-6); 2];
    let sps = [sp(RsfLaw::RsfLawAging, 0.015, 1e-5, 0.0); 2];
    for domain in [RsfDomain::RsfDomainRefuse, RsfDomain::RsfDomainContinue] {
        let m = Mesh::new(&fps, &sps, domain).unwrap();
        let (st, msg) = m.eval(&[1.0, 1e300], &[1.0, 1e300]).unwrap_err();
        assert_eq!(st, RsfStatus::RsfBadInput);
        assert!(msg.contains("element 1") && msg.contains("out of range"), "{msg}");
    }
    let m = Mesh::new(&fps, &sps, RsfDomain::RsfDomainRefuse).unwrap();
    let mut out = [0.0; 3];
    // SAFETY: three values in each array; the call must refuse n = 3 for a mesh of 2
    let st = unsafe { rsf_mesh_state_rate(m.0, 3, [1.0; 3].as_ptr(), [1.0; 3].as_ptr(), out.as_mut_ptr()) };
    assert_eq!(st, RsfStatus::RsfBadInput);
    assert!(last_error().contains("n = 3 but the mesh has 2 elements"), "{}", last_error());
    // SAFETY: a null mesh must be refused
    let st = unsafe { rsf_mesh_friction(std::ptr::null(), 1, [1.0].as_ptr(), [1.0].as_ptr(), out.as_mut_ptr()) };
    assert_eq!(st, RsfStatus::RsfBadInput);

    let mut p: *mut RsfMesh = std::ptr::null_mut();
    // SAFETY: two values each, one out pointer
    let st = unsafe { rsf_mesh_new(2, fps.as_ptr(), sps.as_ptr(), 7, &mut p) };
    assert_eq!(st, RsfStatus::RsfUnknownId);
    assert!(last_error().contains("unknown domain id 7"));
    let bad = [sps[0], sp(RsfLaw::RsfLawAging, 0.015, -1.0, 0.0)];
    let (st, msg) = Mesh::new(&fps, &bad, RsfDomain::RsfDomainRefuse).map(|_| ()).unwrap_err();
    assert_eq!(st, RsfStatus::RsfBadInput);
    assert!(msg.starts_with("element 1:") && msg.contains("dc > 0"), "{msg}");
    // SAFETY: two values each, one out pointer
    let st = unsafe { rsf_mesh_new(2, fps.as_ptr(), bad.as_ptr(), 0, &mut p) };
    assert_eq!(st, RsfStatus::RsfBadInput);
    assert!(p.is_null());
    // SAFETY: freeing null does nothing
    unsafe { rsf_mesh_free(std::ptr::null_mut()) };
}
