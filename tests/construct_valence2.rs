//! Interior vertices of valence 2 (two faces sharing two consecutive edges, as in Blender's
//! Suzanne) are dissolved before either construction (`construct::prepare`): the surface is the
//! one of the mesh without them, closed and G1, and a warning names each dissolved vertex.

use gbsurf::construct::check::join_report;
use gbsurf::construct::{
    build_dual, build_topology, dissolve_valence2, ConstructError, PatchSource, Surface, TwistMode,
};
use gbsurf::ConvertOptions;
use gbsurf::gb::WeightForm;
use gbsurf::mesh::generate::torus;
use gbsurf::mesh::{read_mesh, HalfEdgeMesh, PolyMesh};
use gbsurf::quality::check_mesh;
use gbsurf::tessellate::tessellate_surface;
use gbsurf::DVec3;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

/// Inserts the chain `pts` (new vertices, appended) into edge a → b of both its faces.
fn insert_on_edge(pm: &mut PolyMesh, a: u32, b: u32, pts: &[DVec3]) {
    let first = pm.positions.len() as u32;
    pm.positions.extend_from_slice(pts);
    let chain: Vec<u32> = (first..first + pts.len() as u32).collect();
    let mut hits = 0;
    for face in &mut pm.faces {
        let n = face.len();
        if let Some(i) = (0..n).find(|&i| (face[i], face[(i + 1) % n]) == (a, b)) {
            face.splice(i + 1..i + 1, chain.iter().copied());
            hits += 1;
        } else if let Some(i) = (0..n).find(|&i| (face[i], face[(i + 1) % n]) == (b, a)) {
            face.splice(i + 1..i + 1, chain.iter().rev().copied());
            hits += 1;
        }
    }
    assert_eq!(hits, 2, "edge {a}-{b} must be interior");
}

/// Moves the last `k` vertices to the front (indices 0..k), shifting the others by k.
fn new_vertices_first(pm: &PolyMesh, k: usize) -> PolyMesh {
    let n = pm.positions.len();
    let map = |v: u32| if (v as usize) < n - k { v + k as u32 } else { v - (n - k) as u32 };
    let mut positions = pm.positions[n - k..].to_vec();
    positions.extend_from_slice(&pm.positions[..n - k]);
    PolyMesh::new(positions, pm.faces.iter().map(|f| f.iter().map(|&v| map(v)).collect()).collect())
}

fn he(pm: &PolyMesh) -> HalfEdgeMesh {
    HalfEdgeMesh::from_polymesh(pm).unwrap()
}

fn build(structure: &str, m: &HalfEdgeMesh, mode: TwistMode) -> Result<Surface, ConstructError> {
    let o = ConvertOptions { twist: mode, ..ConvertOptions::triangles_r8() };
    match structure {
        "dual" => build_dual(m, &o),
        _ => build_topology(m, &o),
    }
}

/// G1 ≤ 1e-4°, gap ≤ 1e-12 along every shared side; closed (every side shared, and the
/// tessellation a clean closed two-manifold) when `closed`.
fn assert_g1(s: &Surface, closed: bool, what: &str) {
    let r = join_report(s, 17, WeightForm::Squared);
    assert!(r.angle_deg.value <= 1e-4 && r.gap.value <= 1e-12 && r.degenerate == 0, "{what}: {r:?}");
    let (m, stats) = tessellate_surface(s, 4, WeightForm::Squared, None).unwrap();
    let c = check_mesh(&m.positions, &m.triangles);
    assert!(stats.max_boundary_gap <= 1e-12, "{what}: gap {}", stats.max_boundary_gap);
    if closed {
        assert!(s.neighbors.iter().flatten().all(Option::is_some), "{what}: open side");
        assert!(c.is_clean_closed(), "{what}: {c:?}");
    } else {
        assert!(c.is_two_manifold(), "{what}: {c:?}");
    }
}

/// Same patches and curves; sources of `with` = sources of `without` mapped by `vmap`.
fn assert_same_surface(with: &Surface, without: &Surface, vmap: impl Fn(usize) -> usize, what: &str) {
    assert_eq!(with.patches, without.patches, "{what}");
    assert_eq!(with.neighbors, without.neighbors, "{what}");
    assert_eq!(with.curves, without.curves, "{what}");
    let mapped: Vec<PatchSource> = without
        .sources
        .iter()
        .map(|s| match *s {
            PatchSource::Vertex(v) => PatchSource::Vertex(vmap(v)),
            f => f,
        })
        .collect();
    assert_eq!(with.sources, mapped, "{what}");
}

/// Cube with a vertex in the middle of edge 0–1 (and, bent, pushed off it): both quads at the edge
/// become pentagons and the new vertex is interior of valence 2. Dissolving it gives the cube.
#[test]
fn cube_edge_midpoint_is_dissolved() {
    let cube = read_mesh(format!("{MODELS}/cube.obj")).unwrap();
    for (label, p) in [("straight", DVec3::new(0.0, -1.0, -1.0)), ("bent", DVec3::new(0.1, -1.4, -1.3))] {
        let mut pm = cube.to_polymesh();
        insert_on_edge(&mut pm, 1, 0, &[p]);
        let m = he(&pm);
        assert!(!m.is_boundary_vertex(gbsurf::mesh::VertexId(8)) && m.valence(gbsurf::mesh::VertexId(8)) == 2);
        for structure in ["dual", "topology"] {
            for mode in [TwistMode::Approx, TwistMode::Interp] {
                let what = format!("{label} {structure} {mode:?}");
                let s = build(structure, &m, mode).unwrap_or_else(|e| panic!("{what}: {e}"));
                assert_eq!(s.warnings.len(), 1, "{what}");
                assert!(s.warnings[0].contains("vertex 8 "), "{what}: {:?}", s.warnings);
                assert_g1(&s, true, &what);
                let plain = build(structure, &cube, mode).unwrap();
                assert!(plain.warnings.is_empty());
                assert_same_surface(&s, &plain, |v| v, &what);
                if structure == "dual" {
                    assert!(!s.sources.contains(&PatchSource::Vertex(8)), "{what}");
                } else {
                    assert_eq!(s.sources, (0..6).map(PatchSource::Face).collect::<Vec<_>>());
                }
            }
        }
    }
}

/// Suzanne's case: two triangles sharing an edge get a bent vertex on it, so both become quads
/// whose middle corner is interior of valence 2 (Suzanne's vertex 137 between its quads 142, 143);
/// dissolving gives the octahedron back.
#[test]
fn octahedron_quads_sharing_two_edges() {
    let oct = read_mesh(format!("{MODELS}/octahedron.obj")).unwrap();
    let mut pm = oct.to_polymesh();
    insert_on_edge(&mut pm, 0, 2, &[DVec3::new(0.45, 0.6, 0.1)]);
    assert_eq!(pm.faces.iter().filter(|f| f.len() == 4).count(), 2);
    let m = he(&pm);
    for structure in ["dual", "topology"] {
        for mode in [TwistMode::Approx, TwistMode::Interp] {
            let what = format!("{structure} {mode:?}");
            let s = build(structure, &m, mode).unwrap();
            assert!(s.warnings.len() == 1 && s.warnings[0].contains("vertex 6 "), "{what}");
            assert_g1(&s, true, &what);
            assert_same_surface(&s, &build(structure, &oct, mode).unwrap(), |v| v, &what);
        }
    }
}

/// A 4×4 torus with valence-2 vertices on two edges (one edge gets a chain of two: the faces share
/// three consecutive edges), renumbered so that the new vertices come first: the surface equals
/// the torus's, and the dual sources name the input vertices.
#[test]
fn torus_with_valence_2_chains() {
    let base = torus(4, 4, 3.0, 1.0).unwrap();
    let mut pm = base.clone();
    let (p0, p1, p5, p4) = (pm.positions[0], pm.positions[1], pm.positions[5], pm.positions[4]);
    insert_on_edge(&mut pm, 0, 1, &[0.5 * (p0 + p1) + DVec3::new(0.3, 0.0, 0.1)]);
    insert_on_edge(&mut pm, 5, 4, &[p5 + 0.3 * (p4 - p5), p5 + 0.7 * (p4 - p5) + DVec3::new(0.0, 0.0, -0.2)]);
    let pm = new_vertices_first(&pm, 3);
    let m = he(&pm);
    let (d, vmap, warnings) = dissolve_valence2(&m).unwrap();
    assert_eq!(d.n_vertices(), 16);
    assert_eq!(vmap, (3..19).collect::<Vec<_>>());
    assert_eq!(warnings.len(), 3);
    let plain_m = he(&base);
    for structure in ["dual", "topology"] {
        for mode in [TwistMode::Approx, TwistMode::Interp] {
            let what = format!("{structure} {mode:?}");
            let s = build(structure, &m, mode).unwrap();
            assert_eq!(s.warnings, warnings, "{what}");
            assert_g1(&s, true, &what);
            assert_same_surface(&s, &build(structure, &plain_m, mode).unwrap(), |v| v + 3, &what);
        }
    }
}

/// An open grid with a valence-2 vertex on an interior edge; its boundary corners (valence 2, one
/// face) need no dissolving and are kept.
#[test]
fn open_grid_with_interior_valence_2() {
    let grid = read_mesh(format!("{MODELS}/grid_open.obj")).unwrap();
    let mut pm = grid.to_polymesh();
    // Edge 6–7 is interior (between the first two rows of quads).
    let p = 0.5 * (pm.positions[6] + pm.positions[7]) + DVec3::new(0.0, 0.1, 0.2);
    insert_on_edge(&mut pm, 6, 7, &[p]);
    let m = he(&pm);
    for structure in ["dual", "topology"] {
        for mode in [TwistMode::Approx, TwistMode::Interp] {
            let what = format!("{structure} {mode:?}");
            let s = build(structure, &m, mode).unwrap();
            assert_eq!(s.warnings.len(), 1, "{what}");
            assert!(s.warnings[0].contains("vertex 25 "), "{what}");
            assert_g1(&s, false, &what);
            assert_same_surface(&s, &build(structure, &grid, mode).unwrap(), |v| v, &what);
            if structure == "dual" {
                // Every input vertex but the dissolved one has its patch, corners included.
                assert_eq!(s.sources, (0..25).map(PatchSource::Vertex).collect::<Vec<_>>());
            }
        }
    }
}

/// A triangle (A, V, B) whose corner V is interior of valence 2 (V's other face is the quad
/// (B, V, A, X), closed by the triangle (A, B, X)): dissolving V would leave a 2-gon, a typed
/// error naming V and the face.
#[test]
fn collapsing_face_is_a_typed_error() {
    let pm = PolyMesh {
        positions: vec![DVec3::ZERO, DVec3::new(0.5, 0.5, 0.0), DVec3::X, DVec3::new(0.5, -0.5, 0.3)],
        faces: vec![vec![0, 1, 2], vec![2, 1, 0, 3], vec![0, 2, 3]],
        creases: Default::default(),
        holes: Vec::new(),
    };
    let m = he(&pm);
    for structure in ["dual", "topology"] {
        match build(structure, &m, TwistMode::Interp) {
            Err(e @ ConstructError::Valence2 { vertex: 1, face: 0, .. }) => {
                assert!(e.to_string().contains("vertex 1 ") && e.to_string().contains("face 0"), "{e}")
            }
            other => panic!("{structure}: expected Valence2 error, got {other:?}"),
        }
    }
}

/// Dissolving V (between A and B) where A–B is already an edge of two other faces would give an
/// edge with four faces: a typed error naming V and a face.
#[test]
fn existing_neighbour_edge_is_a_typed_error() {
    let (a, v, b, c, d) = (0u32, 1, 2, 3, 4);
    let pm = PolyMesh {
        positions: vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.5, 0.3, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.5, 1.0, 0.5),
            DVec3::new(0.5, -1.0, 0.5),
        ],
        faces: vec![vec![a, v, b, c], vec![b, v, a, d], vec![b, a, c], vec![a, b, d]],
        creases: Default::default(),
        holes: Vec::new(),
    };
    let m = he(&pm);
    assert!(!m.is_boundary_vertex(gbsurf::mesh::VertexId(1)) && m.valence(gbsurf::mesh::VertexId(1)) == 2);
    match build("dual", &m, TwistMode::Interp) {
        Err(ConstructError::Valence2 { vertex: 1, face, .. }) => assert!(face <= 1, "face {face}"),
        other => panic!("expected Valence2 error, got {other:?}"),
    }
}

/// The conversion reports the dissolved vertex among its warnings.
#[test]
fn convert_warns_about_dissolved_vertices() {
    let cube = read_mesh(format!("{MODELS}/cube.obj")).unwrap();
    let mut pm = cube.to_polymesh();
    insert_on_edge(&mut pm, 1, 0, &[DVec3::new(0.0, -1.0, -1.0)]);
    for method in [gbsurf::api::Method::Dual, gbsurf::api::Method::Topology] {
        let o = gbsurf::api::ConvertOptions { method, resolution: 3, ..ConvertOptions::triangles_r8() };
        let c = gbsurf::api::convert(&pm, &o, None).unwrap();
        assert!(c.report.closed, "{method:?}");
        assert!(c.warnings.iter().any(|w| w.contains("vertex 8 ") && w.contains("valence 2")), "{:?}", c.warnings);
    }
}
