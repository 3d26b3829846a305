//! Fig. 2 of Bhattacharya et al. (2022): friction minima after velocity-step decreases from
//! 3 µm/s by 10^0.5 … 10^3.5, the friction curves against slip and the slip to the minimum.
//!
//! `cargo run --release -p rsf-paper --example fig2_minima [OUT_DIR]` writes
//! `fig2_minima.{svg,csv,json}` to OUT_DIR (default `docs/figures`).

mod common;

use rsf_paper::csv::Csv;
use rsf_paper::plot::{LegendPosition, PALETTE, Panel, Series, lighter, ordered_color, render};
use rsf_paper::{Resolution, fig2_minima};

fn main() -> Result<(), rsf_paper::PaperError> {
    let fig = fig2_minima(&Resolution::figure())?;
    let mut csv = Csv::new(&["law", "a", "log10_step", "slip_um", "delta_mu"]);
    let size_axis = "step size log10(V_i/V_f)";
    let mut minima =
        Panel::new("B/C  Δμ_min = μ_min − μ_ss(V_i)", size_axis, "Δμ_min").legend(LegendPosition::LowerLeft);
    let mut slip_to_min = Panel::new("F  slip from step onset to the minimum", size_axis, "slip to minimum (µm)")
        .legend(LegendPosition::UpperLeft);
    let mut curve_panels = Vec::new();
    println!("V_i = {} µm/s; Δμ_min per step size 10^0.5 … 10^3.5:", fig.v_i);
    for (i, fam) in fig.families.iter().enumerate() {
        let color = PALETTE[i];
        let label = fam.params.label();
        let pts: Vec<(f64, f64)> = fam.points.iter().map(|q| (q.log10_size, q.delta_mu_min)).collect();
        minima = minima.with(Series::markers(label.clone(), pts, color));
        let fit = |x: f64| fam.fit.intercept + fam.fit.slope * x;
        minima = minima.with(Series::dashed(None, vec![(0.5, fit(0.5)), (3.5, fit(3.5))], color));
        let direct: Vec<(f64, f64)> = fam.points.iter().map(|q| (q.log10_size, q.direct_effect)).collect();
        minima = minima.with(Series::line(None, direct, lighter(color, 0.5)));
        let pts: Vec<(f64, f64)> = fam.points.iter().map(|q| (q.log10_size, q.slip_to_min)).collect();
        slip_to_min = slip_to_min.with(Series::markers(label.clone(), pts, color));

        let a = format!("{}", fam.params.a);
        let n = fam.curves.len();
        let mut p = Panel::new(
            format!("{}  {}: Δμ after the step", ["D", "E", "E′"][i], label),
            "slip since step onset (µm)",
            "μ − μ_ss(V_i)",
        )
        .legend(LegendPosition::UpperRight)
        .x_range(0.0, 15.0);
        for (j, (c, q)) in fam.curves.iter().zip(&fam.points).enumerate() {
            let size = format!("{}", q.log10_size);
            csv.curve(&[fam.params.law, &a, &size], &c.x, &c.y);
            p = p.with(Series::line(format!("V ratio 10^{size}"), c.points(), ordered_color(j, n)));
        }
        curve_panels.push(p);
        let d: Vec<String> = fam.points.iter().map(|q| format!("{:.4}", q.delta_mu_min)).collect();
        let s: Vec<String> = fam.points.iter().map(|q| format!("{:.2}", q.slip_to_min)).collect();
        println!("  {label}");
        println!("    Δμ_min: {}", d.join(" "));
        println!("    slip to minimum (µm): {}", s.join(" "));
        println!(
            "    slope {:.5}/decade = {:.5} per e-fold of step size, R² = {:.4}; last/first half-decade increment {:.3}",
            fam.fit.slope, fam.slope_per_efold, fam.fit.r2, fam.increment_ratio
        );
    }
    let mut panels = vec![minima, slip_to_min];
    panels.extend(curve_panels);
    let svg = render(
        "Velocity-step decreases from 3 µm/s (k = 0.065 /µm). B/C: markers = model, dashed = straight-line fit, \
         pale = −a ln(V_i/V_f)",
        &panels,
        2,
        (640, 430),
    )?;
    common::write_all("fig2_minima", &svg, &csv.finish(), &fig);
    Ok(())
}
