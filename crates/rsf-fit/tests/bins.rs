//! A large record fitted on bin means (`fit::bins`) against the fit on every sample: the same
//! parameters within a tenth of their standard errors, the same standard errors and sample
//! count, rms and likelihood per sample within the noise of their estimate, in both loading modes, on a record with holds and steps whose noise is
//! made by the synthetic generator's own recursion (white, and AR(1) with τ = 2 s).

use rsf_core::{Model, StateVariable};
use rsf_fit::fit::{FitOptions, FitResult, LoadingMode, fit, prepare};
use rsf_fit::segment::{SegmentOptions, detect};
use rsf_fit::synthetic::{Noise, record};
use rsf_laws::Slip;

fn both(loading: LoadingMode, noise: Noise) -> (FitResult, FitResult, usize) {
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(Slip, 0.014, 10.0));
    // 100 Hz in slides and holds: 36,000 samples
    let protocol = vec![
        (1.0, 50.0, 0.01),
        (10.0, 30.0, 0.01),
        (1.0, 80.0, 0.01),
        (0.0, 100.0, 0.01),
        (1.0, 60.0, 0.01),
        (0.3, 40.0, 0.01),
    ];
    let rec = record(&truth, 1.0, &protocol, noise, 7).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    // the white form in both: bins carry the samples' information under it (a fit on bin means
    // states it; the noise-model form needs the samples' residuals)
    let o = FitOptions {
        loading,
        starts: 2,
        uncertainty: rsf_fit::fit::Uncertainty::White,
        ..FitOptions::new(vec![std::sync::Arc::new(Slip)], 0.01)
    };
    let full = FitOptions { bins: rsf_fit::fit::BinMeans::Off, ..o.clone() };
    let binned = FitOptions {
        bins: rsf_fit::fit::BinMeans::Replace { above: 10_000, fraction: rsf_fit::fit::BIN_FRACTION },
        ..o
    };
    let (pf, pb) = (prepare(&rec, &segs, &full).unwrap(), prepare(&rec, &segs, &binned).unwrap());
    assert!(pf.binning.is_none());
    let bins = pb.used.len();
    assert_eq!(pb.binning.as_ref().unwrap().samples, pf.used.len());
    assert!(bins * 4 < pf.used.len(), "{bins} bins of {} samples", pf.used.len());
    let (a, b) = (fit(&pf, &full).unwrap(), fit(&pb, &binned).unwrap());
    // asked for the noise model, a fit on bin means states the white form, and says so
    let asked = FitOptions { uncertainty: rsf_fit::fit::Uncertainty::NoiseModel, ..binned.clone() };
    let c = fit(&pb, &asked).unwrap();
    assert_eq!(c.uncertainty, rsf_fit::fit::Uncertainty::White);
    assert!(c.noise.is_none());
    assert_eq!(c.stderr, b.stderr);
    (a, b, bins)
}

fn compare(loading: LoadingMode, noise: Noise) {
    let (f, b, bins) = both(loading, noise);
    println!("{loading:?} {noise:?}: {bins} bins of {} samples", f.n);
    for (name, se) in &f.stderr {
        let (x, y) = (f.params.as_initial(), b.params.as_initial());
        let get =
            |v: &[(rsf_fit::fit::ParamName, f64)]| v.iter().find(|(n, _)| n.text() == *name).map(|p| p.1).unwrap();
        let d = (get(&y) - get(&x)).abs() / se;
        let se_ratio = b.stderr[name] / se;
        println!(
            "  {name}: full {:.6e} ± {se:.2e}, bins {:.6e} ± {:.2e}: {d:.3} se apart",
            get(&x),
            get(&y),
            b.stderr[name]
        );
        assert!(d < 0.1, "{name}: {d} standard errors apart");
        assert!((se_ratio - 1.0).abs() < 0.05, "{name}: standard error ratio {se_ratio}");
    }
    assert_eq!(b.n, f.n);
    assert_eq!(b.bins, Some(bins));
    // the scatter inside the bins is estimated about a line (the model's slope is not noise):
    // unbiased for white noise, to within its sampling error (~√(2/bins) of the bins' share);
    // slow AR(1) noise inside a bin partly passes for a slope
    let rms_tol = if noise.tau > 0.0 { 0.01 } else { 0.003 };
    assert!((b.rms / f.rms - 1.0).abs() < rms_tol, "rms {} vs {}", b.rms, f.rms);
    let dll = (b.log_likelihood - f.log_likelihood).abs() / f.n as f64;
    assert!(dll < rms_tol, "ln L {} vs {}", b.log_likelihood, f.log_likelihood);
    let n = |r: &FitResult| r.segments.iter().map(|s| s.n).collect::<Vec<_>>();
    assert_eq!(n(&b), n(&f));
}

#[test]
fn bin_means_fit_as_every_sample_record_loading_white_noise() {
    compare(LoadingMode::Record, Noise { sigma: 1e-4, tau: 0.0 });
}

#[test]
fn bin_means_fit_as_every_sample_protocol_loading_ar1_noise() {
    compare(LoadingMode::Protocol, Noise { sigma: 1e-4, tau: 2.0 });
}

/// MCMC on bin means: the likelihood of the samples (each bin counts its samples, the scatter
/// inside the bins is part of every sum of squares), so σ is the samples' noise and the
/// intervals are the linearised ones (before, σ would have been the bin means' scatter).
#[test]
fn mcmc_on_bin_means_has_the_samples_noise_and_intervals() {
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(Slip, 0.014, 10.0));
    let protocol = vec![(1.0, 50.0, 0.01), (10.0, 30.0, 0.01), (1.0, 80.0, 0.01), (0.3, 40.0, 0.01)];
    let rec = record(&truth, 1.0, &protocol, Noise { sigma: 1e-4, tau: 0.0 }, 11).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let o = FitOptions {
        loading: LoadingMode::Protocol,
        starts: 1,
        bins: rsf_fit::fit::BinMeans::Replace { above: 10_000, fraction: rsf_fit::fit::BIN_FRACTION },
        // MCMC's likelihood is white: compared with the white linearised interval
        uncertainty: rsf_fit::fit::Uncertainty::White,
        ..FitOptions::new(vec![std::sync::Arc::new(Slip)], 0.01)
    };
    let p = prepare(&rec, &segs, &o).unwrap();
    assert!(p.binning.is_some());
    let f = fit(&p, &o).unwrap();
    let m = rsf_fit::mcmc::McmcOptions { samples: 6000, chains: 2, seed: 3, ..Default::default() };
    let r = rsf_fit::mcmc::run(&p, &o, &f, &m).unwrap();
    let sigma = r.params["sigma"].median;
    assert!((sigma / 1e-4 - 1.0).abs() < 0.03, "σ {sigma}");
    let ci = r.params["a"].ci95;
    let width = (ci[1] - ci[0]) / (2.0 * 1.96 * f.stderr["a"]);
    assert!((width - 1.0).abs() < 0.3, "a's 95% interval is {width} of the linearised one");
}

fn truth_and_record(seed: u64) -> (rsf_fit::data::Record, Vec<rsf_fit::segment::Segment>) {
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(Slip, 0.014, 10.0));
    let protocol =
        vec![(1.0, 50.0, 0.01), (10.0, 30.0, 0.01), (1.0, 80.0, 0.01), (0.0, 100.0, 0.01), (1.0, 60.0, 0.01)];
    let rec = record(&truth, 1.0, &protocol, Noise { sigma: 1e-4, tau: 0.0 }, seed).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    (rec, segs)
}

fn within_tenth_se(f: &FitResult, b: &FitResult) {
    for (name, se) in &f.stderr {
        let get = |r: &FitResult| r.params.as_initial().into_iter().find(|(n, _)| n.text() == *name).unwrap().1;
        let d = (get(b) - get(f)).abs() / se;
        assert!(d < 0.1, "{name}: {} against {}, {d} standard errors apart", get(b), get(f));
    }
}

/// Samples left out at the start of the record (an excluded window) stay in the binned record,
/// unused: a protocol-loading model's clock starts at the record's first sample, not at the
/// first bin. Before, the bins dropped them and the protocol ran 20 s early: the fit on bins
/// was off by many standard errors.
#[test]
fn bins_keep_the_record_clock_when_the_first_samples_are_left_out() {
    let (rec, segs) = truth_and_record(5);
    let t0 = rec.time[0];
    let o = FitOptions {
        loading: LoadingMode::Protocol,
        starts: 2,
        exclude: vec![(t0, t0 + 20.0)],
        ..FitOptions::new(vec![std::sync::Arc::new(Slip)], 0.01)
    };
    let full = FitOptions { bins: rsf_fit::fit::BinMeans::Off, ..o.clone() };
    let binned = FitOptions { bins: rsf_fit::fit::BinMeans::Replace { above: 1_000, fraction: 0.003 }, ..o };
    let (pf, pb) = (prepare(&rec, &segs, &full).unwrap(), prepare(&rec, &segs, &binned).unwrap());
    assert!(pf.used[0] > 0 && pb.binning.is_some());
    assert_eq!(pb.record.time[0], pf.record.time[0], "the binned record starts where the record does");
    within_tenth_se(&fit(&pf, &full).unwrap(), &fit(&pb, &binned).unwrap());
}

/// `BinMeans::Search` (the diagnosis's fits): the optimum sought on bin means, the result on
/// every sample — the curve, the sample count and the likelihood are the samples', the
/// parameters those of the fit on every sample within a tenth of a standard error, and the
/// likelihood within 0.05 of its maximum (the fit on every sample maximises it).
#[test]
fn search_on_bins_reports_on_every_sample() {
    let (rec, segs) = truth_and_record(9);
    let o = FitOptions {
        loading: LoadingMode::Protocol,
        starts: 2,
        ..FitOptions::new(vec![std::sync::Arc::new(Slip)], 0.01)
    };
    let full = FitOptions { bins: rsf_fit::fit::BinMeans::Off, ..o.clone() };
    let search = FitOptions { bins: rsf_fit::fit::BinMeans::Search { above: 1_000, fraction: 0.003 }, ..o };
    let p = prepare(&rec, &segs, &search).unwrap();
    assert!(p.binning.is_none(), "Search leaves the prepared record as it is");
    let (f, s) = (fit(&p, &full).unwrap(), fit(&p, &search).unwrap());
    assert_eq!(s.bins, None);
    assert_eq!((s.n, s.curve.model.len()), (f.n, f.curve.model.len()));
    within_tenth_se(&f, &s);
    let dll = f.log_likelihood - s.log_likelihood;
    assert!((-1e-6..0.05).contains(&dll), "ln L {} vs {}", s.log_likelihood, f.log_likelihood);
}
