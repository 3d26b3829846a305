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
    /// From `um`, `mm` or `m`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "um" | "µm" | "micron" | "microns" => Some(Self::Um),
            "mm" => Some(Self::Mm),
            "m" => Some(Self::M),
            _ => None,
        }
    }
}

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
    /// From `s` or `ms`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "s" => Some(Self::S),
            "ms" => Some(Self::Ms),
            _ => None,
        }
    }
}

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
}

/// What to do with a row whose time equals the previous row's (loggers that write two rows
/// per clock tick).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DuplicateTimes {
    /// Refuse the record, naming the line (the default: a repeated time may mean a broken clock).
    #[default]
    Error,
    /// Keep the first row of each run of equal times, drop the others and count them.
    Drop,
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

/// A data error naming file, line and column where known.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}{}: {}{message}", line.map(|l| format!(":{l}")).unwrap_or_default(), column.as_ref().map(|c| format!("column `{c}`: ")).unwrap_or_default())]
pub struct DataError {
    /// File name.
    pub file: String,
    /// 1-based line.
    pub line: Option<usize>,
    /// Column name.
    pub column: Option<String>,
    /// What is wrong.
    pub message: String,
}

/// Minimum number of rows a record must have.
pub const MIN_ROWS: usize = 10;

/// Reads a record from a file, streaming it line by line (memory stays near the size of the
/// numbers kept). See [`parse_record`] for the format rules.
pub fn read_record(path: &Path, opts: &ReadOptions) -> Result<Record, DataError> {
    use std::io::BufRead;
    let name = path.display().to_string();
    let io_err = |e: std::io::Error| DataError {
        file: name.clone(),
        line: None,
        column: None,
        message: format!("cannot read: {e}"),
    };
    let f = std::fs::File::open(path).map_err(io_err)?;
    let size = f.metadata().map(|m| m.len() as usize).unwrap_or(0);
    let mut rd = std::io::BufReader::with_capacity(1 << 20, f);
    let mut buf = String::new();
    let mut err = None;
    let lines = std::iter::from_fn(|| {
        buf.clear();
        match rd.read_line(&mut buf) {
            Ok(0) => None,
            Ok(_) => Some(buf.trim_end_matches(['\n', '\r']).to_string()),
            Err(e) => {
                err = Some(e);
                None
            }
        }
    });
    let rec = parse_lines(lines, &name, opts, size / 40)?;
    if let Some(e) = err {
        return Err(DataError { file: name, line: None, column: None, message: format!("cannot read: {e}") });
    }
    Ok(rec)
}

fn split_fields(line: &str, delim: Option<char>) -> Vec<&str> {
    match delim {
        Some(d) => line.split(d).map(|f| f.trim().trim_matches('"')).collect(),
        None => line.split_ascii_whitespace().collect(),
    }
}

/// Parses a record from text.
///
/// * The header is the first line (skipping blank and `#` lines) that names the time column;
///   lines before it (instrument preamble) are skipped.
/// * Delimiter: tab if the header has one, else comma, else whitespace.
/// * Lines between the header and the first numeric row (units, record counts) are skipped.
/// * Rows with one more field than the header carry a leading row index (xlook exports).
/// * Missing, non-numeric or non-finite cells, and time that does not strictly increase, are
///   errors naming the line and column.
pub fn parse_record(text: &str, file: &str, opts: &ReadOptions) -> Result<Record, DataError> {
    parse_lines(text.lines().map(str::to_string), file, opts, text.len() / 40)
}

fn parse_lines(
    lines: impl Iterator<Item = String>,
    file: &str,
    opts: &ReadOptions,
    size_hint: usize,
) -> Result<Record, DataError> {
    let err = |line: Option<usize>, column: Option<&str>, message: String| DataError {
        file: file.to_string(),
        line,
        column: column.map(str::to_string),
        message,
    };
    // a UTF-8 byte-order mark (Excel's default CSV) is not part of the first column's name
    let lines = lines.map(|l| match l.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => l,
    });
    let mut lines = lines.enumerate().filter(|(_, l)| {
        let t = l.trim_start();
        !t.is_empty() && !t.starts_with('#')
    });
    // header
    let mut header: Option<(usize, Option<char>)> = None;
    let mut first_seen: Option<String> = None;
    let mut header_line = String::new();
    for (ln, line) in lines.by_ref().take(200) {
        // semicolons separate fields where the comma is the decimal mark (European locales)
        let delim = if line.contains('\t') {
            Some('\t')
        } else if line.contains(';') {
            Some(';')
        } else if line.contains(',') {
            Some(',')
        } else {
            None
        };
        let fields = split_fields(&line, delim);
        if first_seen.is_none() {
            first_seen = Some(fields.join(","));
        }
        if fields.iter().any(|f| *f == opts.time_col) {
            header = Some((ln, delim));
            header_line = line;
            break;
        }
    }
    let Some((hline, delim)) = header else {
        return Err(err(
            None,
            None,
            format!(
                "no header line names the time column `{}` (first line: {})",
                opts.time_col,
                first_seen.unwrap_or_else(|| "none".into())
            ),
        ));
    };
    let names = split_fields(&header_line, delim);
    let find = |c: &str| {
        names
            .iter()
            .position(|h| *h == c)
            .ok_or_else(|| err(Some(hline + 1), Some(c), format!("no such column in the header ({})", names.join(","))))
    };
    let ti = find(&opts.time_col)?;
    let li = find(&opts.lp_col)?;
    enum Fric {
        Mu(usize),
        Shear(usize, Result<usize, f64>),
    }
    // a normal-stress column beside a friction column: read for σ(t)
    let sigma_col = match (&opts.shear_col, &opts.normal_col) {
        (None, Some(c)) => Some(find(c)?),
        _ => None,
    };
    let fric = match &opts.shear_col {
        Some(s) => {
            let si = find(s)?;
            let norm = match (&opts.normal_col, opts.normal_stress) {
                (Some(c), _) => Ok(find(c)?),
                (None, Some(v)) if v > 0.0 && v.is_finite() => Err(v),
                (None, Some(v)) => return Err(err(None, None, format!("normal stress {v} must be positive"))),
                (None, None) => {
                    return Err(err(None, Some(s), "a shear column needs --normal-stress or --normal-col".into()));
                }
            };
            Fric::Shear(si, norm)
        }
        None => Fric::Mu(find(&opts.mu_col)?),
    };
    let (tf, df) = (opts.time_unit.to_s(), opts.disp_unit.to_um());
    let mut rec = Record { source: file.to_string(), ..Default::default() };
    let est = size_hint;
    rec.time.reserve(est);
    rec.load_point.reserve(est);
    rec.mu.reserve(est);
    let mut offset: Option<usize> = None;
    let parse = |cells: &[&str], i: usize, col: &str, ln: usize| -> Result<f64, DataError> {
        let cell = cells.get(i).ok_or_else(|| err(Some(ln + 1), Some(col), "missing".into()))?;
        // a decimal comma, where the comma does not separate fields
        let v: f64 = cell
            .parse::<f64>()
            .or_else(|e| {
                if delim != Some(',') && cell.matches(',').count() == 1 && !cell.contains('.') {
                    cell.replace(',', ".").parse()
                } else {
                    Err(e)
                }
            })
            .map_err(|_| err(Some(ln + 1), Some(col), format!("`{cell}` is not a number")))?;
        if !v.is_finite() {
            return Err(err(Some(ln + 1), Some(col), format!("{v} is not finite")));
        }
        Ok(v)
    };
    for (ln, line) in lines {
        let cells = split_fields(&line, delim);
        let off = match offset {
            Some(o) => o,
            None => {
                // units or count lines before the first numeric row are skipped: the first data
                // row has the header's field count (or one more: a leading index) and numbers
                // in every column read
                if cells.len() != names.len() && cells.len() != names.len() + 1 {
                    continue;
                }
                let o = usize::from(cells.len() == names.len() + 1);
                let needed: Vec<usize> = match &fric {
                    Fric::Mu(i) => vec![ti, li, *i].into_iter().chain(sigma_col).collect(),
                    Fric::Shear(si, Ok(ni)) => vec![ti, li, *si, *ni],
                    Fric::Shear(si, Err(_)) => vec![ti, li, *si],
                };
                if needed.iter().any(|&i| parse(&cells, i + o, "", ln).is_err()) {
                    continue;
                }
                offset = Some(o);
                o
            }
        };
        let t = parse(&cells, ti + off, &opts.time_col, ln)? * tf;
        if let Some(&prev) = rec.time.last() {
            if t == prev && opts.duplicate_times == DuplicateTimes::Drop {
                rec.dropped_duplicate_times += 1;
                continue;
            }
            if !(t > prev) {
                return Err(err(
                    Some(ln + 1),
                    Some(&opts.time_col),
                    if t == prev {
                        format!(
                            "time {} repeats the previous row's (use the option to drop duplicated times, \
                             `--duplicate-times drop`, if the logger writes two rows per tick)",
                            t / tf
                        )
                    } else {
                        format!("time {} does not increase (previous {})", t / tf, prev / tf)
                    },
                ));
            }
        }
        if opts.t_min.is_some_and(|a| t < a) || opts.t_max.is_some_and(|b| t > b) {
            continue;
        }
        let x = parse(&cells, li + off, &opts.lp_col, ln)? * df;
        let positive = |sn: f64| {
            if sn > 0.0 {
                Ok(sn)
            } else {
                Err(err(Some(ln + 1), opts.normal_col.as_deref(), format!("normal stress {sn} must be positive")))
            }
        };
        let mut sigma = None;
        let mu = match &fric {
            Fric::Mu(i) => {
                if let Some(ni) = sigma_col {
                    sigma = Some(positive(parse(&cells, ni + off, opts.normal_col.as_deref().unwrap(), ln)?)?);
                }
                parse(&cells, i + off, &opts.mu_col, ln)?
            }
            Fric::Shear(si, norm) => {
                let tau = parse(&cells, si + off, opts.shear_col.as_deref().unwrap(), ln)?;
                let sn = match norm {
                    Ok(ni) => {
                        let v = positive(parse(&cells, ni + off, opts.normal_col.as_deref().unwrap(), ln)?)?;
                        sigma = Some(v);
                        v
                    }
                    Err(v) => *v,
                };
                tau / sn
            }
        };
        rec.time.push(t);
        rec.load_point.push(x);
        rec.mu.push(mu);
        if let Some(sn) = sigma {
            rec.normal_stress.push(sn);
        }
    }
    if rec.len() < MIN_ROWS {
        return Err(err(None, None, format!("{} data rows; at least {MIN_ROWS} are needed", rec.len())));
    }
    Ok(rec)
}

#[cfg(test)]
mod tests;
