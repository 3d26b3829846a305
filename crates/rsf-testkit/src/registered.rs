//! The kit on a law of the registry: a built-in law, or a law file's law, with the claims its
//! parameters' units imply (`rsf check-law`, Python's `rsf.check_law`). A law registered from
//! Rust is checked in its own crate's tests with [`check`] on its type; a Python
//! function by `rsf.check_law`, which holds its type.

use crate::{Claims, Failure, Report, check};
use rsf_laws::registry::{LawEntry, Origin};
use rsf_laws::{Aging, AgingNoHealing, AgingSlip, KatoTullis, Law, Nagata, Prz, Slip};

/// The unit a law file gives a velocity parameter (the kit rescales it with time and length).
pub const VELOCITY_UNIT: &str = "µm/s";
/// The unit a law file gives a length parameter (the kit rescales it with length).
pub const LENGTH_UNIT: &str = "µm";

/// `claims` with each parameter of `entry` whose unit is a velocity or a length named as such
/// (so that the scaling properties rescale it).
pub fn claims_from_units(entry: &LawEntry, mut claims: Claims) -> Claims {
    for p in entry.parameters() {
        if p.unit == VELOCITY_UNIT {
            claims = claims.velocity_parameter(p.name);
        } else if p.unit == LENGTH_UNIT {
            claims = claims.length_parameter(p.name);
        }
    }
    claims
}

/// Runs the kit on a built-in law or a law file's law, at its parameters' starts (Kato–Tullis
/// at vc = 0.01 µm/s, its velocity scale claimed). The outer error says why the kit cannot
/// run on this entry here (a law registered from Rust or Python); the inner one is the kit's
/// verdict.
pub fn check_entry(entry: &LawEntry, claims: Claims) -> Result<Result<Report, Failure>, String> {
    match entry.origin() {
        Origin::BuiltIn(law) => Ok(match law {
            Law::Aging => check(&Aging, &claims),
            Law::Slip => check(&Slip, &claims),
            Law::Prz => check(&Prz, &claims),
            Law::Nagata => check(&Nagata { c: 1.0 }, &claims),
            Law::AgingSlip => check(&AgingSlip { w: 0.5 }, &claims),
            Law::AgingNoHealing => check(&AgingNoHealing, &claims.no_steady_state()),
            Law::KatoTullis => check(&KatoTullis { vc: 0.01 }, &claims.velocity_parameter("vc")),
        }),
        Origin::TextFile(_) => {
            let law = rsf_laws::text_law::law_at_starts(entry)
                .ok_or_else(|| format!("law `{}`: its law file could not be built at its starts", entry.name()))?;
            Ok(check(&law, &claims_from_units(entry, claims)))
        }
        Origin::Rust => Err(format!(
            "law `{}` was registered from Rust: check it in its own tests with rsf_testkit::check on its type",
            entry.name()
        )),
        Origin::Python => Err(format!("law `{}` is a Python function: check it with rsf.check_law", entry.name())),
    }
}
