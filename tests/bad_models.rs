//! One test per file in ../shared/models/bad: the named error variant and element.
//! Indices in errors are 0-based (OBJ indices minus one); lines are 1-based file lines.

use gbsurf::mesh::{read_mesh, HalfEdgeMesh, MeshError, MeshWarning, PolyMesh, COORDINATE_LIMIT};
use gbsurf::DVec3;

const BAD: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models/bad");

fn err(name: &str) -> MeshError {
    match read_mesh(format!("{BAD}/{name}")) {
        Ok(m) => panic!("{name}: accepted ({} faces)", m.n_faces()),
        Err(e) => e,
    }
}

#[test]
fn bowtie_vertex() {
    // two triangles 1 2 3 and 1 4 5 share only vertex 1 (OBJ numbering, as errors from an OBJ file name it)
    let e = err("bowtie_vertex.obj");
    assert!(matches!(e, MeshError::NonManifoldVertex { vertex: 1, fans: 2, line: Some(2) }), "{e}");
}

#[test]
fn duplicate_face() {
    // the last face (index 6, line 16) repeats face 0
    let e = err("duplicate_face.obj");
    assert_eq!(e, MeshError::DuplicateFace { face: 6, first: 0, line: Some(16) });
}

#[test]
fn empty() {
    assert_eq!(err("empty.obj"), MeshError::Empty);
}

#[test]
fn flipped_face() {
    // face 5 "6 8 4 2" runs 5 → 7 like face 1 "5 6 8 7"
    let e = err("flipped_face.obj");
    assert_eq!(e, MeshError::InconsistentOrientation { edge: (6, 8), faces: (1, 5), line: Some(15) });
}

#[test]
fn garbage() {
    // first line "v 1 2" has only two coordinates; never a partial mesh
    let e = err("garbage.obj");
    assert!(matches!(e, MeshError::Parse { line: Some(1), .. }), "{e}");
}

#[test]
fn huge_coordinates() {
    // a cube of half-size 1e300: its areas (1e600) would overflow, so it is rejected with the
    // documented limit 1e150
    let e = err("huge_coordinates.obj");
    match e {
        MeshError::CoordinateRange { vertex, axis, value, limit, line } => {
            assert_eq!((vertex, axis, line), (1, 0, Some(2)));
            assert_eq!(limit, COORDINATE_LIMIT);
            assert!(value < -1e299);
        }
        e => panic!("{e}"),
    }
}

#[test]
fn index_out_of_range() {
    // "f 2 4 8 42": face 5, corner 3, index 42 as written (1..=8), line 15
    let e = err("index_out_of_range.obj");
    assert_eq!(
        e,
        MeshError::ObjIndexOutOfRange { face: 5, corner: 3, index: 42, available: 8, line: Some(15) }
    );
}

#[test]
fn inf() {
    let e = err("inf.obj");
    assert!(
        matches!(e, MeshError::NonFiniteCoordinate { vertex: 1, axis: 0, value, line: Some(2) } if value == f64::INFINITY),
        "{e}"
    );
}

#[test]
fn nan() {
    let e = err("nan.obj");
    assert!(
        matches!(e, MeshError::NonFiniteCoordinate { vertex: 1, axis: 0, value, line: Some(2) } if value.is_nan()),
        "{e}"
    );
}

#[test]
fn isolated_vertex_is_dropped_with_warning() {
    let m = read_mesh(format!("{BAD}/isolated_vertex.obj")).unwrap();
    assert_eq!(m.warnings(), &[MeshWarning::IsolatedVertex { vertex: 9, line: Some(10) }]);
    assert_eq!((m.n_vertices(), m.n_edges(), m.n_faces()), (8, 12, 6));
    assert_eq!(m.original_vertices(), &[0, 1, 2, 3, 4, 5, 6, 7]);
    assert!(m.positions().iter().all(|p| p.abs().max_element() == 1.0));
}

#[test]
fn nonmanifold_edge() {
    // edge between vertices 1 and 2 (OBJ numbering): cube faces 0 and 2 plus fins 6 and 7
    let e = err("nonmanifold_edge.obj");
    assert_eq!(e, MeshError::NonManifoldEdge { edge: (1, 2), faces: vec![0, 2, 6, 7], line: Some(18) });
}

#[test]
fn repeated_index() {
    // "f 2 4 4 6": face 5 names vertex 4 twice (as the file numbers it)
    let e = err("repeated_index.obj");
    assert_eq!(e, MeshError::RepeatedIndex { face: 5, vertex: 4, line: Some(15) });
}

#[test]
fn zero_area_file() {
    // "f 5 6 9": corners (-1,-1,1), (1,-1,1), (0,-1,1) are collinear (a sliver beside the
    // pentagon "5 9 6 8 7" of an otherwise closed two-manifold cube).
    let e = err("zero_area.obj");
    assert_eq!(e, MeshError::ZeroAreaFace { face: 6, area: 0.0, line: Some(17) });
}

fn cube() -> PolyMesh {
    let p = (0..8)
        .map(|i| DVec3::new(if i & 1 == 0 { -1.0 } else { 1.0 }, if i & 2 == 0 { -1.0 } else { 1.0 }, if i & 4 == 0 { -1.0 } else { 1.0 }))
        .collect();
    let f = vec![vec![0, 2, 3, 1], vec![4, 5, 7, 6], vec![0, 1, 5, 4], vec![2, 6, 7, 3], vec![0, 4, 6, 2], vec![1, 3, 7, 5]];
    PolyMesh::new(p, f)
}

#[test]
fn cube_in_memory_is_valid() {
    let m = HalfEdgeMesh::from_polymesh(&cube()).unwrap();
    assert_eq!(m.euler_characteristic(), 2);
}

#[test]
fn zero_area_collinear_face() {
    // a cube with a face split by a collinear corner (edge midpoint) into a quad and a flat
    // triangle: replace the face 1 3 7 5 by 1 3 8 5 + 3 7 8 with 8 = midpoint of 3–7 → the
    // triangle 3 7 8 has collinear corners
    let mut m = cube();
    m.positions.push((m.positions[3] + m.positions[7]) * 0.5);
    m.faces[5] = vec![1, 3, 8, 7, 5];
    m.faces.push(vec![3, 7, 8]);
    let e = HalfEdgeMesh::from_polymesh(&m).unwrap_err();
    assert!(matches!(e, MeshError::ZeroAreaFace { face: 6, line: None, .. }), "{e}");
    // also a triangle with two coincident corners
    let mut m = cube();
    m.positions.push(m.positions[0]);
    m.faces.push(vec![0, 8, 1]);
    let e = HalfEdgeMesh::from_polymesh(&m).unwrap_err();
    assert!(matches!(e, MeshError::ZeroAreaFace { face: 6, .. }), "{e}");
}

#[test]
fn face_too_small() {
    let mut m = cube();
    m.faces.push(vec![0, 1]);
    assert_eq!(HalfEdgeMesh::from_polymesh(&m).unwrap_err(), MeshError::FaceTooSmall { face: 6, len: 2, line: None });
}

#[test]
fn reversed_duplicate_pillow() {
    // a cube plus a separate two-sided triangle (the same cycle in both orientations)
    let mut m = cube();
    m.positions.extend([DVec3::new(5.0, 0.0, 0.0), DVec3::new(6.0, 0.0, 0.0), DVec3::new(5.0, 1.0, 0.0)]);
    m.faces.push(vec![8, 9, 10]);
    m.faces.push(vec![9, 8, 10]);
    assert_eq!(HalfEdgeMesh::from_polymesh(&m).unwrap_err(), MeshError::DuplicateFace { face: 7, first: 6, line: None });
}

#[test]
fn closed_double_cone_vertex() {
    // two closed pyramids sharing only their apex: no boundary, but two fans at the apex
    let mut p = vec![DVec3::ZERO];
    let mut faces = Vec::new();
    for (s, base) in [(1.0, 1u32), (-1.0, 5u32)] {
        for k in 0..4 {
            let a = k as f64 * std::f64::consts::FRAC_PI_2;
            p.push(DVec3::new(a.cos(), a.sin(), s));
        }
        for k in 0..4 {
            let (i, j) = (base + k, base + (k + 1) % 4);
            // apex at 0, base square at z = s; orientation outward
            if s > 0.0 { faces.push(vec![0, j, i]) } else { faces.push(vec![0, i, j]) }
        }
        if s > 0.0 { faces.push(vec![base, base + 1, base + 2, base + 3]) } else { faces.push(vec![base + 3, base + 2, base + 1, base]) }
    }
    let e = HalfEdgeMesh::from_polymesh(&PolyMesh::new(p, faces)).unwrap_err();
    assert_eq!(e, MeshError::NonManifoldVertex { vertex: 0, fans: 2, line: None });
}

#[test]
fn errors_display_the_element() {
    let s = err("index_out_of_range.obj").to_string();
    assert!(s.contains("face 5") && s.contains("line 15") && s.contains("vertex index 42 out of range (1..=8)"), "{s}");
    let s = err("nonmanifold_edge.obj").to_string();
    assert!(s.contains("edge (1, 2)"), "{s}");
}

#[test]
fn relative_and_slashed_obj_indices() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf -3//1 -2//1 -1//1\n";
    let (m, map) = gbsurf::mesh::io::parse_obj(text).unwrap();
    assert_eq!(m.faces, vec![vec![0, 1, 2]]);
    assert_eq!(map.face_lines, vec![5]);
    assert!(matches!(gbsurf::mesh::io::parse_obj("v 0 0 0\nf 0 1 2\n"), Err(MeshError::Parse { line: Some(2), .. })));
    assert!(matches!(gbsurf::mesh::io::parse_obj("v 0 0 0\nxyz\n"), Err(MeshError::Parse { line: Some(2), .. })));
}
