//! The protocol file's fields as read, before any is checked: from TOML text with their spans,
//! or bare from a table built in memory — one shape for both, so that one validator
//! (`build.rs`) serves both.

use serde::Deserialize;
use serde::de::DeserializeOwned;
use std::ops::Range;
use toml::Spanned;

/// How the raw fields are held: with their byte spans in the TOML text ([`WithSpans`]), or bare,
/// from a table built in memory ([`Bare`]: the Python objects). One validator serves both.
pub(super) trait Wrap {
    type Of<T: DeserializeOwned>: Located<T> + DeserializeOwned;
}

/// A raw field: its value and, from text, where it was written.
pub(super) trait Located<T> {
    fn get(&self) -> &T;
    fn span(&self) -> Option<Range<usize>>;
}

impl<T> Located<T> for Spanned<T> {
    fn get(&self) -> &T {
        self.get_ref()
    }
    fn span(&self) -> Option<Range<usize>> {
        Some(Spanned::span(self))
    }
}

/// A field without a place in any text.
#[derive(Deserialize)]
#[serde(transparent)]
pub(super) struct Bare<T>(T);

impl<T> Located<T> for Bare<T> {
    fn get(&self) -> &T {
        &self.0
    }
    fn span(&self) -> Option<Range<usize>> {
        None
    }
}

/// Fields from TOML text, with spans.
pub(super) struct WithSpans;
impl Wrap for WithSpans {
    type Of<T: DeserializeOwned> = Spanned<T>;
}

/// Fields from a table built in memory.
pub(super) struct InMemory;
impl Wrap for InMemory {
    type Of<T: DeserializeOwned> = Bare<T>;
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, bound = "")]
pub(super) struct RawFile<W: Wrap> {
    /// Law files (TOML, [`rsf_laws::text_law`]) to register before the model is read; paths
    /// relative to the protocol's folder.
    pub(super) law_files: Option<W::Of<Vec<String>>>,
    pub(super) model: W::Of<RawModel<W>>,
    pub(super) loading: W::Of<RawLoading<W>>,
    pub(super) output: Option<W::Of<RawOutput<W>>>,
    pub(super) solver: Option<RawSolver<W>>,
    pub(super) initial: Option<W::Of<RawInitial<W>>>,
}

/// `[initial]`: start off steady state, at slip rate `v` (µm/s) with state `theta` (s, one per
/// state variable), instead of steady state at `loading.v_init`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, bound = "")]
pub(super) struct RawInitial<W: Wrap> {
    pub(super) v: W::Of<f64>,
    pub(super) theta: W::Of<Vec<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, bound = "")]
pub(super) struct RawModel<W: Wrap> {
    pub(super) mu0: W::Of<f64>,
    pub(super) v0: W::Of<f64>,
    pub(super) a: W::Of<f64>,
    pub(super) stiffness: W::Of<f64>,
    pub(super) eta: Option<W::Of<f64>>,
    pub(super) a_slope: Option<W::Of<f64>>,
    pub(super) form: Option<W::Of<String>>,
    pub(super) normal_stress: Option<W::Of<f64>>,
    pub(super) state: Option<Vec<W::Of<RawState<W>>>>,
}

/// A `[[model.state]]` table: `law`, `b`, `dc`, optionally `alpha`, and the law's own
/// parameters by the names its registry entry gives (`vc`, `c`, `n`, …). Read as a table
/// because which keys are allowed depends on the law.
pub(super) type RawState<W> = std::collections::BTreeMap<String, <W as Wrap>::Of<toml::Value>>;

/// A number of a state table and where it was written.
pub(super) type Located64 = (f64, Option<Range<usize>>);

/// The fields of a state table that are not a law's parameters.
pub(super) const STATE_FIELDS: [&str; 4] = ["law", "b", "dc", "alpha"];

#[derive(Deserialize)]
#[serde(deny_unknown_fields, bound = "")]
pub(super) struct RawLoading<W: Wrap> {
    pub(super) v_init: W::Of<f64>,
    pub(super) segment: Option<Vec<W::Of<RawSegment<W>>>>,
    pub(super) record: Option<W::Of<String>>,
    pub(super) time_column: Option<String>,
    pub(super) load_point_column: Option<String>,
    pub(super) friction_column: Option<String>,
    pub(super) normal_stress_column: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, bound = "")]
pub(super) struct RawSegment<W: Wrap> {
    pub(super) v: W::Of<f64>,
    pub(super) duration: Option<W::Of<f64>>,
    pub(super) displacement: Option<W::Of<f64>>,
    pub(super) normal_stress: Option<W::Of<f64>>,
    pub(super) normal_stress_rate: Option<W::Of<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, bound = "")]
pub(super) struct RawOutput<W: Wrap> {
    pub(super) dt: Option<W::Of<f64>>,
    pub(super) peak_slip_rate: Option<bool>,
    pub(super) event_slip_rate: Option<W::Of<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, bound = "")]
pub(super) struct RawSolver<W: Wrap> {
    pub(super) method: Option<W::Of<String>>,
    pub(super) rtol: Option<W::Of<f64>>,
    pub(super) atol: Option<W::Of<f64>>,
    pub(super) max_slip_rate: Option<W::Of<f64>>,
}
