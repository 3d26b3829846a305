//! # rsf-capi — the C ABI of rsf's per-element kernels
//!
//! For fault-simulation codes in C, C++ and Fortran (`iso_c_binding`): friction with its
//! partials, the state contribution, the state rate in log form and the slip-rate solve of the
//! quasi-dynamic balance, one element at a time or over caller-owned arrays. The header
//! `include/rsf.h` is generated from this file by cbindgen (`crates/rsf-capi/cbindgen.toml`);
//! a test checks that the committed header is what cbindgen makes of this source.
//!
//! Conventions (docs/faultsim.md): laws and friction forms are integer ids; parameters travel
//! in flat structs whose first field is `RSF_ABI_VERSION`; every function returns an
//! `RsfStatus` (0 = success) and never unwinds into C (a panic becomes `RSF_INTERNAL`);
//! `rsf_last_error` gives the message of the calling thread's last failure. Variables are
//! logs: `ln_v = ln V`, `ln_theta = ln θ`; units are the host's own (V, V0 and Dc consistent).

mod batch;
mod form;
mod mesh;

pub use batch::{rsf_batch_partials, rsf_batch_rates, rsf_batch_solve_slip_rate};
use form::{form_of, with_law};
pub use mesh::{
    RsfDomain, RsfMesh, rsf_mesh_free, rsf_mesh_friction, rsf_mesh_new, rsf_mesh_partials, rsf_mesh_state_rate,
};
use rsf_core::element::{SlipRateError, psi_term, solve_slip_rate};
use rsf_laws::Law;
use std::cell::RefCell;
use std::ffi::{CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// Version of the parameter structs; a struct with another `version` is refused.
pub const RSF_ABI_VERSION: u32 = 1;

/// Outcome of every call.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RsfStatus {
    /// Success.
    RsfOk = 0,
    /// A null pointer, a non-finite input, a bad count or a struct of another version.
    RsfBadInput = 1,
    /// An unknown law or friction-form id.
    RsfUnknownId = 2,
    /// No slip rate balances the stress.
    RsfNoRoot = 3,
    /// The slip-rate iteration did not converge.
    RsfNotConverged = 4,
    /// A bug in rsf (a caught panic): please report it.
    RsfInternal = 5,
}

/// State-evolution laws by id.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RsfLaw {
    /// Aging (Dieterich): dθ/dt = 1 − Vθ/Dc.
    RsfLawAging = 0,
    /// Slip (Ruina): dθ/dt = −(Vθ/Dc) ln(Vθ/Dc).
    RsfLawSlip = 1,
    /// Kato–Tullis composite with cut-off velocity `vc`.
    RsfLawKatoTullis = 2,
    /// Perrin–Rice–Zheng: dθ/dt = 1 − (Vθ/(2Dc))².
    RsfLawPrz = 3,
    /// Aging without healing: dθ/dt = −Vθ/Dc (QDYN's `itheta_law = 0`; no steady state).
    RsfLawAgingNoHealing = 6,
}

impl RsfLaw {
    /// The C enum value of a registry law, `None` for one this ABI does not carry (Nagata's
    /// law needs the shear-stress rate; the one-state Aging–Slip mixture is not in this ABI
    /// version). Exhaustive: a new law fails to compile here until the
    /// ABI decides.
    pub fn of(law: Law) -> Option<RsfLaw> {
        match law {
            Law::Aging => Some(RsfLaw::RsfLawAging),
            Law::Slip => Some(RsfLaw::RsfLawSlip),
            Law::KatoTullis => Some(RsfLaw::RsfLawKatoTullis),
            Law::Prz => Some(RsfLaw::RsfLawPrz),
            Law::AgingNoHealing => Some(RsfLaw::RsfLawAgingNoHealing),
            Law::Nagata | Law::AgingSlip => None,
        }
    }
}

/// Friction forms by id.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RsfForm {
    /// f = f0 + a ln(V/V0) + Ψ.
    RsfFormClassic = 0,
    /// f = a asinh(V/(2V0) exp((f0 + Ψ)/a)) (SEAS benchmarks).
    RsfFormRegularized = 1,
    /// Cut-off velocities (Okubo 1989; QDYN's law 1): f = f0 − a ln(V1/V + 1) + Ψ with each
    /// state's term b ln(V2 θ/Dc + 1). `RsfFrictionParams::v0` holds V1, the direct effect's
    /// cut-off; each state's `RsfStateParams::vc` holds its V2, the evolution effect's
    /// cut-off (so a Kato–Tullis state, whose `vc` is its own, is refused with this form).
    /// Ψ comes from `rsf_state_term`, not `rsf_psi`; there is no slip-rate solve for it.
    RsfFormCutoff = 2,
}

/// Friction parameters of one element.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RsfFrictionParams {
    /// `RSF_ABI_VERSION`.
    pub version: u32,
    /// An `RsfForm` id.
    pub form: i32,
    /// Reference friction f0.
    pub f0: f64,
    /// Direct-effect parameter a.
    pub a: f64,
    /// Reference slip rate V0 (V1 for `RsfFormCutoff`).
    pub v0: f64,
}

/// One state variable of one element.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RsfStateParams {
    /// `RSF_ABI_VERSION`.
    pub version: u32,
    /// An `RsfLaw` id.
    pub law: i32,
    /// Evolution-effect parameter b.
    pub b: f64,
    /// Characteristic slip distance Dc.
    pub dc: f64,
    /// Cut-off velocity: Kato–Tullis's, or V2 under `RsfFormCutoff`; ignored otherwise.
    pub vc: f64,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn fail(status: RsfStatus, msg: String) -> RsfStatus {
    LAST_ERROR.with(|e| *e.borrow_mut() = CString::new(msg.replace('\0', " ")).unwrap_or_default());
    status
}

/// Runs `f`, turning a panic into `RSF_INTERNAL`.
fn guard(f: impl FnOnce() -> RsfStatus) -> RsfStatus {
    catch_unwind(AssertUnwindSafe(f))
        .unwrap_or_else(|_| fail(RsfStatus::RsfInternal, "internal error in rsf (a caught panic)".into()))
}

fn status_of(e: SlipRateError) -> RsfStatus {
    let code = match e {
        SlipRateError::BadInput => RsfStatus::RsfBadInput,
        SlipRateError::NoRoot => RsfStatus::RsfNoRoot,
        SlipRateError::NotConverged => RsfStatus::RsfNotConverged,
    };
    fail(code, e.to_string())
}

/// The ABI version this library implements (`RSF_ABI_VERSION`).
#[unsafe(no_mangle)]
pub extern "C" fn rsf_abi_version() -> u32 {
    RSF_ABI_VERSION
}

/// The message of the calling thread's last failure (empty if none); valid until the next
/// failing call on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn rsf_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// Refuses a non-finite input, naming it.
fn finite(call: &str, values: &[(&str, f64)]) -> Result<(), RsfStatus> {
    match values.iter().find(|(_, v)| !v.is_finite()) {
        Some((name, v)) => Err(fail(RsfStatus::RsfBadInput, format!("{call}: {name} = {v} is not finite"))),
        None => Ok(()),
    }
}

/// Refuses a result that overflowed (finite inputs far out of range), naming it.
fn finite_out(call: &str, values: &[(&str, f64)]) -> Result<(), RsfStatus> {
    match values.iter().find(|(_, v)| !v.is_finite()) {
        Some((name, v)) => {
            Err(fail(RsfStatus::RsfBadInput, format!("{call}: {name} = {v}: the inputs are out of range")))
        }
        None => Ok(()),
    }
}

/// Element `i`'s failure, with the message of the check that refused it.
fn element(i: usize, st: RsfStatus) -> RsfStatus {
    fail(st, format!("element {i}: {}", last_message()))
}

/// Refuses a null array, or `n` values of `T` that no allocation can hold.
fn addressable<T>(call: &str, what: &str, null: bool, n: usize) -> Result<(), RsfStatus> {
    if null || n > isize::MAX as usize / size_of::<T>().max(1) {
        return Err(fail(RsfStatus::RsfBadInput, format!("{call}: {what} is null or n = {n} is too large")));
    }
    Ok(())
}

/// `n` elements of `T` at `p`, refused when null or when `n` values cannot be addressed.
///
/// # Safety
/// When non-null, `p` must point to `n` valid values of `T` that nothing writes while the
/// slice lives (the header's contract: arrays do not overlap).
unsafe fn input<'a, T>(call: &str, what: &str, p: *const T, n: usize) -> Result<&'a [T], RsfStatus> {
    addressable::<T>(call, what, p.is_null(), n)?;
    // (checked above: non-null, within isize::MAX bytes; valid for n reads, not written meanwhile)
    // SAFETY: the caller's contract, stated in this function's doc, and the checks above
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// `n` writable elements of `T` at `p`.
///
/// # Safety
/// When non-null, `p` must point to `n` values of `T` that no other slice of the call
/// overlaps (the header's contract).
unsafe fn output<'a, T>(call: &str, what: &str, p: *mut T, n: usize) -> Result<&'a mut [T], RsfStatus> {
    addressable::<T>(call, what, p.is_null(), n)?;
    // (checked above: non-null, within isize::MAX bytes; valid for n writes, not aliased)
    // SAFETY: the caller's contract, stated in this function's doc, and the checks above
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// Runs `f`, turning a refusal into its status (the message is already recorded).
fn status(f: impl FnOnce() -> Result<(), RsfStatus>) -> RsfStatus {
    guard(|| match f() {
        Ok(()) => RsfStatus::RsfOk,
        Err(st) => st,
    })
}

/// Friction f at (ln V, Ψ) and its partials ∂f/∂ln V and ∂f/∂Ψ.
///
/// # Safety
/// `p` and the three outputs must be valid pointers (nulls are refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_friction(
    p: *const RsfFrictionParams,
    ln_v: f64,
    psi: f64,
    f: *mut f64,
    df_dln_v: *mut f64,
    df_dpsi: *mut f64,
) -> RsfStatus {
    const CALL: &str = "rsf_friction";
    status(|| {
        // SAFETY: each pointer is checked for null and is one value by the contract above
        let (p, f, df_dln_v, df_dpsi) = unsafe {
            (
                &input(CALL, "p", p, 1)?[0],
                output(CALL, "f", f, 1)?,
                output(CALL, "df_dln_v", df_dln_v, 1)?,
                output(CALL, "df_dpsi", df_dpsi, 1)?,
            )
        };
        let form = form_of(p)?;
        finite(CALL, &[("ln_v", ln_v), ("psi", psi)])?;
        let r = form.friction(p, ln_v, psi);
        finite_out(CALL, &[("f", r.value), ("df_dln_v", r.d_ln_v), ("df_dpsi", r.d_psi)])?;
        (f[0], df_dln_v[0], df_dpsi[0]) = (r.value, r.d_ln_v, r.d_psi);
        Ok(())
    })
}

/// One state variable's contribution to Ψ, b ln(V0 θ/(s Dc)), at `ln_theta` (∂/∂ln θ = b),
/// for the classic and regularized forms (`rsf_state_term` serves every form).
///
/// # Safety
/// `s` and `psi` must be valid pointers (nulls are refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_psi(s: *const RsfStateParams, v0: f64, ln_theta: f64, psi: *mut f64) -> RsfStatus {
    const CALL: &str = "rsf_psi";
    status(|| {
        // SAFETY: each pointer is checked for null and is one value by the contract above
        let (s, psi) = unsafe { (&input(CALL, "s", s, 1)?[0], output(CALL, "psi", psi, 1)?) };
        finite(CALL, &[("v0", v0), ("ln_theta", ln_theta)])?;
        if !(v0 > 0.0) {
            return Err(fail(RsfStatus::RsfBadInput, format!("{CALL}: v0 = {v0} must be positive")));
        }
        let v = with_law(s, |_, scale| psi_term(s.b, v0, s.dc, scale, ln_theta))?;
        finite_out(CALL, &[("psi", v)])?;
        psi[0] = v;
        Ok(())
    })
}

/// d(ln θ)/dt of one state variable at (ln V, ln θ).
///
/// # Safety
/// `s` and `rate` must be valid pointers (nulls are refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_ln_theta_rate(
    s: *const RsfStateParams,
    ln_v: f64,
    ln_theta: f64,
    rate: *mut f64,
) -> RsfStatus {
    const CALL: &str = "rsf_ln_theta_rate";
    status(|| {
        // SAFETY: each pointer is checked for null and is one value by the contract above
        let (s, rate) = unsafe { (&input(CALL, "s", s, 1)?[0], output(CALL, "rate", rate, 1)?) };
        finite(CALL, &[("ln_v", ln_v), ("ln_theta", ln_theta)])?;
        let r = with_law(s, |g, _| g(ln_v, ln_theta))?;
        finite_out(CALL, &[("rate", r)])?;
        rate[0] = r;
        Ok(())
    })
}

/// ln V with τ − ηV = σ f(V, Ψ), from the warm start `ln_v_guess`; `iterations` may be null.
///
/// # Safety
/// `p` and `ln_v` must be valid pointers; `iterations` valid or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_solve_slip_rate(
    p: *const RsfFrictionParams,
    psi: f64,
    tau: f64,
    sigma: f64,
    eta: f64,
    ln_v_guess: f64,
    ln_v: *mut f64,
    iterations: *mut i32,
) -> RsfStatus {
    const CALL: &str = "rsf_solve_slip_rate";
    status(|| {
        // SAFETY: each pointer is checked for null and is one value by the contract above
        let (p, ln_v) = unsafe { (&input(CALL, "p", p, 1)?[0], output(CALL, "ln_v", ln_v, 1)?) };
        let form = form_of(p)?.core(CALL)?;
        finite(CALL, &[("psi", psi), ("tau", tau), ("sigma", sigma), ("eta", eta), ("ln_v_guess", ln_v_guess)])?;
        let r = solve_slip_rate(form, p.f0, p.a, p.v0, psi, tau, sigma, eta, ln_v_guess).map_err(status_of)?;
        ln_v[0] = r.ln_v;
        if !iterations.is_null() {
            // SAFETY: non-null, and one valid value by the contract above
            unsafe { *iterations = r.iterations as i32 };
        }
        Ok(())
    })
}

/// One state variable's contribution to Ψ under the form of `p`, and its partial
/// ∂Ψ/∂ln θ: b ln(V0 θ/(s Dc)) and b for the classic and regularized forms, b ln(V2 θ/(s Dc) + 1)
/// and b V2 θ/(V2 θ + s Dc) for the cut-off form (V2 = `s.vc`).
///
/// # Safety
/// `p`, `s` and the two outputs must be valid pointers (nulls are refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_state_term(
    p: *const RsfFrictionParams,
    s: *const RsfStateParams,
    ln_theta: f64,
    psi: *mut f64,
    dpsi_dln_theta: *mut f64,
) -> RsfStatus {
    const CALL: &str = "rsf_state_term";
    status(|| {
        // SAFETY: each pointer is checked for null and is one value by the contract above
        let (p, s, psi, dpsi) = unsafe {
            (
                &input(CALL, "p", p, 1)?[0],
                &input(CALL, "s", s, 1)?[0],
                output(CALL, "psi", psi, 1)?,
                output(CALL, "dpsi_dln_theta", dpsi_dln_theta, 1)?,
            )
        };
        let form = form_of(p)?;
        form.check_state(s)?;
        finite(CALL, &[("ln_theta", ln_theta)])?;
        let (v, d) = with_law(s, |_, scale| form.state_term(p, s, scale, ln_theta))?;
        finite_out(CALL, &[("psi", v), ("dpsi_dln_theta", d)])?;
        (psi[0], dpsi[0]) = (v, d);
        Ok(())
    })
}

fn last_message() -> String {
    LAST_ERROR.with(|e| e.borrow().to_string_lossy().into_owned())
}
