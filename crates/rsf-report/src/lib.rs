//! Reports a scientist would show: the diagnosis as a self-contained HTML page, and the SVG
//! charts of fits and diagnoses (on the workspace's one chart module, [`rsf_plot`]).
//!
//! The page, top to bottom ([`diagnosis_html`]): the verdict in plain words, the gain, the
//! effect's parameters, the fitted parameters, data with the models and their residuals, where
//! the residuals are, the per-event refits of Dc, the candidates and the evidence. Numbers are
//! formatted by [`rsf_plot::fmt`] (`0.00965 ± 0.00012`, `3.0×10⁻⁶ /µm`); units: friction
//! dimensionless, slip and Dc µm, velocities µm/s, k and g per µm, time s.
//!
//! Each section is one function returning its HTML (`sections::*`): a new field of the
//! diagnosis gets its own function and one line in [`diagnosis_html`].
//!
//! | file | what |
//! |---|---|
//! | `mod.rs` | the page: [`diagnosis_html`], its style, and HTML helpers |
//! | `words.rs` | the verdict paragraph and the names, units and formatting of parameters |
//! | `sections.rs` | the tables: gain, effect, parameters, candidates, per-event refits, evidence |
//! | `design.rs` | `rsf design`'s figure and page: [`design_svg`], [`design_html`] |
//! | `charts.rs` | the SVG charts: [`fit_svg`] (`rsf fit --plot`), [`models_svg`], [`residuals_svg`], [`events_svg`] |

mod adequacy;
mod charts;
mod design;
mod sections;
mod words;

pub use charts::{adequacy_svg, events_svg, fit_svg, fit_title, models_svg, noise_svg, residuals_svg};
pub use design::{design_html, design_svg};
pub use words::{effect_summary, param_rows, verdict};

use rsf_diagnose::Diagnosis;

/// The page style: fits a 1000 px page, tables wrap rather than overflow, SVG scales down.
const STYLE: &str = "body{font-family:system-ui,-apple-system,'Segoe UI',Helvetica,Arial,sans-serif;\
max-width:1000px;margin:1.5em auto;padding:0 10px;color:#222;line-height:1.45}\
h1{font-size:1.5em;margin-bottom:.2em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid #ddd}\
p.verdict{font-size:1.08em;background:#f3f6fb;border-left:4px solid #1f77b4;padding:.7em 1em}\
p.verdict.none{border-left-color:#7f7f7f}p.note,p.sub{color:#555;font-size:.92em}\
table{border-collapse:collapse;margin:.6em 0;font-size:.9em;max-width:100%}\
th,td{border:1px solid #d4d4d4;padding:3px 7px;vertical-align:top}th{background:#f4f4f4;font-weight:600}\
td{text-align:right;font-variant-numeric:tabular-nums}td.l,th.l{text-align:left}\
table.wide{width:100%}tr.chosen td{background:#fdf3e1}tr.second td{background:#eef6ee}\
svg{max-width:100%;height:auto;display:block;margin:.4em 0}";

/// Escapes text for HTML.
pub(crate) fn esc(t: &str) -> String {
    t.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// An HTML table: `head` cells (HTML), then rows of cells (HTML); a cell starting with `<l>` is
/// left-aligned text. `class` is the table's class (`wide`: full width).
pub(crate) fn table(class: &str, head: &[&str], rows: &[(String, Vec<String>)]) -> String {
    let cell = |tag: &str, c: &str| match c.strip_prefix("<l>") {
        Some(c) => format!("<{tag} class=\"l\">{c}</{tag}>"),
        None => format!("<{tag}>{c}</{tag}>"),
    };
    let mut s = format!("<table class=\"{class}\"><thead><tr>");
    s += &head.iter().map(|h| cell("th", h)).collect::<String>();
    s += "</tr></thead><tbody>";
    for (row_class, cells) in rows {
        if row_class.is_empty() {
            s += "<tr>";
        } else {
            s += &format!("<tr class=\"{row_class}\">");
        }
        s += &cells.iter().map(|c| cell("td", c)).collect::<String>();
        s += "</tr>";
    }
    s + "</tbody></table>"
}

/// A chart, or a note saying why it could not be drawn.
pub(crate) fn chart(svg: Result<String, rsf_plot::PlotError>) -> String {
    match svg {
        Ok(s) => s,
        Err(e) => format!("<p class=\"note\">(chart not drawn: {})</p>", esc(&e.to_string())),
    }
}

/// The diagnosis as a self-contained HTML page (inline SVG and style, no external resources).
/// `name` is the record's name (e.g. its file name).
pub fn diagnosis_html(d: &Diagnosis, name: &str) -> String {
    let body = [
        sections::header(d, name),
        sections::verdict_section(d),
        sections::record_quality(d),
        sections::gain(d),
        sections::effect(d),
        sections::parameters(d),
        sections::models(d),
        sections::residuals(d),
        adequacy::adequacy(d),
        sections::noise(d),
        sections::events(d),
        sections::candidates(d),
        sections::evidence(d),
    ]
    .concat();
    format!(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <title>rsf diagnose: {}</title><style>{STYLE}</style></head>\n<body>\n{body}\n</body></html>\n",
        esc(name)
    )
}
