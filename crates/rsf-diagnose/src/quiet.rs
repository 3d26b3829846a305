//! The quiet test: is the slow wander that the noise model counts as noise there where no model
//! can carry error?
//!
//! A model's residuals get a fitted noise model (`rsf-noise`: white, AR(1) and a power-law drift),
//! and every score of the diagnosis is a likelihood under it. Its drift part is free: a wrong
//! model's slow, structured misfit — whole segments at the wrong level, a healing that is off
//! after every hold — has a spectrum like a random walk's, and the noise model reads it as
//! drift. The event test (`adequacy.rs`) then compares event windows with placebos that carry
//! the same offsets, the level test (`levels.rs`) allows for a fit uncertainty that the
//! inflated noise makes huge, and the record's misfit is "counted as noise". Real drift is not
//! locked to the protocol: it wanders inside a long stretch of steady sliding as much as
//! anywhere. Misfit is locked to it: inside such a stretch, after the segment's transient, every
//! model of the menu predicts a constant friction and its residual cannot wander.
//!
//! **Statistic.** In each quiet stretch of sliding (after [`WINDOW_DC`] times the model's
//! longest Dc of slip, as the event test's placebos), s = cᵀr, the mean residual over its last
//! quarter minus that over its first: how far the residuals wander across it. Under the fitted
//! noise model (covariance Σ at the samples' times, `rsf-noise`'s `covariance_times`, exact for
//! any sampling) the noise's own wander cᵀe has variance cᵀΣc. But a residual is what the fit
//! left of the noise: r = (I − JA)e for the least squares the diagnosis ran (J the model's
//! change per parameter, A = (JᵀJ)⁻¹Jᵀ), and where a transient still moves the model inside
//! a stretch, the fit spends its parameters on that stretch's wander too. So
//! v = Var(cᵀr) = cᵀΣc − 2 gᵀ(JᵀJ)⁻¹Jᵀ(Σc) + gᵀCg, with g = Jᵀc the parameters' change of the
//! wander and C = AΣAᵀ their covariance (`sensitivity.rs`): exact for the linearised fit, and
//! no larger than cᵀΣc for a stretch the fit cannot move. Over the K stretches whose quarters
//! hold at least [`MIN_WINDOW_SAMPLES`] samples, χ² = Σ s²/v is χ² with K degrees of freedom
//! when the model's noise is the residuals' noise.
//!
//! **Verdict, two ways.** With χ² ~ ρ·χ²_K for residuals that wander ρ times the claim in
//! variance (ρ = χ²/K, the `ratio`):
//!
//! - *Less than claimed: the drift is misfit.* The null ρ ≥ 1/[`ADEQUACY_EXCESS`] is rejected
//!   at p = P(χ²_K < [`ADEQUACY_EXCESS`]·χ²) < [`ADEQUACY_LEVEL`]: the variance the noise model
//!   holds that is not noise is at least as large as the noise's, significantly — the event
//!   test's size rule as one composite test. The slow part of the residuals is misfit the drift
//!   absorbed.
//! - *More than claimed: the stretches hold misfit.* A model whose approach to steady state is
//!   wrong (a law that mimics another's transient but not its tail) leaves a residual that
//!   still moves after [`WINDOW_DC`] Dc, in every stretch, while the noise model — fitted to
//!   the whole record — does not give the stretches that much slow wander; the event test's
//!   placebos lie in those stretches and carry the same misfit, so it cannot see it. Judged by
//!   the event test's rule (`rule.rs`'s `misfit`) on p = P(χ²_K > χ²) and the excess ρ.
//!
//! Either makes the model inadequate (`adequacy.rs`). The two tails are held to different
//! nulls because they are calibrated differently, as measured on the study sets' fits whose
//! law is the truth's (docs/diagnose/detection.md): a wander *below* the claim at p < 1 % under
//! ρ = 1 alone (with the event test's excess) happened on 9 of 192 such fits, not 1 % — few
//! stretches, and the fit's own share of the noise (e.g. the true PRZ fit of the `--outside`
//! study's record 56: its 9 stretches wander 0.18× the claim, p = 0.004 at ρ = 1, 0.05 under
//! the composite null); a wander *above* it, on none of them.

use super::rule::{ADEQUACY_EXCESS, Family, misfit, p_words, quiet_stretches};
#[cfg(doc)]
use super::rule::{ADEQUACY_LEVEL, WINDOW_DC};
use super::sensitivity::FitEffect;
use super::windows::MIN_WINDOW_SAMPLES;
use rsf_fit::fit::FitResult;
use rsf_fit::segment::Segment;
use rsf_noise::NoiseModel;
use serde::Serialize;
use statrs::distribution::ContinuousCDF;

/// One quiet stretch's wander.
#[derive(Clone, Debug, Serialize)]
pub struct QuietStretch {
    /// Start and end of the stretch, s.
    pub t: [f64; 2],
    /// The mean residual over its last quarter minus that over its first (friction).
    pub wander: f64,
    /// The standard deviation of that difference under the fitted noise model, the fit's own
    /// share of the noise taken out (friction).
    pub claimed: f64,
}

/// The quiet test of one fitted model.
#[derive(Clone, Debug, Serialize)]
pub struct QuietTest {
    /// χ²/K: the residuals' wander in the quiet stretches over the noise model's, in variance
    /// (1 when the model's noise is the residuals'; NaN with no stretch tested).
    pub ratio: f64,
    /// The probability of so little wander if the noise model claimed no more than
    /// [`ADEQUACY_EXCESS`] times the wander there is: P(χ²_K < [`ADEQUACY_EXCESS`]·χ²).
    pub p_below: f64,
    /// The probability of so much wander under the noise model: P(χ²_K > χ²).
    pub p_above: f64,
    /// The share of the residuals' variance the noise model puts in its drift part.
    pub drift_share: f64,
    /// Each tested stretch, in time order.
    pub stretches: Vec<QuietStretch>,
    /// The tests its level is shared with (`rule.rs`).
    pub family: Family,
}

impl QuietTest {
    /// No stretch to test.
    pub fn untested() -> Self {
        QuietTest {
            ratio: f64::NAN,
            p_below: f64::NAN,
            p_above: f64::NAN,
            drift_share: f64::NAN,
            stretches: vec![],
            family: Family::ALONE,
        }
    }

    /// The noise model claims wander the quiet stretches do not show: more than
    /// [`ADEQUACY_EXCESS`] times it, at p < [`ADEQUACY_LEVEL`] (shared by the test's
    /// [`Family`]). Its drift is misfit.
    pub fn drift_is_misfit(&self) -> bool {
        self.p_below < self.family.level()
    }

    /// The quiet stretches wander more than the noise model says, by the event test's rule: the
    /// model's transients still misfit there.
    pub fn stretches_misfit(&self) -> bool {
        misfit(self.p_above, self.ratio, self.family)
    }

    /// Whether the test ran (a stretch was tested).
    pub fn ran(&self) -> bool {
        self.p_above.is_finite()
    }

    /// Either: the model does not explain the record.
    pub fn inadequate(&self) -> bool {
        self.drift_is_misfit() || self.stretches_misfit()
    }

    /// The test in words, when it finds misfit.
    pub fn words(&self) -> Option<String> {
        let k = self.stretches.len();
        if self.drift_is_misfit() {
            // the slow part is the drift, or an AR(1) part of long correlation time where the
            // exact likelihood preferred one
            let held = if self.drift_share >= crate::DRIFT_NOTE_SHARE {
                format!("the noise model counts {:.0}% of their variance as drift", 100.0 * self.drift_share)
            } else {
                "their noise model makes them wander slowly".to_string()
            };
            Some(format!(
                "its residuals' slow part is misfit, not noise: {held}, yet inside the {k} quiet stretches of steady \
                 sliding, where no model can carry error, they wander {:.2}× as much in variance as that noise would \
                 make them (p = {})",
                self.ratio,
                p_words(self.p_below)
            ))
        } else if self.stretches_misfit() {
            Some(format!(
                "it still misfits after its transients: inside the {k} quiet stretches of steady sliding the \
                 residuals wander {:.2}× as much in variance as their noise model says (p = {})",
                self.ratio,
                p_words(self.p_above)
            ))
        } else {
            None
        }
    }
}

/// The quiet test of the fit `f` on the record's `segments` (those the fit used), under the
/// noise model `noise` fitted to its residuals, with the fit's own effect `effect` (the model's
/// change per parameter and their covariance under `noise`, `sensitivity.rs`).
pub fn quiet_test(f: &FitResult, segments: &[Segment], noise: &NoiseModel, effect: &FitEffect) -> QuietTest {
    let c = &f.curve;
    let n = c.time.len();
    let m = effect.changes.len();
    if effect.cov.len() != m * m || effect.changes.iter().any(|j| j.len() != n) {
        return QuietTest::untested();
    }
    // (JᵀJ)⁻¹ of the least squares the diagnosis ran, in the units of the steps
    let jtj = nalgebra::DMatrix::from_fn(m, m, |a, b| {
        effect.changes[a].iter().zip(&effect.changes[b]).map(|(x, y)| x * y).sum::<f64>()
    });
    let eps = 1e-12 * jtj.diagonal().max().max(1e-300);
    let Ok(jtj_inv) = jtj.pseudo_inverse(eps) else {
        return QuietTest::untested();
    };
    let cov = nalgebra::DMatrix::from_row_slice(m, m, &effect.cov);
    let dc_max = f.params.dc.iter().copied().fold(0.0f64, f64::max);
    let mut stretches = vec![];
    let mut chi2 = 0.0;
    for (a, b) in quiet_stretches(segments, dc_max) {
        let quarter = (b - a) / 4.0;
        let i0 = c.time.partition_point(|&t| t < a);
        let i1 = c.time.partition_point(|&t| t < a + quarter);
        let i2 = c.time.partition_point(|&t| t < b - quarter);
        let i3 = c.time.partition_point(|&t| t <= b);
        let (n1, n2) = (i1 - i0, i3 - i2);
        if n1 < MIN_WINDOW_SAMPLES || n2 < MIN_WINDOW_SAMPLES {
            continue;
        }
        // the two means' weights over the whole record (zero outside the stretch's quarters)
        let w: Vec<f64> = (0..n)
            .map(|i| {
                if (i0..i1).contains(&i) {
                    -1.0 / n1 as f64
                } else if (i2..i3).contains(&i) {
                    1.0 / n2 as f64
                } else {
                    0.0
                }
            })
            .collect();
        let sw = noise.covariance_times(&c.time, &[], &w);
        let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
        let g = nalgebra::DVector::from_iterator(m, effect.changes.iter().map(|j| dot(j, &w)));
        let js = nalgebra::DVector::from_iterator(m, effect.changes.iter().map(|j| dot(j, &sw)));
        let v = dot(&w, &sw) - 2.0 * g.dot(&(&jtj_inv * js)) + g.dot(&(&cov * &g));
        if !(v > 0.0 && v.is_finite()) {
            continue;
        }
        let s: f64 = (i0..i3).map(|i| w[i] * (c.data[i] - c.model[i])).sum();
        chi2 += s * s / v;
        stretches.push(QuietStretch { t: [a, b], wander: s, claimed: v.sqrt() });
    }
    let k = stretches.len();
    if k == 0 {
        return QuietTest::untested();
    }
    let chi = |f: &dyn Fn(&statrs::distribution::ChiSquared) -> f64| {
        statrs::distribution::ChiSquared::new(k as f64).map_or(f64::NAN, |d| f(&d))
    };
    QuietTest {
        ratio: chi2 / k as f64,
        p_below: chi(&|d| d.cdf(ADEQUACY_EXCESS * chi2.max(0.0))),
        p_above: chi(&|d| d.sf(chi2.max(0.0))),
        drift_share: noise.drift_share,
        stretches,
        family: Family::ALONE,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ADEQUACY_LEVEL;

    /// A true noise model is rejected far less often than the level: at K = 9 stretches, the
    /// chance that χ²_9 falls below half its 1 % quantile (a reader's check of the arithmetic
    /// in the module's doc).
    #[test]
    fn a_true_noise_model_is_rejected_rarely() {
        let d = statrs::distribution::ChiSquared::new(9.0).unwrap();
        let rate = d.cdf(d.inverse_cdf(ADEQUACY_LEVEL) / ADEQUACY_EXCESS);
        assert!(rate > 0.0005 && rate < 0.001, "{rate}");
    }
}
