//! Property tests of the V_i·t scaling identity (Bhattacharya et al. 2022, Eqs. 9–12):
//! for laws without a velocity scale of their own, holds from different initial slip rates
//! trace the same Δμ against V_i·t, equal to the solution of the non-dimensional system
//! (`rsf_core::nondim`), and step decreases follow the hold trajectory while V ≫ V_f.

use nalgebra::{SMatrix, SVector};
use proptest::prelude::*;
use rsf_core::Model;
use rsf_core::nondim::Nondimensional;
use rsf_solvers::{Dopri5, Integrator, OdeSystem, Rodas4, StepStats, solve};
use rsf_tests::{model1, problem_at};

const LAWS: [&str; 4] = ["aging", "slip", "prz", "nagata"];

/// The non-dimensional system of `rsf_core::nondim` as an ODE in T.
struct Nd<'a> {
    nd: Nondimensional<'a>,
    ratio: f64,
}
impl OdeSystem<2> for Nd<'_> {
    fn rhs(&self, _: f64, y: &SVector<f64, 2>) -> SVector<f64, 2> {
        let mut d = SVector::<f64, 2>::zeros();
        self.nd.rhs(self.ratio, y.as_slice(), d.as_mut_slice());
        d
    }
    fn rhs_and_jacobian(&self, _: f64, _: &SVector<f64, 2>) -> (SVector<f64, 2>, SMatrix<f64, 2, 2>) {
        unimplemented!("explicit integration only")
    }
    /// log variables: absolute error control, as in the dimensional solver
    fn error_scale(&self, _: usize, _: f64, _: f64, tol: &rsf_solvers::Tolerances) -> f64 {
        tol.rtol
    }
}

/// Δμ(T) at the non-dimensional times `ts` for a hold (ratio 0) or step (ratio V_f/V_i),
/// from the dimensional solver started at V_i.
fn dimensional(m: &Model, vi: f64, ratio: f64, ts: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let dc1 = m.states[0].dc;
    let times: Vec<f64> = ts.iter().map(|t| t * dc1 / vi).collect();
    let t_end = *times.last().unwrap();
    let p = problem_at(m.clone(), vi, &[(ratio * vi, t_end)], times);
    let sol = solve(&p, &Rodas4::new(1e-11, 1e-14)).unwrap();
    let mu_i = m.steady_state_friction(vi).unwrap();
    (sol.mu.iter().map(|x| x - mu_i).collect(), sol.slip_rate.iter().map(|v| v / vi).collect())
}

fn arb_model() -> impl Strategy<Value = Model> {
    (0usize..4, 0.005f64..0.02, 0.005f64..0.025, 0.5f64..50.0, -3.0f64..-1.0, 0.5f64..3.0)
        .prop_map(|(law, a, b, dc, lk, c)| model1(LAWS[law], a, b, dc, 10f64.powf(lk), c))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, .. ProptestConfig::default() })]

    /// Holds from V_i and from V_i·10^u give the same Δμ at the same V_i·t (to 1e-8), and both
    /// equal the non-dimensional solution.
    #[test]
    fn holds_collapse_on_vi_t(m in arb_model(), vi in 0.01f64..3.0, u in -2.0f64..2.0, t_end in 5.0f64..2000.0) {
        let ts: Vec<f64> = (0..=40).map(|i| t_end * (i as f64 / 40.0).powi(3)).collect();
        let (d1, _) = dimensional(&m, vi, 0.0, &ts);
        let (d2, _) = dimensional(&m, vi * 10f64.powf(u), 0.0, &ts);
        // direct integration of the non-dimensional system from its steady state (V' = 1, θ' = s)
        let nd = Nondimensional { model: &m, v_i: vi };
        let y0 = SVector::<f64, 2>::from_column_slice(&nd.to_nondimensional(vi, &m.steady_state_thetas(vi).unwrap()));
        let mut d3 = vec![nd.delta_mu(y0.as_slice())];
        let mut stats = StepStats::default();
        Dopri5::new(1e-12, 1e-14)
            .integrate(&Nd { nd, ratio: 0.0 }, 0.0, y0, t_end, 0.0, &ts[1..], &mut |_, y| d3.push(nd.delta_mu(y.as_slice())), &mut stats)
            .unwrap();
        for i in 0..ts.len() {
            prop_assert!((d1[i] - d2[i]).abs() < 1e-8, "T = {}: Δμ {} vs {}", ts[i], d1[i], d2[i]);
            prop_assert!((d1[i] - d3[i]).abs() < 1e-8, "T = {}: dimensional {} vs non-dimensional {}", ts[i], d1[i], d3[i]);
        }
        // a hold relaxes: Δμ decreases monotonically
        prop_assert!(d1.windows(2).all(|w| w[1] <= w[0] + 1e-12));
    }

    /// A step from V_i down to V_f follows the hold trajectory while V ≫ V_f: the difference
    /// grows no faster than the load-point term k Dc (V_f/V_i) T of Eq. 9, and never changes sign.
    #[test]
    fn step_decreases_track_the_hold(m in arb_model(), vi in 0.03f64..3.0, drop in 2.0f64..3.5, t_end in 5.0f64..500.0) {
        let ratio = 10f64.powf(-drop);
        let ts: Vec<f64> = (0..=40).map(|i| t_end * (i as f64 / 40.0).powi(2)).collect();
        let (hold, _) = dimensional(&m, vi, 0.0, &ts);
        let (step, vp) = dimensional(&m, vi, ratio, &ts);
        let kdc = m.stiffness * m.states[0].dc;
        for i in 0..ts.len() {
            if vp[i] < 10.0 * ratio {
                break;
            }
            let diff = step[i] - hold[i];
            prop_assert!(diff > -1e-9, "T = {}: step below hold by {}", ts[i], -diff);
            prop_assert!(diff <= kdc * ratio * ts[i] + 1e-9, "T = {}: {} > k Dc r T = {}", ts[i], diff, kdc * ratio * ts[i]);
        }
    }
}

/// The identity fails for Kato–Tullis (its cut-off Vc is a velocity scale): holds from 10 Vc
/// and 0.1 Vc separate.
#[test]
fn kato_tullis_breaks_the_identity() {
    let m = model1("kato-tullis", 0.01, 0.015, 2.0, 0.01, 0.05);
    let ts: Vec<f64> = (0..=20).map(|i| 200.0 * i as f64 / 20.0).collect();
    let (d1, _) = dimensional(&m, 0.5, 0.0, &ts);
    let (d2, _) = dimensional(&m, 0.005, 0.0, &ts);
    let max = d1.iter().zip(&d2).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(max > 1e-3, "max difference {max}");
}
