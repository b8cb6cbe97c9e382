//! Output paths and count options of the command line: nothing overwritten that is an input or
//! another output, nothing written when any output path is bad, no temporary left behind, long
//! names and file modes kept, every count option bounded with a one-line error.

mod common;
use common::{fails_in, run_in};

use std::path::{Path, PathBuf};
use std::process::Command;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/models");
const CUBIC5: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/cubic5.gbp");

/// A fresh directory holding a copy of the cube as `in.obj`.
fn setup(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gbsurf-paths-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    std::fs::copy(format!("{MODELS}/cube.obj"), d.join("in.obj")).unwrap();
    d
}


fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

fn cube_text() -> String {
    std::fs::read_to_string(format!("{MODELS}/cube.obj")).unwrap()
}

#[test]
fn an_output_equal_to_the_input_is_refused() {
    let d = setup("same-input");
    fails_in(&d, &["convert", "in.obj", "-o", "in.obj", "--quiet"], &["-o in.obj is the same file as input in.obj"]);
    fails_in(&d, &["convert", "in.obj", "-o", "out.obj", "--report", "./in.obj", "--quiet"], &["--report ./in.obj", "input in.obj"]);
    let abs = d.join("in.obj");
    fails_in(&d, &["convert", abs.to_str().unwrap(), "-o", "out.obj", "--curves", "in.obj", "--quiet"], &["--curves in.obj", "same file as input"]);
    // A hard link to the input.
    std::fs::hard_link(d.join("in.obj"), d.join("hard.obj")).unwrap();
    fails_in(&d, &["convert", "in.obj", "-o", "hard.obj", "--quiet"], &["-o hard.obj is the same file as input in.obj"]);
    assert_eq!(std::fs::read_to_string(d.join("in.obj")).unwrap(), cube_text());
    assert_eq!(names(&d), ["hard.obj", "in.obj"]);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn two_outputs_naming_one_file_are_refused() {
    let d = setup("same-output");
    fails_in(&d, &["convert", "in.obj", "-o", "x.obj", "--report", "x.obj", "--quiet"], &["--report x.obj is the same file as -o x.obj"]);
    fails_in(&d, &["convert", "in.obj", "-o", "x.obj", "--nets", "./x.obj", "--quiet"], &["--nets ./x.obj is the same file as -o x.obj"]);
    fails_in(&d, &["convert", "in.obj", "-o", "x.obj", "--slices", "s.obj", "--isophotes", "s.obj", "--quiet"], &["--slices s.obj is the same file as --isophotes s.obj"]);
    assert_eq!(names(&d), ["in.obj"]);
    // An existing output and a hard link to it.
    std::fs::write(d.join("x.obj"), "old").unwrap();
    std::fs::hard_link(d.join("x.obj"), d.join("link.json")).unwrap();
    fails_in(&d, &["convert", "in.obj", "-o", "x.obj", "--report", "link.json", "--quiet"], &["--report link.json is the same file as -o x.obj"]);
    assert_eq!(std::fs::read_to_string(d.join("x.obj")).unwrap(), "old");
    // A .gbp file written beside --patches.
    fails_in(
        &d,
        &["convert", "in.obj", "-o", "out.obj", "--report", "p_00000.gbp", "--patches", "p.json", "--quiet"],
        &["--patches ", "p_00000.gbp is the same file as --report p_00000.gbp"],
    );
    assert_eq!(names(&d), ["in.obj", "link.json", "x.obj"]);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_bad_output_path_stops_the_run_before_anything_is_written() {
    let d = setup("bad-output");
    std::fs::write(d.join("out.obj"), "old").unwrap();
    std::fs::create_dir(d.join("dir")).unwrap();
    std::fs::write(d.join("file"), "x").unwrap();
    for (flag, path, needle) in [
        ("--report", "dir", "--report dir: it is a directory"),
        ("--curves", "missing/c.obj", "--curves missing/c.obj: directory missing does not exist"),
        ("--patches", "file/p.json", "--patches file/p.json: file is not a directory"),
        ("--isophotes", "/dev/null", "--isophotes /dev/null: it exists and is not a regular file"),
    ] {
        fails_in(&d, &["convert", "in.obj", "-o", "out.obj", flag, path, "--quiet"], &[needle]);
        assert_eq!(std::fs::read_to_string(d.join("out.obj")).unwrap(), "old", "{flag}");
        assert_eq!(names(&d), ["dir", "file", "in.obj", "out.obj"], "{flag}");
        assert!(names(&d.join("dir")).is_empty());
    }
    // tessellate-gbp: the same checks.
    std::fs::copy(CUBIC5, d.join("p.gbp")).unwrap();
    fails_in(&d, &["tessellate-gbp", "p.gbp", "-o", "p.gbp"], &["-o p.gbp is the same file as input p.gbp"]);
    fails_in(&d, &["tessellate-gbp", "p.gbp", "-o", "dir"], &["-o dir: it is a directory"]);
    assert_eq!(std::fs::read(d.join("p.gbp")).unwrap(), std::fs::read(CUBIC5).unwrap());
    std::fs::remove_dir_all(&d).unwrap();
}

/// A write that fails midway (the file-size limit stands in for a full disk: with SIGXFSZ
/// ignored, a write past the limit fails with EFBIG) leaves every target untouched and no
/// temporary behind.
#[cfg(unix)]
#[test]
fn a_failed_write_leaves_no_temporary() {
    let d = setup("write-fails");
    std::fs::write(d.join("out.ply"), "old").unwrap();
    let script = r#"trap '' XFSZ; ulimit -f 8 || exit 99; exec "$0" "$@""#;
    let out = Command::new("sh")
        .current_dir(&d)
        .args(["-c", script, env!("CARGO_BIN_EXE_gbsurf"), "convert", "in.obj", "-o", "out.ply", "--report", "r.json", "--resolution", "64", "--quiet"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("out.ply"), "{err}");
    assert_eq!(names(&d), ["in.obj", "out.ply"]);
    assert_eq!(std::fs::read_to_string(d.join("out.ply")).unwrap(), "old");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_254_byte_output_name_works() {
    let d = setup("long-name");
    let name = format!("{}.obj", "n".repeat(250));
    let report = format!("{}.json", "r".repeat(249));
    assert_eq!((name.len(), report.len()), (254, 254));
    let out = run_in(&d, &["convert", "in.obj", "-o", &name, "--report", &report, "--patches", "p.json", "--quiet"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::read_to_string(d.join(&name)).unwrap().starts_with("# gbsurf: "));
    // The cube's dual has 8 patches with a .gbp file each; no temporary is left.
    let gbp = names(&d).iter().filter(|n| n.starts_with("p_") && n.ends_with(".gbp")).count();
    assert_eq!((names(&d).len(), gbp), (4 + 8, 8), "{:?}", names(&d));
    std::fs::remove_dir_all(&d).unwrap();
}

#[cfg(unix)]
#[test]
fn an_existing_output_keeps_its_mode() {
    use std::os::unix::fs::PermissionsExt;
    let d = setup("mode");
    let out_path = d.join("out.obj");
    std::fs::write(&out_path, "old").unwrap();
    std::fs::set_permissions(&out_path, std::fs::Permissions::from_mode(0o600)).unwrap();
    let out = run_in(&d, &["convert", "in.obj", "-o", "out.obj", "--quiet"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(std::fs::metadata(&out_path).unwrap().permissions().mode() & 0o7777, 0o600);
    assert!(std::fs::read_to_string(&out_path).unwrap().starts_with("# gbsurf: "));
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn every_count_option_is_bounded() {
    let d = setup("counts");
    let huge = u64::MAX.to_string();
    let convert = |extra: &[&str], needles: &[&str]| {
        let mut args = vec!["convert", "in.obj", "-o", "out.obj", "--slices", "s.obj", "--isophotes", "i.ply", "--quiet"];
        args.extend_from_slice(extra);
        fails_in(&d, &args, needles);
        assert_eq!(names(&d), ["in.obj"], "{extra:?}");
    };
    convert(&["--slice-count", &huge], &[&format!("invalid --slice-count {huge}: must be in 1..=1000")]);
    convert(&["--slice-count", "100000"], &["invalid --slice-count 100000: must be in 1..=1000"]);
    convert(&["--slice-count", "0"], &["invalid --slice-count 0"]);
    convert(&["--stripes", "4294967295"], &["invalid --stripes 4294967295: must be in 1..=1000"]);
    convert(&["--stripes", "0"], &["invalid --stripes 0"]);
    convert(&["--resolution", &huge], &[&format!("invalid --resolution {huge}: must be in 1..=1024")]);
    convert(&["--resolution", "0"], &["invalid --resolution 0"]);
    convert(&["--method", "catmull-clark", "--levels", "4294967295"], &["invalid --levels 4294967295: must be in 0..=8"]);
    // Values beyond the flag's integer type are usage errors (exit 2), not panics.
    let out = run_in(&d, &["convert", "in.obj", "-o", "out.obj", "--stripes", &huge]);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    // tessellate-gbp --resolution.
    std::fs::copy(CUBIC5, d.join("p.gbp")).unwrap();
    fails_in(&d, &["tessellate-gbp", "p.gbp", "-o", "t.obj", "--resolution", &huge], &[&format!("invalid --resolution {huge}: must be in 1..=1024")]);
    fails_in(&d, &["tessellate-gbp", "p.gbp", "-o", "t.obj", "--resolution", "0"], &["invalid --resolution 0"]);
    // The largest values work.
    let out = run_in(&d, &["convert", "in.obj", "-o", "out.obj", "--resolution", "2", "--slices", "s.obj", "--slice-count", "1000", "--isophotes", "i.ply", "--stripes", "1000", "--quiet"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let slices = std::fs::read_to_string(d.join("s.obj")).unwrap();
    assert_eq!(slices.lines().filter(|l| l.starts_with("g slice_")).count(), 1000);
    std::fs::remove_dir_all(&d).unwrap();
}
