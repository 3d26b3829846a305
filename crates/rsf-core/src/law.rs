//! The [`StateLaw`] plugin trait.

use num_dual::{DualNum, DualSVec64};
use std::fmt::Debug;

/// The scalar type a law is written in: `f64` for plain evaluation, or a forward-mode dual
/// number from `num-dual` for exact derivatives.
///
/// Why `num_dual::DualNum` rather than `num_traits::Float` or `nalgebra::RealField`:
/// `Float` is not implemented by dual numbers, so a law written against it could not be
/// differentiated automatically. `RealField` is implemented by duals but offers no arithmetic
/// with plain `f64`, so every constant would need `R::from_f64(2.0).unwrap()`. `DualNum`
/// admits both `f64` and the duals, and allows `x * 2.0`, `x / dc`, `1.0 - …` written as
/// `-(…) + 1.0`, so a law reads like its equation. Instantiated at `f64` it compiles to plain
/// floating-point code: the explicit integrators pay nothing for the generality.
pub trait Real: DualNum<Primitive = f64> + Copy {}
impl<T: DualNum<Primitive = f64> + Copy> Real for T {}

/// What a state-evolution law may depend on. All quantities in rsf units.
#[derive(Clone, Copy, Debug)]
pub struct StateArgs<R> {
    /// Slip rate V, µm/s (always > 0).
    pub v: R,
    /// This state variable θ, s (always > 0).
    pub theta: R,
    /// This state variable's characteristic slip distance Dc, µm.
    pub dc: R,
    /// This state variable's b (dimensionless); Nagata's law divides its stress-rate term by it.
    pub b: R,
    /// Shear-stress rate over normal stress, (dτ/dt)/σ = k (V_lp − V) σ_ref/σ, 1/s (friction
    /// units per s; k (V_lp − V) at constant normal stress).
    pub stress_rate: R,
    /// Normal stress σ, MPa (the model's `normal_stress`; 1 when the model leaves it unset, in
    /// which case it is constant). Linker–Dieterich coupling is added by the solver, not the
    /// law; a law reads σ only for its own σ-dependence.
    pub normal_stress: R,
    /// Normal-stress rate dσ/dt, MPa/s (0 at constant normal stress).
    pub normal_stress_rate: R,
}

impl<R: Real> StateArgs<R> {
    /// The same point in plain values (the dual numbers' real parts): for a law computed in
    /// `f64` whose derivatives come from its own [`jet`](StateLaw::jet) (a Python function, a law
    /// wrapped around another's dynamic rate).
    pub fn plain(&self) -> StateArgs<f64> {
        StateArgs {
            v: self.v.re(),
            theta: self.theta.re(),
            dc: self.dc.re(),
            b: self.b.re(),
            stress_rate: self.stress_rate.re(),
            normal_stress: self.normal_stress.re(),
            normal_stress_rate: self.normal_stress_rate.re(),
        }
    }
}

impl StateArgs<f64> {
    /// Arguments with zero stress rate at unit normal stress (steady or imposed-velocity
    /// sliding).
    pub fn new(v: f64, theta: f64, dc: f64, b: f64) -> Self {
        Self { v, theta, dc, b, stress_rate: 0.0, normal_stress: 1.0, normal_stress_rate: 0.0 }
    }
}

/// What a law's log-form rate [`StateLaw::ln_theta_rate`] may depend on: the integrators'
/// own variables x = ln V and z = ln θ, with V and ln Dc already at hand (the caller has
/// computed them once for all states and steps), and the rest of [`StateArgs`].
#[derive(Clone, Copy, Debug)]
pub struct LnArgs {
    /// x = ln V (V in µm/s).
    pub x: f64,
    /// V = e^x, µm/s.
    pub v: f64,
    /// V/Dc, 1/s (the rate at which θ relaxes at constant V).
    pub v_dc: f64,
    /// z = ln θ (θ in s).
    pub z: f64,
    /// Dc, µm.
    pub dc: f64,
    /// 1/Dc, 1/µm (so that a law can form V·(…/Dc) with V last: V comes from an exponential
    /// at the end of the right-hand side's latency chain).
    pub inv_dc: f64,
    /// ln Dc.
    pub ln_dc: f64,
    /// b (dimensionless).
    pub b: f64,
    /// As [`StateArgs::stress_rate`], 1/s.
    pub stress_rate: f64,
    /// As [`StateArgs::normal_stress`], MPa.
    pub normal_stress: f64,
    /// As [`StateArgs::normal_stress_rate`], MPa/s.
    pub normal_stress_rate: f64,
}

impl LnArgs {
    /// Arguments at x = ln V, z = ln θ with zero stress rate at unit normal stress.
    pub fn new(x: f64, z: f64, dc: f64, b: f64) -> Self {
        Self::with_ln_dc(x, z, dc, dc.ln(), b)
    }

    /// As [`LnArgs::new`] with `ln_dc = ln Dc` already at hand (a host looping over elements
    /// that share Dc computes it once).
    pub fn with_ln_dc(x: f64, z: f64, dc: f64, ln_dc: f64, b: f64) -> Self {
        let v = x.exp();
        Self {
            x,
            v,
            v_dc: v / dc,
            z,
            dc,
            inv_dc: 1.0 / dc,
            ln_dc,
            b,
            stress_rate: 0.0,
            normal_stress: 1.0,
            normal_stress_rate: 0.0,
        }
    }

    /// The same point in the plain variables (θ = e^z).
    pub fn state_args(&self) -> StateArgs<f64> {
        StateArgs {
            v: self.v,
            theta: self.z.exp(),
            dc: self.dc,
            b: self.b,
            stress_rate: self.stress_rate,
            normal_stress: self.normal_stress,
            normal_stress_rate: self.normal_stress_rate,
        }
    }
}

/// The value of dθ/dt and its exact partial derivatives at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet {
    /// dθ/dt (dimensionless: s per s).
    pub rate: f64,
    /// ∂(dθ/dt)/∂V, s/µm.
    pub d_v: f64,
    /// ∂(dθ/dt)/∂θ, 1/s.
    pub d_theta: f64,
    /// ∂(dθ/dt)/∂(dτ/dt), s (per friction unit).
    pub d_stress_rate: f64,
    /// ∂(dθ/dt)/∂Dc, 1/µm (for parameter sensitivities).
    pub d_dc: f64,
    /// ∂(dθ/dt)/∂b (Nagata's law only; 0 for the others).
    pub d_b: f64,
}

/// A state-variable evolution law `dθ/dt = G(V, θ, Dc, b, dτ/dt)`.
///
/// One method is required: [`theta_rate`](StateLaw::theta_rate), written once, generic over
/// the scalar `R`. Everything else has a default: exact partial derivatives for implicit
/// solvers come from evaluating the same method with dual numbers, and the steady state is
/// found by Newton iteration on `G = 0`. Override a default only for speed or where the law's
/// own definition differs (Perrin–Rice–Zheng's θ scale of 2, Kato–Tullis's own steady state).
///
/// A law is a plain value with its own parameters (e.g. a cut-off velocity); it keeps no
/// solution state, so solving twice with the same law gives the same answer.
///
/// ```
/// use rsf_core::{StateLaw, StateArgs, Real};
///
/// /// Ruina's Slip law, dθ/dt = −(Vθ/Dc) ln(Vθ/Dc).
/// #[derive(Debug, Clone)]
/// struct MySlip;
/// impl StateLaw for MySlip {
///     fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
///         let omega = s.v * s.theta / s.dc;
///         -(omega * omega.ln())
///     }
/// }
/// // Default steady state: θ = Dc/V.
/// assert!((MySlip.steady_state_theta(2.0, 10.0).unwrap() - 5.0).abs() < 1e-12);
/// // Exact derivative by dual numbers: ∂G/∂θ at Ω = 1 is −V/Dc.
/// let jet = MySlip.jet(&StateArgs::new(2.0, 5.0, 10.0, 0.01));
/// assert!((jet.d_theta + 0.2).abs() < 1e-15);
/// ```
pub trait StateLaw: Debug + Clone + Send + Sync + 'static {
    /// dθ/dt in s/s. `s.v > 0` and `s.theta > 0` are guaranteed by the solvers.
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R;

    /// A short name for messages and output (e.g. `"slip"`).
    fn name(&self) -> String {
        let full = std::any::type_name::<Self>();
        full.rsplit("::").next().unwrap_or(full).to_lowercase()
    }

    /// The law's own parameters (name, value), e.g. `[("vc", 1e-3)]`.
    fn parameters(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }

    /// Sets one of the law's own parameters by name (used by fitting); the default law has
    /// none.
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), String> {
        let _ = value;
        Err(format!("law `{}` has no parameter `{name}`", self.name()))
    }

    /// Check the law's own parameters; return a message naming the bad one.
    fn validate(&self) -> Result<(), String> {
        Ok(())
    }

    /// ∂(dθ/dt)/∂q for the law's own parameter `q = name`, exact, when the law can give it
    /// (a text-file law: dual numbers over its expression). `None` (the default): fits take
    /// a central difference of [`set_parameter`](StateLaw::set_parameter)'s rate instead.
    fn parameter_derivative(&self, name: &str, s: &StateArgs<f64>) -> Option<f64> {
        let _ = (name, s);
        None
    }

    /// The factor `s` in the friction term `b ln(V0 θ / (s Dc))`. 1 unless the law defines
    /// θ differently (Perrin–Rice–Zheng: 2, so that its steady state θ = 2Dc/V gives the
    /// standard steady-state friction).
    fn theta_scale(&self) -> f64 {
        1.0
    }

    /// d(ln θ)/dt = G/θ in the log variables of rsf's integrators and per-element kernels.
    /// The default evaluates [`theta_rate`](StateLaw::theta_rate) at θ = e^z; a law
    /// overrides it where the log form saves transcendental calls, which dominate the cost of
    /// a right-hand side (the Slip law: none instead of an exponential and a logarithm). An
    /// override must equal the default to rounding; rsf-laws tests each one.
    fn ln_theta_rate(&self, s: &LnArgs) -> f64 {
        let p = s.state_args();
        self.theta_rate(&p) / p.theta
    }

    /// Exact value and partial derivatives of dθ/dt (forward-mode dual numbers over
    /// [`theta_rate`](StateLaw::theta_rate)).
    fn jet(&self, s: &StateArgs<f64>) -> Jet {
        type D5 = DualSVec64<5>;
        let args = StateArgs {
            v: D5::from_re(s.v).derivative(0),
            theta: D5::from_re(s.theta).derivative(1),
            dc: D5::from_re(s.dc).derivative(3),
            b: D5::from_re(s.b).derivative(4),
            stress_rate: D5::from_re(s.stress_rate).derivative(2),
            normal_stress: D5::from_re(s.normal_stress),
            normal_stress_rate: D5::from_re(s.normal_stress_rate),
        };
        let g = self.theta_rate(&args);
        let d = g.eps.unwrap_generic(nalgebra::Const::<5>, nalgebra::U1);
        Jet { rate: g.re, d_v: d[0], d_theta: d[1], d_stress_rate: d[2], d_dc: d[3], d_b: d[4] }
    }

    /// Steady-state θ at slip rate `v` (µm/s) for this `dc` (µm): the root of
    /// `G(V, θ) = 0` at zero stress rate. Default: safeguarded Newton in ln θ from `Dc/V`.
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        steady_state_by_newton(|theta| self.jet(&StateArgs::new(v, theta, dc, 1.0)), v, dc)
    }
}

/// Newton iteration in z = ln θ on G(θ) = 0, bracketing the root so that it cannot wander.
fn steady_state_by_newton(jet: impl Fn(f64) -> Jet, v: f64, dc: f64) -> Result<f64, String> {
    let fail = |why: &str| Err(format!("no steady state found at V = {v:e} µm/s, Dc = {dc} µm: {why}"));
    if !(v > 0.0 && v.is_finite() && dc > 0.0 && dc.is_finite()) {
        return fail("V and Dc must be positive and finite");
    }
    let mut z = (dc / v).ln();
    // Bracket: expand until G changes sign (G > 0 below the root for healing laws).
    let g0 = jet(z.exp()).rate;
    if g0 == 0.0 {
        return Ok(z.exp());
    }
    let (mut lo, mut hi) = (z, z);
    let mut step = 0.5;
    let mut found = false;
    for _ in 0..200 {
        lo -= step;
        hi += step;
        step *= 1.6;
        if jet(lo.exp()).rate.signum() != g0.signum() {
            hi = z;
            found = true;
            // keep lo
            break;
        }
        if jet(hi.exp()).rate.signum() != g0.signum() {
            lo = z;
            found = true;
            break;
        }
    }
    if !found {
        return fail("dθ/dt does not change sign");
    }
    let g_lo = jet(lo.exp()).rate;
    z = 0.5 * (lo + hi);
    for _ in 0..200 {
        let theta = z.exp();
        let j = jet(theta);
        if j.rate == 0.0 {
            return Ok(theta);
        }
        if j.rate.signum() == g_lo.signum() {
            lo = z;
        } else {
            hi = z;
        }
        let dz = -j.rate / (j.d_theta * theta);
        let mut zn = z + dz;
        if !(zn > lo.min(hi) && zn < lo.max(hi) && zn.is_finite()) {
            zn = 0.5 * (lo + hi);
        }
        if (zn - z).abs() <= 1e-15 * (1.0 + z.abs()) || (hi - lo).abs() < 1e-15 {
            return Ok(zn.exp());
        }
        z = zn;
    }
    Ok(z.exp())
}

/// Object-safe face of [`StateLaw`], implemented for every law automatically. Solvers hold
/// laws as `Arc<dyn DynStateLaw>` so that each state variable may use a different law; law
/// authors never implement or name this trait.
pub trait DynStateLaw: Debug + Send + Sync {
    /// dθ/dt at f64 (see [`StateLaw::theta_rate`]).
    fn rate(&self, s: &StateArgs<f64>) -> f64;
    /// See [`StateLaw::ln_theta_rate`].
    fn ln_rate(&self, s: &LnArgs) -> f64;
    /// See [`StateLaw::jet`].
    fn jet(&self, s: &StateArgs<f64>) -> Jet;
    /// See [`StateLaw::steady_state_theta`].
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String>;
    /// See [`StateLaw::theta_scale`].
    fn theta_scale(&self) -> f64;
    /// See [`StateLaw::name`].
    fn name(&self) -> String;
    /// See [`StateLaw::parameters`].
    fn parameters(&self) -> Vec<(&'static str, f64)>;
    /// See [`StateLaw::validate`].
    fn validate(&self) -> Result<(), String>;
    /// A copy of this law with parameter `name` set to `value` (see
    /// [`StateLaw::set_parameter`]).
    fn with_parameter(&self, name: &str, value: f64) -> Result<std::sync::Arc<dyn DynStateLaw>, String>;
    /// dθ/dt of this law with parameter `name` set to `value`: what
    /// [`with_parameter`](Self::with_parameter) then [`rate`](Self::rate) give, on a copy kept
    /// on the stack (the parameter derivatives of a sensitivity solve take it at every step).
    fn rate_with_parameter(&self, name: &str, value: f64, s: &StateArgs<f64>) -> Result<f64, String>;
    /// See [`StateLaw::parameter_derivative`].
    fn parameter_derivative(&self, name: &str, s: &StateArgs<f64>) -> Option<f64>;
    /// The law as `Any`, so a solver can recognise a concrete law and call it directly
    /// (see [`SameLaw`](crate::SameLaw)).
    fn as_any(&self) -> &dyn std::any::Any;
}

impl<L: StateLaw> DynStateLaw for L {
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
    #[inline]
    fn rate(&self, s: &StateArgs<f64>) -> f64 {
        self.theta_rate(s)
    }
    #[inline]
    fn ln_rate(&self, s: &LnArgs) -> f64 {
        self.ln_theta_rate(s)
    }
    fn jet(&self, s: &StateArgs<f64>) -> Jet {
        StateLaw::jet(self, s)
    }
    fn steady_state_theta(&self, v: f64, dc: f64) -> Result<f64, String> {
        StateLaw::steady_state_theta(self, v, dc)
    }
    fn theta_scale(&self) -> f64 {
        StateLaw::theta_scale(self)
    }
    fn name(&self) -> String {
        StateLaw::name(self)
    }
    fn parameters(&self) -> Vec<(&'static str, f64)> {
        StateLaw::parameters(self)
    }
    fn validate(&self) -> Result<(), String> {
        StateLaw::validate(self)
    }
    fn with_parameter(&self, name: &str, value: f64) -> Result<std::sync::Arc<dyn DynStateLaw>, String> {
        let mut l = self.clone();
        l.set_parameter(name, value)?;
        Ok(std::sync::Arc::new(l))
    }
    fn rate_with_parameter(&self, name: &str, value: f64, s: &StateArgs<f64>) -> Result<f64, String> {
        let mut l = self.clone();
        l.set_parameter(name, value)?;
        Ok(l.theta_rate(s))
    }
    fn parameter_derivative(&self, name: &str, s: &StateArgs<f64>) -> Option<f64> {
        StateLaw::parameter_derivative(self, name, s)
    }
}
