//! The manifest: a CSV naming each record (`file`, relative to the manifest) and its options,
//! or a folder whose records share one set of options.

use rsf_diagnose::Baseline;
use rsf_fit::data::{DispUnit, TimeUnit};
use rsf_fit::fit::LoadingMode;
use rsf_laws::registry::LawName;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Per-record options. `None` leaves the batch-wide default in place ([`RecordOptions::or`]).
/// Closed sets are parsed when the manifest is read, so a typo fails before any work.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RecordOptions {
    /// Nominal machine stiffness k, 1/µm.
    pub stiffness: Option<f64>,
    /// Time column.
    pub time_col: Option<String>,
    /// Load-point displacement column.
    pub lp_col: Option<String>,
    /// Friction column.
    pub mu_col: Option<String>,
    /// Shear-stress column (friction = shear / normal stress).
    pub shear_col: Option<String>,
    /// Normal-stress column, MPa.
    pub normal_col: Option<String>,
    /// Constant normal stress, MPa.
    pub normal_stress: Option<f64>,
    /// Unit of the load-point column: `um`, `mm` or `m`.
    pub disp_unit: Option<DispUnit>,
    /// Unit of the time column: `s` or `ms`.
    pub time_unit: Option<TimeUnit>,
    /// Use only rows with time ≥ this, s.
    pub t_min: Option<f64>,
    /// Use only rows with time ≤ this, s.
    pub t_max: Option<f64>,
    /// A law file (TOML; docs/laws.md) registered before this record runs, so that `law` and
    /// `baseline` may name its law: a path relative to the manifest, made absolute when read.
    /// A worker of another process (Dask) registers it again from here.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub law_file: Option<PathBuf>,
    /// Evolution law of the fit (`rsf fit --law`).
    pub law: Option<LawName>,
    /// Baseline law of the diagnosis: any registered law (`slip` by default).
    pub baseline: Option<Baseline>,
    /// Forward-model loading: `record` or `protocol` (default: `record` for a fit, `protocol`
    /// for a diagnosis, as the single-record commands).
    pub loading: Option<LoadingMode>,
    /// Fit the stiffness too.
    pub fit_stiffness: Option<bool>,
    /// Fit a slip trend g too.
    pub fit_slip_trend: Option<bool>,
    /// Fit a rate-dependent direct effect a₁ too (`rsf fit --fit-a-slope`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit_a_slope: Option<bool>,
    /// Drop over-range, sentinel and non-finite rows instead of refusing the record.
    pub drop_invalid: Option<bool>,
    /// Read a record that does not look like a friction experiment (friction outside
    /// 0.05–2, columns swapped, …; `rsf_fit::data::plausible`) instead of refusing it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accept_implausible: Option<bool>,
    /// Seed of the diagnosis's null calibration.
    pub seed: Option<u64>,
}

impl RecordOptions {
    /// These options, each unset one taken from `defaults`.
    pub fn or(&self, d: &RecordOptions) -> RecordOptions {
        fn pick<T: Clone>(a: &Option<T>, b: &Option<T>) -> Option<T> {
            a.clone().or_else(|| b.clone())
        }
        RecordOptions {
            stiffness: pick(&self.stiffness, &d.stiffness),
            time_col: pick(&self.time_col, &d.time_col),
            lp_col: pick(&self.lp_col, &d.lp_col),
            mu_col: pick(&self.mu_col, &d.mu_col),
            shear_col: pick(&self.shear_col, &d.shear_col),
            normal_col: pick(&self.normal_col, &d.normal_col),
            normal_stress: pick(&self.normal_stress, &d.normal_stress),
            disp_unit: pick(&self.disp_unit, &d.disp_unit),
            time_unit: pick(&self.time_unit, &d.time_unit),
            t_min: pick(&self.t_min, &d.t_min),
            t_max: pick(&self.t_max, &d.t_max),
            law_file: pick(&self.law_file, &d.law_file),
            law: pick(&self.law, &d.law),
            baseline: pick(&self.baseline, &d.baseline),
            loading: pick(&self.loading, &d.loading),
            fit_stiffness: pick(&self.fit_stiffness, &d.fit_stiffness),
            fit_slip_trend: pick(&self.fit_slip_trend, &d.fit_slip_trend),
            fit_a_slope: pick(&self.fit_a_slope, &d.fit_a_slope),
            drop_invalid: pick(&self.drop_invalid, &d.drop_invalid),
            accept_implausible: pick(&self.accept_implausible, &d.accept_implausible),
            seed: pick(&self.seed, &d.seed),
        }
    }

    /// Checks every number's range (closed sets are typed: checked when read): the option at
    /// fault and why.
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        if let Some(k) = self.stiffness {
            if !(k > 0.0 && k.is_finite()) {
                return Err(("stiffness", format!("stiffness {k} must be positive and finite (1/µm)")));
            }
        }
        if let Some(s) = self.normal_stress {
            if !(s > 0.0 && s.is_finite()) {
                return Err(("normal_stress", format!("normal_stress {s} must be positive and finite (MPa)")));
            }
        }
        if let (Some(a), Some(b)) = (self.t_min, self.t_max) {
            if !(a < b) {
                return Err(("t_max", format!("t_min {a} is not below t_max {b}")));
            }
        }
        Ok(())
    }
}

/// A column of the manifest. `meta_…` columns are carried into the summary untouched (sample,
/// humidity, operator: whatever the lab records); any other name is refused, so a misspelt
/// option is never silently ignored.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Column {
    /// The record, relative to the manifest.
    File,
    /// A per-record option.
    Option(&'static str),
    /// A `meta_…` column, carried through.
    Meta(String),
}

/// The option columns, named as the fields of [`RecordOptions`].
pub const OPTION_COLUMNS: [&str; 21] = [
    "stiffness",
    "time_col",
    "lp_col",
    "mu_col",
    "shear_col",
    "normal_col",
    "normal_stress",
    "disp_unit",
    "time_unit",
    "t_min",
    "t_max",
    "law_file",
    "law",
    "baseline",
    "loading",
    "fit_stiffness",
    "fit_slip_trend",
    "fit_a_slope",
    "drop_invalid",
    "accept_implausible",
    "seed",
];

impl Column {
    fn parse(name: &str) -> Result<Column, String> {
        if name == "file" {
            return Ok(Column::File);
        }
        if name.starts_with("meta_") {
            return Ok(Column::Meta(name.to_string()));
        }
        OPTION_COLUMNS.iter().find(|c| **c == name).map(|c| Column::Option(c)).ok_or_else(|| {
            format!(
                "unknown column `{name}`: the manifest's columns are file, {}, and meta_… for anything carried into the summary",
                OPTION_COLUMNS.join(", ")
            )
        })
    }
}

/// One record of the batch.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    /// The record as the manifest names it (relative to the manifest), or its file name in a
    /// folder: the summary's `file` column.
    pub name: String,
    /// Its path.
    pub path: PathBuf,
    /// The manifest's line (1-based; 0 for a folder's records).
    pub line: usize,
    /// Its options as the manifest gives them (unset: the batch default).
    pub options: RecordOptions,
    /// Its `meta_…` cells.
    pub meta: Vec<(String, String)>,
}

fn set(o: &mut RecordOptions, col: &str, cell: &str) -> Result<(), String> {
    let num = || cell.parse::<f64>().map_err(|_| format!("`{cell}` is not a number"));
    let flag = || match cell.to_ascii_lowercase().as_str() {
        "true" | "yes" | "1" => Ok(true),
        "false" | "no" | "0" => Ok(false),
        _ => Err(format!("`{cell}` is not true or false")),
    };
    let text = || Some(cell.to_string());
    fn word<T: std::str::FromStr<Err = String>>(cell: &str) -> Result<Option<T>, String> {
        cell.parse().map(Some)
    }
    match col {
        "stiffness" => o.stiffness = Some(num()?),
        "time_col" => o.time_col = text(),
        "lp_col" => o.lp_col = text(),
        "mu_col" => o.mu_col = text(),
        "shear_col" => o.shear_col = text(),
        "normal_col" => o.normal_col = text(),
        "normal_stress" => o.normal_stress = Some(num()?),
        "disp_unit" => o.disp_unit = word(cell)?,
        "time_unit" => o.time_unit = word(cell)?,
        "t_min" => o.t_min = Some(num()?),
        "t_max" => o.t_max = Some(num()?),
        "law_file" => {} // read first, with the manifest's folder (read_manifest)
        "law" => o.law = word(cell)?,
        "baseline" => o.baseline = word(cell)?,
        "loading" => o.loading = word(cell)?,
        "fit_stiffness" => o.fit_stiffness = Some(flag()?),
        "fit_slip_trend" => o.fit_slip_trend = Some(flag()?),
        "fit_a_slope" => o.fit_a_slope = Some(flag()?),
        "drop_invalid" => o.drop_invalid = Some(flag()?),
        "accept_implausible" => o.accept_implausible = Some(flag()?),
        "seed" => o.seed = Some(cell.parse().map_err(|_| format!("`{cell}` is not a whole number"))?),
        other => return Err(format!("column `{other}` is not an option")),
    }
    Ok(())
}

/// Reads a manifest. Every error names the manifest, its line and column; nothing is run
/// until the whole manifest has been read and checked. A record outside the manifest's folder
/// is refused ([`read_manifest_allowing_outside`] reads it).
pub fn read_manifest(path: &Path) -> Result<Vec<Entry>, String> {
    read_manifest_with(path, false)
}

/// [`read_manifest`], reading records outside the manifest's folder too (`rsf batch
/// --allow-outside`).
pub fn read_manifest_allowing_outside(path: &Path) -> Result<Vec<Entry>, String> {
    read_manifest_with(path, true)
}

fn read_manifest_with(path: &Path, allow_outside: bool) -> Result<Vec<Entry>, String> {
    let at = |line: usize, col: &str, msg: String| format!("{}: line {line}, column `{col}`: {msg}", path.display());
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let text = std::str::from_utf8(bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(&bytes))
        .map_err(|e| format!("{}: not UTF-8 text ({e})", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut rdr =
        csv::ReaderBuilder::new().trim(csv::Trim::All).flexible(true).comment(Some(b'#')).from_reader(text.as_bytes());
    let header = rdr.headers().map_err(|e| format!("{}: line 1: {e}", path.display()))?.clone();
    let cols: Vec<Column> = header
        .iter()
        .map(Column::parse)
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{}: line 1: {e}", path.display()))?;
    if !cols.contains(&Column::File) {
        return Err(format!("{}: line 1: no `file` column (the record, relative to the manifest)", path.display()));
    }
    let mut entries: Vec<Entry> = vec![];
    let mut identities: Vec<String> = vec![];
    // (a manifest named without a folder, `manifest.csv`, has the empty path as its parent:
    // the folder is then the working one, whose canonical form the check needs)
    let folder = if dir.as_os_str().is_empty() { Path::new(".") } else { dir }.canonicalize().ok();
    for row in rdr.records() {
        let row = row.map_err(|e| format!("{}: {e}", path.display()))?;
        let line = row.position().map_or(0, |p| p.line() as usize);
        if row.iter().all(str::is_empty) {
            continue;
        }
        if row.len() != cols.len() {
            return Err(format!("{}: line {line}: {} cells, the header has {}", path.display(), row.len(), cols.len()));
        }
        let (mut name, mut options, mut meta) = (String::new(), RecordOptions::default(), vec![]);
        // a row's law file first: its law is then a name for the row's `law` and `baseline`
        if let Some(k) = cols.iter().position(|c| *c == Column::Option("law_file")) {
            let cell = &row[k];
            if !cell.is_empty() {
                let file = dir.join(cell);
                rsf_laws::text_law::register_file(&file).map_err(|e| at(line, "law_file", e))?;
                options.law_file = Some(std::path::absolute(&file).unwrap_or(file));
            }
        }
        for (col, cell) in cols.iter().zip(row.iter()) {
            match col {
                Column::File => name = cell.to_string(),
                Column::Option(c) if !cell.is_empty() => set(&mut options, c, cell).map_err(|e| at(line, c, e))?,
                Column::Option(_) => {}
                Column::Meta(m) => meta.push((m.clone(), cell.to_string())),
            }
        }
        if name.is_empty() {
            return Err(at(line, "file", "empty".into()));
        }
        options.check().map_err(|(c, e)| at(line, c, e))?;
        let record = dir.join(&name);
        if !allow_outside {
            // through a link too: where the file really is
            let outside = match (&folder, record.canonicalize()) {
                (Some(f), Ok(real)) => !real.starts_with(f),
                _ => crate::place::escapes_lexically(Path::new(&name)),
            };
            if outside {
                return Err(at(
                    line,
                    "file",
                    format!(
                        "`{name}` is outside the manifest's folder {}: refused (allow records elsewhere with --allow-outside)",
                        dir.display()
                    ),
                ));
            }
        }
        // one record under several spellings would run, and enter the summary, once per spelling
        let id = crate::place::file_identity(&record);
        if let Some(k) = identities.iter().position(|x| *x == id) {
            let first = &entries[k];
            let same = if first.name == name { String::new() } else { format!(" (as `{}`)", first.name) };
            return Err(at(line, "file", format!("`{name}` is listed already on line {}{same}", first.line)));
        }
        identities.push(id);
        entries.push(Entry { path: record, name, line, options, meta });
    }
    if entries.is_empty() {
        return Err(format!("{}: no records listed", path.display()));
    }
    Ok(entries)
}

/// Registers the law files an entry's or the defaults' JSON names (`law_file`, at the top or
/// under `options`) before the JSON is read into typed options, whose law names must then be
/// known: what a worker in another process (Dask) does first.
pub fn register_law_files(json: &str) -> Result<(), String> {
    let v: serde_json::Value = serde_json::from_str(json).map_err(|e| e.to_string())?;
    for file in [&v["law_file"], &v["options"]["law_file"]] {
        if let Some(f) = file.as_str() {
            rsf_laws::text_law::register_file(Path::new(f))?;
        }
    }
    Ok(())
}

/// The records of a folder: its `.csv`, `.txt`, `.tsv` and `.dat` files (not hidden, not in
/// sub-folders), in name order, each with the batch-wide options.
pub fn folder_entries(dir: &Path) -> Result<Vec<Entry>, String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|d| d.ok())
        .filter(|d| d.file_type().is_ok_and(|t| t.is_file()))
        .filter_map(|d| d.file_name().to_str().map(str::to_string))
        .filter(|n| !n.starts_with('.'))
        .filter(|n| {
            let ext = n.rsplit_once('.').map(|(_, e)| e.to_ascii_lowercase()).unwrap_or_default();
            matches!(ext.as_str(), "csv" | "txt" | "tsv" | "dat")
        })
        .collect();
    names.sort();
    if names.is_empty() {
        return Err(format!("{}: no records (.csv, .txt, .tsv, .dat) in this folder", dir.display()));
    }
    Ok(names
        .into_iter()
        .map(|n| Entry { path: dir.join(&n), name: n, line: 0, options: RecordOptions::default(), meta: vec![] })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn manifest(text: &str) -> (tempfile::TempDir, PathBuf) {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("m.csv");
        std::fs::write(&p, text).unwrap();
        (d, p)
    }

    #[test]
    fn reads_options_and_meta() {
        let (_d, p) = manifest(
            "file,stiffness,law,loading,fit_stiffness,fit_a_slope,meta_sample\n\
             a.csv,0.01,aging,protocol,yes,yes,S1\nsub/b.csv,,,,,,S2\n",
        );
        let e = read_manifest(&p).unwrap();
        assert_eq!(e.len(), 2);
        assert_eq!(e[0].options.stiffness, Some(0.01));
        assert_eq!(e[0].options.law, Some(LawName::from(rsf_laws::Law::Aging)));
        assert_eq!(e[0].options.fit_stiffness, Some(true));
        assert_eq!(e[0].options.fit_a_slope, Some(true));
        assert_eq!(e[0].meta, vec![("meta_sample".to_string(), "S1".to_string())]);
        assert_eq!(e[1].options, RecordOptions::default());
        assert!(e[1].path.ends_with("sub/b.csv"));
        assert_eq!(e[1].line, 3);
    }

    #[test]
    fn errors_name_line_and_column() {
        for (text, want) in [
            ("file,stifness\na.csv,1\n", "unknown column `stifness`"),
            ("stiffness\n1\n", "no `file` column"),
            ("file,stiffness\na.csv,1\nb.csv,x\n", "line 3, column `stiffness`: `x` is not a number"),
            (
                "file,loading\na.csv,recrd\n",
                "line 2, column `loading`: unknown loading `recrd`: use record or protocol",
            ),
            ("file,law\na.csv,agin\n", "line 2, column `law`"),
            ("file,stiffness\na.csv,-1\n", "line 2, column `stiffness`: stiffness -1 must be positive"),
            ("file\na.csv\na.csv\n", "line 3, column `file`: `a.csv` is listed already on line 2"),
            ("file,stiffness\na.csv,1,2\n", "line 2: 3 cells, the header has 2"),
            ("file\n", "no records listed"),
        ] {
            let (_d, p) = manifest(text);
            let e = read_manifest(&p).unwrap_err();
            assert!(e.contains(want), "{text:?}: {e}");
            assert!(e.contains("m.csv"), "{e}");
        }
    }

    #[test]
    fn defaults_fill_unset_options() {
        let a = RecordOptions { stiffness: Some(1.0), ..Default::default() };
        let d = RecordOptions { stiffness: Some(2.0), law: Some(rsf_laws::Law::Slip.into()), ..Default::default() };
        let m = a.or(&d);
        assert_eq!((m.stiffness, m.law), (Some(1.0), Some(rsf_laws::Law::Slip.into())));
    }

    /// One record under several spellings is refused (issue 40: on the main before it, `a.csv`,
    /// `./a.csv` and `sub/../a.csv` ran three times), and a record outside the manifest's
    /// folder is refused unless allowed (before, `../../etc/passwd` was read).
    #[test]
    fn a_record_is_its_file_and_stays_in_the_folder() {
        let (d, p) = manifest("file\na.csv\n./a.csv\n");
        std::fs::write(d.path().join("a.csv"), "t,x,mu\n").unwrap();
        std::fs::create_dir(d.path().join("sub")).unwrap();
        let e = read_manifest(&p).unwrap_err();
        assert!(e.contains("line 3, column `file`: `./a.csv` is listed already on line 2 (as `a.csv`)"), "{e}");
        std::fs::write(&p, "file\na.csv\nsub/../a.csv\n").unwrap();
        assert!(read_manifest(&p).unwrap_err().contains("listed already on line 2"));
        // a file that is not there yet: by its path, `.` and `..` resolved
        std::fs::write(&p, "file\nnew.csv\nsub/../new.csv\n").unwrap();
        assert!(read_manifest(&p).unwrap_err().contains("listed already on line 2"));
        for outside in ["../x.csv", "/etc/passwd", "sub/../../x.csv"] {
            std::fs::write(&p, format!("file\n{outside}\n")).unwrap();
            let e = read_manifest(&p).unwrap_err();
            assert!(e.contains("outside the manifest's folder") && e.contains("--allow-outside"), "{outside}: {e}");
            assert!(read_manifest_allowing_outside(&p).is_ok(), "{outside}");
        }
        #[cfg(unix)]
        {
            let elsewhere = tempfile::tempdir().unwrap();
            std::fs::write(elsewhere.path().join("x.csv"), "t,x,mu\n").unwrap();
            std::os::unix::fs::symlink(elsewhere.path().join("x.csv"), d.path().join("link.csv")).unwrap();
            std::fs::write(&p, "file\nlink.csv\n").unwrap();
            assert!(read_manifest(&p).unwrap_err().contains("outside the manifest's folder"));
        }
    }
}
