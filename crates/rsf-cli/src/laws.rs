//! `rsf laws` (the registry's laws and their parameters) and `rsf check-law` (the conformance
//! kit on a law file or a registered law).

use anyhow::{Result, bail};
use rsf_laws::registry::{self, LawEntry, Origin, Start};
use rsf_laws::{Aging, AgingSlip, KatoTullis, Law, Nagata, Prz, Slip};
use rsf_testkit::{Claims, check};
use std::fmt::Write;
use std::path::Path;

/// The unit a law file gives a velocity parameter (the kit rescales it with time and length).
const VELOCITY_UNIT: &str = "µm/s";
/// The unit a law file gives a length parameter (the kit rescales it with length).
const LENGTH_UNIT: &str = "µm";

/// The registry's laws, one line each, with their parameters.
pub(crate) fn list() -> String {
    let mut s = String::new();
    for e in registry::all() {
        let origin = match e.origin() {
            Origin::BuiltIn(_) => "built in".to_string(),
            Origin::Rust => "registered from Rust".to_string(),
            Origin::TextFile(p) => format!("law file {}", p.display()),
            Origin::Python => "Python function".to_string(),
        };
        let _ = writeln!(s, "{:<14} {} ({origin})", e.name(), e.words());
        for p in e.parameters() {
            let start = match p.start {
                Start::Value(v) => format!("{v}"),
                Start::SlowestLoadPointVelocity => "the slowest load-point velocity".into(),
            };
            let unit = if p.unit.is_empty() { "dimensionless".into() } else { p.unit.to_string() };
            let scale = if p.log { ", fitted as a logarithm" } else { "" };
            let _ =
                writeln!(s, "    {:<6} {unit}, range [{}, {}]{scale}, starts at {start}", p.name, num(p.lo), num(p.hi));
        }
    }
    s
}

/// A number as a person writes it: plain between 1e-3 and 1e6, else with an exponent.
fn num(x: f64) -> String {
    if x == 0.0 || (1e-3..1e6).contains(&x.abs()) { format!("{x}") } else { format!("{x:e}") }
}

/// Runs the conformance kit on `law` (a law file, or a registered law's name).
pub(crate) fn check_law(law: &str, cases: Option<u32>, dc_over_v: bool) -> Result<String> {
    let path = Path::new(law);
    let entry = if path.exists() {
        rsf_laws::text_law::load(path).map_err(anyhow::Error::msg)?
    } else {
        registry::find(law).map_err(anyhow::Error::msg)?
    };
    let mut claims = Claims::new();
    if dc_over_v {
        claims = claims.steady_state_dc_over_v();
    }
    if let Some(n) = cases {
        claims = claims.cases(n);
    }
    let report = match entry.builtin() {
        Some(l) => check_builtin(l, claims),
        None => check_text(&entry, claims)?,
    };
    report.map(|r| r.to_string()).map_err(|f| anyhow::anyhow!("{f}"))
}

fn check_text(entry: &LawEntry, mut claims: Claims) -> Result<Result<rsf_testkit::Report, rsf_testkit::Failure>> {
    let Some(law) = rsf_laws::text_law::law_at_starts(entry) else {
        bail!(
            "law `{}` was registered from Rust or Python: check it in its own tests with rsf_testkit::check",
            entry.name()
        );
    };
    for p in entry.parameters() {
        if p.unit == VELOCITY_UNIT {
            claims = claims.velocity_parameter(p.name);
        } else if p.unit == LENGTH_UNIT {
            claims = claims.length_parameter(p.name);
        }
    }
    Ok(check(&law, &claims))
}

fn check_builtin(l: Law, claims: Claims) -> Result<rsf_testkit::Report, rsf_testkit::Failure> {
    match l {
        Law::Aging => check(&Aging, &claims),
        Law::Slip => check(&Slip, &claims),
        Law::Prz => check(&Prz, &claims),
        Law::Nagata => check(&Nagata { c: 1.0 }, &claims),
        Law::AgingSlip => check(&AgingSlip { w: 0.5 }, &claims),
        Law::KatoTullis => check(&KatoTullis { vc: 0.01 }, &claims.velocity_parameter("vc")),
    }
}
