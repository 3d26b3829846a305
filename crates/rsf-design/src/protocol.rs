//! A proposal as a protocol file for `rsf simulate` (and the machine): the best credible
//! model, the proposal's segments from steady state at the record's end velocity.

use super::Design;
use std::fmt::Write;

/// Most rows the protocol's `rsf simulate` output should have (a preview, not the lab's sampling).
const OUTPUT_ROWS: f64 = 20_000.0;

/// The TOML protocol of the proposal ranked `rank` (1-based) of `d`, or `None` when there is
/// none. The model is the best credible one; the run starts in steady state at the record's end
/// velocity (the design's own predictions carry the record's history instead).
pub fn protocol_toml(d: &Design, rank: usize) -> Option<String> {
    let r = d.proposals.iter().find(|r| r.rank == rank)?;
    let m = d.models.first()?;
    let p = &m.params;
    let mut s = String::new();
    let _ = writeln!(s, "# rsf design: proposal {rank} — {}", r.description);
    let _ = writeln!(
        s,
        "# machine time {:.0} s, load-point displacement {:.1} µm; expected to settle {:.2} of {} model pairs",
        r.machine_time_s,
        r.slip_um,
        r.score,
        r.pairs.len()
    );
    let names: Vec<String> = d.models.iter().map(|m| format!("{} (ΔBIC {:.1})", m.name, m.delta_bic)).collect();
    let _ = writeln!(s, "# credible models: {}", names.join(", "));
    let _ = writeln!(s, "# model below: {} — {}; starts in steady state at {} µm/s", m.name, m.extension, d.v_end);
    if p.g != 0.0 {
        let _ = writeln!(s, "# its slip trend g = {:e} /µm is not part of rsf simulate's model", p.g);
    }
    let _ = writeln!(s, "[model]\nmu0 = {:?}\nv0 = {:?}\na = {:?}\nstiffness = {:?}", p.mu0, p.v0, p.a, p.k);
    if p.a_slope != 0.0 {
        let _ = writeln!(s, "a_slope = {:?}", p.a_slope);
    }
    let sigma = r.normal_stress.iter().any(|&x| x != 1.0);
    if sigma {
        let _ = writeln!(
            s,
            "normal_stress = 1.0   # σ in units of the record's σ (only ratios enter; scale every σ by it for MPa)"
        );
    }
    for (i, law) in p.laws.iter().enumerate() {
        let _ = writeln!(s, "\n[[model.state]]\nlaw = \"{law}\"\nb = {:?}\ndc = {:?}", p.b[i], p.dc[i]);
        if let Some(&alpha) = p.alpha.get(i).filter(|&&x| x != 0.0 && sigma) {
            let _ = writeln!(s, "alpha = {alpha:?}");
        }
        for (name, v) in &p.law_params {
            if name.strip_suffix(&(i + 1).to_string()).is_some_and(|n| n.chars().all(|c| c.is_ascii_alphabetic())) {
                let _ = writeln!(s, "{} = {v:?}", name.trim_end_matches(|c: char| c.is_ascii_digit()));
            }
        }
    }
    let _ = writeln!(s, "\n[loading]\nv_init = {:?}", d.v_end);
    let mut level = 1.0;
    for (&(v, dur), &to) in r.segments.iter().zip(&r.normal_stress) {
        let _ = writeln!(s, "\n[[loading.segment]]\nv = {v:?}\nduration = {dur:?}");
        if to != level {
            let _ = writeln!(s, "normal_stress_rate = {:?}   # σ ramps to {to:?} × the record's", (to - level) / dur);
            level = to;
        }
    }
    // the record's own interval, coarsened to at most OUTPUT_ROWS rows for a long proposal
    let _ = writeln!(s, "\n[output]\ndt = {:?}", d.dt_slide_s.max(r.machine_time_s / OUTPUT_ROWS));
    Some(s)
}
