//! The `gbsurf convert` command line: outputs, report keys, one-line errors for every bad model,
//! nothing written on failure.

use std::path::{Path, PathBuf};
use std::process::Command;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/models");

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gbsurf-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn gbsurf(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_gbsurf")).args(args).output().unwrap();
    (out.status.success(), String::from_utf8_lossy(&out.stderr).into_owned())
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

/// Runs a failing conversion writing every kind of output; checks one error line containing
/// `needle` and an empty output folder.
fn fails(input: &str, extra: &[&str], needle: &str) {
    let dir = tmpdir(&format!("fail-{}", input.replace('/', "_")));
    let d = |f: &str| dir.join(f).to_string_lossy().into_owned();
    let (out, curves, report, patches) = (d("out.ply"), d("curves.obj"), d("report.json"), d("patches.json"));
    let mut args = vec!["convert", input, "-o", &out, "--curves", &curves, "--report", &report, "--patches", &patches, "--quiet"];
    args.extend_from_slice(extra);
    let (ok, err) = gbsurf(&args);
    assert!(!ok, "{input}: succeeded");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{input}: {err}");
    assert!(lines[0].starts_with("gbsurf: error: "), "{err}");
    assert!(lines[0].contains(needle), "{input}: {err} lacks {needle:?}");
    assert!(files_in(&dir).is_empty(), "{input}: wrote {:?}", files_in(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

fn bad(name: &str) -> String {
    format!("{MODELS}/bad/{name}")
}

#[test]
fn bad_bowtie_vertex() {
    fails(&bad("bowtie_vertex.obj"), &[], "vertex 1 (line 2) is non-manifold");
}
#[test]
fn bad_duplicate_face() {
    fails(&bad("duplicate_face.obj"), &[], "face 6 (line 16) duplicates face 0");
}
#[test]
fn bad_empty() {
    fails(&bad("empty.obj"), &[], "empty mesh");
}
#[test]
fn bad_flipped_face() {
    fails(&bad("flipped_face.obj"), &[], "inconsistent orientation");
}
#[test]
fn bad_garbage() {
    fails(&bad("garbage.obj"), &[], "line 1");
}
#[test]
fn bad_huge_coordinates() {
    fails(&bad("huge_coordinates.obj"), &[], "vertex 1 (line 2): coordinate 0");
}
#[test]
fn bad_index_out_of_range() {
    fails(&bad("index_out_of_range.obj"), &[], "face 5 (line 15) corner 3: vertex index 42 out of range (1..=8)");
}
#[test]
fn bad_inf() {
    fails(&bad("inf.obj"), &[], "vertex 1 (line 2): coordinate 0 is inf");
}
#[test]
fn bad_nan() {
    fails(&bad("nan.obj"), &[], "vertex 1 (line 2): coordinate 0 is NaN");
}
#[test]
fn bad_nonmanifold_edge() {
    fails(&bad("nonmanifold_edge.obj"), &[], "edge (1, 2) is shared by 4 faces");
}
#[test]
fn bad_repeated_index() {
    fails(&bad("repeated_index.obj"), &[], "face 5 (line 15) names vertex 4 more than once");
}
#[test]
fn bad_zero_area() {
    fails(&bad("zero_area.obj"), &[], "face 6 (line 17) has zero area");
}
#[test]
fn bad_options_and_paths() {
    let cube = format!("{MODELS}/cube.obj");
    fails(&cube, &["--resolution", "0"], "--resolution 0");
    fails(&cube, &["--fullness", "1.5"], "--fullness 1.5");
    fails(&cube, &["--tile-depth", "1"], "--tile-depth 1");
    fails(&cube, &["--levels", "20"], "--levels 20");
    fails(&format!("{MODELS}/missing.obj"), &[], "missing.obj");
    // An output folder that does not exist: nothing anywhere.
    let (ok, err) = gbsurf(&["convert", &cube, "-o", "/nonexistent-dir-gbsurf/x.obj", "--quiet"]);
    assert!(!ok && err.lines().count() == 1, "{err}");
    // An unknown output extension is refused before any work.
    let dir = tmpdir("ext");
    let (ok, err) = gbsurf(&["convert", &cube, "-o", &dir.join("x.xyz").to_string_lossy(), "--quiet"]);
    assert!(!ok && err.contains("--output") && err.lines().count() == 1, "{err}");
    assert!(files_in(&dir).is_empty());
}

fn report_of(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

const KEYS: [&str; 11] = [
    "method", "patches", "sides_histogram", "vertices", "triangles", "closed", "boundary_edges", "max_g1_deg", "mean_g1_deg",
    "max_boundary_gap", "seconds",
];

#[test]
fn subdivision_methods_write_mesh_and_report() {
    let dir = tmpdir("subdiv");
    for (method, ext) in [("catmull-clark", "ply"), ("doo-sabin", "stl")] {
        let out = dir.join(format!("{method}.{ext}"));
        let rep = dir.join(format!("{method}.json"));
        let (ok, err) = gbsurf(&[
            "convert",
            &format!("{MODELS}/house.obj"),
            "-o",
            &out.to_string_lossy(),
            "--method",
            method,
            "--levels",
            "2",
            "--report",
            &rep.to_string_lossy(),
            "--quiet",
        ]);
        assert!(ok, "{method}: {err}");
        assert!(err.is_empty(), "--quiet printed {err}");
        let r = report_of(&rep);
        for k in KEYS {
            assert!(r.get(k).is_some(), "{method}: key {k} missing");
        }
        assert_eq!(r["method"], method);
        assert_eq!(r["closed"], true);
        assert_eq!(r["boundary_edges"], 0);
        assert_eq!(r["max_g1_deg"], 0.0);
        // The written mesh reads back closed with the reported counts.
        let m = gbsurf::mesh::read_mesh(&out).unwrap();
        assert!(m.is_closed());
        if ext == "ply" {
            assert_eq!(m.n_vertices() as u64, r["vertices"].as_u64().unwrap());
        }
        assert_eq!(m.n_faces() as u64, r["triangles"].as_u64().unwrap());
    }
    // Curves of a subdivision surface do not exist: a clear error, nothing written.
    fails(&format!("{MODELS}/cube.obj"), &["--method", "catmull-clark"], "needs a patch method");
}

#[test]
fn dual_and_topology_write_all_outputs() {
    let dir = tmpdir("patch");
    for method in ["dual", "topology"] {
        let p = |f: &str| dir.join(format!("{method}-{f}")).to_string_lossy().into_owned();
        let (ok, err) = gbsurf(&[
            "convert",
            &format!("{MODELS}/l_prism.obj"),
            "-o",
            &p("surface.ply"),
            "--method",
            method,
            "--resolution",
            "4",
            "--curves",
            &p("curves.obj"),
            "--nets",
            &p("nets.obj"),
            "--patches",
            &p("patches.json"),
            "--report",
            &p("report.json"),
        ]);
        assert!(ok, "{method}: {err}");
        // Not quiet: one summary line on stderr.
        assert!(err.contains(&format!("{method}: ")), "{err}");
        let r = report_of(Path::new(&p("report.json")));
        for k in KEYS {
            assert!(r.get(k).is_some(), "{method}: key {k} missing");
        }
        assert_eq!(r["closed"], true, "{method}");
        assert!(r["max_boundary_gap"].as_f64().unwrap() <= 1e-12, "{method}: {}", r["max_boundary_gap"]);
        assert!(r["max_g1_deg"].as_f64().unwrap() <= 1e-4, "{method}: {}", r["max_g1_deg"]);
        let hist: u64 = r["sides_histogram"].as_object().unwrap().values().map(|v| v.as_u64().unwrap()).sum();
        assert_eq!(hist, r["patches"].as_u64().unwrap());
        let m = gbsurf::mesh::read_mesh(p("surface.ply")).unwrap();
        assert!(m.is_closed());
        let j: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(p("patches.json")).unwrap()).unwrap();
        assert_eq!(j["patches"].as_array().unwrap().len() as u64, r["patches"].as_u64().unwrap());
        let expected = if method == "dual" { "gb" } else { "cgb" };
        assert_eq!(j["patches"][0]["type"], expected);
        let curves = std::fs::read_to_string(p("curves.obj")).unwrap();
        assert_eq!(curves.lines().filter(|l| l.starts_with("l ")).count(), j["curves"].as_array().unwrap().len());
        // The nets: quads between ribbon rows; a GB patch's centre is joined by spoke lines.
        let nets = std::fs::read_to_string(p("nets.obj")).unwrap();
        assert!(nets.lines().any(|l| l.starts_with("f ")), "{method}");
        assert_eq!(nets.lines().any(|l| l.starts_with("l ")), method == "dual", "{method}");
    }
    // No temporary files left behind.
    assert!(files_in(&dir).iter().all(|f| !f.starts_with('.')), "{:?}", files_in(&dir));
}

#[test]
fn isophotes_and_slices_of_the_torus() {
    let dir = tmpdir("iso-slices");
    let out = dir.join("t.ply");
    let iso = dir.join("iso.ply");
    let sl = dir.join("slices.obj");
    let torus = format!("{MODELS}/torus.obj");
    let (ok, err) = gbsurf(&[
        "convert", &torus, "-o", out.to_str().unwrap(), "--quiet", "--resolution", "4",
        "--isophotes", iso.to_str().unwrap(), "--light", "0,0,1", "--stripes", "8",
        "--slices", sl.to_str().unwrap(), "--slice-normal", "0,0,1", "--slice-count", "3",
    ]);
    assert!(ok, "{err}");
    let bytes = std::fs::read(&iso).unwrap();
    let header = String::from_utf8_lossy(&bytes[..bytes.windows(10).position(|w| w == b"end_header").unwrap()]).into_owned();
    assert!(header.contains("property float isophote") && header.contains("property float stripe"), "{header}");
    // Three horizontal planes through a torus around z: each cuts an inner and an outer loop.
    let text = std::fs::read_to_string(&sl).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("l ")).count(), 6, "{text}");
    assert_eq!(text.lines().filter(|l| l.starts_with("g slice_")).count(), 3);
    // The middle plane is z = 0 (the torus is symmetric): its points lie in the plane.
    let mut group = String::new();
    for line in text.lines() {
        if let Some(g) = line.strip_prefix("g ") {
            group = g.to_string();
        } else if let (Some(v), "slice_1") = (line.strip_prefix("v "), group.as_str()) {
            let z: f64 = v.split_whitespace().nth(2).unwrap().parse().unwrap();
            assert!(z.abs() < 1e-9, "{line}");
        }
    }
    // A zero light direction is a usage error; nothing is written.
    let bad_out = dir.join("bad.ply");
    let (ok, err) = gbsurf(&["convert", &torus, "-o", bad_out.to_str().unwrap(), "--quiet", "--light", "0,0,0"]);
    assert!(!ok && err.contains("non-zero"), "{err}");
    assert!(!bad_out.exists());
}

#[test]
fn output_too_large_is_one_error_line_naming_the_flag() {
    let torus = format!("{MODELS}/torus.obj");
    fails(
        &torus,
        &["--method", "catmull-clark", "--levels", "8"],
        "output too large: catmull-clark would make about 6291456 output vertices and need about 4288 MiB, above the limit of 2048 MiB; lower --resolution or --levels, or raise --max-memory-mb",
    );
    fails(&torus, &["--max-memory-mb", "1"], "above the limit of 1 MiB");
    fails(&torus, &["--max-memory-mb", "0"], "invalid --max-memory-mb 0: must be in 1..=1048576");
    let (ok, _) = gbsurf(&["convert", "--help"]);
    assert!(ok);
    let help = Command::new(env!("CARGO_BIN_EXE_gbsurf")).args(["convert", "--help"]).output().unwrap();
    assert!(String::from_utf8_lossy(&help.stdout).contains("[default: 2048]"));
}

/// The default layout is quads at resolution 2 (Subdivision Surface level 2): OBJ and PLY hold
/// the quads (a quad cage gets Catmull–Clark level 2's counts), STL their triangles; the
/// triangle layout at r = 8 (the old default) is one flag away.
#[test]
fn quad_layout_counts_in_obj_ply_and_stl() {
    let dir = tmpdir("quads");
    let cube = format!("{MODELS}/cube.obj");
    for ext in ["obj", "ply", "stl"] {
        let out = dir.join(format!("cube.{ext}"));
        let rep = dir.join(format!("cube-{ext}.json"));
        let (ok, err) = gbsurf(&["convert", &cube, "-o", &out.to_string_lossy(), "--method", "topology", "--report", &rep.to_string_lossy()]);
        assert!(ok, "{err}");
        // Not quiet: the summary names the quads.
        assert!(err.contains(", 96 quads,"), "{err}");
        let r = report_of(&rep);
        assert_eq!((r["layout"].as_str(), r["resolution"].as_u64()), (Some("quads"), Some(2)));
        // Catmull–Clark level 2 of the cube: 98 vertices, 96 quads.
        assert_eq!((r["vertices"].as_u64(), r["quads"].as_u64(), r["triangles"].as_u64()), (Some(98), Some(96), Some(192)));
        let m = gbsurf::mesh::read_mesh(&out).unwrap();
        assert!(m.is_closed());
        let want = if ext == "stl" { 192 } else { 96 };
        assert_eq!(m.n_faces(), want, "{ext}");
        if ext != "stl" {
            assert_eq!(m.n_vertices(), 98, "{ext}");
            assert!((0..m.n_faces()).all(|f| m.face_size(gbsurf::mesh::halfedge::FaceId::from(f)) == 4), "{ext}");
        }
    }
    let out = dir.join("tri.obj");
    let rep = dir.join("tri.json");
    let (ok, err) = gbsurf(&["convert", &cube, "-o", &out.to_string_lossy(), "--layout", "triangles", "--resolution", "8", "--quiet", "--report", &rep.to_string_lossy()]);
    assert!(ok, "{err}");
    let r = report_of(&rep);
    assert_eq!((r["layout"].as_str(), r["quads"].as_u64(), r["triangles"].as_u64()), (Some("triangles"), Some(0), Some(8 * 3 * 64)));
    let (ok, err) = gbsurf(&["convert", &cube, "-o", &out.to_string_lossy(), "--layout", "hexagons"]);
    assert!(!ok && err.contains("hexagons"), "{err}");
}

/// The command line converts with only the arrays its outputs need (`ConvertOptions::keep_surface`
/// and `quality_arrays` off unless an output reads them): its OBJ, PLY and STL files are byte for
/// byte those of a default conversion that keeps everything, written by the same writers.
#[test]
fn default_outputs_equal_those_of_a_full_conversion() {
    use gbsurf::export::{MeshFormat, WriteMesh};
    let dir = tmpdir("full-conversion");
    for model in ["cube.obj", "torus.obj", "grid_open.obj"] {
        let input = format!("{MODELS}/{model}");
        let cage = gbsurf::read_mesh(&input).unwrap();
        let full = gbsurf::api::convert(&cage, &gbsurf::ConvertOptions::default(), None).unwrap();
        assert!(full.surface.is_some() && !full.mesh.mean_curvature.is_empty());
        for (ext, format) in [("obj", MeshFormat::Obj), ("ply", MeshFormat::Ply), ("stl", MeshFormat::Stl)] {
            let out = dir.join(format!("{model}.{ext}")).to_string_lossy().into_owned();
            let (ok, err) = gbsurf(&["convert", &input, "-o", &out, "--quiet"]);
            assert!(ok, "{model} {ext}: {err}");
            let mut expected = Vec::new();
            full.mesh.write_format(format, &mut expected).unwrap();
            assert!(std::fs::read(&out).unwrap() == expected, "{model} {ext}: the file differs from the full conversion's");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--middle fair` reaches the construction (a different surface from `--middle seed`, the
/// default); a value that is not a rule is a usage error naming the flag.
#[test]
fn middle_flag_selects_the_rule() {
    let dir = tmpdir("middle");
    let input = format!("{MODELS}/cube_nonplanar.obj");
    let out = |rule: &str| dir.join(format!("{rule}.obj")).to_string_lossy().into_owned();
    for rule in ["seed", "fair"] {
        let (ok, err) = gbsurf(&["convert", &input, "-o", &out(rule), "--middle", rule, "--quiet"]);
        assert!(ok, "{rule}: {err}");
    }
    let (ok, err) = gbsurf(&["convert", &input, "-o", &out("default"), "--quiet"]);
    assert!(ok, "{err}");
    let read = |rule: &str| std::fs::read(out(rule)).unwrap();
    assert!(read("seed") == read("default"), "the default is not the seed's rule");
    assert!(read("seed") != read("fair"), "--middle fair changed nothing");
    let (ok, err) = gbsurf(&["convert", &input, "-o", &out("bogus"), "--middle", "bogus"]);
    assert!(!ok && err.contains("--middle"), "{err}");
    assert!(!dir.join("bogus.obj").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
