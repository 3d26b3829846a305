//! Panels of series on linear or logarithmic axes, rendered to an SVG string.
//!
//! One range rule for every figure: a linear axis spans the data padded by 5 % of their span on
//! each side (a degenerate span, all values equal, by 10 % of the value, or 10⁻⁶ at zero); a
//! logarithmic axis spans whole decades. Tick labels: on a linear axis all with the decimals that
//! keep them exact and distinct, values below 10⁻² (or from 10⁵) scaled by a power of ten shown
//! in the axis label (`residual (×10⁻⁴)`); on a logarithmic axis only powers of ten (`10⁻³`).

use crate::fmt::{superscript, tick_decimals};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::panel::{BLACK, LegendPosition, Panel, RGBColor, Style};

/// Drawing failed (the SVG backend only fails on a bad layout).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlotError(pub String);

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "plot: {}", self.0)
    }
}

impl std::error::Error for PlotError {}

fn err(e: impl std::fmt::Display) -> PlotError {
    PlotError(e.to_string())
}

/// Height of the figure title, px.
const TITLE_H: u32 = 40;

/// Renders `panels` on a grid of `columns` columns, each panel `panel_size` pixels, under
/// `title` (empty: none), as an SVG document.
pub fn render(title: &str, panels: &[Panel], columns: usize, panel_size: (u32, u32)) -> Result<String, PlotError> {
    let columns = columns.max(1);
    let rows = panels.len().div_ceil(columns).max(1);
    let head = if title.is_empty() { 0 } else { TITLE_H };
    let size = (panel_size.0 * columns as u32, panel_size.1 * rows as u32 + head);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = if title.is_empty() { root } else { root.titled(title, ("sans-serif", 20)).map_err(err)? };
        for (area, p) in root.split_evenly((rows, columns)).iter().zip(panels) {
            panel(area, p)?;
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// Renders `panels` one above the other, each `(panel, height px)`, `width` pixels wide, under
/// `title` (empty: none), as an SVG document.
pub fn render_stack(title: &str, panels: &[(Panel, u32)], width: u32) -> Result<String, PlotError> {
    let head = if title.is_empty() { 0 } else { TITLE_H };
    let size = (width, panels.iter().map(|p| p.1).sum::<u32>() + head);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = if title.is_empty() { root } else { root.titled(title, ("sans-serif", 17)).map_err(err)? };
        let mut rest = root;
        for (p, h) in panels {
            let (area, below) = rest.split_vertically(*h);
            panel(&area, p)?;
            rest = below;
        }
        rest.present().map_err(err)?;
    }
    Ok(svg)
}

/// The range of one coordinate over all series (with error bars in y) and bands (in x), by the
/// range rule of this module.
pub fn range(p: &Panel, x: bool, log: bool) -> (f64, f64) {
    let mut vals: Vec<f64> = Vec::new();
    for s in &p.series {
        for (i, q) in s.points.iter().enumerate() {
            if x {
                vals.push(q.0);
            } else {
                let e = s.y_err.get(i).copied().filter(|e| e.is_finite()).unwrap_or(0.0);
                vals.extend([q.1 - e, q.1 + e]);
            }
        }
    }
    if x {
        vals.extend(p.bands.iter().flat_map(|b| [b.0, b.1]));
    }
    padded(vals.into_iter(), log)
}

/// The range rule: linear, the span padded by 5 % on each side (a degenerate span by 10 % of
/// the value, 10⁻⁶ at zero); logarithmic, whole decades. Non-finite (and on a logarithmic axis,
/// non-positive) values are ignored; no values give 0–1 (0.1–10 on a logarithmic axis).
pub fn padded(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    if !lo.is_finite() {
        return if log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        let (a, b) = (lo.log10().floor(), hi.log10().ceil());
        return (10f64.powf(a), 10f64.powf(if b > a { b } else { a + 1.0 }));
    }
    let scale = hi.abs().max(lo.abs());
    let pad = if hi - lo > 1e-9 * scale { 0.05 * (hi - lo) } else { (0.1 * scale).max(1e-6) };
    (lo - pad, hi + pad)
}

/// Labels per axis (plotters' default is 11 at most).
const N_LABELS: usize = 9;

/// How the ticks of one axis are labelled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AxisLabels {
    /// Logarithmic: only powers of ten are labelled.
    pub log: bool,
    /// Labels show value / 10^exp (0: unscaled).
    pub exp: i32,
    /// Decimals of the scaled labels.
    pub decimals: usize,
    /// Only whole numbers are labelled.
    pub integer: bool,
}

impl AxisLabels {
    /// The labelling of an axis over `lo..hi` with plotters' ticks for at most `n` labels.
    pub fn new(lo: f64, hi: f64, log: bool, n: usize) -> Self {
        if log {
            return Self { log, exp: 0, decimals: 0, integer: false };
        }
        let m = lo.abs().max(hi.abs());
        let e = if m > 0.0 { m.log10().floor() as i32 } else { 0 };
        let exp = if (-2..5).contains(&e) { 0 } else { e };
        let s = 10f64.powi(exp);
        let ticks: Vec<f64> = RangedCoordf64::from(lo..hi).key_points(n).iter().map(|t| t / s).collect();
        Self { log, exp, decimals: tick_decimals(&ticks), integer: false }
    }
    /// The label of the tick at `v`.
    pub fn label(&self, v: f64) -> String {
        if self.log {
            let e = v.log10();
            if (e - e.round()).abs() > 1e-6 {
                return String::new();
            }
            return match e.round() as i32 {
                0 => "1".into(),
                1 => "10".into(),
                e => format!("10{}", superscript(e)),
            };
        }
        if self.integer {
            return if (v - v.round()).abs() < 1e-9 * v.abs().max(1.0) {
                format!("{}", v.round() as i64)
            } else {
                String::new()
            };
        }
        let d = self.decimals;
        let s = format!("{:.d$}", v / 10f64.powi(self.exp));
        let s =
            if s.starts_with('-') && s.chars().all(|c| matches!(c, '-' | '0' | '.')) { s[1..].to_string() } else { s };
        s.replacen('-', "−", 1)
    }
    /// The axis description with the scale factor, if any: `residual (×10⁻⁴)`.
    pub fn desc(&self, base: &str) -> String {
        if self.exp == 0 { base.to_string() } else { format!("{base} (×10{})", superscript(self.exp)) }
    }
    /// The labels of plotters' ticks over `lo..hi` (linear axes).
    pub fn tick_labels(&self, lo: f64, hi: f64, n: usize) -> Vec<String> {
        RangedCoordf64::from(lo..hi).key_points(n).iter().map(|&t| self.label(t)).collect()
    }
}

fn panel(area: &DrawingArea<SVGBackend<'_>, Shift>, p: &Panel) -> Result<(), PlotError> {
    let (x0, x1) = p.x_range.unwrap_or_else(|| range(p, true, p.log_x));
    let (y0, y1) = p.y_range.unwrap_or_else(|| range(p, false, p.log_y));
    match (p.log_x, p.log_y) {
        (false, false) => draw(area, p, x0..x1, y0..y1),
        (true, false) => draw(area, p, (x0..x1).log_scale(), y0..y1),
        (false, true) => draw(area, p, x0..x1, (y0..y1).log_scale()),
        (true, true) => draw(area, p, (x0..x1).log_scale(), (y0..y1).log_scale()),
    }
}

fn draw<X, Y>(area: &DrawingArea<SVGBackend<'_>, Shift>, p: &Panel, x: X, y: Y) -> Result<(), PlotError>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut b = ChartBuilder::on(area);
    if !p.title.is_empty() {
        b.caption(&p.title, ("sans-serif", 16));
    }
    let mut c = b.margin(12).x_label_area_size(42).y_label_area_size(72).build_cartesian_2d(x, y).map_err(err)?;
    let (xr, yr) = (c.x_range(), c.y_range());
    let lx = AxisLabels { integer: p.integer_x && !p.log_x, ..AxisLabels::new(xr.start, xr.end, p.log_x, N_LABELS) };
    let ly = AxisLabels::new(yr.start, yr.end, p.log_y, N_LABELS);
    let (x_desc, y_desc) = (lx.desc(&p.x_label), ly.desc(&p.y_label));
    c.configure_mesh()
        .x_labels(N_LABELS)
        .y_labels(N_LABELS)
        .x_desc(x_desc.as_str())
        .y_desc(y_desc.as_str())
        .x_label_formatter(&|v| lx.label(*v))
        .y_label_formatter(&|v| ly.label(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    let shade = RGBColor(232, 238, 248);
    c.draw_series(p.bands.iter().map(|&(a, b)| Rectangle::new([(a, yr.start), (b, yr.end)], shade.filled())))
        .map_err(err)?;
    if p.zero_line && !p.log_y && yr.start < 0.0 && yr.end > 0.0 {
        c.draw_series(LineSeries::new(vec![(xr.start, 0.0), (xr.end, 0.0)], BLACK.stroke_width(1))).map_err(err)?;
    }
    let (log_x, log_y) = (p.log_x, p.log_y);
    let mut any_label = false;
    for s in &p.series {
        let keep = |a: f64, b: f64| {
            a.is_finite()
                && b.is_finite()
                && (!log_x || a > 0.0)
                && (!log_y || b > 0.0)
                && p.x_range.is_none_or(|(lo, hi)| (lo..=hi).contains(&a))
        };
        let idx: Vec<usize> = (0..s.points.len()).filter(|&i| keep(s.points[i].0, s.points[i].1)).collect();
        let pts: Vec<(f64, f64)> = idx.iter().map(|&i| s.points[i]).collect();
        let color = s.color;
        if !s.y_err.is_empty() {
            let bars = idx.iter().filter_map(|&i| {
                let (q, e) = (s.points[i], s.y_err.get(i).copied().unwrap_or(0.0));
                let (lo, hi) = (q.1 - e, q.1 + e);
                (e > 0.0 && e.is_finite() && (!log_y || lo > 0.0))
                    .then(|| PathElement::new(vec![(q.0, lo), (q.0, hi)], color.stroke_width(1)))
            });
            c.draw_series(bars).map_err(err)?;
        }
        let anno = match s.style {
            Style::Line => c.draw_series(LineSeries::new(pts, color.stroke_width(2))).map_err(err)?,
            Style::Dashed => c.draw_series(DashedLineSeries::new(pts, 6, 4, color.stroke_width(2))).map_err(err)?,
            Style::Markers => {
                c.draw_series(LineSeries::new(pts.clone(), color.stroke_width(1))).map_err(err)?;
                c.draw_series(pts.into_iter().map(|q| Circle::new(q, 4, color.filled()))).map_err(err)?
            }
            Style::Points => c.draw_series(pts.into_iter().map(|q| Circle::new(q, 4, color.filled()))).map_err(err)?,
            Style::Dots => c.draw_series(pts.into_iter().map(|q| Circle::new(q, 1, color.filled()))).map_err(err)?,
        };
        if let Some(l) = &s.label {
            any_label = true;
            let style = s.style;
            anno.label(l.as_str()).legend(move |(x, y)| {
                let (radius, width) = match style {
                    Style::Markers => (4, 1),
                    Style::Points | Style::Dots => (3, 0),
                    Style::Line | Style::Dashed => (0, 2),
                };
                EmptyElement::at((x, y))
                    + Circle::new((10, 0), radius, color.filled())
                    + PathElement::new(vec![(0, 0), (20, 0)], color.stroke_width(width))
            });
        }
    }
    if any_label {
        c.configure_series_labels()
            .position(p.legend.clone().unwrap_or_else(|| legend_corner(p, (xr.start, xr.end), (yr.start, yr.end))))
            .label_font(("sans-serif", 12))
            .border_style(plotters::style::BLACK)
            .background_style(WHITE.mix(0.85))
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

/// The corner of the plot where the legend hides the fewest points: the legend box is taken as
/// a share of the plot area that grows with the number and length of its entries.
fn legend_corner(p: &Panel, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> LegendPosition {
    let labels: Vec<&String> = p.series.iter().filter_map(|s| s.label.as_ref()).collect();
    let longest = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0) as f64;
    let w = (0.12 + 0.014 * longest).min(0.7);
    let h = (0.06 + 0.055 * labels.len() as f64).min(0.7);
    let unit = |v: f64, a: f64, b: f64, log: bool| {
        if log { (v.max(1e-300).ln() - a.ln()) / (b.ln() - a.ln()) } else { (v - a) / (b - a) }
    };
    let corners = [
        (LegendPosition::UpperRight, false, true),
        (LegendPosition::UpperLeft, true, true),
        (LegendPosition::LowerRight, false, false),
        (LegendPosition::LowerLeft, true, false),
    ];
    let mut hidden = [0usize; 4];
    for s in &p.series {
        for &(x, y) in &s.points {
            let (u, v) = (unit(x, x0, x1, p.log_x), unit(y, y0, y1, p.log_y));
            if !(u.is_finite() && v.is_finite()) {
                continue;
            }
            for (k, &(_, left, top)) in corners.iter().enumerate() {
                let inx = if left { u < w } else { u > 1.0 - w };
                let iny = if top { v > 1.0 - h } else { v < h };
                hidden[k] += usize::from(inx && iny);
            }
        }
    }
    let best = (0..4).min_by_key(|&k| hidden[k]).unwrap_or(0);
    corners[best].0.clone()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::panel::{PALETTE, Series};

    #[test]
    fn ticks_of_a_narrow_friction_range_are_distinct() {
        for (lo, hi) in [(0.6055, 0.6065), (0.60551, 0.60553), (0.6, 0.61), (-3e-4, 4e-4), (1.0, 1.000001)] {
            for n in [5, N_LABELS, 11] {
                let a = AxisLabels::new(lo, hi, false, n);
                let l = a.tick_labels(lo, hi, n);
                assert!(l.len() >= 2, "{lo}–{hi}: {l:?}");
                let mut u = l.clone();
                u.sort();
                u.dedup();
                assert_eq!(u.len(), l.len(), "{lo}–{hi} ({n} labels): {l:?}");
                assert!(l.iter().all(|s| s.len() <= 9), "{l:?}");
            }
        }
        let a = AxisLabels::new(0.6055, 0.6065, false, N_LABELS);
        assert_eq!(a.tick_labels(0.6055, 0.6065, N_LABELS)[..3], ["0.6056", "0.6058", "0.6060"]);
        let r = AxisLabels::new(-3e-4, 4e-4, false, N_LABELS);
        assert_eq!(r.desc("residual"), "residual (×10⁻⁴)");
        assert!(r.tick_labels(-3e-4, 4e-4, N_LABELS).contains(&"−2".to_string()));
    }

    #[test]
    fn the_legend_goes_where_the_data_are_not() {
        let rising: Vec<(f64, f64)> = (0..100).map(|i| (i as f64, i as f64)).collect();
        let p = Panel::new("", "x", "y").with(Series::dots("data".to_string(), rising, BLACK));
        let (x, y) = (range(&p, true, false), range(&p, false, false));
        assert!(matches!(legend_corner(&p, x, y), LegendPosition::UpperLeft));
        let labels = AxisLabels { integer: true, ..AxisLabels::new(0.5, 3.5, false, N_LABELS) };
        let l: Vec<String> = labels.tick_labels(0.5, 3.5, N_LABELS).into_iter().filter(|s| !s.is_empty()).collect();
        assert_eq!(l, ["1", "2", "3"]);
    }

    #[test]
    fn one_range_rule() {
        assert_eq!(padded([1.0, 3.0].into_iter(), false), (0.9, 3.1));
        let (a, b) = padded([0.6, 0.6].into_iter(), false);
        assert!((a - 0.54).abs() < 1e-12 && (b - 0.66).abs() < 1e-12);
        assert_eq!(padded([0.0].into_iter(), false), (-1e-6, 1e-6));
        assert_eq!(padded([0.02, 3.0].into_iter(), true), (0.01, 10.0));
        assert_eq!(padded(std::iter::empty(), false), (0.0, 1.0));
    }

    #[test]
    fn renders_every_style() {
        let pts: Vec<(f64, f64)> = (1..20).map(|i| (i as f64, (i as f64).ln())).collect();
        let styles = [Style::Line, Style::Dashed, Style::Markers, Style::Points, Style::Dots];
        let p =
            styles.iter().enumerate().fold(Panel::new("all", "x (s)", "y").band(2.0, 4.0).zero_line(), |p, (i, s)| {
                p.with(Series::new(format!("s{i}"), pts.clone(), PALETTE[i], *s).y_err(vec![0.1; pts.len()]))
            });
        let svg = render("", &[p.clone(), p.clone().log_x().log_y()], 2, (400, 300)).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("s4"));
        let svg = render_stack("stack", &[(p.clone(), 300), (p, 200)], 800).unwrap();
        assert!(svg.contains("viewBox=\"0 0 800 540\""));
    }
}
