//! The exact-offset commands `ph5`, `ph-spline` and `pn-grid`: their JSON carries the library's
//! numbers, and every bad input class exits with status 1 and a one-line message naming the
//! argument or the input line.

mod common;
use common::{fails_in, run_in};

use gbsurf::offset::ph::{OpenEnds, PlanarPhQuintic, PlanarPhSpline};
use gbsurf::offset::pn::{PnGrid, PnOptions, PnSurface};
use gbsurf::{DVec2, DVec3};
use proptest::prelude::*;
use serde_json::Value;
use std::path::{Path, PathBuf};


fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gbsurf-offsets-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}


fn ok_json(dir: &Path, args: &[&str]) -> Value {
    let out = run_in(dir, args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

fn read_json(path: PathBuf) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// A JSON number equal to `want` up to the parser's last bit (serde_json reads decimals to within
/// an ulp); `null` stands for an infinite value.
fn same(v: &Value, want: f64, what: &str) {
    if want.is_infinite() {
        assert!(v.is_null(), "{what}: {v} should be null (infinite)");
        return;
    }
    let got = v.as_f64().unwrap_or_else(|| panic!("{what}: {v} is not a number"));
    assert!((got - want).abs() <= 4.0 * f64::EPSILON * want.abs().max(f64::MIN_POSITIVE), "{what}: {got} != {want}");
}

fn same_list(v: &Value, want: &[f64], what: &str) {
    let a = v.as_array().unwrap_or_else(|| panic!("{what}: {v} is not an array"));
    assert_eq!(a.len(), want.len(), "{what}");
    for (k, (g, w)) in a.iter().zip(want).enumerate() {
        same(g, *w, &format!("{what}[{k}]"));
    }
}

fn same_points(v: &Value, want: &[DVec2], what: &str) {
    let a = v.as_array().unwrap();
    assert_eq!(a.len(), want.len(), "{what}");
    for (k, (g, w)) in a.iter().zip(want).enumerate() {
        same_list(g, &w.to_array(), &format!("{what}[{k}]"));
    }
}

/// The fields of one quintic, checked against the library.
fn check_quintic(v: &Value, c: &PlanarPhQuintic, what: &str) {
    same_points(&v["control_points"], &c.control_points(), &format!("{what}.control_points"));
    same(&v["arc_length"], c.arc_length(), &format!("{what}.arc_length"));
    same(&v["bending_energy"], c.bending_energy(), &format!("{what}.bending_energy"));
    same(&v["abs_rotation_index"], c.rotation_index(), &format!("{what}.abs_rotation_index"));
    same(&v["min_curvature_radius"], c.min_radius_of_curvature().unwrap(), &format!("{what}.min_curvature_radius"));
}

fn check_offset(v: &Value, c: &PlanarPhQuintic, d: f64, what: &str) {
    let o = c.offset(d).unwrap();
    same(&v["distance"], d, what);
    assert_eq!(v["degree"], 9, "{what}");
    same_points(&v["control_points"], &o.points, &format!("{what}.control_points"));
    same_list(&v["weights"], &o.weights, &format!("{what}.weights"));
    same_list(&v["cusps"], &o.cusps, &format!("{what}.cusps"));
}

const P0: DVec2 = DVec2::new(0.0, 0.0);
const D0: DVec2 = DVec2::new(1.0, 2.0);
const P1: DVec2 = DVec2::new(2.0, 0.0);
const D1: DVec2 = DVec2::new(1.0, -2.0);

#[test]
fn ph5_prints_all_four_solutions_with_the_library_numbers() {
    let dir = scratch("ph5");
    let v = ok_json(&dir, &["ph5", "--p0", "0,0", "--d0", "1,2", "--p1", "2,0", "--d1", "1,-2"]);
    let sols = PlanarPhQuintic::hermite(P0, D0, P1, D1).unwrap();
    assert_eq!(v["chosen"], sols.best);
    check_quintic(&v, &sols.best().curve, "top");
    let all = v["solutions"].as_array().unwrap();
    assert_eq!(all.len(), 4);
    for (k, (s, want)) in all.iter().zip(&sols.solutions).enumerate() {
        check_quintic(s, &want.curve, &format!("solutions[{k}]"));
        assert_eq!(s["eta0"], want.eta0);
        assert_eq!(s["eta2"], want.eta2);
        assert!(s.get("offset").is_none());
    }
    assert!(v.get("offset").is_none(), "no offset without --offset");
}

#[test]
fn ph5_offset_gives_rational_points_weights_and_cusps() {
    let dir = scratch("ph5-offset");
    let sols = PlanarPhQuintic::hermite(P0, D0, P1, D1).unwrap();
    let best = sols.best().curve;
    // The arc turns right (κ < 0): an offset to the right at a distance between the curvature
    // radii at t = 0 and t = 1/2 meets 1 + dκ = 0 in between.
    let radius = |t: f64| 1.0 / best.curvature(t).abs();
    assert!(best.curvature(0.5) < 0.0 && (radius(0.0) - radius(0.5)).abs() > 0.1);
    let d = 0.5 * (radius(0.0) + radius(0.5));
    let ds = d.to_string();
    let v = ok_json(&dir, &["ph5", "--p0", "0,0", "--d0", "1,2", "--p1", "2,0", "--d1", "1,-2", "--offset", &ds]);
    check_offset(&v["offset"], &best, d, "offset");
    let cusps = v["offset"]["cusps"].as_array().unwrap();
    assert!(!cusps.is_empty(), "cusps expected at d = {d}: {}", v["offset"]);
    for t in cusps {
        let t = t.as_f64().unwrap();
        assert!((1.0 + d * best.curvature(t)).abs() < 1e-9, "1 + dκ({t}) ≠ 0");
    }
    for (k, s) in sols.solutions.iter().enumerate() {
        check_offset(&v["solutions"][k]["offset"], &s.curve, d, &format!("solutions[{k}].offset"));
    }
    // A small offset has no cusp, and the list is there (empty), not left out.
    let v = ok_json(&dir, &["ph5", "--p0", "0,0", "--d0", "1,2", "--p1", "2,0", "--d1", "1,-2", "--offset", "-0.01"]);
    assert_eq!(v["offset"]["cusps"], Value::Array(vec![]));
}

#[test]
fn ph5_bad_arguments_exit_1_naming_them() {
    let dir = scratch("ph5-bad");
    let base = |p0: &str, d0: &str, p1: &str, d1: &str| -> Vec<String> {
        ["ph5", "--p0", p0, "--d0", d0, "--p1", p1, "--d1", d1].iter().map(|s| s.to_string()).collect()
    };
    let check = |args: Vec<String>, needles: &[&str]| {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        fails_in(&dir, &a, needles);
    };
    check(base("0,0", "0,0", "2,0", "1,0"), &["derivative `d0` is zero"]);
    check(base("0,0", "1,0", "2,0", "0,0"), &["derivative `d1` is zero"]);
    check(base("1,1", "1,0", "1,1", "1,0"), &["`p0, p1`", "coincide"]);
    check(base("NaN,0", "1,0", "2,0", "1,0"), &["`p0` is not finite"]);
    check(base("0,0", "1,inf", "2,0", "1,0"), &["`d0` is not finite"]);
    let mut a = base("0,0", "1,0", "2,0", "1,0");
    a.extend(["--offset".to_string(), "0".to_string()]);
    check(a, &["--offset 0", "offset distance `d` is zero"]);
    let mut a = base("0,0", "1,0", "2,0", "1,0");
    a.extend(["--offset".to_string(), "nan".to_string()]);
    check(a, &["--offset NaN", "`d` is not finite"]);
}

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap();
}

#[test]
fn ph_spline_open_closed_and_hermite_match_the_library() {
    let dir = scratch("spline");
    write(&dir, "p.txt", "# four points\n0 0\n1 1  # a comment\n\n2 0\n3 1.5\n");
    write(&dir, "t.txt", "0 0 1 0\n1 1 1 0.5\n2 0 1 -1\n");
    let pts = [DVec2::new(0.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(2.0, 0.0), DVec2::new(3.0, 1.5)];
    let tan = [DVec2::new(1.0, 0.0), DVec2::new(1.0, 0.5), DVec2::new(1.0, -1.0)];
    let cases: [(&[&str], &str, PlanarPhSpline); 3] = [
        (&["ph-spline", "p.txt", "-o", "open.json", "--offset", "0.05"], "open.json", PlanarPhSpline::c2_open(&pts, OpenEnds::CubicEndSpans).unwrap()),
        (&["ph-spline", "p.txt", "-o", "closed.json", "--closed", "--offset", "0.05"], "closed.json", PlanarPhSpline::c2_closed(&pts).unwrap()),
        (&["ph-spline", "t.txt", "-o", "herm.json", "--tangents", "--offset", "0.05"], "herm.json", PlanarPhSpline::hermite(&pts[..3], &tan).unwrap()),
    ];
    for (args, out, want) in cases {
        let o = run_in(&dir, args);
        assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
        let v = read_json(dir.join(out));
        assert_eq!(v["closed"], want.closed, "{out}");
        assert_eq!(v["newton_iterations"], want.iterations, "{out}");
        same(&v["arc_length"], want.arc_length(), out);
        let segs = v["segments"].as_array().unwrap();
        assert_eq!(segs.len(), want.segments.len(), "{out}");
        for (k, (s, c)) in segs.iter().zip(&want.segments).enumerate() {
            check_quintic(s, c, &format!("{out} segment {k}"));
            check_offset(&s["offset"], c, 0.05, &format!("{out} segment {k} offset"));
        }
    }
    assert_eq!(read_json(dir.join("open.json"))["kind"], "c2_open");
    assert_eq!(read_json(dir.join("closed.json"))["kind"], "c2_closed");
    assert_eq!(read_json(dir.join("herm.json"))["kind"], "hermite");
    assert_eq!(read_json(dir.join("closed.json"))["segments"].as_array().unwrap().len(), 4);
}

#[test]
fn ph_spline_bad_input_names_the_line() {
    let dir = scratch("spline-bad");
    write(&dir, "dup.txt", "0 0\n# x\n0 0\n1 1\n");
    write(&dir, "nan.txt", "0 0\n1 NaN\n2 0\n");
    write(&dir, "word.txt", "0 0\n1 one\n2 0\n");
    write(&dir, "short.txt", "0 0\n1\n2 0\n");
    write(&dir, "zero.txt", "0 0 1 0\n1 1 0 0\n2 0 1 0\n");
    write(&dir, "two.txt", "0 0\n1 1\n");
    write(&dir, "ok.txt", "0 0\n1 1\n2 0\n");
    fails_in(&dir, &["ph-spline", "dup.txt", "-o", "o.json"], &["dup.txt lines 1 and 3", "coincide"]);
    fails_in(&dir, &["ph-spline", "nan.txt", "-o", "o.json"], &["nan.txt line 2", "`NaN` is not finite"]);
    fails_in(&dir, &["ph-spline", "word.txt", "-o", "o.json"], &["word.txt line 2", "`one` is not a number"]);
    fails_in(&dir, &["ph-spline", "short.txt", "-o", "o.json"], &["short.txt line 2", "expected 2 numbers"]);
    fails_in(&dir, &["ph-spline", "ok.txt", "-o", "o.json", "--tangents"], &["ok.txt line 1", "expected 4 numbers"]);
    fails_in(&dir, &["ph-spline", "zero.txt", "-o", "o.json", "--tangents"], &["zero.txt line 2", "derivative `tangents` (index 1) is zero"]);
    fails_in(&dir, &["ph-spline", "two.txt", "-o", "o.json"], &["two.txt", "has 2 points; at least 3"]);
    fails_in(&dir, &["ph-spline", "ok.txt", "-o", "o.json", "--offset", "0"], &["--offset 0", "is zero"]);
    fails_in(&dir, &["ph-spline", "ok.txt", "-o", "./ok.txt"], &["-o ./ok.txt is the same file as input ok.txt"]);
    fails_in(&dir, &["ph-spline", "missing.txt", "-o", "o.json"], &["missing.txt"]);
    // Nothing was written by any failure, and the input is intact.
    assert!(!dir.join("o.json").exists());
    assert_eq!(std::fs::read_to_string(dir.join("ok.txt")).unwrap(), "0 0\n1 1\n2 0\n");
}

/// A cap of the unit sphere sampled on rows × cols points, normals = points.
fn cap(rows: usize, cols: usize) -> Vec<Vec<DVec3>> {
    (0..rows)
        .map(|i| (0..cols).map(|j| DVec3::new(0.3 * i as f64 - 0.45, 0.25 * j as f64 - 0.25, -1.0).normalize()).collect())
        .collect()
}

fn grid_json(points: &[Vec<DVec3>], normals: &[Vec<DVec3>]) -> String {
    let g = |v: &[Vec<DVec3>]| -> Vec<Vec<[f64; 3]>> { v.iter().map(|r| r.iter().map(|p| p.to_array()).collect()).collect() };
    serde_json::json!({ "points": g(points), "normals": g(normals) }).to_string()
}

#[test]
fn pn_grid_writes_the_rational_patches_of_the_library() {
    let dir = scratch("pn");
    let pts = cap(4, 3);
    write(&dir, "g.json", &grid_json(&pts, &pts));
    let o = run_in(&dir, &["pn-grid", "g.json", "-o", "out.json", "--offset", "0.5"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v = read_json(dir.join("out.json"));
    // The library gets the grid as the command reads it (decimal JSON may round by an ulp).
    let back = read_json(dir.join("g.json"));
    let grid = |key: &str| -> Vec<Vec<DVec3>> {
        back[key].as_array().unwrap().iter().map(|r| r.as_array().unwrap().iter().map(|p| DVec3::from_array(serde_json::from_value(p.clone()).unwrap())).collect()).collect()
    };
    let s = PnSurface::interpolate(&PnGrid::new(&grid("points"), &grid("normals")).unwrap(), &PnOptions::default()).unwrap();
    assert_eq!((v["rows"].as_u64(), v["cols"].as_u64()), (Some(4), Some(3)));
    assert_eq!((v["patch_rows"].as_u64(), v["patch_cols"].as_u64()), (Some(3), Some(2)));
    let patches = v["patches"].as_array().unwrap();
    assert_eq!(patches.len(), 6);
    for p in patches {
        let (i, j) = (p["patch"][0].as_u64().unwrap() as usize, p["patch"][1].as_u64().unwrap() as usize);
        for (key, r) in [("surface", s.rational(i, j).unwrap()), ("offset", s.rational_offset(i, j, 0.5).unwrap())] {
            let q = if key == "surface" { p } else { &p["offset"] };
            let (du, dv) = r.degree();
            assert_eq!(q["degree"], serde_json::json!([du, dv]), "{key}");
            for (a, row) in r.homogeneous.points().iter().enumerate() {
                for (b, h) in row.iter().enumerate() {
                    same_list(&q["homogeneous"][a][b], &h.to_array(), &format!("patch [{i}][{j}] {key} [{a}][{b}]"));
                    same(&q["weights"][a][b], h.w, key);
                }
            }
        }
    }
}

#[test]
fn pn_grid_bad_input_exits_1() {
    let dir = scratch("pn-bad");
    let pts = cap(3, 3);
    let one = vec![pts[0].clone()];
    write(&dir, "one.json", &grid_json(&one, &one));
    let mut zero = pts.clone();
    zero[1][2] = DVec3::ZERO;
    write(&dir, "zero.json", &grid_json(&pts, &zero));
    write(&dir, "ok.json", &grid_json(&pts, &pts));
    write(&dir, "inf.json", r#"{"points": [[[1e999, 0, 0]]], "normals": []}"#);
    write(&dir, "nan.json", r#"{"points": [[[NaN, 0, 0]]], "normals": []}"#);
    write(&dir, "ragged.json", &grid_json(&pts, &pts[..2]));
    fails_in(&dir, &["pn-grid", "one.json", "-o", "o.json"], &["one.json", "the grid is 1 × 3"]);
    fails_in(&dir, &["pn-grid", "zero.json", "-o", "o.json"], &["zero.json", "normal [1][2] has length zero"]);
    fails_in(&dir, &["pn-grid", "inf.json", "-o", "o.json"], &["inf.json", "line 1 column"]);
    fails_in(&dir, &["pn-grid", "nan.json", "-o", "o.json"], &["nan.json", "line 1 column"]);
    fails_in(&dir, &["pn-grid", "ragged.json", "-o", "o.json"], &["ragged.json", "normals has 2 rows, expected 3"]);
    fails_in(&dir, &["pn-grid", "ok.json", "-o", "o.json", "--offset", "0"], &["--offset 0", "offset distance 0"]);
    fails_in(&dir, &["pn-grid", "ok.json", "-o", "ok.json"], &["-o ok.json is the same file as input ok.json"]);
    assert!(!dir.join("o.json").exists());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// For any regular Hermite data the command reports the library's arc length and the offset
    /// at the reported parameters reproduces the library's offset points.
    #[test]
    fn ph5_matches_the_library(
        p1 in (0.5f64..4.0, -2.0f64..2.0),
        d0 in (-3.0f64..3.0, 0.1f64..3.0),
        d1 in (-3.0f64..3.0, -3.0f64..-0.1),
    ) {
        let (p1, d0, d1) = (DVec2::new(p1.0, p1.1), DVec2::new(d0.0, d0.1), DVec2::new(d1.0, d1.1));
        let arg = |v: DVec2| format!("{:e},{:e}", v.x, v.y);
        let dir = std::env::temp_dir();
        let v = ok_json(&dir, &["ph5", "--p0", "0,0", "--d0", &arg(d0), "--p1", &arg(p1), "--d1", &arg(d1)]);
        let sols = PlanarPhQuintic::hermite(DVec2::ZERO, d0, p1, d1).unwrap();
        prop_assert_eq!(v["chosen"].as_u64(), Some(sols.best as u64));
        for (k, s) in sols.solutions.iter().enumerate() {
            same(&v["solutions"][k]["arc_length"], s.arc_length, "arc_length");
            same_points(&v["solutions"][k]["control_points"], &s.curve.control_points(), "control_points");
        }
    }
}
