//! SVG figures of the CLI, on the workspace's one chart module (`rsf-plot`); the fit figure and
//! the diagnosis report are built by `rsf_report`.

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
    let svg = rsf_report::fit_svg(r, title).map_err(|e| anyhow!("{e}"))?;
    crate::output::write_bytes(path, svg)
}

/// `rsf batch`'s summary figure: a, b and Dc of every record fitted, with their standard
/// errors, against the load-point velocity, the normal stress and the longest hold (the axes
/// no record has are left out); one colour per diagnosed cause.
pub fn batch(rows: &[rsf_batch::Row]) -> Result<String> {
    use rsf_batch::{Row, Status};
    type Axis = (&'static str, fn(&Row) -> Option<f64>, bool);
    let axes: [Axis; 3] = [
        // the geometric mean of the slowest and fastest slide
        (
            "slide velocity (µm/s, geometric mean)",
            |r| r.v_lp_min_um_s.zip(r.v_lp_max_um_s).map(|(a, b)| (a * b).sqrt()),
            true,
        ),
        ("normal stress (MPa)", |r| r.normal_stress_mpa, false),
        ("longest hold (s)", |r| r.longest_hold_s, true),
    ];
    let params = [("a", "a", false), ("b1", "b (first state)", false), ("dc1", "Dc (µm, first state)", true)];
    let ok: Vec<&Row> = rows.iter().filter(|r| r.status == Status::Ok).collect();
    // the groups: each cause the diagnoses named (in order of first appearance), or one group
    let mut groups: Vec<String> = vec![];
    for r in &ok {
        let g = r.cause.clone().unwrap_or_else(|| "fitted".into());
        if !groups.contains(&g) {
            groups.push(g);
        }
    }
    let mut panels = vec![];
    for (x_label, x_of, log_x) in axes {
        if !ok.iter().any(|r| x_of(r).is_some_and(|x| x.is_finite() && (!log_x || x > 0.0))) {
            continue;
        }
        for (name, y_label, log_y) in params {
            let mut panel = Panel::new("", x_label, y_label);
            for (k, g) in groups.iter().enumerate() {
                let (mut pts, mut err) = (vec![], vec![]);
                for r in ok.iter().filter(|r| r.cause.as_deref().unwrap_or("fitted") == g) {
                    if let (Some(x), Some(p)) = (x_of(r), r.params.iter().find(|p| p.name == name)) {
                        pts.push((x, p.value));
                        err.push(p.stderr.unwrap_or(0.0));
                    }
                }
                let label = (groups.len() > 1).then(|| g.clone());
                panel = panel.with(Series::points(label, pts, PALETTE[k % PALETTE.len()]).y_err(err));
            }
            if log_x {
                panel = panel.log_x();
            }
            if log_y {
                panel = panel.log_y();
            }
            panels.push(panel);
        }
    }
    let title = format!("rsf batch: {} of {} records fitted (error bars: ±1 standard error)", ok.len(), rows.len());
    if panels.is_empty() {
        panels.push(Panel::new("no record was fitted", "", ""));
    }
    rsf_plot::render(&title, &panels, params.len(), (440, 320)).map_err(|e| anyhow!("{e}"))
}
