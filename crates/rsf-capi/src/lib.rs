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

use rsf_core::FrictionForm;
use rsf_core::element::{SlipRateError, friction, ln_theta_rate, psi_term, solve_slip_rate};
use rsf_laws::{Aging, KatoTullis, Law, Prz, Slip};
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
}

impl RsfLaw {
    /// The C enum value of a registry law, `None` for one this ABI does not carry (Nagata's
    /// law needs the shear-stress rate). Exhaustive: a new law fails to compile here until the
    /// ABI decides.
    pub fn of(law: Law) -> Option<RsfLaw> {
        match law {
            Law::Aging => Some(RsfLaw::RsfLawAging),
            Law::Slip => Some(RsfLaw::RsfLawSlip),
            Law::KatoTullis => Some(RsfLaw::RsfLawKatoTullis),
            Law::Prz => Some(RsfLaw::RsfLawPrz),
            Law::Nagata => None,
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
    /// Reference slip rate V0.
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
    /// Cut-off velocity (Kato–Tullis only; ignored otherwise).
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

fn form_of(p: &RsfFrictionParams) -> Result<FrictionForm, RsfStatus> {
    if p.version != RSF_ABI_VERSION {
        return Err(fail(
            RsfStatus::RsfBadInput,
            format!("RsfFrictionParams.version {} (expected {RSF_ABI_VERSION})", p.version),
        ));
    }
    if ![p.f0, p.a, p.v0].iter().all(|x| x.is_finite()) || p.a <= 0.0 || p.v0 <= 0.0 {
        return Err(fail(
            RsfStatus::RsfBadInput,
            format!("friction parameters need finite f0, a > 0, v0 > 0 (got {p:?})"),
        ));
    }
    match p.form {
        0 => Ok(FrictionForm::Classic),
        1 => Ok(FrictionForm::Regularized),
        id => Err(fail(RsfStatus::RsfUnknownId, format!("unknown friction form id {id} (0 classic, 1 regularized)"))),
    }
}

/// Calls `f` with the law of `s`, after checking it.
fn with_law<T>(s: &RsfStateParams, f: impl FnOnce(&dyn Fn(f64, f64) -> f64, f64) -> T) -> Result<T, RsfStatus> {
    if s.version != RSF_ABI_VERSION {
        return Err(fail(
            RsfStatus::RsfBadInput,
            format!("RsfStateParams.version {} (expected {RSF_ABI_VERSION})", s.version),
        ));
    }
    if !(s.b.is_finite() && s.dc.is_finite() && s.dc > 0.0) {
        return Err(fail(RsfStatus::RsfBadInput, format!("state parameters need finite b and dc > 0 (got {s:?})")));
    }
    let (b, dc) = (s.b, s.dc);
    let Some(law) = Law::from_c_id(s.law) else {
        let known: Vec<String> = Law::ALL.iter().map(|l| format!("{} {}", l.c_id(), l.name())).collect();
        return Err(fail(RsfStatus::RsfUnknownId, format!("unknown law id {} ({})", s.law, known.join(", "))));
    };
    Ok(match law {
        Law::Aging => f(&|x, z| ln_theta_rate(&Aging, x, z, dc, b), 1.0),
        Law::Slip => f(&|x, z| ln_theta_rate(&Slip, x, z, dc, b), 1.0),
        Law::KatoTullis if s.vc.is_finite() && s.vc > 0.0 => {
            let law = KatoTullis { vc: s.vc };
            f(&|x, z| ln_theta_rate(&law, x, z, dc, b), 1.0)
        }
        Law::KatoTullis => {
            return Err(fail(RsfStatus::RsfBadInput, format!("Kato–Tullis needs vc > 0 (got {})", s.vc)));
        }
        Law::Prz => f(&|x, z| ln_theta_rate(&Prz, x, z, dc, b), 2.0),
        // this ABI's rates take no shear-stress rate, which Nagata's law needs
        Law::Nagata => {
            return Err(fail(
                RsfStatus::RsfUnknownId,
                "law id 4 (nagata) needs the shear-stress rate, which this ABI version does not carry".into(),
            ));
        }
    })
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
        let r = friction(form, p.f0, p.a, p.v0, ln_v, psi);
        finite_out(CALL, &[("f", r.value), ("df_dln_v", r.d_ln_v), ("df_dpsi", r.d_psi)])?;
        (f[0], df_dln_v[0], df_dpsi[0]) = (r.value, r.d_ln_v, r.d_psi);
        Ok(())
    })
}

/// One state variable's contribution to Ψ, b ln(V0 θ/(s Dc)), at `ln_theta` (∂/∂ln θ = b).
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
        let form = form_of(p)?;
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

/// Over `n` elements (arrays of length n, caller-owned): friction, ∂f/∂ln V, ∂f/∂Ψ and
/// d ln θ/dt of element i from `fp[i]`, `sp[i]`, `ln_v[i]`, `ln_theta[i]` (one state
/// variable per element; Ψ = that state's term). Every input is checked as the one-element
/// calls check it; the first bad element is named (`element i: …` in `rsf_last_error`) and
/// nothing after it is written.
///
/// # Safety
/// Every pointer must point to `n` valid values (nulls are refused), and the output arrays
/// must not overlap each other or the inputs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_batch_rates(
    n: usize,
    fp: *const RsfFrictionParams,
    sp: *const RsfStateParams,
    ln_v: *const f64,
    ln_theta: *const f64,
    f: *mut f64,
    df_dln_v: *mut f64,
    df_dpsi: *mut f64,
    ln_theta_rate_out: *mut f64,
) -> RsfStatus {
    const CALL: &str = "rsf_batch_rates";
    status(|| {
        if n == 0 {
            return Ok(());
        }
        // each pointer is checked for null and n for size by `input`/`output`
        // SAFETY: n values each, not overlapping, by the contract in this function's doc
        let (fp, sp, ln_v, ln_theta, f, df_dln_v, df_dpsi, rate) = unsafe {
            (
                input(CALL, "fp", fp, n)?,
                input(CALL, "sp", sp, n)?,
                input(CALL, "ln_v", ln_v, n)?,
                input(CALL, "ln_theta", ln_theta, n)?,
                output(CALL, "f", f, n)?,
                output(CALL, "df_dln_v", df_dln_v, n)?,
                output(CALL, "df_dpsi", df_dpsi, n)?,
                output(CALL, "ln_theta_rate", ln_theta_rate_out, n)?,
            )
        };
        for i in 0..n {
            let (p, s, x, z) = (&fp[i], &sp[i], ln_v[i], ln_theta[i]);
            let form = form_of(p).map_err(|st| element(i, st))?;
            finite(CALL, &[("ln_v", x), ("ln_theta", z)]).map_err(|st| element(i, st))?;
            let (fr, r) = with_law(s, |g, scale| {
                (friction(form, p.f0, p.a, p.v0, x, psi_term(s.b, p.v0, s.dc, scale, z)), g(x, z))
            })
            .map_err(|st| element(i, st))?;
            finite_out(CALL, &[("f", fr.value), ("df_dln_v", fr.d_ln_v), ("df_dpsi", fr.d_psi), ("ln_theta_rate", r)])
                .map_err(|st| element(i, st))?;
            (f[i], df_dln_v[i], df_dpsi[i], rate[i]) = (fr.value, fr.d_ln_v, fr.d_psi, r);
        }
        Ok(())
    })
}

/// Over `n` elements: the slip rate of element i from the balance with its own `tau[i]`,
/// `sigma[i]`, `eta[i]` and state (Ψ from `sp[i]`, `ln_theta[i]`); `ln_v` holds the warm
/// starts on entry and the roots on return. Stops at the first bad element or element without
/// a root and names it (`element i: …` in `rsf_last_error`).
///
/// # Safety
/// Every pointer must point to `n` valid values (nulls are refused), and `ln_v` must not
/// overlap the inputs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_batch_solve_slip_rate(
    n: usize,
    fp: *const RsfFrictionParams,
    sp: *const RsfStateParams,
    ln_theta: *const f64,
    tau: *const f64,
    sigma: *const f64,
    eta: *const f64,
    ln_v: *mut f64,
) -> RsfStatus {
    const CALL: &str = "rsf_batch_solve_slip_rate";
    status(|| {
        if n == 0 {
            return Ok(());
        }
        // each pointer is checked for null and n for size by `input`/`output`
        // SAFETY: n values each, `ln_v` not overlapping the inputs, by the contract in this function's doc
        let (fp, sp, ln_theta, tau, sigma, eta, ln_v) = unsafe {
            (
                input(CALL, "fp", fp, n)?,
                input(CALL, "sp", sp, n)?,
                input(CALL, "ln_theta", ln_theta, n)?,
                input(CALL, "tau", tau, n)?,
                input(CALL, "sigma", sigma, n)?,
                input(CALL, "eta", eta, n)?,
                output(CALL, "ln_v", ln_v, n)?,
            )
        };
        for i in 0..n {
            let (p, s) = (&fp[i], &sp[i]);
            let form = form_of(p).map_err(|st| element(i, st))?;
            finite(
                CALL,
                &[("ln_theta", ln_theta[i]), ("tau", tau[i]), ("sigma", sigma[i]), ("eta", eta[i]), ("ln_v", ln_v[i])],
            )
            .map_err(|st| element(i, st))?;
            let psi =
                with_law(s, |_, scale| psi_term(s.b, p.v0, s.dc, scale, ln_theta[i])).map_err(|st| element(i, st))?;
            finite_out(CALL, &[("psi", psi)]).map_err(|st| element(i, st))?;
            let r = solve_slip_rate(form, p.f0, p.a, p.v0, psi, tau[i], sigma[i], eta[i], ln_v[i])
                .map_err(|e| element(i, status_of(e)))?;
            ln_v[i] = r.ln_v;
        }
        Ok(())
    })
}

fn last_message() -> String {
    LAST_ERROR.with(|e| e.borrow().to_string_lossy().into_owned())
}
