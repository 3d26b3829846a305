//! The slip rate during a 10⁴ s hold from V_i = 0.032 µm/s (the lab reaches ≈ 2·10⁻⁵ µm/s).
//!
//! `cargo run --release -p rsf-paper --example hold_slip_rate [OUT_DIR]` writes
//! `hold_slip_rate.{svg,csv,json}` to OUT_DIR (default `docs/figures`).

mod common;

use rsf_paper::csv::Csv;
use rsf_paper::numerics::log_grid;
use rsf_paper::params::STIFFNESS;
use rsf_paper::plot::{BLACK, LegendPosition, PALETTE, Panel, Series, lighter, render};
use rsf_paper::{Resolution, hold_slip_rate};

fn main() -> Result<(), rsf_paper::PaperError> {
    let fig = hold_slip_rate(&Resolution::figure())?;
    let mut csv = Csv::new(&["law", "a", "b", "dc_um", "time_s", "slip_rate_um_s"]);
    let mut p = Panel::new("slip rate during the hold", "time since hold start (s)", "slip rate V (µm/s)")
        .log_x()
        .log_y()
        .legend(LegendPosition::LowerLeft)
        .x_range(1e-3, 1e4);
    println!(
        "hold of {} s from V_i = {} µm/s (lab: about {:.0e} µm/s at the end):",
        fig.hold_duration, fig.v_i, fig.lab_v_end
    );
    for (i, l) in fig.laws.iter().enumerate() {
        let label = l.params.label();
        let (a, b, dc) = (format!("{}", l.params.a), format!("{}", l.params.b), format!("{}", l.params.dc));
        csv.curve(&[l.params.law, &a, &b, &dc], &l.time, &l.slip_rate);
        let pts = l.time.iter().copied().zip(l.slip_rate.iter().copied()).collect();
        p = p.with(Series::line(label.clone(), pts, PALETTE[i]));
        println!(
            "  {label}: V_end = {:.3e} µm/s = {:.4} nm/s (frozen-state bound {:.3e}{})",
            l.v_end,
            l.v_end * 1e3,
            l.v_frozen_state,
            l.v_aging_asymptote.map(|v| format!(", Aging asymptote (a−b)/(k t) = {v:.3e}")).unwrap_or_default()
        );
    }
    // the frozen-state solution a/(k t + a/V_i) of the hold-fitted Slip law's a: an upper bound
    let a = fig.laws[0].params.a;
    let frozen =
        log_grid(1e-3, fig.hold_duration, 200).into_iter().map(|t| (t, a / (STIFFNESS * t + a / fig.v_i))).collect();
    p = p.with(Series::dashed(format!("state frozen: a/(k t + a/V_i), a = {a}"), frozen, lighter(BLACK, 0.4)));
    p = p.with(Series::markers(
        "lab, end of a 10⁴ s hold".to_string(),
        vec![(fig.hold_duration, fig.lab_v_end)],
        BLACK,
    ));
    let svg = render("10⁴ s hold from 0.032 µm/s (k = 0.065 /µm)", &[p], 1, (820, 560))?;
    common::write_all("hold_slip_rate", &svg, &csv.finish(), &fig);
    Ok(())
}
