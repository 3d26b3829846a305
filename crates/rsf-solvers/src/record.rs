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

/// Reads a load-point record through the one record reader ([`rsf_record`]: the formats and
/// checks of `rsf fit`): a header naming the time (s) and load-point (µm) columns, and
/// optionally friction and normal-stress (MPa) columns. Errors name the file, line and column.
pub fn read_load_record(path: &Path, cols: &RecordColumns) -> Result<ReadRecord, String> {
    use rsf_record::Column;
    let mut spec_cols = vec![Column::new(cols.time), Column::new(cols.load_point)];
    spec_cols.extend(cols.friction.map(Column::friction));
    spec_cols.extend(cols.normal_stress.map(Column::positive));
    // a load history needs two points, not the fewest rows of a record to fit
    let spec = rsf_record::Spec { min_rows: 2, ..rsf_record::Spec::timed(spec_cols) };
    let mut rec = LoadRecord { time: Vec::new(), load_point: Vec::new() };
    let mut mu = Vec::new();
    let mut sn = Vec::new();
    let mi = cols.friction.map(|_| 2);
    let si = cols.normal_stress.map(|_| 2 + usize::from(mi.is_some()));
    rsf_record::read_path(path, &spec, |_, v| {
        rec.time.push(v[0]);
        rec.load_point.push(v[1]);
        mu.extend(mi.map(|i| v[i]));
        sn.extend(si.map(|i| v[i]));
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    rec.validate().map_err(|m| format!("{}: {m}", path.display()))?;
    Ok(ReadRecord { load: rec, friction: mi.map(|_| mu), normal_stress: si.map(|_| sn) })
}
