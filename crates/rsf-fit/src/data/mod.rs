//! Reading measured records: delimited text with a header naming the columns.

use serde::Serialize;
use std::path::Path;

/// Displacement unit of the file's load-point column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DispUnit {
    /// µm (default).
    Um,
    /// mm.
    Mm,
    /// m.
    M,
}

impl DispUnit {
    /// Factor to µm.
    pub fn to_um(self) -> f64 {
        match self {
            Self::Um => 1.0,
            Self::Mm => 1e3,
            Self::M => 1e6,
        }
    }
}

rsf_core::vocabulary!(DispUnit, "displacement unit", { Um => "um" | "µm" | "micron" | "microns", Mm => "mm", M => "m" });

/// Time unit of the file's time column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeUnit {
    /// s (default).
    S,
    /// ms.
    Ms,
}

impl TimeUnit {
    /// Factor to s.
    pub fn to_s(self) -> f64 {
        match self {
            Self::S => 1.0,
            Self::Ms => 1e-3,
        }
    }
}

rsf_core::vocabulary!(TimeUnit, "time unit", { S => "s", Ms => "ms" });

/// Which columns to read and how to convert them.
#[derive(Clone, Debug)]
pub struct ReadOptions {
    /// Time column (default `time_s`).
    pub time_col: String,
    /// Load-point displacement column (default `load_point_um`).
    pub lp_col: String,
    /// Friction column (default `mu`); ignored when `shear_col` is set.
    pub mu_col: String,
    /// Shear-stress column; friction = shear / normal stress.
    pub shear_col: Option<String>,
    /// Normal-stress column (MPa; with a shear column, the same units as shear). Read with a
    /// friction column too: a varying σ drives the forward model.
    pub normal_col: Option<String>,
    /// Constant normal stress (same units as shear), instead of a column.
    pub normal_stress: Option<f64>,
    /// Unit of the load-point column.
    pub disp_unit: DispUnit,
    /// Unit of the time column.
    pub time_unit: TimeUnit,
    /// Keep rows with time ≥ this (s, after unit conversion).
    pub t_min: Option<f64>,
    /// Keep rows with time ≤ this (s).
    pub t_max: Option<f64>,
    /// Rows whose time repeats the previous row's.
    pub duplicate_times: DuplicateTimes,
    /// Rows with an over-range, sentinel or non-finite value: refused (default) or dropped.
    pub invalid: InvalidRows,
    /// Read a record that does not look like a friction experiment ([`plausible::check`]:
    /// friction outside 0.05–2 or negative, columns swapped, the load point backwards or at an
    /// implausible speed) instead of refusing it; each finding becomes a warning of the record.
    pub accept_implausible: bool,
}

impl Default for ReadOptions {
    fn default() -> Self {
        Self {
            time_col: "time_s".into(),
            lp_col: "load_point_um".into(),
            mu_col: "mu".into(),
            shear_col: None,
            normal_col: None,
            normal_stress: None,
            disp_unit: DispUnit::Um,
            time_unit: TimeUnit::S,
            t_min: None,
            t_max: None,
            duplicate_times: DuplicateTimes::Error,
            invalid: InvalidRows::Error,
            accept_implausible: false,
        }
    }
}

/// A measured record in rsf units: time (s), load-point displacement (µm), friction.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Record {
    /// Time, s, strictly increasing.
    pub time: Vec<f64>,
    /// Load-point displacement, µm.
    pub load_point: Vec<f64>,
    /// Friction (shear stress / normal stress).
    pub mu: Vec<f64>,
    /// Normal stress per sample, MPa (empty when the record has no normal-stress column).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub normal_stress: Vec<f64>,
    /// Where it came from.
    pub source: String,
    /// Rows dropped because their time repeated the previous row's
    /// ([`DuplicateTimes::Drop`]).
    pub dropped_duplicate_times: usize,
    /// Rows dropped for an invalid value ([`InvalidRows::Drop`]).
    #[serde(skip_serializing_if = "is_zero")]
    pub dropped_invalid: usize,
    /// What the reader warned of (a dropped cut last line, a Windows-1252 header, dropped rows).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl Record {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time.len()
    }
    /// Whether empty.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }
    /// The rows with `t0 <= time <= t1`.
    pub fn window(&self, t0: f64, t1: f64) -> Record {
        let i0 = self.time.partition_point(|&t| t < t0);
        let i1 = self.time.partition_point(|&t| t <= t1);
        Record {
            time: self.time[i0..i1].to_vec(),
            load_point: self.load_point[i0..i1].to_vec(),
            mu: self.mu[i0..i1].to_vec(),
            normal_stress: if self.normal_stress.is_empty() { vec![] } else { self.normal_stress[i0..i1].to_vec() },
            source: self.source.clone(),
            dropped_duplicate_times: self.dropped_duplicate_times,
            dropped_invalid: self.dropped_invalid,
            warnings: self.warnings.clone(),
        }
    }

    /// The record without the samples `drop` (sorted indices).
    pub fn without(&self, drop: &[usize]) -> Record {
        let keep =
            |v: &[f64]| v.iter().enumerate().filter(|(i, _)| drop.binary_search(i).is_err()).map(|(_, x)| *x).collect();
        Record {
            time: keep(&self.time),
            load_point: keep(&self.load_point),
            mu: keep(&self.mu),
            normal_stress: keep(&self.normal_stress),
            source: self.source.clone(),
            dropped_duplicate_times: self.dropped_duplicate_times,
            dropped_invalid: self.dropped_invalid,
            warnings: self.warnings.clone(),
        }
    }
}

/// A spike's departure from the mean of its two neighbours must exceed this many of its own
/// standard deviations (σ√1.5 for noise σ): Gaussian noise does so with probability 2·10⁻⁹ per
/// sample (and must then also show the neighbours' signature), while a spike of height 10σ
/// stands 8.2 of them out — electrical spikes in friction records are 10–20σ.
pub const SPIKE_SIGMA: f64 = 6.0;

/// Isolated single-sample spikes in `x` (sorted indices): samples that stand more than
/// [`SPIKE_SIGMA`] noise σ off the mean of their neighbours, with both neighbours off the mean
/// of theirs by a quarter to three quarters of that, in the opposite direction — the signature
/// of one bad sample (a jump between two samples, such as a stick-slip drop or the onset of a
/// velocity step, has a different one and is kept).
pub fn isolated_spikes(x: &[f64]) -> Vec<usize> {
    let n = x.len();
    if n < 5 {
        return vec![];
    }
    let mut d: Vec<f64> = x.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    d.sort_by(f64::total_cmp);
    // σ of x from the median |Δx| (of a Gaussian with σ√2: 0.6745 σ√2)
    let sigma = d[d.len() / 2] / (0.6745 * std::f64::consts::SQRT_2);
    if !(sigma > 0.0) {
        return vec![];
    }
    // r_i = x_i − (x_{i−1} + x_{i+1})/2 has standard deviation σ √1.5
    let r = |i: usize| x[i] - 0.5 * (x[i - 1] + x[i + 1]);
    let thr = SPIKE_SIGMA * sigma * 1.5f64.sqrt();
    (2..n - 2)
        .filter(|&i| {
            let ri = r(i);
            ri.abs() > thr
                && [r(i - 1), r(i + 1)]
                    .iter()
                    .all(|&rn| rn * ri < 0.0 && (0.25..=0.75).contains(&(rn.abs() / ri.abs())))
        })
        .collect()
}

/// A data error naming file, line and column where known: the one reader's error.
pub use rsf_record::ReadError as DataError;
pub use rsf_record::{DuplicateTimes, InvalidRows, MIN_ROWS, ReadErrorKind};

impl ReadOptions {
    /// The columns to read, in the order `read_lines` expects them: time, load point, then
    /// friction or shear, then normal stress.
    fn spec(&self) -> Result<rsf_record::Spec, String> {
        use rsf_record::Column;
        let mut cols = vec![Column::new(&self.time_col), Column::new(&self.lp_col)];
        match (&self.shear_col, &self.normal_col, self.normal_stress) {
            (Some(s), Some(n), _) => cols.extend([Column::new(s), Column::positive(n)]),
            (Some(s), None, Some(v)) if v > 0.0 && v.is_finite() => cols.push(Column::new(s)),
            (Some(_), None, Some(v)) => return Err(format!("normal stress {v} must be positive")),
            (Some(s), None, None) => {
                return Err(format!("column `{s}`: a shear column needs --normal-stress or --normal-col"));
            }
            (None, n, _) => {
                cols.push(Column::friction(&self.mu_col));
                cols.extend(n.iter().map(Column::positive));
            }
        }
        Ok(rsf_record::Spec {
            duplicates: self.duplicate_times,
            invalid: self.invalid,
            window: (self.t_min, self.t_max),
            window_scale: self.time_unit.to_s(),
            ..rsf_record::Spec::timed(cols)
        })
    }
}

/// Reads a record from a file, streaming it (memory stays near the size of the numbers kept).
/// The format rules and what is refused are those of the one reader, [`rsf_record`]:
/// comma, tab, semicolon (decimal comma) or whitespace separated, a preamble, unit rows,
/// comments, quotes, a BOM, UTF-16 or Windows-1252, any line ends; a cut, ragged, over-range
/// or non-increasing record is refused naming file, line and column.
pub fn read_record(path: &Path, opts: &ReadOptions) -> Result<Record, DataError> {
    let name = path.display().to_string();
    let size = std::fs::metadata(path).map(|m| m.len() as usize).unwrap_or(0);
    read_with(&name, opts, size / 40, |spec, visit| rsf_record::read_path(path, spec, visit))
}

/// Parses a record held in memory; `file` names it in errors. See [`read_record`].
pub fn parse_record(text: &str, file: &str, opts: &ReadOptions) -> Result<Record, DataError> {
    read_with(file, opts, text.len() / 40, |spec, visit| rsf_record::read_text(text, file, spec, visit))
}

type Visit<'a> = &'a mut dyn FnMut(u64, &[f64]) -> Result<(), rsf_record::RowError>;

fn read_with(
    file: &str,
    opts: &ReadOptions,
    size_hint: usize,
    read: impl FnOnce(&rsf_record::Spec, Visit) -> Result<rsf_record::Summary, DataError>,
) -> Result<Record, DataError> {
    let spec = opts.spec().map_err(|m| DataError {
        file: file.to_string(),
        line: None,
        column: None,
        kind: ReadErrorKind::Invalid(m),
    })?;
    let (tf, df) = (opts.time_unit.to_s(), opts.disp_unit.to_um());
    let mut rec = Record { source: file.to_string(), ..Default::default() };
    rec.time.reserve(size_hint);
    rec.load_point.reserve(size_hint);
    rec.mu.reserve(size_hint);
    let shear = opts.shear_col.is_some();
    let mut visit = |_line: u64, v: &[f64]| {
        let t = v[0] * tf;
        let (mu, sigma) = match (shear, v.len()) {
            (true, 4) => (v[2] / v[3], Some(v[3])),
            (true, _) => (v[2] / opts.normal_stress.unwrap_or(f64::NAN), None),
            (false, 4) => (v[2], Some(v[3])),
            (false, _) => (v[2], None),
        };
        if !(mu.abs() < rsf_record::MAX_ABS_FRICTION) {
            return Err(rsf_record::RowError {
                column: Some(2),
                message: format!(
                    "friction {} (shear / normal stress) is out of range (|μ| must be below {})",
                    rsf_record::short_num(mu),
                    rsf_record::MAX_ABS_FRICTION
                ),
            });
        }
        rec.time.push(t);
        rec.load_point.push(v[1] * df);
        rec.mu.push(mu);
        if let Some(sn) = sigma {
            rec.normal_stress.push(sn);
        }
        Ok(())
    };
    let summary = read(&spec, &mut visit)?;
    rec.dropped_duplicate_times = summary.dropped_duplicates;
    rec.dropped_invalid = summary.dropped_invalid;
    rec.warnings = summary.warnings;
    if rec.len() < MIN_ROWS {
        return Err(DataError {
            file: file.to_string(),
            line: None,
            column: None,
            kind: ReadErrorKind::TooFewRows { rows: rec.len(), min: MIN_ROWS, first_skipped: None },
        });
    }
    let found = plausible::check(&rec);
    if !found.is_empty() {
        let texts: Vec<String> = found.iter().map(plausible::Implausible::text).collect();
        if !opts.accept_implausible {
            return Err(DataError {
                file: file.to_string(),
                line: None,
                column: None,
                kind: ReadErrorKind::Invalid(format!(
                    "the record does not look like a friction experiment: {}. If it is right, read it anyway with \
                     --accept-implausible (Python: accept_implausible=True; a manifest: accept_implausible = true)",
                    texts.join("; ")
                )),
            });
        }
        rec.warnings.extend(texts.into_iter().map(|t| format!("accepted as plausible: {t}")));
    }
    Ok(rec)
}

pub mod plausible;

#[cfg(test)]
mod tests;
