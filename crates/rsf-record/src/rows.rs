//! The reading itself: the header found in the first lines, then the rows streamed through
//! the `csv` crate, checked, and handed to the caller one at a time.

use crate::text::{Lines, SNIFF_BYTES, TextFault, decode_line, decoder, sniff};
use crate::{
    Column, Columns, DuplicateTimes, HEADER_SCAN_LINES, InvalidRows, OVER_RANGE, ReadError, ReadErrorKind, RowError,
    SENTINELS, Spec, Summary, TextEncoding, short_cell,
};
use csv::ByteRecord;
use std::collections::VecDeque;
use std::io::{Cursor, Read};

/// The head of the file held to find the header (instrument preambles are a few kB).
const HEAD_MAX_BYTES: usize = 8 << 20;

/// A last line without a line end is compared with this many rows before it: shorter than all
/// of them, it is taken for a cut line.
const CUT_LINE_WINDOW: usize = 16;

/// How many lines of dropped rows a warning lists.
const LISTED_LINES: usize = 5;

/// Field separators, told from the header line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Delimiter {
    Tab,
    /// Semicolons, where the comma is the decimal mark (European locales).
    Semicolon,
    Comma,
    /// Runs of spaces and tabs.
    Whitespace,
}

impl Delimiter {
    fn of(line: &str) -> Self {
        if line.contains('\t') {
            Self::Tab
        } else if line.contains(';') {
            Self::Semicolon
        } else if line.contains(',') {
            Self::Comma
        } else {
            Self::Whitespace
        }
    }
    fn byte(self) -> u8 {
        match self {
            Self::Tab => b'\t',
            Self::Semicolon => b';',
            Self::Comma => b',',
            Self::Whitespace => b' ',
        }
    }
    fn reader<R: Read>(self, r: R) -> csv::Reader<R> {
        csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .delimiter(self.byte())
            .quoting(self != Self::Whitespace)
            .comment(Some(b'#'))
            .buffer_capacity(1 << 16)
            .from_reader(r)
    }
}

/// A run of spaces separates fields: the csv crate splits on single spaces, this joins them.
fn resplit_whitespace(rec: &ByteRecord, out: &mut ByteRecord) {
    out.clear();
    for f in rec.iter() {
        for tok in f.split(|b| b.is_ascii_whitespace()).filter(|t| !t.is_empty()) {
            out.push_field(tok);
        }
    }
}

/// A cell as a number (decimal commas where the comma does not separate fields); `None` when
/// it does not read as one.
fn number(cell: &[u8], delim: Delimiter) -> Option<f64> {
    let s = unquote(std::str::from_utf8(cell.trim_ascii()).ok()?);
    if s.is_empty() {
        return None;
    }
    s.parse::<f64>().ok().or_else(|| {
        let decimal_comma =
            delim != Delimiter::Comma && s.bytes().filter(|&b| b == b',').count() == 1 && !s.contains('.');
        if decimal_comma { s.replace(',', ".").parse().ok() } else { None }
    })
}

/// A cell written as ` "0.5" ` (padding outside the quotes, which the csv crate keeps as
/// text) without its quotes.
fn unquote(s: &str) -> &str {
    match s.strip_prefix('"').and_then(|r| r.strip_suffix('"')) {
        Some(inner) => inner.trim(),
        None => s,
    }
}

/// Why a value read as a number cannot be used, if it cannot.
fn invalid(v: f64, col: &Column) -> Option<ReadErrorKind> {
    if !v.is_finite() {
        Some(ReadErrorKind::NotFinite { value: v })
    } else if SENTINELS.contains(&v) {
        Some(ReadErrorKind::Sentinel { value: v })
    } else if v.abs() >= col.max_abs.min(OVER_RANGE) {
        Some(ReadErrorKind::OverRange { value: v, limit: col.max_abs.min(OVER_RANGE) })
    } else if col.positive && !(v > 0.0) {
        Some(ReadErrorKind::NotPositive { value: v })
    } else {
        None
    }
}

/// The header: its line, its fields and the separator.
struct Header {
    line: u64,
    delim: Delimiter,
    names: Vec<String>,
    /// Byte offset in the head just past the header line.
    end: usize,
    windows_1252: bool,
}

fn split_line(text: &str, delim: Delimiter) -> Vec<String> {
    let mut rdr = delim.reader(text.as_bytes());
    let mut rec = ByteRecord::new();
    let mut ws = ByteRecord::new();
    if !matches!(rdr.read_byte_record(&mut rec), Ok(true)) {
        return vec![];
    }
    let rec = if delim == Delimiter::Whitespace {
        resplit_whitespace(&rec, &mut ws);
        &ws
    } else {
        &rec
    };
    rec.iter().map(|f| unquote(String::from_utf8_lossy(f).trim()).to_string()).collect()
}

/// The first of the head's complete lines that names `key`; else the first non-blank line.
fn find_header(head: &[u8], complete: bool, key: &str) -> Result<Header, Option<String>> {
    let mut first = None;
    let mut scanned = 0;
    let mut start = 0;
    for (i, raw) in head.split(|&b| b == b'\n').enumerate() {
        let end = start + raw.len();
        // a line the head cut off is not looked at
        if end == head.len() && !complete {
            break;
        }
        start = end + 1;
        let (text, latin) = decode_line(raw);
        let text = text.trim_start_matches('\u{feff}');
        let t = text.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        scanned += 1;
        if scanned > HEADER_SCAN_LINES {
            break;
        }
        first.get_or_insert_with(|| short_cell(t));
        let delim = Delimiter::of(text);
        let names = split_line(text, delim);
        if names.iter().any(|n| n == key) {
            return Ok(Header { line: i as u64 + 1, delim, names, end: start.min(head.len()), windows_1252: latin });
        }
    }
    Err(first)
}

/// Reads the head: enough lines to find the header in.
fn read_head(lines: &mut impl Read) -> std::io::Result<(Vec<u8>, bool)> {
    let mut head = Vec::new();
    let mut chunk = vec![0u8; 64 * 1024];
    let mut newlines = 0;
    loop {
        let n = lines.read(&mut chunk)?;
        if n == 0 {
            return Ok((head, true));
        }
        newlines += chunk[..n].iter().filter(|&&b| b == b'\n').count();
        head.extend_from_slice(&chunk[..n]);
        if newlines > 4 * HEADER_SCAN_LINES || head.len() >= HEAD_MAX_BYTES {
            return Ok((head, false));
        }
    }
}

fn io_kind(e: &std::io::Error) -> (Option<u64>, ReadErrorKind) {
    match e.get_ref().and_then(|x| x.downcast_ref::<TextFault>()) {
        Some(TextFault::Nul { line }) => (Some(*line), ReadErrorKind::Binary),
        Some(TextFault::LineTooLong { line }) => (Some(*line), ReadErrorKind::LineTooLong),
        None => (None, ReadErrorKind::Io(e.to_string())),
    }
}

/// The layout of the data rows, fixed by the first one.
#[derive(Clone, Copy)]
struct Layout {
    /// Fields per row.
    fields: usize,
    /// Leading fields the header does not name (a row index).
    offset: usize,
}

pub(crate) fn read<R: Read>(
    mut source: R,
    file: &str,
    spec: &Spec,
    mut visit: impl FnMut(u64, &[f64]) -> Result<(), RowError>,
) -> Result<Summary, ReadError> {
    let err = |line: Option<u64>, column: Option<&str>, kind| ReadError {
        file: file.to_string(),
        line,
        column: column.map(str::to_string),
        kind,
    };
    let io_err = |e: std::io::Error| {
        let (line, kind) = io_kind(&e);
        err(line, None, kind)
    };
    let mut prefix = Vec::with_capacity(SNIFF_BYTES);
    (&mut source).take(SNIFF_BYTES as u64).read_to_end(&mut prefix).map_err(io_err)?;
    let mut encoding = sniff(&prefix).map_err(|(TextFault::Nul { line } | TextFault::LineTooLong { line })| {
        err(Some(line), None, ReadErrorKind::Binary)
    })?;
    let mut lines = Lines::new(decoder(Cursor::new(prefix).chain(source), encoding).map_err(io_err)?);
    let (head, complete) = read_head(&mut lines).map_err(io_err)?;
    let header = find_header(&head, complete, &spec.header_key).map_err(|first_line| {
        err(None, None, ReadErrorKind::NoHeader { key: spec.header_key.clone(), first_line, encoding })
    })?;
    let mut summary = Summary { header_line: header.line, ..Summary::default() };
    if header.windows_1252 && encoding == TextEncoding::Utf8 {
        encoding = TextEncoding::Windows1252;
        summary.warnings.push(format!("the header is not UTF-8: read as {}", encoding.name()));
    }
    summary.encoding = Some(encoding);
    let mut names = header.names;
    // a delimiter ending the header line names no column
    if names.len() > 1 && names.last().is_some_and(String::is_empty) {
        names.pop();
    }
    let (selected, columns): (Vec<usize>, Vec<Column>) = match &spec.columns {
        Columns::All => ((0..names.len()).collect(), names.iter().map(|n| Column::new(n.clone())).collect()),
        Columns::Named(cols) => {
            let mut idx = Vec::with_capacity(cols.len());
            for c in cols {
                let i = names.iter().position(|n| *n == c.name).ok_or_else(|| {
                    err(Some(header.line), Some(&c.name), ReadErrorKind::NoColumn { header: names.clone() })
                })?;
                idx.push(i);
            }
            (idx, cols.clone())
        }
    };
    summary.names = columns.iter().map(|c| c.name.clone()).collect();
    let delim = header.delim;
    let rest = Cursor::new(head[header.end..].to_vec()).chain(lines);
    let mut rdr = delim.reader(rest);
    let mut state = RowState {
        h: names.len(),
        delim,
        spec,
        selected,
        columns,
        layout: None,
        recent: VecDeque::with_capacity(CUT_LINE_WINDOW),
        previous: None,
        values: vec![],
        first_skipped: None,
        dropped_lines: vec![],
        index: None,
    };
    state.values = vec![0.0; state.selected.len()];
    // each row is checked when the next is read, so that the last one is known as the last;
    // the two records swap, no row allocates
    let mut pending = ByteRecord::new();
    let mut pending_line: Option<u64> = None;
    let mut spare = ByteRecord::new();
    let mut rec = ByteRecord::new();
    loop {
        let more = rdr.read_byte_record(&mut rec).map_err(|e| match e.into_kind() {
            csv::ErrorKind::Io(e) => io_err(e),
            other => err(None, None, ReadErrorKind::Io(format!("{other:?}"))),
        })?;
        if !more {
            break;
        }
        let line = header.line + rec.position().map_or(1, |p| p.line());
        let fields = if delim == Delimiter::Whitespace {
            resplit_whitespace(&rec, &mut spare);
            std::mem::swap(&mut rec, &mut spare);
            &rec
        } else {
            &rec
        };
        if fields.iter().all(|f| f.trim_ascii().is_empty()) {
            continue;
        }
        if let Some(pl) = pending_line {
            state
                .row(&pending, pl, false, &mut summary, &mut visit)
                .map_err(|(c, k)| err(Some(pl), c.as_deref(), k))?;
        }
        std::mem::swap(&mut rec, &mut pending);
        pending_line = Some(line);
    }
    let lines = rdr.get_ref().get_ref().1;
    if let Some(pl) = pending_line {
        let cut = !lines.ended_with_newline && pl == lines.line;
        state.row(&pending, pl, cut, &mut summary, &mut visit).map_err(|(c, k)| err(Some(pl), c.as_deref(), k))?;
    }
    if !state.dropped_lines.is_empty() {
        let listed: Vec<String> = state.dropped_lines.iter().map(u64::to_string).collect();
        summary.warnings.push(format!(
            "dropped {} rows with an invalid value (lines {}{})",
            summary.dropped_invalid,
            listed.join(", "),
            if summary.dropped_invalid > listed.len() { ", …" } else { "" }
        ));
    }
    if summary.rows < spec.min_rows {
        return Err(err(
            None,
            None,
            ReadErrorKind::TooFewRows { rows: summary.rows, min: spec.min_rows, first_skipped: state.first_skipped },
        ));
    }
    Ok(summary)
}

/// What the row checks carry from row to row.
struct RowState<'a> {
    /// Fields the header names.
    h: usize,
    delim: Delimiter,
    spec: &'a Spec,
    /// Header positions of the columns read.
    selected: Vec<usize>,
    columns: Vec<Column>,
    layout: Option<Layout>,
    /// Byte lengths of the last field of the last rows (for a cut last line).
    recent: VecDeque<usize>,
    /// The increasing column's previous value.
    previous: Option<f64>,
    values: Vec<f64>,
    first_skipped: Option<(u64, String, String)>,
    dropped_lines: Vec<u64>,
    /// The previous row's leading index (xlook exports).
    index: Option<i64>,
}

type RowFault = (Option<String>, ReadErrorKind);

impl RowState<'_> {
    /// A leading field the header does not name must be a row index: an integer that increases
    /// from row to row. Anything else is a ragged row, not a shifted record.
    fn check_index(&mut self, cell: &[u8]) -> Result<(), RowFault> {
        let i = std::str::from_utf8(cell.trim_ascii()).ok().and_then(|s| unquote(s).parse::<i64>().ok());
        match i {
            Some(i) if self.index.is_none_or(|p| i > p) => {
                self.index = Some(i);
                Ok(())
            }
            _ => Err((
                None,
                ReadErrorKind::Invalid(format!(
                    "{} fields where the header has {}, and the first, `{}`, is not a row index counting up \
                     (a ragged row: a missing or extra delimiter?)",
                    self.h + 1,
                    self.h,
                    short_cell(&decode_line(cell.trim_ascii()).0)
                )),
            )),
        }
    }

    /// Checks that the increasing column's `t` follows the previous row's; false for a
    /// repeated time that is dropped.
    fn order(&mut self, t: f64, summary: &mut Summary) -> Result<bool, RowFault> {
        let ti = self.spec.increasing.unwrap_or(0);
        if let Some(prev) = self.previous {
            let name = || Some(self.columns[ti].name.clone());
            if t == prev {
                return match self.spec.duplicates {
                    DuplicateTimes::Drop => {
                        summary.dropped_duplicates += 1;
                        Ok(false)
                    }
                    DuplicateTimes::Error => Err((name(), ReadErrorKind::Repeated { value: t })),
                };
            }
            if !(t > prev) {
                return Err((name(), ReadErrorKind::NotIncreasing { value: t, previous: prev }));
            }
        }
        self.previous = Some(t);
        Ok(true)
    }

    /// One non-blank row; `cut`: the file's last line, without a line end.
    fn row(
        &mut self,
        rec: &ByteRecord,
        line: u64,
        cut: bool,
        summary: &mut Summary,
        visit: &mut impl FnMut(u64, &[f64]) -> Result<(), RowError>,
    ) -> Result<(), RowFault> {
        let n = rec.len();
        let drop_cut = |summary: &mut Summary, why: &str| {
            summary.warnings.push(format!(
                "line {line}: the last line has no line end and {why}: taken for a cut line and dropped"
            ));
            Ok(())
        };
        let layout = match self.layout {
            Some(l) => l,
            None => {
                let h = self.h;
                let candidate = if n == h {
                    Some(Layout { fields: h, offset: 0 })
                } else if n == h + 1 && rec.get(h).is_some_and(|f| f.trim_ascii().is_empty()) {
                    Some(Layout { fields: h + 1, offset: 0 })
                } else if n == h + 1 {
                    Some(Layout { fields: h + 1, offset: 1 })
                } else {
                    None
                };
                let off = candidate.map_or(0, |c| c.offset);
                // unit and count rows before the first data row are passed over
                let text_cell = self
                    .selected
                    .iter()
                    .enumerate()
                    .find(|&(_, &i)| rec.get(i + off).is_none_or(|c| number(c, self.delim).is_none()));
                if let Some((k, &i)) = text_cell {
                    if self.first_skipped.is_none() {
                        let cell =
                            rec.get(i + off).map(|c| short_cell(&decode_line(c.trim_ascii()).0)).unwrap_or_default();
                        self.first_skipped = Some((line, self.columns[k].name.clone(), cell));
                    }
                    return Ok(());
                }
                match candidate {
                    // a cut line cannot set the layout: nothing before it to check it against
                    Some(_) if cut => return drop_cut(summary, "no row before it to check it against"),
                    Some(c) => {
                        self.layout = Some(c);
                        c
                    }
                    // a count row (xlook's `424645 recs …`) before the first data row
                    None => return Ok(()),
                }
            }
        };
        if n != layout.fields {
            if cut {
                return drop_cut(summary, "another number of fields than the rows before");
            }
            return Err((None, ReadErrorKind::Ragged { expected: layout.fields, found: n }));
        }
        // a cut shortens the last field: shorter than in the rows before, the line is taken
        // for cut (a writer with a fixed number of decimals never loses a complete line here)
        let len = rec.get(n - 1).map_or(0, |f| f.trim_ascii().len());
        if cut && self.recent.iter().max().is_some_and(|&m| len < m) {
            return drop_cut(summary, "its last field is shorter than in the rows before");
        }
        if self.recent.len() == CUT_LINE_WINDOW {
            self.recent.pop_front();
        }
        self.recent.push_back(len);
        if layout.offset == 1 {
            self.check_index(&rec[0])?;
        }
        // the increasing column first: rows outside the window are not checked further
        if let Some(ti) = self.spec.increasing {
            let cell = &rec[self.selected[ti] + layout.offset];
            if let Some(raw) = number(cell, self.delim) {
                let t = raw * self.spec.window_scale;
                let (lo, hi) = self.spec.window;
                if lo.is_some_and(|a| t < a) || hi.is_some_and(|b| t > b) {
                    return self.order(raw, summary).map(|_| ());
                }
            }
        }
        for (k, &i) in self.selected.iter().enumerate() {
            let col = &self.columns[k];
            let cell = &rec[i + layout.offset];
            let Some(v) = number(cell, self.delim) else {
                let text = short_cell(&decode_line(cell.trim_ascii()).0);
                return Err((Some(col.name.clone()), ReadErrorKind::NotANumber { cell: text }));
            };
            if let Some(kind) = invalid(v, col).filter(|_| self.spec.invalid != InvalidRows::Keep) {
                match self.spec.invalid {
                    InvalidRows::Keep => {}
                    InvalidRows::Error => return Err((Some(col.name.clone()), kind)),
                    InvalidRows::Drop => {
                        summary.dropped_invalid += 1;
                        if self.dropped_lines.len() < LISTED_LINES {
                            self.dropped_lines.push(line);
                        }
                        return Ok(());
                    }
                }
            }
            self.values[k] = v;
        }
        if let Some(ti) = self.spec.increasing {
            if !self.order(self.values[ti], summary)? {
                return Ok(());
            }
        }
        visit(line, &self.values).map_err(|e| {
            (e.column.and_then(|c| self.columns.get(c)).map(|c| c.name.clone()), ReadErrorKind::Invalid(e.message))
        })?;
        summary.rows += 1;
        Ok(())
    }
}
