//! What a figure is made of: [`Panel`]s of [`Series`] drawn in a [`Style`], and the colours.

pub use plotters::style::RGBColor;

/// Where the legend goes.
pub use plotters::chart::SeriesLabelPosition as LegendPosition;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A solid line, 2 px.
    Line,
    /// A dashed line, 2 px (reference lines, analytic results).
    Dashed,
    /// Filled circles joined by a thin line (a few computed points).
    Markers,
    /// Filled circles, not joined (a scatter of a few points, optionally with error bars).
    Points,
    /// Small dots (thousands of samples of a record).
    Dots,
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
    /// Error bars in y, one half-width per point (empty: none).
    pub y_err: Vec<f64>,
}

impl Series {
    /// A series of `style`.
    pub fn new(label: impl Into<Option<String>>, points: Vec<(f64, f64)>, color: RGBColor, style: Style) -> Self {
        Self { label: label.into(), points, color, style, y_err: Vec::new() }
    }
    /// A solid line.
    pub fn line(label: impl Into<Option<String>>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self::new(label, points, color, Style::Line)
    }
    /// A dashed line.
    pub fn dashed(label: impl Into<Option<String>>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self::new(label, points, color, Style::Dashed)
    }
    /// Markers joined by a thin line.
    pub fn markers(label: impl Into<Option<String>>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self::new(label, points, color, Style::Markers)
    }
    /// Markers, not joined.
    pub fn points(label: impl Into<Option<String>>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self::new(label, points, color, Style::Points)
    }
    /// Small dots.
    pub fn dots(label: impl Into<Option<String>>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self::new(label, points, color, Style::Dots)
    }
    /// With error bars in y (half-widths, one per point).
    pub fn y_err(mut self, err: Vec<f64>) -> Self {
        self.y_err = err;
        self
    }
}

/// One panel: axes, labels and series.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Panel title (e.g. `"B  Slip law"`; empty: none).
    pub title: String,
    /// x-axis label with unit.
    pub x_label: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// Fixed x range (default: the data's, by the range rule); points outside it are not drawn.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range.
    pub y_range: Option<(f64, f64)>,
    /// Legend position (none: the corner that hides the fewest points).
    pub legend: Option<LegendPosition>,
    /// Label only whole numbers on the x axis (e.g. segment numbers).
    pub integer_x: bool,
    /// Shaded x intervals behind the series (e.g. alternate segments of a record).
    pub bands: Vec<(f64, f64)>,
    /// A thin black line at y = 0.
    pub zero_line: bool,
    /// The curves, drawn in order.
    pub series: Vec<Series>,
}

impl Panel {
    /// A panel with linear axes, the legend where it hides the fewest points, no series yet.
    pub fn new(title: impl Into<String>, x_label: impl Into<String>, y_label: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            log_x: false,
            log_y: false,
            x_range: None,
            y_range: None,
            legend: None,
            integer_x: false,
            bands: Vec::new(),
            zero_line: false,
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
        self.legend = Some(at);
        self
    }
    /// Label only whole numbers on the x axis.
    pub fn integer_x(mut self) -> Self {
        self.integer_x = true;
        self
    }
    /// A shaded x interval.
    pub fn band(mut self, lo: f64, hi: f64) -> Self {
        self.bands.push((lo, hi));
        self
    }
    /// A thin black line at y = 0.
    pub fn zero_line(mut self) -> Self {
        self.zero_line = true;
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

/// Grey, for measured data behind models.
pub const GREY: RGBColor = RGBColor(140, 140, 140);

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
