//! One `rsf batch` at a time on an output folder: the lock file `DIR/.rsf-batch.lock`,
//! created exclusively and complete (a written file linked to its name), holds the holder's
//! process id, host and start; it is removed when the
//! run ends. A second run on the same folder says who holds it and stops before any work.
//! A lock whose process is gone (same host, no such process) is taken over, with a note: a
//! run that was killed cannot remove its lock.

use anyhow::{Context, Result, bail};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The held lock; dropping it removes the file.
pub(crate) struct Lock {
    path: PathBuf,
}

impl Drop for Lock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// This machine's name, as far as it can be read (only for the lock's message and staleness).
fn host() -> String {
    ["/proc/sys/kernel/hostname", "/etc/hostname"]
        .iter()
        .find_map(|p| std::fs::read_to_string(p).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "this machine".into())
}

/// Whether the lock's holder is a process of this host that no longer exists (Linux: no
/// `/proc/PID`). Anything else counts as alive: a lock is never broken on a guess.
fn stale(held: &str) -> bool {
    let mut words = held.split_whitespace();
    let (Some("pid"), Some(pid), Some("on"), Some(h)) = (words.next(), words.next(), words.next(), words.next()) else {
        return false;
    };
    Path::new("/proc/self").exists() && h == host() && !Path::new(&format!("/proc/{pid}")).exists()
}

/// Takes the lock on `out` (created when missing).
pub(crate) fn lock(out: &Path) -> Result<Lock> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let path = out.join(".rsf-batch.lock");
    let since = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let me = format!("pid {} on {} since {since} (unix seconds)\n", std::process::id(), host());
    // the lock appears with its holder written: a complete file, linked to the lock's name
    // (a link fails when the name exists), so that a second run never reads an empty lock.
    // (Not `.rsf-partial`: the holder's sweep must not remove a contender's file before it
    // links.)
    let mut tmp = tempfile::Builder::new()
        .prefix(".rsf-batch.lock.")
        .suffix(".new")
        .tempfile_in(out)
        .with_context(|| format!("creating a temporary file in {}", out.display()))?;
    tmp.write_all(me.as_bytes()).and_then(|()| tmp.flush()).with_context(|| format!("writing {}", path.display()))?;
    for _ in 0..2 {
        match std::fs::hard_link(tmp.path(), &path) {
            Ok(()) => return Ok(Lock { path }),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                let held = std::fs::read_to_string(&path).unwrap_or_default();
                if stale(&held) {
                    eprintln!("rsf batch: taking over the lock of a run that has ended ({})", held.trim());
                    let _ = std::fs::remove_file(&path);
                    continue;
                }
                bail!(
                    "{} is in use by another rsf batch ({}): wait for it to end (or, if that run is gone, remove {})",
                    out.display(),
                    held.trim(),
                    path.display()
                );
            }
            // a filesystem without hard links: created exclusively, then written
            Err(_) => match std::fs::OpenOptions::new().write(true).create_new(true).open(&path) {
                Ok(mut f) => {
                    f.write_all(me.as_bytes()).with_context(|| format!("writing {}", path.display()))?;
                    return Ok(Lock { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e).with_context(|| format!("creating {}", path.display())),
            },
        }
    }
    bail!("{}: could not take the lock {}", out.display(), path.display())
}

/// Removes the temporary files (`.NAME.*.rsf-partial`) a killed run left in `dir`: under the
/// lock no other run is writing them.
pub(crate) fn sweep_partials(dir: &Path) {
    let Ok(rd) = std::fs::read_dir(dir) else { return };
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().to_string();
        if name.starts_with('.') && name.ends_with(".rsf-partial") && e.file_type().is_ok_and(|t| t.is_file()) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}
