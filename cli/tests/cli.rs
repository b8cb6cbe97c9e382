//! End-to-end tests of the `gbsurf` binary.

use gbsurf::gb::Evaluate;
use gbsurf::gb::gbp::load_gbp;
use gbsurf::gb::WeightForm;
use gbsurf::{assert_near, DVec2, DVec3};
use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

const BIN: &str = env!("CARGO_BIN_EXE_gbsurf");
const CUBIC5: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/cubic5.gbp");
const QUINTIC3: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/quintic3.gbp");

fn run(args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(BIN)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The binary may exit on an error before reading all of its input: a broken pipe is fine.
    if let Err(e) = child.stdin.take().unwrap().write_all(stdin.as_bytes()) {
        assert_eq!(e.kind(), std::io::ErrorKind::BrokenPipe, "writing stdin: {e}");
    }
    child.wait_with_output().unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gbsurf-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn points(stdout: &[u8]) -> Vec<DVec3> {
    String::from_utf8(stdout.to_vec())
        .unwrap()
        .lines()
        .map(|l| {
            let v: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
            assert_eq!(v.len(), 3, "{l}");
            DVec3::new(v[0], v[1], v[2])
        })
        .collect()
}

#[test]
fn eval_gbp_matches_library_eval() {
    let uvs = [
        (0.0, 0.0),
        (0.3, -0.2),
        (1.0, 0.0),
        (-0.4, 0.45),
        (0.1, 0.7),
    ];
    let input: String = uvs
        .iter()
        .map(|(u, v)| format!("{u} {v}\n"))
        .collect::<String>()
        + "\n";
    for (file, weights, form) in [
        (CUBIC5, "squared", WeightForm::Squared),
        (CUBIC5, "linear", WeightForm::Linear),
        (QUINTIC3, "squared", WeightForm::Squared),
    ] {
        let patch = load_gbp(file).unwrap();
        // Keep only points inside this domain (the triangle is smaller).
        let dom = patch.evaluator().unwrap().domain().clone();
        let inside: Vec<_> = uvs
            .iter()
            .filter(|&&(u, v)| dom.contains(DVec2::new(u, v), 0.0))
            .collect();
        let input: String = inside.iter().map(|(u, v)| format!("{u} {v}\n")).collect();
        let out = run(&["eval-gbp", file, "--weights", weights], &input);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let got = points(&out.stdout);
        assert_eq!(got.len(), inside.len());
        for (p, &&(u, v)) in got.iter().zip(&inside) {
            assert_near!(*p, patch.eval(DVec2::new(u, v), form), 1e-15);
        }
        // At least 15 significant digits per coordinate.
        let text = String::from_utf8(out.stdout).unwrap();
        for tok in text.split_whitespace() {
            let mantissa = tok.trim_start_matches('-').split('e').next().unwrap();
            assert!(
                mantissa.chars().filter(|c| c.is_ascii_digit()).count() >= 15,
                "{tok}"
            );
        }
    }
    // The corner at domain vertex 0 is the corner control point (1, 0, 0) of cubic5.
    let out = run(&["eval-gbp", CUBIC5], &input);
    assert!(out.status.success());
    assert_eq!(points(&out.stdout)[2], DVec3::new(1.0, 0.0, 0.0));
}

#[test]
fn eval_gbp_errors_name_the_input_line() {
    for (input, needle) in [
        ("0 0\n0.5 x\n", "stdin line 2: v = `x` is not a number"),
        ("0 0\n\n0.1\n", "stdin line 3: expected two numbers"),
        ("0 0 0\n", "stdin line 1: expected two numbers"),
        ("0.1 NaN\n", "stdin line 1: v = `NaN` is not finite"),
        (
            "0 0\n3 3\n",
            "stdin line 2: (3, 3) is outside the 5-sided domain",
        ),
    ] {
        let out = run(&["eval-gbp", CUBIC5], input);
        assert_eq!(out.status.code(), Some(1), "{input:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(needle), "{err}");
    }
    let dir = scratch("bad-gbp");
    let bad = dir.join("bad.gbp");
    std::fs::write(&bad, "5 3\n0 0 1\n1 2\n").unwrap();
    let out = run(&["eval-gbp", bad.to_str().unwrap()], "0 0\n");
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("bad.gbp: line 3: unexpected end of file"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn tessellate_gbp_writes_obj() {
    let dir = scratch("tess");
    let obj = dir.join("out.obj");
    let out = run(
        &[
            "tessellate-gbp",
            CUBIC5,
            "-o",
            obj.to_str().unwrap(),
            "--resolution",
            "6",
        ],
        "",
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&obj).unwrap();
    let count = |p: &str| text.lines().filter(|l| l.starts_with(p)).count();
    let (n, r) = (5, 6);
    assert_eq!(count("v "), 1 + n * r * (r + 1) / 2);
    assert_eq!(count("vn "), 1 + n * r * (r + 1) / 2);
    assert_eq!(count("f "), n * r * r);
    // Only the output file is left (the temporary file was renamed).
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    // The first vertex is the patch at the domain centre.
    let patch = load_gbp(CUBIC5).unwrap();
    let v0: Vec<f64> = text.lines().next().unwrap()[2..]
        .split(' ')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_near!(
        DVec3::new(v0[0], v0[1], v0[2]),
        patch.eval(DVec2::ZERO, WeightForm::Squared),
        1e-15
    );
}

#[test]
fn tessellate_gbp_failure_writes_nothing() {
    let dir = scratch("tess-fail");
    let obj = dir.join("keep.obj");
    std::fs::write(&obj, "previous").unwrap();
    let bad = dir.join("nan.gbp");
    std::fs::write(&bad, "3 2\n0 0 nan\n").unwrap();
    let out = run(
        &[
            "tessellate-gbp",
            bad.to_str().unwrap(),
            "-o",
            obj.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("line 2") && err.contains("not finite"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&obj).unwrap(), "previous");
    // Bad resolution, and an output directory that does not exist.
    let out = run(
        &[
            "tessellate-gbp",
            CUBIC5,
            "-o",
            obj.to_str().unwrap(),
            "-r",
            "0",
        ],
        "",
    );
    assert_eq!(out.status.code(), Some(1));
    let missing = dir.join("no/such/dir/x.obj");
    let out = run(
        &["tessellate-gbp", CUBIC5, "-o", missing.to_str().unwrap()],
        "",
    );
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(String::from_utf8(out.stderr).unwrap().lines().count(), 1);
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
    // Usage errors (missing -o) come from clap with status 2.
    let out = run(&["tessellate-gbp", CUBIC5], "");
    assert_eq!(out.status.code(), Some(2));
}

/// Points on every side of the n-sided domain (corners excluded).
fn boundary_uvs(n: usize) -> Vec<DVec2> {
    let domain = gbsurf::gb::Domain::regular(n).unwrap();
    let mut uvs = Vec::new();
    for i in 0..n {
        let (a, b) = (domain.vertex((i + n - 1) % n), domain.vertex(i));
        for k in 1..8 {
            uvs.push(a.lerp(b, k as f64 / 8.0));
        }
    }
    uvs
}

#[test]
fn gbp_elevate_keeps_boundary_and_tangent_planes() {
    let dir = scratch("elevate");
    for (input, to) in [(CUBIC5, 4), (CUBIC5, 6), (QUINTIC3, 5), (QUINTIC3, 8)] {
        let out = dir.join(format!("e{to}.gbp"));
        let o = run(&["gbp-elevate", input, "--to", &to.to_string(), "-o", out.to_str().unwrap()], "");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let (a, b) = (load_gbp(input).unwrap(), load_gbp(&out).unwrap());
        assert_eq!(b.degree(), to);
        assert_eq!(b.n(), a.n());
        for uv in boundary_uvs(a.n()) {
            assert_near!(a.eval(uv, WeightForm::Squared), b.eval(uv, WeightForm::Squared), 1e-12);
            let (na, nb) = (a.normal(uv, WeightForm::Squared).unwrap(), b.normal(uv, WeightForm::Squared).unwrap());
            // |na − nb|, not angle_between: acos cannot resolve angles below ~1.5e-8 rad.
            assert!((na - nb).length() < 1e-12, "{input} -> {to} at {uv}: normals differ by {}", (na - nb).length());
        }
    }
}

#[test]
fn gbp_elevate_refuses_a_lower_degree_and_writes_nothing() {
    let dir = scratch("elevate-bad");
    let out = dir.join("low.gbp");
    let o = run(&["gbp-elevate", QUINTIC3, "--to", "4", "-o", out.to_str().unwrap()], "");
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--to 4 is below the patch degree 5"), "{err}");
    assert!(!out.exists());
    let o = run(&["gbp-elevate", CUBIC5, "--to", "1000", "-o", out.to_str().unwrap()], "");
    assert!(String::from_utf8_lossy(&o.stderr).contains("--to 1000 is above 40"), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!out.exists());
}

/// The dual patches of the cube are connected nets (so they have .gbp files).
const CUBE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/models/cube.obj");

#[test]
fn convert_degree_elevates_the_exact_description() {
    let dir = scratch("degree");
    let (json, mesh) = (dir.join("p.json"), dir.join("s.ply"));
    let args = ["convert", CUBE, "--quiet", "-o", mesh.to_str().unwrap(), "--patches", json.to_str().unwrap()];
    let o = run(&[&args[..], &["--degree", "6"]].concat(), "");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let patches = doc["patches"].as_array().unwrap();
    assert!(!patches.is_empty());
    for p in patches {
        assert!(p["degree"].as_array().unwrap().iter().all(|d| d == 6), "{}", p["degree"]);
        // The cube's patches are connected nets: each keeps its .gbp file, now of degree 6.
        let name = p["gbp"].as_str().expect("a .gbp file per patch");
        assert_eq!(load_gbp(dir.join(name)).unwrap().degree(), 6);
    }
    assert!(doc["curves"].as_array().unwrap().iter().all(|c| c.as_array().unwrap().len() == 7));
    // Ribbon-only patches (topology structure) have no common degree: a named error, no output.
    let (json2, mesh2) = (dir.join("t.json"), dir.join("t.ply"));
    let o = run(
        &["convert", CUBE, "--quiet", "--method", "topology", "--degree", "6", "-o", mesh2.to_str().unwrap(), "--patches", json2.to_str().unwrap()],
        "",
    );
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("patch 0 is a ribbon-only (CGB) patch"), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!json2.exists() && !mesh2.exists());
    // --degree only applies to the exact description.
    let o = run(&["convert", CUBE, "--quiet", "--degree", "6", "-o", mesh2.to_str().unwrap()], "");
    assert_eq!(o.status.code(), Some(2));
}

/// `.gbp` inputs are read like meshes: a directory or FIFO is refused (never read without end),
/// and a tessellation whose sample count exceeds the memory limit is refused before anything is
/// allocated, with the figures; nothing is written.
#[test]
fn gbp_inputs_and_huge_tessellations_are_refused() {
    let dir = scratch("gbp-hostile");
    let obj = dir.join("out.obj");
    let out = run(&["tessellate-gbp", dir.to_str().unwrap(), "-o", obj.to_str().unwrap()], "");
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8(out.stderr).unwrap().contains("is not a regular file"));
    #[cfg(unix)]
    {
        let fifo = dir.join("f.gbp");
        let made = Command::new("mkfifo").arg(&fifo).status().map(|s| s.success()).unwrap_or(false);
        if made {
            for args in [vec!["tessellate-gbp", fifo.to_str().unwrap(), "-o", obj.to_str().unwrap()], vec!["eval-gbp", fifo.to_str().unwrap()]] {
                let out = run(&args, "");
                assert_eq!(out.status.code(), Some(1), "{args:?}");
                assert!(String::from_utf8(out.stderr).unwrap().contains("is not a regular file"), "{args:?}");
            }
            std::fs::remove_file(&fifo).unwrap();
        }
    }
    // The documented maximum of sides at the largest resolution: about 131 GB.
    let mut text = String::from("1024 3\n0 0 0.5\n");
    for k in 0..2 {
        for i in 0..1024 {
            for j in k..3 - k {
                let a = std::f64::consts::TAU * ((i as f64 - 1.0) + j as f64 / 3.0) / 1024.0;
                let r = if k == 0 { 1.0 } else { 0.8 };
                text += &format!("{} {} {}\n", r * a.cos(), r * a.sin(), 0.2 * k as f64);
            }
        }
    }
    let big = dir.join("big.gbp");
    std::fs::write(&big, text).unwrap();
    let out = run(&["tessellate-gbp", big.to_str().unwrap(), "-o", obj.to_str().unwrap(), "-r", "1024"], "");
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("1024 sides at resolution 1024 make 537395201 samples") && err.contains("above the limit of 2048 MiB"), "{err}");
    assert!(!obj.exists());
}
