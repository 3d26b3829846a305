//! Fitting a rate-and-state model to a measured record.
//!
//! Parameters live in the layout of [`rsf_core::n_params`] (`mu0, a, k, b_i, dc_i, q_i`) plus,
//! optionally, one friction offset per segment after the first (`mu0` per segment). Positive
//! quantities (a, k, Dc, Vc) are fitted as logarithms, so they cannot leave their domain; `b`,
//! `mu0`, offsets and Nagata's `c` are fitted directly. Linear constraints `X=c`, `X-Y=c` and
//! `X+Y=c` remove Y (or X) from the free set and express it through the other.

use crate::data::Record;
use crate::lm::{self, Eval};
use crate::segment::{Segment, SegmentKind};
use crate::sens::solve_with_sensitivities;
use rsf_core::{DynStateLaw, LoadRecord, Loading, Model, N_GLOBAL, StateVariable, n_params, param_index, state_offset};
use rsf_solvers::{OutputTimes, Problem, SolveError};
use serde::Serialize;
use std::collections::BTreeMap;
use std::sync::Arc;

/// Step budget per piece for forward solves inside fits: a trial point that needs more (a
/// very stiff corner of parameter space) fails quickly and LM steps back.
pub const FIT_MAX_STEPS: u64 = 200_000;

/// What drives the forward model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LoadingMode {
    /// The measured load-point history (piecewise linear between samples).
    Record,
    /// The idealised protocol detected by segmentation (constant velocities).
    Protocol,
}

/// How samples are weighted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Weighting {
    /// Each segment counts equally (weight ∝ 1/N_samples of the segment).
    EqualSegments,
    /// Every sample counts equally.
    Uniform,
}

/// Fit settings.
#[derive(Clone, Debug)]
pub struct FitOptions {
    /// One law per state variable.
    pub laws: Vec<Arc<dyn DynStateLaw>>,
    /// Stiffness k, 1/µm (initial value when fitted).
    pub stiffness: f64,
    /// Fit k as well.
    pub fit_stiffness: bool,
    /// Fit a slip trend g (friction per µm of slip) as well.
    pub fit_slip_trend: bool,
    /// Constraints, e.g. `a-b=-0.003`, `dc=10`.
    pub fix: Vec<String>,
    /// A friction offset per segment.
    pub mu0_per_segment: bool,
    /// Use only the first `window_um` µm of load-point travel of each segment (and the last of
    /// the first segment); holds are used whole.
    pub window_um: Option<f64>,
    /// Sample weights.
    pub weighting: Weighting,
    /// What drives the model.
    pub loading: LoadingMode,
    /// Integrator tolerance.
    pub rtol: f64,
    /// LM iteration limit per start.
    pub max_iter: usize,
    /// Number of starting points (1: the data-derived guess only).
    pub starts: usize,
    /// Initial values overriding the data-derived guesses (`name`, value).
    pub initial: Vec<(String, f64)>,
    /// Wall-time budget of the whole fit, s: past it evaluations fail and LM returns its best
    /// point (a fit must never hang).
    pub time_budget: f64,
}

impl FitOptions {
    /// Defaults for `n` states of `law` at stiffness `k`.
    pub fn new(laws: Vec<Arc<dyn DynStateLaw>>, k: f64) -> Self {
        Self {
            laws,
            stiffness: k,
            fit_stiffness: false,
            fit_slip_trend: false,
            fix: vec![],
            mu0_per_segment: false,
            window_um: None,
            weighting: Weighting::EqualSegments,
            loading: LoadingMode::Record,
            rtol: 1e-7,
            max_iter: 100,
            starts: 5,
            initial: vec![],
            time_budget: 30.0,
        }
    }
}

/// A fit error, in words.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// Bad settings.
    #[error("{0}")]
    Setup(String),
    /// The model could not be evaluated at the starting point.
    #[error("the model cannot be evaluated at the starting point: {0}")]
    Start(SolveError),
}

/// A parameter's value with its uncertainty.
#[derive(Clone, Debug, Serialize)]
pub struct Estimate {
    /// Best-fit value.
    pub value: f64,
    /// Standard error (linearised).
    pub stderr: f64,
    /// 95% interval (asymmetric for log-fitted parameters).
    pub ci95: [f64; 2],
}

/// One segment of the fitted record with its misfit.
#[derive(Clone, Debug, Serialize)]
pub struct SegmentRow {
    /// 1-based index.
    pub index: usize,
    /// Kind.
    pub kind: SegmentKind,
    /// Start and end time, s.
    pub t0: f64,
    /// End time, s.
    pub t1: f64,
    /// Load-point velocity, µm/s.
    pub v: f64,
    /// Samples used in the fit.
    pub n: usize,
    /// RMS misfit of the used samples.
    pub rms: f64,
}

/// Fitted model parameters in physical units.
#[derive(Clone, Debug, Serialize)]
pub struct Params {
    /// Steady-state friction at v0.
    pub mu0: f64,
    /// Reference slip rate (= the initial load-point velocity), µm/s.
    pub v0: f64,
    /// Direct effect.
    pub a: f64,
    /// b_i.
    pub b: Vec<f64>,
    /// Dc_i, µm.
    pub dc: Vec<f64>,
    /// Stiffness, 1/µm.
    pub k: f64,
    /// Slip trend g, friction per µm of slip (0 unless fitted or fixed).
    pub g: f64,
    /// Laws, per state.
    pub laws: Vec<String>,
    /// Law-specific parameters by name (e.g. `vc1`).
    pub law_params: BTreeMap<String, f64>,
    /// Per-segment friction offsets (segment 2 onward), when fitted.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub mu0_offsets: Vec<f64>,
}

impl Params {
    /// These parameters as `FitOptions::initial` starting values (`mu0`, `a`, `k`, `g`, `b1`,
    /// `dc1`, …, law parameters such as `vc1`): to restart a related fit from an optimum.
    pub fn as_initial(&self) -> Vec<(String, f64)> {
        let mut v =
            vec![("mu0".to_string(), self.mu0), ("a".into(), self.a), ("k".into(), self.k), ("g".into(), self.g)];
        for (i, (b, dc)) in self.b.iter().zip(&self.dc).enumerate() {
            v.push((format!("b{}", i + 1), *b));
            v.push((format!("dc{}", i + 1), *dc));
        }
        v.extend(self.law_params.iter().map(|(n, x)| (n.clone(), *x)));
        v.extend(self.mu0_offsets.iter().enumerate().map(|(k, x)| (format!("mu0_seg{}", k + 2), *x)));
        v
    }
}

/// The result of a fit.
#[derive(Clone, Debug, Serialize)]
pub struct FitResult {
    /// Parameters.
    pub params: Params,
    /// Free parameters with standard errors and 95% intervals.
    pub ci95: BTreeMap<String, [f64; 2]>,
    /// Standard errors of the free parameters.
    pub stderr: BTreeMap<String, f64>,
    /// Constraints applied.
    pub constraints: Vec<String>,
    /// Free parameters that ended at a physical bound: the data do not constrain them there.
    pub at_bound: Vec<String>,
    /// RMS misfit (unweighted) over the used samples.
    pub rms: f64,
    /// Samples used.
    pub n: usize,
    /// Number of free parameters.
    pub n_free: usize,
    /// Gaussian log-likelihood at the optimum, σ estimated, of the weighted model (noise σ/w_r
    /// at sample r; the usual one for uniform weights).
    pub log_likelihood: f64,
    /// Akaike information criterion (free parameters + σ).
    pub aic: f64,
    /// Bayesian information criterion.
    pub bic: f64,
    /// Segment table.
    pub segments: Vec<SegmentRow>,
    /// LM iterations of the best start.
    pub iterations: usize,
    /// Why LM stopped.
    pub stop_reason: String,
    /// Starts tried.
    pub starts: usize,
    /// Loading used by the forward model.
    pub loading: LoadingMode,
    /// Weighting.
    pub weighting: Weighting,
    /// Times, data, model and residual of the used samples (for plots and diagnosis).
    #[serde(skip)]
    pub curve: Curve,
    /// Free-parameter names in fit order, transformed scale (`ln` for log-fitted).
    #[serde(skip)]
    pub theta: Vec<f64>,
    /// Covariance of θ.
    #[serde(skip)]
    pub cov_theta: Vec<f64>,
}

/// Samples used by a fit with data and model.
#[derive(Clone, Debug, Default)]
pub struct Curve {
    /// Time, s.
    pub time: Vec<f64>,
    /// Load point, µm.
    pub load_point: Vec<f64>,
    /// Measured friction.
    pub data: Vec<f64>,
    /// Model friction.
    pub model: Vec<f64>,
    /// Segment index (0-based) of each sample.
    pub segment: Vec<usize>,
    /// Model slip rate V at each sample, µm/s (empty if the extra forward solve failed).
    pub slip_rate: Vec<f64>,
}

/// How a full-vector entry depends on θ.
#[derive(Clone, Debug)]
enum Slot {
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

/// The data-dependent part of a fit, shared by LM, MCMC and per-segment fits.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// The record, from the first moving segment on.
    pub record: Record,
    /// Its segments (indices into `record`).
    pub segments: Vec<Segment>,
    /// Used sample indices.
    pub used: Vec<usize>,
    /// Their weights (mean square 1).
    pub weights: Vec<f64>,
    /// Their segment indices.
    pub seg_of: Vec<usize>,
    /// Initial slip rate (steady state), µm/s.
    pub v_init: f64,
}

/// The parameter map of a fit.
#[derive(Clone, Debug)]
pub struct ParamMap {
    n_states: usize,
    names: Vec<String>,
    slots: Vec<Slot>,
    base: Vec<f64>,
    free: Vec<usize>,
    constraints: Vec<String>,
}

fn full_names(opts: &FitOptions, n_off: usize) -> Vec<String> {
    let mut v = vec!["mu0".to_string(), "a".into(), "k".into(), "g".into()];
    for (i, l) in opts.laws.iter().enumerate() {
        let q = l.parameters().first().map(|p| p.0).unwrap_or("q");
        v.extend([format!("b{}", i + 1), format!("dc{}", i + 1), format!("{q}{}", i + 1)]);
    }
    v.extend((0..n_off).map(|s| format!("mu0_seg{}", s + 2)));
    v
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
    fn jac(&self, theta: &[f64]) -> Vec<f64> {
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
    fn theta_of(&self, full: &[f64]) -> Vec<f64> {
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
    /// Whether θ entry k is a logarithm.
    pub fn is_log(&self, k: usize) -> bool {
        matches!(self.slots[self.free[k]], Slot::Free { log: true, .. })
    }
    /// Builds the model for a full vector.
    fn model(&self, opts: &FitOptions, full: &[f64], v0: f64) -> Result<Model, String> {
        let mut m = Model::new(0.0, v0, 1.0, 1.0);
        m.states = opts.laws.iter().map(|l| StateVariable::from_shared(l.clone(), 0.0, 1.0)).collect();
        m.with_parameter_vector(&full[..n_params(self.n_states)])
    }
}

/// Selects the samples and weights, and trims the record to its first moving segment.
pub fn prepare(record: &Record, segments: &[Segment], opts: &FitOptions) -> Result<Prepared, FitError> {
    let first = segments
        .iter()
        .position(|s| s.v > 0.0)
        .ok_or_else(|| FitError::Setup("the record has no moving segment".into()))?;
    if first > 0 {
        // the model starts in steady state: start where the load point first moves
    }
    let i_start = segments[first].i0;
    let rec = Record {
        time: record.time[i_start..].to_vec(),
        load_point: record.load_point[i_start..].to_vec(),
        mu: record.mu[i_start..].to_vec(),
        source: record.source.clone(),
    };
    let segs: Vec<Segment> =
        segments[first..].iter().map(|s| Segment { i0: s.i0 - i_start, i1: s.i1 - i_start, ..s.clone() }).collect();
    if segs.len() < 2 {
        return Err(FitError::Setup(
            "the record is one segment of constant load-point velocity: a, b and Dc cannot be told apart \
             without a velocity change (a step or a hold); include data before and after a change"
                .into(),
        ));
    }
    let mut used = Vec::new();
    let mut seg_of = Vec::new();
    for (k, s) in segs.iter().enumerate() {
        for i in s.i0..=s.i1 {
            let keep = match opts.window_um {
                None => true,
                Some(w) if k == 0 => rec.load_point[s.i1] - rec.load_point[i] <= w,
                Some(w) => s.v == 0.0 || (rec.load_point[i] - s.lp0).abs() <= w,
            };
            if keep {
                used.push(i);
                seg_of.push(k);
            }
        }
    }
    if used.len() < 10 {
        return Err(FitError::Setup(format!("only {} samples fall in the fit windows", used.len())));
    }
    let mut count = vec![0usize; segs.len()];
    for &s in &seg_of {
        count[s] += 1;
    }
    let mut weights: Vec<f64> = match opts.weighting {
        Weighting::Uniform => vec![1.0; used.len()],
        Weighting::EqualSegments => seg_of.iter().map(|&s| 1.0 / (count[s] as f64).sqrt()).collect(),
    };
    let ms = weights.iter().map(|w| w * w).sum::<f64>() / weights.len() as f64;
    weights.iter_mut().for_each(|w| *w /= ms.sqrt());
    let v_init = segs[0].v;
    Ok(Prepared { record: rec, segments: segs, used, weights, seg_of, v_init })
}

/// Data-derived starting values: `(mu0, a, b_total, dc)` from the velocity steps (a from the
/// peak or trough after a step, a − b from the steady states before and after, Dc from the
/// slip over which the transient decays by 1 − 1/e).
pub fn initial_guess(p: &Prepared) -> (f64, f64, f64, f64) {
    let r = &p.record;
    let tail_median = |s: &Segment| {
        let n = s.i1 + 1 - s.i0;
        let mut v: Vec<f64> = r.mu[s.i1 + 1 - (n / 4).max(1)..=s.i1].to_vec();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let mu0 = tail_median(&p.segments[0]);
    let (mut as_, mut ambs, mut dcs) = (vec![], vec![], vec![]);
    for w in p.segments.windows(2) {
        let (s0, s1) = (&w[0], &w[1]);
        if !(s0.v > 0.0 && s1.v > 0.0) || (s1.v / s0.v).ln().abs() < 0.2 {
            continue;
        }
        let l = (s1.v / s0.v).ln();
        let before = tail_median(s0);
        let after = tail_median(s1);
        let n = s1.i1 + 1 - s1.i0;
        let early = &r.mu[s1.i0..s1.i0 + (n / 3).max(1)];
        let (ipk, pk) = if l > 0.0 {
            early.iter().enumerate().fold((0, f64::NEG_INFINITY), |a, (i, &m)| if m > a.1 { (i, m) } else { a })
        } else {
            early.iter().enumerate().fold((0, f64::INFINITY), |a, (i, &m)| if m < a.1 { (i, m) } else { a })
        };
        as_.push((pk - before) / l);
        ambs.push((after - before) / l);
        let target = pk + (after - pk) * (1.0 - (-1f64).exp());
        let i_pk = s1.i0 + ipk;
        let cross = (i_pk..=s1.i1).find(|&i| (r.mu[i] - target) * (pk - target) <= 0.0).unwrap_or(s1.i1);
        dcs.push((r.load_point[cross] - r.load_point[i_pk]).abs());
    }
    let med = |mut v: Vec<f64>, d: f64| {
        v.retain(|x| x.is_finite());
        if v.is_empty() {
            return d;
        }
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let a = med(as_, 0.01).clamp(1e-4, 0.1);
    let amb = med(ambs, -0.002).clamp(-0.05, 0.05);
    let dc = med(dcs, 10.0).clamp(0.1, 1e4);
    (mu0, a, (a - amb).max(1e-4), dc.max(0.1))
}

/// Builds the parameter map: layout, defaults, free set, constraints.
pub fn parameter_map(p: &Prepared, opts: &FitOptions) -> Result<ParamMap, FitError> {
    let n = opts.laws.len();
    if n == 0 {
        return Err(FitError::Setup("at least one state variable is needed".into()));
    }
    let n_off = if opts.mu0_per_segment { p.segments.len().saturating_sub(1) } else { 0 };
    let np = n_params(n);
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
        base[off + 2] = match law.parameters().first() {
            Some(("vc", _)) => vmin,
            Some((_, v)) => *v,
            None => 0.0,
        };
    }
    let mut slots: Vec<Slot> = vec![Slot::Fixed; np + n_off];
    let log_param = |i: usize| {
        i == 1
            || i == 2
            || (i >= N_GLOBAL
                && i < np
                && ((i - N_GLOBAL) % 3 == 1 || ((i - N_GLOBAL) % 3 == 2 && names[i].starts_with("vc"))))
    };
    let mut free_idx = vec![0usize, 1];
    if opts.fit_stiffness {
        free_idx.push(2);
    }
    if opts.fit_slip_trend {
        free_idx.push(3);
    }
    for (i, law) in opts.laws.iter().enumerate() {
        let off = state_offset(i);
        free_idx.extend([off, off + 1]);
        if !law.parameters().is_empty() {
            free_idx.push(off + 2);
        }
    }
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
                && (i - N_GLOBAL) % 3 == 2
                && opts.laws[(i - N_GLOBAL) / 3].parameters().is_empty())
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
        base[index(name)?] = *v;
    }
    // constraints
    let mut constraints = vec![];
    for c in &opts.fix {
        let (lhs, rhs) = c
            .split_once('=')
            .ok_or_else(|| FitError::Setup(format!("constraint `{c}`: expected NAME=VALUE or NAME-NAME=VALUE")))?;
        let value: f64 =
            rhs.trim().parse().map_err(|_| FitError::Setup(format!("constraint `{c}`: `{rhs}` is not a number")))?;
        let lhs = lhs.trim();
        let split = lhs.char_indices().skip(1).find(|(_, ch)| *ch == '-' || *ch == '+');
        match split {
            None => {
                let i = index(lhs)?;
                base[i] = value;
                free_idx.retain(|&j| j != i);
                slots[i] = Slot::Fixed;
            }
            Some((pos, op)) => {
                let (x, y) = (lhs[..pos].trim(), lhs[pos + 1..].trim());
                let (ix, iy) = (index(x)?, index(y)?);
                // X − Y = c  →  Y = X − c ;  X + Y = c  →  Y = −(X − c)
                let sign = if op == '-' { 1.0 } else { -1.0 };
                free_idx.retain(|&j| j != iy);
                slots[iy] = Slot::Derived { src: ix, sign, c: value };
                if !free_idx.contains(&ix) && !matches!(slots[ix], Slot::Fixed) {
                    return Err(FitError::Setup(format!("constraint `{c}`: `{x}` is itself constrained")));
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
    let map = ParamMap { n_states: n, names, slots, base, free: free_idx, constraints };
    let theta = map.theta_of(&map.base);
    let base = map.full(&theta);
    Ok(ParamMap { base, ..map })
}

struct Evaluated {
    model_mu: Vec<f64>,
    raw_j: Vec<f64>, // ∂model/∂θ, row-major n × m
}

/// Physical bounds of each full-vector entry: outside them a trial point is rejected (so LM
/// cannot wander into regions where the model means nothing and integrates slowly).
fn within_bounds(map: &ParamMap, full: &[f64]) -> Result<(), String> {
    let np = n_params(map.n_states);
    for (i, &v) in full.iter().enumerate().take(np) {
        let (lo, hi) = match i {
            0 => (-10.0, 10.0),
            1 => (1e-7, 1.0),
            2 => (1e-9, 1e4),
            3 => (-1e-2, 1e-2),
            _ => match (i - N_GLOBAL) % 3 {
                2 if map.names[i].starts_with("vc") => (1e-9, 1e6),
                0 => (-1.0, 1.0),
                // Dc: 0.01 µm to 10 m; below, a lab spring-slider is a stiff problem that no
                // record of 1–1000 Hz can resolve
                1 => (1e-2, 1e7),
                _ => (-1e9, 1e9),
            },
        };
        if !(v >= lo && v <= hi) {
            return Err(format!("`{}` = {v:e} is outside its physical range [{lo:e}, {hi:e}]", map.names[i]));
        }
    }
    Ok(())
}

fn evaluate(
    p: &Prepared,
    map: &ParamMap,
    opts: &FitOptions,
    theta: &[f64],
    rtol: f64,
) -> Result<Evaluated, SolveError> {
    let full = map.full(theta);
    within_bounds(map, &full).map_err(SolveError::Input)?;
    let model = map.model(opts, &full, p.v_init).map_err(SolveError::Input)?;
    let np = n_params(map.n_states);
    let problem = forward_problem(p, opts, model);
    let s = solve_with_sensitivities(&problem, rtol, rtol * 1e-4)?;
    let m = map.free.len();
    let dfull = map.jac(theta);
    let mut model_mu = s.mu;
    let mut raw_j = vec![0.0; model_mu.len() * m];
    for r in 0..model_mu.len() {
        let seg = p.seg_of[r];
        let off_idx = if seg > 0 && map.slots.len() > np { Some(np + seg - 1) } else { None };
        if let Some(oi) = off_idx {
            model_mu[r] += full[oi];
        }
        for k in 0..m {
            let mut acc = 0.0;
            for j in 0..np {
                acc += s.dmu[r * np + j] * dfull[j * m + k];
            }
            if let Some(oi) = off_idx {
                acc += dfull[oi * m + k];
            }
            raw_j[r * m + k] = acc;
        }
    }
    Ok(Evaluated { model_mu, raw_j })
}

/// Model friction at the used samples for free parameters θ (no sensitivities): the forward
/// model of MCMC and of predictions.
pub fn model_curve(
    p: &Prepared,
    map: &ParamMap,
    opts: &FitOptions,
    theta: &[f64],
    rtol: f64,
) -> Result<Vec<f64>, SolveError> {
    let full = map.full(theta);
    within_bounds(map, &full).map_err(SolveError::Input)?;
    let model = map.model(opts, &full, p.v_init).map_err(SolveError::Input)?;
    let np = n_params(map.n_states);
    let problem = forward_problem(p, opts, model);
    let alg = rsf_solvers::Dopri5 { max_steps: FIT_MAX_STEPS, ..rsf_solvers::Dopri5::new(rtol, rtol * 1e-4) };
    let (mut mu, _) = rsf_solvers::solve_friction(&problem, &alg)?;
    if map.slots.len() > np {
        for (r, &seg) in p.seg_of.iter().enumerate() {
            if seg > 0 {
                mu[r] += full[np + seg - 1];
            }
        }
    }
    Ok(mu)
}

/// Model slip rate at the used samples for the full parameter vector (for residuals against
/// log V): one forward solve.
fn model_slip_rate(p: &Prepared, map: &ParamMap, opts: &FitOptions, full: &[f64]) -> Result<Vec<f64>, SolveError> {
    let model = map.model(opts, full, p.v_init).map_err(SolveError::Input)?;
    let alg = rsf_solvers::Dopri5 { max_steps: FIT_MAX_STEPS, ..rsf_solvers::Dopri5::new(opts.rtol, opts.rtol * 1e-4) };
    Ok(rsf_solvers::solve(&forward_problem(p, opts, model), &alg)?.slip_rate)
}

/// The forward problem of a fit for `model`: loading and output at the used samples.
fn forward_problem(p: &Prepared, opts: &FitOptions, model: Model) -> Problem {
    let times: Vec<f64> = p.used.iter().map(|&i| p.record.time[i]).collect();
    let t0 = p.record.time[0];
    let (loading, out) = match opts.loading {
        LoadingMode::Record => (
            Loading::Record(LoadRecord { time: p.record.time.clone(), load_point: p.record.load_point.clone() }),
            times,
        ),
        LoadingMode::Protocol => {
            let segs =
                p.segments.iter().map(|s| rsf_core::Segment::for_duration(s.v, (s.t1 - s.t0).max(1e-9))).collect();
            (Loading::Segments(segs), times.iter().map(|t| (t - t0).max(0.0)).collect())
        }
    };
    let mut problem = Problem::new(model, loading, p.v_init, 1.0);
    problem.output = OutputTimes::Times(out);
    problem
}

/// Appended to `FitResult::stop_reason` when the best start ran out of its time budget.
pub const TIME_BUDGET_NOTE: &str = "time budget exhausted";

/// Fits the model to the prepared record.
pub fn fit(p: &Prepared, opts: &FitOptions) -> Result<FitResult, FitError> {
    let map = parameter_map(p, opts)?;
    let m = map.free.len();
    let data: Vec<f64> = p.used.iter().map(|&i| p.record.mu[i]).collect();
    // each start after the first gets a time budget (a start that wanders into a stiff corner of
    // parameter space must not hold the fit up): past it, evaluations fail and LM gives up
    let deadline = std::cell::Cell::new(None::<std::time::Instant>);
    let budget_hit = std::cell::Cell::new(false);
    let objective = |theta: &[f64]| -> Result<Eval, SolveError> {
        if deadline.get().is_some_and(|d| std::time::Instant::now() > d) {
            budget_hit.set(true);
            return Err(SolveError::Input("time budget of this start exhausted".into()));
        }
        let e = evaluate(p, &map, opts, theta, opts.rtol)?;
        let r = e.model_mu.iter().zip(&data).zip(&p.weights).map(|((mo, d), w)| w * (mo - d)).collect();
        let mut j = e.raw_j;
        for (row, w) in j.chunks_mut(m).zip(&p.weights) {
            row.iter_mut().for_each(|x| *x *= w);
        }
        Ok(Eval { r, j })
    };
    // starting points: the data-derived guess, then Dc and a scaled
    let theta0 = map.theta_of(&map.base);
    let mut starts = vec![theta0.clone()];
    let scale = |name: &str, f: f64| {
        let mut t = theta0.clone();
        for (k, n) in map.free_names().iter().enumerate() {
            if n.starts_with(name) {
                t[k] = if map.is_log(k) { t[k] + f.ln() } else { t[k] * f };
            }
        }
        t
    };
    // several states: start from the one-state optimum, the extra states small and slower, with
    // either sign of b (a strengthening second state is as plausible as a weakening one)
    if opts.laws.len() > 1 && opts.starts > 1 {
        let mut o1 = opts.clone();
        o1.laws.truncate(1);
        o1.fix.retain(|c| !c.contains('2') && !c.contains('3'));
        o1.initial.retain(|(n, _)| !n.contains('2') && !n.contains('3'));
        // a caller that gives the first state's start (diagnosis: the baseline optimum) spares
        // the nested one-state fit
        let given = |n: &str| opts.initial.iter().any(|(x, _)| x == n);
        let r1 = if given("b1") && given("dc1") && given("a") && given("mu0") {
            let f = |i: usize| map.base[i];
            Ok(Params {
                mu0: f(0),
                v0: p.v_init,
                a: f(1),
                b: vec![f(state_offset(0))],
                dc: vec![f(state_offset(0) + 1)],
                k: f(2),
                g: f(3),
                laws: vec![],
                law_params: BTreeMap::new(),
                mu0_offsets: vec![],
            })
        } else {
            fit(p, &o1).map(|r| r.params)
        };
        if let Ok(r1) = r1 {
            for sign in [1.0, -1.0] {
                let mut full = map.base.clone();
                full[0] = r1.mu0;
                full[1] = r1.a;
                full[2] = r1.k;
                full[3] = r1.g;
                full[state_offset(0)] = r1.b[0];
                full[state_offset(0) + 1] = r1.dc[0];
                for i in 1..opts.laws.len() {
                    full[state_offset(i)] = sign * 0.2 * r1.b[0].abs();
                    full[state_offset(i) + 1] = r1.dc[0] * 10f64.powi(i as i32);
                }
                starts.insert(0, map.theta_of(&full));
            }
        }
    }
    // b of either sign: velocity-strengthening evolution (b < 0) looks like a slow rise after
    // an up-step, which a positive-b start can mistake for a vanishing Dc
    for (name, f) in [("dc", 3.0), ("b", -1.0), ("dc", 0.3), ("a", 1.5), ("dc", 10.0), ("a", 0.7)] {
        starts.push(scale(name, f));
    }
    starts.truncate(opts.starts.max(1) + if opts.laws.len() > 1 { 2 } else { 0 });
    let mut best: Option<lm::LmResult> = None;
    // the best start stopped because its time ran out: not converged, and said so
    let mut best_hit_budget = false;
    let mut first_err = None;
    let mut first_time: Option<f64> = None;
    let fit_start = std::time::Instant::now();
    let fit_deadline = fit_start + std::time::Duration::from_secs_f64(opts.time_budget);
    for s in &starts {
        let t = std::time::Instant::now();
        if t > fit_deadline {
            break;
        }
        deadline.set(Some(match first_time {
            Some(t1) => (t + std::time::Duration::from_secs_f64((5.0 * t1).max(0.5))).min(fit_deadline),
            None => fit_deadline,
        }));
        budget_hit.set(false);
        let res = lm::minimize(s, &objective, opts.max_iter);
        first_time.get_or_insert(t.elapsed().as_secs_f64());
        match res {
            Ok(r) => {
                if best.as_ref().is_none_or(|b| r.ssr < b.ssr) {
                    best_hit_budget = budget_hit.get();
                    best = Some(r);
                }
            }
            Err(e) => {
                first_err.get_or_insert(e);
            }
        }
    }
    let Some(best) = best else {
        return Err(FitError::Start(first_err.expect("no start and no error")));
    };
    let e = evaluate(p, &map, opts, &best.theta, opts.rtol).map_err(FitError::Start)?;
    // covariance (sandwich for non-uniform weights), σ² from the unweighted residuals
    let n = data.len();
    let resid: Vec<f64> = e.model_mu.iter().zip(&data).map(|(a, b)| a - b).collect();
    let ssr_raw: f64 = resid.iter().map(|x| x * x).sum();
    let dof = (n as f64 - m as f64).max(1.0);
    let s2 = ssr_raw / dof;
    let mut h = nalgebra::DMatrix::<f64>::zeros(m, m);
    let mut g = nalgebra::DMatrix::<f64>::zeros(m, m);
    for (r, w) in p.weights.iter().enumerate() {
        let row = &e.raw_j[r * m..(r + 1) * m];
        for a in 0..m {
            for b in 0..m {
                h[(a, b)] += w * w * row[a] * row[b];
                g[(a, b)] += w.powi(4) * row[a] * row[b];
            }
        }
    }
    // invert with column scaling (entries differ by many orders of magnitude) and an SVD
    // pseudo-inverse, so an unidentified direction shows as a huge variance, not a tiny one
    let dsc: Vec<f64> = (0..m).map(|k| h[(k, k)].sqrt().max(1e-300)).collect();
    let hs = nalgebra::DMatrix::from_fn(m, m, |a, b| h[(a, b)] / (dsc[a] * dsc[b]));
    // nalgebra's plain SVD can iterate forever on non-finite input: check, and cap iterations
    let nan = || nalgebra::DMatrix::from_element(m, m, f64::NAN);
    let hsinv = if hs.iter().all(|x| x.is_finite()) {
        match hs.clone().try_svd(true, true, 1e-15, 10_000) {
            Some(svd) => {
                let smax = svd.singular_values.max();
                svd.pseudo_inverse(1e-12 * smax).unwrap_or_else(|_| nan())
            }
            None => nan(),
        }
    } else {
        nan()
    };
    let hinv = nalgebra::DMatrix::from_fn(m, m, |a, b| hsinv[(a, b)] / (dsc[a] * dsc[b]));
    let cov = (&hinv * g * &hinv) * s2;
    let full = map.full(&best.theta);
    let names = map.free_names();
    let mut ci95 = BTreeMap::new();
    let mut stderr = BTreeMap::new();
    for (k, name) in names.iter().enumerate() {
        let sd = cov[(k, k)].max(0.0).sqrt();
        let (v, lo, hi, se) = if map.is_log(k) {
            let v = best.theta[k].exp();
            (v, (best.theta[k] - 1.96 * sd).exp(), (best.theta[k] + 1.96 * sd).exp(), v * sd)
        } else {
            (best.theta[k], best.theta[k] - 1.96 * sd, best.theta[k] + 1.96 * sd, sd)
        };
        let _ = v;
        ci95.insert(name.clone(), [lo, hi]);
        stderr.insert(name.clone(), se);
    }
    // derived parameters: delta method through their source
    for (i, s) in map.slots.iter().enumerate() {
        if let Slot::Derived { src, sign, .. } = s {
            if let Some(se) = stderr.get(&map.names[*src]).copied() {
                let v = full[i];
                ci95.insert(map.names[i].clone(), [v - 1.96 * se * sign.abs(), v + 1.96 * se * sign.abs()]);
                stderr.insert(map.names[i].clone(), se);
            }
        }
    }
    let at_bound: Vec<String> = map
        .free
        .iter()
        .filter(|&&i| {
            let mut f2 = full.clone();
            f2[i] *= 0.999;
            let mut f3 = full.clone();
            f3[i] *= 1.001;
            within_bounds(&map, &f2).is_err() || within_bounds(&map, &f3).is_err()
        })
        .map(|&i| map.names[i].clone())
        .collect();
    // the likelihood of what the fit minimises: noise σ/w_r at sample r (w normalised to mean
    // square 1; uniform weights give the usual Gaussian likelihood), so that models compared by
    // AIC/BIC are compared on the objective they were fitted to
    let ssr_w: f64 = resid.iter().zip(&p.weights).map(|(x, w)| (w * x).powi(2)).sum();
    let sum_ln_w: f64 = p.weights.iter().map(|w| w.ln()).sum();
    let ll = sum_ln_w - 0.5 * n as f64 * ((2.0 * std::f64::consts::PI * ssr_w / n as f64).ln() + 1.0);
    let kf = (m + 1) as f64;
    let np = n_params(map.n_states);
    let params = Params {
        mu0: full[0],
        v0: p.v_init,
        a: full[1],
        b: (0..map.n_states).map(|i| full[state_offset(i)]).collect(),
        dc: (0..map.n_states).map(|i| full[state_offset(i) + 1]).collect(),
        k: full[2],
        g: full[3],
        laws: opts.laws.iter().map(|l| l.name()).collect(),
        law_params: opts
            .laws
            .iter()
            .enumerate()
            .filter_map(|(i, l)| {
                l.parameters().first().map(|(nm, _)| (format!("{nm}{}", i + 1), full[state_offset(i) + 2]))
            })
            .collect(),
        mu0_offsets: full[np..].to_vec(),
    };
    let mut rows: Vec<SegmentRow> = p
        .segments
        .iter()
        .enumerate()
        .map(|(k, s)| SegmentRow { index: k + 1, kind: s.kind, t0: s.t0, t1: s.t1, v: s.v, n: 0, rms: 0.0 })
        .collect();
    for (r, &sg) in p.seg_of.iter().enumerate() {
        rows[sg].n += 1;
        rows[sg].rms += resid[r] * resid[r];
    }
    rows.iter_mut().for_each(|r| r.rms = if r.n > 0 { (r.rms / r.n as f64).sqrt() } else { 0.0 });
    let curve = Curve {
        time: p.used.iter().map(|&i| p.record.time[i]).collect(),
        load_point: p.used.iter().map(|&i| p.record.load_point[i]).collect(),
        data,
        model: e.model_mu,
        segment: p.seg_of.clone(),
        slip_rate: model_slip_rate(p, &map, opts, &full).unwrap_or_default(),
    };
    Ok(FitResult {
        params,
        ci95,
        stderr,
        constraints: map.constraints.clone(),
        at_bound,
        rms: (ssr_raw / n as f64).sqrt(),
        n,
        n_free: m,
        log_likelihood: ll,
        aic: 2.0 * kf - 2.0 * ll,
        bic: kf * (n as f64).ln() - 2.0 * ll,
        segments: rows,
        iterations: best.iterations,
        stop_reason: if best_hit_budget {
            format!("{} ({TIME_BUDGET_NOTE})", best.reason)
        } else {
            best.reason.to_string()
        },
        starts: starts.len(),
        loading: opts.loading,
        weighting: opts.weighting,
        curve,
        theta: best.theta.clone(),
        cov_theta: cov.as_slice().to_vec(),
    })
}
