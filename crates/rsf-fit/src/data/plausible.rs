//! Whether a record read in rsf's units looks like a friction experiment: a column scaled by
//! 1000, sign-flipped or swapped with another reads without error, and a fit of it "converges"
//! to a friction of 6 or −0.6 or a negative b. The reader refuses such a record, naming what
//! looks wrong and the likely cause, unless the caller accepts it
//! ([`ReadOptions::accept_implausible`](super::ReadOptions), `--accept-implausible`); accepted,
//! each finding is kept as a warning of the record.

use super::Record;
use serde::Serialize;

/// Friction of rocks and gouges, dry or wet, at lab and fault conditions: from about 0.1 (clay,
/// talc, serpentine) to about 0.9 (Byerlee 1978, most rocks 0.6–0.85), never near 0.05 nor
/// above 2 outside friction-enhancing contrivances. A median outside this range is a scaled,
/// mis-assigned or wrongly divided column far more often than a material.
pub const FRICTION_RANGE: (f64, f64) = (0.05, 2.0);

/// Load-point velocities of friction experiments, µm/s: from creep tests near 1e-4 µm/s and
/// holds (whose mean over a record is still above 1e-6 once any sliding is in it) to
/// high-velocity rotary shear at several m/s. A mean outside is a time or displacement unit
/// off by 1000 or more.
pub const LOAD_POINT_VELOCITY_RANGE: (f64, f64) = (1e-6, 1e7);

/// A typical rock friction, the reference for naming a scale factor.
const TYPICAL_FRICTION: f64 = 0.6;

/// Share of sample-to-sample increments that must be non-negative for a column to count as
/// "increasing" (a displacement), allowing for noise on holds.
const MONOTONE_SHARE: f64 = 0.95;

/// What looks wrong with a record. Closed: each finding has its own words in [`text`](Self::text).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "finding", rename_all = "snake_case")]
pub enum Implausible {
    /// The friction column is negative overall.
    NegativeFriction {
        /// Median friction.
        median: f64,
    },
    /// The friction column is outside [`FRICTION_RANGE`] overall.
    FrictionScale {
        /// Median friction.
        median: f64,
    },
    /// The friction column increases like a displacement while the load-point column stays in
    /// the range of friction.
    ColumnsSwapped {
        /// Median of the friction column.
        mu_median: f64,
        /// Median of the load-point column, µm.
        lp_median: f64,
    },
    /// The load point moves backwards overall.
    LoadPointBackwards {
        /// Mean load-point velocity, µm/s.
        velocity: f64,
    },
    /// The load point's mean velocity is outside [`LOAD_POINT_VELOCITY_RANGE`].
    LoadPointVelocity {
        /// Mean load-point velocity, µm/s.
        velocity: f64,
    },
}

impl Implausible {
    /// The finding in words, with its likely cause.
    pub fn text(&self) -> String {
        let (lo, hi) = FRICTION_RANGE;
        match *self {
            Implausible::NegativeFriction { median } => format!(
                "friction is negative (median {median:.4}): a sign-flipped friction or shear column? (friction of rocks \
                 and gouges is {lo}–{hi})"
            ),
            Implausible::FrictionScale { median } => {
                // the power of ten that would bring the median to a typical friction of 0.6
                let k = (median / TYPICAL_FRICTION).log10().round() as i32;
                let scaled = median / 10f64.powi(k);
                let hint = match k {
                    1..=6 if (lo..=hi).contains(&scaled) => format!(
                        " (×{} of a plausible friction: a unit or scale factor, e.g. kPa over MPa or percent?)",
                        10u64.pow(k as u32)
                    ),
                    -6..=-1 if (lo..=hi).contains(&scaled) => format!(
                        " (÷{} of a plausible friction: a unit or scale factor, e.g. MPa over kPa?)",
                        10u64.pow((-k) as u32)
                    ),
                    _ => " (a shear stress not divided by the normal stress, or another column?)".to_string(),
                };
                format!("friction has median {median:.4}, outside the {lo}–{hi} of rocks and gouges{hint}")
            }
            Implausible::ColumnsSwapped { mu_median, lp_median } => format!(
                "the friction column increases like a displacement (median {mu_median:.4}) while the load-point \
                 column stays near {lp_median:.4}, a friction: are the two columns swapped?"
            ),
            Implausible::LoadPointBackwards { velocity } => format!(
                "the load point moves backwards overall (mean velocity {velocity:.4e} µm/s): a sign-flipped \
                 displacement column?"
            ),
            Implausible::LoadPointVelocity { velocity } => {
                let (vlo, vhi) = LOAD_POINT_VELOCITY_RANGE;
                format!(
                    "the load point's mean velocity is {velocity:.3e} µm/s, outside the {vlo:e}–{vhi:e} µm/s of \
                     friction experiments: is --disp-unit or --time-unit right?"
                )
            }
        }
    }
}

/// Every finding on `rec` (empty when it looks like a friction experiment).
pub fn check(rec: &Record) -> Vec<Implausible> {
    let mut found = vec![];
    let n = rec.len();
    if n < 2 {
        return found;
    }
    let mu_median = median(&rec.mu);
    let lp_median = median(&rec.load_point);
    let (lo, hi) = FRICTION_RANGE;
    let in_range = |x: f64| (lo..=hi).contains(&x);
    if mu_median < 0.0 {
        found.push(Implausible::NegativeFriction { median: mu_median });
    } else if !in_range(mu_median) {
        if increasing(&rec.mu) && in_range(lp_median) && !increasing(&rec.load_point) {
            found.push(Implausible::ColumnsSwapped { mu_median, lp_median });
        } else {
            found.push(Implausible::FrictionScale { median: mu_median });
        }
    }
    let duration = rec.time[n - 1] - rec.time[0];
    let velocity = (rec.load_point[n - 1] - rec.load_point[0]) / duration;
    if velocity.is_finite() && !found.iter().any(|f| matches!(f, Implausible::ColumnsSwapped { .. })) {
        let (vlo, vhi) = LOAD_POINT_VELOCITY_RANGE;
        if velocity < 0.0 {
            found.push(Implausible::LoadPointBackwards { velocity });
        } else if !(vlo..=vhi).contains(&velocity) {
            found.push(Implausible::LoadPointVelocity { velocity });
        }
    }
    found
}

fn median(x: &[f64]) -> f64 {
    let mut v = x.to_vec();
    let mid = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(mid, |a, b| a.total_cmp(b));
    *m
}

/// Whether `x` increases as a displacement does: almost every increment non-negative, and a
/// net rise.
fn increasing(x: &[f64]) -> bool {
    let ups = x.windows(2).filter(|w| w[1] >= w[0]).count();
    ups as f64 >= MONOTONE_SHARE * (x.len() - 1) as f64 && x[x.len() - 1] > x[0]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A velocity step at 1 → 10 µm/s with friction near 0.6 and a little noise, 200 rows.
    fn record() -> Record {
        let mut r = Record::default();
        let mut lp = 0.0;
        for i in 0..200 {
            let t = i as f64 * 0.5;
            let v = if i < 100 { 1.0 } else { 10.0 };
            if i > 0 {
                lp += v * 0.5;
            }
            r.time.push(t);
            r.load_point.push(lp);
            r.mu.push(0.6 + 0.002 * ((i * 7919) % 13) as f64 / 13.0 - if i >= 100 { 0.003 } else { 0.0 });
        }
        r
    }

    #[test]
    fn a_friction_experiment_passes() {
        assert_eq!(check(&record()), vec![]);
    }

    /// The four: friction ×1000 (kPa over MPa), ×0.001, sign-flipped, and swapped with
    /// the load point; and a displacement in the wrong unit.
    #[test]
    fn scaled_flipped_and_swapped_columns_are_named() {
        let mut r = record();
        r.mu.iter_mut().for_each(|m| *m *= 1000.0);
        let f = check(&r);
        assert!(matches!(f[..], [Implausible::FrictionScale { .. }]), "{f:?}");
        assert!(f[0].text().contains("×1000"), "{}", f[0].text());

        let mut r = record();
        r.mu.iter_mut().for_each(|m| *m *= 0.001);
        let f = check(&r);
        assert!(f[0].text().contains("÷1000"), "{}", f[0].text());

        let mut r = record();
        r.mu.iter_mut().for_each(|m| *m = -*m);
        assert!(matches!(check(&r)[..], [Implausible::NegativeFriction { .. }]));

        let mut r = record();
        std::mem::swap(&mut r.mu, &mut r.load_point);
        let f = check(&r);
        assert!(matches!(f[..], [Implausible::ColumnsSwapped { .. }]), "{f:?}");
        assert!(f[0].text().contains("swapped"));

        let mut r = record();
        r.load_point.iter_mut().for_each(|x| *x = -*x);
        assert!(matches!(check(&r)[..], [Implausible::LoadPointBackwards { .. }]));

        // a displacement in metres read as µm: 1e-6 of the true velocity
        let mut r = record();
        r.load_point.iter_mut().for_each(|x| *x *= 1e-7);
        assert!(matches!(check(&r)[..], [Implausible::LoadPointVelocity { .. }]), "{:?}", check(&r));
    }

    /// Holds in a record do not make it implausible, nor does friction as low as clay's.
    #[test]
    fn long_holds_and_weak_gouge_pass() {
        let mut r = record();
        let last = *r.load_point.last().unwrap();
        let t_last = *r.time.last().unwrap();
        for i in 1..=100 {
            r.time.push(t_last + i as f64 * 100.0);
            r.load_point.push(last);
            r.mu.push(0.59);
        }
        r.mu.iter_mut().for_each(|m| *m *= 0.15);
        assert_eq!(check(&r), vec![]);
    }
}
