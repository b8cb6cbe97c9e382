//! Catmull–Clark subdivision (seed 000 §1.2.1.2, eq. 1.1–1.2) with the usual boundary rules.

use super::topology::Topology;
use super::{check_size, SubdivError};
use crate::mesh::PolyMesh;
use glam::DVec3;

/// Catmull–Clark subdivision, `levels` times, on any polygon mesh (n-gons allowed, open or closed).
///
/// One level, with `n` the valence of vertex `V`:
/// - face point `F` = centroid of the face's vertices;
/// - interior edge point = `(a + b + F₀ + F₁)/4`; boundary edge point = midpoint `(a + b)/2`;
/// - interior vertex: `V' = (Q + 2R + (n−3)V)/n`, `Q` = mean of the adjacent face points,
///   `R` = mean of the adjacent edge *midpoints* (seed 000 eq. 1.1 read with midpoints);
/// - boundary vertex with boundary neighbours `a`, `b`: `V' = (a + 6V + b)/8` (cubic B-spline);
/// - corner (boundary vertex in a single face, valence 2): `V' = V`;
/// - unused vertices are kept unchanged.
///
/// Each face of size k becomes k quads `[V', E'(i), F, E'(i−1)]` (eq. 1.2), with the original
/// orientation. Output vertex order: vertex points (same indices as the input), then edge points
/// (edges by first appearance in the face list), then face points (face order).
/// Counts: `V' = V + E + F`, `F' = Σ|f|`, `E' = 2E + Σ|f|`.
pub fn catmull_clark(mesh: &PolyMesh, levels: u32) -> Result<PolyMesh, SubdivError> {
    let mut current = mesh.clone();
    if levels == 0 {
        Topology::new(mesh)?;
    }
    for _ in 0..levels {
        current = catmull_clark_once(&current)?;
    }
    Ok(current)
}

fn catmull_clark_once(mesh: &PolyMesh) -> Result<PolyMesh, SubdivError> {
    let topo = Topology::new(mesh)?;
    let p = &mesh.positions;
    let (nv, ne, nf) = (p.len(), topo.edges.len(), topo.face_count());
    check_size((nv + ne + nf) as u64)?;

    let face_points: Vec<DVec3> = (0..nf)
        .map(|f| {
            let corners = topo.face_corners(f);
            let k = corners.len() as f64;
            corners
                .map(|c| p[topo.corner_vertex[c] as usize])
                .sum::<DVec3>()
                / k
        })
        .collect();

    let edge_points: Vec<DVec3> = topo
        .edges
        .iter()
        .map(|e| {
            let (a, b) = (p[e.v[0] as usize], p[e.v[1] as usize]);
            if e.is_boundary() {
                0.5 * (a + b)
            } else {
                0.25 * (a + b + face_points[e.faces[0] as usize] + face_points[e.faces[1] as usize])
            }
        })
        .collect();

    let vertex_points: Vec<DVec3> = (0..nv)
        .map(|v| {
            let fan = &topo.fans[v];
            let pv = p[v];
            if fan.corners.is_empty() {
                return pv;
            }
            if fan.boundary {
                if fan.corners.len() == 1 {
                    return pv;
                }
                let first = fan.corners[0];
                let last = *fan.corners.last().unwrap();
                let a = p[topo.corner_vertex[topo.next(first) as usize] as usize];
                let b = p[topo.corner_vertex[topo.prev(last) as usize] as usize];
                return (a + 6.0 * pv + b) / 8.0;
            }
            let n = fan.corners.len() as f64;
            let mut q = DVec3::ZERO;
            let mut r = DVec3::ZERO;
            for &c in &fan.corners {
                q += face_points[topo.corner_face[c as usize] as usize];
                let other = p[topo.corner_vertex[topo.next(c) as usize] as usize];
                r += 0.5 * (pv + other);
            }
            (q / n + 2.0 * r / n + (n - 3.0) * pv) / n
        })
        .collect();

    let mut positions = vertex_points;
    positions.extend(edge_points);
    positions.extend(face_points);

    let (e0, f0) = (nv as u32, (nv + ne) as u32);
    let mut faces = Vec::with_capacity(topo.corner_vertex.len());
    for f in 0..nf {
        for c in topo.face_corners(f) {
            let c32 = c as u32;
            faces.push(vec![
                topo.corner_vertex[c],
                e0 + topo.corner_edge[c],
                f0 + f as u32,
                e0 + topo.corner_edge[topo.prev(c32) as usize],
            ]);
        }
    }
    Ok(PolyMesh::new(positions, faces))
}
