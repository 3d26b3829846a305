//! Calibration: over repeated synthetic trials (independent noise, white, σ = 2e-4), the 95%
//! intervals cover the true parameters at about their nominal rate — both the linearised
//! (covariance) intervals of the LM fit and the MCMC credible intervals.

use rsf_core::{Model, StateVariable};
use rsf_fit::fit::{FitOptions, LoadingMode, fit, prepare};
use rsf_fit::mcmc::{self, McmcOptions};
use rsf_fit::segment::{SegmentOptions, detect};
use rsf_fit::synthetic::{Noise, record};
use rsf_laws::{Slip, law_by_name};

#[test]
fn intervals_cover_the_truth_at_their_nominal_rate() {
    let truth = Model::new(0.6, 1.0, 0.010, 0.005).with_state(StateVariable::new(Slip, 0.013, 8.0));
    let protocol = [(1.0, 30.0, 0.1), (10.0, 10.0, 0.1), (1.0, 60.0, 0.1), (0.1, 200.0, 0.2)];
    let (mut lm_hits, mut mc_hits, mut total) = (0, 0, 0);
    let trials = 24;
    let mut rhat_max: f64 = 0.0;
    for seed in 0..trials {
        let rec = record(&truth, 1.0, &protocol, Noise { sigma: 2e-4, tau: 0.0 }, 100 + seed).unwrap();
        let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
        let mut opts = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], 0.005);
        opts.loading = LoadingMode::Protocol;
        let p = prepare(&rec, &segs, &opts).unwrap();
        let r = fit(&p, &opts).unwrap();
        let m = McmcOptions { samples: 6000, chains: 2, seed, ..Default::default() };
        let mc = mcmc::run(&p, &opts, &r, &m).unwrap();
        for (name, t) in [("a", truth.a), ("b1", 0.013), ("dc1", 8.0)] {
            let ci = r.ci95[name];
            lm_hits += usize::from(ci[0] <= t && t <= ci[1]);
            let pc = &mc.params[name];
            mc_hits += usize::from(pc.ci95[0] <= t && t <= pc.ci95[1]);
            rhat_max = rhat_max.max(pc.rhat);
            total += 1;
        }
    }
    let (lm_rate, mc_rate) = (lm_hits as f64 / total as f64, mc_hits as f64 / total as f64);
    println!(
        "coverage of 95% intervals over {trials} trials × 3 parameters: LM {lm_rate:.3}, MCMC {mc_rate:.3}; max R-hat {rhat_max:.3}"
    );
    // 72 intervals at 95%: a binomial 99% range is about 0.85–1.0
    assert!((0.85..=1.0).contains(&lm_rate), "LM coverage {lm_rate}");
    assert!((0.85..=1.0).contains(&mc_rate), "MCMC coverage {mc_rate}");
    assert!(rhat_max < 1.1, "R-hat {rhat_max}");
}
