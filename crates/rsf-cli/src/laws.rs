//! `rsf laws` (the registry's laws and their parameters) and `rsf check-law` (the conformance
//! kit on a law file or a registered law).

use anyhow::Result;
use rsf_laws::registry::{self, Origin, Start};
use rsf_testkit::Claims;
use std::fmt::Write;
use std::path::Path;

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
    let report = rsf_testkit::check_entry(&entry, claims).map_err(anyhow::Error::msg)?;
    report.map(|r| r.to_string()).map_err(|f| anyhow::anyhow!("{f}"))
}
