//! Half-edge mesh on the good models: Euler characteristic, twin/next/prev invariants, CCW fans,
//! boundary loops, round trip to PolyMesh.

use gbsurf::mesh::{read_mesh, FaceId, HalfEdgeMesh, PolyMesh, VertexId};
use gbsurf::DVec3;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

fn load(name: &str) -> HalfEdgeMesh {
    read_mesh(format!("{MODELS}/{name}")).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// (file, V, E, F, χ, boundary loops)
const GOOD: &[(&str, usize, usize, usize, i64, usize)] = &[
    ("cube.obj", 8, 12, 6, 2, 0),
    ("cube_extruded.obj", 16, 28, 14, 2, 0),
    ("cube_nonplanar.obj", 8, 12, 6, 2, 0),
    ("cube_corner_pulled.obj", 8, 12, 6, 2, 0),
    ("dodecahedron.obj", 20, 30, 12, 2, 0),
    ("grid_open.obj", 25, 40, 16, 1, 1),
    ("house.obj", 10, 15, 7, 2, 0),
    ("l_prism.obj", 12, 18, 8, 2, 0),
    ("octahedron.obj", 6, 12, 8, 2, 0),
    ("prism3.obj", 6, 9, 5, 2, 0),
    ("pyramid.obj", 5, 8, 5, 2, 0),
    ("star_prism.obj", 20, 30, 12, 2, 0),
    ("torus.obj", 96, 192, 96, 0, 0),
];

fn check_invariants(m: &HalfEdgeMesh) {
    for h in m.halfedges() {
        assert_eq!(m.twin(m.twin(h)), h);
        assert_ne!(m.twin(h), h);
        assert_eq!(m.next(m.prev(h)), h);
        assert_eq!(m.prev(m.next(h)), h);
        assert_eq!(m.target(h), m.origin(m.next(h)));
        assert_eq!(m.target(h), m.origin(m.twin(h)));
        assert_eq!(m.face(h), m.face(m.next(h)));
        assert_eq!(m.edge(h), m.edge(m.twin(h)));
        // a boundary edge has exactly one face side
        if m.is_boundary_halfedge(h) {
            assert!(m.face(m.twin(h)).is_some());
            assert!(m.is_boundary_edge(m.edge(h)));
            assert!(m.is_boundary_vertex(m.origin(h)));
        }
    }
    for f in m.faces() {
        for h in m.face_halfedges(f) {
            assert_eq!(m.face(h), Some(f));
        }
        assert_eq!(m.face_vertices(f).count(), m.face_size(f));
    }
    let mut total_valence = 0;
    for v in m.vertices() {
        let outs: Vec<_> = m.vertex_outgoing(v).collect();
        total_valence += outs.len();
        assert_eq!(outs.len(), m.valence(v));
        for (i, &h) in outs.iter().enumerate() {
            assert_eq!(m.origin(h), v);
            // CCW: the successor is twin(prev(h))
            assert_eq!(outs[(i + 1) % outs.len()], m.twin(m.prev(h)));
        }
        // boundary vertex: iteration starts at the outgoing boundary half-edge and only it is
        // face-less, so the faces form one contiguous fan
        let n_boundary = outs.iter().filter(|&&h| m.is_boundary_halfedge(h)).count();
        if m.is_boundary_vertex(v) {
            assert_eq!(n_boundary, 1);
            assert!(m.is_boundary_halfedge(outs[0]));
            assert_eq!(m.vertex_faces(v).count(), outs.len() - 1);
        } else {
            assert_eq!(n_boundary, 0);
            assert_eq!(m.vertex_faces(v).count(), outs.len());
        }
    }
    assert_eq!(total_valence, m.n_halfedges());
    assert_eq!(m.n_halfedges(), 2 * m.n_edges());
}

#[test]
fn good_models_euler_and_invariants() {
    for &(name, v, e, f, chi, loops) in GOOD {
        let m = load(name);
        assert_eq!((m.n_vertices(), m.n_edges(), m.n_faces()), (v, e, f), "{name}");
        assert_eq!(m.euler_characteristic(), chi, "{name}");
        assert_eq!(m.boundary_loops().len(), loops, "{name}");
        assert_eq!(m.is_closed(), loops == 0, "{name}");
        assert!(m.warnings().is_empty(), "{name}");
        check_invariants(&m);
    }
}

#[test]
fn closed_models_genus() {
    // χ = 2 − 2g: torus g = 1, the rest g = 0
    for &(name, ..) in GOOD.iter().filter(|g| g.5 == 0) {
        let m = load(name);
        let g = (2 - m.euler_characteristic()) / 2;
        assert_eq!(g, i64::from(name == "torus.obj"), "{name}");
    }
}

/// Angle of `d` projected into the tangent plane with normal `n`, measured from `e1`.
fn angle_in_plane(d: DVec3, n: DVec3, e1: DVec3) -> f64 {
    let e2 = n.cross(e1);
    let d = d - n * d.dot(n);
    d.dot(e2).atan2(d.dot(e1))
}

#[test]
fn fans_turn_counter_clockwise_seen_from_outside() {
    // Convex closed models: the outward normal at a vertex is the position (centred at origin);
    // the neighbours in vertex_outgoing order have increasing angle (mod 2π) about it.
    for name in ["cube.obj", "dodecahedron.obj", "octahedron.obj", "pyramid.obj", "prism3.obj"] {
        let m = load(name);
        let c = m.positions().iter().sum::<DVec3>() / m.n_vertices() as f64;
        for v in m.vertices() {
            let n = (m.position(v) - c).normalize();
            let nb: Vec<DVec3> = m.vertex_vertices(v).map(|w| m.position(w) - m.position(v)).collect();
            let e1 = (nb[0] - n * nb[0].dot(n)).normalize();
            let mut total = 0.0;
            for i in 0..nb.len() {
                let a = angle_in_plane(nb[(i + 1) % nb.len()], n, e1) - angle_in_plane(nb[i], n, e1);
                let a = a.rem_euclid(std::f64::consts::TAU);
                assert!(a > 0.0 && a < std::f64::consts::PI, "{name} v{}", v.0);
                total += a;
            }
            gbsurf::assert_near!(total, std::f64::consts::TAU, 1e-9);
        }
    }
}

#[test]
fn grid_open_boundary() {
    let m = load("grid_open.obj");
    let loops = m.boundary_loops();
    assert_eq!(loops.len(), 1);
    assert_eq!(loops[0].len(), 16);
    for w in loops[0].windows(2) {
        assert_eq!(m.next(w[0]), w[1]);
        assert_eq!(m.target(w[0]), m.origin(w[1]));
    }
    let n_boundary = m.vertices().filter(|&v| m.is_boundary_vertex(v)).count();
    assert_eq!(n_boundary, 16);
    // corner vertices have valence 2 and one face, interior ones valence 4
    let valences: Vec<usize> = m.vertices().map(|v| m.valence(v)).collect();
    assert_eq!(valences.iter().filter(|&&k| k == 2).count(), 4);
    assert_eq!(valences.iter().filter(|&&k| k == 3).count(), 12);
    assert_eq!(valences.iter().filter(|&&k| k == 4).count(), 9);
    // boundary fans: faces of a boundary vertex are contiguous: consecutive faces share an edge
    for v in m.vertices().filter(|&v| m.is_boundary_vertex(v)) {
        let outs: Vec<_> = m.vertex_outgoing(v).collect();
        for w in outs[1..].windows(2) {
            // faces of w[0] and w[1] share the edge w[1]
            assert_eq!(m.face(m.twin(w[1])), m.face(w[0]));
        }
    }
}

#[test]
fn round_trip_polymesh() {
    for &(name, ..) in GOOD {
        let m = load(name);
        let p = m.to_polymesh();
        let m2 = HalfEdgeMesh::from_polymesh(&p).unwrap();
        assert_eq!(m2.to_polymesh(), p, "{name}");
        for f in m.faces() {
            assert_eq!(m.face_vertices(f).collect::<Vec<_>>(), m2.face_vertices(f).collect::<Vec<_>>());
        }
    }
}

#[test]
fn single_triangle_and_face_order() {
    let p = PolyMesh::new(
        vec![DVec3::ZERO, DVec3::X, DVec3::Y],
        vec![vec![0, 1, 2]],
    );
    let m = HalfEdgeMesh::from_polymesh(&p).unwrap();
    assert_eq!((m.n_vertices(), m.n_edges(), m.n_faces(), m.n_halfedges()), (3, 3, 1, 6));
    assert_eq!(m.face_vertices(FaceId(0)).map(|v| v.0).collect::<Vec<_>>(), vec![0, 1, 2]);
    for v in m.vertices() {
        assert!(m.is_boundary_vertex(v));
        assert_eq!(m.valence(v), 2);
        assert_eq!(m.vertex_faces(v).collect::<Vec<_>>(), vec![FaceId(0)]);
    }
    let loops = m.boundary_loops();
    assert_eq!(loops.len(), 1);
    // boundary loop runs opposite to the face: 0 → 2 → 1
    let lp: Vec<u32> = loops[0].iter().map(|&h| m.origin(h).0).collect();
    assert_eq!(lp.len(), 3);
    let k = lp.iter().position(|&x| x == 0).unwrap();
    assert_eq!([lp[k], lp[(k + 1) % 3], lp[(k + 2) % 3]], [0, 2, 1]);
    assert_eq!(m.vertex_halfedge(VertexId(0)), loops[0][k]);
}

use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    /// Arbitrary face lists never panic; whatever is accepted satisfies all invariants and
    /// round-trips.
    #[test]
    fn arbitrary_face_lists_never_panic(
        nv in 1usize..9,
        faces in prop::collection::vec(prop::collection::vec(0u32..10, 0..6), 0..10),
        seed in 0u64..1000,
    ) {
        let positions: Vec<DVec3> = (0..nv)
            .map(|i| {
                let a = (i as f64 + 1.0) * (seed as f64 + 1.3);
                DVec3::new(a.sin(), (1.7 * a).cos(), (0.3 * a).sin() * 2.0)
            })
            .collect();
        let p = PolyMesh::new(positions, faces);
        if let Ok(m) = HalfEdgeMesh::from_polymesh(&p) {
            check_invariants(&m);
            let q = m.to_polymesh();
            prop_assert_eq!(q.faces.len(), p.faces.len());
            prop_assert_eq!(HalfEdgeMesh::from_polymesh(&q).map(|m2| m2.to_polymesh()), Ok(q));
        }
    }

    /// Random text never panics the OBJ parser.
    #[test]
    fn obj_parser_never_panics(text in "([vf#g ]{0,2}[-0-9a-z./ ]{0,12}\n){0,12}") {
        let _ = gbsurf::mesh::io::parse_obj(&text);
    }

    /// Random bytes never panic the PLY/STL/OFF parsers.
    #[test]
    fn binary_parsers_never_panic(mut bytes in prop::collection::vec(any::<u8>(), 0..300), k in 0usize..3) {
        if k == 0 {
            let head = b"ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
            let mut b = head.to_vec();
            b.append(&mut bytes);
            let _ = gbsurf::mesh::io::parse_ply(&b);
        } else if k == 1 {
            let _ = gbsurf::mesh::io::parse_stl(&bytes);
        } else {
            let _ = gbsurf::mesh::io::parse_off(&bytes);
        }
    }
}
