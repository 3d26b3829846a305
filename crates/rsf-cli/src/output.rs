//! Writing the CLI's output files.
//!
//! Every file the CLI writes goes through [`write_file`], which writes the new contents over
//! the old bytes and then trims the file to its new length, instead of truncating it to zero
//! first (`File::create`). Why: on ext4 (the default `auto_da_alloc` mount option) a file
//! truncated to zero and rewritten is flushed to disk when it is closed, to protect programs
//! that replace files without `fsync`. For the 200 kB CSV of the seed protocol that flush cost
//! 0.26–0.33 ms per run, more than formatting the numbers, and re-running a simulation into
//! the same file is the common case. Overwriting in place leaves the bytes in the page cache
//! (10 µs for the same write). A failed write still returns an error naming the file, and the
//! file is trimmed to what was written (also when the writer panics), as a truncating write
//! would leave it. The price: a run killed while it writes (which takes milliseconds even for
//! a million rows) leaves the start of the new output followed by the end of the old, where a
//! truncating write would leave a short file; docs/cli.md says so.

use anyhow::{Context, Result};
use std::fs::{File, OpenOptions};
use std::io::{self, Write};
use std::path::Path;

/// A file being rewritten in place, counting the bytes written so the old tail can be cut.
/// Dropped untrimmed (a panicking writer), it trims itself.
struct Overwrite {
    file: File,
    written: u64,
    /// Whether the file is a regular file (pipes, terminals and devices are not trimmed).
    regular: bool,
    trimmed: bool,
}

impl Overwrite {
    fn trim(&mut self) -> io::Result<()> {
        self.trimmed = true;
        if self.regular { self.file.set_len(self.written) } else { Ok(()) }
    }
}

impl Drop for Overwrite {
    fn drop(&mut self) {
        if !self.trimmed {
            let _ = self.trim();
        }
    }
}

impl Write for Overwrite {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.file.write(buf)?;
        self.written += n as u64;
        Ok(n)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

/// Creates or rewrites `path` with what `fill` writes (see the module notes for why the file
/// is not truncated first). Pipes, terminals and devices (`/dev/stdout`) are written as they
/// are; only regular files are trimmed.
pub fn write_file(path: &Path, fill: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<()> {
    let file = OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .with_context(|| format!("creating {}", path.display()))?;
    // an open file whose type cannot be read is treated as regular: trimming is then tried,
    // and a failure is reported
    let regular = file.metadata().map(|m| m.is_file()).unwrap_or(true);
    let mut out = Overwrite { file, written: 0, regular, trimmed: false };
    let filled = fill(&mut out).and_then(|()| out.flush());
    let trimmed = out.trim();
    // the writer's own error first: it is the cause
    filled.with_context(|| format!("writing {}", path.display()))?;
    trimmed.with_context(|| format!("trimming {}", path.display()))
}

/// [`write_file`] with bytes already in memory.
pub fn write_bytes(path: &Path, bytes: impl AsRef<[u8]>) -> Result<()> {
    write_file(path, |w| w.write_all(bytes.as_ref()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rewriting_a_longer_file_leaves_only_the_new_contents() {
        let dir = std::env::temp_dir().join(format!("rsf-output-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("out.csv");
        write_bytes(&p, "a much longer first version of the file\nwith two lines\n").unwrap();
        write_bytes(&p, "short\n").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "short\n");
        write_bytes(&p, "").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "");
        write_bytes(&p, "grows again, longer than before\n").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "grows again, longer than before\n");
        // a failing writer leaves what was written (the prefix), not the old tail
        let err = write_file(&p, |w| {
            w.write_all(b"part")?;
            Err(io::Error::other("disk full"))
        })
        .unwrap_err();
        assert!(format!("{err:#}").contains("writing") && format!("{err:#}").contains("disk full"), "{err:#}");
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "part");
        // a panicking writer leaves what it wrote, not the old tail
        write_bytes(&p, "a long old version of the output\n").unwrap();
        let caught = std::panic::catch_unwind(|| {
            let _ = write_file(&p, |w| {
                w.write_all(b"new")?;
                panic!("writer failed")
            });
        });
        assert!(caught.is_err());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_missing_directory_is_named_in_the_error() {
        let p = Path::new("/nonexistent-rsf-dir/out.csv");
        let err = write_bytes(p, "x").unwrap_err();
        assert!(format!("{err:#}").contains("/nonexistent-rsf-dir/out.csv"), "{err:#}");
    }
}
