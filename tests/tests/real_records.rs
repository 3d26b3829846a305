//! The readers and the segmentation on every real record in ../shared/data (the unlicensed
//! ones stay there; this test prints SKIP when the folder is absent). Expected protocols are
//! those stated in each record's SOURCE.md.

use rsf_fit::data::{ReadOptions, read_record};
use rsf_fit::segment::{SegmentKind, SegmentOptions, detect};
use rsf_tests::shared_data;

fn opts(t: &str, x: &str, mu: &str) -> ReadOptions {
    ReadOptions { time_col: t.into(), lp_col: x.into(), mu_col: mu.into(), ..Default::default() }
}

/// (velocity, start time) of every moving segment, for comparisons.
fn moving(segs: &[rsf_fit::segment::Segment]) -> Vec<(f64, f64)> {
    segs.iter().filter(|s| s.v != 0.0).map(|s| (s.v, s.t0)).collect()
}

#[test]
fn giacomel_records_load_and_segment() {
    let Some(dir) = shared_data("giacomel-steadystate") else {
        println!("SKIP: ../shared/data/giacomel-steadystate not found");
        return;
    };
    let o = opts("Time(s)", "Displ(microns)", "Friction");
    for (file, rows, steps) in [
        ("demo-branch/velstep4_BRAVA_expb819_basalt.txt", 5849, vec![(2.98, 10.12)]),
        ("main-history/velstep7_BRAVA_expb819_basalt.txt", 4508, vec![(100.07, 300.11)]),
        ("main-history/velstep7_BRAVA_expb819_basalt_Giacomel_et_al_2021.txt", 3948, vec![(100.07, 300.11)]),
        ("demo-branch/velstep3_TR2_exp013_sepiolite.txt", 0, vec![]),
        ("main-history/velstep1_TR2_exp013_sepiolite.txt", 0, vec![]),
        ("main-history/velstep2_TR2_exp013_sepiolite.txt", 0, vec![]),
        ("main-history/velstep3_TR2_exp013_sepiolite.txt", 0, vec![]),
    ] {
        let r = read_record(&dir.join(file), &o).unwrap_or_else(|e| panic!("{e}"));
        if rows > 0 {
            assert_eq!(r.len(), rows, "{file}");
        }
        let segs = detect(&r.time, &r.load_point, &SegmentOptions::default());
        let mv = moving(&segs);
        println!(
            "{file}: {} rows, {} segments, velocities {:?}",
            r.len(),
            segs.len(),
            mv.iter().map(|m| m.0).collect::<Vec<_>>()
        );
        for (v0, v1) in steps {
            assert_eq!(mv.len(), 2, "{file}: {segs:?}");
            assert!((mv[0].0 / v0 - 1.0).abs() < 0.02 && (mv[1].0 / v1 - 1.0).abs() < 0.02, "{file}: {mv:?}");
        }
        if file.contains("sepiolite") {
            // sepiolite steps 0.2 <-> 2 µm/s: at least one step, all velocities near 0.2 or 2
            assert!(mv.len() >= 2, "{file}: {mv:?}");
            for (v, _) in &mv {
                assert!((v / 0.2 - 1.0).abs() < 0.1 || (v / 2.0 - 1.0).abs() < 0.1, "{file}: v = {v}");
            }
        }
    }
}

#[test]
fn penn_state_records_load_and_segment() {
    let Some(dir) = shared_data("psu-xlook-examples") else {
        println!("SKIP: ../shared/data/psu-xlook-examples not found");
        return;
    };
    let o = opts("time_s", "lp_disp_um", "mu");
    let r = read_record(&dir.join("p655intact100_reduced.csv"), &o).unwrap();
    assert_eq!(r.len(), 86813);
    let segs = detect(&r.time, &r.load_point, &SegmentOptions::default());
    // the up-steps of SOURCE.md: 3058.44 (2.29→22.85), 3082.19 (→228.8), 3852.37 (2.31→22.87), 3875.38 (→229.0)
    for (t, v) in [(3058.44, 22.85), (3082.19, 228.8), (3852.37, 22.87), (3875.38, 229.0)] {
        let s = segs
            .iter()
            .find(|s| (s.t0 - t).abs() < 0.1)
            .unwrap_or_else(|| panic!("p655: no segment starting at {t} s: {segs:?}"));
        assert!((s.v / v - 1.0).abs() < 0.02 && s.kind == SegmentKind::StepUp, "p655 at {t}: {s:?}");
    }
    // the ≈47 s load-point stop at 2636.7 s and the σn change at 3173.8–3331.1 s are holds
    for t in [2636.7, 3173.8] {
        assert!(segs.iter().any(|s| s.kind == SegmentKind::Hold && (s.t0 - t).abs() < 1.0), "p655: no hold at {t}");
    }
    let r = read_record(&dir.join("p446s7tr005_reduced.csv"), &o).unwrap();
    let segs = detect(&r.time, &r.load_point, &SegmentOptions::default());
    // the 5 MPa staircase 1 → 3 → 10 → 30 → 100 → 300 → 100 → 30 → 10 → 3 → 1 µm/s (1303–2490 s)
    let stair: Vec<f64> =
        segs.iter().filter(|s| s.t0 > 1290.0 && s.t0 < 2450.0 && s.t1 - s.t0 > 1.0).map(|s| s.v).collect();
    let want = [1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 100.0, 30.0, 10.0, 3.0, 1.0];
    assert_eq!(stair.len(), want.len(), "p446 staircase {stair:?}");
    for (v, w) in stair.iter().zip(want) {
        assert!((v / w - 1.0).abs() < 0.05, "p446 staircase {stair:?}");
    }
}

#[test]
fn leeman_records_load_and_segment() {
    let Some(dir) = shared_data("leeman2016-p4309") else {
        println!("SKIP: ../shared/data/leeman2016-p4309 not found");
        return;
    };
    let o = opts("Time", "LP_Disp", "mu");
    for (file, rows, v0, v1, t_step) in
        [("step_2_model.txt", 1164, 11.97, 1.199, 2536.22), ("step_35_model.txt", 607, 1.197, 12.01, 2645.38)]
    {
        let r = read_record(&dir.join(file), &o).unwrap();
        assert_eq!(r.len(), rows);
        let segs = detect(&r.time, &r.load_point, &SegmentOptions::default());
        assert_eq!(segs.len(), 2, "{file}: {segs:?}");
        assert!((segs[0].v / v0 - 1.0).abs() < 0.02 && (segs[1].v / v1 - 1.0).abs() < 0.02, "{file}: {segs:?}");
        assert!((segs[1].t0 - t_step).abs() < 0.2, "{file}: step at {}", segs[1].t0);
    }
}
