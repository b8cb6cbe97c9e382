//! Doo–Sabin subdivision (seed 000 §1.2.1.1) with the original Doo–Sabin weights and a
//! Chaikin boundary rule for open meshes.

use super::topology::{Topology, NONE};
use super::{check_size, SubdivError};
use crate::mesh::PolyMesh;
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

/// Doo–Sabin subdivision, `levels` times, on any polygon mesh (n-gons allowed, open or closed).
///
/// One level: every corner `i` of an n-sided face gets the new point `Σ_j α_{(j−i) mod n} v_j`
/// ([`doo_sabin_weights`]). New faces, all oriented like the input:
/// - F-face: per face, its n new corner points;
/// - E-face: per interior edge, the quad of the four new points at its ends;
/// - V-face: per interior vertex of valence k, the k new points around it.
///
/// Open meshes (our choice; the seeds leave it open): the new boundary is Chaikin's corner
/// cutting of the old boundary polygon, so the limit boundary is the quadratic B-spline of the
/// boundary polygon. Each boundary edge `a → b` gets two new points `3/4·a + 1/4·b` and
/// `1/4·a + 3/4·b` and a quad joining them to the two new points of its face at `a` and `b`;
/// each boundary vertex with k faces gets a (k+2)-gon: the Chaikin point on its outgoing
/// boundary edge, its k new face points in counter-clockwise order, and the Chaikin point on its
/// incoming boundary edge (a triangle at a corner of a single face, which is cut off like every
/// other boundary vertex). Unused vertices disappear.
///
/// Output vertex order: new corner points (faces in order, corners in order), then the two
/// Chaikin points of each boundary edge. Face order: F-faces, E-faces, boundary-edge quads,
/// V-faces (vertex order, interior and boundary).
/// Counts on a closed mesh: `V' = Σ|f| = 2E`, `E' = 4E`, `F' = F + E + V`.
pub fn doo_sabin(mesh: &PolyMesh, levels: u32) -> Result<PolyMesh, SubdivError> {
    let mut current = mesh.clone();
    if levels == 0 {
        Topology::new(mesh)?;
    }
    for _ in 0..levels {
        current = doo_sabin_once(&current)?;
    }
    Ok(current)
}

fn doo_sabin_once(mesh: &PolyMesh) -> Result<PolyMesh, SubdivError> {
    let topo = Topology::new(mesh)?;
    let p = &mesh.positions;
    let nc = topo.corner_vertex.len();

    // Boundary edges get consecutive numbers for their two Chaikin points.
    let mut boundary_index = vec![NONE; topo.edges.len()];
    let mut nb = 0u32;
    for (e, edge) in topo.edges.iter().enumerate() {
        if edge.is_boundary() {
            boundary_index[e] = nb;
            nb += 1;
        }
    }
    check_size(nc as u64 + 2 * nb as u64)?;

    let mut positions = Vec::with_capacity(nc + 2 * nb as usize);
    for f in 0..topo.face_count() {
        let corners = topo.face_corners(f);
        let n = corners.len();
        let alpha = doo_sabin_weights(n);
        let verts: Vec<DVec3> = corners
            .clone()
            .map(|c| p[topo.corner_vertex[c] as usize])
            .collect();
        for i in 0..n {
            let q = (0..n)
                .map(|j| alpha[(j + n - i) % n] * verts[j])
                .sum::<DVec3>();
            positions.push(q);
        }
    }
    for edge in topo.edges.iter().filter(|e| e.is_boundary()) {
        let (a, b) = (p[edge.v[0] as usize], p[edge.v[1] as usize]);
        positions.push(0.75 * a + 0.25 * b);
        positions.push(0.25 * a + 0.75 * b);
    }
    let chaikin = |e: u32, near_end: usize| -> u32 {
        nc as u32 + 2 * boundary_index[e as usize] + near_end as u32
    };

    let mut faces: Vec<Vec<u32>> = Vec::new();
    // F-faces.
    for f in 0..topo.face_count() {
        faces.push(topo.face_corners(f).map(|c| c as u32).collect());
    }
    // E-faces: edge a → b in f, b → a in g: [P(f,b), P(f,a), P(g,a), P(g,b)].
    for edge in topo.edges.iter().filter(|e| !e.is_boundary()) {
        let [fa, gb] = edge.corners;
        faces.push(vec![topo.next(fa), fa, topo.next(gb), gb]);
    }
    // Boundary-edge quads: [P(f,b), P(f,a), C(a), C(b)].
    for (e, edge) in topo
        .edges
        .iter()
        .enumerate()
        .filter(|(_, e)| e.is_boundary())
    {
        let fa = edge.corners[0];
        faces.push(vec![
            topo.next(fa),
            fa,
            chaikin(e as u32, 0),
            chaikin(e as u32, 1),
        ]);
    }
    // V-faces.
    for fan in topo.fans.iter().filter(|fan| !fan.corners.is_empty()) {
        if fan.boundary {
            let first = fan.corners[0];
            let last = *fan.corners.last().unwrap();
            let mut face = vec![chaikin(topo.corner_edge[first as usize], 0)];
            face.extend(&fan.corners);
            face.push(chaikin(topo.corner_edge[topo.prev(last) as usize], 1));
            faces.push(face);
        } else if fan.corners.len() >= 3 {
            faces.push(fan.corners.clone());
        } else {
            // An interior vertex of valence 2 (two faces sharing two consecutive edges) would
            // give a two-sided V-face, which a polygon mesh cannot hold.
            return Err(SubdivError::InteriorValenceTwo {
                vertex: topo.corner_vertex[fan.corners[0] as usize] as usize,
            });
        }
    }
    Ok(PolyMesh::new(positions, faces))
}
