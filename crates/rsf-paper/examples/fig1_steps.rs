//! Fig. 1B/C of Bhattacharya et al. (2022): friction after velocity steps of 10^0.5 … 10^3.5,
//! normalised between its extremum and 4 µm of slip later, against slip since the extremum.
//!
//! `cargo run --release -p rsf-paper --example fig1_steps [OUT_DIR]` writes
//! `fig1_steps.{svg,csv,json}` to OUT_DIR (default `docs/figures`).

mod common;

use rsf_paper::csv::Csv;
use rsf_paper::plot::{BLACK, LegendPosition, Panel, Series, ordered_color, render};
use rsf_paper::{NORMALISATION_SLIP, Resolution, fig1_steps};

fn main() -> Result<(), rsf_paper::PaperError> {
    let fig = fig1_steps(&Resolution::figure())?;
    let mut csv = Csv::new(&["law", "direction", "log10_step", "slip_since_extremum_um", "normalised_friction"]);
    let mut panels = Vec::new();
    println!("half-recovery slip (µm past the extremum where normalised friction reaches 1/2):");
    for (i, fam) in fig.families.iter().enumerate() {
        let n = fam.steps.len();
        let mut panel = Panel::new(
            format!("{}  {} law, step {}s", ["B", "C", "D", "E"][i], fam.params.name(), fam.direction),
            format!("slip since the friction {} (µm)", if fam.direction == "decrease" { "minimum" } else { "maximum" }),
            "normalised friction change",
        )
        .legend(LegendPosition::LowerRight);
        for (j, s) in fam.steps.iter().enumerate() {
            let size = format!("{}", s.log10_size);
            csv.curve(&[fam.params.law, fam.direction, &size], &s.curve.x, &s.curve.y);
            panel = panel.with(Series::line(format!("V ratio 10^{size}"), s.curve.points(), ordered_color(j, n)));
        }
        if fam.params.law == "slip" {
            // imposed slip rate (k → ∞): ln(Vθ/Dc) ∝ exp(−δ/Dc), so the normalised change is
            // (1 − e^(−s/Dc)) / (1 − e^(−4/Dc)) whatever the step size
            let dc = fam.params.dc;
            let pts = (0..=120)
                .map(|i| {
                    let s = 6.0 * i as f64 / 120.0;
                    (s, (1.0 - (-s / dc).exp()) / (1.0 - (-NORMALISATION_SLIP / dc).exp()))
                })
                .collect();
            panel = panel.with(Series::dashed("imposed V (k → ∞)".to_string(), pts, BLACK));
        }
        panels.push(panel.x_range(0.0, 6.0));
        let halves: Vec<String> = fam.steps.iter().map(|s| format!("{:.2}", s.half_recovery_slip)).collect();
        println!(
            "  {:<6} {:<8}: {} (max/min {:.3})",
            fam.params.law,
            fam.direction,
            halves.join(" "),
            fam.half_recovery_spread
        );
    }
    let svg = render(
        &format!(
            "Velocity steps from/to {} µm/s (k = 0.065 /µm), smoothed over 0.2 µm (decreases) / 0.4 µm (increases)",
            fig.v_high
        ),
        &panels,
        2,
        (620, 430),
    )?;
    common::write_all("fig1_steps", &svg, &csv.finish(), &fig);
    Ok(())
}
