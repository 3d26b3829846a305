//! Properties of the law inside rsf's solvers: the V_i·t identity of N-state models, a shifted
//! clock, and explicit against implicit integration. Lab-like models: a 0.005–0.02,
//! b 0.005–0.025, Dc 0.5–50 µm, k 1e-3–1e-1 /µm, V 0.01–3 µm/s.

use crate::pointwise::log_uniform;
use crate::{Claims, Outcome, Property, run_cases};
use proptest::prelude::*;
use rsf_core::{LoadRecord, Loading, Model, Segment, StateLaw, StateVariable};
use rsf_laws::{Aging, Slip};
use rsf_solvers::{Dopri5, OutputTimes, Problem, Rodas4, solve};

/// Δμ at the same V_i·t from two initial slip rates (both solved at rtol 1e-11).
const IDENTITY_TOL: f64 = 1e-8;
/// Friction with the clock shifted by [`CLOCK_SHIFT`] (rounding of the shifted times: ~1e-10 s).
const SHIFT_TOL: f64 = 1e-8;
/// Where the shifted clock starts, s.
const CLOCK_SHIFT: f64 = 1e6;
/// Dopri5 against Rodas4, both at rtol 1e-10.
const AGREE_TOL: f64 = 1e-7;
/// Stiffness over the critical stiffness estimate for the record and integrator comparisons:
/// linear stability (k > k_c) is not enough after large steps (Gu et al. 1984, Slip law).
const STABLE_MARGIN: f64 = 10.0;
/// Σb/a at most this in the record and step comparisons: velocity strengthening, which slides
/// stably through any step (weakening PRZ, b = 4a, fails on reloading 33× faster even at
/// 10 k_c; so does 1 − Ω² at b = 1.5a).
const MAX_WEAKENING: f64 = 0.8;
/// The record and step protocols step down by at most this factor (a hold becomes this step).
const MIN_RATIO: f64 = 0.03;
/// Stiffness over Σ b_i/Dc_i (the weakening per unit slip of states that only decay) for a
/// model with a law without healing.
const NO_HEALING_MARGIN: f64 = 2.0;
/// The longest protocol, in units of Dc/V_i, for a model with a law without healing: θ falls
/// by e per Dc of slip without end, and after tens of Dc it is e^(−tens) — a state no
/// physical surface reaches (a slip of 20 Dc takes θ to 2e-9 of its start).
const NO_HEALING_SPAN: f64 = 20.0;
/// Solver-level inputs: an eighth of the pointwise count, at least this many.
const MIN_SOLVER_CASES: u32 = 8;

/// A lab-like model with the law as its first state and up to two more states, each the law
/// again, Aging or Slip.
#[derive(Clone, Debug)]
pub(crate) struct Setup {
    a: f64,
    b: f64,
    dc: f64,
    stiffness: f64,
    /// Extra states: (0 the law, 1 Aging, 2 Slip; b; Dc over the first Dc).
    extra: Vec<(u8, f64, f64)>,
    /// Initial slip rate, µm/s.
    v_i: f64,
    /// log10 of the second initial slip rate over the first.
    decades: f64,
    /// 0: a hold; otherwise the step's V_f/V_i.
    ratio: f64,
    /// Duration in units of Dc/V_i.
    t_end: f64,
}

fn setups() -> impl Strategy<Value = Setup> {
    (
        0.005f64..0.02,
        0.005f64..0.025,
        log_uniform((0.5, 50.0)),
        log_uniform((1e-3, 1e-1)),
        proptest::collection::vec((0u8..3, 0.001f64..0.01, 2.0f64..100.0), 0..=2),
        log_uniform((0.01, 3.0)),
        -2.0f64..2.0,
        prop_oneof![Just(0.0), log_uniform((1e-3, 0.3))],
        log_uniform((5.0, 500.0)),
    )
        .prop_map(|(a, b, dc, stiffness, extra, v_i, decades, ratio, t_end)| Setup {
            a,
            b,
            dc,
            stiffness,
            extra,
            v_i,
            decades,
            ratio,
            t_end,
        })
}

impl Setup {
    fn model<L: StateLaw>(&self, law: &L) -> Model {
        let mut m =
            Model::new(0.6, 1.0, self.a, self.stiffness).with_state(StateVariable::new(law.clone(), self.b, self.dc));
        for &(kind, b, f) in &self.extra {
            let dc = self.dc * f;
            m = m.with_state(match kind {
                0 => StateVariable::new(law.clone(), b, dc),
                1 => StateVariable::new(Aging, b, dc),
                _ => StateVariable::new(Slip, b, dc),
            });
        }
        m
    }

    /// The same model, velocity strengthening ([`MAX_WEAKENING`]), in a machine at least
    /// [`STABLE_MARGIN`] times stiffer than critical, so
    /// that reloading after a hold slides stably (a slip event would make the comparison one
    /// of two chaotic runs).
    fn stable_model<L: StateLaw>(&self, law: &L) -> Model {
        let mut m = self.model(law);
        let b: f64 = m.states.iter().map(|s| s.b).sum();
        if b > MAX_WEAKENING * m.a {
            let f = MAX_WEAKENING * m.a / b;
            m.states.iter_mut().for_each(|s| s.b *= f);
        }
        m.stiffness = m.stiffness.max(STABLE_MARGIN * m.critical_stiffness_estimate());
        if without_steady_state(&m, self.v_i) {
            // θ of a law without healing only decays, weakening by b_i per Dc_i of slip at any
            // V: the spring must unload faster than that for sliding to stay stable
            let weakening: f64 = m.states.iter().map(|s| s.b / s.dc).sum();
            m.stiffness = m.stiffness.max(NO_HEALING_MARGIN * weakening);
        }
        m
    }

    /// The second piece's velocity in the record and step protocols: the step, at most
    /// [`MIN_RATIO`] down (a hold or a larger step would make reloading a slip event).
    fn second_velocity(&self) -> f64 {
        self.ratio.max(MIN_RATIO) * self.v_i
    }

    /// The duration in units of Dc/V_i, at most [`NO_HEALING_SPAN`] for a model with a law
    /// without healing.
    fn span<L: StateLaw>(&self, law: &L) -> f64 {
        if without_steady_state(&self.model(law), self.v_i) { self.t_end.min(NO_HEALING_SPAN) } else { self.t_end }
    }
}

pub(crate) fn run<L: StateLaw>(p: Property, law: &L, claims: &Claims) -> Result<Outcome, (String, String)> {
    let n = (claims.cases / 8).max(MIN_SOLVER_CASES);
    match p {
        Property::ViTIdentity => {
            if !claims.scale_free() {
                return Ok(Outcome::Skipped("the law has a velocity parameter: a velocity scale of its own"));
            }
            run_cases(n, &setups(), |s| vi_t_identity(law, &s))
        }
        Property::TimeShift => run_cases(n, &setups(), |s| time_shift(law, &s)),
        Property::IntegratorsAgree => run_cases(n, &setups(), |s| integrators_agree(law, &s)),
        Property::Finite
        | Property::LogForm
        | Property::Jacobian
        | Property::SteadyState
        | Property::TimeScaling
        | Property::UnitScaling
        | Property::ParameterRoundTrip
        | Property::ParameterDerivative => unreachable!("pointwise properties are run by pointwise.rs"),
    }
}

/// Whether a state of `m` has no steady state at `v` (the Aging law without healing).
fn without_steady_state(m: &Model, v: f64) -> bool {
    m.states.iter().any(|s| s.law.steady_state_theta(v, s.dc).is_err())
}

/// A problem starting at `v_i`: in steady state, or, for a model with a state without one (the
/// Aging law without healing), with every state at θ = Dc/V_i (the V_i·t identity holds from
/// any start that scales so).
fn problem(m: &Model, loading: Loading, v_i: f64, dt: f64) -> Problem {
    let mut p = Problem::new(m.clone(), loading, v_i, dt);
    if without_steady_state(m, v_i) {
        p.initial_theta = Some(m.states.iter().map(|s| s.dc / v_i).collect());
    }
    p
}

/// Δμ against T = V_i t / Dc₁ at `ts` (`ts[0]` = 0) for a hold or step from sliding at `v_i`.
fn delta_mu(m: &Model, v_i: f64, ratio: f64, ts: &[f64]) -> Result<Vec<f64>, String> {
    let dc1 = m.states[0].dc;
    let times: Vec<f64> = ts.iter().map(|t| t * dc1 / v_i).collect();
    let t_end = *times.last().unwrap_or(&1.0);
    let mut p = problem(m, Loading::Segments(vec![Segment::for_duration(ratio * v_i, t_end)]), v_i, 1.0);
    p.output = OutputTimes::Times(times);
    let sol = solve(&p, &Rodas4::new(1e-11, 1e-14)).map_err(|e| format!("solve from V_i = {v_i:e}: {e}"))?;
    let mu_i = sol.mu.first().copied().ok_or("no output")?;
    Ok(sol.mu.iter().map(|x| x - mu_i).collect())
}

fn vi_t_identity<L: StateLaw>(law: &L, s: &Setup) -> Result<(), String> {
    // a law without healing weakens without end in a soft machine: the stable model for it
    let m = if without_steady_state(&s.model(law), s.v_i) { s.stable_model(law) } else { s.model(law) };
    let t_end = s.span(law);
    let ts: Vec<f64> = (0..=40).map(|i| t_end * (i as f64 / 40.0).powi(3)).collect();
    let d1 = delta_mu(&m, s.v_i, s.ratio, &ts)?;
    let d2 = delta_mu(&m, s.v_i * 10f64.powf(s.decades), s.ratio, &ts)?;
    for ((t, x), y) in ts.iter().zip(&d1).zip(&d2) {
        if (x - y).abs() > IDENTITY_TOL {
            return Err(format!("at V_i·t/Dc = {t:.4}: Δμ = {x:e} from V_i but {y:e} from V_i·10^{:.3}", s.decades));
        }
    }
    Ok(())
}

/// A load-point record: V_i, then V_i·ratio (or a hold), then V_i again, 301 samples.
fn record(s: &Setup, span_dc: f64, t0: f64) -> LoadRecord {
    let span = span_dc * s.dc / s.v_i;
    let v2 = s.second_velocity();
    let (mut time, mut load_point) = (vec![], vec![]);
    let mut x = 0.0;
    for i in 0..=300 {
        let t = span * i as f64 / 300.0;
        if i > 0 {
            let v = if i <= 100 {
                s.v_i
            } else if i <= 200 {
                v2
            } else {
                s.v_i
            };
            x += v * span / 300.0;
        }
        time.push(t0 + t);
        load_point.push(x);
    }
    LoadRecord { time, load_point }
}

fn time_shift<L: StateLaw>(law: &L, s: &Setup) -> Result<(), String> {
    let m = s.stable_model(law);
    let run = |t0: f64| {
        let r = record(s, s.span(law), t0);
        let mut p = problem(&m, Loading::Record(r.clone()), s.v_i, 1.0);
        p.output = OutputTimes::Times(r.time);
        solve(&p, &Rodas4::new(1e-10, 1e-13)).map_err(|e| format!("solve with the clock at {t0:e} s: {e}"))
    };
    let (a, b) = (run(0.0)?, run(CLOCK_SHIFT)?);
    if a.mu.len() != b.mu.len() {
        return Err(format!("{} rows but {} with the clock shifted", a.mu.len(), b.mu.len()));
    }
    for (i, (x, y)) in a.mu.iter().zip(&b.mu).enumerate() {
        if (x - y).abs() > SHIFT_TOL {
            return Err(format!("row {i}: μ = {x} but {y} with the clock starting at {CLOCK_SHIFT:e} s"));
        }
    }
    Ok(())
}

fn integrators_agree<L: StateLaw>(law: &L, s: &Setup) -> Result<(), String> {
    let m = s.stable_model(law);
    let d = s.span(law) * s.dc / s.v_i;
    let segs = vec![
        Segment::for_duration(s.v_i, d),
        Segment::for_duration(s.second_velocity(), d),
        Segment::for_duration(s.v_i, d),
    ];
    let p = problem(&m, Loading::Segments(segs), s.v_i, d / 50.0);
    let e = solve(&p, &Dopri5::new(1e-10, 1e-13)).map_err(|e| format!("Dopri5: {e}"))?;
    let i = solve(&p, &Rodas4::new(1e-10, 1e-13)).map_err(|e| format!("Rodas4: {e}"))?;
    for (r, ((t, x), y)) in e.time.iter().zip(&e.mu).zip(&i.mu).enumerate() {
        if (x - y).abs() > AGREE_TOL {
            return Err(format!("row {r} (t = {t:.4} s): μ = {x} by Dopri5 but {y} by Rodas4"));
        }
    }
    Ok(())
}
