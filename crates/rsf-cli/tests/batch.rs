//! `rsf batch`: a manifest with a failing record, the same work as the single-record commands,
//! resumption (unchanged records skipped, a changed option or record re-run alone), thread
//! count independence, folders, and a manifest refused before any work.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn rsf() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rsf"))
}
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}
fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

const BASALT: &str = "examples/data/giacomel-basalt/velstep4_BRAVA_expb819_basalt.txt";
const NS: [&str; 2] = ["ns_small_a0_s+30.csv", "ns_small_a0.3_s-20.csv"];

/// A lab folder: the basalt record (its own column names), two normal-stress records in a
/// sub-folder, a record with a non-number in it, and the manifest.
fn lab() -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    std::fs::copy(repo().join(BASALT), d.path().join("basalt.txt")).unwrap();
    std::fs::create_dir(d.path().join("ns")).unwrap();
    for f in NS {
        std::fs::copy(repo().join("tests/data/normal_stress").join(f), d.path().join("ns").join(f)).unwrap();
    }
    std::fs::write(d.path().join("bad.csv"), "time_s,load_point_um,mu\n0,0,0.6\n1,1,0.6\n2,2,0.6x\n").unwrap();
    let m = format!(
        "file,stiffness,time_col,lp_col,mu_col,normal_col,loading,meta_sample\n\
         basalt.txt,0.0151,Time(s),Displ(microns),Friction,,protocol,BRAVA b819\n\
         ns/{},0.01,,lp_um,,normal_stress_mpa,,S2\n\
         ns/{},0.01,,lp_um,,normal_stress_mpa,,S3\n\
         bad.csv,0.01,,,,,,S4\n",
        NS[0], NS[1]
    );
    std::fs::write(d.path().join("manifest.csv"), m).unwrap();
    d
}

fn batch(dir: &Path, extra: &[&str]) -> Output {
    rsf().arg("batch").arg(dir.join("manifest.csv")).arg("--out").arg(dir.join("out")).args(extra).output().unwrap()
}

fn summary(dir: &Path) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_path(dir.join("out/summary.csv")).unwrap();
    let head: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    let mut rows = vec![head];
    rows.extend(r.records().map(|x| x.unwrap().iter().map(String::from).collect::<Vec<_>>()));
    rows
}

fn cell<'a>(rows: &'a [Vec<String>], file: &str, col: &str) -> &'a str {
    let j = rows[0].iter().position(|c| c == col).unwrap_or_else(|| panic!("no column {col}"));
    &rows.iter().find(|r| r[0] == file).unwrap_or_else(|| panic!("no row {file}"))[j]
}

/// `summary.parquet` holds the CSV's table, typed: every cell read back equals the CSV's (numbers
/// bit for bit, counts as integers, text as UTF-8), an empty CSV cell is a null.
fn parquet_is_the_csv(dir: &Path, csv: &[Vec<String>]) {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::record::Field;
    let file = std::fs::File::open(dir.join("out/summary.parquet")).unwrap();
    let reader = SerializedFileReader::new(file).unwrap();
    let names: Vec<String> =
        reader.metadata().file_metadata().schema_descr().columns().iter().map(|c| c.name().to_string()).collect();
    assert_eq!(names, csv[0]);
    let rows: Vec<parquet::record::Row> = reader.into_iter().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), csv.len() - 1);
    for (row, want) in rows.iter().zip(&csv[1..]) {
        for ((name, field), cell) in row.get_column_iter().zip(want) {
            match field {
                Field::Null => assert!(cell.is_empty(), "{name}: null for `{cell}`"),
                Field::Double(x) => assert_eq!(*x, cell.parse::<f64>().unwrap(), "{name}"),
                Field::Long(n) => assert_eq!(n.to_string(), *cell, "{name}"),
                Field::Str(s) => assert_eq!(s, cell, "{name}"),
                other => panic!("{name}: unexpected {other:?}"),
            }
        }
    }
    // the kinds: a count, a number, text
    let kind = |c: &str| rows[0].get_column_iter().find(|(n, _)| *n == c).map(|(_, f)| f.clone()).unwrap();
    assert!(matches!(kind("samples"), Field::Long(_)));
    assert!(matches!(kind("a"), Field::Double(_)));
    assert!(matches!(kind("status"), Field::Str(_)));
}

#[test]
fn a_lab_archive_fitted_and_diagnosed_resumed_and_rerun_where_changed() {
    let d = lab();
    let p = d.path();
    // the first run: three records done, the bad one named, exit status 1
    let out = batch(p, &["--fit", "--diagnose", "--jobs", "2"]);
    let t = text(&out);
    assert_eq!(out.status.code(), Some(1), "{t}");
    assert!(t.contains("4 records: 3 ok (0 reused from an earlier run), 1 failed"), "{t}");
    assert!(t.contains("bad.csv: read_failed:") && t.contains("bad.csv:4: column `mu`"), "{t}");
    let rows = summary(p);
    assert_eq!(rows.len(), 5);
    let head = &rows[0];
    for c in ["file", "status", "error", "cause", "delta_bic", "effect", "a", "a_se", "b1", "b1_se", "dc1", "dc1_se"] {
        assert!(head.contains(&c.to_string()), "column {c} missing: {head:?}");
    }
    assert_eq!(head.last().unwrap(), "meta_sample");
    for f in ["basalt.txt", &format!("ns/{}", NS[0]), &format!("ns/{}", NS[1])] {
        assert_eq!(cell(&rows, f, "status"), "ok");
        assert!(cell(&rows, f, "a_se").parse::<f64>().unwrap() > 0.0);
        assert!(!cell(&rows, f, "cause").is_empty());
    }
    assert_eq!(cell(&rows, "bad.csv", "status"), "read_failed");
    assert_eq!(cell(&rows, "bad.csv", "meta_sample"), "S4");
    assert_eq!(cell(&rows, &format!("ns/{}", NS[0]), "normal_stress_mpa"), "10");
    assert_eq!(cell(&rows, "basalt.txt", "meta_sample"), "BRAVA b819");
    let recs = p.join("out/records");
    for f in ["basalt.txt.fit.json", "basalt.txt.diagnosis.json", "basalt.txt.html", "ns__ns_small_a0_s+30.csv.stamp"] {
        assert!(recs.join(f).is_file(), "{f}");
    }
    assert!(std::fs::read_to_string(p.join("out/summary.svg")).unwrap().contains("<svg"));
    parquet_is_the_csv(p, &rows);

    // the same work as `rsf fit` on the one record with the same options
    let fit_json = p.join("fit.json");
    let o = rsf()
        .args(["fit", p.join("basalt.txt").to_str().unwrap(), "--time-col", "Time(s)", "--lp-col", "Displ(microns)"])
        .args(["--mu-col", "Friction", "--stiffness", "0.0151", "--loading", "protocol", "--json"])
        .arg(&fit_json)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&fit_json).unwrap()).unwrap();
    for (name, col) in [("a", "a"), ("mu0", "mu0")] {
        assert_eq!(v["params"][name].as_f64().unwrap(), cell(&rows, "basalt.txt", col).parse::<f64>().unwrap());
    }
    assert_eq!(v["stderr"]["dc1"].as_f64().unwrap(), cell(&rows, "basalt.txt", "dc1_se").parse::<f64>().unwrap());

    // a re-run: every complete record reused, the table byte for byte the same; the failed
    // record is tried again
    let first = std::fs::read(p.join("out/summary.csv")).unwrap();
    let first_parquet = std::fs::read(p.join("out/summary.parquet")).unwrap();
    let out = batch(p, &["--fit", "--diagnose"]);
    assert!(text(&out).contains("3 ok (3 reused from an earlier run), 1 failed"), "{}", text(&out));
    assert_eq!(std::fs::read(p.join("out/summary.csv")).unwrap(), first);
    assert_eq!(std::fs::read(p.join("out/summary.parquet")).unwrap(), first_parquet);

    // one option changed for one record: that record alone runs again
    let m = std::fs::read_to_string(p.join("manifest.csv")).unwrap();
    std::fs::write(
        p.join("manifest.csv"),
        m.replacen(&format!("ns/{},0.01", NS[1]), &format!("ns/{},0.012", NS[1]), 1),
    )
    .unwrap();
    let out = batch(p, &["--fit", "--diagnose"]);
    assert!(text(&out).contains("3 ok (2 reused from an earlier run)"), "{}", text(&out));
    let rows2 = summary(p);
    assert_eq!(cell(&rows2, &format!("ns/{}", NS[1]), "k"), "0.012");
    assert_eq!(cell(&rows2, "basalt.txt", "a"), cell(&rows, "basalt.txt", "a"));

    // a record whose bytes changed runs again; an interrupted record (no stamp) runs again
    let f = p.join("ns").join(NS[0]);
    let changed = std::fs::read_to_string(&f).unwrap().replace('\n', "\r\n");
    std::fs::write(&f, changed).unwrap();
    std::fs::remove_file(recs.join("basalt.txt.stamp")).unwrap();
    let out = batch(p, &["--fit", "--diagnose"]);
    assert!(text(&out).contains("3 ok (1 reused from an earlier run)"), "{}", text(&out));
    // the same numbers: CRLF line ends are the same record
    assert_eq!(summary(p)[1..3], rows2[1..3]);

    // one record at a time and all records again: the same table
    let now = std::fs::read(p.join("out/summary.csv")).unwrap();
    let out = batch(p, &["--fit", "--diagnose", "--jobs", "1", "--force"]);
    assert!(text(&out).contains("(0 reused"), "{}", text(&out));
    assert_eq!(std::fs::read(p.join("out/summary.csv")).unwrap(), now);
}

#[test]
fn a_folder_takes_its_options_once() {
    let d = tempfile::tempdir().unwrap();
    for f in NS {
        std::fs::copy(repo().join("tests/data/normal_stress").join(f), d.path().join(f)).unwrap();
    }
    std::fs::write(d.path().join("notes.md"), "not a record").unwrap();
    let out = rsf()
        .arg("batch")
        .arg(d.path())
        .args(["--out", d.path().join("out").to_str().unwrap(), "--fit", "--stiffness", "0.01", "--lp-col", "lp_um"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out));
    assert!(text(&out).contains("2 records: 2 ok"), "{}", text(&out));
    let rows = summary(d.path());
    assert_eq!(rows.len(), 3);
    // without a stiffness anywhere each record says so
    let out = rsf()
        .arg("batch")
        .arg(d.path())
        .args(["--out", d.path().join("out2").to_str().unwrap(), "--fit", "--lp-col", "lp_um"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out).contains("options_invalid: no stiffness"), "{}", text(&out));
}

#[test]
fn a_bad_manifest_is_refused_before_any_work() {
    let d = lab();
    let p = d.path();
    for (manifest, want) in [
        ("file,stifness\nbasalt.txt,0.01\n", "line 1: unknown column `stifness`"),
        ("file,stiffness,loading\nbasalt.txt,0.01,protocol\nbad.csv,0.01,recrd\n", "line 3, column `loading`"),
        ("file,stiffness\nbasalt.txt,0.01,3\n", "line 2: 3 cells, the header has 2"),
    ] {
        std::fs::write(p.join("manifest.csv"), manifest).unwrap();
        let out = batch(p, &["--fit"]);
        assert!(!out.status.success());
        assert!(text(&out).contains(want), "{manifest:?}: {}", text(&out));
        assert!(!p.join("out").exists(), "nothing is written for a refused manifest");
    }
    // an output that is an input is refused
    std::fs::create_dir_all(p.join("out")).unwrap();
    std::fs::write(p.join("out/summary.csv"), "time_s,load_point_um,mu\n").unwrap();
    std::fs::write(p.join("manifest.csv"), "file,stiffness\nout/summary.csv,0.01\n").unwrap();
    let out = batch(p, &["--fit"]);
    assert!(!out.status.success());
    assert!(text(&out).contains("is the record") && text(&out).contains("would be destroyed"), "{}", text(&out));
    assert_eq!(std::fs::read_to_string(p.join("out/summary.csv")).unwrap(), "time_s,load_point_um,mu\n");
    // two records whose output files would be one
    std::fs::create_dir_all(p.join("a")).unwrap();
    std::fs::copy(p.join("bad.csv"), p.join("a/b.csv")).unwrap();
    std::fs::copy(p.join("bad.csv"), p.join("a__b.csv")).unwrap();
    std::fs::write(p.join("manifest.csv"), "file,stiffness\na/b.csv,0.01\na__b.csv,0.01\n").unwrap();
    let out = batch(p, &["--fit"]);
    assert!(text(&out).contains("would share their output files"), "{}", text(&out));
    // neither --fit nor --diagnose
    let out = batch(p, &[]);
    assert!(text(&out).contains("--fit, --diagnose or both"));
}
