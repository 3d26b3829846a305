//! Friction parameters, state variables and the machine.

use crate::friction::FrictionForm;
use crate::law::{DynStateLaw, StateLaw};
use std::sync::Arc;
use thiserror::Error;

/// One state variable: its evolution law, its `b` and its `Dc` (µm).
#[derive(Clone, Debug)]
pub struct StateVariable {
    /// The evolution law (any [`StateLaw`], possibly from the user's own crate).
    pub law: Arc<dyn DynStateLaw>,
    /// Magnitude of the evolution effect (dimensionless).
    pub b: f64,
    /// Characteristic slip distance, µm.
    pub dc: f64,
    /// Linker–Dieterich normal-stress coupling α ≥ 0 (dimensionless; 0 by default): the solver
    /// adds −(α θ/(b σ)) dσ/dt to dθ/dt, so a step σ⁻ → σ⁺ maps θ to θ (σ⁻/σ⁺)^(α/b).
    pub alpha: f64,
}

impl StateVariable {
    /// A state variable evolving by `law`.
    pub fn new<L: StateLaw>(law: L, b: f64, dc: f64) -> Self {
        Self { law: Arc::new(law), b, dc, alpha: 0.0 }
    }
    /// A state variable from an already shared law.
    pub fn from_shared(law: Arc<dyn DynStateLaw>, b: f64, dc: f64) -> Self {
        Self { law, b, dc, alpha: 0.0 }
    }
    /// Sets the Linker–Dieterich coupling α.
    pub fn with_alpha(mut self, alpha: f64) -> Self {
        self.alpha = alpha;
        self
    }
}

/// An invalid model parameter, named.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ModelError {
    /// A parameter has a value that makes the model meaningless.
    #[error("invalid parameter `{name}` = {value}: {why}")]
    Parameter {
        /// Parameter name as in the protocol file, e.g. `state[2].dc`.
        name: String,
        /// The value given.
        value: f64,
        /// What is required.
        why: &'static str,
    },
    /// A state law rejected its own parameters or has no steady state.
    #[error("state {index} ({law}): {why}")]
    Law {
        /// 1-based state index.
        index: usize,
        /// The law's name.
        law: String,
        /// The law's message.
        why: String,
    },
    /// No state variable was given.
    #[error("the model needs at least one state variable")]
    NoState,
}

/// A rate-and-state friction model coupled to a spring (the testing machine).
///
/// Units: `v0` µm/s, `stiffness` 1/µm (friction per µm of load-point displacement; use
/// `f64::INFINITY` to impose the slip rate V = V_lp exactly), `eta` friction per µm/s.
#[derive(Clone, Debug)]
pub struct Model {
    /// Steady-state friction at `v0`.
    pub mu0: f64,
    /// Reference slip rate V0, µm/s.
    pub v0: f64,
    /// Direct-effect coefficient a (dimensionless): ∂f/∂ln V at V0.
    pub a: f64,
    /// Rate dependence of the direct effect a₁ (dimensionless, 0 by default): the direct
    /// effect's local slope ∂f/∂ln V is `a + a₁ ln(V/V0)`, so friction gains
    /// `(a₁/2) ln²(V/V0)` and steady state bends in ln V. Classic form without radiation
    /// damping only ([`validate`](Self::validate)); the slip rate of a friction is then the
    /// root of a quadratic in ln V on the branch where the local slope is positive.
    pub a_slope: f64,
    /// Machine stiffness k divided by normal stress, 1/µm. `INFINITY` imposes V = V_lp.
    pub stiffness: f64,
    /// Radiation damping η, friction per µm/s (0: quasi-static).
    pub eta: f64,
    /// Classic or regularized friction.
    pub form: FrictionForm,
    /// Slip trend g, friction per µm of slip: a term g·δ added to friction (gouge growth, wear,
    /// slip hardening); 0 by default.
    pub slip_trend: f64,
    /// The state variables (N ≥ 1); laws may differ between them.
    pub states: Vec<StateVariable>,
    /// Reference normal stress σ_ref, MPa: the initial normal stress, and the σ at which
    /// `stiffness` = K/σ_ref is stated (K the machine stiffness, MPa/µm). `None`: σ is constant
    /// and its value does not matter (laws see σ = 1).
    pub normal_stress: Option<f64>,
}

impl Model {
    /// A model with no state variables yet (add them with [`with_state`](Self::with_state)).
    pub fn new(mu0: f64, v0: f64, a: f64, stiffness: f64) -> Self {
        Self {
            mu0,
            v0,
            a,
            a_slope: 0.0,
            stiffness,
            eta: 0.0,
            form: FrictionForm::Classic,
            slip_trend: 0.0,
            states: Vec::new(),
            normal_stress: None,
        }
    }
    /// Sets the reference (and initial) normal stress σ_ref, MPa.
    pub fn with_normal_stress(mut self, sigma: f64) -> Self {
        self.normal_stress = Some(sigma);
        self
    }
    /// σ_ref in MPa, or 1 when the model leaves it unset.
    pub fn sigma_ref(&self) -> f64 {
        self.normal_stress.unwrap_or(1.0)
    }
    /// Adds a state variable.
    pub fn with_state(mut self, s: StateVariable) -> Self {
        self.states.push(s);
        self
    }
    /// Sets the radiation damping η (friction per µm/s).
    pub fn with_eta(mut self, eta: f64) -> Self {
        self.eta = eta;
        self
    }
    /// Sets the slip trend g (friction per µm of slip).
    pub fn with_slip_trend(mut self, g: f64) -> Self {
        self.slip_trend = g;
        self
    }
    /// Sets the rate dependence of the direct effect a₁ (see [`a_slope`](Self::a_slope)).
    pub fn with_a_slope(mut self, a_slope: f64) -> Self {
        self.a_slope = a_slope;
        self
    }
    /// Sets the friction form.
    pub fn with_form(mut self, form: FrictionForm) -> Self {
        self.form = form;
        self
    }

    /// Number of state variables N.
    pub fn n_states(&self) -> usize {
        self.states.len()
    }

    /// Whether the slip rate is imposed (infinite stiffness).
    pub fn imposed_velocity(&self) -> bool {
        self.stiffness == f64::INFINITY
    }

    /// Checks every parameter; the error names the first bad one.
    pub fn validate(&self) -> Result<(), ModelError> {
        let p = |name: &str, value: f64, why| Err(ModelError::Parameter { name: name.into(), value, why });
        if !self.mu0.is_finite() {
            return p("mu0", self.mu0, "must be finite");
        }
        if !(self.v0 > 0.0 && self.v0.is_finite()) {
            return p("v0", self.v0, "must be positive and finite");
        }
        if !(self.a > 0.0 && self.a.is_finite()) {
            return p("a", self.a, "must be positive and finite");
        }
        if !self.a_slope.is_finite() {
            return p("a_slope", self.a_slope, "must be finite");
        }
        if self.a_slope != 0.0 && (self.form != FrictionForm::Classic || self.eta != 0.0) {
            return p("a_slope", self.a_slope, "needs the classic friction form without radiation damping");
        }
        if !(self.stiffness > 0.0) {
            return p("stiffness", self.stiffness, "must be positive (inf imposes V = V_lp)");
        }
        if !(self.eta >= 0.0 && self.eta.is_finite()) {
            return p("eta", self.eta, "must be zero or positive and finite");
        }
        if !self.slip_trend.is_finite() {
            return p("slip_trend", self.slip_trend, "must be finite (friction per µm)");
        }
        if let Some(sn) = self.normal_stress {
            if !(sn > 0.0 && sn.is_finite()) {
                return p("normal_stress", sn, "must be positive and finite (MPa)");
            }
        }
        if self.states.is_empty() {
            return Err(ModelError::NoState);
        }
        for (i, s) in self.states.iter().enumerate() {
            if !s.b.is_finite() {
                return p(&format!("state[{}].b", i + 1), s.b, "must be finite");
            }
            if !(s.dc > 0.0 && s.dc.is_finite()) {
                return p(&format!("state[{}].dc", i + 1), s.dc, "must be positive and finite (µm)");
            }
            if !(s.alpha >= 0.0 && s.alpha.is_finite()) {
                return p(&format!("state[{}].alpha", i + 1), s.alpha, "must be zero or positive and finite");
            }
            if s.alpha != 0.0 && s.b == 0.0 {
                return p(&format!("state[{}].alpha", i + 1), s.alpha, "needs a non-zero b (the coupling is α/b)");
            }
            s.law.validate().map_err(|why| ModelError::Law { index: i + 1, law: s.law.name(), why })?;
        }
        Ok(())
    }

    /// State contribution Ψ = Σ b_i ln(V0 θ_i / (s_i Dc_i)) from ln θ_i.
    pub fn psi_from_ln_theta(&self, ln_theta: &[f64]) -> f64 {
        let lv0 = self.v0.ln();
        self.states.iter().zip(ln_theta).map(|(s, z)| s.b * (lv0 + z - (s.law.theta_scale() * s.dc).ln())).sum()
    }

    /// Friction (without radiation damping) at slip rate `v` (µm/s) and states `theta` (s).
    pub fn friction(&self, v: f64, theta: &[f64]) -> f64 {
        let z: Vec<f64> = theta.iter().map(|t| t.ln()).collect();
        let x = (v / self.v0).ln();
        self.form.friction(self.mu0, self.a, self.v0, v.ln(), self.psi_from_ln_theta(&z)) + 0.5 * self.a_slope * x * x
    }

    /// The slip rate V (µm/s) at which friction (without damping) equals `mu` for the state
    /// contribution `psi`: the form's inverse, or with a rate-dependent direct effect the root
    /// of `(a₁/2) X² + a X = r`, `X = ln(V/V0)`, `r = mu − μ0 − Ψ`, on the branch where the local
    /// slope a + a₁X = sqrt(a² + 2a₁r) is positive (written without cancellation); `None` where
    /// no positive V exists.
    pub fn slip_rate(&self, mu: f64, psi: f64) -> Option<f64> {
        if self.a_slope == 0.0 {
            return self.form.slip_rate(self.mu0, self.a, self.v0, mu, psi);
        }
        let r = mu - self.mu0 - psi;
        let disc = self.a * self.a + 2.0 * self.a_slope * r;
        if !(disc >= 0.0) {
            return None;
        }
        let x = 2.0 * r / (self.a + disc.sqrt());
        Some(self.v0 * x.exp())
    }

    /// The local slope of the direct effect, ∂f/∂ln V = a + a₁ ln(V/V0), at `x = ln V`
    /// (classic form).
    #[inline]
    pub fn direct_slope(&self, x: f64) -> f64 {
        self.a + self.a_slope * (x - self.v0.ln())
    }

    /// Steady-state θ_i (s) of every state variable at slip rate `v` (µm/s).
    pub fn steady_state_thetas(&self, v: f64) -> Result<Vec<f64>, ModelError> {
        self.states
            .iter()
            .enumerate()
            .map(|(i, s)| {
                s.law.steady_state_theta(v, s.dc).map_err(|why| ModelError::Law {
                    index: i + 1,
                    law: s.law.name(),
                    why,
                })
            })
            .collect()
    }

    /// Steady-state friction at slip rate `v` (µm/s); for laws whose steady state is θ = s Dc/V
    /// this is `mu0 + (a − Σ b_i) ln(V/V0) + (a₁/2) ln²(V/V0)`.
    pub fn steady_state_friction(&self, v: f64) -> Result<f64, ModelError> {
        let th = self.steady_state_thetas(v)?;
        Ok(self.friction(v, &th))
    }

    /// Critical stiffness `k_c = Σ_i b_i/Dc_i − a/…`, here the classic single-state result
    /// `(b − a)/Dc` generalised to `max(0, (Σ b_i − a)/min Dc)`, an upper bound used only for
    /// messages; 0 for velocity strengthening. (With a rate-dependent direct effect, `a` is its
    /// value at V0.)
    pub fn critical_stiffness_estimate(&self) -> f64 {
        let b: f64 = self.states.iter().map(|s| s.b).sum();
        let dc = self.states.iter().map(|s| s.dc).fold(f64::INFINITY, f64::min);
        ((b - self.a) / dc).max(0.0)
    }
}
