//! The design's figure and page: the credible models' predicted friction through the best
//! proposal with their noise bands, and the ranking.

use super::{STYLE, chart, esc, table};
use rsf_design::Design;
use rsf_plot::{PALETTE, Panel, PlotError, Series, fmt_num, render_stack};

/// Noise bands are ± this many standard deviations (95%).
const BAND_SIGMAS: f64 = 2.0;

/// Each model's prediction through the best proposal (top), and its difference from the best
/// model's (bottom), with bands of ±2 sd of the noise and the parameter draws' spread.
pub fn design_svg(d: &Design) -> Result<String, PlotError> {
    let Some(best) = d.proposals.first() else {
        return Err(PlotError("no proposal to draw".into()));
    };
    let sigma = d.noise.variance.max(0.0).sqrt();
    // log time: the transients at the start of each segment and the long holds both show
    let mut top = Panel::new(best.description.clone(), "time after the record's end (s)", "friction μ").log_x();
    let mut bottom = Panel::new(
        format!("difference from {} (dashed: ±{BAND_SIGMAS} sd of noise and parameters)", d.models[0].name),
        "time after the record's end (s)",
        "Δμ",
    )
    .log_x()
    .zero_line();
    let Some(base) = d.curves.first() else {
        return Err(PlotError("no predictions to draw".into()));
    };
    for (i, c) in d.curves.iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        let pts =
            |f: &dyn Fn(usize) -> f64| -> Vec<(f64, f64)> { (0..c.time.len()).map(|k| (c.time[k], f(k))).collect() };
        let band = |k: usize| BAND_SIGMAS * (sigma * sigma + c.mu_sd[k] * c.mu_sd[k]).sqrt();
        top = top.with(Series::line(Some(c.model.clone()), pts(&|k| c.mu[k]), color));
        let diff = |k: usize| c.mu[k] - base.mu.get(k).copied().unwrap_or(f64::NAN);
        bottom = bottom.with(Series::line(Some(c.model.clone()), pts(&diff), color));
        bottom = bottom.with(Series::dashed(None, pts(&|k| diff(k) + band(k)), color));
        bottom = bottom.with(Series::dashed(None, pts(&|k| diff(k) - band(k)), color));
    }
    render_stack(
        &format!(
            "rsf design: next segment, expected to settle {} of {} model pairs",
            fmt_num(best.score, 2),
            best.pairs.len()
        ),
        &[(top, 380), (bottom, 300)],
        960,
    )
}

/// The design as a self-contained HTML page: the summary, the figure, the ranking and the
/// models. `name` is the record's name.
pub fn design_html(d: &Design, name: &str) -> String {
    let mut body = format!("<h1>rsf design: {}</h1>\n<p class=\"verdict\">{}</p>\n", esc(name), esc(&d.summary));
    for n in &d.notes {
        body += &format!("<p class=\"note\">{}</p>\n", esc(n));
    }
    if !d.proposals.is_empty() {
        body += "<h2>The best proposal</h2>\n";
        body += &chart(design_svg(d));
    }
    body += "<h2>Credible models</h2>\n";
    let rows: Vec<(String, Vec<String>)> = d
        .models
        .iter()
        .map(|m| {
            (
                String::new(),
                vec![
                    format!("<l>{}", esc(&m.name)),
                    format!("<l>{}", esc(&m.extension)),
                    format!("{:.1}", m.delta_bic),
                    m.draws.to_string(),
                ],
            )
        })
        .collect();
    body += &table("", &["model", "<l>extension", "ΔBIC", "draws"], &rows);
    if !d.proposals.is_empty() {
        body += "<h2>Ranking</h2>\n<p class=\"sub\">score: model pairs expected to be settled, Σ (1 − exp(−Δχ²/40)); \
                 Δχ² of the lead pair (the best model and the runner-up); per hour of machine time; the fastest slip \
                 rate a credible model reaches (µm/s; stick-slip: one runs away, ranked last).</p>\n";
        let peak = |r: &rsf_design::Ranked| {
            format!("{:.3e}{}", r.peak_slip_rate, if r.stick_slip { " stick-slip" } else { "" })
        };
        let mut rows: Vec<(String, Vec<String>)> = d
            .proposals
            .iter()
            .take(15)
            .map(|r| {
                (
                    if r.rank == 1 { "chosen".into() } else { String::new() },
                    vec![
                        r.rank.to_string(),
                        format!("<l>{}", esc(&r.description)),
                        format!("{:.0}", r.machine_time_s),
                        format!("{:.1}", r.slip_um),
                        format!("{:.2}", r.score),
                        format!("{:.1}", r.lead_pair_dchi2),
                        format!("{:.2}", r.score_per_hour),
                        peak(r),
                    ],
                )
            })
            .collect();
        for s in &d.standards {
            rows.push((
                "second".into(),
                vec![
                    "std".into(),
                    format!("<l>standard: {}", esc(&s.description)),
                    format!("{:.0}", s.machine_time_s),
                    format!("{:.1}", s.slip_um),
                    format!("{:.2}", s.score),
                    format!("{:.1}", s.lead_pair_dchi2),
                    format!("{:.2}", s.score_per_hour),
                    peak(s),
                ],
            ));
        }
        body += &table(
            "wide",
            &["#", "<l>proposal", "time (s)", "slip (µm)", "score", "lead Δχ²", "score/h", "peak V (µm/s)"],
            &rows,
        );
    }
    format!(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <title>rsf design: {}</title><style>{STYLE}</style></head>\n<body>\n{body}\n</body></html>\n",
        esc(name)
    )
}
