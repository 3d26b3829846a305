//! What a design starts from: the diagnosis's verdict and its models, each a fit with the options
//! it was made with; from a diagnosis in memory ([`Basis::of`]) or rebuilt from its JSON
//! ([`Rebuilt::from_json`], `rsf design --from`).

use rsf_diagnose::{
    AdequacyVerdict, Cause, DiagnoseOptions, Diagnosis, cause_variants, diagnosis_fit_options, without_spikes,
};
use rsf_fit::data::Record;
use rsf_fit::fit::{FitError, FitOptions, FitResult, LoadingMode, Params, fit, prepare};
use rsf_fit::parallel::par_map;
use rsf_fit::segment::Segment;
use serde_json::Value;

/// A refit from the reported optimum lands within a small fraction of a unit of ln L of it; a
/// different record, or different column or loading options, moves ln L by far more. A rebuilt
/// baseline further away than this is refused.
pub const REBUILD_LNL_TOLERANCE: f64 = 1.0;

/// What a diagnosis says of one candidate model, whatever it was read from.
#[derive(Clone, Debug)]
pub struct CandidateScore {
    /// The model's name in the design: the cause's, or for another way of it the cause's with
    /// its laws (`evolution_law (nagata)`).
    pub name: String,
    /// The cause it stands for.
    pub cause: Cause,
    /// Whether its fit reached an optimum (one that did not is not designed for).
    pub converged: bool,
    /// The extension in words.
    pub extension: String,
    /// Its ΔBIC against the baseline.
    pub delta_bic: f64,
    /// Its ΔAIC against the baseline.
    pub delta_aic: f64,
    /// Why it cannot be designed for (a parameter at a bound, an effect below resolution).
    pub excluded: Option<String>,
}

/// One candidate model of a diagnosis.
pub struct BasisModel<'a> {
    /// What the diagnosis says of it.
    pub score: CandidateScore,
    /// Its fit and the options it was made with (`None` when it has none or is excluded).
    pub fit: Option<(&'a FitResult, &'a FitOptions)>,
}

/// What a design starts from.
pub struct Basis<'a> {
    /// The diagnosis's verdict.
    pub cause: Cause,
    /// How the diagnosis drove the model.
    pub loading: LoadingMode,
    /// The baseline's fit.
    pub baseline: &'a FitResult,
    /// The options it was made with.
    pub baseline_options: &'a FitOptions,
    /// The adequacy test's verdict on the model named (the baseline for `none`).
    pub adequacy: AdequacyVerdict,
    /// The candidate extensions, and the other ways of each (another law, a mixture).
    pub candidates: Vec<BasisModel<'a>>,
}

/// The design's name of another way of `cause` whose model has the laws `laws`.
pub fn alternative_name(cause: Cause, laws: &[String]) -> String {
    format!("{} ({})", cause.as_str(), laws.join("+"))
}

/// An alternative's parameters at a bound that the baseline did not already have there.
fn alternative_at_bound(a: &rsf_diagnose::Alternative, base: &FitResult) -> Vec<String> {
    a.fit.at_bound.iter().filter(|n| !base.at_bound.contains(n)).cloned().collect()
}

fn excluded(at_bound: &[String], unresolved: Option<&String>) -> Option<String> {
    match unresolved {
        Some(u) => Some(u.clone()),
        None if !at_bound.is_empty() => Some(format!("{} at a bound", at_bound.join(", "))),
        None => None,
    }
}

impl<'a> Basis<'a> {
    /// The basis of a diagnosis made in this process.
    pub fn of(d: &'a Diagnosis) -> Result<Self, FitError> {
        let baseline_options = d
            .baseline_options
            .as_ref()
            .ok_or_else(|| FitError::Setup("the diagnosis carries no baseline options to design from".into()))?;
        let mut candidates = vec![];
        for c in &d.candidates {
            candidates.push(BasisModel {
                score: CandidateScore {
                    name: c.cause.as_str().into(),
                    cause: c.cause,
                    converged: c.converged,
                    extension: c.extension.clone(),
                    delta_bic: c.delta_bic,
                    delta_aic: c.delta_aic,
                    excluded: excluded(&c.at_bound, c.unresolved.as_ref()),
                },
                fit: c.fit.as_ref().zip(c.options.as_ref()),
            });
            for a in &c.alternatives {
                candidates.push(BasisModel {
                    score: CandidateScore {
                        name: alternative_name(c.cause, &a.fit.params.laws),
                        cause: c.cause,
                        converged: a.converged,
                        extension: a.extension.clone(),
                        delta_bic: a.delta_bic,
                        delta_aic: a.delta_aic,
                        excluded: excluded(&alternative_at_bound(a, &d.baseline), None),
                    },
                    fit: Some((&a.fit, &a.options)),
                });
            }
        }
        Ok(Basis {
            cause: d.cause,
            loading: d.loading,
            baseline: &d.baseline,
            baseline_options,
            adequacy: d.adequacy.verdict,
            candidates,
        })
    }
}

/// A candidate rebuilt from JSON.
struct RebuiltModel {
    score: CandidateScore,
    fit: Option<(FitResult, FitOptions)>,
}

/// A diagnosis read back from its JSON (`rsf diagnose --json`): every model that can be designed
/// for is refitted on the record from its reported parameters (one start, warm), which gives the
/// covariance and the residuals the JSON does not hold. The ΔBICs and the verdict are the JSON's.
pub struct Rebuilt {
    cause: Cause,
    adequacy: AdequacyVerdict,
    loading: LoadingMode,
    baseline: FitResult,
    baseline_options: FitOptions,
    candidates: Vec<RebuiltModel>,
    /// What the rebuild noticed (candidates it could not rebuild), for the design's notes.
    pub notes: Vec<String>,
}

/// A field of the diagnosis JSON, or an error naming it.
fn field<'v>(v: &'v Value, path: &[&str]) -> Result<&'v Value, FitError> {
    path.iter()
        .try_fold(v, |v, k| v.get(k))
        .ok_or_else(|| FitError::Setup(format!("diagnosis JSON: no `{}`", path.join("."))))
}

fn params(v: &Value, what: &str) -> Result<Params, FitError> {
    serde_json::from_value(v.clone()).map_err(|e| FitError::Setup(format!("diagnosis JSON: {what}: {e}")))
}

/// A refit of `opts` from `from` on the cleaned record: one start, warm.
fn refit(rec: &Record, segs: &[Segment], opts: &FitOptions, from: &Params) -> Result<FitResult, FitError> {
    let warm = FitOptions { initial: from.as_initial(), starts: 1, ..opts.clone() };
    fit(&prepare(rec, segs, opts)?, &warm)
}

impl Rebuilt {
    /// Reads the diagnosis `json` of `rec` (its segments `segs`), made with the options `dopts`
    /// (the same column, baseline and loading options as `rsf diagnose` was given). Refused,
    /// with the reason, when the JSON is not a diagnosis of this record with these options.
    pub fn from_json(rec: &Record, segs: &[Segment], json: &str, dopts: &DiagnoseOptions) -> Result<Self, FitError> {
        let v: Value =
            serde_json::from_str(json).map_err(|e| FitError::Setup(format!("diagnosis JSON does not parse: {e}")))?;
        let cause_s = field(&v, &["cause"])?.as_str().unwrap_or_default();
        let cause = Cause::parse(cause_s)
            .ok_or_else(|| FitError::Setup(format!("diagnosis JSON: cause `{cause_s}` is not one rsf knows")))?;
        // (a JSON written before the adequacy test holds none: its verdict untested)
        let adequacy = match v.get("adequacy").and_then(|a| a.get("verdict")).and_then(Value::as_str) {
            Some("adequate") => AdequacyVerdict::Adequate,
            Some("inadequate") => AdequacyVerdict::Inadequate,
            _ => AdequacyVerdict::Untestable,
        };
        let loading: LoadingMode = field(&v, &["loading"])?
            .as_str()
            .unwrap_or_default()
            .parse()
            .map_err(|e| FitError::Setup(format!("diagnosis JSON: {e}")))?;
        let base_params = params(field(&v, &["baseline", "params"])?, "baseline.params")?;
        let mut base_opts = FitOptions { loading, ..diagnosis_fit_options(dopts) };
        let base_law = base_opts.laws.first().map(|l| l.name()).unwrap_or_default();
        if base_params.laws.len() != 1 || base_params.laws[0] != base_law {
            return Err(FitError::Setup(format!(
                "the diagnosis's baseline is the {} law, these options' the {base_law} law: give the baseline it was made with",
                base_params.laws.join("+")
            )));
        }
        // the samples the diagnosis left out, as it did: a short suspect segment (the
        // reconstruction check), replaced by the break-timing windows when it masked them
        for path in [["reconstruction", "excluded"], ["timing", "windows"]] {
            if let Some(w) = v.get(path[0]).and_then(|t| t.get(path[1])) {
                base_opts.exclude = serde_json::from_value(w.clone())
                    .map_err(|e| FitError::Setup(format!("diagnosis JSON: {}: {e}", path.join("."))))?;
            }
        }
        // the warm start carries k: a stiffness other than the one the diagnosis was made
        // with would be fitted at one k and run at another
        if !base_opts.fit_stiffness && (base_params.k - base_opts.stiffness).abs() > 1e-9 * base_opts.stiffness.abs() {
            return Err(FitError::Setup(format!(
                "the diagnosis was made with stiffness {}, these options give {}: give the stiffness it was made with",
                base_params.k, base_opts.stiffness
            )));
        }
        let (clean, csegs, spikes) = without_spikes(rec, segs);
        let reported: Vec<f64> = v
            .get("spikes_removed")
            .map(|s| serde_json::from_value(s.clone()))
            .transpose()
            .map_err(|e| FitError::Setup(format!("diagnosis JSON: spikes_removed: {e}")))?
            .unwrap_or_default();
        if reported != spikes {
            return Err(FitError::Setup(format!(
                "the diagnosis removed spikes at {} samples, this record has {}: it is not the record the diagnosis was made on",
                reported.len(),
                spikes.len()
            )));
        }
        let baseline = refit(&clean, &csegs, &base_opts, &base_params)?;
        let reported_n = field(&v, &["baseline", "n"])?.as_u64().unwrap_or(0) as usize;
        let reported_lnl = field(&v, &["baseline", "log_likelihood"])?.as_f64().unwrap_or(f64::NAN);
        if baseline.n != reported_n || !((baseline.log_likelihood - reported_lnl).abs() <= REBUILD_LNL_TOLERANCE) {
            return Err(FitError::Setup(format!(
                "the baseline refitted on this record has {} samples and ln L {:.2}, the diagnosis reports {reported_n} and {reported_lnl:.2}: not the record or the options the diagnosis was made with",
                baseline.n, baseline.log_likelihood
            )));
        }
        let mut notes = vec![];
        let empty = vec![];
        let entries = field(&v, &["candidates"])?.as_array().unwrap_or(&empty);
        let mut todo = vec![];
        let mut candidates = vec![];
        for c in entries {
            let cs = c.get("cause").and_then(Value::as_str).unwrap_or_default();
            let Some(cause) = Cause::parse(cs) else {
                notes.push(format!("candidate `{cs}` left out: not a cause rsf knows"));
                continue;
            };
            let alternatives = c.get("alternatives").and_then(Value::as_array).cloned().unwrap_or_default();
            for (k, c) in std::iter::once(c).chain(alternatives.iter()).enumerate() {
                let num = |k: &str| c.get(k).and_then(Value::as_f64).unwrap_or(f64::NAN);
                let at_bound: Vec<String> =
                    c.get("at_bound").and_then(|a| serde_json::from_value(a.clone()).ok()).unwrap_or_default();
                let unresolved = c.get("unresolved").and_then(Value::as_str).map(str::to_string);
                let laws: Vec<String> = c
                    .get("params")
                    .and_then(|p| p.get("laws"))
                    .and_then(|l| serde_json::from_value(l.clone()).ok())
                    .unwrap_or_default();
                let m = CandidateScore {
                    name: if k == 0 { cs.to_string() } else { alternative_name(cause, &laws) },
                    cause,
                    converged: c.get("converged").and_then(Value::as_bool).unwrap_or(true),
                    extension: c.get("extension").and_then(Value::as_str).unwrap_or_default().to_string(),
                    delta_bic: num("delta_bic"),
                    delta_aic: num("delta_aic"),
                    excluded: excluded(&at_bound, unresolved.as_ref()),
                };
                match c.get("params").filter(|p| !p.is_null()) {
                    Some(p) if m.excluded.is_none() && m.delta_bic.is_finite() => {
                        let p = params(p, &format!("candidate {}", m.name))?;
                        // the variant (the other law or the mixture) whose laws the parameters name
                        let opts = cause_variants(cause, &base_opts, &base_law)
                            .into_iter()
                            .map(|(_, o)| o)
                            .find(|o| o.laws.iter().map(|l| l.name()).eq(p.laws.iter().cloned()));
                        match opts {
                            Some(o) => todo.push((candidates.len(), p, o)),
                            None => notes
                                .push(format!("{cs} left out: its laws {} are none of its variants", p.laws.join("+"))),
                        }
                    }
                    None if m.excluded.is_none() && m.delta_bic.is_finite() => notes
                        .push(format!("{cs} left out: the JSON holds no parameters for it (written by an older rsf?)")),
                    _ => {}
                }
                candidates.push(RebuiltModel { score: m, fit: None });
            }
        }
        let fits = par_map(&todo, dopts.threads, |(_, p, o)| refit(&clean, &csegs, o, p).map(|f| (f, o.clone())));
        for ((i, _, _), r) in todo.iter().zip(fits) {
            match r {
                Ok(f) => candidates[*i].fit = Some(f),
                Err(e) => notes.push(format!("{} left out: its refit failed: {e}", candidates[*i].score.name)),
            }
        }
        Ok(Rebuilt { cause, adequacy, loading, baseline, baseline_options: base_opts, candidates, notes })
    }

    /// Its basis for [`super::design_basis`].
    pub fn basis(&self) -> Basis<'_> {
        Basis {
            cause: self.cause,
            loading: self.loading,
            baseline: &self.baseline,
            baseline_options: &self.baseline_options,
            adequacy: self.adequacy,
            candidates: self
                .candidates
                .iter()
                .map(|c| BasisModel { score: c.score.clone(), fit: c.fit.as_ref().map(|(f, o)| (f, o)) })
                .collect(),
        }
    }
}
