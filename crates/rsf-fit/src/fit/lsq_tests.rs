//! The report at the search's own evaluation of its optimum against the report that solves the
//! problem there again: the same result to the last bit, on every sample and on bin means.

use super::super::{BinMeans, FitOptions, Uncertainty, prepare};
use super::{report, search};
use crate::segment::{SegmentOptions, detect};
use crate::synthetic::{Noise, record};
use rsf_core::{Model, StateVariable};
use rsf_laws::Slip;
use std::sync::Arc;

#[test]
fn the_search_s_evaluation_at_its_optimum_reports_as_a_new_solve() {
    let truth = Model::new(0.6, 1.0, 0.010, 0.01).with_state(StateVariable::new(Slip, 0.014, 10.0));
    let protocol = [(1.0, 20.0, 0.01), (10.0, 15.0, 0.01), (1.0, 30.0, 0.01), (0.0, 40.0, 0.01), (1.0, 30.0, 0.01)];
    let rec = record(&truth, 1.0, &protocol, Noise { sigma: 2e-4, tau: 0.5 }, 3).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let base = FitOptions { starts: 3, ..FitOptions::new(vec![Arc::new(Slip)], 0.01) };
    let ways = [
        FitOptions { bins: BinMeans::Off, uncertainty: Uncertainty::NoiseModel, ..base.clone() },
        FitOptions { bins: BinMeans::Search { above: 5_000, fraction: super::super::BIN_FRACTION }, ..base },
    ];
    for o in &ways {
        let p = prepare(&rec, &segs, o).unwrap();
        let pb = o.bins.search_points(&p);
        let on = pb.as_ref().unwrap_or(&p);
        let (kept, again) = (search(on, o).unwrap(), search(on, o).unwrap());
        // the search kept its evaluation of the optimum (else this test would compare a
        // report with itself)
        assert!(kept.at_best.as_ref().is_some_and(|b| b.theta == kept.best.theta), "{:?}", o.bins);
        let again = super::Searched { at_best: None, ..again };
        let (a, b) = (report(&p, pb.as_ref(), o, kept).unwrap(), report(&p, pb.as_ref(), o, again).unwrap());
        assert!(a.iterations > 2, "{}", a.iterations);
        assert_eq!(serde_json::to_string(&a).unwrap(), serde_json::to_string(&b).unwrap(), "{:?}", o.bins);
    }
}
