//! A fit's later starts run side by side on `FitOptions::threads`; the result is the one they
//! give one after another, bit for bit — also when the step budget cuts the later starts short
//! (a run made beside the others at a wider allowance is then made again at its own).

use rsf_core::{Model, StateVariable};
use rsf_fit::fit::{Budget, FitOptions, FitResult, fit, prepare};
use rsf_fit::segment::{SegmentOptions, detect};
use rsf_fit::synthetic::{Noise, record};
use rsf_laws::{Aging, law_by_name};

fn fitted(budget: Budget, threads: usize) -> FitResult {
    // Aging-law truth fitted with the Slip law: the starts end at different optima
    let m = Model::new(0.6, 1.0, 0.009, 0.01).with_state(StateVariable::new(Aging, 0.012, 8.0));
    let legs = [(1.0, 60.0, 0.05), (10.0, 30.0, 0.05), (0.3, 120.0, 0.05), (3.0, 60.0, 0.05)];
    let rec = record(&m, 1.0, &legs, Noise { sigma: 2e-4, tau: 0.5 }, 7).unwrap();
    let segs = detect(&rec.time, &rec.load_point, &SegmentOptions::default());
    let mut o = FitOptions::new(vec![law_by_name("slip", |_| None).unwrap()], 0.01);
    o.starts = 6;
    o.budget = budget;
    o.threads = threads;
    let p = prepare(&rec, &segs, &o).unwrap();
    fit(&p, &o).unwrap()
}

fn text(r: &FitResult) -> String {
    serde_json::to_string(r).unwrap()
}

#[test]
fn threads_do_not_change_a_fit() {
    let free = fitted(Budget::default(), 1);
    assert!(free.starts >= 5 && free.budget_hit.is_none(), "{} starts, {:?}", free.starts, free.budget_hit);
    for threads in [2, 3] {
        assert_eq!(text(&free), text(&fitted(Budget::default(), threads)), "{threads} threads");
    }
    // budgets that stop the later starts part-way, each at a different point of their runs
    for share in [0.35, 0.6, 0.85] {
        let budget = Budget::steps((free.steps as f64 * share) as u64);
        let one = fitted(budget, 1);
        assert!(one.steps <= budget.steps + free.steps / 4, "{} steps for a budget of {}", one.steps, budget.steps);
        assert_eq!(text(&one), text(&fitted(budget, 2)), "budget {share} of the free fit's work");
    }
}
