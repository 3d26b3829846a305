//! The closed vocabulary of causes, and what each does to a model: the extension it applies,
//! its words, and the effect parameters it reports.

use crate::fit::{AlphaFit, FitOptions, FitResult};
use rsf_laws::Law;
use serde::Serialize;
use std::collections::BTreeMap;
use std::sync::Arc;

/// What a fitted model gets wrong (serialised as its snake_case name).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Cause {
    /// Nothing: no extension earns its parameters.
    None,
    /// The evolution law: the other law, or a share of time-dependent (Aging) healing.
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
}

impl Cause {
    /// The candidate extensions, in the order they are tried.
    pub const CANDIDATES: [Cause; 6] = [
        Cause::EvolutionLaw,
        Cause::SecondStateVariable,
        Cause::CutoffVelocity,
        Cause::SlipTrend,
        Cause::Stiffness,
        Cause::NormalStressCoupling,
    ];

    /// The snake_case name (as in JSON).
    pub fn as_str(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::EvolutionLaw => "evolution_law",
            Self::SecondStateVariable => "second_state_variable",
            Self::CutoffVelocity => "cutoff_velocity",
            Self::SlipTrend => "slip_trend",
            Self::Stiffness => "stiffness",
            Self::NormalStressCoupling => "normal_stress_coupling",
        }
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
        }
    }

    /// Applies this extension to fit options (composable: a combination applies two). `None`
    /// when it does not apply (e.g. the cut-off on top of a law change).
    pub fn extend(self, o: &FitOptions, base_law: &str) -> Option<FitOptions> {
        let mut o = o.clone();
        match self {
            Self::None => {}
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
                if o.laws[0].name() != base_law || o.laws.len() != 1 {
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
    fn add_effect(self, f: &FitResult, effect: &mut BTreeMap<String, serde_json::Value>) {
        let pr = &f.params;
        match self {
            Self::None => {}
            Self::EvolutionLaw => {
                effect.insert("law".into(), serde_json::json!(pr.laws.join("+")));
                if pr.b.len() == 2 {
                    // share of the evolution effect carried by the other law
                    effect.insert("b_other_fraction".into(), serde_json::json!(pr.b[1] / (pr.b[0] + pr.b[1])));
                }
            }
            Self::SecondStateVariable => {
                // the states are exchangeable in the fit: report the slower one as the second
                let i = (0..pr.dc.len()).max_by(|&x, &y| pr.dc[x].total_cmp(&pr.dc[y])).unwrap_or(0);
                effect.insert("b2".into(), serde_json::json!(pr.b.get(i)));
                effect.insert("dc2".into(), serde_json::json!(pr.dc.get(i)));
            }
            Self::CutoffVelocity => {
                effect.insert("vc".into(), serde_json::json!(pr.law_params.get("vc1")));
            }
            Self::SlipTrend => {
                effect.insert("g".into(), serde_json::json!(pr.g));
            }
            Self::Stiffness => {
                effect.insert("k".into(), serde_json::json!(pr.k));
            }
            Self::NormalStressCoupling => {
                effect.insert("alpha".into(), serde_json::json!(pr.alpha.first()));
            }
        }
    }
}

impl std::fmt::Display for Cause {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // pad: tables align causes with `{:24}`
        f.pad(self.as_str())
    }
}

/// The effect parameters of `causes` applied together in the fit `f`.
pub fn effect_of(causes: &[Cause], f: &FitResult) -> BTreeMap<String, serde_json::Value> {
    let mut effect = BTreeMap::new();
    for c in causes {
        c.add_effect(f, &mut effect);
    }
    effect
}

/// The baseline law of a diagnosis: one of the two classic laws (the candidates try the other).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Baseline {
    /// Ruina's Slip law (the default: it fits velocity steps of bare rock best).
    Slip,
    /// Dieterich's Aging law.
    Aging,
}

rsf_core::vocabulary!(Baseline, "baseline", { Slip => "slip", Aging => "aging" });

impl Baseline {
    /// The law.
    pub fn law(self) -> Law {
        match self {
            Baseline::Slip => Law::Slip,
            Baseline::Aging => Law::Aging,
        }
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
