//! The law template `examples/custom-law` builds when copied out of the repository, with its
//! dependencies pointed at a clone on disk as its Cargo.toml says (no workspace lints, no
//! relative path into the repository left, no repository file included).

use std::path::{Path, PathBuf};
use std::process::Command;

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), &target).unwrap();
        }
    }
}

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() { files(&p, out) } else { out.push(p) }
    }
}

#[test]
fn the_law_template_builds_when_copied_out() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").canonicalize().unwrap();
    let tmp = std::env::temp_dir().join(format!("rsf-template-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let dir = tmp.join("my-rsf-law");
    copy_dir(&repo.join("examples/custom-law"), &dir);
    // what a user does with a clone on disk: the crates' path dependencies point at it
    let manifest = dir.join("Cargo.toml");
    let text = std::fs::read_to_string(&manifest).unwrap();
    assert!(!text.contains("workspace = true"), "the template inherits from rsf's workspace");
    let text = text.replace("path = \"../../crates/", &format!("path = \"{}/crates/", repo.display()));
    std::fs::write(&manifest, text).unwrap();
    let mut all = vec![];
    files(&dir, &mut all);
    for f in &all {
        let t = std::fs::read_to_string(f).unwrap();
        assert!(!t.contains("../../") && !t.contains("include_str!"), "{} refers into the repository", f.display());
    }
    // the repository's versions of every dependency, so that the check runs offline
    std::fs::copy(repo.join("Cargo.lock"), dir.join("Cargo.lock")).unwrap();
    // its tests, and its `rsf-power` binary (rsf's CLI with the law; the `cli` feature)
    let checks: [&[&str]; 2] = [
        &["check", "--offline", "--tests", "--quiet"],
        &["check", "--offline", "--features", "cli", "--bins", "--quiet"],
    ];
    for args in checks {
        let out = Command::new(env!("CARGO"))
            .args(args)
            .current_dir(&dir)
            .env("CARGO_TARGET_DIR", repo.join("target/template-check"))
            .output()
            .unwrap();
        if !out.status.success() {
            let _ = std::fs::remove_dir_all(&tmp);
            panic!("cargo {} of the copied template failed:\n{}", args.join(" "), String::from_utf8_lossy(&out.stderr));
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
}
