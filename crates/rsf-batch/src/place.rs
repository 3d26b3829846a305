//! Where a manifest's record is: whether its `file` cell leaves the manifest's folder, and
//! what identifies the file whatever its spelling.

use std::path::{Component, Path, PathBuf};

/// `rel` (a manifest's `file` cell) leaves the folder it is relative to, read lexically: an
/// absolute path, or more `..` than folders before them.
pub(crate) fn escapes_lexically(rel: &Path) -> bool {
    let mut depth = 0i64;
    for c in rel.components() {
        match c {
            Component::Prefix(_) | Component::RootDir => return true,
            Component::CurDir => {}
            Component::ParentDir => {
                depth -= 1;
                if depth < 0 {
                    return true;
                }
            }
            Component::Normal(_) => depth += 1,
        }
    }
    false
}

/// What identifies a record's file whatever its spelling (`a.csv`, `./a.csv`, `sub/../a.csv`,
/// a link to it): its device and inode where the file exists (Unix), else its resolved path,
/// else its path with `.` and `..` resolved lexically.
pub(crate) fn file_identity(path: &Path) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let Ok(m) = std::fs::metadata(path) {
            return format!("inode {}:{}", m.dev(), m.ino());
        }
    }
    if let Ok(c) = path.canonicalize() {
        return c.display().to_string();
    }
    let mut out = PathBuf::new();
    for c in std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()).components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out.display().to_string()
}
