//! OpenMesh bridge (feature `openmesh`): our Catmull–Clark against OpenMesh's `CatmullClarkT`,
//! the documented boundary difference, and file round trips through OpenMesh's writers/readers.
//! Run with `cargo test --features openmesh --test openmesh_bridge`.


use gbsurf::mesh::{PolyMesh, TriMesh};
use gbsurf_openmesh::{
    openmesh_catmull_clark, read_mesh, write_mesh, write_mesh_binary, write_tri_mesh, OpenMeshError,
};
use gbsurf::mesh::MeshError;
use gbsurf::subdiv::catmull_clark;
use gbsurf::{assert_near, DVec3};
use std::path::PathBuf;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/models");

const CLOSED_MODELS: [&str; 12] = [
    "cube.obj",
    "cube_extruded.obj",
    "cube_nonplanar.obj",
    "cube_corner_pulled.obj",
    "dodecahedron.obj",
    "house.obj",
    "l_prism.obj",
    "octahedron.obj",
    "prism3.obj",
    "pyramid.obj",
    "star_prism.obj",
    "torus.obj",
];

fn model(name: &str) -> String {
    format!("{MODELS}/{name}")
}

/// Independent minimal OBJ reader (`v`, `f a[/..] ...`), f64.
fn load(name: &str) -> PolyMesh {
    let text = std::fs::read_to_string(model(name)).unwrap();
    let mut m = PolyMesh::default();
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f64> = it.take(3).map(|s| s.parse().unwrap()).collect();
                m.positions.push(DVec3::new(c[0], c[1], c[2]));
            }
            Some("f") => m.faces.push(
                it.map(|s| s.split('/').next().unwrap().parse::<u32>().unwrap() - 1)
                    .collect(),
            ),
            _ => {}
        }
    }
    m
}

/// A fresh scratch directory for one test.
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gbsurf_om_{}_{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Maps each vertex of `a` to the vertex of `b` at the same position (within `tol`), requiring a
/// bijection whose matches are unambiguous (every other vertex of `b` is farther than 1e-6).
fn match_vertices(a: &PolyMesh, b: &PolyMesh, tol: f64) -> Vec<u32> {
    assert_eq!(a.positions.len(), b.positions.len(), "vertex counts differ");
    let mut used = vec![false; b.positions.len()];
    a.positions
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let mut d: Vec<(f64, usize)> = b
                .positions
                .iter()
                .enumerate()
                .map(|(j, &q)| ((p - q).length(), j))
                .collect();
            d.sort_by(|x, y| x.0.total_cmp(&y.0));
            assert!(
                d[0].0 <= tol,
                "vertex {i} at {p:?}: nearest is {:e} away",
                d[0].0
            );
            assert!(
                d.len() < 2 || d[1].0 > 1e-6,
                "vertex {i} at {p:?} matches ambiguously"
            );
            assert!(!used[d[0].1], "vertex {} matched twice", d[0].1);
            used[d[0].1] = true;
            d[0].1 as u32
        })
        .collect()
}

/// Faces as rotation-normalised loops (smallest index first, orientation kept), sorted.
fn canonical_faces(faces: impl IntoIterator<Item = Vec<u32>>) -> Vec<Vec<u32>> {
    let mut out: Vec<Vec<u32>> = faces
        .into_iter()
        .map(|mut f| {
            let k = (0..f.len()).min_by_key(|&i| f[i]).unwrap();
            f.rotate_left(k);
            f
        })
        .collect();
    out.sort();
    out
}

/// `a` and `b` are the same mesh up to vertex numbering and face order/rotation.
fn assert_same_mesh(a: &PolyMesh, b: &PolyMesh, tol: f64) {
    let map = match_vertices(a, b, tol);
    let mapped = a
        .faces
        .iter()
        .map(|f| f.iter().map(|&v| map[v as usize]).collect());
    assert_eq!(canonical_faces(mapped), canonical_faces(b.faces.clone()));
}

// ---------------------------------------------------------------- Catmull–Clark vs OpenMesh

#[test]
fn catmull_clark_matches_openmesh_on_closed_models() {
    for name in CLOSED_MODELS {
        let m = load(name);
        for levels in 1..=2 {
            let ours = catmull_clark(&m, levels).unwrap();
            let theirs = openmesh_catmull_clark(&m, levels).unwrap();
            assert_eq!(ours.faces.len(), theirs.faces.len(), "{name} {levels}");
            assert_same_mesh(&ours, &theirs, 1e-12);
        }
    }
}

#[test]
fn catmull_clark_matches_openmesh_on_mixed_faces() {
    // Triangles, quads and pentagons in one closed mesh: the house with one roof quad split
    // into two triangles.
    let mut m = load("house.obj");
    let roof: Vec<Vec<u32>> = m.faces.iter().filter(|f| f.len() == 4).cloned().collect();
    let split = roof.last().unwrap().clone();
    m.faces.retain(|f| *f != split);
    m.faces.push(vec![split[0], split[1], split[2]]);
    m.faces.push(vec![split[0], split[2], split[3]]);
    for levels in 1..=2 {
        assert_same_mesh(
            &catmull_clark(&m, levels).unwrap(),
            &openmesh_catmull_clark(&m, levels).unwrap(),
            1e-12,
        );
    }
}

#[test]
fn openmesh_boundary_rule_differs_as_documented() {
    // OpenMesh: boundary vertex (corners too) → (V + m₁ + m₂)/3 = (a + 4V + b)/6.
    // Ours: (a + 6V + b)/8, corners fixed. Everything else (edge and face points, interior
    // vertices, topology) agrees after one level.
    let m = load("grid_open.obj");
    let ours = catmull_clark(&m, 1).unwrap();
    let theirs = openmesh_catmull_clark(&m, 1).unwrap();
    assert_eq!(ours.positions.len(), theirs.positions.len());
    // Both keep the old vertices first, in order.
    let p = |i: usize| m.positions[i];
    // Corner 0 with boundary neighbours 1 and 5.
    assert_near!(ours.positions[0], p(0));
    assert_near!(theirs.positions[0], (p(1) + 4.0 * p(0) + p(5)) / 6.0);
    // Boundary vertex 2 with boundary neighbours 1 and 3.
    assert_near!(ours.positions[2], (p(1) + 6.0 * p(2) + p(3)) / 8.0);
    assert_near!(theirs.positions[2], (p(1) + 4.0 * p(2) + p(3)) / 6.0);
    // Interior vertex 12 agrees.
    assert_near!(ours.positions[12], theirs.positions[12]);
    // With the 16 boundary vertices of the old mesh replaced by OpenMesh's rule, the meshes agree.
    let boundary: Vec<usize> = (0..25)
        .filter(|&i| i % 5 == 0 || i % 5 == 4 || !(5..20).contains(&i))
        .collect();
    assert_eq!(boundary.len(), 16);
    let mut patched = ours.clone();
    for &i in &boundary {
        patched.positions[i] = theirs.positions[i];
    }
    assert_same_mesh(&patched, &theirs, 1e-12);
    assert!((ours.positions[2] - theirs.positions[2]).length() > 1e-3);
}

// ---------------------------------------------------------------- file I/O

/// Each coordinate rounded to single precision.
fn to_f32(p: &[DVec3]) -> Vec<DVec3> {
    p.iter().map(|p| p.as_vec3().as_dvec3()).collect()
}

#[test]
fn openmesh_reads_obj_like_our_reader() {
    for name in CLOSED_MODELS.iter().chain(&["grid_open.obj"]) {
        let ours = load(name);
        let theirs = read_mesh(model(name)).unwrap();
        // OpenMesh 9.0's OBJ reader parses coordinates as f32.
        assert_near!(theirs.positions, to_f32(&ours.positions), 0.0);
        assert_eq!(theirs.faces, ours.faces, "{name}");
    }
}

#[test]
fn round_trips_through_off_ply_om_obj() {
    let dir = scratch("roundtrip");
    for name in CLOSED_MODELS.iter().chain(&["grid_open.obj"]) {
        // Positions that are not short decimals, to see that 17 digits / binary keep every bit.
        let mut m = read_mesh(model(name)).unwrap();
        for (i, p) in m.positions.iter_mut().enumerate() {
            *p += DVec3::new(
                1.0 / 3.0,
                (i as f64).sqrt() * 1e-7,
                -std::f64::consts::PI * 1e-3,
            );
        }
        for ext in ["off", "ply", "om", "obj"] {
            for binary in [false, true] {
                if binary && ext == "obj" {
                    continue;
                }
                let path = dir.join(format!("{name}.{binary}.{ext}"));
                if binary {
                    write_mesh_binary(&m, &path).unwrap();
                } else {
                    write_mesh(&m, &path).unwrap();
                }
                let back = read_mesh(&path).unwrap();
                assert_eq!(back.faces, m.faces, "{name} {ext} binary={binary}");
                // OpenMesh 9.0 passes OBJ/OFF/PLY coordinates through f32 (even for a Vec3d
                // mesh, text with 17 digits included); only OM keeps the doubles.
                let expected = if ext == "om" {
                    m.positions.clone()
                } else {
                    to_f32(&m.positions)
                };
                assert_near!(
                    back.positions,
                    expected,
                    0.0,
                    "{name} {ext} binary={binary}"
                );
            }
        }
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// Fan triangulation (all shared models have convex faces).
fn triangulate(m: &PolyMesh) -> PolyMesh {
    let faces = m
        .faces
        .iter()
        .flat_map(|f| (1..f.len() - 1).map(move |i| vec![f[0], f[i], f[i + 1]]));
    PolyMesh::new(m.positions.clone(), faces.collect())
}

#[test]
fn stl_round_trip_on_triangulated_models() {
    let dir = scratch("stl");
    for name in CLOSED_MODELS.iter().chain(&["grid_open.obj"]) {
        let tri = triangulate(&read_mesh(model(name)).unwrap());
        for binary in [false, true] {
            let path = dir.join(format!("{name}.{binary}.stl"));
            if binary {
                write_mesh_binary(&tri, &path).unwrap();
            } else {
                write_mesh(&tri, &path).unwrap();
            }
            let back = read_mesh(&path).unwrap();
            // STL has no shared vertices and single precision: OpenMesh merges corners by
            // position, so compare position-matched, to float accuracy.
            assert_same_mesh(&tri, &back, 1e-6);
        }
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn tri_mesh_with_normals_round_trips() {
    let dir = scratch("trimesh");
    let m = triangulate(&load("octahedron.obj"));
    let mut t = TriMesh::default();
    for p in &m.positions {
        t.positions.push(*p);
        t.normals.push(p.normalize());
    }
    t.triangles = m.faces.iter().map(|f| [f[0], f[1], f[2]]).collect();
    for ext in ["obj", "off", "ply", "om"] {
        let path = dir.join(format!("oct.{ext}"));
        write_tri_mesh(&t, &path).unwrap();
        let back = read_mesh(&path).unwrap();
        let expected = if ext == "om" {
            t.positions.clone()
        } else {
            to_f32(&t.positions)
        };
        assert_near!(back.positions, expected, 0.0, "{ext}");
        assert_eq!(back.faces, m.faces, "{ext}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

// ---------------------------------------------------------------- errors

#[test]
fn failures_are_errors_not_aborts() {
    let dir = scratch("errors");
    assert!(matches!(
        read_mesh(dir.join("missing.obj")),
        Err(OpenMeshError::OpenMesh(_))
    ));
    assert!(matches!(
        read_mesh(dir.join("unknown.xyz")),
        Err(OpenMeshError::OpenMesh(_))
    ));
    let cube = load("cube.obj");
    assert!(matches!(
        write_mesh(&cube, dir.join("cube.stl")),
        Err(OpenMeshError::NotTriangles { face: 0, len: 4 })
    ));
    assert!(matches!(
        write_mesh(&cube, dir.join("no_such_dir/cube.off")),
        Err(OpenMeshError::OpenMesh(_))
    ));
    assert!(matches!(
        write_mesh(&cube, dir.join("cube.xyz")),
        Err(OpenMeshError::OpenMesh(_))
    ));
    let mut bad = cube.clone();
    bad.faces[5][3] = 41;
    match write_mesh(&bad, dir.join("bad.off")) {
        Err(OpenMeshError::OpenMesh(msg)) => assert!(msg.contains("face 5"), "{msg}"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        openmesh_catmull_clark(&bad, 1),
        Err(OpenMeshError::InvalidMesh(MeshError::IndexOutOfRange {
            face: 5,
            index: 41,
            ..
        }))
    ));
    let flipped = load("bad/flipped_face.obj");
    match write_mesh(&flipped, dir.join("flipped.off")) {
        Err(OpenMeshError::OpenMesh(msg)) => assert!(msg.contains("face 5"), "{msg}"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        openmesh_catmull_clark(&flipped, 1),
        Err(OpenMeshError::InvalidMesh(
            MeshError::InconsistentOrientation { .. }
        ))
    ));
    assert!(matches!(
        openmesh_catmull_clark(&cube, 40),
        Err(OpenMeshError::TooLarge { .. })
    ));
    std::fs::remove_dir_all(dir).unwrap();
}
