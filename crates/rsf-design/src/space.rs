//! The proposals: velocity steps, slide–hold–reslides and (when the machine can) normal-stress
//! changes appended at the record's end, and sequences of two; each as protocol segments,
//! machine time, slip, and the samples a lab would record.

use super::DesignOptions;
use serde::Serialize;

/// Step sizes, decades (up and down): the range of lab velocity steps.
pub const STEP_DECADES: [f64; 7] = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5];
/// Slip after a step, in units of the baseline's Dc: 3 Dc brings a state to within e⁻³ of its
/// new steady state, 30 Dc shows a slow second state or a trend.
pub const STEP_SLIP_DC: [f64; 3] = [3.0, 10.0, 30.0];
/// Hold times, s: a log grid over the lab's range (10–10⁴ s).
pub const HOLD_TIMES: [f64; 7] = [10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0];
/// Reslide distance after a hold, in units of the baseline's Dc: the peak and most of its decay
/// (3 Dc), or the return to steady state (10 Dc).
pub const RESLIDE_DC: [f64; 2] = [3.0, 10.0];
/// Sequences are formed from this many of the best single proposals (ordered pairs).
pub const SEQUENCE_SEEDS: usize = 6;
/// Prediction points per segment: the samples themselves up to this many, else this many
/// samples on a geometric grid from the segment's start (where transients are), each standing
/// for the samples around it.
pub const POINTS_PER_SEGMENT: usize = 150;

/// Normal-stress changes proposed, fractions of the record's σ (up and down, those within
/// [`DesignOptions::max_sigma_change`]): the range of the normal-stress steps of lab
/// experiments on the Linker–Dieterich effect, from a few to some tens of percent.
pub const SIGMA_CHANGES: [f64; 5] = [0.05, 0.1, 0.2, 0.3, 0.5];

/// Time over which a proposed normal-stress change is ramped, s: a servo changes σ within about
/// a second, and a ramp (not an instantaneous step) is what the forward sensitivities carry
/// exactly.
pub const SIGMA_RAMP_S: f64 = 1.0;

/// Shortest protocol segment a proposal holds (σ ramps aside), s: a lab's servo settles and its sampling
/// resolves a new velocity within seconds, not within a fraction of one (a 0.8 s step of 7
/// samples predicts far more than a real machine shows).
pub const MIN_SEGMENT_S: f64 = 10.0;

/// One building block of a proposal.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Primitive {
    /// Load-point velocity `v` (µm/s) for `slip` µm.
    Step {
        /// Velocity, µm/s.
        v: f64,
        /// Load-point displacement, µm.
        slip: f64,
    },
    /// A hold of `hold_s` s, then a reslide at `v` (µm/s) for `slip` µm.
    Hold {
        /// Hold time, s.
        hold_s: f64,
        /// Reslide velocity, µm/s.
        v: f64,
        /// Reslide displacement, µm.
        slip: f64,
    },
    /// The normal stress ramped to `level` × the record's over [`SIGMA_RAMP_S`] at `v` (µm/s),
    /// then sliding at `v` for `slip` µm at that σ.
    NormalStress {
        /// σ after the change over the record's σ.
        level: f64,
        /// Load-point velocity, µm/s.
        v: f64,
        /// Load-point displacement after the ramp, µm.
        slip: f64,
    },
}

impl Primitive {
    /// (velocity µm/s, duration s) of its protocol segments.
    pub fn segments(&self) -> Vec<(f64, f64)> {
        match *self {
            Primitive::Step { v, slip } => vec![(v, slip / v)],
            Primitive::Hold { hold_s, v, slip } => vec![(0.0, hold_s), (v, slip / v)],
            Primitive::NormalStress { v, slip, .. } => vec![(v, SIGMA_RAMP_S), (v, slip / v)],
        }
    }

    /// σ over the record's at the end of each of its segments, from `level` before it.
    fn sigma_levels(&self, level: f64) -> Vec<f64> {
        match *self {
            Primitive::Step { .. } => vec![level],
            Primitive::Hold { .. } => vec![level; 2],
            Primitive::NormalStress { level: to, .. } => vec![to; 2],
        }
    }

    /// In words, with the step relative to `v_from` µm/s.
    pub fn describe(&self, v_from: f64) -> String {
        match *self {
            Primitive::Step { v, slip } => {
                let d = (v / v_from).log10();
                let dir = if d >= 0.0 { "up" } else { "down" };
                format!("step {dir} {:.1} decades to {} µm/s for {} µm", d.abs(), num(v), num(slip))
            }
            Primitive::Hold { hold_s, v, slip } => {
                format!("hold {} s, reslide at {} µm/s for {} µm", num(hold_s), num(v), num(slip))
            }
            Primitive::NormalStress { level, v, slip } => format!(
                "normal stress to {}× the record's (over {} s) at {} µm/s, slide {} µm",
                num(level),
                num(SIGMA_RAMP_S),
                num(v),
                num(slip)
            ),
        }
    }

    fn end_velocity(&self) -> f64 {
        match *self {
            Primitive::Step { v, .. } | Primitive::Hold { v, .. } | Primitive::NormalStress { v, .. } => v,
        }
    }
}

/// Three significant digits, without trailing zeros.
pub(crate) fn num(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let mag = x.abs().log10().floor() as i32;
    let dec = (2 - mag).max(0) as usize;
    let s = format!("{x:.dec$}");
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
}

/// A proposal: one primitive or a sequence of two, appended at the record's end.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Proposal {
    /// Its primitives, in order.
    pub parts: Vec<Primitive>,
}

impl Proposal {
    /// (velocity µm/s, duration s) of every protocol segment.
    pub fn segments(&self) -> Vec<(f64, f64)> {
        self.parts.iter().flat_map(|p| p.segments()).collect()
    }

    /// σ over the record's at the end of each protocol segment (1: unchanged); a change is a
    /// linear ramp through its segment.
    pub fn sigma_levels(&self) -> Vec<f64> {
        let mut level = 1.0;
        let mut out = vec![];
        for p in &self.parts {
            let l = p.sigma_levels(level);
            level = *l.last().unwrap_or(&level);
            out.extend(l);
        }
        out
    }

    /// Whether it changes the normal stress.
    pub fn changes_normal_stress(&self) -> bool {
        self.parts.iter().any(|p| matches!(p, Primitive::NormalStress { .. }))
    }

    /// Its protocol segments as the solvers take them: σ ramps as normal-stress rates in units
    /// of the record's σ (the model's σ_ref is then 1: only ratios of σ enter).
    pub fn protocol(&self) -> Vec<rsf_core::Segment> {
        let mut level = 1.0;
        self.segments()
            .iter()
            .zip(self.sigma_levels())
            .map(|(&(v, d), s)| {
                let seg = rsf_core::Segment::for_duration(v, d);
                let rate = (s - level) / d;
                level = s;
                if rate != 0.0 { seg.with_normal_stress_rate(rate) } else { seg }
            })
            .collect()
    }

    /// The primitive each of `times` (s after the record's end, increasing) falls in: the one
    /// whose span (start, end] holds it; past the end, the last.
    pub fn parts_at(&self, times: &[f64]) -> Vec<&Primitive> {
        let mut ends = self.parts.iter().scan(0.0, |t, p| {
            *t += p.segments().iter().map(|s| s.1).sum::<f64>();
            Some(*t)
        });
        let (mut k, mut end) = (0, ends.next().unwrap_or(f64::INFINITY));
        times
            .iter()
            .map(|&t| {
                while t > end && k + 1 < self.parts.len() {
                    k += 1;
                    end = ends.next().unwrap_or(f64::INFINITY);
                }
                &self.parts[k]
            })
            .collect()
    }

    /// Machine time, s.
    pub fn machine_time(&self) -> f64 {
        self.segments().iter().map(|s| s.1).sum()
    }

    /// Load-point displacement, µm.
    pub fn slip(&self) -> f64 {
        self.segments().iter().map(|(v, d)| v * d).sum()
    }

    /// The kind, as in JSON: `step`, `hold` or `sequence`.
    pub fn kind(&self) -> &'static str {
        match self.parts[..] {
            [Primitive::Step { .. }] => "step",
            [Primitive::Hold { .. }] => "hold",
            [Primitive::NormalStress { .. }] => "normal_stress",
            _ => "sequence",
        }
    }

    /// In words, starting from `v_end` µm/s.
    pub fn describe(&self, v_end: f64) -> String {
        let mut from = v_end;
        let mut words = vec![];
        for p in &self.parts {
            words.push(p.describe(from));
            from = p.end_velocity();
        }
        words.join("; then ")
    }

    pub(crate) fn fits(&self, o: &DesignOptions) -> bool {
        let holds_ok = self.parts.iter().all(|p| match *p {
            Primitive::Hold { hold_s, .. } => hold_s <= o.max_hold * (1.0 + 1e-9),
            Primitive::Step { .. } | Primitive::NormalStress { .. } => true,
        });
        // every segment but a σ ramp lasts MIN_SEGMENT_S
        let long_enough = self.parts.iter().all(|p| {
            let segs = p.segments();
            let skip = usize::from(matches!(p, Primitive::NormalStress { .. }));
            segs[skip..].iter().all(|s| s.1 >= MIN_SEGMENT_S * (1.0 - 1e-9))
        });
        // each σ change changes σ, and σ stays within the machine's range
        let mut level = 1.0;
        let sigma_ok = self.parts.iter().all(|p| match *p {
            Primitive::NormalStress { level: to, .. } => {
                let ok = (to - level).abs() > 1e-9 && (to - 1.0).abs() <= o.max_sigma_change * (1.0 + 1e-9) && to > 0.0;
                level = to;
                ok
            }
            Primitive::Step { .. } | Primitive::Hold { .. } => true,
        });
        holds_ok
            && long_enough
            && sigma_ok
            && self.machine_time() <= o.max_time * (1.0 + 1e-9)
            && self.slip() <= o.max_slip * (1.0 + 1e-9)
    }
}

/// The single proposals from the record's end velocity `v_end` (µm/s) on the slip scale
/// `dc_ref` µm (the baseline's Dc), within the options' constraints; normal-stress changes only
/// when `sigma` (the machine can change σ and the record's σ is not a measured history). A slip
/// longer than the constraints allow is shortened to the most they allow once (so a long-Dc
/// model still gets its longest step).
pub fn singles(v_end: f64, dc_ref: f64, o: &DesignOptions, sigma: bool) -> Vec<Proposal> {
    let mut out: Vec<Proposal> = vec![];
    let mut push = |p: Proposal| {
        if p.fits(o) && !out.contains(&p) {
            out.push(p);
        }
    };
    let in_range = |v: f64| v >= o.v_range.0 * (1.0 - 1e-9) && v <= o.v_range.1 * (1.0 + 1e-9);
    for &d in &STEP_DECADES {
        for sign in [-1.0, 1.0] {
            let v = v_end * 10f64.powf(sign * d);
            if !in_range(v) {
                continue;
            }
            for &m in &STEP_SLIP_DC {
                let slip = (m * dc_ref).max(v * MIN_SEGMENT_S).min(o.max_slip).min(v * o.max_time);
                push(Proposal { parts: vec![Primitive::Step { v, slip }] });
            }
        }
    }
    if in_range(v_end) {
        for &h in HOLD_TIMES.iter().filter(|&&h| h <= o.max_hold) {
            for &m in &RESLIDE_DC {
                let slip =
                    (m * dc_ref).max(v_end * MIN_SEGMENT_S).min(o.max_slip).min(v_end * (o.max_time - h).max(0.0));
                if slip > 0.0 {
                    push(Proposal { parts: vec![Primitive::Hold { hold_s: h, v: v_end, slip }] });
                }
            }
        }
        if sigma {
            for &f in SIGMA_CHANGES.iter().filter(|&&f| f <= o.max_sigma_change * (1.0 + 1e-9)) {
                for level in [1.0 + f, 1.0 - f] {
                    for &m in &STEP_SLIP_DC {
                        let ramp = v_end * SIGMA_RAMP_S;
                        let slip = (m * dc_ref)
                            .max(v_end * MIN_SEGMENT_S)
                            .min(o.max_slip - ramp)
                            .min(v_end * (o.max_time - SIGMA_RAMP_S));
                        if slip > 0.0 {
                            push(Proposal { parts: vec![Primitive::NormalStress { level, v: v_end, slip }] });
                        }
                    }
                }
            }
        }
    }
    out
}

/// Sequences of two of `best` (ordered pairs of different proposals) within the constraints.
pub fn sequences(best: &[Proposal], o: &DesignOptions) -> Vec<Proposal> {
    let mut out = vec![];
    for (i, a) in best.iter().enumerate() {
        for (j, b) in best.iter().enumerate() {
            if i == j {
                continue;
            }
            let p = Proposal { parts: a.parts.iter().chain(&b.parts).copied().collect() };
            if p.fits(o) {
                out.push(p);
            }
        }
    }
    out
}

/// The samples a proposal would record and the points it is predicted at.
#[derive(Clone, Debug)]
pub struct Sampling {
    /// Prediction times, s after the record's end.
    pub times: Vec<f64>,
    /// Samples each point stands for (its white noise is divided by this).
    pub counts: Vec<f64>,
    /// Samples the lab would record.
    pub samples: usize,
}

/// The sampling plan of `proposal`: the record's own interval while sliding (`dt_slide`, s) and
/// in holds (`dt_hold`), each segment's samples thinned to [`POINTS_PER_SEGMENT`] points on a
/// geometric grid from its start.
pub fn sampling(proposal: &Proposal, dt_slide: f64, dt_hold: f64) -> Sampling {
    let (mut times, mut counts, mut samples) = (vec![], vec![], 0);
    let mut t0 = 0.0;
    for (v, dur) in proposal.segments() {
        let dt = if v > 0.0 { dt_slide } else { dt_hold };
        let n = ((dur / dt).floor() as usize).max(1);
        samples += n;
        // sample indices 1..=n kept: all, or a geometric grid (consecutive at the start)
        let keep: Vec<usize> = if n <= POINTS_PER_SEGMENT {
            (1..=n).collect()
        } else {
            let mut k: Vec<usize> = (0..POINTS_PER_SEGMENT)
                .map(|g| ((n as f64).powf(g as f64 / (POINTS_PER_SEGMENT - 1) as f64)).round() as usize)
                .collect();
            k.dedup();
            k
        };
        for (g, &k) in keep.iter().enumerate() {
            // the samples between the midpoints to the neighbouring kept ones
            let lo = if g == 0 { 0.5 } else { 0.5 * (keep[g - 1] + k) as f64 };
            let hi = if g + 1 == keep.len() { n as f64 + 0.5 } else { 0.5 * (k + keep[g + 1]) as f64 };
            times.push(t0 + dur * k as f64 / n as f64);
            counts.push((hi - lo).max(1e-9));
        }
        t0 += dur;
    }
    Sampling { times, counts, samples }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn singles_respect_the_constraints() {
        let o = DesignOptions { v_range: (0.01, 100.0), max_hold: 1000.0, max_time: 2000.0, ..Default::default() };
        let s = singles(1.0, 10.0, &o, false);
        assert!(!s.is_empty());
        for p in &s {
            assert!(p.machine_time() <= 2000.0 * (1.0 + 1e-9), "{p:?}");
            for (v, _) in p.segments() {
                assert!(v == 0.0 || (0.01 * (1.0 - 1e-9)..=100.0 * (1.0 + 1e-9)).contains(&v), "{p:?}");
            }
        }
        // no segment shorter than MIN_SEGMENT_S
        assert!(s.iter().all(|p| p.segments().iter().all(|x| x.1 >= MIN_SEGMENT_S * (1.0 - 1e-9))));
        // 2 decades up would need 1000 µm in 10 s: more than max_slip allows, so not proposed
        let o2 = DesignOptions { max_slip: 500.0, ..o.clone() };
        assert!(
            !singles(1.0, 10.0, &o2, false).iter().any(|p| matches!(p.parts[0], Primitive::Step { v, .. } if v > 50.0))
        );
        // a 3000 s hold is over max_hold; 2 decades down is inside the range, 2.5 is not
        assert!(!s.iter().any(|p| matches!(p.parts[0], Primitive::Hold { hold_s, .. } if hold_s > 1000.0)));
        assert!(s.iter().any(|p| matches!(p.parts[0], Primitive::Step { v, .. } if (v - 0.01).abs() < 1e-12)));
        assert!(!s.iter().any(|p| matches!(p.parts[0], Primitive::Step { v, .. } if v < 0.009)));
    }

    #[test]
    fn normal_stress_changes_stay_within_the_machine_range() {
        let o = DesignOptions { max_sigma_change: 0.2, ..Default::default() };
        assert!(!singles(1.0, 10.0, &o, false).iter().any(Proposal::changes_normal_stress));
        let s: Vec<Proposal> =
            singles(1.0, 10.0, &o, true).into_iter().filter(Proposal::changes_normal_stress).collect();
        // 5, 10 and 20 %, up and down, three slips each
        assert_eq!(s.len(), 3 * 2 * STEP_SLIP_DC.len(), "{s:?}");
        for p in &s {
            let segs = p.protocol();
            // a 1 s ramp to the new level, then the slide at it
            assert_eq!(segs.len(), 2);
            let level = 1.0 + segs[0].normal_stress_rate * SIGMA_RAMP_S;
            assert!((level - p.sigma_levels()[0]).abs() < 1e-12 && (level - 1.0).abs() <= 0.2 + 1e-12);
            assert_eq!(segs[1].normal_stress_rate, 0.0);
            assert!(p.segments()[1].1 >= MIN_SEGMENT_S);
        }
        // up 20 % then down to 0.8: within range; up then up again to the same level: no change
        let up = Primitive::NormalStress { level: 1.2, v: 1.0, slip: 30.0 };
        let down = Primitive::NormalStress { level: 0.8, v: 1.0, slip: 30.0 };
        assert!(Proposal { parts: vec![up, down] }.fits(&o));
        assert!(!Proposal { parts: vec![up, up] }.fits(&o));
        let too_far = Primitive::NormalStress { level: 1.3, v: 1.0, slip: 30.0 };
        assert!(!Proposal { parts: vec![too_far] }.fits(&o));
        let seq = Proposal { parts: vec![up, Primitive::Hold { hold_s: 100.0, v: 1.0, slip: 30.0 }] };
        assert_eq!(seq.sigma_levels(), vec![1.2, 1.2, 1.2, 1.2]);
        let rates: Vec<f64> = seq.protocol().iter().map(|s| s.normal_stress_rate).collect();
        assert!((rates[0] - 0.2).abs() < 1e-12 && rates[1..].iter().all(|&r| r == 0.0), "{rates:?}");
        // machines without σ control (the default) get none
        assert!(!singles(1.0, 10.0, &DesignOptions::default(), true).iter().any(Proposal::changes_normal_stress));
    }

    #[test]
    fn each_time_falls_in_its_primitive() {
        let h = Primitive::Hold { hold_s: 100.0, v: 1.0, slip: 50.0 };
        let st = Primitive::Step { v: 10.0, slip: 100.0 };
        let p = Proposal { parts: vec![h, st] };
        // the hold spans (0, 150] s, the step (150, 160]
        let at = p.parts_at(&[1.0, 100.0, 150.0, 150.5, 160.0, 170.0]);
        assert_eq!(at, vec![&h, &h, &h, &st, &st, &st]);
        assert_eq!(Proposal { parts: vec![st] }.parts_at(&[0.5, 10.0]), vec![&st, &st]);
    }

    #[test]
    fn sampling_stands_for_every_sample() {
        let p = Proposal { parts: vec![Primitive::Hold { hold_s: 1000.0, v: 1.0, slip: 50.0 }] };
        let s = sampling(&p, 0.1, 1.0);
        assert_eq!(s.samples, 1000 + 500);
        let total: f64 = s.counts.iter().sum();
        assert!((total - 1500.0).abs() < 1e-6, "{total}");
        assert!(s.times.windows(2).all(|w| w[1] > w[0]));
        assert!((s.times.last().unwrap() - 1050.0).abs() < 1e-9);
        assert!(s.times.len() <= 2 * POINTS_PER_SEGMENT && s.times.len() > POINTS_PER_SEGMENT);
    }
}
