//! The BP1-QD parameters (SEAS Benchmark Problem BP1-QD, Erickson & Jiang, 2018), SI units.

/// The state-evolution law of the fault (the benchmark's is the aging law; the slip law is a
/// variant no fault code of the benchmark offers).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EvolutionLaw {
    /// dθ/dt = 1 − Vθ/Dc.
    #[default]
    Aging,
    /// dθ/dt = −(Vθ/Dc) ln(Vθ/Dc).
    Slip,
}

/// A second state variable (a variant: the benchmark has one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SecondState {
    /// Its evolution law.
    pub law: EvolutionLaw,
    /// Its b (the first state keeps `b0`; the steady-state b is the sum).
    pub b: f64,
    /// Its characteristic slip distance, m.
    pub dc: f64,
}

/// Parameters of the benchmark.
#[derive(Clone, Debug)]
pub struct Bp1 {
    /// State-evolution law.
    pub law: EvolutionLaw,
    /// An optional second state variable (`None` in the benchmark).
    pub second: Option<SecondState>,
    /// Density ρ, kg/m³.
    pub rho: f64,
    /// Shear-wave speed c_s, m/s.
    pub cs: f64,
    /// Effective normal stress σ_n, Pa.
    pub sigma: f64,
    /// a in the shallow velocity-weakening region.
    pub a0: f64,
    /// a in the deep velocity-strengthening region.
    pub a_max: f64,
    /// b (uniform).
    pub b0: f64,
    /// Critical slip distance D_c, m.
    pub dc: f64,
    /// Plate rate V_p, m/s.
    pub vp: f64,
    /// Initial slip rate, m/s.
    pub v_init: f64,
    /// Reference slip rate V_0, m/s.
    pub v0: f64,
    /// Reference friction f_0.
    pub f0: f64,
    /// Depth of the uniform velocity-weakening region H, m.
    pub h: f64,
    /// Width of the transition to velocity strengthening, m.
    pub h_trans: f64,
    /// Depth of the rate-and-state fault W_f, m.
    pub wf: f64,
}

impl Default for Bp1 {
    fn default() -> Self {
        Self {
            law: EvolutionLaw::Aging,
            second: None,
            rho: 2670.0,
            cs: 3464.0,
            sigma: 50e6,
            a0: 0.010,
            a_max: 0.025,
            b0: 0.015,
            dc: 0.008,
            vp: 1e-9,
            v_init: 1e-9,
            v0: 1e-6,
            f0: 0.6,
            h: 15e3,
            h_trans: 3e3,
            wf: 40e3,
        }
    }
}

impl Bp1 {
    /// Shear modulus μ = ρ c_s², Pa.
    pub fn mu(&self) -> f64 {
        self.rho * self.cs * self.cs
    }
    /// Radiation damping η = μ / (2 c_s) = ρ c_s / 2, Pa s/m.
    pub fn eta(&self) -> f64 {
        self.mu() / (2.0 * self.cs)
    }
    /// a(z): a0 above H, linear to a_max over the transition, a_max below.
    pub fn a(&self, z: f64) -> f64 {
        if z < self.h {
            self.a0
        } else if z < self.h + self.h_trans {
            self.a0 + (self.a_max - self.a0) * (z - self.h) / self.h_trans
        } else {
            self.a_max
        }
    }
    /// The steady-state b: b0, plus the second state's b if any.
    pub fn b_total(&self) -> f64 {
        self.b0 + self.second.map_or(0.0, |s| s.b)
    }
    /// The uniform pre-stress τ0: steady state at V_init with a = a_max, plus η V_init, Pa.
    pub fn tau0(&self) -> f64 {
        let (am, b) = (self.a_max, self.b_total());
        let l = (self.v_init / (2.0 * self.v0)).ln() + (self.f0 + b * (self.v0 / self.v_init).ln()) / am;
        self.sigma * am * l.exp().asinh() + self.eta() * self.v_init
    }
    /// The initial ln θ at depth z (the benchmark's depth-dependent, not steady, state), ln s.
    /// With a second state both share the same V0 θ/Dc, so that Ψ balances τ0 as in the
    /// benchmark; the second's ln θ is this plus ln(Dc2/Dc).
    pub fn ln_theta_init(&self, z: f64) -> f64 {
        let (a, b) = (self.a(z), self.b_total());
        let s = (self.tau0() - self.eta() * self.v_init) / (a * self.sigma);
        // ln sinh(s) without overflow: s + ln((1 − e^(−2s))/2)
        let ln_sinh = s + (0.5 * (-(-2.0 * s).exp_m1())).ln();
        (self.dc / self.v0).ln() + (a / b) * ((2.0 * self.v0 / self.v_init).ln() + ln_sinh) - self.f0 / b
    }
    /// Number of state variables (1 in the benchmark).
    pub fn states(&self) -> usize {
        1 + usize::from(self.second.is_some())
    }
    /// (law, b, Dc) of state `k`.
    pub fn state(&self, k: usize) -> (EvolutionLaw, f64, f64) {
        match (k, self.second) {
            (0, _) => (self.law, self.b0, self.dc),
            (_, Some(s)) => (s.law, s.b, s.dc),
            _ => panic!("state {k} of a one-state fault"),
        }
    }
    /// Quasi-static process zone Λ0 = μ D_c / (b σ_n), m (the cell size must resolve it).
    pub fn process_zone(&self) -> f64 {
        self.mu() * self.dc / (self.b0 * self.sigma)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The derived numbers of the specification: μ 32.04 GPa, η 4.624 MPa s/m, τ0 26.546 MPa,
    /// Λ0 342 m; and the initial state balances τ0 at V_init at every depth.
    #[test]
    fn derived_numbers_match_the_specification() {
        let p = Bp1::default();
        assert!((p.mu() / 1e9 - 32.04).abs() < 0.01);
        assert!((p.eta() / 1e6 - 4.624).abs() < 0.001);
        assert!((p.tau0() / 1e6 - 26.546).abs() < 0.001, "{}", p.tau0());
        assert!((p.process_zone() - 342.0).abs() < 1.0);
        for z in [0.0, 10e3, 16e3, 30e3] {
            let psi = rsf_core::element::psi_term(p.b0, p.v0, p.dc, 1.0, p.ln_theta_init(z));
            let f = rsf_core::element::friction(
                rsf_core::FrictionForm::Regularized,
                p.f0,
                p.a(z),
                p.v0,
                p.v_init.ln(),
                psi,
            );
            let tau = p.sigma * f.value + p.eta() * p.v_init;
            assert!((tau - p.tau0()).abs() < 1e-3, "z {z}: {tau} vs {}", p.tau0());
        }
    }
}
