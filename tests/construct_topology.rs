//! Topology-preserving structure (seed 000 §3, §4) on the shared models, ribbon level: tiles,
//! node tangent planes, corner blocks, G1 of the blend twists.

use gbsurf::construct::check::{corner_block_defect, ribbon_g1_angle, ribbon_gap};
use gbsurf::construct::{
    build_topology, convex_mesh, tiles, topology_network, Patch, PatchSource, TwistMode,
};
use gbsurf::ConvertOptions;
use gbsurf::mesh::{read_mesh, HalfEdgeMesh, PolyMesh};
use gbsurf::{assert_near, DVec3};

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");
const GOOD: &[&str] = &[
    "cube", "cube_corner_pulled", "cube_extruded", "cube_nonplanar", "dodecahedron", "grid_open", "house", "l_prism", "octahedron",
    "prism3", "pyramid", "star_prism", "torus",
];

fn load(name: &str) -> HalfEdgeMesh {
    read_mesh(format!("{MODELS}/{name}.obj")).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn opts(t: TwistMode) -> ConvertOptions {
    ConvertOptions { twist: t, ..ConvertOptions::triangles_r8() }
}

#[test]
fn cube_tiles_are_doo_sabin_points() {
    // Planar square faces: tile vertex of p in a face = p + (q − p)/w + (r − p)/w (q, r the face
    // neighbours of p); centre of the triangular tile = p + (Σ neighbours − 3p)·2/(3w).
    let m = load("cube");
    for w in [2.5, 3.0, 7.0] {
        let t = tiles(&m, &ConvertOptions { tile_depth: w, ..ConvertOptions::triangles_r8() }).unwrap();
        for h in m.halfedges() {
            let p = m.position(m.origin(h));
            let q = m.position(m.target(h));
            let r = m.position(m.origin(m.prev(h)));
            assert_near!(t.vertex[h.idx()], p + (q - p) / w + (r - p) / w);
        }
        for v in m.vertices() {
            let p = m.position(v);
            let s: DVec3 = m.vertex_vertices(v).map(|u| m.position(u) - p).sum();
            assert_near!(t.center[v.idx()], p + s * 2.0 / (3.0 * w));
        }
    }
}

#[test]
fn flat_grid_gives_uniform_straight_curves() {
    // 3×3 planar unit grid, w = 3: interior curves are the edges with uniform control points.
    let mut pos = Vec::new();
    for j in 0..4 {
        for i in 0..4 {
            pos.push(DVec3::new(i as f64, j as f64, 0.0));
        }
    }
    let mut faces = Vec::new();
    for j in 0..3u32 {
        for i in 0..3u32 {
            let a = j * 4 + i;
            faces.push(vec![a, a + 1, a + 5, a + 4]);
        }
    }
    let m = HalfEdgeMesh::from_polymesh(&PolyMesh::new(pos, faces)).unwrap();
    let net = topology_network(&m, &ConvertOptions::triangles_r8()).unwrap();
    let interior = |p: DVec3| p.x > 0.5 && p.x < 2.5 && p.y > 0.5 && p.y < 2.5;
    let mut n = 0;
    for c in &net.curves {
        if interior(c[0]) && interior(c[3]) {
            n += 1;
            assert_near!(c[1], c[0] + (c[3] - c[0]) / 3.0);
            assert_near!(c[2], c[0] + 2.0 * (c[3] - c[0]) / 3.0);
        }
    }
    assert_eq!(n, 4);
}

#[test]
fn patch_per_face_and_node_planes() {
    for name in GOOD {
        let m = load(name);
        let net = topology_network(&m, &opts(TwistMode::Interp)).unwrap();
        for (c, ends) in net.curves.iter().zip(&net.curve_nodes) {
            let t0 = (c[1] - c[0]).normalize();
            let t1 = (c[3] - c[2]).normalize();
            assert!(net.node_normals[ends[0]].dot(t0).abs() < 1e-12, "{name}");
            assert!(net.node_normals[ends[1]].dot(t1).abs() < 1e-12, "{name}");
        }
        let s = build_topology(&m, &opts(TwistMode::Interp)).unwrap();
        let (cm, origin) = convex_mesh(&m).unwrap();
        assert_eq!(s.patches.len(), cm.n_faces());
        for f in cm.faces() {
            let Patch::Cgb(p) = &s.patches[f.idx()] else { panic!("topology patches are CGB") };
            assert_eq!(p.ribbons.len(), cm.face_size(f));
            assert_eq!(s.sources[f.idx()], PatchSource::Face(origin[f.idx()]));
        }
    }
}

#[test]
fn blend_twists_are_g1_on_every_model() {
    for name in GOOD {
        let m = load(name);
        for mode in [TwistMode::Approx, TwistMode::Interp] {
            for w in [2.5, 3.0, 6.0] {
                let o = ConvertOptions { tile_depth: w, ..opts(mode) };
                let s = build_topology(&m, &o).unwrap();
                assert_eq!(corner_block_defect(&s).value, 0.0, "{name}");
                assert!(ribbon_gap(&s, 17).value < 1e-14, "{name}");
                let g = ribbon_g1_angle(&s, 33);
                assert!(g.value < 1e-8, "{name} {mode:?} w={w}: {g:?}");
            }
        }
    }
}

#[test]
fn tile_vertex_twists_report_g1_error() {
    // Not G1 where tiles are not parallelograms (valence ≠ 4).
    for name in ["dodecahedron", "cube", "prism3", "pyramid"] {
        let s = build_topology(&load(name), &opts(TwistMode::None)).unwrap();
        let g = ribbon_g1_angle(&s, 17);
        assert!(g.value > 0.01, "{name}: {g:?}");
        let r = s.patches[0].ribbons();
        assert_eq!(r[0].row(1)[2], r[1].row(1)[1], "{name}: twists shared at corners");
    }
    // Valence 4 everywhere with planar faces (square tiles): the tile-vertex twists are C1 across.
    for name in ["octahedron", "torus"] {
        let s = build_topology(&load(name), &opts(TwistMode::None)).unwrap();
        let g = ribbon_g1_angle(&s, 17);
        assert!(g.value < 1e-8, "{name}: {g:?}");
    }
}

/// n-gonal prism (two n-gon caps, face size n) and bipyramid (two apices of valence n).
fn prism(n: usize) -> HalfEdgeMesh {
    let mut pos = Vec::new();
    for z in [-0.5, 0.5] {
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            pos.push(DVec3::new(a.cos(), a.sin(), z));
        }
    }
    let n32 = n as u32;
    let mut faces = vec![(0..n32).rev().collect::<Vec<_>>(), (n32..2 * n32).collect()];
    for i in 0..n32 {
        let j = (i + 1) % n32;
        faces.push(vec![i, j, j + n32, i + n32]);
    }
    HalfEdgeMesh::from_polymesh(&PolyMesh::new(pos, faces)).unwrap()
}

fn bipyramid(n: usize) -> HalfEdgeMesh {
    let mut pos: Vec<DVec3> = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            DVec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    pos.push(DVec3::Z);
    pos.push(-DVec3::Z);
    let n32 = n as u32;
    let mut faces = Vec::new();
    for i in 0..n32 {
        let j = (i + 1) % n32;
        faces.push(vec![i, j, n32]);
        faces.push(vec![j, i, n32 + 1]);
    }
    HalfEdgeMesh::from_polymesh(&PolyMesh::new(pos, faces)).unwrap()
}

#[test]
fn face_sizes_and_valences_3_to_64() {
    for n in [3, 5, 8, 17, 33, 64] {
        for m in [prism(n), bipyramid(n)] {
            for mode in [TwistMode::Approx, TwistMode::Interp] {
                let mut max_sides = 0;
                for s in [build_topology(&m, &opts(mode)).unwrap(), gbsurf::construct::build_dual(&m, &opts(mode)).unwrap()] {
                    assert_eq!(corner_block_defect(&s).value, 0.0);
                    let g = ribbon_g1_angle(&s, 33);
                    assert!(g.value < 1e-8, "n = {n} {mode:?}: {g:?}");
                    max_sides = max_sides.max(s.patches.iter().map(|p| p.sides()).max().unwrap());
                }
                // Prism: n-gon faces (topology); bipyramid: valence-n apices (dual).
                assert_eq!(max_sides, n.max(4));
            }
        }
    }
}

#[test]
fn concave_faces_are_split_deterministically() {
    for name in ["l_prism", "star_prism"] {
        let m = load(name);
        let (cm, origin) = convex_mesh(&m).unwrap();
        assert!(cm.n_faces() > m.n_faces(), "{name}");
        assert_eq!(origin.len(), cm.n_faces());
        for f in cm.faces() {
            let pts: Vec<DVec3> = cm.face_vertices(f).map(|v| cm.position(v)).collect();
            assert!(pts.len() == 3 || gbsurf::mesh::geometry::is_convex_polygon(&pts), "{name} face {}", f.idx());
        }
        let a = build_topology(&m, &opts(TwistMode::Interp)).unwrap();
        let b = build_topology(&m, &opts(TwistMode::Interp)).unwrap();
        assert_eq!(a, b);
    }
    // A convex mesh is used as it is.
    let m = load("cube");
    let (cm, origin) = convex_mesh(&m).unwrap();
    assert!(matches!(cm, std::borrow::Cow::Borrowed(_)));
    assert_eq!(origin, (0..6).collect::<Vec<_>>());
}

/// Blender's cone (n triangles around an apex of valence n, an n-gon cap), seed 000 §3.3.1 as
/// prescribed: in a triangle (p0, p1, p2) both division lines at p0 lie at barycentric height 1/w,
/// so the tile vertex of p0 is (1 − 2/w) p0 + (p1 + p2)/w (for w = 3 all three coincide at the
/// centroid), and the apex tile's centre, the highest node, is at z = 1 − 4/w for apex z = 1 and
/// base z = −1: −1/3 for the default w = 3 (Blender's Catmull–Clark limit reaches 0.748).
#[test]
fn cone_apex_tile_depth() {
    let n = 32;
    let mut positions = vec![DVec3::Z];
    positions.extend((0..n).map(|i| {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        DVec3::new(a.cos(), a.sin(), -1.0)
    }));
    let mut faces: Vec<Vec<u32>> = (0..n as u32).map(|i| vec![0, 1 + i, 1 + (i + 1) % n as u32]).collect();
    faces.push((1..=n as u32).rev().collect());
    let m = HalfEdgeMesh::from_polymesh(&PolyMesh::new(positions, faces)).unwrap();
    for w in [2.5, 3.0, 4.0, 7.0] {
        let o = ConvertOptions { tile_depth: w, ..ConvertOptions::triangles_r8() };
        let t = tiles(&m, &o).unwrap();
        for h in m.halfedges().filter(|&h| m.face(h).is_some_and(|f| m.face_size(f) == 3)) {
            let (p0, p1, p2) =
                (m.position(m.origin(h)), m.position(m.target(h)), m.position(m.origin(m.prev(h))));
            assert_near!(t.vertex[h.idx()], (1.0 - 2.0 / w) * p0 + (p1 + p2) / w);
        }
        assert_near!(t.center[0], DVec3::new(0.0, 0.0, 1.0 - 4.0 / w));
        // The highest curve point: the apex node, or (w < 4) the base vertices' tile vertices in
        // the triangles, at z = −(1 − 2/w).
        let s = build_topology(&m, &o).unwrap();
        let top = s.curves.iter().flatten().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max);
        assert_near!(top, (1.0 - 4.0 / w).max(2.0 / w - 1.0));
    }
}
