//! What rsf writes for the bundled inputs is what it wrote when the committed outputs were
//! made, byte for byte apart from wall-clock fields: a refactor (typed vocabularies, a new
//! crate) changes no number and no word. When a change is meant to alter an output,
//! regenerate it (`bash docs/fits/make.sh`, `bash docs/diagnose/make.sh`, and for the
//! examples the command printed on failure) and say why in the commit.

use std::path::{Path, PathBuf};
use std::process::Command;

fn rsf() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rsf"))
}
fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}
fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rsf-unchanged-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

const BASALT: &str = "examples/data/giacomel-basalt/velstep4_BRAVA_expb819_basalt.txt";
const COLUMNS: [&str; 6] = ["--time-col", "Time(s)", "--lp-col", "Displ(microns)", "--mu-col", "Friction"];

/// The text without the lines that carry wall-clock time (`wall_s`, `simulations_per_s`).
fn without_timings(text: &str) -> String {
    text.lines().filter(|l| !l.contains("\"wall_s\"") && !l.contains("_per_s\"")).collect::<Vec<_>>().join("\n")
}

fn same(committed: &Path, written: &Path, strip: bool) {
    let a = std::fs::read_to_string(committed).unwrap();
    let b = std::fs::read_to_string(written).unwrap();
    let (a, b) = if strip { (without_timings(&a), without_timings(&b)) } else { (a, b) };
    if a != b {
        let line =
            a.lines().zip(b.lines()).position(|(x, y)| x != y).unwrap_or(a.lines().count().min(b.lines().count()));
        panic!(
            "{} differs from what rsf writes now, first at line {}:\n  committed: {}\n  now:       {}",
            committed.display(),
            line + 1,
            a.lines().nth(line).unwrap_or("(end)"),
            b.lines().nth(line).unwrap_or("(end)")
        );
    }
}

#[test]
fn the_bundled_diagnosis_is_unchanged() {
    let out = tmp("basalt4.diagnosis.json");
    let st = rsf()
        .current_dir(repo())
        .args(["diagnose", BASALT])
        .args(COLUMNS)
        .args(["--stiffness", "0.0151", "--json", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(st.status.success(), "{}", String::from_utf8_lossy(&st.stderr));
    same(&repo().join("docs/diagnose/basalt4.json"), &out, false);
}

#[test]
fn the_bundled_fit_is_unchanged() {
    let out = tmp("basalt4.fit.json");
    let st = rsf()
        .current_dir(repo())
        .args(["fit", BASALT])
        .args(COLUMNS)
        .args(["--law", "slip", "--stiffness", "0.0151", "--fit-stiffness", "--loading", "protocol"])
        .args(["--mcmc", "20000", "--seed", "1", "--json", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(st.status.success(), "{}", String::from_utf8_lossy(&st.stderr));
    same(&repo().join("docs/fits/basalt4.json"), &out, true);
}

/// SHA-256 of `rsf simulate` on every example protocol, as committed in
/// `tests/golden/simulate.sha256` (one `HASH  FILE` line per output; the CSVs themselves are
/// up to a few MB). Regenerate with `RSF_WRITE_GOLDEN=1 cargo test -p rsf-cli --test
/// outputs_unchanged` after a change meant to alter them.
#[test]
fn every_example_simulates_as_before() {
    use sha2::{Digest, Sha256};
    let golden = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden/simulate.sha256");
    let mut lines = vec![];
    let mut protocols: Vec<PathBuf> = std::fs::read_dir(repo().join("examples"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    protocols.sort();
    for p in &protocols {
        let stem = p.file_stem().unwrap().to_string_lossy().to_string();
        let out = tmp(&format!("{stem}.csv"));
        let st = rsf()
            .current_dir(repo())
            .args(["simulate", p.to_str().unwrap(), "-o", out.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(st.status.success(), "{stem}: {}", String::from_utf8_lossy(&st.stderr));
        let mut files = vec![out.clone()];
        let events = out.with_file_name(format!("{stem}_events.csv"));
        if events.exists() {
            files.push(events);
        }
        for f in files {
            let hash = Sha256::digest(std::fs::read(&f).unwrap());
            let hex: String = hash.iter().map(|b| format!("{b:02x}")).collect();
            lines.push(format!("{hex}  {}", f.file_name().unwrap().to_string_lossy()));
        }
    }
    let now = lines.join("\n") + "\n";
    // a test-only switch to rewrite the committed hashes; the library reads no environment
    if std::env::var_os("RSF_WRITE_GOLDEN").is_some() {
        std::fs::create_dir_all(golden.parent().unwrap()).unwrap();
        std::fs::write(&golden, &now).unwrap();
        return;
    }
    let committed = std::fs::read_to_string(&golden).unwrap_or_default();
    assert_eq!(committed, now, "examples' simulate output changed (committed hashes first)");
}
