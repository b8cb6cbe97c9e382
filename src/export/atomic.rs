//! The one atomic writer: every file goes to a temporary file beside its target and is renamed
//! into place only when all of them are complete.

use super::ExportError;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use tempfile::NamedTempFile;

/// Files written together. [`AtomicFiles::add`] (and its variants) write a file completely into
/// a temporary file in the target's directory; [`AtomicFiles::commit`] then renames every
/// temporary over its target, in the order added.
///
/// - A failure while producing or writing any file (before `commit`) touches no target.
/// - Temporaries never survive: they are deleted when dropped (an error, a panic, or a failed
///   rename in `commit`).
/// - A rename is atomic per file (a reader sees the old or the new content, never a part), but
///   the set is not: if a rename in `commit` fails (rare: everything is already written in the
///   same directory, and targets that are directories are refused before the first rename), the
///   targets renamed before it already hold their new content and the later ones keep their old
///   content.
#[derive(Debug, Default)]
pub struct AtomicFiles {
    staged: Vec<(PathBuf, NamedTempFile)>,
}

impl AtomicFiles {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `bytes` as the new content of `path`.
    pub fn add(&mut self, path: impl Into<PathBuf>, bytes: &[u8]) -> Result<(), ExportError> {
        self.add_with(path, |w| w.write_all(bytes))
    }

    /// Adds the output of `write` (buffered, flushed and synced here) as the new content of `path`.
    pub fn add_with(
        &mut self,
        path: impl Into<PathBuf>,
        write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    ) -> Result<(), ExportError> {
        let path = path.into();
        let mut tmp = temporary_for(&path, "")?;
        let written = (|| {
            let mut w = BufWriter::new(tmp.as_file_mut());
            write(&mut w)?;
            w.flush()?;
            drop(w);
            tmp.as_file().sync_all()
        })();
        written.map_err(|e| ExportError::io(&path, e))?;
        self.staged.push((path, tmp));
        Ok(())
    }

    /// Adds a file that an outside writer creates by name (e.g. OpenMesh): `write` gets the path
    /// of the temporary, which ends in the target's extension since such writers choose the
    /// format by it, and may replace the file there.
    pub fn add_by_path<E: std::fmt::Display>(
        &mut self,
        path: impl Into<PathBuf>,
        write: impl FnOnce(&Path) -> Result<(), E>,
    ) -> Result<(), ExportError> {
        let path = path.into();
        let ext = path.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
        let tmp = temporary_for(&path, &ext)?;
        write(tmp.path()).map_err(|e| ExportError::io(&path, io::Error::other(e.to_string())))?;
        self.staged.push((path, tmp));
        Ok(())
    }

    /// Renames every temporary over its target (see the type's documentation for what a failure
    /// here leaves behind).
    pub fn commit(self) -> Result<(), ExportError> {
        // The one failure that is easy to foresee: a target that is a directory.
        if let Some((path, _)) = self.staged.iter().find(|(p, _)| p.is_dir()) {
            return Err(ExportError::io(path, io::Error::new(io::ErrorKind::InvalidInput, "is a directory")));
        }
        for (path, tmp) in self.staged {
            tmp.persist(&path).map_err(|e| ExportError::io(&path, e.error))?;
        }
        Ok(())
    }
}

/// A new temporary file in the directory of `path`, named `.<file name>.<random><suffix>`, with
/// the permissions of a normally created file (0666 less the umask; `NamedTempFile::new_in`
/// alone would give 0600, and the rename keeps them).
fn temporary_for(path: &Path, suffix: &str) -> Result<NamedTempFile, ExportError> {
    let name = path
        .file_name()
        .ok_or_else(|| ExportError::io(path, io::Error::new(io::ErrorKind::InvalidInput, "not a file name")))?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let prefix = format!(".{}.", name.to_string_lossy());
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(suffix);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder.tempfile_in(dir).map_err(|e| ExportError::io(path, e))
}

/// Writes one file atomically: the output of `write` goes to a temporary file beside `path`,
/// renamed over it only when complete (readers never see a partial file; on failure `path` is
/// untouched and the temporary is removed).
pub fn write_atomic(path: impl AsRef<Path>, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<(), ExportError> {
    let mut files = AtomicFiles::new();
    files.add_with(path.as_ref(), write)?;
    files.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("gbsurf-atomic-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        v.sort();
        v
    }

    #[test]
    fn nothing_is_written_when_one_file_fails() {
        let d = dir("fail");
        std::fs::write(d.join("a.txt"), "old").unwrap();
        let mut set = AtomicFiles::new();
        set.add(d.join("a.txt"), b"new").unwrap();
        let e = set.add_with(d.join("b.txt"), |_| Err(io::Error::other("boom"))).unwrap_err();
        assert!(e.to_string().contains("b.txt") && e.to_string().contains("boom"), "{e}");
        drop(set);
        assert_eq!(names(&d), ["a.txt"]);
        assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "old");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn all_files_appear_on_commit_and_no_temporary_remains() {
        let d = dir("ok");
        let mut set = AtomicFiles::new();
        set.add(d.join("a.txt"), b"1").unwrap();
        set.add(d.join("b.om"), b"2").unwrap();
        set.commit().unwrap();
        assert_eq!(names(&d), ["a.txt", "b.om"]);
        let mut set = AtomicFiles::new();
        set.add_by_path(d.join("c.om"), |p: &Path| {
            assert!(p.extension().is_some_and(|e| e == "om"), "{}", p.display());
            std::fs::write(p, "3").map_err(|e| e.to_string())
        })
        .unwrap();
        set.commit().unwrap();
        assert_eq!(names(&d), ["a.txt", "b.om", "c.om"]);
        assert_eq!(std::fs::read_to_string(d.join("c.om")).unwrap(), "3");
        // A target that is a directory: nothing is renamed, no temporary remains.
        std::fs::create_dir(d.join("sub")).unwrap();
        let mut set = AtomicFiles::new();
        set.add(d.join("d.txt"), b"4").unwrap();
        set.add(d.join("sub"), b"x").unwrap();
        assert!(set.commit().is_err());
        assert_eq!(names(&d), ["a.txt", "b.om", "c.om", "sub"]);
        let _ = std::fs::remove_dir_all(&d);
    }
}
