//! Slide–hold–slide at 1 µm/s: peak friction on reslide against hold time (10 … 10⁴ s).
//!
//! `cargo run --release -p rsf-paper --example peak_vs_hold [OUT_DIR]` writes
//! `peak_vs_hold.{svg,csv,json}` to OUT_DIR (default `docs/figures`).

mod common;

use rsf_paper::csv::Csv;
use rsf_paper::plot::{LegendPosition, PALETTE, Panel, Series, lighter, ordered_color, render};
use rsf_paper::{LONG_HOLD, Resolution, peak_vs_hold};

fn main() -> Result<(), rsf_paper::PaperError> {
    let fig = peak_vs_hold(&Resolution::figure())?;
    let mut csv = Csv::new(&["law", "a", "hold_s", "load_point_since_reslide_um", "delta_mu"]);
    let mut peaks = Panel::new("A  peak on reslide", "hold time (s)", "Δμ_pk = μ_pk − μ_ss(V_i)")
        .log_x()
        .legend(LegendPosition::UpperLeft);
    let mut reslides = Vec::new();
    println!("slide–hold–slide at V = {} µm/s; Δμ_pk per hold 10 … 10⁴ s:", fig.v);
    for (i, f) in fig.families.iter().enumerate() {
        let label = f.params.label();
        let pts: Vec<(f64, f64)> = f.holds.iter().map(|s| (s.hold, s.peak)).collect();
        peaks = peaks.with(Series::markers(label.clone(), pts, PALETTE[i]));
        // slope-b guide through the longest hold: the Aging law's expected long-hold slope
        let last = f.holds.last().expect("holds");
        let guide = |t: f64| last.peak + f.params.b * (t / last.hold).ln();
        peaks =
            peaks.with(Series::dashed(None, vec![(10.0, guide(10.0)), (1e4, guide(1e4))], lighter(PALETTE[i], 0.4)));
        let mut p = Panel::new(
            format!("{}  {}: reslide", ["B", "C", "D"][i], label),
            "load point since reslide (µm)",
            "μ − μ_ss(V_i)",
        )
        .legend(LegendPosition::UpperRight);
        let a = format!("{}", f.params.a);
        for (j, s) in f.holds.iter().enumerate() {
            let hold = format!("{}", s.hold);
            csv.curve(&[f.params.law, &a, &hold], &s.reslide.x, &s.reslide.y);
            let l = (j % 3 == 0).then(|| format!("hold {:.0} s", s.hold));
            p = p.with(Series::line(l, s.reslide.points(), ordered_color(j, f.holds.len())));
        }
        reslides.push(p);
        let d: Vec<String> = f.holds.iter().map(|s| format!("{:.4}", s.peak)).collect();
        println!("  {label}: {}", d.join(" "));
        println!(
            "    dΔμ_pk/d ln t_h = {:.5} for holds ≥ {LONG_HOLD} s ({:.2} b), {:.5} over all holds",
            f.slope_long, f.slope_over_b, f.slope_all
        );
    }
    let mut panels = vec![peaks];
    panels.extend(reslides);
    let svg = render(
        "Slide–hold–slide at 1 µm/s (k = 0.065 /µm); dashed: slope b per e-fold of hold time",
        &panels,
        2,
        (640, 440),
    )?;
    common::write_all("peak_vs_hold", &svg, &csv.finish(), &fig);
    Ok(())
}
