//! Records that read without error but are not friction experiments as given (issue 40): the
//! bundled basalt record with its friction column ×1000, ×0.001, sign-flipped, or swapped
//! with the load point. Each is refused by `rsf fit`, `rsf diagnose` and `rsf batch`, naming
//! what looks wrong; `--accept-implausible` (a manifest's `accept_implausible` column) reads
//! it with a warning. On the main before this test, `rsf fit` fitted all four with exit 0.

use std::path::PathBuf;
use std::process::{Command, Output};

fn rsf() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rsf"))
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("rsf-plausible-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A change of a row's (load point, friction).
type Transform = fn(f64, f64) -> (f64, f64);

const COLS: [&str; 6] = ["--time-col", "Time(s)", "--lp-col", "Displ(microns)", "--mu-col", "Friction"];

/// The bundled record with `f(load point, friction)` applied to each data row, written as CSV.
fn variant(name: &str, f: impl Fn(f64, f64) -> (f64, f64)) -> PathBuf {
    let src = repo().join("examples/data/giacomel-basalt/velstep4_BRAVA_expb819_basalt.txt");
    let text = std::fs::read_to_string(src).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split('\t').collect();
    let (it, ix, im) = (
        header.iter().position(|h| *h == "Time(s)").unwrap(),
        header.iter().position(|h| *h == "Displ(microns)").unwrap(),
        header.iter().position(|h| *h == "Friction").unwrap(),
    );
    let mut out = String::from("Time(s),Displ(microns),Friction\n");
    for l in lines {
        let v: Vec<f64> = l.split('\t').map(|c| c.trim().parse().unwrap()).collect();
        let (x, m) = f(v[ix], v[im]);
        out += &format!("{},{x},{m}\n", v[it]);
    }
    let p = dir().join(name);
    std::fs::write(&p, out).unwrap();
    p
}

fn fit(path: &PathBuf, extra: &[&str]) -> Output {
    rsf()
        .arg("fit")
        .arg(path)
        .args(COLS)
        .args(["--law", "slip", "--stiffness", "0.0151", "--starts", "1", "--max-iter", "3"])
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn implausible_columns_are_refused_naming_what_looks_wrong() {
    // ×1000 (friction ~600) is refused already as over-range by the reader, naming its line
    let p = variant("x1000.csv", |x, m| (x, m * 1000.0));
    let o = fit(&p, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("x1000.csv:2: column `Friction`"), "{err}");
    let cases: [(&str, Transform, &str); 4] = [
        ("x10.csv", |x, m| (x, m * 10.0), "×10 "),
        ("x0001.csv", |x, m| (x, m * 0.001), "÷1000"),
        ("flipped.csv", |x, m| (x, -m), "sign-flipped"),
        // the displacement in mm (8.5) stays below the reader's over-range bound
        ("swapped.csv", |x, m| (m, x / 1000.0), "swapped"),
    ];
    for (name, f, words) in cases {
        let p = variant(name, f);
        let o = fit(&p, &[]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{name}: fitted with exit 0:\n{err}");
        assert!(err.contains("does not look like a friction experiment") && err.contains(words), "{name}: {err}");
        assert!(err.contains("--accept-implausible"), "{name}: {err}");
        assert!(err.contains(name), "{name}: the message names the file: {err}");
        // the same refusal from `rsf diagnose`
        let o = rsf().arg("diagnose").arg(&p).args(COLS).args(["--stiffness", "0.0151"]).output().unwrap();
        assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains(words), "{name}: diagnose");
    }
    // accepted: read, the finding reported as a warning, and the work done (a 3-iteration
    // fit does not converge: exit 1 with NOT CONVERGED, not the refusal)
    let p = variant("x0001b.csv", |x, m| (x, m * 0.001));
    let o = fit(&p, &["--accept-implausible"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("accepted as plausible") && err.contains("÷1000"), "{err}");
    assert!(!err.contains("does not look like a friction experiment"), "{err}");
    // and the untouched record is not flagged
    let o = rsf()
        .arg("segments")
        .arg(repo().join("examples/data/giacomel-basalt/velstep4_BRAVA_expb819_basalt.txt"))
        .args(COLS)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!String::from_utf8_lossy(&o.stderr).contains("plausible"));
}

#[test]
fn a_batch_refuses_an_implausible_record_in_its_row_unless_accepted() {
    let d = dir().join("batch");
    std::fs::create_dir_all(&d).unwrap();
    let p = variant("batch/flipped.csv", |x, m| (x, -m));
    assert!(p.exists());
    let manifest = d.join("manifest.csv");
    std::fs::write(
        &manifest,
        "file,time_col,lp_col,mu_col,stiffness,accept_implausible\nflipped.csv,Time(s),Displ(microns),Friction,0.0151,\n",
    )
    .unwrap();
    let out = d.join("out");
    let o = rsf().arg("batch").arg(&manifest).arg("--out").arg(&out).arg("--fit").output().unwrap();
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap_or_default();
    assert!(summary.contains("read_failed") && summary.contains("sign-flipped"), "{summary}\n{o:?}");
    // the manifest's column accepts it
    std::fs::write(
        &manifest,
        "file,time_col,lp_col,mu_col,stiffness,accept_implausible\nflipped.csv,Time(s),Displ(microns),Friction,0.0151,true\n",
    )
    .unwrap();
    let out2 = d.join("out2");
    rsf().arg("batch").arg(&manifest).arg("--out").arg(&out2).arg("--fit").output().unwrap();
    let summary = std::fs::read_to_string(out2.join("summary.csv")).unwrap();
    assert!(!summary.contains("read_failed"), "{summary}");
}
