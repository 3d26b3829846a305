//! A law written in a text file: its rate as an expression, its parameters with their specs.
//! Loaded at run time (`--law-file`, a protocol's `law_files`, a manifest, Python), evaluated
//! with dual numbers so that implicit solvers, fits and the conformance kit get exact
//! derivatives as they do from a law written in Rust.
//!
//! ```toml
//! # power-law aging: dθ/dt = 1 − Ω^n (n = 1 is the Aging law, n = 2 is PRZ's shape)
//! name = "power-aging"
//! words = "power-law aging"
//! theta_rate = "1 - omega^n"
//!
//! [[parameter]]
//! name = "n"
//! range = [0.2, 5.0]
//! start = 1.0
//! ```
//!
//! The rate is either `theta_rate` (dθ/dt, s/s) or `ln_theta_rate` (d ln θ/dt, 1/s). It may
//! read [`VARIABLES`] and the law's own parameters. A parameter has `name`, `range = [lo,
//! hi]`, `start`, and optionally `unit` and `log = true` (fitted as a logarithm; needs
//! lo > 0). `theta_scale` (default 1) is the `s` of the friction term `b ln(V0 θ/(s Dc))`.

use crate::expr::Expr;
use crate::registry::{self, LawEntry, LawParameter, Origin, Start};
use rsf_core::{LnArgs, Real, StateArgs, StateLaw};
use serde::Deserialize;
use std::path::Path;
use std::sync::Arc;

/// The names a law's expression may read besides its own parameters, in slot order:
/// V (µm/s), θ (s), Dc (µm), b, (dτ/dt)/σ (1/s), σ (MPa), dσ/dt (MPa/s), Ω = Vθ/Dc.
pub const VARIABLES: [&str; 8] = ["v", "theta", "dc", "b", "tau_rate", "sigma", "sigma_rate", "omega"];

/// Most parameters a text law may have (its slots live on the stack).
pub const MAX_PARAMETERS: usize = 8;

const SLOTS: usize = VARIABLES.len() + MAX_PARAMETERS;

/// Which rate the expression gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// dθ/dt.
    ThetaRate,
    /// d ln θ/dt.
    LnThetaRate,
}

#[derive(Debug)]
struct Definition {
    name: String,
    words: String,
    form: Form,
    expr: Expr,
    parameters: Vec<LawParameter>,
    theta_scale: f64,
}

/// A law read from a text file, with its parameter values.
#[derive(Clone, Debug)]
pub struct TextLaw {
    def: Arc<Definition>,
    values: [f64; MAX_PARAMETERS],
}

impl TextLaw {
    fn slots<R: Real>(&self, s: &StateArgs<R>) -> [R; SLOTS] {
        let mut x = [R::zero(); SLOTS];
        x[0] = s.v;
        x[1] = s.theta;
        x[2] = s.dc;
        x[3] = s.b;
        x[4] = s.stress_rate;
        x[5] = s.normal_stress;
        x[6] = s.normal_stress_rate;
        x[7] = s.v * s.theta / s.dc;
        for (i, v) in self.values.iter().enumerate().take(self.def.parameters.len()) {
            x[VARIABLES.len() + i] = R::from(*v);
        }
        x
    }
    /// The law's own parameter values, in the order of its file.
    pub fn values(&self) -> &[f64] {
        &self.values[..self.def.parameters.len()]
    }
}

impl StateLaw for TextLaw {
    fn theta_rate<R: Real>(&self, s: &StateArgs<R>) -> R {
        let r = self.def.expr.eval(&self.slots(s));
        match self.def.form {
            Form::ThetaRate => r,
            Form::LnThetaRate => r * s.theta,
        }
    }
    fn ln_theta_rate(&self, s: &LnArgs) -> f64 {
        let p = s.state_args();
        let r = self.def.expr.eval(&self.slots(&p));
        match self.def.form {
            Form::ThetaRate => r / p.theta,
            Form::LnThetaRate => r,
        }
    }
    fn name(&self) -> String {
        self.def.name.clone()
    }
    fn parameters(&self) -> Vec<(&'static str, f64)> {
        self.def.parameters.iter().zip(self.values).map(|(p, v)| (p.name, v)).collect()
    }
    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), String> {
        match self.def.parameters.iter().position(|p| p.name == name) {
            Some(i) => {
                self.values[i] = value;
                Ok(())
            }
            None => Err(format!("law `{}` has no parameter `{name}`", self.def.name)),
        }
    }
    fn validate(&self) -> Result<(), String> {
        self.def.parameters.iter().zip(self.values).try_for_each(|(p, v)| p.check(v))
    }
    fn theta_scale(&self) -> f64 {
        self.def.theta_scale
    }
    /// Exact: the expression evaluated with a dual number in the parameter's slot.
    fn parameter_derivative(&self, name: &str, s: &StateArgs<f64>) -> Option<f64> {
        let i = self.def.parameters.iter().position(|p| p.name == name)?;
        let d = |x: f64| num_dual::Dual64::from_re(x);
        let args = StateArgs {
            v: d(s.v),
            theta: d(s.theta),
            dc: d(s.dc),
            b: d(s.b),
            stress_rate: d(s.stress_rate),
            normal_stress: d(s.normal_stress),
            normal_stress_rate: d(s.normal_stress_rate),
        };
        let mut slots = self.slots(&args);
        slots[VARIABLES.len() + i] = slots[VARIABLES.len() + i].derivative();
        let r = self.def.expr.eval(&slots);
        Some(match self.def.form {
            Form::ThetaRate => r.eps,
            Form::LnThetaRate => r.eps * s.theta,
        })
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLaw {
    name: toml::Spanned<String>,
    words: Option<String>,
    theta_rate: Option<toml::Spanned<String>>,
    ln_theta_rate: Option<toml::Spanned<String>>,
    theta_scale: Option<f64>,
    #[serde(default)]
    parameter: Vec<toml::Spanned<RawParameter>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawParameter {
    name: String,
    #[serde(default)]
    unit: String,
    range: [f64; 2],
    #[serde(default)]
    log: bool,
    start: f64,
}

/// 1-based line and column (in characters) of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// Reads a law from TOML text; `origin` names the file in errors (`FILE:LINE:COLUMN: …`).
pub fn parse(text: &str, origin: &str) -> Result<LawEntry, String> {
    let def = Arc::new(definition(text, origin)?);
    let (name, words, parameters) = (def.name.clone(), def.words.clone(), def.parameters.clone());
    let entry = LawEntry::new(&name, &words, parameters, move |v: &[f64]| {
        let mut values = [0.0; MAX_PARAMETERS];
        values[..v.len()].copy_from_slice(v);
        Ok(Arc::new(TextLaw { def: def.clone(), values }))
    })
    .with_source(text);
    // judged as the registry judges it, whether or not it is registered (`rsf check-law`)
    registry::check_entry(&entry).map_err(|m| format!("{origin}: {m}"))?;
    entry.with_starting_values().map_err(|m| format!("{origin}: {m}"))?;
    Ok(entry)
}

fn definition(text: &str, origin: &str) -> Result<Definition, String> {
    let at = |offset: usize, m: &str| {
        let (l, c) = line_column(text, offset);
        format!("{origin}:{l}:{c}: {m}")
    };
    let raw: RawLaw = toml::from_str(text).map_err(|e| match e.span() {
        Some(sp) => at(sp.start, e.message()),
        None => format!("{origin}: {}", e.message()),
    })?;
    let name = raw.name.get_ref().clone();
    registry::check_name(&name).map_err(|m| at(raw.name.span().start, &m))?;
    let mut parameters = Vec::new();
    for p in &raw.parameter {
        let (r, span) = (p.get_ref(), p.span());
        if parameters.len() == MAX_PARAMETERS {
            return Err(at(span.start, &format!("a text law has at most {MAX_PARAMETERS} parameters")));
        }
        if VARIABLES.contains(&r.name.as_str()) {
            return Err(at(
                span.start,
                &format!("parameter name `{}` is one of the law's variables ({})", r.name, VARIABLES.join(", ")),
            ));
        }
        registry::check_parameter_name(&r.name).map_err(|m| at(span.start, &m))?;
        parameters.push(LawParameter {
            name: registry::intern(&r.name),
            unit: registry::intern(&r.unit),
            lo: r.range[0],
            hi: r.range[1],
            log: r.log,
            start: Start::Value(r.start),
        });
    }
    let (form, expr_text) = match (&raw.theta_rate, &raw.ln_theta_rate) {
        (Some(e), None) => (Form::ThetaRate, e),
        (None, Some(e)) => (Form::LnThetaRate, e),
        (Some(_), Some(e)) => return Err(at(e.span().start, "give either theta_rate or ln_theta_rate, not both")),
        (None, None) => {
            return Err(format!("{origin}: the law needs `theta_rate` (dθ/dt) or `ln_theta_rate` (d ln θ/dt)"));
        }
    };
    let names: Vec<&str> = VARIABLES.iter().copied().chain(parameters.iter().map(|p| p.name)).collect();
    let expr = Expr::parse(expr_text.get_ref(), &names).map_err(|e| {
        // the column inside the string, after its opening quote
        at(expr_text.span().start + 1 + char_offset(expr_text.get_ref(), e.column), &e.message)
    })?;
    let theta_scale = raw.theta_scale.unwrap_or(1.0);
    if !(theta_scale > 0.0 && theta_scale.is_finite()) {
        return Err(format!("{origin}: theta_scale = {theta_scale} must be positive"));
    }
    let words = raw.words.unwrap_or_else(|| name.clone());
    Ok(Definition { name, words, form, expr, parameters, theta_scale })
}

/// The concrete [`TextLaw`] of an entry a law file made, at its parameters' starts: what the
/// conformance kit (generic over the law type) checks. `None` for an entry from elsewhere.
pub fn law_at_starts(entry: &LawEntry) -> Option<TextLaw> {
    let def = Arc::new(definition(entry.source()?, "").ok()?);
    let mut values = [0.0; MAX_PARAMETERS];
    for (v, p) in values.iter_mut().zip(&def.parameters) {
        *v = p.start_value(None);
    }
    Some(TextLaw { def, values })
}

impl TextLaw {
    /// The same law with parameter `name` set to `value` (range-checked).
    pub fn with_value(mut self, name: &str, value: f64) -> Result<Self, String> {
        self.set_parameter(name, value)?;
        self.validate()?;
        Ok(self)
    }
}

/// Byte offset of the 1-based character column `col` of `s`.
fn char_offset(s: &str, col: usize) -> usize {
    s.char_indices().nth(col.saturating_sub(1)).map_or(s.len(), |(i, _)| i)
}

/// Reads a law file; errors name the file, line and column.
pub fn load(path: &Path) -> Result<LawEntry, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(parse(&text, &path.display().to_string())?.with_origin(Origin::TextFile(path.to_path_buf())))
}

/// Reads a law file and registers its law; returns the law's name.
pub fn register_file(path: &Path) -> Result<String, String> {
    let entry = load(path)?;
    let name = entry.name().to_string();
    registry::register(entry).map_err(|m| format!("{}: {m}", path.display()))?;
    Ok(name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Aging, Prz};

    const POWER: &str = "name = \"power-aging-t\"\ntheta_rate = \"1 - omega^n\"\n\n[[parameter]]\nname = \"n\"\nrange = [0.2, 5.0]\nstart = 1.0\n";

    #[test]
    fn a_text_law_equals_the_built_in_one_it_writes() {
        let e = parse(POWER, "p.toml").unwrap();
        let at1 = e.build(|_| Some(1.0)).unwrap();
        let prz =
            parse("name = \"prz-t\"\ntheta_scale = 2\nln_theta_rate = \"1/theta - (v/(2*dc))^2*theta\"\n", "q.toml")
                .unwrap()
                .with_starting_values()
                .unwrap();
        for &(v, th, dc) in &[(1.0, 3.0, 10.0), (1e-3, 5e3, 7.0), (40.0, 0.02, 2.0)] {
            let s = StateArgs { stress_rate: 0.01, ..StateArgs::new(v, th, dc, 0.01) };
            let (a, b) = (at1.jet(&s), StateLaw::jet(&Aging, &s));
            for (x, y) in [(a.rate, b.rate), (a.d_v, b.d_v), (a.d_theta, b.d_theta), (a.d_dc, b.d_dc)] {
                assert!((x - y).abs() <= 1e-13 * y.abs().max(1e-12), "{x} vs {y}");
            }
            let (c, d) = (prz.jet(&s), StateLaw::jet(&Prz, &s));
            assert!((c.rate - d.rate).abs() <= 1e-12 * d.rate.abs().max(1.0));
            assert!((c.d_theta - d.d_theta).abs() <= 1e-12 * d.d_theta.abs().max(1e-9));
            let ln = LnArgs::new(v.ln(), th.ln(), dc, 0.01);
            assert!((prz.ln_rate(&ln) - StateLaw::ln_theta_rate(&Prz, &ln)).abs() < 1e-12 * (v / dc + 1.0 / th));
        }
        assert_eq!(prz.theta_scale(), 2.0);
        assert!((prz.steady_state_theta(2.0, 5.0).unwrap() - 5.0).abs() < 1e-13);
    }

    #[test]
    fn errors_name_line_and_column() {
        let bad = POWER.replace("omega^n", "omega^m");
        let e = parse(&bad, "p.toml").unwrap_err();
        assert!(e.starts_with("p.toml:2:"), "{e}");
        assert!(e.contains("unknown name `m`"), "{e}");
        // column of `m` in `theta_rate = "1 - omega^m"`: 14 + 11 = 25
        assert!(e.starts_with("p.toml:2:25:"), "{e}");
        let e = parse(&POWER.replace("range = [0.2, 5.0]", "range = [0.2, 5.0]\nsize = 3"), "p.toml").unwrap_err();
        assert!(e.starts_with("p.toml:") && e.contains("size"), "{e}");
        let e = parse(&POWER.replace("start = 1.0", "start = 9.0"), "p.toml").unwrap_err();
        assert!(e.contains("outside its range"), "{e}");
        let e = parse("name = \"x\"\n", "p.toml").unwrap_err();
        assert!(e.contains("theta_rate"), "{e}");
        let e = parse(&POWER.replace("name = \"n\"", "name = \"omega\""), "p.toml").unwrap_err();
        assert!(e.contains("parameter name `omega`"), "{e}");
    }

    #[test]
    fn parameters_round_trip_and_validate() {
        let e = parse(POWER, "p.toml").unwrap();
        let law = e.build(|_| Some(1.5)).unwrap();
        assert_eq!(law.parameters(), vec![("n", 1.5)]);
        let l2 = law.with_parameter("n", 2.5).unwrap();
        assert_eq!(l2.parameters(), vec![("n", 2.5)]);
        assert!(law.with_parameter("q", 1.0).is_err());
        assert!(law.with_parameter("n", 9.0).unwrap().validate().is_err());
        // the exact parameter derivative: ∂(1 − Ω^n)/∂n = −Ω^n ln Ω
        let s = StateArgs::new(2.0, 3.0, 1.5, 0.01);
        let omega: f64 = 4.0;
        let d = law.parameter_derivative("n", &s).unwrap();
        assert!((d + omega.powf(1.5) * omega.ln()).abs() < 1e-13, "{d}");
        assert_eq!(law.parameter_derivative("q", &s), None);
    }
}
