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

/// Data, model and residuals of a fit against load-point displacement; segments alternate
/// in shade.
pub fn fit(r: &rsf_fit::fit::FitResult, path: &Path, title: &str) -> Result<()> {
    // at most ~4000 points per series in the figure (the fit used every sample)
    let stride = r.curve.time.len().div_ceil(4000).max(1);
    let thin = |v: &[f64]| v.iter().step_by(stride).copied().collect::<Vec<f64>>();
    let curve = rsf_fit::fit::Curve {
        time: thin(&r.curve.time),
        load_point: thin(&r.curve.load_point),
        data: thin(&r.curve.data),
        model: thin(&r.curve.model),
        segment: r.curve.segment.iter().step_by(stride).copied().collect(),
    };
    let c = &curve;
    let root = SVGBackend::new(path, (1000, 700)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    let head = format!(
        "{title} — {} law(s): a = {:.5}, b = {:?}, Dc = {:?} µm, rms {:.2e}",
        r.params.laws.join("+"),
        r.params.a,
        r.params.b.iter().map(|x| format!("{x:.5}")).collect::<Vec<_>>(),
        r.params.dc.iter().map(|x| format!("{x:.2}")).collect::<Vec<_>>(),
        r.rms
    );
    let root = root.titled(&head, ("sans-serif", 15)).map_err(|e| anyhow!("{e}"))?;
    let (top, bottom) = root.split_vertically(440);
    let (x0, x1) = range(c.load_point.iter().copied());
    let (m0, m1) = range(c.data.iter().chain(&c.model).copied());
    let res: Vec<f64> = c.data.iter().zip(&c.model).map(|(d, m)| d - m).collect();
    let (r0, r1) = range(res.iter().copied());
    let shade = |ch: &mut ChartContext<
        '_,
        SVGBackend,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
                 lo: f64,
                 hi: f64|
     -> Result<()> {
        for g in &r.segments {
            if g.index % 2 == 0 {
                let xs: Vec<f64> =
                    c.segment.iter().zip(&c.load_point).filter(|(s, _)| **s + 1 == g.index).map(|(_, x)| *x).collect();
                if let (Some(a), Some(b)) = (xs.first(), xs.last()) {
                    ch.draw_series(std::iter::once(Rectangle::new(
                        [(*a, lo), (*b, hi)],
                        RGBColor(235, 240, 250).filled(),
                    )))
                    .map_err(|e| anyhow!("{e}"))?;
                }
            }
        }
        Ok(())
    };
    let mut ch = ChartBuilder::on(&top)
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(75)
        .build_cartesian_2d(x0..x1, m0..m1)
        .map_err(|e| anyhow!("{e}"))?;
    ch.configure_mesh()
        .x_desc("load-point displacement (µm)")
        .y_desc("friction μ")
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    shade(&mut ch, m0, m1)?;
    ch.draw_series(
        c.load_point.iter().zip(&c.data).map(|(&x, &y)| Circle::new((x, y), 1, RGBColor(120, 120, 120).filled())),
    )
    .map_err(|e| anyhow!("{e}"))?
    .label("data")
    .legend(|(x, y)| Circle::new((x + 10, y), 3, RGBColor(120, 120, 120).filled()));
    // model drawn per segment so that windows do not join across gaps
    let mut first = true;
    for g in &r.segments {
        let pts: Vec<(f64, f64)> = c
            .segment
            .iter()
            .zip(c.load_point.iter().zip(&c.model))
            .filter(|(s, _)| **s + 1 == g.index)
            .map(|(_, (x, m))| (*x, *m))
            .collect();
        let s = ch.draw_series(LineSeries::new(pts, RED.stroke_width(2))).map_err(|e| anyhow!("{e}"))?;
        if first {
            s.label("model").legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED.stroke_width(2)));
            first = false;
        }
    }
    ch.configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    let mut ch = ChartBuilder::on(&bottom)
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(75)
        .build_cartesian_2d(x0..x1, r0..r1)
        .map_err(|e| anyhow!("{e}"))?;
    ch.configure_mesh()
        .x_desc("load-point displacement (µm)")
        .y_desc("residual (data − model)")
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    shade(&mut ch, r0, r1)?;
    ch.draw_series(c.load_point.iter().zip(&res).map(|(&x, &y)| Circle::new((x, y), 1, BLUE.filled())))
        .map_err(|e| anyhow!("{e}"))?;
    ch.draw_series(LineSeries::new(vec![(x0, 0.0), (x1, 0.0)], BLACK)).map_err(|e| anyhow!("{e}"))?;
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// A self-contained HTML report of a diagnosis: data with baseline and extended models,
/// residuals of both against load point, and the candidate table (SVG inline).
pub fn diagnosis_html(d: &rsf_fit::diagnose::Diagnosis, name: &str, table: &str) -> Result<String> {
    let b = &d.baseline.curve;
    let ext = d.extended.as_ref().map(|e| &e.curve);
    let stride = b.time.len().div_ceil(3000).max(1);
    let idx: Vec<usize> = (0..b.time.len()).step_by(stride).collect();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 760)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let (top, bottom) = root.split_vertically(420);
        let xs: Vec<f64> = idx.iter().map(|&i| b.load_point[i]).collect();
        let (x0, x1) = range(xs.iter().copied());
        let (m0, m1) = range(idx.iter().map(|&i| b.data[i]).chain(idx.iter().map(|&i| b.model[i])));
        let mut ch = ChartBuilder::on(&top)
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(75)
            .build_cartesian_2d(x0..x1, m0..m1)
            .map_err(|e| anyhow!("{e}"))?;
        ch.configure_mesh()
            .x_desc("load-point displacement (µm)")
            .y_desc("friction μ")
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        ch.draw_series(
            idx.iter().map(|&i| Circle::new((b.load_point[i], b.data[i]), 1, RGBColor(130, 130, 130).filled())),
        )
        .map_err(|e| anyhow!("{e}"))?
        .label("data")
        .legend(|(x, y)| Circle::new((x + 10, y), 3, RGBColor(130, 130, 130).filled()));
        ch.draw_series(idx.iter().map(|&i| Circle::new((b.load_point[i], b.model[i]), 1, BLUE.filled())))
            .map_err(|e| anyhow!("{e}"))?
            .label("baseline")
            .legend(|(x, y)| Circle::new((x + 10, y), 3, BLUE.filled()));
        if let Some(e) = ext {
            if e.time.len() == b.time.len() {
                ch.draw_series(idx.iter().map(|&i| Circle::new((e.load_point[i], e.model[i]), 1, RED.filled())))
                    .map_err(|er| anyhow!("{er}"))?
                    .label(format!("extended ({})", d.cause))
                    .legend(|(x, y)| Circle::new((x + 10, y), 3, RED.filled()));
            }
        }
        ch.configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .border_style(BLACK)
            .background_style(WHITE.mix(0.8))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        let rb: Vec<f64> = idx.iter().map(|&i| b.data[i] - b.model[i]).collect();
        let re: Vec<f64> = match ext {
            Some(e) if e.time.len() == b.time.len() => idx.iter().map(|&i| e.data[i] - e.model[i]).collect(),
            _ => vec![],
        };
        let (r0, r1) = range(rb.iter().chain(&re).copied());
        let mut ch = ChartBuilder::on(&bottom)
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(75)
            .build_cartesian_2d(x0..x1, r0..r1)
            .map_err(|e| anyhow!("{e}"))?;
        ch.configure_mesh()
            .x_desc("load-point displacement (µm)")
            .y_desc("residual (data − model)")
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        ch.draw_series(xs.iter().zip(&rb).map(|(&x, &y)| Circle::new((x, y), 1, BLUE.filled())))
            .map_err(|e| anyhow!("{e}"))?;
        ch.draw_series(xs.iter().zip(&re).map(|(&x, &y)| Circle::new((x, y), 1, RED.filled())))
            .map_err(|e| anyhow!("{e}"))?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    let esc = |t: &str| t.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;");
    Ok(format!(
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>rsf diagnose: {n}</title>\
         <style>body{{font-family:sans-serif;max-width:1040px;margin:2em auto}}pre{{background:#f4f4f4;padding:1em;overflow-x:auto}}</style></head>\
         <body><h1>rsf diagnose: {n}</h1><p><b>cause: {c}</b></p><p>{r}</p>{svg}<h2>Candidates</h2><pre>{t}</pre></body></html>\n",
        n = esc(name),
        c = esc(&d.cause),
        r = esc(&d.reason),
        t = esc(table),
    ))
}
