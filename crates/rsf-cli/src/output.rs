//! Writing the CLI's output files so that no run destroys data.
//!
//! * Every output (CSV, JSON, SVG, HTML, the events file) is written to a temporary file in the
//!   target's folder and renamed over the target only when complete ([`write_file`], with the
//!   `tempfile` crate). A run killed while writing, or a full disk, leaves the old file as it
//!   was (a full disk says so); the temporary file is removed. Pipes, terminals and devices
//!   (`/dev/null`) are written directly. An output that is this process's standard output —
//!   `-`, `/dev/stdout`, `/proc/self/fd/1`, a link to them, or the file stdout is redirected
//!   to — is written to standard output itself ([`is_stdout`]), never renamed over, and the
//!   command's table then goes to standard error.
//! * Before any work starts, [`Files::check`] refuses an output that is the same file as an
//!   input (by device and inode, so links and `./` spellings are caught) and two outputs that
//!   are one file, naming both.
//!
//! Not done: `fsync` before the rename. A killed process cannot leave a mix either way; only a
//! power cut right after the run could leave an empty new file on a file system without
//! ext4's rename-replace flush. Outputs are regenerated from their inputs, which are never
//! written.

use anyhow::{Context, Result, bail};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// Set when an output is standard output: the command's own text then goes to stderr.
static STDOUT_TAKEN: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether an output file of this command is standard output.
pub fn stdout_taken() -> bool {
    STDOUT_TAKEN.load(std::sync::atomic::Ordering::Relaxed)
}

/// Whether `path` names this process's standard output: `-`, or the very file standard output
/// is (same device and inode: `/dev/stdout`, `/proc/self/fd/1`, a link to them, or the file
/// a shell redirected it to).
pub fn is_stdout(path: &Path) -> bool {
    if path.as_os_str() == "-" {
        return true;
    }
    #[cfg(unix)]
    {
        use std::os::fd::AsFd;
        use std::os::unix::fs::MetadataExt;
        let Ok(fd) = std::io::stdout().as_fd().try_clone_to_owned() else { return false };
        let Ok(me) = std::fs::File::from(fd).metadata() else { return false };
        if let Ok(m) = std::fs::metadata(path) {
            return m.dev() == me.dev() && m.ino() == me.ino();
        }
    }
    false
}

/// The inputs and outputs of one command, checked against each other before it runs.
#[derive(Default)]
pub struct Files<'a> {
    inputs: Vec<(&'static str, &'a Path)>,
    outputs: Vec<(&'static str, PathBuf)>,
}

/// What identifies a file: its device and inode when it exists, else its canonical folder and
/// name.
#[derive(PartialEq, Eq, Debug)]
enum FileId {
    #[cfg(unix)]
    Inode(u64, u64),
    Path(PathBuf),
}

fn file_id(p: &Path) -> Option<FileId> {
    if let Ok(m) = std::fs::metadata(p) {
        if !m.is_file() {
            // devices, pipes and folders are not files that a write could destroy
            return None;
        }
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            return Some(FileId::Inode(m.dev(), m.ino()));
        }
        #[cfg(not(unix))]
        return std::fs::canonicalize(p).ok().map(FileId::Path);
    }
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(FileId::Path(std::fs::canonicalize(dir).ok()?.join(p.file_name()?)))
}

impl<'a> Files<'a> {
    /// An input file, named by its option in messages.
    pub fn input(mut self, what: &'static str, p: &'a Path) -> Self {
        self.inputs.push((what, p));
        self
    }
    /// An output file, if given.
    pub fn output(mut self, what: &'static str, p: Option<&Path>) -> Self {
        self.outputs.extend(p.map(|p| (what, p.to_path_buf())));
        self
    }
    /// Refuses an output that is an input or another output, naming both. Notes an output that
    /// is standard output ([`stdout_taken`]); two such are refused.
    pub fn check(&self) -> Result<()> {
        let to_stdout: Vec<&PathBuf> = self.outputs.iter().filter(|(_, p)| is_stdout(p)).map(|(_, p)| p).collect();
        if let [a, b, ..] = to_stdout[..] {
            bail!("the outputs {} and {} are both standard output; give one a file", a.display(), b.display());
        }
        if !to_stdout.is_empty() {
            STDOUT_TAKEN.store(true, std::sync::atomic::Ordering::Relaxed);
        }
        let ins: Vec<_> = self.inputs.iter().map(|(w, p)| (w, p, file_id(p))).collect();
        let outs: Vec<_> = self.outputs.iter().map(|(w, p)| (w, p, file_id(p))).collect();
        for (k, (w, p, id)) in outs.iter().enumerate() {
            let Some(id) = id else { continue };
            if let Some((wi, pi, _)) = ins.iter().find(|(_, _, i)| i.as_ref() == Some(id)) {
                bail!(
                    "the {w} output {} is the {wi} {}: it would be destroyed; choose another output path",
                    p.display(),
                    pi.display()
                );
            }
            if let Some((w2, p2, _)) = outs[..k].iter().find(|(_, _, i)| i.as_ref() == Some(id)) {
                bail!(
                    "the {w2} output {} and the {w} output {} are one file; give them different paths",
                    p2.display(),
                    p.display()
                );
            }
        }
        Ok(())
    }
}

/// Writes `path` with what `fill` writes: into a temporary file beside it, renamed over it
/// when complete. A device or pipe (`/dev/stdout`) is written directly.
pub fn write_file(path: &Path, fill: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<()> {
    if is_stdout(path) {
        let mut out = io::stdout().lock();
        return fill(&mut out).and_then(|()| out.flush()).with_context(|| format!("writing {}", path.display()));
    }
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .with_context(|| format!("opening {}", path.display()))?;
        let mut w = io::BufWriter::new(&mut f);
        return fill(&mut w).and_then(|()| w.flush()).with_context(|| format!("writing {}", path.display()));
    }
    let tmp = temp_beside(path)?;
    let kept = if path.exists() { format!("; {} is unchanged", path.display()) } else { String::new() };
    let mut w = io::BufWriter::with_capacity(1 << 16, tmp);
    fill(&mut w).and_then(|()| w.flush()).with_context(|| format!("writing {}{kept}", path.display()))?;
    let tmp =
        w.into_inner().map_err(|e| e.into_error()).with_context(|| format!("writing {}{kept}", path.display()))?;
    commit(tmp, path, &kept)
}

/// An empty temporary file beside `path` (`.NAME.*.rsf-partial`, which a later `rsf batch`
/// sweeps if this process is killed), with the permissions a plain create would give.
fn temp_beside(path: &Path) -> Result<tempfile::NamedTempFile> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path.file_name().with_context(|| format!("{}: not a file name", path.display()))?;
    let prefix = format!(".{}.", name.to_string_lossy());
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".rsf-partial");
    // the new file gets the permissions a plain create would (0666 less the umask), not
    // tempfile's private 0600
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder
        .tempfile_in(dir)
        .with_context(|| format!("creating a temporary file in {} for {}", dir.display(), path.display()))
}

/// Renames the finished temporary file over `path`.
fn commit(tmp: tempfile::NamedTempFile, path: &Path, kept: &str) -> Result<()> {
    let name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let dir = path.parent().map(|d| d.display().to_string()).unwrap_or_default();
    tmp.persist(path)
        .map_err(|e| e.error)
        .with_context(|| format!("renaming the finished output to {name} (in {dir}){kept}"))?;
    Ok(())
}

/// Files written completely before any of them replaces its target ([`Staged::commit`]): a
/// set of outputs that belong together (`rsf batch`'s summary set) is never half new because
/// one of them failed to write.
pub struct Staged {
    files: Vec<(tempfile::NamedTempFile, PathBuf)>,
}

impl Staged {
    /// Writes each `(path, bytes)` to its temporary file; nothing is replaced yet.
    pub fn write(parts: &[(&Path, &[u8])]) -> Result<Self> {
        let mut files = vec![];
        for (path, bytes) in parts {
            let mut tmp = temp_beside(path)?;
            tmp.write_all(bytes).and_then(|()| tmp.flush()).with_context(|| format!("writing {}", path.display()))?;
            files.push((tmp, path.to_path_buf()));
        }
        Ok(Self { files })
    }

    /// Renames each finished file over its target, in order.
    pub fn commit(self) -> Result<()> {
        for (tmp, path) in self.files {
            commit(tmp, &path, "")?;
        }
        Ok(())
    }
}

/// [`write_file`] with bytes already in memory.
pub fn write_bytes(path: &Path, bytes: impl AsRef<[u8]>) -> Result<()> {
    write_file(path, |w| w.write_all(bytes.as_ref()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir() -> tempfile::TempDir {
        tempfile::tempdir().unwrap()
    }

    #[test]
    fn rewriting_replaces_the_whole_file() {
        let d = dir();
        let p = d.path().join("out.csv");
        write_bytes(&p, "a much longer first version of the file\nwith two lines\n").unwrap();
        write_bytes(&p, "short\n").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "short\n");
        write_bytes(&p, "").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "");
        // nothing is left beside it
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 1);
    }

    #[test]
    fn a_failing_or_panicking_writer_leaves_the_old_file() {
        let d = dir();
        let p = d.path().join("out.csv");
        write_bytes(&p, "the old run\n").unwrap();
        let err = write_file(&p, |w| {
            w.write_all(b"part")?;
            Err(io::Error::other("No space left on device"))
        })
        .unwrap_err();
        let msg = format!("{err:#}");
        assert!(msg.contains("No space left") && msg.contains("is unchanged"), "{msg}");
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "the old run\n");
        let caught = std::panic::catch_unwind(|| {
            let _ = write_file(&p, |w| {
                w.write_all(b"new")?;
                panic!("writer failed")
            });
        });
        assert!(caught.is_err());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "the old run\n");
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 1, "the temporary file is removed");
    }

    #[test]
    fn outputs_that_are_inputs_or_each_other_are_refused() {
        let d = dir();
        let rec = d.path().join("rec.txt");
        std::fs::write(&rec, "data").unwrap();
        let other = d.path().join("out.json");
        // the same file by another spelling
        let spelled = d.path().join(".").join("rec.txt");
        let e = Files::default().input("record", &rec).output("--json", Some(&spelled)).check().unwrap_err();
        assert!(e.to_string().contains("--json output") && e.to_string().contains("record"), "{e}");
        #[cfg(unix)]
        {
            let link = d.path().join("link.txt");
            std::os::unix::fs::symlink(&rec, &link).unwrap();
            assert!(Files::default().input("record", &rec).output("--plot", Some(&link)).check().is_err());
        }
        let e = Files::default()
            .input("record", &rec)
            .output("-o", Some(&other))
            .output("--plot", Some(&other))
            .check()
            .unwrap_err();
        assert!(e.to_string().contains("are one file"), "{e}");
        assert!(Files::default().input("record", &rec).output("-o", Some(&other)).check().is_ok());
        // devices are not files a write destroys
        let null = Path::new("/dev/null");
        assert!(Files::default().output("-o", Some(null)).output("--plot", Some(null)).check().is_ok());
        assert_eq!(std::fs::read_to_string(&rec).unwrap(), "data");
    }

    #[test]
    fn a_missing_directory_is_named_in_the_error() {
        let p = Path::new("/nonexistent-rsf-dir/out.csv");
        let err = write_bytes(p, "x").unwrap_err();
        assert!(format!("{err:#}").contains("/nonexistent-rsf-dir"), "{err:#}");
    }

    #[test]
    fn devices_are_written_directly() {
        write_bytes(Path::new("/dev/null"), "x").unwrap();
    }
}
