//! One level of Doo–Sabin subdivision (seed 000 §1.2.1.1) with the original Doo–Sabin weights
//! and a Chaikin boundary rule for open meshes; the rules and the output order are documented on
//! [`super::doo_sabin()`].

use super::{check_size, first_halfedge, Corners, Level, LevelOutput, SubdivError};
use crate::mesh::PolyMesh;
use crate::progress::Ticker;
use glam::DVec3;
use std::f64::consts::TAU;

/// Doo–Sabin weight `α_k` for an n-sided face (Doo and Sabin 1978):
/// `α_0 = 1/4 + 5/(4n)`, `α_k = (3 + 2cos(2πk/n))/(4n)` for `k = 1..n−1`; they sum to 1.
pub fn doo_sabin_weights(n: usize) -> Vec<f64> {
    let nf = n as f64;
    (0..n)
        .map(|k| {
            if k == 0 {
                0.25 + 5.0 / (4.0 * nf)
            } else {
                (3.0 + 2.0 * (TAU * k as f64 / nf).cos()) / (4.0 * nf)
            }
        })
        .collect()
}

/// One level; the parent of an output face is the face of its first new corner point.
pub(super) fn level(level: &Level<'_>, ticker: &mut Ticker<'_>) -> Result<LevelOutput, SubdivError> {
    let (he, index) = (&*level.he, &level.index);
    let corners = Corners::new(he);
    let nc = corners.count;
    // Progress: corner points and F-faces per face, E-faces per edge, V-faces per vertex.
    let (nf, ne) = (he.n_faces(), he.n_edges());
    let total = 2 * nf + ne + he.n_vertices();
    ticker.at(0, total)?;

    // Boundary edges get consecutive numbers for their two Chaikin points.
    const NONE: u32 = u32::MAX;
    let mut boundary_index = vec![NONE; he.n_edges()];
    let mut nb = 0u32;
    for e in he.edges().filter(|&e| he.is_boundary_edge(e)) {
        boundary_index[e.idx()] = nb;
        nb += 1;
    }
    check_size(nc as u64 + 2 * nb as u64)?;

    let mut positions = Vec::with_capacity(nc + 2 * nb as usize);
    for f in he.faces() {
        ticker.at(f.idx(), total)?;
        let verts: Vec<DVec3> = he.face_vertices(f).map(|v| he.position(v)).collect();
        let n = verts.len();
        let alpha = doo_sabin_weights(n);
        for i in 0..n {
            let q = (0..n)
                .map(|j| alpha[(j + n - i) % n] * verts[j])
                .sum::<DVec3>();
            positions.push(q);
        }
    }
    for e in he.edges().filter(|&e| he.is_boundary_edge(e)) {
        let h = first_halfedge(he, e);
        let (a, b) = (he.position(he.origin(h)), he.position(he.target(h)));
        positions.push(0.75 * a + 0.25 * b);
        positions.push(0.25 * a + 0.75 * b);
    }
    let chaikin = |e: crate::mesh::EdgeId, near_end: u32| -> u32 {
        nc as u32 + 2 * boundary_index[e.idx()] + near_end
    };
    let face_of = |h| he.face(h).map_or(0, |f| f.0);

    let mut faces: Vec<Vec<u32>> = Vec::new();
    let mut parent: Vec<u32> = Vec::new();
    // F-faces.
    for f in he.faces() {
        ticker.at(nf + f.idx(), total)?;
        faces.push(he.face_halfedges(f).map(|h| corners.of(h)).collect());
        parent.push(f.0);
    }
    // E-faces: edge a → b in f, b → a in g: [P(f,b), P(f,a), P(g,a), P(g,b)].
    for e in he.edges().filter(|&e| !he.is_boundary_edge(e)) {
        ticker.at(2 * nf + e.idx(), total)?;
        let fa = first_halfedge(he, e);
        let gb = he.twin(fa);
        faces.push(vec![
            corners.of(he.next(fa)),
            corners.of(fa),
            corners.of(he.next(gb)),
            corners.of(gb),
        ]);
        parent.push(face_of(fa));
    }
    // Boundary-edge quads: [P(f,b), P(f,a), C(a), C(b)].
    for e in he.edges().filter(|&e| he.is_boundary_edge(e)) {
        let fa = first_halfedge(he, e);
        faces.push(vec![
            corners.of(he.next(fa)),
            corners.of(fa),
            chaikin(e, 0),
            chaikin(e, 1),
        ]);
        parent.push(face_of(fa));
    }
    // V-faces.
    for v in he.vertices() {
        ticker.at(2 * nf + ne + v.idx(), total)?;
        let fan = corners.fan(he, v);
        let (first, last) = (fan[0], fan[fan.len() - 1]);
        if he.is_boundary_vertex(v) {
            let mut face = vec![chaikin(he.edge(first), 0)];
            face.extend(fan.iter().map(|&h| corners.of(h)));
            face.push(chaikin(he.edge(he.prev(last)), 1));
            faces.push(face);
        } else if fan.len() >= 3 {
            faces.push(fan.iter().map(|&h| corners.of(h)).collect());
        } else {
            // An interior vertex of valence 2 (two faces sharing two consecutive edges) would
            // give a two-sided V-face, which a polygon mesh cannot hold.
            return Err(SubdivError::InteriorValenceTwo {
                vertex: index[v.idx()] as usize,
            });
        }
        parent.push(face_of(first));
    }
    Ok((PolyMesh::new(positions, faces), parent))
}
