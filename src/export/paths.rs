//! The check of a set of output paths before anything is written: no output may be an input or
//! another output, and every output must be writable as a new regular file.

use std::io;
use std::path::{Component, Path, PathBuf};

/// A path with the flag that named it (`-o`, `--report`, … or `input` for a positional input),
/// for messages.
#[derive(Clone, Copy, Debug)]
pub struct FlagPath<'a> {
    /// The flag as the user wrote it.
    pub flag: &'a str,
    /// The path as the user wrote it.
    pub path: &'a Path,
}

impl<'a> FlagPath<'a> {
    /// `path` named by `flag`.
    pub fn new(flag: &'a str, path: &'a Path) -> Self {
        FlagPath { flag, path }
    }
}

/// What is wrong with one output path.
#[derive(Debug, thiserror::Error)]
pub enum OutputPathProblem {
    /// The path ends in `..`, `.` or `/` (no file name).
    #[error("it names no file")]
    NoFileName,
    /// The directory the file would go into does not exist.
    #[error("directory {} does not exist", .0.display())]
    NoDirectory(PathBuf),
    /// The path of the directory exists but is not a directory.
    #[error("{} is not a directory", .0.display())]
    NotADirectory(PathBuf),
    /// The target is an existing directory.
    #[error("it is a directory")]
    IsDirectory,
    /// The target exists and is not a regular file (a device, a FIFO, a socket): replacing it
    /// would not write into it.
    #[error("it exists and is not a regular file")]
    NotARegularFile,
    /// No file can be created in the target's directory (read-only, no permission, …).
    #[error("no file can be created in {}: {source}", dir.display())]
    NotWritable {
        dir: PathBuf,
        #[source]
        source: io::Error,
    },
}

/// Why a set of output paths is refused; names the flags as the user wrote them.
#[derive(Debug, thiserror::Error)]
pub enum OutputPathError {
    /// An output is the same file as an input, or as another output (same path after resolving
    /// `.`, `..` and symbolic links, or the same existing file by device and inode, e.g. a hard
    /// link).
    #[error("{flag} {} is the same file as {other_flag} {}", path.display(), other.display())]
    SameFile { flag: String, path: PathBuf, other_flag: String, other: PathBuf },
    /// An output cannot be written as a new regular file.
    #[error("{flag} {}: {problem}", path.display())]
    Unwritable { flag: String, path: PathBuf, problem: OutputPathProblem },
}

/// Identity of a file: its resolved path, and device and inode when it exists.
struct FileKey {
    resolved: PathBuf,
    inode: Option<(u64, u64)>,
}

impl FileKey {
    fn same(&self, other: &FileKey) -> bool {
        self.resolved == other.resolved || (self.inode.is_some() && self.inode == other.inode)
    }
}

#[cfg(unix)]
fn inode(meta: &std::fs::Metadata) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    Some((meta.dev(), meta.ino()))
}

#[cfg(not(unix))]
fn inode(_: &std::fs::Metadata) -> Option<(u64, u64)> {
    None
}

/// The directory `path` goes into (`.` for a bare file name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// The key of an input (which exists, or else is reported by its reader: then only its path as
/// given, made absolute, is compared).
fn input_key(path: &Path) -> FileKey {
    let resolved = std::fs::canonicalize(path).unwrap_or_else(|_| std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()));
    FileKey { resolved, inode: std::fs::metadata(path).ok().as_ref().and_then(inode) }
}

/// The key of an output after checking that it can be written as a new regular file.
fn output_key(path: &Path) -> Result<FileKey, OutputPathProblem> {
    let name = match path.components().next_back() {
        Some(Component::Normal(name)) => name,
        _ => return Err(OutputPathProblem::NoFileName),
    };
    let dir = parent_dir(path);
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => return Err(OutputPathProblem::NotADirectory(dir.to_path_buf())),
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Err(OutputPathProblem::NoDirectory(dir.to_path_buf())),
        Err(e) => return Err(OutputPathProblem::NotWritable { dir: dir.to_path_buf(), source: e }),
    }
    let meta = std::fs::metadata(path).ok();
    if let Some(m) = &meta {
        if m.is_dir() {
            return Err(OutputPathProblem::IsDirectory);
        }
        if !m.is_file() {
            return Err(OutputPathProblem::NotARegularFile);
        }
    }
    // The one sure test that the temporaries can be created: create one (and remove it).
    super::atomic::probe_dir(dir).map_err(|source| OutputPathProblem::NotWritable { dir: dir.to_path_buf(), source })?;
    let resolved = match &meta {
        Some(_) => std::fs::canonicalize(path),
        None => std::fs::canonicalize(dir).map(|d| d.join(name)),
    }
    .map_err(|source| OutputPathProblem::NotWritable { dir: dir.to_path_buf(), source })?;
    Ok(FileKey { resolved, inode: meta.as_ref().and_then(inode) })
}

/// Checks a set of output paths before anything is written (and, for a command, before any
/// work): every output must go into an existing directory where files can be created, must not be
/// a directory or a special file, and must differ from every input and every other output.
/// Paths are compared after resolving `.`, `..` and symbolic links, and existing files also by
/// device and inode (hard links).
///
/// The error names both flags as the caller gave them.
pub fn check_output_paths(inputs: &[FlagPath<'_>], outputs: &[FlagPath<'_>]) -> Result<(), OutputPathError> {
    let inputs: Vec<(FlagPath<'_>, FileKey)> = inputs.iter().map(|i| (*i, input_key(i.path))).collect();
    let mut seen: Vec<(FlagPath<'_>, FileKey)> = Vec::with_capacity(outputs.len());
    for out in outputs {
        let key = output_key(out.path).map_err(|problem| OutputPathError::Unwritable {
            flag: out.flag.to_string(),
            path: out.path.to_path_buf(),
            problem,
        })?;
        if let Some((other, _)) = inputs.iter().chain(seen.iter()).find(|(_, k)| k.same(&key)) {
            return Err(OutputPathError::SameFile {
                flag: out.flag.to_string(),
                path: out.path.to_path_buf(),
                other_flag: other.flag.to_string(),
                other: other.path.to_path_buf(),
            });
        }
        seen.push((*out, key));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("gbsurf-paths-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn check(inputs: &[(&str, &Path)], outputs: &[(&str, &Path)]) -> Result<(), OutputPathError> {
        fn f<'a>(v: &[(&'a str, &'a Path)]) -> Vec<FlagPath<'a>> {
            v.iter().map(|(f, p)| FlagPath::new(f, p)).collect()
        }
        check_output_paths(&f(inputs), &f(outputs))
    }

    #[test]
    fn an_output_equal_to_an_input_or_another_output_is_refused() {
        let d = dir("same");
        let input = d.join("in.obj");
        std::fs::write(&input, "v 0 0 0\n").unwrap();
        let out = d.join("out.obj");
        assert!(check(&[("input", &input)], &[("-o", &out), ("--report", &d.join("r.json"))]).is_ok());
        // The input itself, spelled differently.
        let dotted = d.join(".").join("sub/..").join("in.obj");
        std::fs::create_dir(d.join("sub")).unwrap();
        let e = check(&[("input", &input)], &[("-o", &out), ("--report", &dotted)]).unwrap_err();
        assert!(matches!(e, OutputPathError::SameFile { ref flag, ref other_flag, .. } if flag == "--report" && other_flag == "input"), "{e}");
        assert_eq!(e.to_string(), format!("--report {} is the same file as input {}", dotted.display(), input.display()));
        // Two outputs naming one new file.
        let e = check(&[("input", &input)], &[("-o", &out), ("--curves", &d.join("sub/../out.obj"))]).unwrap_err();
        assert!(e.to_string().starts_with("--curves ") && e.to_string().contains("same file as -o"), "{e}");
        // A hard link to the input, and a symbolic link to it.
        std::fs::hard_link(&input, d.join("hard.obj")).unwrap();
        let e = check(&[("input", &input)], &[("-o", &d.join("hard.obj"))]).unwrap_err();
        assert!(matches!(e, OutputPathError::SameFile { .. }), "{e}");
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&input, d.join("soft.obj")).unwrap();
            let e = check(&[("input", &input)], &[("-o", &d.join("soft.obj"))]).unwrap_err();
            assert!(matches!(e, OutputPathError::SameFile { .. }), "{e}");
        }
        // A relative path and the absolute one.
        let cwd = std::env::current_dir().unwrap();
        let rel = Path::new("Cargo.toml");
        let e = check(&[("input", &cwd.join("Cargo.toml"))], &[("--report", rel)]).unwrap_err();
        assert!(matches!(e, OutputPathError::SameFile { .. }), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn unwritable_outputs_are_named() {
        let d = dir("unwritable");
        std::fs::write(d.join("file"), "x").unwrap();
        let problem = |p: &Path| match check(&[], &[("--report", p)]) {
            Err(OutputPathError::Unwritable { flag, problem, .. }) => {
                assert_eq!(flag, "--report");
                problem
            }
            other => panic!("{other:?}"),
        };
        assert!(matches!(problem(&d), OutputPathProblem::IsDirectory));
        assert!(matches!(problem(&d.join("missing/r.json")), OutputPathProblem::NoDirectory(_)));
        assert!(matches!(problem(&d.join("file/r.json")), OutputPathProblem::NotADirectory(_)));
        assert!(matches!(problem(&d.join("..")), OutputPathProblem::NoFileName));
        #[cfg(unix)]
        assert!(matches!(problem(Path::new("/dev/null")), OutputPathProblem::NotARegularFile));
        let e = check(&[], &[("-o", &d)]).unwrap_err();
        assert_eq!(e.to_string(), format!("-o {}: it is a directory", d.display()));
        // The probe leaves nothing behind.
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        let _ = std::fs::remove_dir_all(&d);
    }
}
