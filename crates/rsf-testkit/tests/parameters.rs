//! The kit checks a law's own parameters: each one listed can be set (a fit sets it by name),
//! and an exact parameter derivative equals central differences. A text-file law passes the
//! kit like a built-in one.

use rsf_core::{Real, StateArgs, StateLaw};
use rsf_testkit::{Claims, Outcome, Property, check};

/// Power-law aging that lists `n` but never implemented `set_parameter`: the kit passed it
/// before it checked the round trip, and fitting it then failed.
#[derive(Debug, Clone)]
struct ListsButCannotSet {
    n: f64,
}
impl StateLaw for ListsButCannotSet {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        -(s.v * s.theta / s.dc).powf(self.n) + 1.0
    }
    fn parameters(&self) -> Vec<(&'static str, f64)> {
        vec![("n", self.n)]
    }
}

#[test]
fn a_parameter_that_cannot_be_set_is_caught() {
    let f = check(&ListsButCannotSet { n: 1.5 }, &Claims::new().steady_state_dc_over_v().cases(16)).unwrap_err();
    assert_eq!(f.property, Property::ParameterRoundTrip, "{f}");
    assert!(f.reason.contains("set_parameter(\"n\""), "{f}");
}

fn examples() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/laws")
}

#[test]
fn the_power_aging_law_file_conforms_with_an_exact_parameter_derivative() {
    let entry = rsf_laws::text_law::load(&examples().join("power_aging.toml")).unwrap();
    let law = rsf_laws::text_law::law_at_starts(&entry).unwrap().with_value("n", 1.6).unwrap();
    let report = check(&law, &Claims::new().steady_state_dc_over_v().cases(64)).unwrap_or_else(|f| panic!("{f}"));
    let outcome = |p| report.outcomes.iter().find(|(q, _)| *q == p).unwrap().1.clone();
    assert_eq!(outcome(Property::ParameterDerivative), Outcome::Passed(64), "{report}");
    assert_eq!(outcome(Property::ParameterRoundTrip), Outcome::Passed(1), "{report}");
    assert!(matches!(outcome(Property::ViTIdentity), Outcome::Passed(_)), "{report}");
}

/// A text law whose steady state is not Dc/V though it claims so is caught, like a Rust one.
#[test]
fn a_wrong_text_law_fails_on_the_property_that_is_wrong() {
    let text = "name = \"off-steady\"\ntheta_rate = \"1.1 - omega\"\n";
    let entry = rsf_laws::text_law::parse(text, "off.toml").unwrap();
    let law = rsf_laws::text_law::law_at_starts(&entry).unwrap();
    let f = check(&law, &Claims::new().steady_state_dc_over_v().cases(32)).unwrap_err();
    assert_eq!(f.property, Property::SteadyState, "{f}");
}
