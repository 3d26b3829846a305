//! The standard segments a lab would run next without a design, each of the design's machine
//! time and within the same limits (`--v-range`, `--max-hold`, `--max-slip`): the yardsticks
//! a proposal's value is measured against. One of them cannot reach an effect another can (a
//! step never shows a cut-off below its slip rates; a hold does), so a design is compared
//! with each and with the best of them.

use super::DesignOptions;
use super::space::{MIN_SEGMENT_S, Primitive, Proposal};

/// The kinds of standard segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StandardKind {
    /// The longest hold the time allows, then a reslide at the record's last velocity for
    /// [`RESLIDE_DC`] of the baseline's Dc (or [`MIN_SEGMENT_S`] of sliding, if longer).
    HoldReslide,
    /// One decade down from the record's last velocity and back, half the time each.
    StepDownBack,
    /// One decade up and back, half the time each.
    StepUpBack,
}

rsf_core::vocabulary!(StandardKind, "standard segment", {
    HoldReslide => "hold_reslide",
    StepDownBack => "step_down_back",
    StepUpBack => "step_up_back",
});

/// The reslide after a standard hold, in the baseline's Dc: the peak and its return to steady
/// sliding, as a lab's slide–hold–slide test does.
pub const RESLIDE_DC: f64 = 10.0;

/// A standard step changes the velocity by this factor (one decade): the lab's usual step.
pub const STEP_FACTOR: f64 = 10.0;

/// Every standard segment of `machine_time` s from the record's last velocity `v_end` (µm/s),
/// on the slip scale `dc_ref` µm, that fits the options' limits: a slip the time would exceed
/// is shortened to `--max-slip`, a hold to `--max-hold`, a velocity kept within `--v-range`.
/// A kind that cannot fit (no hold allowed, no room above `v_end` in the range) is left out.
pub fn standards(v_end: f64, machine_time: f64, dc_ref: f64, o: &DesignOptions) -> Vec<(StandardKind, Proposal)> {
    let step_and_back = |v1: f64| {
        let half = (machine_time / 2.0).min(o.max_slip / (v1 + v_end));
        Proposal {
            parts: vec![Primitive::Step { v: v1, slip: v1 * half }, Primitive::Step { v: v_end, slip: v_end * half }],
        }
    };
    let mut out = vec![];
    for kind in StandardKind::ALL {
        let p = match kind {
            StandardKind::HoldReslide => {
                // at least the shortest segment a proposal holds, at most the slip allowed
                let slip =
                    (RESLIDE_DC * dc_ref).max(v_end * MIN_SEGMENT_S).min(o.max_slip).min(v_end * machine_time / 2.0);
                let hold_s = (machine_time - slip / v_end).min(o.max_hold);
                if !(hold_s > 0.0) {
                    continue;
                }
                Proposal { parts: vec![Primitive::Hold { hold_s, v: v_end, slip }] }
            }
            StandardKind::StepDownBack => step_and_back((v_end / STEP_FACTOR).max(o.v_range.0)),
            StandardKind::StepUpBack => {
                let v1 = (v_end * STEP_FACTOR).min(o.v_range.1);
                if !(v1 > v_end * (1.0 + 1e-9)) {
                    continue;
                }
                step_and_back(v1)
            }
        };
        if p.fits(o) {
            out.push((*kind, p));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each standard lasts the design's time unless a limit shortens it, and keeps the limits.
    #[test]
    fn the_standards_keep_the_time_and_the_limits() {
        let o = DesignOptions::default();
        let all = standards(1.0, 600.0, 10.0, &o);
        let kinds: Vec<StandardKind> = all.iter().map(|s| s.0).collect();
        assert_eq!(kinds, StandardKind::ALL);
        for (_, p) in &all[..2] {
            assert!((p.machine_time() - 600.0).abs() < 1e-9, "{p:?}");
        }
        // a step up of 300 s at 10 µm/s would slide 3 mm: shortened to 1 mm
        let up = &all[2].1;
        assert!((up.slip() - 1000.0).abs() < 1e-6 && up.machine_time() < 600.0);
        // no hold allowed: no hold standard; at the top of the range: no step up
        let o2 = DesignOptions { max_hold: 0.0, v_range: (1e-3, 1.0), ..DesignOptions::default() };
        let kinds: Vec<StandardKind> = standards(1.0, 600.0, 10.0, &o2).iter().map(|s| s.0).collect();
        assert_eq!(kinds, vec![StandardKind::StepDownBack]);
        // a decade down and back of 600 s from 3 µm/s slides 990 µm; with --max-slip 500 it is
        // shortened to 500 µm
        let o3 = DesignOptions { max_slip: 500.0, ..DesignOptions::default() };
        let down = standards(3.0, 600.0, 10.0, &o3).into_iter().find(|s| s.0 == StandardKind::StepDownBack).unwrap().1;
        assert_eq!(down.segments()[0].0, 0.3);
        assert!((down.slip() - 500.0).abs() < 1e-9 && down.machine_time() < 600.0);
        // a hold longer than --max-hold is capped
        let h = standards(1.0, 20000.0, 10.0, &o);
        assert!(matches!(h[0].1.parts[0], Primitive::Hold { hold_s, .. } if hold_s == 1e4));
    }
}
