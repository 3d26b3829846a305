//! The parameter map: the full-vector layout, which entries are free (and fitted as
//! logarithms), constraints between them, and physical bounds (the names and their ranges are
//! `param_name.rs`).

use super::AlphaFit;
use super::param_name::law_spec;
use super::param_name::{ParamName, ParamSpec};
use super::{FitError, FitOptions, Prepared, initial_guess};
use rsf_core::{Model, N_GLOBAL, PER_STATE, StateVariable, n_params, param_index, state_offset};

/// The least share of a that the direct effect's local slope a + a₁ ln(V/V0) may fall to over
/// [`FitOptions::a_slope_range`]: a quadratic direct effect is a local description of a's
/// change with rate, and one that halves a within the slip rates of a record is already far
/// beyond the ±35 % lab measurements report; past it the solve slows as the slope nears zero.
pub const DIRECT_SLOPE_FLOOR: f64 = 0.5;

/// Starting value of a fitted Linker–Dieterich α: inside (0, 5), mid-range of published
/// values (0.1–0.6).
pub const ALPHA_START: f64 = 0.2;

/// A linear constraint as written: `X=c`, `X-Y=c` or `X+Y=c`, parsed once where it is given
/// (`--fix`, Python's `fix`, the diagnosis's own ties).
#[derive(Clone, Debug, PartialEq)]
pub struct Constraint {
    /// The constraint as written (shown in results).
    pub text: String,
    /// The first name.
    pub x: String,
    /// The second name and the sign it enters with (`-` or `+`), when there is one.
    pub y: Option<(char, String)>,
    /// The constant.
    pub value: f64,
}

impl Constraint {
    /// Parses `c`; the error names what is wrong.
    pub fn parse(c: &str) -> Result<Self, FitError> {
        c.parse().map_err(FitError::Setup)
    }
    /// `name = value`.
    pub fn fixed(name: &str, value: f64) -> Self {
        Self { text: format!("{name}={value:e}"), x: name.into(), y: None, value }
    }
    /// `x − y = value`.
    pub fn difference(x: &str, y: &str, value: f64) -> Self {
        Self { text: format!("{x}-{y}={value}"), x: x.into(), y: Some(('-', y.into())), value }
    }
    /// The highest state variable (1-based) the constraint names, 0 for none.
    pub fn max_state(&self) -> usize {
        std::iter::once(&self.x)
            .chain(self.y.as_ref().map(|y| &y.1))
            .filter_map(|n| ParamName::parse(n).and_then(|p| p.state()))
            .max()
            .unwrap_or(0)
    }
}

impl std::str::FromStr for Constraint {
    type Err = String;
    fn from_str(c: &str) -> Result<Self, String> {
        let (lhs, rhs) =
            c.split_once('=').ok_or_else(|| format!("constraint `{c}`: expected NAME=VALUE or NAME-NAME=VALUE"))?;
        let value: f64 = rhs.trim().parse().map_err(|_| format!("constraint `{c}`: `{rhs}` is not a number"))?;
        let lhs = lhs.trim();
        let text = c.to_string();
        Ok(match lhs.char_indices().skip(1).find(|(_, ch)| *ch == '-' || *ch == '+') {
            None => Self { text, x: lhs.to_string(), y: None, value },
            Some((pos, op)) => {
                Self { text, x: lhs[..pos].trim().to_string(), y: Some((op, lhs[pos + 1..].trim().to_string())), value }
            }
        })
    }
}

impl std::fmt::Display for Constraint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

/// How a full-vector entry depends on θ.
#[derive(Clone, Debug)]
pub(super) enum Slot {
    Fixed,
    Free {
        k: usize,
        log: bool,
    },
    /// value = sign · (full[src] − c)
    Derived {
        src: usize,
        sign: f64,
        c: f64,
    },
}

/// The parameter map of a fit.
#[derive(Clone, Debug)]
pub struct ParamMap {
    pub(super) n_states: usize,
    /// Entries of the model's parameter layout ([`rsf_core::n_params_of`]): the fixed block
    /// and the laws' further own parameters; the segments' friction offsets follow.
    pub(super) np: usize,
    pub(super) names: Vec<String>,
    pub(super) slots: Vec<Slot>,
    pub(super) base: Vec<f64>,
    pub(super) free: Vec<usize>,
    pub(super) constraints: Vec<String>,
    /// Scale and range of each full-vector entry.
    pub(super) specs: Vec<ParamSpec>,
    /// The largest |ln(V/V0)| of [`FitOptions::a_slope_range`], when a₁ is fitted there.
    pub(super) a_slope_reach: Option<f64>,
}

fn full_names(opts: &FitOptions, n_off: usize) -> Vec<String> {
    let mut v = vec!["mu0".to_string(), "a".into(), "k".into(), "g".into(), "a_slope".into()];
    for (i, l) in opts.laws.iter().enumerate() {
        let q = l.parameters().first().map(|p| p.0).unwrap_or("q");
        v.extend([format!("b{}", i + 1), format!("dc{}", i + 1), format!("{q}{}", i + 1), format!("alpha{}", i + 1)]);
    }
    v.extend(extra_parameters(opts).iter().map(|(i, name)| format!("{name}{}", i + 1)));
    v.extend((0..n_off).map(|s| format!("mu0_seg{}", s + 2)));
    v
}

/// The laws' own parameters past each law's first, as laid out after the fixed block
/// ([`rsf_core::extra_law_parameters`]): (0-based state, name).
fn extra_parameters(opts: &FitOptions) -> Vec<(usize, &'static str)> {
    opts.laws
        .iter()
        .enumerate()
        .flat_map(|(i, l)| l.parameters().into_iter().skip(1).map(move |(name, _)| (i, name)))
        .collect()
}

/// Where a law's own parameter starts: where the law was built (`with_starting_values`: the
/// spec's start), except a velocity scale whose spec starts it at the record's slowest load
/// point `vmin` (µm/s).
fn own_start(law: &dyn rsf_core::DynStateLaw, name: &str, value: f64, vmin: f64) -> f64 {
    match law_spec(law, name).map(|p| p.start) {
        Some(rsf_laws::Start::SlowestLoadPointVelocity) if vmin.is_finite() => vmin,
        Some(rsf_laws::Start::SlowestLoadPointVelocity | rsf_laws::Start::Value(_)) | None => value,
    }
}

impl ParamMap {
    /// Full parameter vector at θ.
    pub fn full(&self, theta: &[f64]) -> Vec<f64> {
        let mut f = self.base.clone();
        for (i, s) in self.slots.iter().enumerate() {
            if let Slot::Free { k, log } = s {
                f[i] = if *log { theta[*k].exp() } else { theta[*k] };
            }
        }
        for (i, s) in self.slots.iter().enumerate() {
            if let Slot::Derived { src, sign, c } = s {
                f[i] = sign * (f[*src] - c);
            }
        }
        f
    }
    /// ∂full/∂θ as a dense (full × m) row-major matrix.
    pub(super) fn jac(&self, theta: &[f64]) -> Vec<f64> {
        let m = self.free.len();
        let f = self.full(theta);
        let mut d = vec![0.0; self.slots.len() * m];
        for (i, s) in self.slots.iter().enumerate() {
            if let Slot::Free { k, log } = s {
                d[i * m + k] = if *log { f[i] } else { 1.0 };
            }
        }
        for (i, s) in self.slots.iter().enumerate() {
            if let Slot::Derived { src, sign, .. } = s {
                for k in 0..m {
                    d[i * m + k] = sign * d[src * m + k];
                }
            }
        }
        d
    }
    /// θ for a full vector (free entries only).
    pub(super) fn theta_of(&self, full: &[f64]) -> Vec<f64> {
        let mut t = vec![0.0; self.free.len()];
        for (i, s) in self.slots.iter().enumerate() {
            if let Slot::Free { k, log } = s {
                t[*k] = if *log { full[i].ln() } else { full[i] };
            }
        }
        t
    }
    /// Free-parameter names in θ order.
    pub fn free_names(&self) -> Vec<String> {
        self.free.iter().map(|&i| self.names[i].clone()).collect()
    }
    /// Whether θ lies inside every parameter's physical range.
    pub fn in_bounds(&self, theta: &[f64]) -> bool {
        within_bounds(self, &self.full(theta)).is_ok()
    }
    /// Each θ entry's physical range on its own scale (logarithms for log-fitted entries), for
    /// the search's box (`lm::minimize_in`); unbounded where the parameter has no spec.
    pub(super) fn theta_bounds(&self) -> Vec<(f64, f64)> {
        self.free
            .iter()
            .enumerate()
            .map(|(k, &i)| {
                if i >= self.np {
                    return (f64::NEG_INFINITY, f64::INFINITY);
                }
                let ParamSpec { lo, hi, .. } = self.specs[i];
                if self.is_log(k) { (lo.max(0.0).ln(), hi.ln()) } else { (lo, hi) }
            })
            .collect()
    }
    /// Whether θ entry k is a logarithm.
    pub fn is_log(&self, k: usize) -> bool {
        matches!(self.slots[self.free[k]], Slot::Free { log: true, .. })
    }
    /// Builds the model for a full vector.
    pub(super) fn model(&self, opts: &FitOptions, full: &[f64], v0: f64) -> Result<Model, String> {
        let mut m = Model::new(0.0, v0, 1.0, 1.0);
        m.states = opts.laws.iter().map(|l| StateVariable::from_shared(l.clone(), 0.0, 1.0)).collect();
        m.with_parameter_vector(&full[..self.np])
    }
    /// Every law's own parameters by name (`vc1`, `n1`, `w2`) at the full vector `full`.
    pub(super) fn law_parameter_values(
        &self,
        opts: &FitOptions,
        full: &[f64],
    ) -> std::collections::BTreeMap<String, f64> {
        let mut out = std::collections::BTreeMap::new();
        for (i, l) in opts.laws.iter().enumerate() {
            if let Some((nm, _)) = l.parameters().first() {
                out.insert(format!("{nm}{}", i + 1), full[state_offset(i) + 2]);
            }
        }
        let np0 = n_params(self.n_states);
        for (k, (i, name)) in extra_parameters(opts).into_iter().enumerate() {
            out.insert(format!("{name}{}", i + 1), full[np0 + k]);
        }
        out
    }
}

/// Builds the parameter map: layout, defaults, free set, constraints.
pub fn parameter_map(p: &Prepared, opts: &FitOptions) -> Result<ParamMap, FitError> {
    let n = opts.laws.len();
    if n == 0 {
        return Err(FitError::Setup("at least one state variable is needed".into()));
    }
    let n_off = if opts.mu0_per_segment { p.segments.len().saturating_sub(1) } else { 0 };
    let extra = extra_parameters(opts);
    let np = n_params(n) + extra.len();
    let names = full_names(opts, n_off);
    let (mu0, a, b, dc) = initial_guess(p);
    let mut base = vec![0.0; np + n_off];
    base[0] = mu0;
    base[1] = a;
    base[2] = opts.stiffness;
    let moving: Vec<f64> = p.segments.iter().filter(|s| s.v > 0.0).map(|s| s.v).collect();
    let vmin = moving.iter().copied().fold(f64::INFINITY, f64::min);
    for (i, law) in opts.laws.iter().enumerate() {
        let off = state_offset(i);
        // split b between states; later states slower (Dc × 10 per state)
        base[off] = b * if n == 1 { 1.0 } else { 0.6 * 0.4f64.powi(i as i32) / 0.6f64.max(1e-9) * 0.6 };
        base[off + 1] = dc * 10f64.powi(i as i32);
        // where the law was built (`with_starting_values`: the spec's start), except a
        // velocity scale whose spec starts it at the record's slowest load point
        base[off + 2] = match law.parameters().first() {
            Some((name, v)) => own_start(law.as_ref(), name, *v, vmin),
            None => 0.0,
        };
        // α starts inside its domain when fitted: at its bound α = 0 every LM step that
        // lowers it is rejected, and the other parameters would stall with it
        base[off + 3] = if opts.alpha == AlphaFit::Fixed { 0.0 } else { ALPHA_START };
    }
    for (k, &(i, name)) in extra.iter().enumerate() {
        let law = &opts.laws[i];
        let value = law.parameters().iter().find(|p| p.0 == name).map_or(0.0, |p| p.1);
        base[n_params(n) + k] = own_start(law.as_ref(), name, value, vmin);
    }
    let mut slots: Vec<Slot> = vec![Slot::Fixed; np + n_off];
    let specs: Vec<ParamSpec> = names
        .iter()
        .map(|n| {
            ParamName::parse(n)
                .map(|p| p.spec(&opts.laws))
                .ok_or_else(|| FitError::Setup(format!("internal: parameter name `{n}` does not parse")))
        })
        .collect::<Result<_, _>>()?;
    let log_param = |i: usize| i < np && specs[i].log;
    let mut free_idx = vec![0usize, 1];
    if opts.fit_stiffness {
        free_idx.push(2);
    }
    if opts.fit_slip_trend {
        free_idx.push(3);
    }
    if opts.fit_a_slope {
        free_idx.push(4);
    }
    for (i, law) in opts.laws.iter().enumerate() {
        let off = state_offset(i);
        free_idx.extend([off, off + 1]);
        if !law.parameters().is_empty() {
            free_idx.push(off + 2);
        }
        if opts.alpha == AlphaFit::PerState || (opts.alpha == AlphaFit::Shared && i == 0) {
            free_idx.push(off + 3);
        }
        if opts.alpha == AlphaFit::Shared && i > 0 {
            // one α for all states: α_i follows α_1
            slots[off + 3] = Slot::Derived { src: state_offset(0) + 3, sign: 1.0, c: 0.0 };
        }
    }
    // every further own parameter of a law is fitted, as the first is
    free_idx.extend(n_params(n)..np);
    free_idx.extend(np..np + n_off);
    // initial overrides
    let tmp_model = {
        let mut m = Model::new(0.0, 1.0, 1.0, 1.0);
        for l in &opts.laws {
            m.states.push(StateVariable::from_shared(l.clone(), 0.0, 1.0));
        }
        m
    };
    let known: Vec<&String> = names
        .iter()
        .enumerate()
        .filter(|(i, _)| {
            !(*i >= N_GLOBAL
                && *i < np
                && (i - N_GLOBAL) % PER_STATE == 2
                && opts.laws[(i - N_GLOBAL) / PER_STATE].parameters().is_empty())
        })
        .map(|(_, n)| n)
        .collect();
    let index = |name: &str| -> Result<usize, FitError> {
        param_index(&tmp_model, name).or_else(|| names.iter().position(|x| x == name && known.contains(&x))).ok_or_else(
            || {
                FitError::Setup(format!(
                    "unknown parameter `{name}` (known: {})",
                    known.iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", ")
                ))
            },
        )
    };
    for (name, v) in &opts.initial {
        base[index(&name.text())?] = *v;
    }
    // constraints
    let mut constraints = vec![];
    for parsed in &opts.fix {
        let c = &parsed.text;
        match &parsed.y {
            None => {
                let i = index(&parsed.x)?;
                base[i] = parsed.value;
                free_idx.retain(|&j| j != i);
                slots[i] = Slot::Fixed;
            }
            Some((op, y)) => {
                let (ix, iy) = (index(&parsed.x)?, index(y)?);
                // X − Y = c  →  Y = X − c ;  X + Y = c  →  Y = −(X − c)
                let sign = if *op == '-' { 1.0 } else { -1.0 };
                free_idx.retain(|&j| j != iy);
                slots[iy] = Slot::Derived { src: ix, sign, c: parsed.value };
                if !free_idx.contains(&ix) && !matches!(slots[ix], Slot::Fixed) {
                    return Err(FitError::Setup(format!("constraint `{c}`: `{}` is itself constrained", parsed.x)));
                }
            }
        }
        constraints.push(c.clone());
    }
    for (k, &i) in free_idx.iter().enumerate() {
        let log = log_param(i);
        if log && !(base[i] > 0.0) {
            return Err(FitError::Setup(format!("`{}` must start positive (got {})", names[i], base[i])));
        }
        slots[i] = Slot::Free { k, log };
    }
    // derived values follow their sources at the start
    let a_slope_reach = opts
        .a_slope_range
        .filter(|_| opts.fit_a_slope)
        .map(|(lo, hi)| (lo / p.v_init).ln().abs().max((hi / p.v_init).ln().abs()))
        .filter(|r| r.is_finite());
    let map = ParamMap { n_states: n, np, names, slots, base, free: free_idx, constraints, specs, a_slope_reach };
    let theta = map.theta_of(&map.base);
    let base = map.full(&theta);
    Ok(ParamMap { base, ..map })
}

/// Physical bounds of each full-vector entry: outside them a trial point is rejected (so LM
/// cannot wander into regions where the model means nothing and integrates slowly).
pub(super) fn within_bounds(map: &ParamMap, full: &[f64]) -> Result<(), String> {
    let np = map.np;
    for (i, &v) in full.iter().enumerate().take(np) {
        let ParamSpec { lo, hi, .. } = map.specs[i];
        if !(v >= lo && v <= hi) {
            return Err(format!("`{}` = {v:e} is outside its physical range [{lo:e}, {hi:e}]", map.names[i]));
        }
    }
    if let Some(reach) = map.a_slope_reach {
        let (a, a1) = (full[1], full[4]);
        if a1.abs() * reach > (1.0 - DIRECT_SLOPE_FLOOR) * a {
            return Err(format!(
                "`a_slope` = {a1:e} takes the direct effect's slope below {DIRECT_SLOPE_FLOOR} a = {:e} within the \
                 slip rates given (|ln(V/V0)| up to {reach:.2})",
                DIRECT_SLOPE_FLOOR * a
            ));
        }
    }
    Ok(())
}
