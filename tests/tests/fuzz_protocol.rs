//! The TOML protocol loader's boundary under random input (proptest):
//!
//! * **round trip**: random models and segment lists written as protocol text load back to
//!   exactly the numbers written (shortest round-trip formatting, as `{}` prints);
//! * **mutations**: random byte edits of the bundled example protocols never panic or hang;
//!   what loads has finite, valid numbers (the model validates).
//!
//! Case counts are proptest's (`PROPTEST_CASES`); docs/fuzzing.md records a longer campaign.

use proptest::prelude::*;
use rsf_core::{Loading, SegmentEnd};
use rsf_solvers::protocol;

fn examples() -> Vec<String> {
    let dir = rsf_tests::crate_dir().join("../examples");
    ["step_down.toml", "slide_hold_slide.toml", "two_state_mixed.toml", "normal_stress_steps.toml"]
        .iter()
        .map(|f| std::fs::read_to_string(dir.join(f)).unwrap())
        .collect()
}

#[derive(Debug, Clone)]
struct Written {
    mu0: f64,
    v0: f64,
    a: f64,
    k: f64,
    states: Vec<(&'static str, f64, f64)>,
    v_init: f64,
    segments: Vec<(f64, bool, f64)>,
}

fn written() -> impl Strategy<Value = Written> {
    (
        0.1f64..1.0,
        1e-3f64..1e3,
        1e-4f64..0.05,
        1e-4f64..10.0,
        prop::collection::vec((prop::sample::select(vec!["aging", "slip", "prz"]), -0.05f64..0.05, 1e-3f64..1e3), 1..4),
        1e-3f64..1e3,
        prop::collection::vec((1e-3f64..1e3, any::<bool>(), 1e-2f64..1e3), 1..6),
    )
        .prop_map(|(mu0, v0, a, k, states, v_init, segments)| Written { mu0, v0, a, k, states, v_init, segments })
}

fn text(w: &Written) -> String {
    let mut t = format!("[model]\nmu0 = {:?}\nv0 = {:?}\na = {:?}\nstiffness = {:?}\n", w.mu0, w.v0, w.a, w.k);
    for (law, b, dc) in &w.states {
        t += &format!("[[model.state]]\nlaw = \"{law}\"\nb = {b:?}\ndc = {dc:?}\n");
    }
    t += &format!("[loading]\nv_init = {:?}\n", w.v_init);
    for (v, by_time, x) in &w.segments {
        let end = if *by_time { "duration" } else { "displacement" };
        t += &format!("[[loading.segment]]\nv = {v:?}\n{end} = {x:?}\n");
    }
    t + "[output]\ndt = 1.0\n"
}

fn config() -> ProptestConfig {
    // a hang is a failure, not a stuck CI run
    ProptestConfig { timeout: 20_000, ..ProptestConfig::default() }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn protocols_load_back_the_numbers_written(w in written()) {
        let p = protocol::parse(&text(&w), None, "fuzz.toml").map_err(|e| TestCaseError::fail(e.to_string()))?;
        let m = &p.problem.model;
        prop_assert_eq!((m.mu0, m.v0, m.a, m.stiffness), (w.mu0, w.v0, w.a, w.k));
        prop_assert_eq!(m.states.len(), w.states.len());
        for (s, (_, b, dc)) in m.states.iter().zip(&w.states) {
            prop_assert_eq!((s.b, s.dc), (*b, *dc));
        }
        prop_assert_eq!(p.problem.v_init, w.v_init);
        let Loading::Segments(segs) = &p.problem.loading else { return Err(TestCaseError::fail("not segments")) };
        prop_assert_eq!(segs.len(), w.segments.len());
        for (s, (v, by_time, x)) in segs.iter().zip(&w.segments) {
            prop_assert_eq!(s.v, *v);
            let end = if *by_time { SegmentEnd::Duration(*x) } else { SegmentEnd::Displacement(*x) };
            prop_assert_eq!(s.end, end);
        }
    }

    #[test]
    fn mutated_protocols_never_panic(
        which in 0usize..4,
        edits in prop::collection::vec((0.0f64..1.0, prop::sample::select(vec![
            b'=', b'[', b']', b'"', b'\n', b'#', b'.', b'-', b'e', b'0', b'9', b'x', b' ', 0xFF, b'{', b',',
        ]), 0u8..3), 1..8),
    ) {
        let mut bytes = examples()[which].clone().into_bytes();
        for (at, byte, op) in edits {
            let i = ((bytes.len() as f64) * at) as usize;
            match op {
                0 => bytes.insert(i.min(bytes.len()), byte),
                1 if i < bytes.len() => { bytes.remove(i); }
                _ if i < bytes.len() => bytes[i] = byte,
                _ => {}
            }
        }
        let Ok(text) = String::from_utf8(bytes) else { return Ok(()) };
        if let Ok(p) = protocol::parse(&text, None, "fuzz.toml") {
            let m = &p.problem.model;
            prop_assert!(m.validate().is_ok());
            prop_assert!([m.mu0, m.v0, m.a, m.stiffness].iter().all(|x| !x.is_nan()));
            prop_assert!(p.problem.v_init.is_finite() && p.problem.v_init > 0.0);
        }
    }
}
