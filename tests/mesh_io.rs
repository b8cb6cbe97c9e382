//! File I/O: OBJ/OFF/PLY/STL reading, writers and round trips.

use gbsurf::export::{ExportError, PlyFormat, VertexScalar};
use gbsurf::mesh::io::*;
use gbsurf::mesh::{read_mesh, read_polymesh, MeshError, PolyMesh, TriMesh};
use gbsurf::DVec3;
use std::path::PathBuf;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gbsurf_mesh_io_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn house() -> PolyMesh {
    read_mesh(format!("{MODELS}/house.obj")).unwrap().to_polymesh()
}

#[test]
fn obj_round_trip_exact() {
    let m = house();
    let mut buf = Vec::new();
    m.write_obj(&mut buf).unwrap();
    let (back, map) = parse_obj(std::str::from_utf8(&buf).unwrap()).unwrap();
    assert_eq!(back, m);
    assert_eq!(map.vertex_lines, (1..=10).collect::<Vec<_>>());
    assert_eq!(map.face_lines, (11..=17).collect::<Vec<_>>());
    // odd values survive the 17-digit text form exactly
    let odd = PolyMesh::new(vec![DVec3::new(0.1, 1.0 / 3.0, -2e-300), DVec3::new(1e150, 7.0, 0.0), DVec3::Y], vec![vec![0, 1, 2]]);
    let mut buf = Vec::new();
    odd.write_obj(&mut buf).unwrap();
    assert_eq!(parse_obj(std::str::from_utf8(&buf).unwrap()).unwrap().0, odd);
}

#[test]
fn obj_groups_are_merged_and_normals_ignored() {
    let text = "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\ng one\nf 1//1 3//1 2//1\nf 1/1/1 2/1/1 4/1/1\ng two\nusemtl x\ns off\nf 2 3 4\nf 1 4 3\n";
    let (m, _) = parse_obj(text).unwrap();
    assert_eq!(m.faces.len(), 4);
    assert_eq!(m.positions.len(), 4);
    assert_eq!(m.faces[3], vec![0, 3, 2]);
}

#[test]
fn obj_cube_with_per_face_normals_and_texcoords_keeps_8_vertices() {
    // Every corner carries its own v/vt/vn triple (24 distinct triples, as exported by Blender
    // with split normals); only the position index counts, so the cube stays closed with 8
    // vertices. Two groups, a comment after a statement and relative indices in the last face.
    let text = "\
v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n\
g bottom_top\n\
f 1/1/1 3/2/1 4/3/1 2/4/1\nf 5/1/2 6/2/2 8/3/2 7/4/2 # top\n\
g sides\n\
f 1/1/3 2/2/3 6/3/3 5/4/3\nf 3/1/4 7/2/4 8/3/4 4/4/4\nf 1//5 5//5 7//5 3//5\nf -7/1/-1 -5/2/-1 -1/3/-1 -3/4/-1\n";
    let (m, map) = parse_obj(text).unwrap();
    assert_eq!(m.positions.len(), 8);
    assert_eq!(m.positions[7], DVec3::ONE);
    assert_eq!(
        m.faces,
        vec![vec![0, 2, 3, 1], vec![4, 5, 7, 6], vec![0, 1, 5, 4], vec![2, 6, 7, 3], vec![0, 4, 6, 2], vec![1, 3, 7, 5]]
    );
    assert_eq!(map.vertex_lines, (1..=8).collect::<Vec<_>>());
    assert_eq!(map.face_lines, vec![20, 21, 23, 24, 25, 26]);
    let he = gbsurf::mesh::HalfEdgeMesh::from_polymesh(&m).unwrap();
    assert_eq!((he.n_vertices(), he.n_edges(), he.n_faces()), (8, 12, 6));
    assert!(he.warnings().is_empty());
}

#[test]
fn obj_garbage_is_an_error_naming_the_line() {
    let cases = [
        ("v 1 2\n", 1),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", 4),
        ("v 0 0 0\nhello world\n", 2),
        ("v a b c\n", 1),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 0\n", 5),
    ];
    for (text, line) in cases {
        match parse_obj(text) {
            Err(MeshError::Parse { line: l, .. }) => assert_eq!(l, Some(line), "{text:?}"),
            r => panic!("{text:?}: {r:?}"),
        }
    }
    // out of range index (also negative relative) with its line, named as written
    match parse_obj("v 0 0 0\nv 1 0 0\nf 1 2 -3\n") {
        Err(MeshError::ObjIndexOutOfRange { face: 0, corner: 2, index: -3, available: 2, line: Some(3) }) => {}
        r => panic!("{r:?}"),
    }
}

#[test]
fn ply_round_trip_ascii_and_binary_with_scalars() {
    let m = house();
    let quality: Vec<f64> = (0..m.positions.len()).map(|i| i as f64 * 0.5).collect();
    for format in [PlyFormat::Ascii, PlyFormat::BinaryLittleEndian] {
        let mut buf = Vec::new();
        m.write_ply(&mut buf, format, &[VertexScalar::float("quality", &quality)]).unwrap();
        let header_end = buf.windows(10).position(|w| w == b"end_header").unwrap();
        let header = std::str::from_utf8(&buf[..header_end]).unwrap();
        assert!(header.contains("property float quality"), "{header}");
        let (back, _) = parse_ply(&buf).unwrap();
        assert_eq!(back, m, "{format:?}");
    }
    // mismatched scalar length is refused
    let mut buf = Vec::new();
    assert!(m.write_ply(&mut buf, PlyFormat::Ascii, &[VertexScalar::float("q", &[1.0])]).is_err());
}

fn tri_mesh() -> TriMesh {
    let m = read_mesh(format!("{MODELS}/octahedron.obj")).unwrap();
    let p = m.to_polymesh();
    TriMesh {
        normals: p.positions.iter().map(|q| q.normalize()).collect(),
        positions: p.positions,
        triangles: p.faces.iter().map(|f| [f[0], f[1], f[2]]).collect(),
    }
}

#[test]
fn trimesh_ply_and_stl() {
    let t = tri_mesh();
    let mut buf = Vec::new();
    t.write_ply(&mut buf, PlyFormat::BinaryLittleEndian, &[]).unwrap();
    let (back, _) = parse_ply(&buf).unwrap();
    assert_eq!(back.positions, t.positions);
    assert_eq!(back.faces, t.triangles.iter().map(|x| x.to_vec()).collect::<Vec<_>>());
    let mut stl = Vec::new();
    t.write_stl(&mut stl).unwrap();
    assert_eq!(stl.len(), 84 + 50 * 8);
    let back = parse_stl(&stl).unwrap();
    // welded back to 6 vertices (coordinates are exact in f32 here)
    assert_eq!(back.positions.len(), 6);
    assert_eq!(back.faces.len(), 8);
    let he = gbsurf::mesh::HalfEdgeMesh::from_polymesh(&back).unwrap();
    assert_eq!(he.euler_characteristic(), 2);
    // facet normal of the first triangle points outwards
    let n = DVec3::new(
        f32::from_le_bytes(stl[84..88].try_into().unwrap()) as f64,
        f32::from_le_bytes(stl[88..92].try_into().unwrap()) as f64,
        f32::from_le_bytes(stl[92..96].try_into().unwrap()) as f64,
    );
    gbsurf::assert_near!(n, DVec3::ONE.normalize(), 1e-6);
}

#[test]
fn polymesh_stl_splits_concave_faces() {
    let m = read_mesh(format!("{MODELS}/l_prism.obj")).unwrap().to_polymesh();
    let mut stl = Vec::new();
    m.write_stl(&mut stl).unwrap();
    // 6 side quads → 12 triangles; each L → two quads → 4 triangles
    assert_eq!(stl.len(), 84 + 50 * 20);
    let back = parse_stl(&stl).unwrap();
    let he = gbsurf::mesh::HalfEdgeMesh::from_polymesh(&back).unwrap();
    assert!(he.is_closed());
    assert_eq!(he.euler_characteristic(), 2);
}

#[test]
fn files_atomic_and_dispatch() {
    let m = house();
    for ext in ["obj", "ply", "stl"] {
        let path = tmp(&format!("house.{ext}"));
        m.write_file(&path).unwrap();
        let back = read_mesh(&path).unwrap();
        assert_eq!(back.n_vertices(), 10, "{ext}");
        assert_eq!(back.euler_characteristic(), 2, "{ext}");
        if ext != "stl" {
            assert_eq!(back.to_polymesh(), m, "{ext}");
        }
        // no temporary (a hidden file beside the target) left behind
        let left: Vec<_> = std::fs::read_dir(path.parent().unwrap()).unwrap().filter_map(|e| e.ok()).filter(|e| e.file_name().to_string_lossy().starts_with('.')).collect();
        assert!(left.is_empty());
    }
    let t = tri_mesh();
    let path = tmp("octa.obj");
    t.write_file(&path).unwrap();
    assert_eq!(read_mesh(&path).unwrap().n_faces(), 8);
    // unwritable target: error, not panic
    assert!(matches!(m.write_file("/nonexistent_dir_gbsurf/x.obj"), Err(ExportError::Io { .. })));
    assert!(matches!(m.write_file(tmp("x.xyz")), Err(ExportError::UnknownFormat { .. })));
    assert!(matches!(read_mesh("/nonexistent_dir_gbsurf/x.obj"), Err(MeshError::Io { .. })));
    assert!(matches!(read_polymesh(tmp("x.xyz")), Err(MeshError::Io { .. }) | Err(MeshError::Parse { .. })));
    let _ = std::fs::remove_dir_all(path.parent().unwrap());
}

#[test]
fn off_reading() {
    let text = "OFF\n# pyramid\n5 5 0\n-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n0 0 1.5\n4 3 2 1 0\n3 0 1 4\n3 1 2 4\n3 2 3 4\n3 3 0 4 255 0 0\n";
    let (m, map) = parse_off(text).unwrap();
    let py = read_mesh(format!("{MODELS}/pyramid.obj")).unwrap().to_polymesh();
    assert_eq!(m, py);
    assert_eq!(map.face_lines[0], 9);
    assert!(matches!(parse_off("OFF\n1 1 0\n0 0 0\n3 0 1 2\n"), Err(MeshError::IndexOutOfRange { face: 0, corner: 1, line: Some(4), .. })));
    assert!(matches!(parse_off("NOPE\n"), Err(MeshError::Parse { .. })));
}

#[test]
fn ply_errors() {
    assert!(matches!(parse_ply(b"not a ply"), Err(MeshError::Parse { .. })));
    let truncated = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n\0\0";
    assert!(matches!(parse_ply(truncated), Err(MeshError::Parse { .. })));
}
