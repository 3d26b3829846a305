//! The closed vocabulary of causes, and what each does to a model: the extension it applies,
//! its words, and the effect parameters it reports.

use rsf_fit::fit::{AlphaFit, FitOptions, FitResult, ParamName};
use rsf_laws::Law;
use serde::Serialize;
use std::sync::Arc;

/// What a fitted model gets wrong (serialised as its snake_case name, [`Cause::name`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Cause {
    /// Nothing: no extension earns its parameters.
    None,
    /// The evolution law: the other classic law, a share of time-dependent (Aging) healing, or a
    /// law of the library (PRZ, Nagata, the one-state Aging–Slip mixture) with its own parameters.
    EvolutionLaw,
    /// A second state variable.
    SecondStateVariable,
    /// The Kato–Tullis cut-off velocity Vc.
    CutoffVelocity,
    /// A slip trend g·δ in friction.
    SlipTrend,
    /// The machine stiffness differs from the nominal one.
    Stiffness,
    /// Linker–Dieterich coupling of state to normal-stress changes (α > 0); a candidate only
    /// when the record's normal stress varies.
    NormalStressCoupling,
    /// Not explained: the best model on the menu (the baseline, or the best extension) still
    /// misfits the record beyond its noise where the protocol's events are (the adequacy test,
    /// `diagnose/adequacy.rs`). Never a candidate: a verdict about the menu.
    Unexplained,
    /// Undecided: two extensions each explain the record, credibly and decisively better than
    /// the baseline, and score within [`crate::UNDECIDED_DBIC`] of each other, so the record
    /// does not tell which one it needs (`Diagnosis::undecided` holds both; `rsf design` plans
    /// the experiment that tells them apart). Never a candidate: a verdict about the record.
    Undecided,
}

impl Cause {
    /// Whether the cause is an extension a diagnosis tries (the others are verdicts about the
    /// menu). Matched exhaustively: a new cause does not compile until it says which it is.
    pub fn is_candidate(self) -> bool {
        match self {
            Self::EvolutionLaw
            | Self::SecondStateVariable
            | Self::CutoffVelocity
            | Self::SlipTrend
            | Self::Stiffness
            | Self::NormalStressCoupling => true,
            Self::None | Self::Unexplained | Self::Undecided => false,
        }
    }

    /// The candidate extensions, in the order they are tried (the vocabulary's order).
    pub fn candidates() -> impl Iterator<Item = Cause> {
        Self::ALL.iter().copied().filter(|c| c.is_candidate())
    }

    /// The cause named `s` (its [`name`](Self::name), as in JSON).
    pub fn parse(s: &str) -> Option<Cause> {
        s.parse().ok()
    }

    /// The snake_case name (as in JSON): [`Cause::name`].
    pub fn as_str(self) -> &'static str {
        self.name()
    }

    /// The extension in words, for a baseline of `base_law`.
    pub fn describe(self, base_law: &str) -> String {
        match self {
            Self::None => "the baseline".into(),
            Self::EvolutionLaw => format!("{} law instead of {base_law}", other_law(base_law)),
            Self::SecondStateVariable => format!("second state variable ({base_law})"),
            Self::CutoffVelocity => "Kato–Tullis law with cut-off velocity Vc".into(),
            Self::SlipTrend => "slip trend g·slip".into(),
            Self::Stiffness => "stiffness fitted".into(),
            Self::NormalStressCoupling => "Linker–Dieterich normal-stress coupling α".into(),
            Self::Unexplained => "no model on the menu".into(),
            Self::Undecided => "one of two extensions the record cannot tell apart".into(),
        }
    }

    /// Applies this extension to fit options (composable: a combination applies two). `None`
    /// when it does not apply (e.g. the cut-off on top of a law change).
    pub fn extend(self, o: &FitOptions, base_law: &str) -> Option<FitOptions> {
        let mut o = o.clone();
        match self {
            Self::None => {}
            Self::Unexplained | Self::Undecided => return None,
            Self::EvolutionLaw => {
                if o.laws.iter().any(|l| l.name() != base_law) {
                    return None;
                }
                o.laws = o.laws.iter().map(|_| builtin(other_law(base_law))).collect();
            }
            Self::SecondStateVariable => {
                if o.laws.len() != 1 {
                    return None;
                }
                let l = o.laws[0].clone();
                o.laws.push(l);
            }
            Self::CutoffVelocity => {
                // a Kato–Tullis baseline has its cut-off already
                if o.laws[0].name() != base_law || o.laws.len() != 1 || base_law == Law::KatoTullis.name() {
                    return None;
                }
                o.laws[0] = builtin(Law::KatoTullis);
            }
            Self::SlipTrend => {
                if o.fit_slip_trend {
                    return None;
                }
                o.fit_slip_trend = true;
            }
            Self::Stiffness => {
                if o.fit_stiffness {
                    return None;
                }
                o.fit_stiffness = true;
            }
            Self::NormalStressCoupling => {
                if o.alpha != AlphaFit::Fixed {
                    return None;
                }
                o.alpha = AlphaFit::Shared;
            }
        }
        Some(o)
    }

    /// This cause's effect parameters in a fit (added to `effect`).
    fn add_effect(self, f: &FitResult, effect: &mut Effect) {
        let pr = &f.params;
        match self {
            Self::None | Self::Unexplained | Self::Undecided => {}
            Self::EvolutionLaw => {
                effect.law = Some(pr.laws.join("+"));
                if pr.b.len() == 2 {
                    // share of the evolution effect carried by the other law
                    effect.b_other_fraction = Some(pr.b[1] / (pr.b[0] + pr.b[1]));
                }
                // a library law's own parameter (Nagata's c, the one-state mixture's aging share);
                // a registered law's own parameters (power-law aging's n) by their names
                let entry = match pr.laws.as_slice() {
                    [law] => rsf_laws::registry::find(law).ok(),
                    _ => None,
                };
                match entry.as_ref().map(|e| (e.builtin(), e)) {
                    Some((None, e)) => {
                        for p in e.parameters() {
                            if let Some(x) = pr.law_params.get(&format!("{}1", p.name)) {
                                effect.law_parameters.insert(p.name.to_string(), *x);
                            }
                        }
                    }
                    Some((Some(_), _)) | None => {
                        effect.c = pr.law_params.get("c1").copied();
                        effect.w = pr.law_params.get("w1").copied();
                    }
                }
            }
            Self::SecondStateVariable => {
                // the states are exchangeable in the fit: report the slower one as the second
                let i = (0..pr.dc.len()).max_by(|&x, &y| pr.dc[x].total_cmp(&pr.dc[y])).unwrap_or(0);
                effect.b2 = pr.b.get(i).copied();
                effect.dc2 = pr.dc.get(i).copied();
                effect.second_state = Some(i + 1);
            }
            Self::CutoffVelocity => effect.vc = pr.law_params.get("vc1").copied(),
            Self::SlipTrend => effect.g = Some(pr.g),
            Self::Stiffness => effect.k = Some(pr.k),
            Self::NormalStressCoupling => effect.alpha = pr.alpha.first().copied(),
        }
    }
}

/// How large a cause is: the extension's fitted parameters that measure it (serialised in key
/// order, each only when the cause sets it).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Effect {
    /// Linker–Dieterich α (normal-stress coupling).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    /// b of the added, slower state variable.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub b2: Option<f64>,
    /// Share of b carried by the other law in a mixture of laws.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub b_other_fraction: Option<f64>,
    /// Nagata's stress-weakening coefficient c (dimensionless), when the law named is Nagata's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub c: Option<f64>,
    /// Dc of the added, slower state variable, µm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dc2: Option<f64>,
    /// Slip trend g, friction per µm of slip.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub g: Option<f64>,
    /// Machine stiffness k, 1/µm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k: Option<f64>,
    /// The law(s) of the extended model (`aging`, `slip+aging`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub law: Option<String>,
    /// Cut-off velocity Vc, µm/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vc: Option<f64>,
    /// Aging share w of a one-state Aging–Slip mixture (`aging-slip`), dimensionless.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub w: Option<f64>,
    /// Which fitted state (1-based) `b2` and `dc2` are: the states are exchangeable in the
    /// fit, and the slower one is reported as the second.
    #[serde(skip)]
    pub second_state: Option<usize>,
    /// The own parameters of a registered (not built-in) law named as the evolution law, by
    /// name (power-law aging's `n`; serialised after the fields above).
    #[serde(flatten)]
    pub law_parameters: std::collections::BTreeMap<String, f64>,
}

/// Which parameter of an [`Effect`] an entry is: one per field, so that a reader (the report's
/// words, a study) matches on it and a new field fails to compile until every reader handles
/// it. Serialised by [`EffectKey::text`] (the JSON key).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EffectKey {
    /// Linker–Dieterich α.
    Alpha,
    /// b of the added state.
    B2,
    /// Share of b carried by the other law of a mixture.
    BOtherFraction,
    /// Nagata's c.
    C,
    /// Dc of the added state.
    Dc2,
    /// Slip trend g.
    G,
    /// Stiffness k.
    K,
    /// The law(s) of the extended model.
    Law,
    /// Cut-off velocity Vc.
    Vc,
    /// Aging share w of one state.
    W,
    /// An own parameter of a registered law, by its name.
    LawParameter(&'static str),
}

impl EffectKey {
    /// The key as serialised in the JSON (and a batch summary's `effect` cell).
    pub fn text(&self) -> &'static str {
        match self {
            Self::Alpha => "alpha",
            Self::B2 => "b2",
            Self::BOtherFraction => "b_other_fraction",
            Self::C => "c",
            Self::Dc2 => "dc2",
            Self::G => "g",
            Self::K => "k",
            Self::Law => "law",
            Self::Vc => "vc",
            Self::W => "w",
            Self::LawParameter(name) => name,
        }
    }
}

/// One set parameter of an [`Effect`]: its key, its value, and the fitted parameter it reports
/// (whose standard error is its own; none for a derived share or the law).
#[derive(Clone, Debug, PartialEq)]
pub struct EffectEntry {
    /// Which parameter.
    pub key: EffectKey,
    /// The value.
    pub value: EffectValue,
    /// The fitted parameter it is.
    pub parameter: Option<ParamName>,
}

/// One value of an [`Effect`]: a number, or the law as text.
#[derive(Clone, Debug, PartialEq)]
pub enum EffectValue {
    /// A parameter's value.
    Number(f64),
    /// The law(s).
    Law(String),
}

impl Effect {
    /// The effect without the evolution law's part (the law, its own parameters and a mixture's
    /// share): what is left when the record cannot tell the law from another as simple
    /// ([`crate::Candidate::law_undecided`]).
    pub fn without_law(self) -> Self {
        Self { law: None, c: None, w: None, b_other_fraction: None, law_parameters: Default::default(), ..self }
    }

    /// No parameter set.
    pub fn is_empty(&self) -> bool {
        self.entries().is_empty()
    }

    /// The number set under the serialised `key` (a study's configured key; code that knows
    /// the cause reads the field).
    pub fn number(&self, key: &str) -> Option<f64> {
        self.entries().into_iter().find_map(|e| match e.value {
            EffectValue::Number(x) if e.key.text() == key => Some(x),
            EffectValue::Number(_) | EffectValue::Law(_) => None,
        })
    }

    /// The set parameters, in key order (as serialised).
    pub fn entries(&self) -> Vec<EffectEntry> {
        let Effect { alpha, b2, b_other_fraction, c, dc2, g, k, law, vc, w, second_state, law_parameters } = self;
        let num = |key: EffectKey, x: &Option<f64>, parameter: Option<ParamName>| {
            x.map(|x| EffectEntry { key, value: EffectValue::Number(x), parameter })
        };
        let state = second_state.unwrap_or(2);
        [
            num(EffectKey::Alpha, alpha, Some(ParamName::Alpha(1))),
            num(EffectKey::B2, b2, Some(ParamName::B(state))),
            num(EffectKey::BOtherFraction, b_other_fraction, None),
            num(EffectKey::C, c, Some(ParamName::Law("c".into(), 1))),
            num(EffectKey::Dc2, dc2, Some(ParamName::Dc(state))),
            num(EffectKey::G, g, Some(ParamName::G)),
            num(EffectKey::K, k, Some(ParamName::K)),
            law.clone().map(|l| EffectEntry { key: EffectKey::Law, value: EffectValue::Law(l), parameter: None }),
            num(EffectKey::Vc, vc, Some(ParamName::Law("vc".into(), 1))),
            num(EffectKey::W, w, Some(ParamName::Law("w".into(), 1))),
        ]
        .into_iter()
        .flatten()
        .chain(law_parameters.iter().map(|(name, x)| EffectEntry {
            key: EffectKey::LawParameter(rsf_laws::registry::intern(name)),
            value: EffectValue::Number(*x),
            parameter: Some(ParamName::Law(name.clone(), 1)),
        }))
        .collect()
    }
}

rsf_core::vocabulary!(Cause, "cause", {
    None => "none",
    EvolutionLaw => "evolution_law",
    SecondStateVariable => "second_state_variable",
    CutoffVelocity => "cutoff_velocity",
    SlipTrend => "slip_trend",
    Stiffness => "stiffness",
    NormalStressCoupling => "normal_stress_coupling",
    Unexplained => "unexplained",
    Undecided => "undecided",
});

/// The effect parameters of `causes` applied together in the fit `f`.
pub fn effect_of(causes: &[Cause], f: &FitResult) -> Effect {
    let mut effect = Effect::default();
    for c in causes {
        c.add_effect(f, &mut effect);
    }
    effect
}

/// The baseline law of a diagnosis: any law of the registry ([`rsf_laws::registry`]), by
/// name; Ruina's Slip law by default (it fits velocity steps of bare rock best). The
/// candidates try the other classic law (Aging for any baseline but Aging), the two-state
/// forms, the cut-off and every other law of the registry.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Baseline(pub rsf_laws::registry::LawName);

impl Baseline {
    /// Ruina's Slip law.
    pub fn slip() -> Self {
        Self(Law::Slip.into())
    }
    /// Dieterich's Aging law.
    pub fn aging() -> Self {
        Self(Law::Aging.into())
    }
    /// The law's name.
    pub fn name(&self) -> &str {
        self.0.as_str()
    }
    /// The law at its parameters' starts; the error says when the registry lost it (a law file
    /// loaded again without it).
    pub fn law(&self) -> Result<Arc<dyn rsf_core::DynStateLaw>, String> {
        self.0.with_starting_values()
    }
}

impl Default for Baseline {
    fn default() -> Self {
        Self::slip()
    }
}

impl std::str::FromStr for Baseline {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        s.parse().map(Self).map_err(|e| format!("baseline: {e}"))
    }
}

impl std::fmt::Display for Baseline {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

impl serde::Serialize for Baseline {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

impl<'de> serde::Deserialize<'de> for Baseline {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        rsf_laws::registry::LawName::deserialize(d).map(Self)
    }
}

/// The other of the two classic laws.
pub(super) fn other_law(base_law: &str) -> Law {
    if base_law == Law::Aging.name() { Law::Slip } else { Law::Aging }
}

/// A built-in law at its fit starting values (Vc 0.01 µm/s; the fit sets it).
pub(super) fn builtin(law: Law) -> Arc<dyn rsf_core::DynStateLaw> {
    law.with_starting_values()
}

/// The laws of the registry tried as the evolution law besides the other classic law: every
/// built-in law but the two classic ones (the baseline and the other law, tried first) and the
/// Kato–Tullis law (its own cause, `cutoff_velocity`, with its Vc profile) and the Aging law
/// without healing (no steady state: it cannot describe the steady sliding every lab record
/// starts from, and a fit cannot start it there), then every law a
/// program registered (a Rust type, a text file, a Python function) in the order registered.
/// Exhaustive over the built-in laws: a new one fails to compile here until the diagnosis
/// decides whether it is a candidate.
pub(super) fn library_laws() -> Vec<rsf_laws::LawEntry> {
    rsf_laws::registry::all()
        .into_iter()
        .filter(|e| match e.builtin() {
            Some(Law::Aging | Law::Slip | Law::KatoTullis | Law::AgingNoHealing) => false,
            Some(Law::Prz | Law::Nagata | Law::AgingSlip) => true,
            None => e.candidate(),
        })
        .collect()
}
