//! The batch entry points: one call over caller-owned arrays of elements.

use crate::form::{AbiLaw, Form, LnMemo, form_of, with_law};
use crate::{
    RsfFrictionParams, RsfStateParams, RsfStatus, element, finite, finite_out, input, output, status, status_of,
};
use rsf_core::LnArgs;
use rsf_core::element::{friction_at, reference_rate};
use rsf_core::element::{psi_term, solve_slip_rate};

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
    // SAFETY: forwarded, with this function's contract
    unsafe {
        over_elements(
            "rsf_batch_rates",
            Third::DfDpsi,
            n,
            fp,
            sp,
            ln_v,
            ln_theta,
            f,
            df_dln_v,
            df_dpsi,
            ln_theta_rate_out,
        )
    }
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
            let form = form_of(p).and_then(|f| f.core(CALL)).map_err(|st| element(i, st))?;
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

/// Over `n` elements (arrays of length n, caller-owned), what a host integrating V and θ (or
/// their logs) asks for at every right-hand side: friction f, ∂f/∂ln V, ∂f/∂ln θ and
/// d ln θ/dt of element i from `fp[i]`, `sp[i]`, `ln_v[i]`, `ln_theta[i]`, one state variable
/// per element, in any form (the cut-off form included). In θ variables: ∂f/∂V = ∂f/∂ln V / V,
/// ∂f/∂θ = ∂f/∂ln θ / θ and dθ/dt = θ d ln θ/dt. Checks and failures as `rsf_batch_rates`.
///
/// # Safety
/// Every pointer must point to `n` valid values (nulls are refused), and the output arrays
/// must not overlap each other or the inputs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rsf_batch_partials(
    n: usize,
    fp: *const RsfFrictionParams,
    sp: *const RsfStateParams,
    ln_v: *const f64,
    ln_theta: *const f64,
    f: *mut f64,
    df_dln_v: *mut f64,
    df_dln_theta: *mut f64,
    ln_theta_rate_out: *mut f64,
) -> RsfStatus {
    // SAFETY: forwarded, with this function's contract
    unsafe {
        over_elements(
            "rsf_batch_partials",
            Third::DfDlnTheta,
            n,
            fp,
            sp,
            ln_v,
            ln_theta,
            f,
            df_dln_v,
            df_dln_theta,
            ln_theta_rate_out,
        )
    }
}

/// The third output of [`over_elements`]: ∂f/∂Ψ (`rsf_batch_rates`) or ∂f/∂ln θ
/// (`rsf_batch_partials`).
#[derive(Clone, Copy)]
enum Third {
    DfDpsi,
    DfDlnTheta,
}

/// Friction, ∂f/∂ln V, the `third` partial and d ln θ/dt of every element: the body of both
/// batch rate calls. The logs of V0, s Dc, Dc and the form's reference rate are taken once for
/// a run of elements that share them (the same numbers as the one-element calls).
///
/// # Safety
/// As `rsf_batch_partials`.
#[allow(clippy::too_many_arguments)]
unsafe fn over_elements(
    call: &str,
    third: Third,
    n: usize,
    fp: *const RsfFrictionParams,
    sp: *const RsfStateParams,
    ln_v: *const f64,
    ln_theta: *const f64,
    f: *mut f64,
    df_dln_v: *mut f64,
    df_third: *mut f64,
    ln_theta_rate_out: *mut f64,
) -> RsfStatus {
    let third_name = match third {
        Third::DfDpsi => "df_dpsi",
        Third::DfDlnTheta => "df_dln_theta",
    };
    status(|| {
        if n == 0 {
            return Ok(());
        }
        // each pointer is checked for null and n for size by `input`/`output`
        // SAFETY: n values each, not overlapping, by the caller's contract
        let (fp, sp, ln_v, ln_theta, f, df_dln_v, df_third, rate) = unsafe {
            (
                input(call, "fp", fp, n)?,
                input(call, "sp", sp, n)?,
                input(call, "ln_v", ln_v, n)?,
                input(call, "ln_theta", ln_theta, n)?,
                output(call, "f", f, n)?,
                output(call, "df_dln_v", df_dln_v, n)?,
                output(call, third_name, df_third, n)?,
                output(call, "ln_theta_rate", ln_theta_rate_out, n)?,
            )
        };
        let (mut ln_v0, mut ln_sdc, mut ln_dc, mut ln_ref) =
            (LnMemo::default(), LnMemo::default(), LnMemo::default(), LnMemo::default());
        for i in 0..n {
            let (p, s, x, z) = (&fp[i], &sp[i], ln_v[i], ln_theta[i]);
            let form = form_of(p).map_err(|st| element(i, st))?;
            form.check_state(s).map_err(|st| element(i, st))?;
            let law = AbiLaw::of(s).map_err(|st| element(i, st))?;
            finite(call, &[("ln_v", x), ("ln_theta", z)]).map_err(|st| element(i, st))?;
            let scale = law.theta_scale();
            // Ψ's term as `psi_term` and `cutoff_psi_term` write it, with the logs memoised
            let (psi, dpsi) = match form {
                Form::Core(_) => (s.b * (ln_v0.ln(p.v0) + z - ln_sdc.ln(scale * s.dc)), s.b),
                Form::Cutoff => form.state_term(p, s, scale, z),
            };
            let fr = match form {
                Form::Core(core) => friction_at(core, p.f0, p.a, ln_ref.ln(reference_rate(core, p.v0)), x, psi),
                Form::Cutoff => form.friction(p, x, psi),
            };
            let r = law.ln_rate(&LnArgs::with_ln_dc(x, z, s.dc, ln_dc.ln(s.dc), s.b));
            let d3 = match third {
                Third::DfDpsi => fr.d_psi,
                Third::DfDlnTheta => fr.d_psi * dpsi,
            };
            finite_out(call, &[("f", fr.value), ("df_dln_v", fr.d_ln_v), (third_name, d3), ("ln_theta_rate", r)])
                .map_err(|st| element(i, st))?;
            (f[i], df_dln_v[i], df_third[i], rate[i]) = (fr.value, fr.d_ln_v, d3, r);
        }
        Ok(())
    })
}
