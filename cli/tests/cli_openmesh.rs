//! The CLI with the `openmesh` feature: `.om` files go through OpenMesh, and a model written by
//! OpenMesh as OFF/PLY/OM converts to the same surface as its OBJ twin.
#![cfg(feature = "openmesh")]

use gbsurf::mesh::read_polymesh;
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_gbsurf");

fn model(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/models").join(name)
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gbsurf-cli-om-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn convert(input: &Path, output: &Path, method: &str) {
    let out = Command::new(BIN)
        .args(["convert", "--quiet", "--resolution", "4", "--method", method, "-o"])
        .arg(output)
        .arg(input)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// Vertex positions of a converted surface, read back with OpenMesh (any format it reads).
fn surface_points(path: &Path) -> Vec<gbsurf::DVec3> {
    gbsurf_openmesh::read_mesh(path).unwrap().positions
}

#[test]
fn om_and_off_twins_convert_like_the_obj() {
    for name in ["cube", "house", "dodecahedron"] {
        let dir = scratch(name);
        let obj = model(&format!("{name}.obj"));
        let (mesh, _) = read_polymesh(&obj).unwrap();
        let om = dir.join("in.om");
        let off = dir.join("in.off");
        gbsurf_openmesh::write_mesh_binary(&mesh, &om).unwrap();
        gbsurf_openmesh::write_mesh(&mesh, &off).unwrap();
        for method in ["dual", "topology"] {
            let reference = dir.join(format!("ref-{method}.om"));
            convert(&obj, &reference, method);
            let want = surface_points(&reference);
            assert!(!want.is_empty());
            for (input, tol) in [(&om, 0.0_f64), (&off, 1e-6)] {
                let out = dir.join(format!("out-{method}.om"));
                convert(input, &out, method);
                let got = surface_points(&out);
                assert_eq!(got.len(), want.len(), "{name} {method} {}", input.display());
                let worst = got.iter().zip(&want).map(|(a, b)| (*a - *b).length()).fold(0.0, f64::max);
                // OM keeps doubles (exact); OFF goes through OpenMesh's single-precision writer.
                assert!(worst <= tol, "{name} {method}: {worst:e}");
            }
        }
    }
}

#[test]
fn unreadable_om_input_is_one_error_line_and_writes_nothing() {
    let dir = scratch("bad");
    let bad = dir.join("bad.om");
    std::fs::write(&bad, b"not an OM file").unwrap();
    let out_path = dir.join("out.om");
    let out = Command::new(BIN).args(["convert", "--quiet", "-o"]).arg(&out_path).arg(&bad).output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("bad.om"), "{err}");
    assert!(!out_path.exists());
}
