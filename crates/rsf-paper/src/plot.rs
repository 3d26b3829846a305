//! Multi-panel SVG figures (plotters, SVG backend), in the house style of `rsf simulate --plot`:
//! white background, sans-serif labels with units, a boxed legend, linear or logarithmic axes.
//! Figures are rendered to a string; the caller decides where to write it.

use crate::PaperError;
use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::prelude::*;

pub use plotters::style::RGBColor;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A solid line, 2 px.
    Line,
    /// A dashed line, 1.5 px (reference lines, analytic results).
    Dashed,
    /// Filled circles joined by a thin line (a few computed points).
    Markers,
}

/// One curve of a panel.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend entry (none: not in the legend).
    pub label: Option<String>,
    /// The points; on a logarithmic axis non-positive values are skipped.
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub color: RGBColor,
    /// Line style.
    pub style: Style,
}

impl Series {
    /// A solid line.
    pub fn line(label: impl Into<Option<String>>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self { label: label.into(), points, color, style: Style::Line }
    }
    /// A dashed line.
    pub fn dashed(label: impl Into<Option<String>>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self { label: label.into(), points, color, style: Style::Dashed }
    }
    /// Markers joined by a thin line.
    pub fn markers(label: impl Into<Option<String>>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self { label: label.into(), points, color, style: Style::Markers }
    }
}

/// Where the legend goes.
pub use plotters::chart::SeriesLabelPosition as LegendPosition;

/// One panel: axes, labels and series.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Panel title (e.g. `"B  Slip law"`).
    pub title: String,
    /// x-axis label with unit.
    pub x_label: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// Fixed x range (default: the data's, padded by 5 % on linear axes); points outside it
    /// are not drawn.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range.
    pub y_range: Option<(f64, f64)>,
    /// Legend position.
    pub legend: LegendPosition,
    /// The curves, drawn in order.
    pub series: Vec<Series>,
}

impl Panel {
    /// A panel with linear axes, the legend upper right and no series yet.
    pub fn new(title: impl Into<String>, x_label: impl Into<String>, y_label: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            log_x: false,
            log_y: false,
            x_range: None,
            y_range: None,
            legend: LegendPosition::UpperRight,
            series: Vec::new(),
        }
    }
    /// Logarithmic x axis.
    pub fn log_x(mut self) -> Self {
        self.log_x = true;
        self
    }
    /// Logarithmic y axis.
    pub fn log_y(mut self) -> Self {
        self.log_y = true;
        self
    }
    /// Fixed x range.
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }
    /// Fixed y range.
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }
    /// Legend position.
    pub fn legend(mut self, at: LegendPosition) -> Self {
        self.legend = at;
        self
    }
    /// Adds a series.
    pub fn with(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }
}

/// Black, for reference lines.
pub const BLACK: RGBColor = RGBColor(0, 0, 0);

/// Ten distinguishable colours (Tableau 10), for unordered series.
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// `c` mixed towards white by the fraction `w` (0: unchanged, 1: white), for secondary lines.
pub fn lighter(c: RGBColor, w: f64) -> RGBColor {
    let m = |x: u8| (x as f64 + (255.0 - x as f64) * w).round() as u8;
    RGBColor(m(c.0), m(c.1), m(c.2))
}

/// Colour `i` of `n` ordered series (e.g. step sizes): dark blue through teal to orange-red.
pub fn ordered_color(i: usize, n: usize) -> RGBColor {
    const STOPS: [(f64, f64, f64); 3] = [(37.0, 52.0, 148.0), (44.0, 162.0, 130.0), (230.0, 85.0, 13.0)];
    let s = if n > 1 { i as f64 / (n - 1) as f64 } else { 0.0 } * 2.0;
    let k = (s.floor() as usize).min(1);
    let w = s - k as f64;
    let mix = |a: f64, b: f64| (a + (b - a) * w).round() as u8;
    RGBColor(mix(STOPS[k].0, STOPS[k + 1].0), mix(STOPS[k].1, STOPS[k + 1].1), mix(STOPS[k].2, STOPS[k + 1].2))
}

/// Renders `panels` on a grid of `columns` columns, each panel `panel_size` pixels, under
/// `title`, as an SVG document.
pub fn render(title: &str, panels: &[Panel], columns: usize, panel_size: (u32, u32)) -> Result<String, PaperError> {
    let rows = panels.len().div_ceil(columns);
    let size = (panel_size.0 * columns as u32, panel_size.1 * rows as u32 + 40);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = root.titled(title, ("sans-serif", 20)).map_err(err)?;
        for (area, p) in root.split_evenly((rows, columns)).iter().zip(panels) {
            let (x0, x1) = p.x_range.unwrap_or_else(|| range(p, |q| q.0, p.log_x));
            let (y0, y1) = p.y_range.unwrap_or_else(|| range(p, |q| q.1, p.log_y));
            match (p.log_x, p.log_y) {
                (false, false) => draw(area, p, x0..x1, y0..y1)?,
                (true, false) => draw(area, p, (x0..x1).log_scale(), y0..y1)?,
                (false, true) => draw(area, p, x0..x1, (y0..y1).log_scale())?,
                (true, true) => draw(area, p, (x0..x1).log_scale(), (y0..y1).log_scale())?,
            }
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}

fn err(e: impl std::fmt::Display) -> PaperError {
    PaperError::Plot(e.to_string())
}

/// The data range of one coordinate over all series; padded by 5 % on linear axes, widened to
/// whole decades on logarithmic ones.
fn range(p: &Panel, coord: impl Fn(&(f64, f64)) -> f64, log: bool) -> (f64, f64) {
    let (lo, hi) = p
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(&coord))
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    if !lo.is_finite() {
        return if log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        let (a, b) = (lo.log10().floor(), hi.log10().ceil());
        (10f64.powf(a), 10f64.powf(if b > a { b } else { a + 1.0 }))
    } else {
        let pad = ((hi - lo) * 0.05).max(1e-12 * hi.abs().max(1.0));
        (lo - pad, hi + pad)
    }
}

/// Tick label: on a logarithmic axis only powers of ten are labelled (`10⁻³`); on a linear axis
/// the shortest decimal form.
fn tick(v: f64, log: bool) -> String {
    if log {
        let e = v.log10();
        if (e - e.round()).abs() > 1e-6 {
            return String::new();
        }
        let e = e.round() as i32;
        return match e {
            0 => "1".into(),
            1 => "10".into(),
            _ => format!("10{}", superscript(e)),
        };
    }
    let s = format!("{:.6}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

fn superscript(e: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::new();
    if e < 0 {
        s.push('⁻');
    }
    for c in e.unsigned_abs().to_string().chars() {
        s.push(DIGITS[c.to_digit(10).expect("a decimal digit") as usize]);
    }
    s
}

fn draw<X, Y>(area: &DrawingArea<SVGBackend<'_>, Shift>, p: &Panel, x: X, y: Y) -> Result<(), PaperError>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut c = ChartBuilder::on(area)
        .caption(&p.title, ("sans-serif", 16))
        .margin(12)
        .x_label_area_size(42)
        .y_label_area_size(72)
        .build_cartesian_2d(x, y)
        .map_err(err)?;
    let (lx, ly) = (p.log_x, p.log_y);
    c.configure_mesh()
        .x_desc(p.x_label.as_str())
        .y_desc(p.y_label.as_str())
        .x_label_formatter(&|v| tick(*v, lx))
        .y_label_formatter(&|v| tick(*v, ly))
        .light_line_style(RGBColor(235, 235, 235))
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    let mut any_label = false;
    for s in &p.series {
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|&(a, b)| a.is_finite() && b.is_finite() && (!lx || a > 0.0) && (!ly || b > 0.0))
            .filter(|&(a, _)| p.x_range.is_none_or(|(lo, hi)| (lo..=hi).contains(&a)))
            .collect();
        let color = s.color;
        let anno = match s.style {
            Style::Line => c.draw_series(LineSeries::new(pts, color.stroke_width(2))).map_err(err)?,
            Style::Dashed => c.draw_series(DashedLineSeries::new(pts, 6, 4, color.stroke_width(2))).map_err(err)?,
            Style::Markers => {
                c.draw_series(LineSeries::new(pts.clone(), color.stroke_width(1))).map_err(err)?;
                c.draw_series(pts.into_iter().map(|q| Circle::new(q, 4, color.filled()))).map_err(err)?
            }
        };
        if let Some(l) = &s.label {
            any_label = true;
            let markers = s.style == Style::Markers;
            anno.label(l.as_str()).legend(move |(x, y)| {
                let (radius, width) = if markers { (4, 1) } else { (0, 2) };
                EmptyElement::at((x, y))
                    + Circle::new((10, 0), radius, color.filled())
                    + PathElement::new(vec![(0, 0), (20, 0)], color.stroke_width(width))
            });
        }
    }
    if any_label {
        c.configure_series_labels()
            .position(p.legend.clone())
            .label_font(("sans-serif", 12))
            .border_style(plotters::style::BLACK)
            .background_style(WHITE.mix(0.85))
            .draw()
            .map_err(err)?;
    }
    Ok(())
}
