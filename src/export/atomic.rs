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
/// - An existing target keeps its permission mode (0600 stays 0600); owner and group become
///   those of the writing process. The rename gives the target a new inode, so a hard link to
///   the old file is detached and keeps the old content: an atomic replacement cannot write
///   through it.
/// - Temporaries are named `.gbsurf<random>` (plus the extension for [`AtomicFiles::add_by_path`]),
///   so a target name of up to 255 bytes works.
/// - A rename is atomic per file (a reader sees the old or the new content, never a part), but
///   the set is not: if a rename in `commit` fails (rare: everything is already written in the
///   same directory, and targets that are directories or special files are refused before the
///   first rename), the targets renamed before it already hold their new content and the later
///   ones keep their old content.
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
        // The failures that are easy to foresee: a target that is a directory, or a special file
        // (a device such as /dev/null, a FIFO) that a rename would replace instead of writing to.
        for (path, _) in &self.staged {
            if let Ok(m) = std::fs::metadata(path) {
                let what = if m.is_dir() { "is a directory" } else { "exists and is not a regular file" };
                if !m.is_file() {
                    return Err(ExportError::io(path, io::Error::new(io::ErrorKind::InvalidInput, what)));
                }
            }
        }
        // An existing target keeps its mode (by path: an outside writer may have replaced the
        // temporary's file; set after writing, so a read-only mode does not stop the writer).
        for (path, tmp) in &self.staged {
            if let Some(m) = std::fs::metadata(path).ok().filter(|m| m.is_file()) {
                std::fs::set_permissions(tmp.path(), m.permissions()).map_err(|e| ExportError::io(path, e))?;
            }
        }
        for (path, tmp) in self.staged {
            tmp.persist(&path).map_err(|e| ExportError::io(&path, e.error))?;
        }
        Ok(())
    }
}

/// The prefix of every temporary: short, so that the temporary's name fits the file-name limit
/// (NAME_MAX, 255 bytes) whenever the target's does.
const TEMP_PREFIX: &str = ".gbsurf";

/// The directory `path` goes into (`.` for a bare file name).
fn dir_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Creates (and removes) a temporary in `dir`: the test that the temporaries of
/// [`AtomicFiles`] can be created there.
pub(super) fn probe_dir(dir: &Path) -> io::Result<()> {
    tempfile::Builder::new().prefix(TEMP_PREFIX).tempfile_in(dir).map(drop)
}

/// A new temporary file in the directory of `path`, named `.gbsurf<random><suffix>`, with the
/// permissions of a normally created file (0666 less the umask; `NamedTempFile::new_in` alone
/// would give 0600, and the rename keeps them). [`AtomicFiles::commit`] gives it the mode of an
/// existing target.
fn temporary_for(path: &Path, suffix: &str) -> Result<NamedTempFile, ExportError> {
    if path.file_name().is_none() {
        return Err(ExportError::io(path, io::Error::new(io::ErrorKind::InvalidInput, "not a file name")));
    }
    let mut builder = tempfile::Builder::new();
    builder.prefix(TEMP_PREFIX).suffix(suffix);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder.tempfile_in(dir_of(path)).map_err(|e| ExportError::io(path, e))
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
        // A special file is never replaced.
        #[cfg(unix)]
        {
            let e = write_atomic("/dev/null", |w| w.write_all(b"x")).unwrap_err();
            assert!(e.to_string().contains("not a regular file"), "{e}");
            assert!(!std::fs::metadata("/dev/null").unwrap().is_file());
        }
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_write_error_after_partial_output_leaves_no_temporary() {
        let d = dir("partial");
        std::fs::write(d.join("a.txt"), "old").unwrap();
        let mut set = AtomicFiles::new();
        set.add(d.join("b.txt"), b"staged").unwrap();
        // A writer that fails after 1 MiB (as a full disk would): the error names the target.
        let e = set
            .add_with(d.join("a.txt"), |w| {
                w.write_all(&vec![b'x'; 1 << 20])?;
                Err(io::Error::new(io::ErrorKind::StorageFull, "no space left"))
            })
            .unwrap_err();
        assert!(e.to_string().contains("a.txt") && e.to_string().contains("no space"), "{e}");
        // The failed temporary is gone at once, the staged one when the set is dropped.
        assert_eq!(names(&d).len(), 2, "{:?}", names(&d));
        drop(set);
        assert_eq!(names(&d), ["a.txt"]);
        assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "old");
        // A later file in a directory that does not exist: same.
        let mut set = AtomicFiles::new();
        set.add(d.join("c.txt"), b"1").unwrap();
        assert!(set.add(d.join("missing/d.txt"), b"2").is_err());
        drop(set);
        assert_eq!(names(&d), ["a.txt"]);
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_file_name_of_254_bytes_works() {
        let d = dir("long");
        let name = format!("{}.obj", "n".repeat(250));
        assert_eq!(name.len(), 254);
        write_atomic(d.join(&name), |w| w.write_all(b"v 0 0 0\n")).unwrap();
        write_atomic(d.join(&name), |w| w.write_all(b"v 1 0 0\n")).unwrap();
        assert_eq!(names(&d), [name.as_str()]);
        assert_eq!(std::fs::read_to_string(d.join(&name)).unwrap(), "v 1 0 0\n");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[cfg(unix)]
    #[test]
    fn an_existing_target_keeps_its_mode_and_a_hard_link_is_detached() {
        use std::os::unix::fs::PermissionsExt;
        let d = dir("mode");
        let (a, link) = (d.join("a.txt"), d.join("link.txt"));
        std::fs::write(&a, "old").unwrap();
        std::fs::set_permissions(&a, std::fs::Permissions::from_mode(0o600)).unwrap();
        std::fs::hard_link(&a, &link).unwrap();
        write_atomic(&a, |w| w.write_all(b"new")).unwrap();
        assert_eq!(std::fs::metadata(&a).unwrap().permissions().mode() & 0o7777, 0o600);
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "new");
        assert_eq!(std::fs::read_to_string(&link).unwrap(), "old");
        // A read-only target is replaced (the mode is set after writing) and stays read-only.
        std::fs::set_permissions(&a, std::fs::Permissions::from_mode(0o444)).unwrap();
        let mut set = AtomicFiles::new();
        set.add_by_path(&a, |p: &Path| std::fs::write(p, "by path").map_err(|e| e.to_string())).unwrap();
        set.commit().unwrap();
        assert_eq!(std::fs::metadata(&a).unwrap().permissions().mode() & 0o7777, 0o444);
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "by path");
        // A new file gets 0666 less the umask, never the 0600 of a bare temporary.
        write_atomic(d.join("new.txt"), |w| w.write_all(b"x")).unwrap();
        assert_ne!(std::fs::metadata(d.join("new.txt")).unwrap().permissions().mode() & 0o7777, 0o600);
        let _ = std::fs::remove_dir_all(&d);
    }
}
