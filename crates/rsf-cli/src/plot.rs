//! SVG figures (plotters, SVG backend only: no system libraries needed).

use anyhow::{Result, anyhow};
use plotters::prelude::*;
use rsf_solvers::Solution;
use std::path::Path;

fn range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) =
        v.filter(|x| x.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-12 * hi.abs().max(1.0));
    (lo - pad, hi + pad)
}

/// Friction and log10 slip rate against time, two stacked panels.
/// With `measured` (friction at the solution's times), the data are drawn as grey points.
pub fn simulation(sol: &Solution, measured: Option<&[f64]>, path: &Path, title: &str) -> Result<()> {
    let root = SVGBackend::new(path, (900, 650)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    let root = root.titled(title, ("sans-serif", 18)).map_err(|e| anyhow!("{e}"))?;
    let (top, bottom) = root.split_vertically(320);
    let (t0, t1) = range(sol.time.iter().copied());
    let measured = measured.filter(|m| m.len() == sol.len());
    let (m0, m1) = range(sol.mu.iter().copied().chain(measured.into_iter().flatten().copied()));
    let mut c = ChartBuilder::on(&top)
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(70)
        .build_cartesian_2d(t0..t1, m0..m1)
        .map_err(|e| anyhow!("{e}"))?;
    c.configure_mesh().x_desc("time (s)").y_desc("friction μ").draw().map_err(|e| anyhow!("{e}"))?;
    if let Some(m) = measured {
        c.draw_series(sol.time.iter().zip(m).map(|(&t, &y)| Circle::new((t, y), 1, RGBColor(150, 150, 150).filled())))
            .map_err(|e| anyhow!("{e}"))?
            .label("measured")
            .legend(|(x, y)| Circle::new((x + 10, y), 3, RGBColor(150, 150, 150).filled()));
    }
    c.draw_series(LineSeries::new(sol.time.iter().copied().zip(sol.mu.iter().copied()), BLUE.stroke_width(2)))
        .map_err(|e| anyhow!("{e}"))?
        .label("model")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE.stroke_width(2)));
    c.configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    let logv: Vec<f64> = sol.slip_rate.iter().map(|v| v.log10()).collect();
    let (v0, v1) = range(logv.iter().copied());
    let mut c = ChartBuilder::on(&bottom)
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(70)
        .build_cartesian_2d(t0..t1, v0..v1)
        .map_err(|e| anyhow!("{e}"))?;
    c.configure_mesh().x_desc("time (s)").y_desc("log10 slip rate (µm/s)").draw().map_err(|e| anyhow!("{e}"))?;
    c.draw_series(LineSeries::new(sol.time.iter().copied().zip(logv), RED.stroke_width(2)))
        .map_err(|e| anyhow!("{e}"))?;
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}
