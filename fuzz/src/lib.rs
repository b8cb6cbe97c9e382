//! The invariants the fuzz targets check (one place, shared by every reader target).
//!
//! A reader either returns a typed error (non-empty message; a parse error names a line that
//! exists in the input) or a mesh; the same bytes give the same result through the format's own
//! parser and through `parse_mesh_bytes`; a read mesh's source map matches its element counts;
//! the mesh then either passes the one validator (`HalfEdgeMesh::from_polymesh`), giving a
//! consistent half-edge structure over finite positions, or gets a typed error.

use gbsurf::gb::gbp::{parse_gbp, read_gbp, to_gbp_string};
use gbsurf::mesh::io::{parse_mesh_bytes, parse_obj, parse_off, parse_ply, parse_stl};
use gbsurf::mesh::{HalfEdgeMesh, HalfedgeId, MeshError, PolyMesh, SourceMap};

/// Checks the invariants above for `data` read as a mesh file with extension `ext`.
pub fn check_mesh_reader(data: &[u8], ext: &str) {
    let direct = match ext {
        "obj" => parse_obj(data),
        "off" => parse_off(data),
        "ply" => parse_ply(data),
        "stl" => parse_stl(data).map(|m| (m, SourceMap::default())),
        _ => unreachable!("no reader for {ext}"),
    };
    let dispatched = parse_mesh_bytes(data, ext);
    assert_eq!(
        format!("{direct:?}"),
        format!("{dispatched:?}"),
        "parse_mesh_bytes differs from the {ext} reader"
    );
    match direct {
        Err(e) => check_error(&e, data),
        Ok((mesh, map)) => check_read_mesh(&mesh, &map),
    }
}

fn check_error(e: &MeshError, data: &[u8]) {
    let message = e.to_string();
    assert!(!message.trim().is_empty(), "empty error message: {e:?}");
    if let MeshError::Parse { line: Some(line), .. } = e {
        let lines = 1 + data.iter().filter(|&&b| b == b'\n').count();
        assert!((1..=lines).contains(line), "parse error on line {line} of {lines}: {message}");
    }
}

fn check_read_mesh(mesh: &PolyMesh, map: &SourceMap) {
    // text formats record a line per element; binary ones none
    if !map.face_lines.is_empty() {
        assert_eq!(map.face_lines.len(), mesh.faces.len(), "face lines");
    }
    if !map.vertex_lines.is_empty() {
        assert_eq!(map.vertex_lines.len(), mesh.positions.len(), "vertex lines");
    }
    assert_eq!(map.edge_crease_lines.len(), mesh.creases.edges.len(), "edge crease lines");
    assert_eq!(map.vertex_crease_lines.len(), mesh.creases.vertices.len(), "vertex crease lines");
    match HalfEdgeMesh::from_polymesh(mesh) {
        Err(e) => {
            let e = e.with_source(map);
            assert!(!e.to_string().trim().is_empty(), "empty validation message: {e:?}");
        }
        Ok(he) => check_halfedge(&he, mesh),
    }
}

/// A validated mesh: every face of the input kept, finite positions, a consistent half-edge
/// structure (twins, next/prev, face loops of the input's sizes).
pub fn check_halfedge(he: &HalfEdgeMesh, mesh: &PolyMesh) {
    assert_eq!(he.n_faces(), mesh.faces.len(), "validated mesh lost faces");
    assert!(he.n_vertices() <= mesh.positions.len());
    assert!(he.positions().iter().all(|p| p.is_finite()), "non-finite position passed validation");
    for h in 0..he.n_halfedges() {
        let h = HalfedgeId::from(h);
        assert_eq!(he.twin(he.twin(h)), h);
        assert_eq!(he.prev(he.next(h)), h);
        assert_eq!(he.origin(he.next(h)), he.target(h));
        assert!(he.origin(h).idx() < he.n_vertices());
    }
    for (f, face) in mesh.faces.iter().enumerate() {
        let start = he.face_halfedge(f.into());
        let mut h = start;
        let mut n = 0;
        loop {
            assert_eq!(he.face(h).map(|g| g.idx()), Some(f));
            n += 1;
            assert!(n <= face.len(), "face {f} loop longer than its {} corners", face.len());
            h = he.next(h);
            if h == start {
                break;
            }
        }
        assert_eq!(n, face.len(), "face {f} loop length");
    }
}

/// The `.gbp` reader: a typed error, or a patch whose `.gbp` text (when it has one) reads back
/// to the same patch.
pub fn check_gbp_reader(data: &[u8]) {
    match read_gbp(data) {
        Err(e) => assert!(!e.to_string().trim().is_empty(), "empty error message: {e:?}"),
        Ok(patch) => {
            assert!(patch.ribbons.len() >= 3);
            assert!(patch.center.is_finite());
            for r in &patch.ribbons {
                assert!(r.points().iter().all(|p| p.is_finite()), "non-finite control point");
            }
            if let Ok(text) = to_gbp_string(&patch) {
                let again = parse_gbp(&text).expect("a written .gbp reads back");
                assert_eq!(again, patch, ".gbp round trip");
            }
        }
    }
}
