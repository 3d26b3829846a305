//! Load-point histories, reduced to pieces of constant load-point velocity.

use serde::{Deserialize, Serialize};

/// How a protocol segment ends.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum SegmentEnd {
    /// After this many seconds.
    Duration(f64),
    /// After this much load-point displacement, µm (same sign as the velocity).
    Displacement(f64),
}

/// A protocol segment: constant load-point velocity `v` (µm/s; 0 = hold) until `end`, with
/// the normal stress optionally stepped at its start and ramped through it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// Load-point velocity, µm/s.
    pub v: f64,
    /// When the segment ends.
    pub end: SegmentEnd,
    /// Normal stress from the segment's start, MPa: an instantaneous step at fixed load point
    /// (`None`: σ carries on from the previous segment).
    pub normal_stress: Option<f64>,
    /// Normal-stress rate through the segment, MPa/s (after the step, if any); 0: constant.
    pub normal_stress_rate: f64,
}

impl Segment {
    /// Constant velocity `v` (µm/s) for `duration` seconds.
    pub fn for_duration(v: f64, duration: f64) -> Self {
        Self { v, end: SegmentEnd::Duration(duration), normal_stress: None, normal_stress_rate: 0.0 }
    }
    /// Constant velocity `v` (µm/s) for `displacement` µm of load-point travel.
    pub fn for_displacement(v: f64, displacement: f64) -> Self {
        Self { v, end: SegmentEnd::Displacement(displacement), normal_stress: None, normal_stress_rate: 0.0 }
    }
    /// Steps the normal stress to `sigma` (MPa) at the segment's start.
    pub fn with_normal_stress(mut self, sigma: f64) -> Self {
        self.normal_stress = Some(sigma);
        self
    }
    /// Ramps the normal stress at `rate` (MPa/s) through the segment.
    pub fn with_normal_stress_rate(mut self, rate: f64) -> Self {
        self.normal_stress_rate = rate;
        self
    }
    /// Whether the segment changes the normal stress.
    pub fn changes_normal_stress(&self) -> bool {
        self.normal_stress.is_some() || self.normal_stress_rate != 0.0
    }
    /// Duration in s, or a message naming what is wrong.
    pub fn duration(&self) -> Result<f64, String> {
        if !self.v.is_finite() {
            return Err(format!("v = {} is not finite", self.v));
        }
        match self.end {
            SegmentEnd::Duration(d) => {
                if d > 0.0 && d.is_finite() {
                    Ok(d)
                } else {
                    Err(format!("duration = {d} must be positive and finite"))
                }
            }
            SegmentEnd::Displacement(x) => {
                if self.v == 0.0 {
                    Err("a hold (v = 0) cannot end after a displacement; give a duration".into())
                } else if !(x.is_finite() && x != 0.0 && x.signum() == self.v.signum()) {
                    Err(format!("displacement = {x} must be finite, non-zero and of the sign of v = {}", self.v))
                } else {
                    Ok(x / self.v)
                }
            }
        }
    }
}

/// A measured load-point history: load-point displacement (µm) at strictly increasing times
/// (s), taken as piecewise linear between samples.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoadRecord {
    /// Times, s, strictly increasing.
    pub time: Vec<f64>,
    /// Load-point displacement, µm.
    pub load_point: Vec<f64>,
}

impl LoadRecord {
    /// Checks the record: at least two samples, equal lengths, finite values, strictly
    /// increasing time. The message names the first offending sample (0-based).
    pub fn validate(&self) -> Result<(), String> {
        if self.time.len() != self.load_point.len() {
            return Err(format!("{} times but {} load-point values", self.time.len(), self.load_point.len()));
        }
        if self.time.len() < 2 {
            return Err("a load-point record needs at least two samples".into());
        }
        for (i, (&t, &x)) in self.time.iter().zip(&self.load_point).enumerate() {
            if !t.is_finite() {
                return Err(format!("sample {i}: time {t} is not finite"));
            }
            if !x.is_finite() {
                return Err(format!("sample {i}: load point {x} is not finite"));
            }
            if i > 0 && t <= self.time[i - 1] {
                return Err(format!("sample {i}: time {t} s does not increase (previous {} s)", self.time[i - 1]));
            }
        }
        Ok(())
    }
}

/// A measured normal-stress history: σ (MPa) at strictly increasing times (s), piecewise
/// linear between samples (like a [`LoadRecord`]'s load point).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NormalStressRecord {
    /// Times, s, strictly increasing.
    pub time: Vec<f64>,
    /// Normal stress, MPa (> 0).
    pub sigma: Vec<f64>,
}

impl NormalStressRecord {
    /// Checks the record: at least two samples, equal lengths, finite and positive σ, strictly
    /// increasing time. The message names the first offending sample (0-based).
    pub fn validate(&self) -> Result<(), String> {
        if self.time.len() != self.sigma.len() {
            return Err(format!("{} times but {} normal-stress values", self.time.len(), self.sigma.len()));
        }
        if self.time.len() < 2 {
            return Err("a normal-stress record needs at least two samples".into());
        }
        for (i, (&t, &s)) in self.time.iter().zip(&self.sigma).enumerate() {
            if !t.is_finite() {
                return Err(format!("normal-stress sample {i}: time {t} is not finite"));
            }
            if !(s > 0.0 && s.is_finite()) {
                return Err(format!("normal-stress sample {i}: σ = {s} MPa must be positive and finite"));
            }
            if i > 0 && t <= self.time[i - 1] {
                return Err(format!(
                    "normal-stress sample {i}: time {t} s does not increase (previous {} s)",
                    self.time[i - 1]
                ));
            }
        }
        Ok(())
    }

    /// Whether σ changes at all.
    pub fn varies(&self) -> bool {
        self.sigma.iter().any(|&s| s != self.sigma[0])
    }

    /// The record simplified to the fewest vertices that keep every sample within `tol` MPa of
    /// the polyline (Ramer–Douglas–Peucker, deterministic): a noisy but piecewise-steady σ then
    /// costs the integrator a few pieces instead of one per sample.
    pub fn simplified(&self, tol: f64) -> NormalStressRecord {
        let n = self.time.len();
        let mut keep = vec![false; n];
        keep[0] = true;
        keep[n - 1] = true;
        let mut stack = vec![(0usize, n - 1)];
        while let Some((i0, i1)) = stack.pop() {
            if i1 <= i0 + 1 {
                continue;
            }
            let (t0, s0, t1, s1) = (self.time[i0], self.sigma[i0], self.time[i1], self.sigma[i1]);
            let slope = (s1 - s0) / (t1 - t0);
            let (mut worst, mut at) = (0.0, i0);
            for j in i0 + 1..i1 {
                let d = (self.sigma[j] - (s0 + slope * (self.time[j] - t0))).abs();
                if d > worst {
                    worst = d;
                    at = j;
                }
            }
            if worst > tol {
                keep[at] = true;
                stack.push((i0, at));
                stack.push((at, i1));
            }
        }
        let idx: Vec<usize> = (0..n).filter(|&i| keep[i]).collect();
        NormalStressRecord {
            time: idx.iter().map(|&i| self.time[i]).collect(),
            sigma: idx.iter().map(|&i| self.sigma[i]).collect(),
        }
    }

    /// The same history with every time shifted by `dt` seconds.
    pub fn shifted(&self, dt: f64) -> NormalStressRecord {
        NormalStressRecord { time: self.time.iter().map(|t| t + dt).collect(), sigma: self.sigma.clone() }
    }
}

/// How the load point moves.
#[derive(Clone, Debug, PartialEq)]
pub enum Loading {
    /// A protocol: segments in order, starting at t = 0 with the load point at 0.
    Segments(Vec<Segment>),
    /// A measured record; output is at the record's own times.
    Record(LoadRecord),
}

/// A piece of constant load-point velocity `v` and constant normal-stress rate on `[t0, t1]`,
/// with the load point at `lp0` and the normal stress at `sigma0` at `t0`. Every velocity
/// discontinuity, normal-stress step and change of normal-stress rate is a piece boundary, so
/// integrators stop on it exactly. A normal-stress step is a piece whose `sigma0` differs from
/// where the previous piece ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// Start time, s.
    pub t0: f64,
    /// End time, s.
    pub t1: f64,
    /// Load point at `t0`, µm.
    pub lp0: f64,
    /// Load-point velocity, µm/s.
    pub v: f64,
    /// Normal stress at `t0` (after any step there), MPa.
    pub sigma0: f64,
    /// Normal-stress rate, MPa/s.
    pub sigma_rate: f64,
}

impl Piece {
    /// Load point at time `t` (µm).
    #[inline]
    pub fn load_point(&self, t: f64) -> f64 {
        self.lp0 + self.v * (t - self.t0)
    }
    /// Normal stress at time `t` (MPa).
    #[inline]
    pub fn normal_stress(&self, t: f64) -> f64 {
        if self.sigma_rate == 0.0 { self.sigma0 } else { self.sigma0 + self.sigma_rate * (t - self.t0) }
    }
    /// Normal stress at the end of the piece (MPa).
    pub fn sigma_end(&self) -> f64 {
        self.normal_stress(self.t1)
    }
}

/// Whether any piece changes the normal stress (a step or a ramp).
pub fn normal_stress_varies(pieces: &[Piece]) -> bool {
    pieces.iter().any(|p| p.sigma_rate != 0.0 || p.sigma0 != pieces[0].sigma0)
}

impl Loading {
    /// The pieces at constant normal stress `sigma` (MPa): see [`pieces_with`](Self::pieces_with).
    pub fn pieces(&self, sigma: f64) -> Result<Vec<Piece>, String> {
        self.pieces_with(sigma, None)
    }

    /// The pieces, or a message naming the bad segment (1-based) or sample. The normal stress
    /// starts at `sigma_init` (MPa) and follows the segments' `normal_stress` steps and ramps,
    /// or the measured history `normal_stress` (piecewise linear; it must span the loading) —
    /// not both.
    pub fn pieces_with(
        &self,
        sigma_init: f64,
        normal_stress: Option<&NormalStressRecord>,
    ) -> Result<Vec<Piece>, String> {
        if !(sigma_init > 0.0 && sigma_init.is_finite()) {
            return Err(format!("normal stress {sigma_init} MPa must be positive and finite"));
        }
        let mut pieces = self.load_point_pieces(sigma_init)?;
        if let Some(h) = normal_stress {
            if let Loading::Segments(segs) = self {
                if let Some(i) = segs.iter().position(|s| s.changes_normal_stress()) {
                    return Err(format!(
                        "segment {}: the normal stress is given both by the segments and by a record",
                        i + 1
                    ));
                }
            }
            pieces = split_by_history(&pieces, h)?;
        }
        Ok(pieces)
    }

    fn load_point_pieces(&self, sigma_init: f64) -> Result<Vec<Piece>, String> {
        let constant = |t0, t1, lp0, v| Piece { t0, t1, lp0, v, sigma0: sigma_init, sigma_rate: 0.0 };
        match self {
            Loading::Segments(segs) => {
                if segs.is_empty() {
                    return Err("the protocol has no segments".into());
                }
                let mut out = Vec::with_capacity(segs.len());
                let (mut t, mut lp, mut sigma) = (0.0, 0.0, sigma_init);
                for (i, s) in segs.iter().enumerate() {
                    let d = s.duration().map_err(|e| format!("segment {}: {e}", i + 1))?;
                    if let Some(sn) = s.normal_stress {
                        if !(sn > 0.0 && sn.is_finite()) {
                            return Err(format!(
                                "segment {}: normal_stress = {sn} must be positive and finite (MPa)",
                                i + 1
                            ));
                        }
                        // the first segment's value is the initial normal stress, not a step
                        sigma = sn;
                    }
                    let rate = s.normal_stress_rate;
                    if !rate.is_finite() {
                        return Err(format!("segment {}: normal_stress_rate = {rate} is not finite", i + 1));
                    }
                    let end = sigma + rate * d;
                    if !(end > 0.0) {
                        return Err(format!(
                            "segment {}: the normal stress ramps from {sigma} to {end} MPa; it must stay positive",
                            i + 1
                        ));
                    }
                    let piece = Piece { sigma0: sigma, sigma_rate: rate, ..constant(t, t + d, lp, s.v) };
                    if rate != 0.0 {
                        // the next piece starts where this one ends, as the solvers compute it
                        // ((t + d) − t may differ from d in the last bit): no spurious step
                        sigma = piece.sigma_end();
                    }
                    out.push(piece);
                    t += d;
                    lp += s.v * d;
                }
                Ok(out)
            }
            Loading::Record(r) => {
                r.validate()?;
                // Consecutive intervals of exactly the same velocity (to round-off) are one
                // piece: a synthetic or idealized record then costs what its protocol costs.
                let mut out: Vec<Piece> = Vec::new();
                for (t, x) in r.time.windows(2).zip(r.load_point.windows(2)) {
                    let v = (x[1] - x[0]) / (t[1] - t[0]);
                    if let Some(last) = out.last_mut() {
                        // equal to round-off of the recorded numbers, and the merged line still
                        // passes through this sample to 1e-10 of its value
                        if (v - last.v).abs() <= 1e-9 * v.abs().max(last.v.abs())
                            && (last.load_point(t[1]) - x[1]).abs() <= 1e-10 * x[1].abs().max(1.0)
                        {
                            last.t1 = t[1];
                            continue;
                        }
                    }
                    out.push(constant(t[0], t[1], x[0], v));
                }
                Ok(out)
            }
        }
    }
}

/// A normal-stress sample and a piece boundary this many ulps of their time apart (64 ε |t|)
/// coincide: a piece that short is a rounding apart, not a time an integrator can step across.
const SLIVER_ULPS: f64 = 64.0;

/// Splits constant-σ `pieces` at the vertices of the history `h` and gives each piece σ and its
/// rate from `h`. Consecutive pieces continue each other's σ exactly (no spurious steps).
fn split_by_history(pieces: &[Piece], h: &NormalStressRecord) -> Result<Vec<Piece>, String> {
    h.validate()?;
    let (t_start, t_end) = (pieces[0].t0, pieces[pieces.len() - 1].t1);
    let span = (t_end - t_start).abs().max(1.0);
    if h.time[0] > t_start + 1e-9 * span || h.time[h.time.len() - 1] < t_end - 1e-9 * span {
        return Err(format!(
            "the normal-stress record spans [{}, {}] s but the loading [{t_start}, {t_end}] s",
            h.time[0],
            h.time[h.time.len() - 1]
        ));
    }
    // the interval of h containing t (the last one starting at or before t)
    let interval = |t: f64| h.time.partition_point(|&x| x <= t).clamp(1, h.time.len() - 1) - 1;
    let slope = |j: usize| (h.sigma[j + 1] - h.sigma[j]) / (h.time[j + 1] - h.time[j]);
    let at = |t: f64| {
        let j = interval(t);
        h.sigma[j] + slope(j) * (t - h.time[j])
    };
    // a sample of h within this of a piece's boundary starts or ends no piece of its own: a
    // sliver of a few ulps (a measured σ sampled at the detected break time, a rounding apart)
    // is a piece no integrator can step across
    let tol = SLIVER_ULPS * f64::EPSILON * t_start.abs().max(t_end.abs()).max(1.0);
    let mut out: Vec<Piece> = Vec::with_capacity(pieces.len());
    for p in pieces {
        let mut t0 = p.t0;
        loop {
            let mut j = interval(t0);
            while j + 1 < h.time.len() - 1 && h.time[j + 1] - t0 <= tol {
                j += 1;
            }
            let t1 = if j + 1 < h.time.len() - 1 { h.time[j + 1].min(p.t1) } else { p.t1 };
            let t1 = if t1 <= t0 || p.t1 - t1 <= tol { p.t1 } else { t1 };
            let sigma0 = match out.last() {
                Some(prev) if prev.t1 == t0 => prev.sigma_end(),
                _ => at(t0),
            };
            let rate = slope(j);
            out.push(Piece { t0, t1, lp0: p.load_point(t0), v: p.v, sigma0, sigma_rate: rate });
            if t1 >= p.t1 {
                break;
            }
            t0 = t1;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A measured σ sampled a few ulps before (or after) a break of the loading makes no piece
    /// of a few ulps (no integrator steps across one), and σ stays continuous.
    #[test]
    fn a_normal_stress_sample_at_a_break_makes_no_sliver() {
        let t_break = 5892.632341782755;
        for ulps in [-12.0, 0.0, 12.0] {
            let t_s = t_break + ulps * 9.094947017729282e-13;
            let l = Loading::Segments(vec![Segment::for_duration(0.1, t_break), Segment::for_duration(3.0, 50.0)]);
            let h = NormalStressRecord {
                time: vec![0.0, t_s - 0.4, t_s, t_s + 0.4, t_s + 0.8, t_break + 60.0],
                sigma: vec![10.0, 10.0, 10.0, 10.8, 11.6, 11.6],
            };
            let p = l.pieces_with(10.0, Some(&h)).unwrap();
            assert!(p.iter().all(|q| q.t1 - q.t0 > 1e-6), "{ulps}: {p:?}");
            assert!(p.windows(2).all(|w| (w[1].sigma0 - w[0].sigma_end()).abs() < 1e-9 && w[1].t0 == w[0].t1));
            let last = p.last().unwrap();
            assert!((last.sigma_end() - 11.6).abs() < 1e-6, "{ulps}: {}", last.sigma_end());
        }
    }

    #[test]
    fn segments_become_pieces() {
        let l = Loading::Segments(vec![Segment::for_duration(1.0, 10.0), Segment::for_displacement(0.5, 2.0)]);
        let p = l.pieces(1.0).unwrap();
        assert_eq!(p[1], Piece { t0: 10.0, t1: 14.0, lp0: 10.0, v: 0.5, sigma0: 1.0, sigma_rate: 0.0 });
        assert_eq!(p[1].load_point(14.0), 12.0);
    }

    #[test]
    fn record_intervals_of_equal_velocity_merge() {
        // 0..2 s at 1 µm/s sampled every 0.5 s, then a hold, then 3 µm/s
        let time = vec![0.0, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 4.5];
        let load_point = vec![0.0, 0.5, 1.0, 1.5, 2.0, 2.0, 2.0, 3.5];
        let p = Loading::Record(LoadRecord { time, load_point }).pieces(1.0).unwrap();
        assert_eq!(p.len(), 3);
        assert_eq!((p[0].t0, p[0].t1, p[0].v), (0.0, 2.0, 1.0));
        assert_eq!((p[1].t0, p[1].t1, p[1].v), (2.0, 4.0, 0.0));
        assert_eq!((p[2].t0, p[2].t1, p[2].v, p[2].lp0), (4.0, 4.5, 3.0, 2.0));
    }

    #[test]
    fn bad_segments_are_named() {
        let e = Loading::Segments(vec![Segment::for_duration(1.0, 1.0), Segment::for_displacement(0.0, 2.0)])
            .pieces(1.0)
            .unwrap_err();
        assert!(e.contains("segment 2") && e.contains("hold"), "{e}");
        let e = Loading::Segments(vec![Segment::for_duration(1.0, -1.0)]).pieces(1.0).unwrap_err();
        assert!(e.contains("duration"), "{e}");
        let r = LoadRecord { time: vec![0.0, 1.0, 1.0], load_point: vec![0.0, 1.0, 2.0] };
        let e = Loading::Record(r).pieces(1.0).unwrap_err();
        assert!(e.contains("sample 2") && e.contains("does not increase"), "{e}");
        let r = LoadRecord { time: vec![0.0, 1.0], load_point: vec![0.0, f64::NAN] };
        assert!(Loading::Record(r).pieces(1.0).unwrap_err().contains("not finite"));
        let e = Loading::Segments(vec![Segment::for_duration(1.0, 10.0).with_normal_stress_rate(-2.0)])
            .pieces(10.0)
            .unwrap_err();
        assert!(e.contains("segment 1") && e.contains("positive"), "{e}");
    }

    #[test]
    fn normal_stress_steps_and_ramps_become_pieces() {
        let l = Loading::Segments(vec![
            Segment::for_duration(1.0, 10.0),
            Segment::for_duration(1.0, 10.0).with_normal_stress(12.0),
            Segment::for_duration(0.0, 5.0).with_normal_stress_rate(0.4),
            Segment::for_duration(1.0, 1.0),
        ]);
        let p = l.pieces(10.0).unwrap();
        assert_eq!(p.iter().map(|p| p.sigma0).collect::<Vec<_>>(), vec![10.0, 12.0, 12.0, 14.0]);
        assert_eq!(p[2].sigma_rate, 0.4);
        assert_eq!(p[2].sigma_end(), 14.0);
        assert!(normal_stress_varies(&p));
        assert!(!normal_stress_varies(&Loading::Segments(vec![Segment::for_duration(1.0, 1.0)]).pieces(3.0).unwrap()));
        // ramps at awkward times continue exactly: a step appears only where one is written
        let segs: Vec<Segment> =
            (0..50).map(|i| Segment::for_duration(1.0, 0.1 + 0.013 * i as f64).with_normal_stress_rate(0.37)).collect();
        let p = Loading::Segments(segs).pieces(10.0).unwrap();
        assert!(p.windows(2).all(|w| w[1].sigma0 == w[0].sigma_end()));
    }

    #[test]
    fn a_measured_normal_stress_splits_pieces_continuously() {
        let l = Loading::Segments(vec![Segment::for_duration(1.0, 10.0), Segment::for_duration(0.0, 10.0)]);
        let h = NormalStressRecord { time: vec![0.0, 4.0, 15.0, 20.0], sigma: vec![5.0, 5.0, 10.0, 10.0] };
        let p = l.pieces_with(5.0, Some(&h)).unwrap();
        let cuts: Vec<(f64, f64)> = p.iter().map(|p| (p.t0, p.t1)).collect();
        assert_eq!(cuts, vec![(0.0, 4.0), (4.0, 10.0), (10.0, 15.0), (15.0, 20.0)]);
        for w in p.windows(2) {
            assert_eq!(w[1].sigma0, w[0].sigma_end(), "no step at {}", w[1].t0);
        }
        assert!((p[2].sigma_end() - 10.0).abs() < 1e-12 && p[3].sigma_rate == 0.0);
        assert_eq!(p[1].lp0, 4.0);
        let short = NormalStressRecord { time: vec![1.0, 20.0], sigma: vec![5.0, 5.0] };
        assert!(l.pieces_with(5.0, Some(&short)).unwrap_err().contains("spans"));
        let both = Loading::Segments(vec![Segment::for_duration(1.0, 20.0).with_normal_stress(6.0)]);
        assert!(both.pieces_with(5.0, Some(&h)).unwrap_err().contains("both"));
    }

    #[test]
    fn simplification_keeps_steps_and_drops_noise() {
        let time: Vec<f64> = (0..200).map(|i| i as f64 * 0.1).collect();
        let sigma: Vec<f64> = time
            .iter()
            .enumerate()
            .map(|(i, &t)| if t < 10.0 { 5.0 } else { 7.0 } + 1e-4 * ((i * 7919) % 13) as f64 / 13.0)
            .collect();
        let h = NormalStressRecord { time, sigma };
        let s = h.simplified(1e-3);
        assert!(s.time.len() <= 6, "{} vertices", s.time.len());
        assert!(s.time.contains(&9.9) && s.time.contains(&10.0));
    }
}
