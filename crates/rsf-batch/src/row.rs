//! One summary row per record, and the summary table of a batch.

use serde::{Deserialize, Serialize};

/// How a record's work ended. Serialised as the summary's `status` cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Everything asked for was done.
    Ok,
    /// The record could not be read (the message names file, line and column).
    ReadFailed,
    /// The fit failed.
    FitFailed,
    /// The fit returned its best point without converging (the row carries those numbers and,
    /// in `error`, why).
    NotConverged,
    /// The diagnosis failed.
    DiagnoseFailed,
    /// The options were incomplete or wrong for this record (e.g. no stiffness).
    OptionsInvalid,
    /// The work panicked: a defect of rsf, reported, and the other records go on.
    Crashed,
    /// The results could not be written (a full disk, a folder without permission).
    WriteFailed,
}

impl Status {
    /// The summary's word for it.
    pub fn text(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::ReadFailed => "read_failed",
            Status::FitFailed => "fit_failed",
            Status::NotConverged => "not_converged",
            Status::DiagnoseFailed => "diagnose_failed",
            Status::OptionsInvalid => "options_invalid",
            Status::Crashed => "crashed",
            Status::WriteFailed => "write_failed",
        }
    }
}

/// A fitted parameter: name (`mu0`, `a`, `b1`, `dc1`, `vc1`, `k`, `g`, …), value, standard
/// error (absent when fixed).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Param {
    /// Its name, as in `rsf fit`'s output.
    pub name: String,
    /// Its value.
    pub value: f64,
    /// Its standard error (linearised), when it was free.
    pub stderr: Option<f64>,
}

/// A record's line in the summary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// The record as the manifest names it.
    pub file: String,
    /// How its work ended.
    pub status: Status,
    /// What failed, when something did.
    pub error: String,
    /// Samples read.
    pub samples: Option<usize>,
    /// Record duration, s.
    pub duration_s: Option<f64>,
    /// Slowest and fastest load-point velocity of its slides, µm/s.
    pub v_lp_min_um_s: Option<f64>,
    /// Fastest load-point velocity, µm/s.
    pub v_lp_max_um_s: Option<f64>,
    /// Longest hold, s (absent without holds).
    pub longest_hold_s: Option<f64>,
    /// Median normal stress, MPa (from the record's column or the constant given).
    pub normal_stress_mpa: Option<f64>,
    /// Laws of the model whose parameters are given (the fit's; for a diagnosis alone, the
    /// baseline's), `+`-joined.
    pub laws: Option<String>,
    /// Its rms misfit.
    pub rms: Option<f64>,
    /// Its parameters.
    pub params: Vec<Param>,
    /// The diagnosis's cause (`none` when the baseline suffices).
    pub cause: Option<String>,
    /// ΔBIC of the cause's extension (its gain; negative is better).
    pub delta_bic: Option<f64>,
    /// rms(extended)/rms(baseline).
    pub rms_ratio: Option<f64>,
    /// The effect's parameters, JSON.
    pub effect: Option<String>,
    /// The runner-up cause.
    pub runner_up: Option<String>,
    /// For `unexplained`: the best partial extension; for `undecided`: the better of the two
    /// causes the record cannot tell apart (the other is `runner_up`).
    pub partial: Option<String>,
    /// The adequacy test of the model named: `adequate`, `inadequate` or `untestable`.
    pub adequacy: Option<String>,
    /// Its excess (1: the event windows look like noise).
    pub adequacy_excess: Option<f64>,
    /// The record's events (steps and reslides) the adequacy test judged…
    pub events_tested: Option<usize>,
    /// …of this many.
    pub events: Option<usize>,
    /// Drift rms left in the residuals of the model named, when reported.
    pub drift_rms: Option<f64>,
    /// The quiet test of the model named: how much its residuals wander inside the quiet
    /// stretches of sliding over what its noise model says, in variance (about 1: the noise
    /// model's drift is noise; far below 1: its slow part is misfit, `diagnose/quiet.rs`).
    pub quiet_wander: Option<f64>,
    /// The form test of the model named: ΔBIC of the best model reshaped in state (its own or a
    /// rival's law read at θ_ref(θ/θ_ref)^p) against it; below −10 its law is not the
    /// record's (`diagnose/form.rs`).
    pub form_delta_bic: Option<f64>,
    /// The lead of the cause chosen over its best credible, decisive rival in spreads of their
    /// log-likelihood ratio under the noise (`diagnose/lead.rs`); below 2.58 it decides nothing
    /// where the model chosen is untestable (`undecided`). Empty with no such rival.
    pub lead_z: Option<f64>,
    /// The manifest's `meta_…` cells.
    pub meta: Vec<(String, String)>,
}

impl Row {
    /// A row for a record whose work failed.
    pub fn failed(file: &str, status: Status, error: String) -> Row {
        Row {
            file: file.to_string(),
            status,
            error,
            samples: None,
            duration_s: None,
            v_lp_min_um_s: None,
            v_lp_max_um_s: None,
            longest_hold_s: None,
            normal_stress_mpa: None,
            laws: None,
            rms: None,
            params: vec![],
            cause: None,
            delta_bic: None,
            rms_ratio: None,
            effect: None,
            runner_up: None,
            partial: None,
            adequacy: None,
            adequacy_excess: None,
            events_tested: None,
            events: None,
            drift_rms: None,
            quiet_wander: None,
            form_delta_bic: None,
            lead_z: None,
            meta: vec![],
        }
    }
}

/// The fixed columns before the parameters, and their kinds.
const HEAD: [(&str, CellKind); 11] = [
    ("file", CellKind::Text),
    ("status", CellKind::Text),
    ("error", CellKind::Text),
    ("samples", CellKind::Count),
    ("duration_s", CellKind::Number),
    ("v_lp_min_um_s", CellKind::Number),
    ("v_lp_max_um_s", CellKind::Number),
    ("longest_hold_s", CellKind::Number),
    ("normal_stress_mpa", CellKind::Number),
    ("laws", CellKind::Text),
    ("rms", CellKind::Number),
];
/// The fixed columns after the parameters, and their kinds.
const TAIL: [(&str, CellKind); 14] = [
    ("cause", CellKind::Text),
    ("delta_bic", CellKind::Number),
    ("rms_ratio", CellKind::Number),
    ("effect", CellKind::Text),
    ("runner_up", CellKind::Text),
    ("partial", CellKind::Text),
    ("adequacy", CellKind::Text),
    ("adequacy_excess", CellKind::Number),
    ("events_tested", CellKind::Count),
    ("events", CellKind::Count),
    ("drift_rms", CellKind::Number),
    ("quiet_wander", CellKind::Number),
    ("form_delta_bic", CellKind::Number),
    ("lead_z", CellKind::Number),
];

/// The order of parameter columns: mu0, a, then b_i and Dc_i state by state, then the laws'
/// own parameters and α by name, then k and g (the machine and the trend last).
fn param_order(name: &str) -> (u32, String) {
    let state = |p: &str| name.strip_prefix(p).and_then(|i| i.parse::<u32>().ok());
    match name {
        "mu0" => (0, String::new()),
        "a" => (1, String::new()),
        "k" => (1000, String::new()),
        "g" => (1001, String::new()),
        _ => match (state("b"), state("dc")) {
            (Some(i), _) => (10 + 2 * i, String::new()),
            (_, Some(i)) => (11 + 2 * i, String::new()),
            _ => (500, name.to_string()),
        },
    }
}

/// One cell of the summary table, typed: text, a number, or a count.
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    /// Text (empty: none).
    Text(String),
    /// A number (`None`: none).
    Number(Option<f64>),
    /// A count (`None`: none).
    Count(Option<u64>),
}

impl Cell {
    /// As written in `summary.csv`: numbers in full (shortest round-trip form), none as empty.
    pub fn text(&self) -> String {
        match self {
            Cell::Text(t) => t.clone(),
            Cell::Number(x) => x.map_or(String::new(), |v| format!("{v}")),
            Cell::Count(n) => n.map_or(String::new(), |v| v.to_string()),
        }
    }
}

/// A text cell as a spreadsheet cannot take it for a formula: one that begins with `=`, `@`,
/// a tab or a carriage return, or with `+` or `-` without being a number, gets a leading `'`
/// (OWASP's advice on CSV injection; a spreadsheet shows the text, and `'` marks it as such).
/// A meta cell `=HYPERLINK(…)` from a manifest stays text; `-20` stays a number.
pub fn spreadsheet_safe(t: &str) -> String {
    match t.chars().next() {
        Some('=' | '@' | '\t' | '\r') => format!("'{t}"),
        Some('+' | '-') if t.trim().parse::<f64>().is_err() => format!("'{t}"),
        _ => t.to_string(),
    }
}

/// What a column of the summary holds (every cell of it is of this kind).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellKind {
    /// Text.
    Text,
    /// Numbers (f64).
    Number,
    /// Counts (u64).
    Count,
}

/// The summary table: header, the kind of each column, and the rows' cells.
#[derive(Clone, Debug, PartialEq)]
pub struct SummaryTable {
    /// Column names.
    pub header: Vec<String>,
    /// Each column's kind.
    pub kinds: Vec<CellKind>,
    /// One row of cells per record.
    pub rows: Vec<Vec<Cell>>,
}

/// The summary table: one row per record, in the order given; the parameter columns are the
/// union over the records (`NAME` and `NAME_se`), the `meta_…` columns in order of first
/// appearance.
pub fn summary_table(rows: &[Row]) -> SummaryTable {
    let mut params: Vec<String> = vec![];
    let mut metas: Vec<String> = vec![];
    for r in rows {
        for p in &r.params {
            if !params.contains(&p.name) {
                params.push(p.name.clone());
            }
        }
        for (m, _) in &r.meta {
            if !metas.contains(m) {
                metas.push(m.clone());
            }
        }
    }
    params.sort_by_key(|p| param_order(p));
    let text = |s: &str| Cell::Text(s.to_string());
    let num = Cell::Number;
    let mut out = SummaryTable { header: vec![], kinds: vec![], rows: vec![] };
    let mut col = |name: String, kind: CellKind| {
        out.header.push(name);
        out.kinds.push(kind);
    };
    for (name, kind) in HEAD {
        col(name.to_string(), kind);
    }
    for p in &params {
        col(p.clone(), CellKind::Number);
        col(format!("{p}_se"), CellKind::Number);
    }
    for (name, kind) in TAIL {
        col(name.to_string(), kind);
    }
    for m in &metas {
        col(m.clone(), CellKind::Text);
    }
    for r in rows {
        let mut cells = vec![
            text(&r.file),
            text(r.status.text()),
            text(&r.error),
            Cell::Count(r.samples.map(|n| n as u64)),
            num(r.duration_s),
            num(r.v_lp_min_um_s),
            num(r.v_lp_max_um_s),
            num(r.longest_hold_s),
            num(r.normal_stress_mpa),
            text(r.laws.as_deref().unwrap_or_default()),
            num(r.rms),
        ];
        for name in &params {
            let p = r.params.iter().find(|p| &p.name == name);
            cells.push(num(p.map(|p| p.value)));
            cells.push(num(p.and_then(|p| p.stderr)));
        }
        cells.extend([
            text(r.cause.as_deref().unwrap_or_default()),
            num(r.delta_bic),
            num(r.rms_ratio),
            text(r.effect.as_deref().unwrap_or_default()),
            text(r.runner_up.as_deref().unwrap_or_default()),
            text(r.partial.as_deref().unwrap_or_default()),
            text(r.adequacy.as_deref().unwrap_or_default()),
            num(r.adequacy_excess),
            Cell::Count(r.events_tested.map(|n| n as u64)),
            Cell::Count(r.events.map(|n| n as u64)),
            num(r.drift_rms),
            num(r.quiet_wander),
            num(r.form_delta_bic),
            num(r.lead_z),
        ]);
        for m in &metas {
            cells.push(text(r.meta.iter().find(|(k, _)| k == m).map_or("", |(_, v)| v.as_str())));
        }
        out.rows.push(cells);
    }
    out
}

/// The summary table as CSV ([`summary_table`]). Numbers are written in full (shortest
/// round-trip form), so the table is the same wherever the rows were computed.
pub fn summary_csv(rows: &[Row]) -> String {
    let t = summary_table(rows);
    let mut w = csv::Writer::from_writer(vec![]);
    // writing to a Vec cannot fail
    let _ = w.write_record(t.header.iter().map(|h| spreadsheet_safe(h)));
    for r in &t.rows {
        let _ = w.write_record(r.iter().map(|c| match c {
            Cell::Text(t) => spreadsheet_safe(t),
            Cell::Number(_) | Cell::Count(_) => c.text(),
        }));
    }
    String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_are_the_union_in_field_order() {
        let mut a = Row::failed("a.csv", Status::Ok, String::new());
        a.params = vec![
            Param { name: "k".into(), value: 0.01, stderr: None },
            Param { name: "dc1".into(), value: 10.0, stderr: Some(1.0) },
            Param { name: "a".into(), value: 0.01, stderr: Some(1e-4) },
        ];
        a.meta = vec![("meta_sample".into(), "S1".into())];
        let mut b = Row::failed("b.csv", Status::Ok, String::new());
        b.params = vec![Param { name: "b2".into(), value: 0.002, stderr: Some(1e-4) }];
        let c = Row::failed("c, d.csv", Status::ReadFailed, "c.csv: line 3, column `mu`: not a number".into());
        let t = summary_csv(&[a, b, c]);
        let lines: Vec<&str> = t.lines().collect();
        assert!(lines[0].contains(",rms,a,a_se,dc1,dc1_se,b2,b2_se,k,k_se,cause,"), "{}", lines[0]);
        assert!(lines[0].ends_with(",drift_rms,quiet_wander,form_delta_bic,lead_z,meta_sample"));
        assert!(lines[1].contains(",0.01,0.0001,10,1,,,0.01,,"), "{}", lines[1]);
        assert!(lines[3].starts_with("\"c, d.csv\",read_failed,"), "{}", lines[3]);
        assert_eq!(lines.len(), 4);
    }

    /// A manifest's meta cell cannot become a spreadsheet formula (issue 40: on the main before
    /// it, `=HYPERLINK(…)` was written raw); numbers stay numbers.
    #[test]
    fn formula_like_text_is_neutralised() {
        for (cell, want) in [
            ("=HYPERLINK(\"x\")", "'=HYPERLINK(\"x\")"),
            ("@SUM(A1)", "'@SUM(A1)"),
            ("+cmd", "'+cmd"),
            ("-cmd", "'-cmd"),
            ("-20", "-20"),
            ("+1.5e3", "+1.5e3"),
            ("S1", "S1"),
            ("", ""),
        ] {
            assert_eq!(spreadsheet_safe(cell), want);
        }
        let mut a = Row::failed("a.csv", Status::Ok, String::new());
        a.meta = vec![("meta_note".into(), "=1+1".into())];
        let t = summary_csv(&[a]);
        assert!(t.lines().nth(1).unwrap().ends_with(",'=1+1"), "{t}");
    }
}
