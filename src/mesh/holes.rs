//! Faces with holes (inner loops): their checks and the deterministic split into simple convex
//! faces (docs/math.md, "Faces with holes").
//!
//! A face with holes is an outer loop ([`PolyMesh::faces`]`[f]`, counter-clockwise seen from
//! outside) plus inner loops ([`PolyMesh::holes`] entries naming `f`) in the opposite
//! orientation. [`split_holes`] is applied by the one validator
//! ([`super::HalfEdgeMesh::from_polymesh`]) before anything else sees the mesh, so both GB
//! structures, the subdivision methods and every writer get proper faces only.
//!
//! Split rule: all loops of the face are projected into the best-fit plane of the outer loop;
//! their edges are the constraints of a constrained Delaunay triangulation (crate `spade`, the
//! well-kept CDT already in our dependency tree; a hand-written ear clipper with hole bridges
//! would need zero-width slits, which are no manifold faces). The triangles inside the outer
//! loop and outside every hole are then merged greedily (Hertel–Mehlhorn): the shared
//! diagonals are visited longest first (ties: smaller vertex pair first) and removed when both
//! of their ends stay strictly convex in the merged piece. Every piece is a convex simple
//! polygon over the face's own vertices (no new vertex, no slit), every diagonal is an edge of
//! exactly two pieces, so a closed two-manifold cage stays one; the existing concave split
//! ([`super::geometry::convexify`]) leaves these pieces unchanged.

use super::error::{HoleDefect, MeshError};
use super::geometry::best_fit_plane;
use super::PolyMesh;
use glam::{DVec2, DVec3};
use robust::{orient2d, Coord};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};
use std::collections::HashMap;

fn coord(p: DVec2) -> Coord<f64> {
    Coord { x: p.x, y: p.y }
}

/// Exact orientation of `c` against the line `a → b` (> 0: left).
fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    orient2d(coord(a), coord(b), coord(c))
}

/// Closed segments `ab` and `cd` share a point (exact predicates).
fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let (o1, o2, o3, o4) = (orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b));
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    let within = |p: DVec2, q: DVec2, r: DVec2| {
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    (o1 == 0.0 && within(a, b, c)) || (o2 == 0.0 && within(a, b, d)) || (o3 == 0.0 && within(c, d, a)) || (o4 == 0.0 && within(c, d, b))
}

/// `p` strictly inside the closed polygon `poly` (crossing number; points on an edge count as
/// outside).
fn strictly_inside(poly: &[DVec2], p: DVec2) -> bool {
    let n = poly.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if orient(a, b, p) == 0.0 && p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y) {
            return false;
        }
        if (a.y > p.y) != (b.y > p.y) {
            // the edge crosses the horizontal line through p: left of p?
            let left = if b.y > a.y { orient(a, b, p) < 0.0 } else { orient(a, b, p) > 0.0 };
            if left {
                inside = !inside;
            }
        }
    }
    inside
}

fn signed_area(p: &[DVec2]) -> f64 {
    let n = p.len();
    let o = p[0];
    (0..n).map(|i| (p[i] - o).perp_dot(p[(i + 1) % n] - o)).sum::<f64>() * 0.5
}

/// One face with its holes, projected.
struct Loops {
    /// Mesh vertex index of each local vertex (outer loop first, then the holes in order).
    keys: Vec<u32>,
    pts: Vec<DVec2>,
    /// Local index ranges of the loops (outer first).
    ranges: Vec<std::ops::Range<usize>>,
}

impl Loops {
    fn loop_pts(&self, l: usize) -> &[DVec2] {
        &self.pts[self.ranges[l].clone()]
    }
}

/// Checks the holes of face `f` (entries `holes` of [`PolyMesh::holes`]; the outer loop is
/// already valid) and projects the loops.
fn check_face(mesh: &PolyMesh, f: usize, holes: &[usize]) -> Result<Loops, MeshError> {
    let outer = &mesh.faces[f];
    let nv = mesh.positions.len();
    let err = |hole: usize, defect: HoleDefect| MeshError::Hole { face: f, hole, defect, line: None };
    let max = crate::limits::MAX_HOLED_FACE_CORNERS;
    let mut corners = outer.len();
    for &h in holes {
        corners = corners.saturating_add(mesh.holes[h].vertices.len());
        if corners > max {
            return Err(err(h, HoleDefect::TooManyCorners { corners, max }));
        }
    }
    let mut owner: HashMap<u32, Option<usize>> = outer.iter().map(|&v| (v, None)).collect();
    for &h in holes {
        let lp = &mesh.holes[h].vertices;
        if lp.len() < 3 {
            return Err(err(h, HoleDefect::TooSmall { len: lp.len() }));
        }
        for (corner, &v) in lp.iter().enumerate() {
            if v as usize >= nv {
                return Err(err(h, HoleDefect::IndexOutOfRange { corner, index: v as i64, n_vertices: nv }));
            }
            match owner.insert(v, Some(h)) {
                None => {}
                Some(Some(o)) if o == h => return Err(err(h, HoleDefect::RepeatedVertex { vertex: v as usize })),
                Some(other) => return Err(err(h, HoleDefect::SharedVertex { vertex: v as usize, other })),
            }
        }
    }
    let outer_pts: Vec<DVec3> = outer.iter().map(|&v| mesh.positions[v as usize]).collect();
    let Some(plane) = best_fit_plane(&outer_pts) else {
        return Err(MeshError::ZeroAreaFace { face: f, area: 0.0, line: None });
    };
    let mut keys: Vec<u32> = outer.clone();
    let mut ranges = vec![0..outer.len()];
    for &h in holes {
        let s = keys.len();
        keys.extend_from_slice(&mesh.holes[h].vertices);
        ranges.push(s..keys.len());
    }
    let pts = keys.iter().map(|&v| plane.to_2d(mesh.positions[v as usize])).collect();
    let lo = Loops { keys, pts, ranges };
    let outer2 = lo.loop_pts(0);
    for (k, &h) in holes.iter().enumerate() {
        let hp = lo.loop_pts(k + 1);
        let (lo_b, hi_b) = hp.iter().fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(l, u), p| (l.min(*p), u.max(*p)));
        let d = (hi_b - lo_b).max_element();
        let area = signed_area(hp);
        if area.abs() <= super::error::ZERO_AREA_REL * d * d {
            return Err(err(h, HoleDefect::ZeroArea { area: area.abs() }));
        }
        if area > 0.0 {
            return Err(err(h, HoleDefect::SameOrientation));
        }
        let n = hp.len();
        for i in 0..n {
            let (a, b) = (hp[i], hp[(i + 1) % n]);
            let m = outer2.len();
            if (0..m).any(|j| segments_meet(a, b, outer2[j], outer2[(j + 1) % m])) {
                return Err(err(h, HoleDefect::CrossesOuter { corner: i }));
            }
        }
        if let Some(c) = (0..n).find(|&i| !strictly_inside(outer2, hp[i])) {
            return Err(err(h, HoleDefect::Outside { vertex: mesh.holes[h].vertices[c] as usize }));
        }
        for (k2, &h2) in holes.iter().enumerate().take(k) {
            let qp = lo.loop_pts(k2 + 1);
            let m = qp.len();
            for i in 0..n {
                let (a, b) = (hp[i], hp[(i + 1) % n]);
                if (0..m).any(|j| segments_meet(a, b, qp[j], qp[(j + 1) % m])) {
                    return Err(err(h, HoleDefect::CrossesHole { other: h2 }));
                }
            }
            if strictly_inside(qp, hp[0]) || strictly_inside(hp, qp[0]) {
                return Err(err(h, HoleDefect::Nested { other: h2 }));
            }
        }
    }
    Ok(lo)
}

/// The convex pieces of one checked face with holes, as lists of mesh vertex indices (the
/// outer loop's orientation; each piece starts at its smallest vertex index; pieces sorted).
fn split_face(f: usize, lo: &Loops) -> Result<Vec<Vec<u32>>, MeshError> {
    let degenerate = |what: &str| MeshError::Degenerate(format!("face {f} with holes: {what}"));
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> = ConstrainedDelaunayTriangulation::new();
    let mut handles = Vec::with_capacity(lo.pts.len());
    for (i, p) in lo.pts.iter().enumerate() {
        let h = cdt.insert(Point2::new(p.x, p.y)).map_err(|e| degenerate(&format!("triangulation: {e:?}")))?;
        if h.index() != i {
            return Err(degenerate(&format!("vertex {} coincides with vertex {} in the face's plane", lo.keys[i], lo.keys[h.index()])));
        }
        handles.push(h);
    }
    for r in &lo.ranges {
        let n = r.len();
        for i in 0..n {
            let (a, b) = (r.start + i, r.start + (i + 1) % n);
            if cdt.try_add_constraint(handles[a], handles[b]).len() != 1 {
                return Err(degenerate(&format!("edge ({}, {}) passes through another loop", lo.keys[a], lo.keys[b])));
            }
        }
    }
    let holes: Vec<&[DVec2]> = (1..lo.ranges.len()).map(|l| lo.loop_pts(l)).collect();
    let outer = lo.loop_pts(0);
    let mut pieces: Vec<Vec<usize>> = Vec::new();
    for face in cdt.inner_faces() {
        let t = face.vertices().map(|v| v.fix().index());
        let c = (lo.pts[t[0]] + lo.pts[t[1]] + lo.pts[t[2]]) / 3.0;
        if strictly_inside(outer, c) && !holes.iter().any(|h| strictly_inside(h, c)) {
            pieces.push(t.to_vec());
        }
    }
    // Hertel–Mehlhorn twice (diagonals longest first, then shortest first); keep the result with
    // fewer pieces, on a tie the one with the larger smallest corner angle, on a tie longest first.
    let longest = merge_triangles(lo, &pieces, true);
    let shortest = merge_triangles(lo, &pieces, false);
    let score = |p: &Vec<Vec<usize>>| (p.len(), -min_angle(lo, p));
    let pieces = if score(&shortest) < score(&longest) { shortest } else { longest };
    let mut out: Vec<Vec<u32>> = pieces
        .into_iter()
        .map(|pc| {
            let k = (0..pc.len()).min_by_key(|&i| lo.keys[pc[i]]).unwrap_or(0);
            pc[k..].iter().chain(pc[..k].iter()).map(|&i| lo.keys[i]).collect()
        })
        .collect();
    out.sort();
    if out.is_empty() {
        return Err(degenerate("no piece inside the outer loop"));
    }
    Ok(out)
}

/// Hertel–Mehlhorn: merges the triangles (local indices, counter-clockwise) across their shared
/// diagonals, visited by length (`longest_first` or shortest first; ties: smaller vertex pair),
/// when both ends of the diagonal stay strictly convex.
fn merge_triangles(lo: &Loops, triangles: &[Vec<usize>], longest_first: bool) -> Vec<Vec<usize>> {
    let mut pieces: Vec<Option<Vec<usize>>> = triangles.iter().cloned().map(Some).collect();
    let mut edge_piece: HashMap<(usize, usize), usize> = HashMap::new();
    for (p, t) in triangles.iter().enumerate() {
        for i in 0..3 {
            edge_piece.insert((t[i], t[(i + 1) % 3]), p);
        }
    }
    let mut diagonals: Vec<(usize, usize)> =
        edge_piece.keys().filter(|&&(a, b)| a < b && edge_piece.contains_key(&(b, a))).copied().collect();
    let key = |&(a, b): &(usize, usize)| {
        let (ka, kb) = (lo.keys[a], lo.keys[b]);
        let d = lo.pts[a].distance_squared(lo.pts[b]);
        (if longest_first { -d } else { d }, ka.min(kb), ka.max(kb))
    };
    diagonals.sort_by(|x, y| key(x).partial_cmp(&key(y)).unwrap_or(std::cmp::Ordering::Equal));
    for (a, b) in diagonals {
        let (Some(&p), Some(&q)) = (edge_piece.get(&(a, b)), edge_piece.get(&(b, a))) else { continue };
        if p == q {
            continue;
        }
        let (Some(pp), Some(qq)) = (pieces[p].as_ref(), pieces[q].as_ref()) else { continue };
        // pp holds a → b; start it at b so it ends at a. qq holds b → a; start it at a.
        let rot = |v: &Vec<usize>, s: usize| -> Vec<usize> {
            let k = v.iter().position(|&x| x == s).unwrap_or(0);
            v[k..].iter().chain(v[..k].iter()).copied().collect()
        };
        let mut merged = rot(pp, b);
        let qr = rot(qq, a);
        merged.extend_from_slice(&qr[1..qr.len() - 1]);
        let n = merged.len();
        let convex_at = |k: usize| {
            let (u, v, w) = (lo.pts[merged[(k + n - 1) % n]], lo.pts[merged[k]], lo.pts[merged[(k + 1) % n]]);
            orient(u, v, w) > 0.0
        };
        let ia = pp.len() - 1; // position of a in merged
        if !(convex_at(0) && convex_at(ia)) {
            continue;
        }
        for i in 0..n {
            edge_piece.insert((merged[i], merged[(i + 1) % n]), p);
        }
        edge_piece.remove(&(a, b));
        edge_piece.remove(&(b, a));
        pieces[p] = Some(merged);
        pieces[q] = None;
    }
    pieces.into_iter().flatten().collect()
}

/// Smallest corner angle (radians) over the pieces.
fn min_angle(lo: &Loops, pieces: &[Vec<usize>]) -> f64 {
    let mut m = f64::INFINITY;
    for pc in pieces {
        let n = pc.len();
        for k in 0..n {
            let (u, v, w) = (lo.pts[pc[(k + n - 1) % n]], lo.pts[pc[k]], lo.pts[pc[(k + 1) % n]]);
            m = m.min((u - v).angle_to(w - v).abs());
        }
    }
    m
}

/// The result of [`split_holes`]: the mesh without holes and how its faces and their corners
/// map back to the input as the user wrote it.
#[derive(Clone, Debug, PartialEq)]
pub struct HoleSplit {
    /// The mesh of simple convex faces (no holes).
    pub mesh: PolyMesh,
    /// `origin[f]`: the input face that face `f` of [`Self::mesh`] is (a piece of). Face `f` of
    /// the input keeps its index (holding its first piece); further pieces are appended after the
    /// input faces in face order.
    pub origin: Vec<u32>,
    /// `corner[f][i]`: the user's corner index of corner i of face `f` of [`Self::mesh`] in its
    /// input face, numbered "outer loop 0..m−1, then the first hole's loop, then the second's …"
    /// (holes in [`PolyMesh::holes`] order); empty for a face without holes (its corners are
    /// numbered as written). The numbering of cage maps and per-corner values
    /// (docs/math.md#cage-corners).
    pub corner: Vec<Vec<u32>>,
}

/// Splits every face with holes into convex simple faces (see the module doc and
/// [`HoleSplit`]). The mesh's faces must already have passed the ordinary checks (outer loops
/// valid); errors name the face and the hole (an index into [`PolyMesh::holes`]).
pub fn split_holes(mesh: &PolyMesh) -> Result<HoleSplit, MeshError> {
    let nf = mesh.faces.len();
    let mut by_face: Vec<Vec<usize>> = vec![Vec::new(); nf];
    for (h, hole) in mesh.holes.iter().enumerate() {
        let Some(list) = by_face.get_mut(hole.face as usize) else {
            return Err(MeshError::HoleFaceOutOfRange { hole: h, face: hole.face as usize, n_faces: nf, line: None });
        };
        list.push(h);
    }
    let mut faces = mesh.faces.clone();
    let mut origin: Vec<u32> = (0..nf as u32).collect();
    let mut corner: Vec<Vec<u32>> = vec![Vec::new(); nf];
    for (f, holes) in by_face.iter().enumerate() {
        if holes.is_empty() {
            continue;
        }
        let lo = check_face(mesh, f, holes)?;
        // lo.keys lists the loops as the user wrote them (outer, then the holes in order), and a
        // vertex occurs once in them (checked), so its position there is its user corner.
        let user: HashMap<u32, u32> = lo.keys.iter().enumerate().map(|(i, &v)| (v, i as u32)).collect();
        let corners = |p: &[u32]| -> Vec<u32> { p.iter().map(|v| user[v]).collect() };
        let mut pieces = split_face(f, &lo)?.into_iter();
        if let Some(first) = pieces.next() {
            corner[f] = corners(&first);
            faces[f] = first;
        }
        for p in pieces {
            corner.push(corners(&p));
            faces.push(p);
            origin.push(f as u32);
        }
    }
    let mesh = PolyMesh { positions: mesh.positions.clone(), faces, creases: mesh.creases.clone(), holes: Vec::new() };
    Ok(HoleSplit { mesh, origin, corner })
}
