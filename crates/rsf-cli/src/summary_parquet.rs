//! `summary.parquet` of `rsf batch`: the summary table with typed columns (numbers DOUBLE,
//! counts INT64, text UTF-8; every column optional: an empty cell is a null), written with the
//! `parquet` crate (plain encoding, no compression: the table is small and every reader takes it).

use anyhow::Result;
use parquet::basic::{LogicalType, Repetition, Type as Physical};
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;
use rsf_batch::{Cell, CellKind, SummaryTable};
use std::sync::Arc;

/// The table as the bytes of a Parquet file: one row group, one column per summary column.
pub fn summary_parquet(t: &SummaryTable) -> Result<Vec<u8>> {
    let fields = t
        .header
        .iter()
        .zip(&t.kinds)
        .map(|(name, kind)| {
            let b = match kind {
                CellKind::Number => Type::primitive_type_builder(name, Physical::DOUBLE),
                CellKind::Count => Type::primitive_type_builder(name, Physical::INT64),
                CellKind::Text => Type::primitive_type_builder(name, Physical::BYTE_ARRAY)
                    .with_logical_type(Some(LogicalType::String)),
            };
            Ok(Arc::new(b.with_repetition(Repetition::OPTIONAL).build()?))
        })
        .collect::<Result<Vec<_>>>()?;
    let schema = Arc::new(Type::group_type_builder("summary").with_fields(fields).build()?);
    let mut w = SerializedFileWriter::new(vec![], schema, Arc::new(WriterProperties::builder().build()))?;
    let mut group = w.next_row_group()?;
    let mut j = 0;
    while let Some(mut col) = group.next_column()? {
        let cells: Vec<&Cell> = t.rows.iter().map(|r| &r[j]).collect();
        match t.kinds[j] {
            CellKind::Number => {
                let (v, def) = present(&cells, |c| match c {
                    Cell::Number(x) => *x,
                    Cell::Text(_) | Cell::Count(_) => None,
                });
                col.typed::<DoubleType>().write_batch(&v, Some(&def), None)?;
            }
            CellKind::Count => {
                let (v, def) = present(&cells, |c| match c {
                    Cell::Count(x) => x.and_then(|n| i64::try_from(n).ok()),
                    Cell::Text(_) | Cell::Number(_) => None,
                });
                col.typed::<Int64Type>().write_batch(&v, Some(&def), None)?;
            }
            CellKind::Text => {
                let (v, def) = present(&cells, |c| match c {
                    Cell::Text(s) if !s.is_empty() => Some(ByteArray::from(s.as_bytes().to_vec())),
                    Cell::Text(_) | Cell::Number(_) | Cell::Count(_) => None,
                });
                col.typed::<ByteArrayType>().write_batch(&v, Some(&def), None)?;
            }
        }
        col.close()?;
        j += 1;
    }
    group.close()?;
    // writes the footer
    Ok(w.into_inner()?)
}

/// A column's values that are present, and its definition levels (1: a value, 0: a null).
fn present<V>(cells: &[&Cell], value: impl Fn(&Cell) -> Option<V>) -> (Vec<V>, Vec<i16>) {
    let mut def = Vec::with_capacity(cells.len());
    let v = cells
        .iter()
        .filter_map(|c| {
            let x = value(c);
            def.push(i16::from(x.is_some()));
            x
        })
        .collect();
    (v, def)
}
