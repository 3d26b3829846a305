//! Fig. 3A/B of Bhattacharya et al. (2022): holds from V_i = 1, 0.32 and 0.032 µm/s against
//! time and against V_i·t, and step decreases following the hold trajectory.
//!
//! `cargo run --release -p rsf-paper --example fig3_holds [OUT_DIR]` writes
//! `fig3_holds.{svg,csv,json}` to OUT_DIR (default `docs/figures`).

mod common;

use rsf_paper::csv::Csv;
use rsf_paper::plot::{BLACK, LegendPosition, Panel, Series, ordered_color, render};
use rsf_paper::{HOLD_VI, Resolution, fig3_holds};

fn main() -> Result<(), rsf_paper::PaperError> {
    let fig = fig3_holds(&Resolution::figure())?;
    let mut csv = Csv::new(&["law", "v_i_um_s", "v_lp_um_s", "vi_t_um", "delta_mu", "slip_rate_um_s"]);
    let mut by_time = Panel::new("A  holds against time", "time since hold start (s)", "μ − μ_ss(V_i)")
        .log_x()
        .legend(LegendPosition::LowerLeft);
    let mut by_vit = Panel::new("B  the same holds against V_i·t", "V_i·t (µm)", "μ − μ_ss(V_i)")
        .log_x()
        .legend(LegendPosition::LowerLeft);
    for h in &fig.holds {
        let i = HOLD_VI.iter().position(|&v| v == h.v_i).expect("a Fig. 3 initial rate");
        let color = ordered_color(i, HOLD_VI.len());
        let label = format!("{}, V_i = {} µm/s", h.params.name(), h.v_i);
        let t: Vec<(f64, f64)> = h.vi_t.iter().zip(&h.delta_mu).map(|(x, y)| (x / h.v_i, *y)).collect();
        let g: Vec<(f64, f64)> = h.vi_t.iter().copied().zip(h.delta_mu.iter().copied()).collect();
        let (a, b) = if h.params.law == "slip" {
            (Series::line(label.clone(), t, color), Series::line(label, g, color))
        } else {
            (Series::dashed(label.clone(), t, color), Series::dashed(label, g, color))
        };
        by_time = by_time.with(a);
        by_vit = by_vit.with(b);
    }
    let mut steps = Panel::new("C  Slip law: steps from 3 µm/s track the hold", "V_i·t (µm)", "μ − μ_ss(V_i)")
        .log_x()
        .legend(LegendPosition::LowerLeft)
        .y_range(-0.11, 0.03);
    for (j, s) in fig.steps.iter().enumerate() {
        let pts: Vec<(f64, f64)> = s.vi_t.iter().copied().zip(s.delta_mu.iter().copied()).collect();
        steps = steps.with(if s.v_lp == 0.0 {
            Series::line("hold (V_lp = 0)".to_string(), pts, BLACK)
        } else {
            Series::line(format!("step to V_f = {} µm/s", s.v_lp), pts, ordered_color(j - 1, fig.steps.len() - 1))
        });
    }
    for h in fig.holds.iter().chain(&fig.steps) {
        let (vi, vlp) = (format!("{}", h.v_i), format!("{}", h.v_lp));
        for k in 0..h.vi_t.len() {
            csv.row(&[h.params.law, &vi, &vlp], &[h.vi_t[k], h.delta_mu[k], h.slip_rate[k]]);
        }
    }
    println!("{} s holds from V_i = {:?} µm/s:", fig.hold_duration, HOLD_VI);
    for (p, worst) in &fig.collapse {
        println!("  {}: largest |Δμ| difference between V_i at equal V_i·t = {worst:.2e}", p.label());
    }
    for h in &fig.holds {
        println!(
            "  {} V_i = {}: Δμ at the end of the hold = {:.4} (V_i·t = {:.0} µm)",
            h.params.name(),
            h.v_i,
            h.delta_mu.last().expect("samples"),
            h.vi_t.last().expect("samples")
        );
    }
    let svg = render(
        "Holds (V_lp = 0, k = 0.065 /µm), step-fitted parameters: solid Slip law, dashed Aging law",
        &[by_time, by_vit, steps],
        3,
        (560, 470),
    )?;
    common::write_all("fig3_holds", &svg, &csv.finish(), &fig);
    Ok(())
}
