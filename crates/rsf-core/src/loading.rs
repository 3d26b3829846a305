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

/// A protocol segment: constant load-point velocity `v` (µm/s; 0 = hold) until `end`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// Load-point velocity, µm/s.
    pub v: f64,
    /// When the segment ends.
    pub end: SegmentEnd,
}

impl Segment {
    /// Constant velocity `v` (µm/s) for `duration` seconds.
    pub fn for_duration(v: f64, duration: f64) -> Self {
        Self { v, end: SegmentEnd::Duration(duration) }
    }
    /// Constant velocity `v` (µm/s) for `displacement` µm of load-point travel.
    pub fn for_displacement(v: f64, displacement: f64) -> Self {
        Self { v, end: SegmentEnd::Displacement(displacement) }
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

/// How the load point moves.
#[derive(Clone, Debug, PartialEq)]
pub enum Loading {
    /// A protocol: segments in order, starting at t = 0 with the load point at 0.
    Segments(Vec<Segment>),
    /// A measured record; output is at the record's own times.
    Record(LoadRecord),
}

/// A piece of constant load-point velocity `v` on `[t0, t1]` with the load point at `lp0` at
/// `t0`. Every velocity discontinuity is a piece boundary, so integrators stop on it exactly.
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
}

impl Piece {
    /// Load point at time `t` (µm).
    #[inline]
    pub fn load_point(&self, t: f64) -> f64 {
        self.lp0 + self.v * (t - self.t0)
    }
}

impl Loading {
    /// The constant-velocity pieces, or a message naming the bad segment (1-based) or sample.
    pub fn pieces(&self) -> Result<Vec<Piece>, String> {
        match self {
            Loading::Segments(segs) => {
                if segs.is_empty() {
                    return Err("the protocol has no segments".into());
                }
                let mut out = Vec::with_capacity(segs.len());
                let (mut t, mut lp) = (0.0, 0.0);
                for (i, s) in segs.iter().enumerate() {
                    let d = s.duration().map_err(|e| format!("segment {}: {e}", i + 1))?;
                    out.push(Piece { t0: t, t1: t + d, lp0: lp, v: s.v });
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
                    out.push(Piece { t0: t[0], t1: t[1], lp0: x[0], v });
                }
                Ok(out)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_become_pieces() {
        let l = Loading::Segments(vec![Segment::for_duration(1.0, 10.0), Segment::for_displacement(0.5, 2.0)]);
        let p = l.pieces().unwrap();
        assert_eq!(p[1], Piece { t0: 10.0, t1: 14.0, lp0: 10.0, v: 0.5 });
        assert_eq!(p[1].load_point(14.0), 12.0);
    }

    #[test]
    fn record_intervals_of_equal_velocity_merge() {
        // 0..2 s at 1 µm/s sampled every 0.5 s, then a hold, then 3 µm/s
        let time = vec![0.0, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 4.5];
        let load_point = vec![0.0, 0.5, 1.0, 1.5, 2.0, 2.0, 2.0, 3.5];
        let p = Loading::Record(LoadRecord { time, load_point }).pieces().unwrap();
        assert_eq!(p.len(), 3);
        assert_eq!((p[0].t0, p[0].t1, p[0].v), (0.0, 2.0, 1.0));
        assert_eq!((p[1].t0, p[1].t1, p[1].v), (2.0, 4.0, 0.0));
        assert_eq!((p[2].t0, p[2].t1, p[2].v, p[2].lp0), (4.0, 4.5, 3.0, 2.0));
    }

    #[test]
    fn bad_segments_are_named() {
        let e = Loading::Segments(vec![Segment::for_duration(1.0, 1.0), Segment::for_displacement(0.0, 2.0)])
            .pieces()
            .unwrap_err();
        assert!(e.contains("segment 2") && e.contains("hold"), "{e}");
        let e = Loading::Segments(vec![Segment::for_duration(1.0, -1.0)]).pieces().unwrap_err();
        assert!(e.contains("duration"), "{e}");
        let r = LoadRecord { time: vec![0.0, 1.0, 1.0], load_point: vec![0.0, 1.0, 2.0] };
        let e = Loading::Record(r).pieces().unwrap_err();
        assert!(e.contains("sample 2") && e.contains("does not increase"), "{e}");
        let r = LoadRecord { time: vec![0.0, 1.0], load_point: vec![0.0, f64::NAN] };
        assert!(Loading::Record(r).pieces().unwrap_err().contains("not finite"));
    }
}
