//! The archive never mixes runs (issue 40, defects 6, 7, 8's partial files, 9, 10, 11): each
//! test fails on the main before the change (noted per test).

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn rsf() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rsf"))
}
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}
fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// A lab folder with one record (power-law aging from the outside generator; a fit takes 0.2 s)
/// and its manifest, fitted with the law file the manifest names.
fn lab() -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    std::fs::copy(repo().join("tests/data/outside/power_aging.csv"), d.path().join("a.csv")).unwrap();
    std::fs::copy(repo().join("examples/laws/power_aging.toml"), d.path().join("power.toml")).unwrap();
    std::fs::write(d.path().join("manifest.csv"), "file,stiffness,law_file,law\na.csv,0.02,power.toml,power-aging\n")
        .unwrap();
    d
}

fn batch(dir: &Path, extra: &[&str]) -> Output {
    rsf()
        .arg("batch")
        .arg(dir.join("manifest.csv"))
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--fit")
        .args(extra)
        .output()
        .unwrap()
}

/// Defect 6: a record that fails on a re-run leaves no output of its earlier run beside its
/// failed row (on the main: a.csv.fit.json stayed).
#[test]
fn a_record_that_now_fails_leaves_no_earlier_outputs() {
    let d = lab();
    let o = batch(d.path(), &[]);
    assert!(o.status.success(), "{}", text(&o));
    let fit = d.path().join("out/records/a.csv.fit.json");
    assert!(fit.is_file());
    std::fs::write(d.path().join("a.csv"), "time_s,load_point_um,mu\n0,0,0.6\n1,1,0.6x\n").unwrap();
    let o = batch(d.path(), &[]);
    assert!(!o.status.success());
    assert!(text(&o).contains("read_failed"), "{}", text(&o));
    assert!(!fit.exists(), "the earlier run's fit.json is still beside a read_failed row");
}

/// Defect 7: a second run on the same output folder is refused while the first holds it, and
/// says who holds it; a lock left by a run that is gone is taken over (on the main: no lock).
#[test]
fn one_batch_at_a_time_on_an_output_folder() {
    let d = lab();
    let out = d.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    let host = ["/proc/sys/kernel/hostname", "/etc/hostname"]
        .iter()
        .find_map(|p| std::fs::read_to_string(p).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "this machine".into());
    // held by this test's own process: alive
    std::fs::write(
        out.join(".rsf-batch.lock"),
        format!("pid {} on {host} since 0 (unix seconds)\n", std::process::id()),
    )
    .unwrap();
    let o = batch(d.path(), &[]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("in use by another rsf batch") && text(&o).contains(&format!("pid {}", std::process::id()))
    );
    assert!(!out.join("summary.csv").exists(), "no work under another run's lock");
    if Path::new("/proc/self").exists() {
        // held by a process that is gone
        std::fs::write(out.join(".rsf-batch.lock"), format!("pid 4194303999 on {host} since 0 (unix seconds)\n"))
            .unwrap();
        let o = batch(d.path(), &[]);
        assert!(o.status.success(), "{}", text(&o));
        assert!(text(&o).contains("taking over the lock"), "{}", text(&o));
    }
    assert!(!out.join(".rsf-batch.lock").exists(), "the lock is removed when the run ends");
}

/// Defect 8 (its partial files): a killed run's temporary files are swept by the next run
/// (on the main: `.summary.parquet.*.rsf-partial` stayed for ever).
#[test]
fn a_killed_runs_partial_files_are_swept() {
    let d = lab();
    let out = d.path().join("out");
    std::fs::create_dir_all(out.join("records")).unwrap();
    let left = [out.join(".summary.parquet.x1y2.rsf-partial"), out.join("records/.a.csv.fit.json.z3.rsf-partial")];
    for f in &left {
        std::fs::write(f, "half").unwrap();
    }
    let o = batch(d.path(), &[]);
    assert!(o.status.success(), "{}", text(&o));
    for f in &left {
        assert!(!f.exists(), "{} is still there", f.display());
    }
}

/// Defect 8 (the mix): the summary set is one run's. A run's three summary files are named
/// with their SHA-256 in `summary.set.json`, written last; a folder a kill left between the
/// renames (a new CSV beside the old Parquet and figure, no set file) is found by the next run,
/// which removes the three with a note and writes one run's set (on the main: no set file, and
/// the mix stayed until a run ended; the next run's note did not exist).
#[test]
fn the_summary_set_is_one_runs() {
    let d = lab();
    let out = d.path().join("out");
    let o = batch(d.path(), &[]);
    assert!(o.status.success(), "{}", text(&o));
    let set: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.set.json")).unwrap()).unwrap();
    for f in ["summary.csv", "summary.parquet", "summary.svg"] {
        let bytes = std::fs::read(out.join(f)).unwrap();
        assert_eq!(set["files"][f]["bytes"].as_u64(), Some(bytes.len() as u64), "{f}");
        assert_eq!(set["files"][f]["sha256"].as_str().map(str::len), Some(64), "{f}");
    }
    // what a kill between the renames leaves: the set file removed, one file of a new run
    std::fs::remove_file(out.join("summary.set.json")).unwrap();
    std::fs::write(out.join("summary.csv"), "file,status\nother.csv,ok\n").unwrap();
    let o = batch(d.path(), &[]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("are not one run's"), "{}", text(&o));
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert!(csv.contains("a.csv") && !csv.contains("other.csv"), "{csv}");
    let set2: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.set.json")).unwrap()).unwrap();
    assert_eq!(set2["files"], set["files"], "the same record and options give the same set");
}

/// Defect 14 through a manifest named without its folder (`rsf batch manifest.csv` run in the
/// lab folder): a symlink to a file elsewhere is refused as outside the folder, and nothing of
/// it is read. Found by the probe campaign (benches/probe): the folder of `manifest.csv` was
/// the empty path, which has no canonical form, and the check fell back to the link's spelling;
/// the first line of /etc/hostname reached summary.csv's error cell.
#[cfg(unix)]
#[test]
fn a_symlink_out_is_refused_when_the_manifest_is_named_without_its_folder() {
    let d = lab();
    let elsewhere = tempfile::tempdir().unwrap();
    std::fs::write(elsewhere.path().join("secret.csv"), "secret first line\n").unwrap();
    std::os::unix::fs::symlink(elsewhere.path().join("secret.csv"), d.path().join("link.csv")).unwrap();
    std::fs::write(d.path().join("manifest.csv"), "file,stiffness\na.csv,0.02\nlink.csv,0.02\n").unwrap();
    let o = rsf().current_dir(d.path()).args(["batch", "manifest.csv", "--out", "out", "--fit"]).output().unwrap();
    assert!(!o.status.success());
    assert!(text(&o).contains("outside the manifest's folder"), "{}", text(&o));
    assert!(!text(&o).contains("secret first line"));
    assert!(!d.path().join("out/summary.csv").exists(), "refused before any work");
}

/// Defect 9: a manifest row naming one of the output folder's per-record files is refused
/// before any work (on the main: its bytes were replaced by the run).
#[test]
fn a_per_record_output_cannot_be_an_input() {
    let d = lab();
    let o = batch(d.path(), &[]);
    assert!(o.status.success(), "{}", text(&o));
    let row = d.path().join("out/records/a.csv.row.json");
    let before = std::fs::read(&row).unwrap();
    std::fs::write(
        d.path().join("manifest.csv"),
        "file,stiffness,law_file,law\na.csv,0.02,power.toml,power-aging\nout/records/a.csv.row.json,0.02,,\n",
    )
    .unwrap();
    let o = batch(d.path(), &["--force"]);
    assert!(!o.status.success());
    assert!(text(&o).contains("is the record"), "{}", text(&o));
    assert_eq!(std::fs::read(&row).unwrap(), before, "the input's bytes changed");
}

/// Defect 11: a FIFO record is a failed row at once (on the main: `rsf batch` waited for ever).
#[cfg(unix)]
#[test]
fn a_fifo_record_is_refused_not_waited_on() {
    let d = lab();
    let fifo = d.path().join("pipe.csv");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("SKIP: mkfifo is not available");
        return;
    }
    std::fs::write(d.path().join("manifest.csv"), "file,stiffness\npipe.csv,0.02\n").unwrap();
    let mut child = rsf()
        .arg("batch")
        .arg(d.path().join("manifest.csv"))
        .arg("--out")
        .arg(d.path().join("out"))
        .arg("--fit")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("rsf batch is still waiting on the FIFO after 60 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let o = child.wait_with_output().unwrap();
    assert!(text(&o).contains("not a regular file"), "{}", text(&o));
}

/// Defect 10: `--json -` and `--json /dev/stdout` write the JSON to standard output, whole,
/// and the table goes to standard error (on the main: a file named `-`; /dev/stdout renamed
/// over when stdout was a file).
#[test]
fn json_to_standard_output() {
    let d = lab();
    let rec = d.path().join("a.csv");
    let law = d.path().join("power.toml");
    let args = |json: &str| {
        let mut c = rsf();
        c.arg("--law-file").arg(&law).arg("fit").arg(&rec).args([
            "--law",
            "power-aging",
            "--stiffness",
            "0.02",
            "--json",
            json,
        ]);
        c.current_dir(d.path());
        c
    };
    let o = args("-").output().unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is the JSON alone");
    assert!(v["params"]["law_params"]["n1"].is_f64());
    assert!(String::from_utf8_lossy(&o.stderr).contains("rms"), "the table is on stderr");
    assert!(!d.path().join("-").exists(), "a file named `-`");
    if Path::new("/dev/stdout").exists() {
        let file = d.path().join("redirected.json");
        let o = args("/dev/stdout").stdout(std::fs::File::create(&file).unwrap()).output().unwrap();
        assert!(o.status.success(), "{}", text(&o));
        let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap())
            .expect("the redirected file is the JSON alone");
        assert!(v["params"]["law_params"]["n1"].is_f64());
    }
}
