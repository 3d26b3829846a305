//! Relaxation during a 10⁴ s hold from 1 µm/s: the Aging law (a − b = −0.003, Dc = 10.05 µm)
//! stops relaxing once V_i·t/Dc exceeds a few, the Slip law keeps relaxing log-linearly.
//!
//! `cargo run --release -p rsf-paper --example aging_hold_flattening [OUT_DIR]` writes
//! `aging_hold_flattening.{svg,csv,json}` to OUT_DIR (default `docs/figures`).

mod common;

use rsf_paper::csv::Csv;
use rsf_paper::plot::{LegendPosition, PALETTE, Panel, Series, render};
use rsf_paper::{Resolution, aging_hold_flattening};

fn main() -> Result<(), rsf_paper::PaperError> {
    let fig = aging_hold_flattening(&Resolution::figure())?;
    let mut csv = Csv::new(&["law", "a", "b", "dc_um", "vi_t_over_dc", "delta_mu", "minus_dmu_dlnt"]);
    let x_label = "V_i·t / Dc";
    let mut mu =
        Panel::new("A  friction during the hold", x_label, "μ − μ_ss(V_i)").log_x().legend(LegendPosition::LowerLeft);
    let mut rate = Panel::new("B  relaxation rate −dμ/d ln t = k V t", x_label, "−dμ/d ln t")
        .log_x()
        .legend(LegendPosition::UpperLeft)
        .x_range(1e-2, 1e3);
    println!("hold of {} s from V_i = {} µm/s; −dμ/d ln t at V_i·t/Dc = 0.5, 2, 20, 200:", fig.hold_duration, fig.v_i);
    for (i, l) in fig.laws.iter().enumerate() {
        let label = l.params.label();
        let (a, b, dc) = (format!("{}", l.params.a), format!("{}", l.params.b), format!("{}", l.params.dc));
        for k in 0..l.t_nd.len() {
            csv.row(&[l.params.law, &a, &b, &dc], &[l.t_nd[k], l.delta_mu[k], l.rate[k]]);
        }
        let pts = |y: &[f64]| l.t_nd.iter().copied().zip(y.iter().copied()).collect::<Vec<_>>();
        mu = mu.with(Series::line(label.clone(), pts(&l.delta_mu), PALETTE[i]));
        rate = rate.with(Series::line(label.clone(), pts(&l.rate), PALETTE[i]));
        let r: Vec<String> = l.rate_at.iter().map(|(_, r)| format!("{r:.5}")).collect();
        println!("  {label}: {}  rate(20)/rate(0.5) = {:.3}", r.join(" "), l.flattening_ratio);
    }
    let svg = render(
        "10⁴ s hold from 1 µm/s (k = 0.065 /µm): Aging-law relaxation flattens beyond V_i·t/Dc ≈ 2",
        &[mu, rate],
        2,
        (640, 460),
    )?;
    common::write_all("aging_hold_flattening", &svg, &csv.finish(), &fig);
    Ok(())
}
