//! Parameter names, parsed once at the edge ([`ParamName`]), and each one's scale and physical
//! range ([`ParamSpec`]).

/// A parameter name, parsed: the one place where names such as `b2`, `dc1`, `vc1` or
/// `mu0_seg3` are read ([`ParamName::parse`]) and written ([`ParamName::text`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ParamName {
    /// Steady-state friction at v0.
    Mu0,
    /// Direct effect a.
    A,
    /// Stiffness k.
    K,
    /// Slip trend g.
    G,
    /// Rate dependence a₁ of the direct effect (`a_slope`): ∂f/∂ln V = a + a₁ ln(V/V0).
    ASlope,
    /// b of state i (1-based).
    B(usize),
    /// Dc of state i (1-based).
    Dc(usize),
    /// Linker–Dieterich α of state i (1-based).
    Alpha(usize),
    /// A law's own parameter (e.g. `vc`) of state i (1-based).
    Law(String, usize),
    /// The friction offset of segment s (1-based, from 2).
    Mu0Seg(usize),
}

impl ParamName {
    /// Parses a name; `None` when it has no known form.
    pub fn parse(name: &str) -> Option<Self> {
        let name = name.trim();
        match name {
            "mu0" => return Some(Self::Mu0),
            "a" => return Some(Self::A),
            "k" => return Some(Self::K),
            "g" => return Some(Self::G),
            "a_slope" => return Some(Self::ASlope),
            _ => {}
        }
        if let Some(s) = name.strip_prefix("mu0_seg") {
            return s.parse().ok().filter(|&s| s >= 2).map(Self::Mu0Seg);
        }
        let split = name.find(|c: char| c.is_ascii_digit())?;
        let (stem, idx) = name.split_at(split);
        let i: usize = idx.parse().ok().filter(|&i| i >= 1)?;
        match stem {
            "b" => Some(Self::B(i)),
            "dc" => Some(Self::Dc(i)),
            "alpha" => Some(Self::Alpha(i)),
            s if !s.is_empty() && s.chars().all(|c| c.is_ascii_alphabetic()) => Some(Self::Law(s.to_string(), i)),
            _ => None,
        }
    }
    /// The name as written (`mu0`, `b2`, `vc1`, `mu0_seg3`): the inverse of [`Self::parse`].
    pub fn text(&self) -> String {
        match self {
            Self::Mu0 => "mu0".into(),
            Self::A => "a".into(),
            Self::K => "k".into(),
            Self::G => "g".into(),
            Self::ASlope => "a_slope".into(),
            Self::B(i) => format!("b{i}"),
            Self::Dc(i) => format!("dc{i}"),
            Self::Alpha(i) => format!("alpha{i}"),
            Self::Law(name, i) => format!("{name}{i}"),
            Self::Mu0Seg(s) => format!("mu0_seg{s}"),
        }
    }
    /// The state variable (1-based) this parameter belongs to, if any.
    pub fn state(&self) -> Option<usize> {
        match self {
            Self::B(i) | Self::Dc(i) | Self::Alpha(i) | Self::Law(_, i) => Some(*i),
            _ => None,
        }
    }
}

impl std::fmt::Display for ParamName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(&self.text())
    }
}

impl std::str::FromStr for ParamName {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::parse(s)
            .ok_or_else(|| format!("`{s}` is not a parameter name (mu0, a, k, g, b1, dc1, vc1, alpha1, mu0_seg2, …)"))
    }
}

/// How a full-vector entry is fitted: as a logarithm or not, and the physical range outside
/// which a trial point is rejected (so LM cannot wander where the model means nothing and
/// integrates slowly).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSpec {
    /// Fitted as a logarithm.
    pub log: bool,
    /// Lowest physical value.
    pub lo: f64,
    /// Highest physical value.
    pub hi: f64,
}

impl ParamName {
    /// Scale and range of this parameter; a law's own parameter from its spec in the law
    /// registry ([`rsf_laws::registry`]); a law used without registering it has no spec, and
    /// its parameters are fitted linearly in ±1e9.
    pub fn spec(&self, laws: &[std::sync::Arc<dyn rsf_core::DynStateLaw>]) -> ParamSpec {
        let (log, lo, hi) = match self {
            Self::Mu0 => (false, -10.0, 10.0),
            Self::A => (true, 1e-7, 1.0),
            Self::K => (true, 1e-9, 1e4),
            Self::G => (false, -1e-2, 1e-2),
            // a₁: the local direct effect a + a₁ ln(V/V0) changes by a₁ per e-fold of V; beyond
            // ±0.05 it would change sign within a decade for any lab a (0.001–0.03)
            Self::ASlope => (false, -5e-2, 5e-2),
            Self::B(_) => (false, -1.0, 1.0),
            // Dc: 0.01 µm to 10 m; below, a lab spring-slider is a stiff problem that no
            // record of 1–1000 Hz can resolve
            Self::Dc(_) => (true, 1e-2, 1e7),
            // Linker–Dieterich α: published values 0–0.6; beyond 5 the coupling would dominate
            // every other term
            Self::Alpha(_) => (false, 0.0, 5.0),
            Self::Law(name, i) => match laws.get(i - 1).and_then(|l| law_spec(l.as_ref(), name)) {
                Some(r) => (r.log, r.lo, r.hi),
                None => (false, -1e9, 1e9),
            },
            Self::Mu0Seg(_) => (false, f64::NEG_INFINITY, f64::INFINITY),
        };
        ParamSpec { log, lo, hi }
    }
}

/// The registry's spec of parameter `name` of `law`, when the law is registered.
pub(crate) fn law_spec(law: &dyn rsf_core::DynStateLaw, name: &str) -> Option<rsf_laws::LawParameter> {
    rsf_laws::registry::find(&law.name()).ok().and_then(|e| e.parameter(name).copied())
}
