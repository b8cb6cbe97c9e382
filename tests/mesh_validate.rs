//! Checks 4–7 of `gbsurf::mesh::validate` (duplicate faces, non-manifold edges, inconsistent
//! orientation) against a literal, quadratic reading of their rules, and the half-edge
//! structure's edge numbering (edges in order of first use) against the same reading.

use gbsurf::mesh::{validate::check_polymesh, EdgeId, HalfEdgeMesh, MeshError, PolyMesh};
use gbsurf::DVec3;
use proptest::prelude::*;

/// The directed edges of a face, corner by corner.
fn edges(face: &[u32]) -> Vec<(u32, u32)> {
    (0..face.len()).map(|i| (face[i], face[(i + 1) % face.len()])).collect()
}

/// True when `b` is `a` rotated (same orientation).
fn rotated(a: &[u32], b: &[u32]) -> bool {
    a.len() == b.len() && (0..a.len()).any(|k| (0..a.len()).all(|i| a[i] == b[(i + k) % a.len()]))
}

/// Checks 4–7 read literally: faces in order, each compared with every earlier one.
fn oracle(faces: &[Vec<u32>]) -> Result<(), MeshError> {
    for f in 0..faces.len() {
        if let Some(g) = (0..f).find(|&g| rotated(&faces[g], &faces[f])) {
            return Err(MeshError::DuplicateFace { face: f, first: g, line: None });
        }
    }
    let key = |(a, b): (u32, u32)| (a.min(b), a.max(b));
    for face in faces {
        for e in edges(face) {
            let users: Vec<usize> =
                (0..faces.len()).filter(|&g| edges(&faces[g]).iter().any(|&d| key(d) == key(e))).collect();
            if users.len() > 2 {
                let k = key(e);
                return Err(MeshError::NonManifoldEdge { edge: (k.0 as usize, k.1 as usize), faces: users, line: None });
            }
        }
    }
    for f in 0..faces.len() {
        for e in edges(&faces[f]) {
            if let Some(g) = (0..f).find(|&g| edges(&faces[g]).contains(&e)) {
                return Err(MeshError::InconsistentOrientation { edge: (e.0 as usize, e.1 as usize), faces: (g, f), line: None });
            }
        }
    }
    for f in 0..faces.len() {
        let reversed: Vec<u32> = faces[f].iter().rev().copied().collect();
        if let Some(g) = (0..f).find(|&g| rotated(&faces[g], &reversed)) {
            return Err(MeshError::DuplicateFace { face: f, first: g, line: None });
        }
    }
    Ok(())
}

/// Points on a twisted curve: no three collinear, no four coplanar, so no face has zero area.
fn positions(n: usize) -> Vec<DVec3> {
    (0..n).map(|i| (i as f64 + 1.0) * 0.37).map(|t| DVec3::new(t, t * t, t * t * t)).collect()
}

/// A face list with repeats: `picks` choose faces of `pool`, each possibly reversed or rotated.
fn faces_from(pool: &[Vec<u32>], picks: &[(usize, bool, usize)]) -> Vec<Vec<u32>> {
    picks
        .iter()
        .map(|&(i, reverse, rot)| {
            let mut f = pool[i % pool.len()].clone();
            if reverse {
                f.reverse();
            }
            let r = rot % f.len();
            f.rotate_left(r);
            f
        })
        .collect()
}

/// Faces without repeated vertices over `nv` vertices.
fn pool(nv: u32) -> impl Strategy<Value = Vec<Vec<u32>>> {
    prop::collection::vec(prop::sample::subsequence((0..nv).collect::<Vec<u32>>(), 3..5).prop_shuffle(), 1..8)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    /// The first error of checks 4–7 (kind, face, edge and face list) is the literal rules'.
    #[test]
    fn checks_4_to_7_follow_their_rules(
        pool in pool(7),
        picks in prop::collection::vec((0usize..8, any::<bool>(), 0usize..5), 1..10),
    ) {
        let faces = faces_from(&pool, &picks);
        let mesh = PolyMesh::new(positions(7), faces.clone());
        let got = check_polymesh(&mesh);
        // Checks 1–3 (none should fire here) come first.
        prop_assume!(!matches!(got, Err(MeshError::ZeroAreaFace { .. } | MeshError::UnresolvableExtent { .. })));
        prop_assert_eq!(got, oracle(&faces));
    }

    /// Edges are numbered in order of first use: edge e's vertices are those of the e-th
    /// distinct undirected edge met reading the faces in order.
    #[test]
    fn edges_are_numbered_in_order_of_first_use(
        pool in pool(9),
        picks in prop::collection::vec((0usize..8, any::<bool>(), 0usize..5), 1..8),
    ) {
        let faces = faces_from(&pool, &picks);
        let mesh = PolyMesh::new(positions(9), faces.clone());
        if let Ok(m) = HalfEdgeMesh::from_polymesh(&mesh) {
            let mut order: Vec<(u32, u32)> = Vec::new();
            for face in &faces {
                for (a, b) in edges(face) {
                    if !order.contains(&(a.min(b), a.max(b))) {
                        order.push((a.min(b), a.max(b)));
                    }
                }
            }
            prop_assert_eq!(m.n_edges(), order.len());
            for (e, &(a, b)) in order.iter().enumerate() {
                let (x, y) = m.edge_vertices(EdgeId(e as u32));
                let (x, y) = (m.original_vertex(x) as u32, m.original_vertex(y) as u32);
                prop_assert_eq!((x.min(y), x.max(y)), (a, b), "edge {}", e);
            }
        }
    }
}

/// A vertex of valence 40 (more than the pairwise scan's bucket size): a fan of triangles,
/// then the same fan with one triangle repeated, and with a third face on one of its edges.
#[test]
fn high_valence_fan() {
    let n = 40u32;
    let fan: Vec<Vec<u32>> = (0..n).map(|i| vec![0, 1 + i, 1 + (i + 1) % n]).collect();
    let mut pos = vec![DVec3::new(0.0, 0.0, 1.0)];
    pos.extend((0..n).map(|i| {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        DVec3::new(a.cos(), a.sin(), 0.0)
    }));
    pos.push(DVec3::new(0.3, 0.2, -1.0));
    let mesh = |faces: Vec<Vec<u32>>| PolyMesh::new(pos.clone(), faces);
    assert_eq!(check_polymesh(&mesh(fan.clone())), Ok(()));
    let mut dup = fan.clone();
    dup.push(vec![5, 6, 0]);
    assert_eq!(check_polymesh(&mesh(dup.clone())), oracle(&dup));
    assert!(matches!(check_polymesh(&mesh(dup)), Err(MeshError::DuplicateFace { face: 40, first: 4, .. })));
    let mut fin = fan;
    fin.push(vec![0, 7, n + 1]);
    assert_eq!(check_polymesh(&mesh(fin.clone())), oracle(&fin));
    let fin_faces = vec![5, 6, 40];
    assert!(matches!(check_polymesh(&mesh(fin)), Err(MeshError::NonManifoldEdge { edge: (0, 7), faces, .. }) if faces == fin_faces));
}
