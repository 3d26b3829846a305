//! Measured load-point records (delimited text) read for protocols and fits.

use rsf_core::LoadRecord;
use std::path::Path;

/// Column names of a load-point record.
#[derive(Clone, Copy, Debug)]
pub struct RecordColumns<'a> {
    /// Time, s.
    pub time: &'a str,
    /// Load-point displacement, µm.
    pub load_point: &'a str,
    /// Measured friction (optional).
    pub friction: Option<&'a str>,
    /// Normal stress, MPa (optional): drives σ(t).
    pub normal_stress: Option<&'a str>,
}

/// What [`read_load_record`] read.
#[derive(Clone, Debug)]
pub struct ReadRecord {
    /// Time and load point.
    pub load: LoadRecord,
    /// Measured friction, when asked for.
    pub friction: Option<Vec<f64>>,
    /// Normal stress (MPa), when asked for.
    pub normal_stress: Option<Vec<f64>>,
}

/// Reads a load-point record: a delimited text file (comma- or tab-separated, detected from
/// the header) whose header names the time (s) and load-point (µm) columns, and optionally
/// friction and normal-stress (MPa) columns. Lines starting with `#` are skipped. Errors name
/// the line and column.
pub fn read_load_record(path: &Path, cols: &RecordColumns) -> Result<ReadRecord, String> {
    let (time_col, lp_col, mu_col, sn_col) = (cols.time, cols.load_point, cols.friction, cols.normal_stress);
    let name = path.display();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{name}: cannot read: {e}"))?;
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim_start().starts_with('#') && !l.trim().is_empty());
    let (_, header) = lines.next().ok_or_else(|| format!("{name}: empty file"))?;
    let delim = if header.contains('\t') { '\t' } else { ',' };
    let cols: Vec<&str> = header.split(delim).map(str::trim).collect();
    let find = |c: &str| {
        cols.iter()
            .position(|h| *h == c)
            .ok_or_else(|| format!("{name}: no column `{c}` in header ({})", cols.join(",")))
    };
    let (ti, li) = (find(time_col)?, find(lp_col)?);
    let mi = mu_col.map(find).transpose()?;
    let si = sn_col.map(find).transpose()?;
    let mut rec = LoadRecord { time: Vec::new(), load_point: Vec::new() };
    let mut mu = Vec::new();
    let mut sn = Vec::new();
    for (ln, line) in lines {
        let cells: Vec<&str> = line.split(delim).collect();
        let get = |i: usize, c: &str| -> Result<f64, String> {
            let cell = cells.get(i).ok_or_else(|| format!("{name}:{}: missing column `{c}`", ln + 1))?.trim();
            let v: f64 =
                cell.parse().map_err(|_| format!("{name}:{}: column `{c}`: `{cell}` is not a number", ln + 1))?;
            if !v.is_finite() {
                return Err(format!("{name}:{}: column `{c}`: {v} is not finite", ln + 1));
            }
            Ok(v)
        };
        let t = get(ti, time_col)?;
        if let Some(&prev) = rec.time.last() {
            if t <= prev {
                return Err(format!(
                    "{name}:{}: column `{time_col}`: time {t} does not increase (previous {prev})",
                    ln + 1
                ));
            }
        }
        rec.time.push(t);
        rec.load_point.push(get(li, lp_col)?);
        if let (Some(i), Some(c)) = (mi, mu_col) {
            mu.push(get(i, c)?);
        }
        if let (Some(i), Some(c)) = (si, sn_col) {
            let v = get(i, c)?;
            if !(v > 0.0) {
                return Err(format!("{name}:{}: column `{c}`: normal stress {v} must be positive", ln + 1));
            }
            sn.push(v);
        }
    }
    rec.validate().map_err(|m| format!("{name}: {m}"))?;
    Ok(ReadRecord { load: rec, friction: mi.map(|_| mu), normal_stress: si.map(|_| sn) })
}
