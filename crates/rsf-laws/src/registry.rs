//! The law registry: every law rsf can name — the built-in ones first, then those a program
//! registers (a Rust type, a text file, a Python function) — with its parameters' specs and a
//! constructor. The protocol loader, the CLI, the batch manifest, Python, fitting, the
//! diagnosis and design all look laws up here, so a law registered once is usable everywhere.
//!
//! The registry is one per process (like a program's set of commands), filled by explicit
//! calls to [`register`]; nothing is read from the environment. Looking a law up by name gives
//! the same law whatever thread asks.
//!
//! ```
//! use rsf_core::{Real, StateArgs, StateLaw};
//! use rsf_laws::registry::{self, LawEntry, LawParameter, Start};
//! use std::sync::Arc;
//!
//! /// Power-law aging, dθ/dt = 1 − Ω^n (n = 1: Aging).
//! #[derive(Debug, Clone)]
//! struct PowerAging { n: f64 }
//! impl StateLaw for PowerAging {
//!     fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
//!         -(s.v * s.theta / s.dc).powf(self.n) + 1.0
//!     }
//!     fn name(&self) -> String { "power-aging-doc".into() }
//!     fn parameters(&self) -> Vec<(&'static str, f64)> { vec![("n", self.n)] }
//!     fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), String> {
//!         match name { "n" => { self.n = value; Ok(()) } _ => Err(format!("no parameter `{name}`")) }
//!     }
//! }
//! let n = LawParameter { name: "n", unit: "", lo: 0.2, hi: 5.0, log: false, start: Start::Value(1.0) };
//! registry::register(LawEntry::new("power-aging-doc", "power-law aging", vec![n],
//!     |p| Ok(Arc::new(PowerAging { n: p[0] }))))
//!     .unwrap();
//! let law = rsf_laws::law_by_name("power-aging-doc", |p| (p == "n").then_some(1.5)).unwrap();
//! assert_eq!(law.parameters(), vec![("n", 1.5)]);
//! ```

use crate::Law;
use crate::reshaped::RESHAPED_SUFFIX;
use rsf_core::DynStateLaw;
use std::path::PathBuf;
use std::sync::{Arc, LazyLock, RwLock};

/// Where a fit starts a law parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    /// At this value.
    Value(f64),
    /// At the slowest non-zero load-point velocity of the record (µm/s; a velocity scale such
    /// as a cut-off velocity, which then starts where the record can see it). Without a record
    /// at hand, [`START_VELOCITY`].
    SlowestLoadPointVelocity,
}

/// A velocity parameter's start when no record is at hand, µm/s (a slow lab load point).
pub const START_VELOCITY: f64 = 0.01;

/// One of a law's own parameters: its name, unit, physical range, fitting scale and start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawParameter {
    /// Name in files, on the command line and in fitted-parameter names (`vc` → `vc1`).
    pub name: &'static str,
    /// Unit (`µm/s`; empty for a dimensionless one).
    pub unit: &'static str,
    /// Lowest physical value: a fit never tries below it, a model with less is refused.
    pub lo: f64,
    /// Highest physical value.
    pub hi: f64,
    /// Fitted as a logarithm (a positive quantity that spans decades).
    pub log: bool,
    /// Where a fit starts it.
    pub start: Start,
}

impl LawParameter {
    /// The starting value, given the slowest non-zero load-point velocity when known (µm/s).
    pub fn start_value(&self, slowest_velocity: Option<f64>) -> f64 {
        match self.start {
            Start::Value(v) => v,
            Start::SlowestLoadPointVelocity => slowest_velocity.unwrap_or(START_VELOCITY),
        }
    }
    /// Checks that `value` lies in the physical range; the error names the parameter.
    pub fn check(&self, value: f64) -> Result<(), String> {
        if value >= self.lo && value <= self.hi {
            Ok(())
        } else {
            let unit = if self.unit.is_empty() { String::new() } else { format!(" {}", self.unit) };
            Err(format!("{} = {value} is outside its range [{}, {}]{unit}", self.name, self.lo, self.hi))
        }
    }
}

/// Where a registered law comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// One of rsf's own laws.
    BuiltIn(Law),
    /// A Rust type registered by a program.
    Rust,
    /// A text file ([`crate::text_law`]).
    TextFile(PathBuf),
    /// A Python function (rsf-py).
    Python,
}

/// Builds a law from its parameter values, in the order of [`LawEntry::parameters`].
pub type Constructor = Arc<dyn Fn(&[f64]) -> Result<Arc<dyn DynStateLaw>, String> + Send + Sync>;

/// A registered law: name, parameter specs, constructor.
#[derive(Clone)]
pub struct LawEntry {
    name: String,
    words: String,
    parameters: Vec<LawParameter>,
    origin: Origin,
    source: Option<String>,
    candidate: bool,
    construct: Constructor,
}

impl std::fmt::Debug for LawEntry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LawEntry")
            .field("name", &self.name)
            .field("parameters", &self.parameters)
            .field("origin", &self.origin)
            .finish()
    }
}

impl LawEntry {
    /// A law registered from Rust: its name (lower case, digits and `-`), its name in prose,
    /// its parameters and a constructor taking their values in that order.
    pub fn new(
        name: &str,
        words: &str,
        parameters: Vec<LawParameter>,
        construct: impl Fn(&[f64]) -> Result<Arc<dyn DynStateLaw>, String> + Send + Sync + 'static,
    ) -> Self {
        Self {
            name: name.into(),
            words: words.into(),
            parameters,
            origin: Origin::Rust,
            source: None,
            candidate: true,
            construct: Arc::new(construct),
        }
    }
    /// The same entry with another origin (a text file's loader, rsf-py).
    pub fn with_origin(mut self, origin: Origin) -> Self {
        self.origin = origin;
        self
    }
    /// The same entry with the text that defines it (a law file's), so that a result can say
    /// which definition it was computed with.
    pub fn with_source(mut self, source: &str) -> Self {
        self.source = Some(source.into());
        self
    }
    /// The same entry, tried by the diagnosis as a candidate law or not (a Python function
    /// registered only because it was given to a fit is not: it would slow every later
    /// diagnosis of the session to its pace).
    pub fn with_candidate(mut self, candidate: bool) -> Self {
        self.candidate = candidate;
        self
    }
    /// Whether the diagnosis tries it as a candidate law.
    pub fn candidate(&self) -> bool {
        self.candidate
    }
    /// The text that defines the law, when it came from one.
    pub fn source(&self) -> Option<&str> {
        self.source.as_deref()
    }
    /// Name in files and on the command line.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Name in prose.
    pub fn words(&self) -> &str {
        &self.words
    }
    /// The law's own parameters.
    pub fn parameters(&self) -> &[LawParameter] {
        &self.parameters
    }
    /// One parameter's spec by name.
    pub fn parameter(&self, name: &str) -> Option<&LawParameter> {
        self.parameters.iter().find(|p| p.name == name)
    }
    /// Where it comes from.
    pub fn origin(&self) -> &Origin {
        &self.origin
    }
    /// The built-in law, when it is one.
    pub fn builtin(&self) -> Option<Law> {
        match self.origin {
            Origin::BuiltIn(l) => Some(l),
            Origin::Rust | Origin::TextFile(_) | Origin::Python => None,
        }
    }
    /// The law with each parameter looked up by `param`; the error names a missing or
    /// out-of-range one.
    pub fn build(&self, param: impl Fn(&str) -> Option<f64>) -> Result<Arc<dyn DynStateLaw>, String> {
        let values = self
            .parameters
            .iter()
            .map(|p| {
                let v = param(p.name).ok_or_else(|| format!("law `{}` needs parameter `{}`", self.name, p.name))?;
                p.check(v).map_err(|m| format!("law `{}`: {m}", self.name))?;
                Ok(v)
            })
            .collect::<Result<Vec<f64>, String>>()?;
        (self.construct)(&values)
    }
    /// The law with its parameters at their starts (velocity scales at [`START_VELOCITY`]).
    pub fn with_starting_values(&self) -> Result<Arc<dyn DynStateLaw>, String> {
        self.build(|n| self.parameter(n).map(|p| p.start_value(None)))
    }
}

fn builtin_entries() -> Vec<LawEntry> {
    Law::ALL
        .iter()
        .map(|&l| LawEntry {
            name: l.name().into(),
            words: l.words().into(),
            parameters: l.specs().to_vec(),
            origin: Origin::BuiltIn(l),
            source: None,
            candidate: true,
            construct: Arc::new(move |v: &[f64]| {
                let specs = l.specs();
                l.build(|p| specs.iter().position(|s| s.name == p).map(|i| v[i]))
            }),
        })
        .collect()
}

static REGISTRY: LazyLock<RwLock<Vec<LawEntry>>> = LazyLock::new(|| RwLock::new(builtin_entries()));

fn read() -> std::sync::RwLockReadGuard<'static, Vec<LawEntry>> {
    // a panic while the lock was held cannot leave the list half-written (pushes and
    // replacements are single moves), so a poisoned lock is still a consistent list
    REGISTRY.read().unwrap_or_else(|e| e.into_inner())
}

/// Checks a law name: lower-case letters, digits and `-`, starting with a letter.
/// A name ending in [`RESHAPED_SUFFIX`] is refused: it names a registered law reshaped, which
/// the registry derives ([`find`]).
pub fn check_name(name: &str) -> Result<(), String> {
    let ok = name.chars().next().is_some_and(|c| c.is_ascii_lowercase())
        && name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-');
    if !ok {
        return Err(format!("law name `{name}`: use lower-case letters, digits and `-`, from a letter"));
    }
    if name.ends_with(RESHAPED_SUFFIX) {
        return Err(format!(
            "law name `{name}`: a name ending in `{RESHAPED_SUFFIX}` is a registered law reshaped in state, which \
             rsf derives; choose another"
        ));
    }
    Ok(())
}

/// Names a law's own parameter may not take: the model's parameters and a state table's fields
/// (a fit names a law parameter `n` of state 1 `n1`, beside `b1`, `dc1`, `alpha1`).
pub const RESERVED_PARAMETER_NAMES: [&str; 8] = ["mu0", "a", "k", "g", "b", "dc", "alpha", "law"];

/// Checks a law parameter's name: lower-case letters only (a fit appends the state's number),
/// none of [`RESERVED_PARAMETER_NAMES`].
pub fn check_parameter_name(name: &str) -> Result<(), String> {
    if !name.is_empty() && name.chars().all(|c| c.is_ascii_lowercase()) && !RESERVED_PARAMETER_NAMES.contains(&name) {
        Ok(())
    } else {
        Err(format!(
            "parameter name `{name}`: use lower-case letters only (a fit names it with the state's number: n → n1), \
             and none of {}",
            RESERVED_PARAMETER_NAMES.join(", ")
        ))
    }
}

/// Checks an entry's name and parameter specs (what [`register`] refuses).
pub fn check_entry(entry: &LawEntry) -> Result<(), String> {
    check_name(&entry.name)?;
    let mut seen = std::collections::HashSet::new();
    for p in &entry.parameters {
        check_parameter_name(p.name).map_err(|m| format!("law `{}`: {m}", entry.name))?;
        if !seen.insert(p.name) {
            return Err(format!("law `{}` lists parameter `{}` twice", entry.name, p.name));
        }
        if !(p.lo <= p.hi) || (p.log && !(p.lo > 0.0)) {
            return Err(format!(
                "law `{}`: parameter `{}` has an empty or (log scale) non-positive range",
                entry.name, p.name
            ));
        }
        let s = p.start_value(None);
        p.check(s).map_err(|m| format!("law `{}`: the start of {m}", entry.name))?;
    }
    Ok(())
}

/// Registers a law. A name rsf has built in is refused; a name already registered by a
/// program is replaced (so that a text file edited and loaded again takes effect).
pub fn register(entry: LawEntry) -> Result<(), String> {
    check_entry(&entry)?;
    let mut list = REGISTRY.write().unwrap_or_else(|e| e.into_inner());
    match list.iter().position(|e| e.name == entry.name) {
        Some(i) if list[i].builtin().is_some() => {
            Err(format!("`{}` is a built-in law; choose another name", entry.name))
        }
        Some(i) => {
            list[i] = entry;
            Ok(())
        }
        None => {
            list.push(entry);
            Ok(())
        }
    }
}

/// The law registered under `name`, or — for `name` a registered law's with
/// [`RESHAPED_SUFFIX`] — that law reshaped in state ([`crate::reshaped`]); the error lists the
/// names known.
pub fn find(name: &str) -> Result<LawEntry, String> {
    let list = read();
    if let Some(base) = name.strip_suffix(RESHAPED_SUFFIX).and_then(|b| list.iter().find(|e| e.name == b)) {
        return crate::reshaped::entry(base);
    }
    list.iter().find(|e| e.name == name).cloned().ok_or_else(|| {
        let names: Vec<&str> = list.iter().map(|e| e.name.as_str()).collect();
        format!(
            "unknown law `{name}`: use {} (or load a law file with --law-file)",
            rsf_core::vocabulary::one_of(&names)
        )
    })
}

/// Every registered law, the built-in ones first, then in the order registered.
pub fn all() -> Vec<LawEntry> {
    read().clone()
}

/// Interns a parameter name given at run time (a text file's, Python's), so that it can be
/// reported as `&'static str` like a built-in law's. Each distinct name is stored once.
pub fn intern(name: &str) -> &'static str {
    static NAMES: LazyLock<RwLock<Vec<&'static str>>> = LazyLock::new(|| RwLock::new(Vec::new()));
    if let Some(n) = NAMES.read().unwrap_or_else(|e| e.into_inner()).iter().find(|n| **n == name) {
        return n;
    }
    let mut names = NAMES.write().unwrap_or_else(|e| e.into_inner());
    if let Some(n) = names.iter().find(|n| **n == name) {
        return n;
    }
    let n: &'static str = Box::leak(name.to_string().into_boxed_str());
    names.push(n);
    n
}

/// A law's name, checked against the registry when parsed (`"power-aging".parse()` succeeds
/// once the law is registered). What manifests and options hold in place of a closed `Law`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct LawName(String);

impl LawName {
    /// The name.
    pub fn as_str(&self) -> &str {
        &self.0
    }
    /// The registry's entry (a law registered since the name was parsed is never removed; a
    /// law file loaded again may have replaced it).
    pub fn entry(&self) -> Result<LawEntry, String> {
        find(&self.0)
    }
    /// The law at its parameters' starts.
    pub fn with_starting_values(&self) -> Result<Arc<dyn DynStateLaw>, String> {
        self.entry()?.with_starting_values()
    }
}

impl std::str::FromStr for LawName {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        find(s).map(|e| LawName(e.name))
    }
}

impl From<Law> for LawName {
    fn from(l: Law) -> Self {
        LawName(l.name().into())
    }
}

impl serde::Serialize for LawName {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.0)
    }
}

impl<'de> serde::Deserialize<'de> for LawName {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

impl std::fmt::Display for LawName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(&self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtins_come_first_and_cannot_be_replaced() {
        let names: Vec<String> = all().iter().map(|e| e.name().to_string()).collect();
        assert_eq!(&names[..Law::ALL.len()], Law::NAMES);
        let e = LawEntry::new("slip", "mine", vec![], |_| Ok(Arc::new(crate::Slip)));
        assert!(register(e).unwrap_err().contains("built-in"));
        assert!(register(LawEntry::new("Bad Name", "", vec![], |_| Ok(Arc::new(crate::Slip)))).is_err());
        assert!(find("no-such-law").unwrap_err().contains("aging, slip"));
    }

    /// A parameter a fit could not name, or would confuse with the model's own, is refused.
    #[test]
    fn parameter_names_a_fit_can_use() {
        let law = |name: &'static str| {
            let p = LawParameter { name, unit: "", lo: 0.0, hi: 1.0, log: false, start: Start::Value(0.5) };
            LawEntry::new("names-test", "", vec![p], |_| Ok(Arc::new(crate::Slip)))
        };
        for bad in ["alpha", "b", "dc", "n_exp", "k2x", "N", ""] {
            assert!(register(law(bad)).unwrap_err().contains("parameter name"), "{bad}");
        }
        assert!(check_entry(&law("nexp")).is_ok());
    }

    #[test]
    fn build_checks_presence_and_range() {
        let kt = find("kato-tullis").unwrap();
        assert!(kt.build(|_| None).unwrap_err().contains("needs parameter `vc`"));
        assert!(kt.build(|_| Some(-1.0)).unwrap_err().contains("outside its range"));
        assert_eq!(kt.build(|_| Some(0.5)).unwrap().parameters(), vec![("vc", 0.5)]);
        assert_eq!(kt.with_starting_values().unwrap().parameters(), vec![("vc", START_VELOCITY)]);
    }

    #[test]
    fn interned_names_are_shared() {
        let a = intern("zeta-test");
        let b = intern(&String::from("zeta-test"));
        assert!(std::ptr::eq(a, b));
    }
}
