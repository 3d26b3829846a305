//! Is the lead of the cause chosen over its best credible rival a property of the data?
//!
//! Two causes' models are not nested (a Kato–Tullis cut-off and a weighted Aging–Slip law each
//! bend the Slip law a different way), and when the truth is neither — power-law aging, say —
//! the record may prefer one by tens of ΔBIC on its noise alone: another draw of the same
//! noise would prefer the other. A fixed ΔBIC margin ([`crate::UNDECIDED_DBIC`]) cannot tell
//! that lead from a real one, because how far two models' log-likelihoods move apart by chance
//! grows with how differently they predict.
//!
//! For Gaussian noise of covariance Σ and two models predicting m₁ and m₂, the log-likelihood
//! ratio is a fixed part plus εᵀΣ⁻¹Δ (ε the noise, Δ = m₁ − m₂): its chance spread is
//! exactly √(ΔᵀΣ⁻¹Δ). When neither model is closer to the truth (Vuong 1989, *Econometrica*
//! 57:307, whose null this is) the BIC-penalised ratio over that spread is standard normal; the
//! lead is the record's when its one-sided chance is below the false-alarm level. Vuong's own
//! estimate of the spread, the sample variance of per-term differences, is not used: a friction
//! model's difference sits in a few slow transients (a few Fourier frequencies), whose unequal
//! sizes it would count as noise. Both models are read under one noise model, the chosen fit's
//! own (Whittle's quadratic form, or the Kalman-whitened difference of a model in time).
//!
//! When the truth is one of the two, its lead is about ½ΔᵀΣ⁻¹Δ and z = ½√(ΔᵀΣ⁻¹Δ): the test
//! is passed by every pair of models whose predictions differ by more than about 5 standard
//! deviations of the noise (ΔᵀΣ⁻¹Δ > 27), and fails where they differ by less.
//!
//! **When it decides** (`run.rs`). Vuong's null, that neither model is the truth, is the live
//! possibility where nothing checked that the model chosen explains the record: its adequacy
//! untestable (no event with a quiet stretch to compare, too few events alike to compare with
//! each other). There a lead that does not hold leaves the verdict `undecided`. Where the model
//! chosen passed the event tests, it explains the record to the noise level, and a smaller
//! lead still names it: the rival, were it the truth, would lead by about ½ΔᵀΣ⁻¹Δ itself
//! (Cox's test of the rival, which no diagnosis of the study sets fails). The lead is reported
//! in either case.

use rsf_noise::NoiseModel;
use serde::Serialize;

/// The lead of one fit over another against its chance spread.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Lead {
    /// The lead in ln L under the chosen fit's noise model, BIC-penalised (½ ln n per free
    /// parameter).
    pub lead: f64,
    /// The chance spread of the log-likelihood ratio, √(ΔᵀΣ⁻¹Δ).
    pub sd: f64,
    /// `lead / sd`: standard normal when neither model is closer to the truth.
    pub z: f64,
    /// The chance that the better of two models equally close to the truth leads by this much,
    /// 2(1 − Φ(z)) (two-sided: the chosen one is the better by choice).
    pub p: f64,
}

impl Lead {
    /// Whether the lead holds at the false-alarm `level`.
    pub fn holds(&self, level: f64) -> bool {
        self.p < level
    }
}

/// One fit as the test reads it: its residuals at the record's sample times and its free
/// parameters.
pub(super) struct Side<'a> {
    /// Data minus model.
    pub(super) residuals: &'a [f64],
    /// The fit's free parameters (BIC's penalty).
    pub(super) n_free: usize,
}

/// The test of the chosen fit's lead over the rival's at the sample `times`, both read under
/// one `noise` model (the chosen fit's own): their log-likelihoods, penalised as BIC is by
/// ½ ln `n` per free parameter, and the spread of their ratio. `None` when the residuals are
/// not sampled alike.
pub(super) fn lead(chosen: Side, rival: Side, times: &[f64], n: usize, noise: &NoiseModel) -> Option<Lead> {
    let (rc, rr) = (chosen.residuals, rival.residuals);
    if rc.len() != times.len() || rr.len() != times.len() || times.len() < 2 {
        return None;
    }
    let ll = noise.log_likelihoods_at(&[rc, rr], times);
    let penalty = 0.5 * (chosen.n_free as f64 - rival.n_free as f64) * (n.max(2) as f64).ln();
    let lead = ll[0] - ll[1] - penalty;
    // the models' difference: Δ = m_c − m_r = r_r − r_c; every model fits its own μ0, and both
    // likelihoods leave the mean out
    let mut delta: Vec<f64> = rr.iter().zip(rc).map(|(a, b)| a - b).collect();
    let mean = delta.iter().sum::<f64>() / delta.len() as f64;
    delta.iter_mut().for_each(|d| *d -= mean);
    let q = match &noise.sampling {
        None => noise.quadratic_form(&delta),
        Some(_) => {
            let mut w = [delta];
            rsf_noise::whiten(noise, times, &vec![1.0; times.len()], &mut w);
            w[0].iter().map(|x| x * x).sum()
        }
    };
    let sd = q.max(0.0).sqrt();
    let z = if sd > 0.0 { lead / sd } else { f64::INFINITY.copysign(lead) };
    let p = statrs::function::erf::erfc(z / std::f64::consts::SQRT_2).min(1.0);
    Some(Lead { lead, sd, z, p })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    /// Two models equally wrong in different places: the leads chance gives one over the other
    /// hold as often as the level says; the truth's lead over a model that misfits by twice the noise holds.
    #[test]
    fn a_lead_by_chance_holds_at_the_level_and_a_real_one_holds() {
        let n = 2000;
        let times: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let bump =
            |c: f64, h: f64| -> Vec<f64> { times.iter().map(|t| h * (-((t - c) / 100.0).powi(2)).exp()).collect() };
        let noise = NoiseModel::white(1.0, n, 1.0);
        let white = Normal::new(0.0, 1.0).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let (ma, mb, mt, mc) = (bump(500.0, 0.5), bump(1500.0, 0.5), vec![0.0; n], bump(1000.0, 2.0));
        let (mut held, mut truth_held, draws) = (0, 0, 400);
        for _ in 0..draws {
            let data: Vec<f64> = (0..n).map(|_| white.sample(&mut rng)).collect();
            let r = |m: &[f64]| -> Vec<f64> { data.iter().zip(m).map(|(d, m)| d - m).collect() };
            let (ra, rb, rt, rc) = (r(&ma), r(&mb), r(&mt), r(&mc));
            let side = |r| Side { residuals: r, n_free: 0 };
            let ll = |r: &[f64]| noise.log_likelihood_at(r, &times);
            // the better of the two wrong models, chosen as a diagnosis would
            let (best, other) = if ll(&ra) > ll(&rb) { (&ra, &rb) } else { (&rb, &ra) };
            let t = lead(side(best), side(other), &times, n, &noise).unwrap();
            assert!(t.lead >= 0.0);
            held += usize::from(t.holds(0.05));
            truth_held += usize::from(lead(side(&rt), side(&rc), &times, n, &noise).unwrap().holds(0.01));
        }
        let rate = held as f64 / draws as f64;
        assert!((0.025..0.085).contains(&rate), "chance leads held on {rate}");
        assert_eq!(truth_held, draws);
    }
}
