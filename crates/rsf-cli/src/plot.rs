//! SVG figures of the CLI, on the workspace's one chart module (`rsf-plot`); the fit figure and
//! the diagnosis report are built by `rsf_fit::report`.

use anyhow::{Result, anyhow};
use rsf_plot::{GREY, PALETTE, Panel, Series, render_stack};
use rsf_solvers::Solution;
use std::path::Path;

/// Friction and log10 slip rate against time, two stacked panels.
/// With `measured` (friction at the solution's times), the data are drawn as grey points.
pub fn simulation(sol: &Solution, measured: Option<&[f64]>, path: &Path, title: &str) -> Result<()> {
    let t = &sol.time;
    let mut top = Panel::new("", "time (s)", "friction μ");
    if let Some(m) = measured.filter(|m| m.len() == sol.len()) {
        top = top.with(Series::dots("measured".to_string(), t.iter().copied().zip(m.iter().copied()).collect(), GREY));
    }
    top = top.with(Series::line(
        "model".to_string(),
        t.iter().copied().zip(sol.mu.iter().copied()).collect(),
        PALETTE[0],
    ));
    let v: Vec<(f64, f64)> = t.iter().copied().zip(sol.slip_rate.iter().copied()).filter(|p| p.1 > 0.0).collect();
    let bottom = Panel::new("", "time (s)", "slip rate V (µm/s)").log_y().with(Series::line(None, v, PALETTE[1]));
    let svg = render_stack(title, &[(top, 320), (bottom, 290)], 900).map_err(|e| anyhow!("{e}"))?;
    crate::output::write_bytes(path, svg)
}

/// Data, model and residuals of a fit against load-point displacement (`rsf fit --plot`).
pub fn fit(r: &rsf_fit::fit::FitResult, path: &Path, title: &str) -> Result<()> {
    let svg = rsf_fit::report::fit_svg(r, title).map_err(|e| anyhow!("{e}"))?;
    crate::output::write_bytes(path, svg)
}
