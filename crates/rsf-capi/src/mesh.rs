//! A mesh: every element's parameters checked once, at set-up, and evaluated in the plain
//! variables V and θ a host integrates (QDYN, most Runge–Kutta earthquake-cycle codes).
//!
//! The batch calls (`rsf_batch_partials`) check every element's structs and take logs at
//! every right-hand side; a host that calls them 10^5–10^6 times per run with parameters that
//! never change pays for that. A mesh checks the structs when it is made, keeps per-element
//! constants (the friction's constant part, b/a, V2/(s Dc)), and then each call is the
//! closed forms in V and θ — the arithmetic a host writes itself (a/V, b/θ, 1 − Vθ/Dc for the
//! classic form and the aging law), with the outputs still checked for finiteness.
//!
//! **Outside V > 0, θ > 0.** A host that integrates V can reach V ≤ 0 in a trial stage of its
//! solver (an explicit stage overshooting zero). Rate-and-state friction is defined for V > 0
//! only, so the mesh's `domain` (`RsfDomain`) says what happens there:
//! - `RSF_DOMAIN_REFUSE`: the call fails with `RSF_BAD_INPUT`, naming the element, V and θ;
//! - `RSF_DOMAIN_CONTINUE`: each closed form is evaluated as written at the signed values —
//!   the classic partials a/V and b/θ, the regularized form (odd in V), the aging rate
//!   1 − Vθ/Dc, PRZ's, the rate without healing — and is NaN where the formula itself is
//!   undefined (a log of a negative number: the classic and cut-off friction, the slip law's
//!   rate). This is what a host's own hand-written friction returns there (QDYN's), so the
//!   host's solver sees the same numbers and makes the same step decisions (its error
//!   estimate rejects the step, or the stage is a transient of an accepted one).

use crate::form::{AbiLaw, Form, form_of};
use crate::{RsfFrictionParams, RsfStateParams, RsfStatus, element, fail, input, output, status};
use rsf_core::{FrictionForm, asinh_exp_and_slope};

/// What a mesh does at an element with V ≤ 0 or θ ≤ 0 (or V, θ not finite).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RsfDomain {
    /// Refuse the call (`RSF_BAD_INPUT`), naming the element, V and θ.
    RsfDomainRefuse = 0,
    /// Evaluate each closed form as written at the signed values, NaN where it is undefined.
    RsfDomainContinue = 1,
}

/// A mesh of elements whose parameters were checked once (`rsf_mesh_new`); opaque to C.
/// Immutable after it is made: calls from several threads on one mesh are safe.
#[derive(Debug)]
pub struct RsfMesh {
    elements: Vec<Element>,
    domain: RsfDomain,
    /// When every element has the same form and the same law without own parameters (a fault
    /// of one law, the usual case): that form and law, and the parameters as columns, so that
    /// a call dispatches once and runs one loop the compiler can vectorize.
    uniform: Option<Uniform>,
}

/// The columns of a mesh of one form and one law.
#[derive(Debug)]
struct Uniform {
    form: Form,
    law: AbiLaw,
    a: Vec<f64>,
    b: Vec<f64>,
    dc: Vec<f64>,
    c: Vec<f64>,
    b_over_a: Vec<f64>,
    v1: Vec<f64>,
    v2_sdc: Vec<f64>,
}

impl Uniform {
    /// The columns of `elements` when they share one form and one law without parameters.
    fn of(elements: &[Element]) -> Option<Uniform> {
        let first = elements.first()?;
        let same_form = |e: &Element| match (e.form, first.form) {
            (Form::Core(x), Form::Core(y)) => x == y,
            (Form::Cutoff, Form::Cutoff) => true,
            (Form::Core(_), Form::Cutoff) | (Form::Cutoff, Form::Core(_)) => false,
        };
        let same_law = |e: &Element| match (e.law, first.law) {
            (AbiLaw::Aging, AbiLaw::Aging)
            | (AbiLaw::Slip, AbiLaw::Slip)
            | (AbiLaw::Prz, AbiLaw::Prz)
            | (AbiLaw::NoHealing, AbiLaw::NoHealing) => true,
            // Kato–Tullis carries its own vc per element: the per-element path serves it
            (AbiLaw::KatoTullis { .. }, _) | (AbiLaw::Aging | AbiLaw::Slip | AbiLaw::Prz | AbiLaw::NoHealing, _) => {
                false
            }
        };
        if !elements.iter().all(|e| same_form(e) && same_law(e)) {
            return None;
        }
        let col = |f: fn(&Element) -> f64| elements.iter().map(f).collect::<Vec<f64>>();
        Some(Uniform {
            form: first.form,
            law: first.law,
            a: col(|e| e.a),
            b: col(|e| e.b),
            dc: col(|e| e.dc),
            c: col(|e| e.c),
            b_over_a: col(|e| e.b_over_a),
            v1: col(|e| e.v1),
            v2_sdc: col(|e| e.v2_sdc),
        })
    }

    /// ∂f/∂V and ∂f/∂θ of every element: one loop per form, the same arithmetic as
    /// [`Element::partials`].
    fn partials(&self, v: &[f64], theta: &[f64], dv: &mut [f64], dth: &mut [f64]) {
        let n = v.len();
        let (v, theta, dv, dth) = (&v[..n], &theta[..n], &mut dv[..n], &mut dth[..n]);
        let (a, b) = (&self.a[..n], &self.b[..n]);
        match self.form {
            Form::Core(FrictionForm::Classic) => {
                for i in 0..n {
                    dv[i] = a[i] / v[i];
                    dth[i] = b[i] / theta[i];
                }
            }
            Form::Core(FrictionForm::Regularized) => {
                let (c, ba) = (&self.c[..n], &self.b_over_a[..n]);
                let mut w = [0.0; BLOCK];
                for start in (0..n).step_by(BLOCK) {
                    let m = BLOCK.min(n - start);
                    let w = &mut w[..m];
                    // z⁻² = e^(−2 ln z), ln z = c + (b/a) ln θ: the two calls per element
                    for (j, w) in w.iter_mut().enumerate() {
                        *w = (-2.0 * (c[start + j] + ba[start + j] * theta[start + j].ln())).exp();
                    }
                    let (v, theta, a, ba) =
                        (&v[start..start + m], &theta[start..start + m], &a[start..start + m], &ba[start..start + m]);
                    let (dv, dth) = (&mut dv[start..start + m], &mut dth[start..start + m]);
                    for j in 0..m {
                        let df_dv = a[j] / (w[j] + v[j] * v[j]).sqrt();
                        dv[j] = df_dv;
                        dth[j] = df_dv * ba[j] * v[j] / theta[j];
                    }
                }
            }
            Form::Cutoff => {
                let (v1, v2) = (&self.v1[..n], &self.v2_sdc[..n]);
                for i in 0..n {
                    dv[i] = a[i] * v1[i] / (v[i] * (v1[i] + v[i]));
                    dth[i] = b[i] * v2[i] / (v2[i] * theta[i] + 1.0);
                }
            }
        }
    }

    /// dθ/dt of every element: one loop per law, the law's closed form as written.
    fn state_rate(&self, v: &[f64], theta: &[f64], rate: &mut [f64]) {
        let n = v.len();
        let (v, theta, rate, dc) = (&v[..n], &theta[..n], &mut rate[..n], &self.dc[..n]);
        match self.law {
            AbiLaw::Aging => {
                for i in 0..n {
                    rate[i] = -(v[i] * theta[i] / dc[i]) + 1.0;
                }
            }
            AbiLaw::NoHealing => {
                for i in 0..n {
                    rate[i] = -(v[i] * theta[i] / dc[i]);
                }
            }
            AbiLaw::Prz => {
                for i in 0..n {
                    let h = v[i] * theta[i] / (dc[i] * 2.0);
                    rate[i] = -(h * h) + 1.0;
                }
            }
            AbiLaw::Slip | AbiLaw::KatoTullis { .. } => {
                let b = &self.b[..n];
                for i in 0..n {
                    rate[i] = self.law.rate(v[i], theta[i], dc[i], b[i]);
                }
            }
        }
    }
}

/// One element: its form and law, the parameters the closed forms read, and their constants.
#[derive(Clone, Copy, Debug)]
struct Element {
    form: Form,
    law: AbiLaw,
    a: f64,
    b: f64,
    dc: f64,
    /// Classic: f0 − a ln V0 + b ln(V0/(s Dc)), so f = c + a ln V + b ln θ. Regularized:
    /// (f0 + b ln(V0/(s Dc)))/a − ln(2 V0), so ln z = c + (b/a) ln θ and f = a asinh(V z).
    /// Cut-off: f0.
    c: f64,
    /// b/a (regularized form).
    b_over_a: f64,
    /// Cut-off form: V1, the direct effect's cut-off.
    v1: f64,
    /// Cut-off form: V2/(s Dc), so the state term is b ln(θ V2/(s Dc) + 1).
    v2_sdc: f64,
}

/// Elements per block of the uniform loops: the transcendental calls of a block fill a
/// buffer on the stack, then the arithmetic runs over it as one vectorizable loop.
const BLOCK: usize = 64;

impl Element {
    fn new(p: &RsfFrictionParams, s: &RsfStateParams) -> Result<Self, RsfStatus> {
        let form = form_of(p)?;
        form.check_state(s)?;
        let law = AbiLaw::of(s)?;
        let sdc = law.theta_scale() * s.dc;
        let (c, v1, v2_sdc) = match form {
            Form::Core(FrictionForm::Classic) => (p.f0 - p.a * p.v0.ln() + s.b * (p.v0 / sdc).ln(), 0.0, 0.0),
            Form::Core(FrictionForm::Regularized) => {
                ((p.f0 + s.b * (p.v0 / sdc).ln()) / p.a - (2.0 * p.v0).ln(), 0.0, 0.0)
            }
            Form::Cutoff => (p.f0, p.v0, s.vc / sdc),
        };
        let e = Element { form, law, a: p.a, b: s.b, dc: s.dc, c, b_over_a: s.b / p.a, v1, v2_sdc };
        if ![e.c, e.b_over_a, e.v2_sdc].iter().all(|x| x.is_finite()) {
            return Err(fail(
                RsfStatus::RsfBadInput,
                format!("parameters out of range (f0, a, V0, b, Dc: {p:?}, {s:?})"),
            ));
        }
        Ok(e)
    }

    /// Friction f at (V, θ).
    #[inline]
    fn friction(&self, v: f64, theta: f64) -> f64 {
        match self.form {
            Form::Core(FrictionForm::Classic) => self.c + self.a * v.ln() + self.b * theta.ln(),
            Form::Core(FrictionForm::Regularized) => {
                // a asinh(V z) = ±a asinh(e^l), l = ln|V| + ln z: odd in V, no overflow
                let l = v.abs().ln() + self.c + self.b_over_a * theta.ln();
                v.signum() * self.a * asinh_exp_and_slope(l).0
            }
            Form::Cutoff => self.c - self.a * (self.v1 / v).ln_1p() + self.b * (theta * self.v2_sdc).ln_1p(),
        }
    }

    /// ∂f/∂V and ∂f/∂θ at (V, θ).
    #[inline]
    fn partials(&self, v: f64, theta: f64) -> (f64, f64) {
        match self.form {
            Form::Core(FrictionForm::Classic) => (self.a / v, self.b / theta),
            Form::Core(FrictionForm::Regularized) => {
                // ∂f/∂V = a/√(z⁻² + V²), ∂f/∂θ = ∂f/∂V · bV/(aθ); z⁻² = e^(−2 ln z) underflows
                // to 0 harmlessly when z is huge
                let ln_z = self.c + self.b_over_a * theta.ln();
                let df_dv = self.a / ((-2.0 * ln_z).exp() + v * v).sqrt();
                (df_dv, df_dv * self.b_over_a * v / theta)
            }
            Form::Cutoff => {
                (self.a * self.v1 / (v * (self.v1 + v)), self.b * self.v2_sdc / (self.v2_sdc * theta + 1.0))
            }
        }
    }

    /// dθ/dt at (V, θ).
    #[inline]
    fn state_rate(&self, v: f64, theta: f64) -> f64 {
        self.law.rate(v, theta, self.dc, self.b)
    }
}

/// Whether (V, θ) is inside the domain of rate-and-state friction.
#[inline]
fn inside(v: f64, theta: f64) -> bool {
    v > 0.0 && theta > 0.0 && v.is_finite() && theta.is_finite()
}

impl RsfMesh {
    /// Runs `eval` over the elements, writing `K` outputs each; afterwards checks the inputs'
    /// domain (under `RsfDomainRefuse`) and the outputs' finiteness inside it, naming the first
    /// element that fails. The loop itself does no checking, so it stays the closed forms.
    #[allow(clippy::too_many_arguments)]
    fn over<const K: usize>(
        &self,
        call: &str,
        v: &[f64],
        theta: &[f64],
        mut outs: [&mut [f64]; K],
        names: [&str; K],
        fast: impl FnOnce(&Uniform, &mut [&mut [f64]; K]) -> bool,
        eval: impl Fn(&Element, f64, f64) -> [f64; K],
    ) -> Result<(), RsfStatus> {
        let filled = match &self.uniform {
            Some(u) => fast(u, &mut outs),
            None => false,
        };
        if !filled {
            for (i, e) in self.elements.iter().enumerate() {
                let r = eval(e, v[i], theta[i]);
                for k in 0..K {
                    outs[k][i] = r[k];
                }
            }
        }
        let all_finite = outs.iter().all(|o| o.iter().fold(true, |ok, x| ok & x.is_finite()));
        let all_inside = || v.iter().zip(theta).fold(true, |ok, (&v, &t)| ok & inside(v, t));
        if all_finite && (self.domain == RsfDomain::RsfDomainContinue || all_inside()) {
            return Ok(());
        }
        for i in 0..self.elements.len() {
            if !inside(v[i], theta[i]) {
                match self.domain {
                    RsfDomain::RsfDomainContinue => continue,
                    RsfDomain::RsfDomainRefuse => {
                        return Err(element(
                            i,
                            fail(
                                RsfStatus::RsfBadInput,
                                format!(
                                    "{call}: V = {:e}, theta = {:e}: rate-and-state friction is defined for V > 0 \
                                     and theta > 0 (a mesh made with RSF_DOMAIN_CONTINUE evaluates the closed \
                                     forms there)",
                                    v[i], theta[i]
                                ),
                            ),
                        ));
                    }
                }
            }
            if let Some(k) = (0..K).find(|&k| !outs[k][i].is_finite()) {
                return Err(element(
                    i,
                    fail(
                        RsfStatus::RsfBadInput,
                        format!(
                            "{call}: {} = {} at V = {:e}, theta = {:e}: the inputs are out of range",
                            names[k], outs[k][i], v[i], theta[i]
                        ),
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Makes a mesh of `n` elements from their friction and state structs (one state variable
/// per element), checking every element as the batch calls do; `*mesh` receives it (free it
/// with `rsf_mesh_free`). `domain` is an `RsfDomain` id: what the evaluations do at V ≤ 0 or
/// θ ≤ 0 (docs/faultsim.md). On failure `*mesh` is null and the first bad element is named.
///
/// # Safety
/// `fp` and `sp` must point to `n` valid values and `mesh` to one writable pointer (nulls are
/// refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_mesh_new(
    n: usize,
    fp: *const RsfFrictionParams,
    sp: *const RsfStateParams,
    domain: i32,
    mesh: *mut *mut RsfMesh,
) -> RsfStatus {
    const CALL: &str = "rsf_mesh_new";
    status(|| {
        // SAFETY: checked for null, one value, by the contract above
        let out = unsafe { output(CALL, "mesh", mesh, 1)? };
        out[0] = std::ptr::null_mut();
        let domain = match domain {
            0 => RsfDomain::RsfDomainRefuse,
            1 => RsfDomain::RsfDomainContinue,
            id => {
                return Err(fail(
                    RsfStatus::RsfUnknownId,
                    format!("{CALL}: unknown domain id {id} (0 refuse, 1 continue)"),
                ));
            }
        };
        let (fp, sp) = if n == 0 {
            (&[][..], &[][..])
        } else {
            // SAFETY: n values each, by the contract above
            unsafe { (input(CALL, "fp", fp, n)?, input(CALL, "sp", sp, n)?) }
        };
        let elements = fp
            .iter()
            .zip(sp)
            .enumerate()
            .map(|(i, (p, s))| Element::new(p, s).map_err(|st| element(i, st)))
            .collect::<Result<Vec<_>, _>>()?;
        let uniform = Uniform::of(&elements);
        out[0] = Box::into_raw(Box::new(RsfMesh { elements, domain, uniform }));
        Ok(())
    })
}

/// Frees a mesh made by `rsf_mesh_new` (null is allowed and does nothing).
///
/// # Safety
/// `mesh` must be null or a mesh from `rsf_mesh_new` not freed before, and no call may be
/// using it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_mesh_free(mesh: *mut RsfMesh) {
    if !mesh.is_null() {
        // SAFETY: made by Box::into_raw in rsf_mesh_new and not freed before, by the contract
        drop(unsafe { Box::from_raw(mesh) });
    }
}

/// The mesh behind `mesh` and the `n` values of each array, refused when `n` is not the
/// mesh's size.
///
/// # Safety
/// As the calls below.
unsafe fn checked<'a>(call: &str, mesh: *const RsfMesh, n: usize) -> Result<&'a RsfMesh, RsfStatus> {
    if mesh.is_null() {
        return Err(fail(RsfStatus::RsfBadInput, format!("{call}: mesh is null")));
    }
    // SAFETY: a live mesh from rsf_mesh_new, by the caller's contract
    let m = unsafe { &*mesh };
    if m.elements.len() != n {
        return Err(fail(
            RsfStatus::RsfBadInput,
            format!("{call}: n = {n} but the mesh has {} elements", m.elements.len()),
        ));
    }
    Ok(m)
}

/// Friction f of every element at (V, θ) (`n` must be the mesh's size).
///
/// # Safety
/// `mesh` must be a live mesh from `rsf_mesh_new`; `v`, `theta` and `mu` must point to `n`
/// values, `mu` overlapping neither input (nulls are refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_mesh_friction(
    mesh: *const RsfMesh,
    n: usize,
    v: *const f64,
    theta: *const f64,
    mu: *mut f64,
) -> RsfStatus {
    const CALL: &str = "rsf_mesh_friction";
    status(|| {
        // SAFETY: the contract above; nulls and sizes are checked by `checked`, `input`, `output`
        let (m, v, theta, mu) = unsafe {
            (
                checked(CALL, mesh, n)?,
                input(CALL, "v", v, n)?,
                input(CALL, "theta", theta, n)?,
                output(CALL, "mu", mu, n)?,
            )
        };
        m.over(CALL, v, theta, [mu], ["mu"], |_, _| false, |e, v, th| [e.friction(v, th)])
    })
}

/// ∂f/∂V and ∂f/∂θ of every element at (V, θ) (`n` must be the mesh's size).
///
/// # Safety
/// As `rsf_mesh_friction`, with the two outputs overlapping nothing.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_mesh_partials(
    mesh: *const RsfMesh,
    n: usize,
    v: *const f64,
    theta: *const f64,
    dmu_dv: *mut f64,
    dmu_dtheta: *mut f64,
) -> RsfStatus {
    const CALL: &str = "rsf_mesh_partials";
    status(|| {
        // SAFETY: the contract above; nulls and sizes are checked by `checked`, `input`, `output`
        let (m, v, theta, dv, dth) = unsafe {
            (
                checked(CALL, mesh, n)?,
                input(CALL, "v", v, n)?,
                input(CALL, "theta", theta, n)?,
                output(CALL, "dmu_dv", dmu_dv, n)?,
                output(CALL, "dmu_dtheta", dmu_dtheta, n)?,
            )
        };
        m.over(
            CALL,
            v,
            theta,
            [dv, dth],
            ["dmu_dv", "dmu_dtheta"],
            |u, [dv, dth]| {
                u.partials(v, theta, dv, dth);
                true
            },
            |e, v, th| {
                let (a, b) = e.partials(v, th);
                [a, b]
            },
        )
    })
}

/// dθ/dt of every element at (V, θ) (`n` must be the mesh's size).
///
/// # Safety
/// As `rsf_mesh_friction`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_mesh_state_rate(
    mesh: *const RsfMesh,
    n: usize,
    v: *const f64,
    theta: *const f64,
    dtheta_dt: *mut f64,
) -> RsfStatus {
    const CALL: &str = "rsf_mesh_state_rate";
    status(|| {
        // SAFETY: the contract above; nulls and sizes are checked by `checked`, `input`, `output`
        let (m, v, theta, rate) = unsafe {
            (
                checked(CALL, mesh, n)?,
                input(CALL, "v", v, n)?,
                input(CALL, "theta", theta, n)?,
                output(CALL, "dtheta_dt", dtheta_dt, n)?,
            )
        };
        m.over(
            CALL,
            v,
            theta,
            [rate],
            ["dtheta_dt"],
            |u, [rate]| {
                u.state_rate(v, theta, rate);
                true
            },
            |e, v, th| [e.state_rate(v, th)],
        )
    })
}
