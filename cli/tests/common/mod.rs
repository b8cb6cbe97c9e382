//! Helpers shared by the command-line tests: run the binary in a directory and expect a one-line
//! error.

use std::path::Path;
use std::process::{Command, Output};

/// Runs `gbsurf args` with `dir` as the working directory.
pub fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gbsurf")).current_dir(dir).args(args).output().unwrap()
}

/// Runs `gbsurf args` in `dir`; expects exit 1 and exactly one stderr line, starting with
/// `gbsurf: error: ` and containing every needle.
pub fn fails_in(dir: &Path, args: &[&str], needles: &[&str]) {
    let out = run_in(dir, args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: {err}");
    assert!(lines[0].starts_with("gbsurf: error: "), "{err}");
    for n in needles {
        assert!(lines[0].contains(n), "{args:?}: {err} lacks {n:?}");
    }
}
