//! `gbsurf offset`: the offset of a GB surface through PN pieces, written through the atomic
//! writer after the output path checks; typed one-line errors for bad distances and grids.

mod common;
use common::{fails_in, run_in};

use serde_json::Value;
use std::path::PathBuf;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/models");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gbsurf-offset-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn offset_writes_mesh_report_and_export() {
    let dir = scratch("ok");
    let torus = format!("{MODELS}/torus.obj");
    let out = run_in(
        &dir,
        &["offset", &torus, "-o", "off.obj", "--distance", "0.05", "--resolution", "4", "--report", "r.json", "--export", "x.json", "--shell"],
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let r: Value = serde_json::from_slice(&std::fs::read(dir.join("r.json")).unwrap()).unwrap();
    assert_eq!(r["closed"], Value::Bool(true));
    assert_eq!(r["shell"], Value::Bool(true));
    assert!(r["max_gap_pn"].as_f64().unwrap() <= 1e-12);
    assert!(r["max_normal_residual"].as_f64().unwrap() <= 1e-9);
    let pieces = r["pieces"].as_u64().unwrap();
    let singular = r["singular_pieces"].as_u64().unwrap();
    let x: Value = serde_json::from_slice(&std::fs::read(dir.join("x.json")).unwrap()).unwrap();
    let patches = x["patches"].as_array().unwrap();
    assert_eq!(patches.len() as u64, (pieces - singular) * 9);
    assert_eq!(patches[0]["degree"], serde_json::json!([11, 11]));
    // The torus has singular pieces (its parabolic lines): the export names its holes, each a
    // piece without patches, and says so on stderr.
    assert!(singular > 0);
    let holes = x["singular_pieces"].as_array().unwrap();
    assert_eq!(holes.len() as u64, singular);
    assert_eq!(x["complete"], Value::Bool(false));
    assert_eq!(x["pieces"].as_u64(), Some(pieces));
    let key = |v: &Value| (v["patch"].as_u64().unwrap(), v["piece"].as_u64().unwrap());
    for h in holes {
        assert!(!h["reason"].as_str().unwrap().is_empty());
        assert!(patches.iter().all(|p| key(&p["piece"]) != key(h)), "{h}");
    }
    let covered: std::collections::HashSet<_> = patches.iter().map(|p| key(&p["piece"])).chain(holes.iter().map(key)).collect();
    assert_eq!(covered.len() as u64, pieces);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains(&format!("{singular} of {pieces} pieces are singular")), "{stderr}");
    let mesh = gbsurf::api::read_mesh(dir.join("off.obj")).unwrap();
    assert_eq!(mesh.faces.len() as u64, r["triangles"].as_u64().unwrap());
}

#[test]
fn bad_offset_arguments_fail_with_one_line() {
    let dir = scratch("bad");
    let cube = format!("{MODELS}/cube.obj");
    fails_in(&dir, &["offset", &cube, "-o", "a.obj", "--distance", "0"], &["--distance 0"]);
    fails_in(&dir, &["offset", &cube, "-o", "a.obj", "--distance", "nan"], &["--distance NaN"]);
    fails_in(&dir, &["offset", &cube, "-o", "a.obj", "--distance", "0.1", "--grid", "1"], &["--grid 1"]);
    fails_in(&dir, &["offset", &cube, "-o", "a.obj", "--distance", "0.1", "--grid", "65"], &["--grid 65"]);
    fails_in(&dir, &["offset", &cube, "-o", "a.txt", "--distance", "0.1"], &["a.txt"]);
    fails_in(&dir, &["offset", &cube, "-o", &cube, "--distance", "0.1"], &["input"]);
    fails_in(&dir, &["offset", &cube, "-o", "a.obj", "--distance", "0.1", "--method", "catmull-clark"], &["method"]);
    assert!(!dir.join("a.obj").exists());
}
