//! One level of Catmull–Clark subdivision (seed 000 §1.2.1.2, eq. 1.1–1.2) with the usual
//! boundary rules; the rules and the output order are documented on [`super::catmull_clark()`].

use super::{check_size, first_halfedge, Corners, Level, LevelOutput, SubdivError};
use crate::mesh::PolyMesh;
use crate::progress::Ticker;
use glam::DVec3;

/// One level; the parent of output face `k` is the input face it lies in.
pub(super) fn level(level: &Level<'_>, ticker: &mut Ticker<'_>) -> Result<LevelOutput, SubdivError> {
    let (he, p, index) = (&*level.he, level.positions, &level.index);
    let (nv, ne, nf) = (p.len(), he.n_edges(), he.n_faces());
    check_size((nv + ne + nf) as u64)?;
    let corners = Corners::new(he);
    // Progress: face points, edge points, vertex points, faces (one item each).
    let total = 2 * nf + ne + nv;
    ticker.at(0, total)?;

    let face_points: Vec<DVec3> = he
        .faces()
        .map(|f| {
            ticker.at(f.idx(), total)?;
            let k = he.face_size(f) as f64;
            Ok(he.face_vertices(f)
                .map(|v| p[index[v.idx()] as usize])
                .sum::<DVec3>()
                / k)
        })
        .collect::<Result<_, crate::progress::Cancelled>>()?;

    let edge_points: Vec<DVec3> = he
        .edges()
        .map(|e| {
            ticker.at(nf + e.idx(), total)?;
            let h = first_halfedge(he, e);
            let (a, b) = (
                p[index[he.origin(h).idx()] as usize],
                p[index[he.target(h).idx()] as usize],
            );
            Ok(match he.face(he.twin(h)) {
                None => 0.5 * (a + b),
                Some(g) => {
                    let f = he.face(h).map_or(0, |f| f.idx());
                    0.25 * (a + b + face_points[f] + face_points[g.idx()])
                }
            })
        })
        .collect::<Result<_, crate::progress::Cancelled>>()?;

    // Unused vertices keep their positions.
    let mut positions = p.to_vec();
    for v in he.vertices() {
        ticker.at(nf + ne + v.idx(), total)?;
        let pv = he.position(v);
        let fan = corners.fan(he, v);
        let new = if he.is_boundary_vertex(v) {
            if fan.len() == 1 {
                pv
            } else {
                let a = he.position(he.target(fan[0]));
                let b = he.position(he.origin(he.prev(fan[fan.len() - 1])));
                (a + 6.0 * pv + b) / 8.0
            }
        } else {
            let n = fan.len() as f64;
            let mut q = DVec3::ZERO;
            let mut r = DVec3::ZERO;
            for &h in &fan {
                q += face_points[he.face(h).map_or(0, |f| f.idx())];
                r += 0.5 * (pv + he.position(he.target(h)));
            }
            (q / n + 2.0 * r / n + (n - 3.0) * pv) / n
        };
        positions[index[v.idx()] as usize] = new;
    }
    positions.extend(edge_points);
    positions.extend(face_points);

    let (e0, f0) = (nv as u32, (nv + ne) as u32);
    let mut faces = Vec::with_capacity(corners.count);
    let mut parent = Vec::with_capacity(corners.count);
    for f in he.faces() {
        ticker.at(nf + ne + nv + f.idx(), total)?;
        for h in he.face_halfedges(f) {
            faces.push(vec![
                index[he.origin(h).idx()],
                e0 + he.edge(h).0,
                f0 + f.0,
                e0 + he.edge(he.prev(h)).0,
            ]);
            parent.push(f.0);
        }
    }
    Ok((PolyMesh::new(positions, faces), parent))
}
