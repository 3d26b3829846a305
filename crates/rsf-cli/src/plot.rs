//! SVG figures (plotters, SVG backend only: no system libraries needed).

use anyhow::{Result, anyhow};
use plotters::prelude::*;
use rsf_solvers::Solution;
use std::path::Path;

/// A chart with the house margins and axis labels on `area`.
fn chart<'a, 'b: 'a>(
    area: &'a DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    x_desc: &str,
    y_desc: &str,
) -> Result<
    ChartContext<
        'a,
        SVGBackend<'b>,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
> {
    let mut ch = ChartBuilder::on(area)
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(75)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| anyhow!("{e}"))?;
    ch.configure_mesh().x_desc(x_desc).y_desc(y_desc).draw().map_err(|e| anyhow!("{e}"))?;
    Ok(ch)
}

fn range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) =
        v.filter(|x| x.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    // a degenerate range (one point, or all equal) gets a visible span around it
    let pad =
        if hi - lo > 1e-9 * hi.abs().max(lo.abs()).max(1e-300) { (hi - lo) * 0.05 } else { 0.1 * hi.abs().max(1e-6) };
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
    let mut c = chart(&top, (t0, t1), (m0, m1), "time (s)", "friction μ")?;
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
    let mut c = chart(&bottom, (t0, t1), (v0, v1), "time (s)", "log10 slip rate (µm/s)")?;
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
        slip_rate: thin(&r.curve.slip_rate),
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
    let mut ch = chart(&top, (x0, x1), (m0, m1), "load-point displacement (µm)", "friction μ")?;
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
    let mut ch = chart(&bottom, (x0, x1), (r0, r1), "load-point displacement (µm)", "residual (data − model)")?;
    shade(&mut ch, r0, r1)?;
    ch.draw_series(c.load_point.iter().zip(&res).map(|(&x, &y)| Circle::new((x, y), 1, BLUE.filled())))
        .map_err(|e| anyhow!("{e}"))?;
    ch.draw_series(LineSeries::new(vec![(x0, 0.0), (x1, 0.0)], BLACK)).map_err(|e| anyhow!("{e}"))?;
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// A scatter series: label, colour, points, error bars in y (empty: none).
type Series = (String, RGBColor, Vec<(f64, f64)>, Vec<f64>);

/// One scatter panel as an inline SVG string: series of (label, colour, points), optional
/// error bars in y (same length as the points, or empty).
fn scatter_svg(title: &str, x_desc: &str, y_desc: &str, series: &[Series], zero_line: bool) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (490, 340)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let root = root.titled(title, ("sans-serif", 14)).map_err(|e| anyhow!("{e}"))?;
        let (x0, x1) = range(series.iter().flat_map(|s| s.2.iter().map(|p| p.0)));
        let (y0, y1) = range(series.iter().flat_map(|s| {
            s.2.iter().enumerate().flat_map(move |(i, p)| {
                let e = s.3.get(i).copied().unwrap_or(0.0);
                [p.1 - e, p.1 + e]
            })
        }));
        let mut ch = chart(&root, (x0, x1), (y0, y1), x_desc, y_desc)?;
        if zero_line {
            ch.draw_series(LineSeries::new(vec![(x0, 0.0), (x1, 0.0)], BLACK)).map_err(|e| anyhow!("{e}"))?;
        }
        for (label, color, pts, err) in series {
            let color = *color;
            let r = if pts.len() > 50 { 1 } else { 4 };
            ch.draw_series(pts.iter().map(|&(x, y)| Circle::new((x, y), r, color.filled())))
                .map_err(|e| anyhow!("{e}"))?
                .label(label.as_str())
                .legend(move |(x, y)| Circle::new((x + 10, y), 3, color.filled()));
            if !err.is_empty() {
                ch.draw_series(
                    pts.iter()
                        .zip(err)
                        .map(|(&(x, y), &e)| PathElement::new(vec![(x, y - e), (x, y + e)], color.stroke_width(1))),
                )
                .map_err(|e| anyhow!("{e}"))?;
            }
        }
        ch.configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .border_style(BLACK)
            .background_style(WHITE.mix(0.8))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    Ok(svg)
}

/// A self-contained HTML report of a diagnosis: data with baseline and extended models and
/// their residuals against load point, residuals per segment and against log slip rate,
/// per-event refits of Dc, the gain table and every candidate (SVG inline).
pub fn diagnosis_html(d: &rsf_fit::diagnose::Diagnosis, name: &str, table: &str) -> Result<String> {
    let b = &d.baseline.curve;
    let ext = d.extended.as_ref().map(|e| &e.curve).filter(|e| e.time.len() == b.time.len());
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
        let mut ch = chart(&top, (x0, x1), (m0, m1), "load-point displacement (µm)", "friction μ")?;
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
            ch.draw_series(idx.iter().map(|&i| Circle::new((e.load_point[i], e.model[i]), 1, RED.filled())))
                .map_err(|er| anyhow!("{er}"))?
                .label(format!("extended ({})", d.cause))
                .legend(|(x, y)| Circle::new((x + 10, y), 3, RED.filled()));
        }
        ch.configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .border_style(BLACK)
            .background_style(WHITE.mix(0.8))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        let rb: Vec<f64> = idx.iter().map(|&i| b.data[i] - b.model[i]).collect();
        let re: Vec<f64> = match ext {
            Some(e) => idx.iter().map(|&i| e.data[i] - e.model[i]).collect(),
            None => vec![],
        };
        let (r0, r1) = range(rb.iter().chain(&re).copied());
        let mut ch = chart(&bottom, (x0, x1), (r0, r1), "load-point displacement (µm)", "residual (data − model)")?;
        ch.draw_series(xs.iter().zip(&rb).map(|(&x, &y)| Circle::new((x, y), 1, BLUE.filled())))
            .map_err(|e| anyhow!("{e}"))?;
        ch.draw_series(xs.iter().zip(&re).map(|(&x, &y)| Circle::new((x, y), 1, RED.filled())))
            .map_err(|e| anyhow!("{e}"))?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    let ext_label = format!("extended ({})", d.cause);
    // residuals per segment: rms of each, baseline and extended
    let seg_rms = |c: &rsf_fit::fit::Curve| -> Vec<(f64, f64)> {
        let n = c.segment.iter().max().map_or(0, |m| m + 1);
        let mut acc = vec![(0.0, 0usize); n];
        for (k, &s) in c.segment.iter().enumerate() {
            acc[s].0 += (c.data[k] - c.model[k]).powi(2);
            acc[s].1 += 1;
        }
        acc.iter()
            .enumerate()
            .filter(|(_, a)| a.1 > 0)
            .map(|(i, a)| ((i + 1) as f64, (a.0 / a.1 as f64).sqrt()))
            .collect()
    };
    let mut series = vec![("baseline".to_string(), BLUE, seg_rms(b), vec![])];
    if let Some(e) = ext {
        series.push((ext_label.clone(), RED, seg_rms(e), vec![]));
    }
    let per_seg = scatter_svg("rms misfit per segment", "segment", "rms residual", &series, false)?;
    // residuals against log10 of the model slip rate
    let vs_v = |c: &rsf_fit::fit::Curve| -> Vec<(f64, f64)> {
        if c.slip_rate.len() != c.data.len() {
            return vec![];
        }
        idx.iter()
            .filter(|&&i| c.slip_rate[i] > 0.0)
            .map(|&i| (c.slip_rate[i].log10(), c.data[i] - c.model[i]))
            .collect()
    };
    let mut series = vec![("baseline".to_string(), BLUE, vs_v(b), vec![])];
    if let Some(e) = ext {
        series.push((ext_label.clone(), RED, vs_v(e), vec![]));
    }
    let per_v = scatter_svg("residuals against slip rate", "log10 V (model, µm/s)", "residual", &series, true)?;
    // per-event Dc against step size and against hold duration
    let mut dc_svgs = String::new();
    type Axis = fn(&rsf_fit::diagnose::EventFit) -> Option<f64>;
    let panels: [(&str, &str, &str, RGBColor, Axis); 2] = [
        ("Dc refitted step by step", "log10 (V after / V before)", "steps", BLUE, |e| {
            e.hold_s.is_none().then(|| (e.v_after / e.v_before).log10())
        }),
        ("Dc refitted hold by hold", "log10 hold duration (s)", "holds", RED, |e| e.hold_s.map(f64::log10)),
    ];
    for (title, x_desc, label, color, x) in panels {
        let ev: Vec<(f64, &rsf_fit::diagnose::EventFit)> =
            d.per_segment.iter().filter_map(|e| x(e).map(|x| (x, e))).collect();
        if ev.len() >= 2 {
            let pts = ev.iter().map(|(x, e)| (*x, e.dc.log10())).collect();
            let err = ev.iter().map(|(_, e)| e.ln_dc_stderr / std::f64::consts::LN_10).collect();
            dc_svgs += &scatter_svg(title, x_desc, "log10 Dc (µm)", &[(label.into(), color, pts, err)], false)?;
        }
    }
    let esc = |t: &str| t.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;");
    let f = |x: Option<f64>| x.map_or("–".to_string(), |v| format!("{v:.3e}"));
    let gain = match &d.gain {
        Some(g) => format!(
            "<table><tr><th>ΔBIC<sub>eff</sub></th><th>ΔAIC<sub>eff</sub></th><th>rms ratio</th><th>held-out rms before</th><th>held-out rms after</th></tr>\
             <tr><td>{:.1}</td><td>{:.1}</td><td>{:.4}</td><td>{}</td><td>{}</td></tr></table>",
            g.delta_bic,
            g.delta_aic,
            g.rms_ratio,
            f(g.heldout_rms_before),
            f(g.heldout_rms_after)
        ),
        None => "<p>No extension is decisive: the baseline stands.</p>".into(),
    };
    let secondary = match &d.secondary {
        Some(s) => format!(
            "<p><b>Second cause: {}</b> — on top of {}, ΔBIC<sub>eff</sub> = {:.1}, rms ratio {:.4}, held-out {} → {}; effect {}</p>",
            esc(&s.cause),
            esc(&d.cause),
            s.delta_bic,
            s.rms_ratio,
            f(s.heldout_rms_before),
            f(s.heldout_rms_after),
            esc(&serde_json::to_string(&s.effect)?)
        ),
        None => String::new(),
    };
    let mut events = String::new();
    if !d.per_segment.is_empty() {
        events += "<table><tr><th>event</th><th>t (s)</th><th>V before → after (µm/s)</th><th>hold (s)</th><th>a</th><th>b</th><th>Dc (µm)</th><th>±ln Dc</th><th>rms</th></tr>";
        for e in &d.per_segment {
            events += &format!(
                "<tr><td>{}</td><td>{:.1}</td><td>{:.3} → {:.3}</td><td>{}</td><td>{:.5}</td><td>{:.5}</td><td>{:.3}</td><td>{:.3}</td><td>{:.2e}</td></tr>",
                e.event,
                e.t,
                e.v_before,
                e.v_after,
                e.hold_s.map_or("–".into(), |h| format!("{h:.0}")),
                e.a,
                e.b,
                e.dc,
                e.ln_dc_stderr,
                e.rms
            );
        }
        events += "</table>";
    }
    Ok(format!(
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>rsf diagnose: {n}</title>\
         <style>body{{font-family:sans-serif;max-width:1040px;margin:2em auto}}pre{{background:#f4f4f4;padding:1em;overflow-x:auto}}\
         table{{border-collapse:collapse;margin:1em 0}}td,th{{border:1px solid #ccc;padding:3px 8px;text-align:right}}</style></head>\
         <body><h1>rsf diagnose: {n}</h1><p><b>cause: {c}</b></p><p>{r}</p>{sec}<h2>Gain</h2>{gain}\
         <h2>Data, models and residuals</h2><p>Blue: baseline; red: extended. Held-out test: fitted before t = {split:.1} s, predicted after.</p>{svg}\
         <h2>Where the residuals are</h2>{per_seg}{per_v}\
         <h2>Parameter consistency: each step and hold refitted alone</h2>\
         <p>One law with one Dc should serve every event; Dc that drifts with step size or hold duration points at the evolution law.</p>{dc_svgs}{events}\
         <h2>Candidates and evidence</h2><pre>{t}</pre></body></html>\n",
        n = esc(name),
        c = esc(&d.cause),
        r = esc(&d.reason),
        sec = secondary,
        split = d.heldout_split_t,
        t = esc(table),
    ))
}
