//! A record's clock may start anywhere: the answer does not depend on where (found by
//! rsf-testkit's `time_shift`: a record starting at 10⁶ s failed at its first step, the first
//! step guess being below what 10⁶ s resolves).

use rsf_core::{LoadRecord, Loading, Model, StateVariable};
use rsf_laws::KatoTullis;
use rsf_solvers::{Dopri5, OutputTimes, Problem, Rodas4, Solution, solve};

/// 60 Hz record: 1 µm/s, then 1e-3 µm/s, then 1 µm/s again, starting at `t0`.
fn run(t0: f64, implicit: bool) -> Solution {
    let m = Model::new(0.6, 1.0, 0.005, 0.03).with_state(StateVariable::new(KatoTullis { vc: 0.05 }, 0.02, 1.0));
    let (mut time, mut load_point, mut x) = (vec![], vec![], 0.0);
    for i in 0..=300 {
        if i > 0 {
            x += if (101..=200).contains(&i) { 1e-3 } else { 1.0 } / 60.0;
        }
        time.push(t0 + i as f64 / 60.0);
        load_point.push(x);
    }
    let mut p = Problem::new(m, Loading::Record(LoadRecord { time: time.clone(), load_point }), 1.0, 1.0);
    p.output = OutputTimes::Times(time);
    if implicit { solve(&p, &Rodas4::new(1e-10, 1e-13)) } else { solve(&p, &Dopri5::new(1e-10, 1e-13)) }
        .unwrap_or_else(|e| panic!("clock at {t0} s: {e}"))
}

#[test]
fn a_record_starting_at_a_million_seconds_solves_as_one_starting_at_zero() {
    for implicit in [false, true] {
        let (a, b) = (run(0.0, implicit), run(1e6, implicit));
        let worst = a.mu.iter().zip(&b.mu).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
        // the shifted times carry ~1e-10 s of rounding: far below the tolerance's 1e-8
        assert!(worst < 1e-8, "implicit {implicit}: friction differs by {worst:e}");
    }
}
