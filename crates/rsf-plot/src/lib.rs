//! # rsf-plot — the one chart module of rsf
//!
//! Multi-panel SVG figures on plotters' SVG backend (no system libraries), in one house style:
//! white background, sans-serif labels with units, a boxed legend, linear or logarithmic axes,
//! and one range-padding rule. Used by `rsf fit --plot`, `rsf simulate --plot`, the diagnosis
//! report of `rsf-fit` and the figures of `rsf-paper`. Figures are rendered to a string; the
//! caller decides where to write it.
//!
//! | module | what |
//! |---|---|
//! | [`panel`] | [`Panel`], [`Series`], [`Style`], the palette |
//! | [`chart`] | [`render`] (a grid of panels), [`render_stack`] (panels of given heights, one above the other), the range rule, tick labels, legend placement |
//! | [`fmt`] | numbers for people: [`fmt_value`], [`fmt_with_err`], [`fmt_pair`], tick labels that are always distinct |
//!
//! ```
//! use rsf_plot::{Panel, Series, PALETTE, render};
//!
//! let pts: Vec<(f64, f64)> = (0..50).map(|i| (i as f64, 0.6055 + 1e-3 * (i as f64 / 50.0))).collect();
//! let p = Panel::new("friction", "time (s)", "friction μ").with(Series::line("model".to_string(), pts, PALETTE[0]));
//! let svg = render("one panel", &[p], 1, (600, 400)).unwrap();
//! assert!(svg.starts_with("<svg") && svg.contains("0.6060"));
//! ```
#![forbid(unsafe_code)]

pub mod chart;
pub mod fmt;
pub mod panel;

pub use chart::{PlotError, render, render_stack};
pub use fmt::{fmt_common, fmt_num, fmt_pair, fmt_value, fmt_with_err, superscript, tick_labels};
pub use panel::{BLACK, GREY, LegendPosition, PALETTE, Panel, RGBColor, Series, Style, lighter, ordered_color};
