//! Properties of dθ/dt at one point: finite values, the log form, the Jacobian, the steady
//! state, and invariance under changes of the time and length units.

use crate::{Claims, Outcome, Property, Ranges, run_cases};
use proptest::prelude::*;
use rsf_core::{Jet, LnArgs, Real, StateArgs, StateLaw};

/// Agreement of the log form with dθ/dt / θ, relative to the size of the rate's terms.
const LOG_FORM_TOL: f64 = 1e-11;
/// Agreement of a hand-written Jacobian with the dual-number one (both exact: rounding only).
const DUAL_TOL: f64 = 1e-10;
/// Agreement with central differences (step 1e-6 in ln x: truncation ~1e-12, rounding ~1e-10).
const FD_TOL: f64 = 1e-6;
/// Relative step of the central differences.
const FD_STEP: f64 = 1e-6;
/// |dθ/dt| at the steady state, relative to the size of the rate's terms.
const ROOT_TOL: f64 = 1e-9;
/// θ_ss against the claimed s·Dc/V.
const CLOSED_FORM_TOL: f64 = 1e-12;
/// Invariance under rescaling, relative to the size of the rate's terms (a few roundings of Ω).
const SCALING_TOL: f64 = 1e-10;

/// One point of the law's arguments, and a unit-change exponent for the scaling properties.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Point {
    v: f64,
    omega: f64,
    dc: f64,
    b: f64,
    stress_rate: f64,
    normal_stress: f64,
    normal_stress_rate: f64,
    /// log10 of the unit change c (time) or s (length).
    decades: f64,
}

impl Point {
    fn args(&self) -> StateArgs<f64> {
        StateArgs {
            v: self.v,
            theta: self.omega * self.dc / self.v,
            dc: self.dc,
            b: self.b,
            stress_rate: self.stress_rate,
            normal_stress: self.normal_stress,
            normal_stress_rate: self.normal_stress_rate,
        }
    }
}

pub(crate) fn log_uniform((lo, hi): (f64, f64)) -> BoxedStrategy<f64> {
    if hi > lo && lo > 0.0 { (lo.ln()..hi.ln()).prop_map(f64::exp).boxed() } else { Just(lo).boxed() }
}

fn uniform((lo, hi): (f64, f64)) -> BoxedStrategy<f64> {
    if hi > lo { (lo..hi).boxed() } else { Just(lo).boxed() }
}

fn points(r: &Ranges) -> impl Strategy<Value = Point> + use<> {
    (
        log_uniform(r.v),
        log_uniform(r.omega),
        log_uniform(r.dc),
        log_uniform(r.b),
        uniform(r.stress_rate),
        log_uniform(r.normal_stress),
        uniform(r.normal_stress_rate),
        -3.0f64..3.0,
    )
        .prop_map(|(v, omega, dc, b, stress_rate, normal_stress, normal_stress_rate, decades)| Point {
            v,
            omega,
            dc,
            b,
            stress_rate,
            normal_stress,
            normal_stress_rate,
            decades,
        })
}

/// The law with only `theta_rate` of its own: every default, so its Jacobian is the
/// dual-number one.
#[derive(Debug, Clone)]
struct Auto<L>(L);
impl<L: StateLaw> StateLaw for Auto<L> {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        self.0.theta_rate(s)
    }
}

/// The partial derivatives the kit judges with: the dual numbers over `theta_rate`, or the
/// law's own `jet` when its derivatives are central differences (a Python function, whose
/// dual partials are zero).
fn reference_jet<L: StateLaw>(law: &L, claims: &Claims, s: &StateArgs<f64>) -> Jet {
    if claims.derivatives_by_differences { law.jet(s) } else { Auto(law.clone()).jet(s) }
}

/// The size of the rate's terms at `s`: 1, |G|, Ω(1 + |ln Ω|) and each partial times its
/// variable (from the dual-number Jacobian) — what rounding is measured against.
fn magnitude(g: f64, s: &StateArgs<f64>, j: &Jet) -> f64 {
    let omega = s.v * s.theta / s.dc;
    1.0 + g.abs()
        + omega * (1.0 + omega.ln().abs())
        + (j.d_v * s.v).abs()
        + (j.d_theta * s.theta).abs()
        + (j.d_dc * s.dc).abs()
        + (j.d_b * s.b).abs()
        + j.d_stress_rate.abs() * (1.0 + s.stress_rate.abs())
}

/// A copy of `law` with each named parameter multiplied by `factor`.
fn rescaled<L: StateLaw>(law: &L, names: &[&'static str], factor: f64) -> Result<L, String> {
    let mut out = law.clone();
    let params = law.parameters();
    for &name in names {
        let Some(&(_, value)) = params.iter().find(|(n, _)| *n == name) else {
            return Err(format!("the claims name parameter `{name}`, which parameters() does not list"));
        };
        out.set_parameter(name, value * factor).map_err(|e| format!("cannot rescale `{name}`: {e}"))?;
    }
    Ok(out)
}

pub(crate) fn run<L: StateLaw>(p: Property, law: &L, claims: &Claims) -> Result<Outcome, (String, String)> {
    let pts = points(&claims.ranges);
    let n = claims.cases;
    match p {
        Property::Finite => run_cases(n, &pts, |pt| finite(law, &pt)),
        Property::LogForm => run_cases(n, &pts, |pt| log_form(law, claims, &pt)),
        Property::Jacobian => run_cases(n, &pts, |pt| jacobian(law, claims, &pt)),
        Property::SteadyState => run_cases(n, &pts, |pt| steady_state(law, claims, &pt)),
        Property::TimeScaling => run_cases(n, &pts, |pt| time_scaling(law, claims, &pt)),
        Property::UnitScaling => run_cases(n, &pts, |pt| unit_scaling(law, claims, &pt)),
        Property::ParameterRoundTrip => parameter_round_trip(law),
        Property::ParameterDerivative => {
            let exact = law.parameters().iter().any(|(q, _)| law.parameter_derivative(q, &pts_any(claims)).is_some());
            if law.parameters().is_empty() {
                Ok(Outcome::Skipped("the law has no parameter of its own"))
            } else if !exact {
                Ok(Outcome::Skipped("no exact parameter derivative: fits take central differences"))
            } else {
                run_cases(n, &pts, |pt| parameter_derivative(law, &pt))
            }
        }
        Property::ViTIdentity | Property::TimeShift | Property::IntegratorsAgree => {
            unreachable!("solver-level properties are run by solver.rs")
        }
    }
}

fn finite<L: StateLaw>(law: &L, pt: &Point) -> Result<(), String> {
    let s = pt.args();
    let g = law.theta_rate(&s);
    let ln = law.ln_theta_rate(&ln_args(pt));
    let j = law.jet(&s);
    let all = [g, ln, j.rate, j.d_v, j.d_theta, j.d_stress_rate, j.d_dc, j.d_b];
    if all.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(format!("not finite: dθ/dt {g:e}, log form {ln:e}, jet {j:?}"))
    }
}

fn ln_args(pt: &Point) -> LnArgs {
    let s = pt.args();
    LnArgs {
        stress_rate: pt.stress_rate,
        normal_stress: pt.normal_stress,
        normal_stress_rate: pt.normal_stress_rate,
        ..LnArgs::new(s.v.ln(), s.theta.ln(), s.dc, s.b)
    }
}

fn log_form<L: StateLaw>(law: &L, claims: &Claims, pt: &Point) -> Result<(), String> {
    let a = ln_args(pt);
    let s = a.state_args();
    let g = law.theta_rate(&s);
    let generic = g / s.theta;
    let ln = law.ln_theta_rate(&a);
    let tol = LOG_FORM_TOL * magnitude(g, &s, &reference_jet(law, claims, &s)) / s.theta;
    if (ln - generic).abs() <= tol {
        Ok(())
    } else {
        Err(format!("ln_theta_rate {ln:e} but theta_rate/θ {generic:e} (allowed difference {tol:e})"))
    }
}

fn jacobian<L: StateLaw>(law: &L, claims: &Claims, pt: &Point) -> Result<(), String> {
    let s = pt.args();
    let j = law.jet(&s);
    let auto = Auto(law.clone()).jet(&s);
    let g = law.theta_rate(&s);
    // a law without dual numbers has zero dual partials: its terms' size from its own jet
    let mag = magnitude(g, &s, if claims.derivatives_by_differences { &j } else { &auto });
    if (j.rate - g).abs() > DUAL_TOL * mag {
        return Err(format!("jet().rate {:e} but theta_rate {g:e}", j.rate));
    }
    // central differences of x·∂G/∂x: in ln x for the positive variables, in x for dτ/dt
    let fd_log = |set: &dyn Fn(f64) -> StateArgs<f64>, x: f64| {
        (law.theta_rate(&set(x * FD_STEP.exp())) - law.theta_rate(&set(x * (-FD_STEP).exp()))) / (2.0 * FD_STEP)
    };
    let h_sr = FD_STEP * (1.0 + s.stress_rate.abs());
    let fd_sr = (law.theta_rate(&StateArgs { stress_rate: s.stress_rate + h_sr, ..s })
        - law.theta_rate(&StateArgs { stress_rate: s.stress_rate - h_sr, ..s }))
        / (2.0 * h_sr)
        * (1.0 + s.stress_rate.abs());
    let rows = [
        ("∂G/∂V·V", j.d_v * s.v, auto.d_v * s.v, fd_log(&|x| StateArgs { v: x, ..s }, s.v)),
        ("∂G/∂θ·θ", j.d_theta * s.theta, auto.d_theta * s.theta, fd_log(&|x| StateArgs { theta: x, ..s }, s.theta)),
        ("∂G/∂Dc·Dc", j.d_dc * s.dc, auto.d_dc * s.dc, fd_log(&|x| StateArgs { dc: x, ..s }, s.dc)),
        ("∂G/∂b·b", j.d_b * s.b, auto.d_b * s.b, fd_log(&|x| StateArgs { b: x, ..s }, s.b)),
        (
            "∂G/∂(dτ/dt)·(1 + |dτ/dt|)",
            j.d_stress_rate * (1.0 + s.stress_rate.abs()),
            auto.d_stress_rate * (1.0 + s.stress_rate.abs()),
            fd_sr,
        ),
    ];
    for (name, got, dual, fd) in rows {
        if !claims.derivatives_by_differences && (got - dual).abs() > DUAL_TOL * mag {
            return Err(format!("{name} = {got:e} from jet() but {dual:e} from dual numbers over theta_rate"));
        }
        if (got - fd).abs() > FD_TOL * mag {
            return Err(format!("{name} = {got:e} from jet() but {fd:e} from central differences"));
        }
    }
    Ok(())
}

fn steady_state<L: StateLaw>(law: &L, claims: &Claims, pt: &Point) -> Result<(), String> {
    let (v, dc) = (pt.v, pt.dc);
    if claims.no_steady_state {
        if let Ok(theta) = law.steady_state_theta(v, dc) {
            return Err(format!("the law claims no steady state but steady_state_theta gives {theta:e} s"));
        }
        let theta = pt.omega * dc / v;
        let g = law.theta_rate(&StateArgs::new(v, theta, dc, pt.b));
        if !(g < 0.0) {
            return Err(format!("dθ/dt = {g:e} ≥ 0 at θ = {theta:e} s: a law without a steady state must decay"));
        }
        return Ok(());
    }
    let theta = law.steady_state_theta(v, dc).map_err(|e| format!("steady_state_theta failed: {e}"))?;
    if !(theta > 0.0 && theta.is_finite()) {
        return Err(format!("steady_state_theta = {theta:e}"));
    }
    let s = StateArgs::new(v, theta, dc, pt.b);
    let j = reference_jet(law, claims, &s);
    let g = law.theta_rate(&s);
    let mag = magnitude(g, &s, &j);
    if g.abs() > ROOT_TOL * mag {
        return Err(format!("dθ/dt = {g:e} at θ_ss = {theta:e} s (Ω = {:e}): not a root", v * theta / dc));
    }
    if !(j.d_theta < 0.0) {
        return Err(format!(
            "∂(dθ/dt)/∂θ = {:e} ≥ 0 at θ_ss = {theta:e} s: the steady state does not attract",
            j.d_theta
        ));
    }
    if claims.steady_state_dc_over_v {
        let want = law.theta_scale() * dc / v;
        if (theta / want - 1.0).abs() > CLOSED_FORM_TOL {
            return Err(format!("θ_ss = {theta:e} s but the claimed s·Dc/V = {want:e} s"));
        }
    }
    Ok(())
}

/// Rates are compared at the same point after a change of units.
fn compare<L: StateLaw>(what: &str, law: &L, s: &StateArgs<f64>, other: &L, t: &StateArgs<f64>) -> Result<(), String> {
    let g = law.theta_rate(s);
    let h = other.theta_rate(t);
    let mag = magnitude(g, s, &Auto(law.clone()).jet(s));
    if (g - h).abs() <= SCALING_TOL * mag { Ok(()) } else { Err(format!("dθ/dt = {g:e} but {h:e} after {what}")) }
}

fn time_scaling<L: StateLaw>(law: &L, claims: &Claims, pt: &Point) -> Result<(), String> {
    let c = 10f64.powf(pt.decades);
    let s = pt.args();
    let t = StateArgs {
        v: s.v / c,
        theta: s.theta * c,
        stress_rate: s.stress_rate / c,
        normal_stress_rate: s.normal_stress_rate / c,
        ..s
    };
    let other = rescaled(law, &claims.velocity_parameters, 1.0 / c)?;
    compare(&format!("time in units of {c:e} s (V/c, cθ, rates/c, velocities/c)"), law, &s, &other, &t)
}

fn unit_scaling<L: StateLaw>(law: &L, claims: &Claims, pt: &Point) -> Result<(), String> {
    // up to six decades: µm ↔ m
    let f = 10f64.powf(2.0 * pt.decades);
    let s = pt.args();
    let t = StateArgs { v: s.v * f, dc: s.dc * f, ..s };
    let other = rescaled(law, &claims.velocity_parameters, f)?;
    let other = rescaled(&other, &claims.length_parameters, f)?;
    compare(
        &format!("lengths in units of {:e} µm (V, Dc, the law's lengths and velocities × {f:e})", 1.0 / f),
        law,
        &s,
        &other,
        &t,
    )
}

/// A point inside the ranges (their geometric middle), for asking what a law offers.
fn pts_any(claims: &Claims) -> StateArgs<f64> {
    let mid = |(lo, hi): (f64, f64)| if lo > 0.0 { (lo * hi).sqrt() } else { 0.5 * (lo + hi) };
    let r = &claims.ranges;
    let (v, omega, dc) = (mid(r.v), mid(r.omega), mid(r.dc));
    StateArgs {
        v,
        theta: omega * dc / v,
        dc,
        b: mid(r.b),
        stress_rate: 0.0,
        normal_stress: mid(r.normal_stress),
        normal_stress_rate: 0.0,
    }
}

/// Every parameter `parameters()` lists can be set by `set_parameter` and reads back, the
/// others unchanged (a fit sets them by name; a law that lists one it cannot set fails there).
fn parameter_round_trip<L: StateLaw>(law: &L) -> Result<Outcome, (String, String)> {
    let own = law.parameters();
    if own.is_empty() {
        return Ok(Outcome::Skipped("the law has no parameter of its own"));
    }
    for (i, &(name, value)) in own.iter().enumerate() {
        let new = if value != 0.0 { value * 1.25 } else { 0.5 };
        let mut l = law.clone();
        l.set_parameter(name, new).map_err(|e| {
            (format!("parameters() lists `{name}` but set_parameter(\"{name}\", {new}) fails: {e}"), format!("{own:?}"))
        })?;
        let back = l.parameters();
        let expect: Vec<(&str, f64)> =
            own.iter().enumerate().map(|(j, &(n, v))| (n, if j == i { new } else { v })).collect();
        if back != expect {
            return Err((
                format!("after set_parameter(\"{name}\", {new}) parameters() gives {back:?}, expected {expect:?}"),
                format!("{own:?}"),
            ));
        }
    }
    Ok(Outcome::Passed(own.len() as u32))
}

/// An exact parameter derivative equals a central difference of the rate in that parameter.
fn parameter_derivative<L: StateLaw>(law: &L, pt: &Point) -> Result<(), String> {
    let s = pt.args();
    for (name, q) in law.parameters() {
        let Some(exact) = law.parameter_derivative(name, &s) else { continue };
        let h = FD_STEP * q.abs().max(1e-3);
        let rate = |x: f64| {
            let mut l = law.clone();
            l.set_parameter(name, x).map(|()| l.theta_rate(&s))
        };
        let fd = (rate(q + h)? - rate(q - h)?) / (2.0 * h);
        let scale = exact.abs().max(fd.abs()).max(rate(q)?.abs()).max(1e-300);
        if !((exact - fd).abs() <= FD_TOL * scale) {
            return Err(format!("∂(dθ/dt)/∂{name}: exact {exact:e}, central difference {fd:e}"));
        }
    }
    Ok(())
}
