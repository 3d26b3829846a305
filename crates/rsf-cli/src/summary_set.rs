//! `rsf batch`'s summary as one unit: `summary.csv`, `summary.parquet` and `summary.svg` are
//! one run's when `summary.set.json` lists each with its SHA-256.
//!
//! Three files cannot be renamed at once. So a run writes all three completely first
//! ([`crate::output::Staged`]), removes the set file, renames the three, and writes the set
//! file last. A run killed between the renames leaves no set file: the folder then says, by
//! its absence, that the three are not known to be one run's. The next run (under the lock)
//! finds that, removes the three with a note, and writes a new set at its end. A reader checks
//! a set with [`check`] (Python's `rsf.batch` does the same).

use anyhow::{Context, Result};
use sha2::{Digest, Sha256};
use std::path::Path;

/// The set file.
pub(crate) const SET: &str = "summary.set.json";
/// The files of the set, in the order they are renamed.
pub(crate) const FILES: [&str; 3] = ["summary.csv", "summary.parquet", "summary.svg"];

/// What a folder's summary set is.
#[derive(Debug, PartialEq)]
pub(crate) enum SetState {
    /// No summary files and no set file: no run has finished here.
    Absent,
    /// The set file lists the three files and each has the bytes it names.
    Complete,
    /// Anything else, in words: a run stopped between renames, a file edited or removed.
    Broken(String),
}

fn sha256(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// Reads the state of `out`'s summary set.
pub(crate) fn check(out: &Path) -> SetState {
    let present: Vec<&str> = FILES.iter().copied().filter(|f| out.join(f).exists()).collect();
    let Ok(text) = std::fs::read_to_string(out.join(SET)) else {
        return if present.is_empty() {
            SetState::Absent
        } else {
            SetState::Broken(format!("{} without {SET}", present.join(", ")))
        };
    };
    let Ok(set) = serde_json::from_str::<serde_json::Value>(&text) else {
        return SetState::Broken(format!("{SET} is not JSON"));
    };
    for f in FILES {
        let want = set["files"][f]["sha256"].as_str().unwrap_or_default();
        match std::fs::read(out.join(f)) {
            Ok(b) if sha256(&b) == want => {}
            Ok(_) => return SetState::Broken(format!("{f} is not the one {SET} lists")),
            Err(_) => return SetState::Broken(format!("{f} is missing")),
        }
    }
    SetState::Complete
}

/// Before a run's work: a set that is not one run's is removed (the three files are outputs,
/// rewritten at this run's end), with a note. Called under the batch lock.
pub(crate) fn clear_broken(out: &Path) -> Result<()> {
    if let SetState::Broken(why) = check(out) {
        eprintln!(
            "rsf batch: the summary files in {} are not one run's ({why}): removed, and written again at this run's end",
            out.display()
        );
        for f in FILES.iter().chain([&SET]) {
            match std::fs::remove_file(out.join(f)) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(e).with_context(|| format!("removing {}", out.join(f).display()));
                }
                _ => {}
            }
        }
    }
    Ok(())
}

/// Writes the set: the three files complete, then the set file removed, the three renamed
/// over their targets, and the set file written last.
pub(crate) fn write(out: &Path, csv: &[u8], parquet: &[u8], svg: &[u8], records: usize) -> Result<()> {
    let bytes = [csv, parquet, svg];
    let paths: Vec<std::path::PathBuf> = FILES.iter().map(|f| out.join(f)).collect();
    let staged = crate::output::Staged::write(&[(&paths[0], csv), (&paths[1], parquet), (&paths[2], svg)])?;
    let set_path = out.join(SET);
    match std::fs::remove_file(&set_path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            return Err(e).with_context(|| format!("removing {}", set_path.display()));
        }
        _ => {}
    }
    staged.commit()?;
    let files: serde_json::Map<String, serde_json::Value> = FILES
        .iter()
        .zip(bytes)
        .map(|(f, b)| (f.to_string(), serde_json::json!({ "sha256": sha256(b), "bytes": b.len() })))
        .collect();
    let set = serde_json::json!({ "rsf": env!("CARGO_PKG_VERSION"), "records": records, "files": files });
    crate::output::write_bytes(&set_path, serde_json::to_string_pretty(&set)? + "\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_set_is_complete_only_as_written() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path();
        assert_eq!(check(out), SetState::Absent);
        write(out, b"csv 1\n", b"pq 1", b"<svg/>", 1).unwrap();
        assert_eq!(check(out), SetState::Complete);
        // a new run's CSV beside the old run's Parquet and figure (a kill between renames)
        std::fs::write(out.join("summary.csv"), "csv 2\n").unwrap();
        assert!(matches!(check(out), SetState::Broken(w) if w.contains("summary.csv")));
        // what the kill really leaves: no set file
        std::fs::remove_file(out.join(SET)).unwrap();
        assert!(matches!(check(out), SetState::Broken(w) if w.contains("without")));
        clear_broken(out).unwrap();
        assert_eq!(check(out), SetState::Absent);
        write(out, b"csv 3\n", b"pq 3", b"<svg/>", 1).unwrap();
        assert_eq!(check(out), SetState::Complete);
        // nothing but the set is left in the folder
        let mut names: Vec<String> =
            std::fs::read_dir(out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().to_string()).collect();
        names.sort();
        assert_eq!(names, ["summary.csv", "summary.parquet", "summary.set.json", "summary.svg"]);
    }
}
