//! Topology-preserving structure (seed 000 §3): one ribbon-only (CGB) patch per mesh face, curves
//! along the mesh edges built from auxiliary "tiles" around the mesh vertices.
//!
//! Tiles (§3.3.1). Every edge (p, q) gets the split points p + (q − p)/w and q + (p − q)/w (w > 2).
//! In a face p_0..p_{m−1} with edges E_k = (p_k, p_{k+1}), let a_k be E_k's split point near p_k and
//! b_k the one near p_{k+1}. The division line of E_k joins b_{k−1} to a_{k+1} ("the first point of
//! an edge with the second point of the edge two before"); the tile vertex of p_k in this face is
//! the intersection of the division lines of E_{k−1} and E_k, computed in the face's best-fit plane
//! (Newell normal through the centroid; the 3D point is the mean of the two lines' points at the
//! 2D solution, so it lies on the face for planar faces). If the lines are parallel the mean of
//! b_{k−1} and a_k is used.
//!
//! The tile of vertex v joins its tile vertices of the faces around v (counter-clockwise). At a
//! boundary vertex (not in the seed; defined here) the tile also contains the split points of the
//! two boundary edges at v: [e_0, t_0, …, t_{n−2}, e_{n−1}].
//!
//! Best tile plane (§3.3.2, eq. 3.1–3.6): centre p = mean of the tile points, normal
//! n_p = Σ (q_i − p) × (q_{i+1} − p) normalized; with `best_plane` the tile points are projected:
//! Q' = Q − ((Q − p)·n) n. Where that plane would fold the network (the projected curve tangents
//! at p out of counter-clockwise order: strongly bent tiles), the normal is tilted just enough to
//! order them, and a tile that no plane can order is a [`ConstructError::FoldedTile`]
//! (see `fan_normal`). At an interior vertex whose plane leaves a tile vertex out of order, the
//! plane that orders the tile vertices too, interleaved with the tangents (t_k between m_{k−1}
//! and m_k), replaces it where it keeps the tangents' margin (not in the seed: saddle tiles,
//! docs/math.md#topology).
//!
//! Curves (§3.3.3): the curve of edge (u, v) has C0 = centre of tile u, C1 = midpoint of tile u's
//! edge across (u, v), C2 = the same for tile v, C3 = centre of tile v. All tangents at a tile
//! centre lie in the tile plane. The tile edge across the edge of outgoing half-edge h joins the
//! tile vertex in face(twin h) and the one in face(h) (a boundary split point where there is no
//! face), so an open mesh gets its boundary curves along the boundary edges the same way.
//!
//! Patches (§3.4): face p_0..p_{m−1} gives an m-sided CGB patch; side i runs along edge
//! (p_{i−1}, p_i), corner i is the centre of tile p_i. First-approximation twist at corner i: the
//! tile vertex of p_i in this face (§3.4.1), shared by both sides of the corner.
//!
//! CGB and G1: on side i the other ribbons' weights vanish to second order (squared correction
//! weights for the neighbours, B³_0, B³_1 at h = 1 for the far sides) and ∂B_sum/∂h_i = 0, so the
//! normalized patch (eq. 3.8) has ribbon i's cross-derivative along side i; measured with the
//! `gb` CGB evaluator the normal angle across shared sides is ≤ 4e-13° on all test models
//! (tests/construct_g1.rs).
//!
//! D_{0.5} (§4.4.5): the vector from the centre of the edge's "edge tile" (the quad of the four
//! tile vertices next to the edge, a Doo–Sabin edge face) to the midpoint of its side in the face,
//! times three (as a first chord of a cubic): with M_f, M_g the midpoints of the two tile vertices
//! of the edge in faces f and g, D_{0.5} = 3 · (M_f − M_g)/2, pointing into f's patch.

use super::network::{CurveNetwork, PatchLayout, SideUse};
use super::surface::{PatchSource, Surface};
use super::{check_options, ConstructError};
use crate::options::ConvertOptions;
use crate::mesh::geometry::newell_normal;
use crate::mesh::{EdgeId, FaceId, HalfEdgeMesh, HalfedgeId};
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// Tile geometry of a mesh: per half-edge h with a face, the tile vertex of origin(h) in face(h);
/// per boundary half-edge-adjacent outgoing h, the split point on its edge; tile centres/normals.
#[derive(Clone, Debug, PartialEq)]
pub struct Tiles {
    /// `vertex[h]`: tile vertex of origin(h) in face(h) (unused for boundary half-edges).
    pub vertex: Vec<DVec3>,
    /// `split[h]`: the split point origin(h) + (target(h) − origin(h))/w, projected into the tile
    /// plane of origin(h) when `best_plane` (used only on boundary edges).
    pub split: Vec<DVec3>,
    /// Tile centre of each mesh vertex.
    pub center: Vec<DVec3>,
    /// Unit normal of each tile's best-fit plane.
    pub normal: Vec<DVec3>,
}

/// Intersection of the lines a0 + s(a1 − a0) and b0 + t(b1 − b0) in the plane (c, n).
fn intersect_in_plane(a0: DVec3, a1: DVec3, b0: DVec3, b1: DVec3, c: DVec3, n: DVec3) -> Option<DVec3> {
    let ex = n.any_orthonormal_vector();
    let ey = n.cross(ex);
    let p2 = |p: DVec3| DVec2::new((p - c).dot(ex), (p - c).dot(ey));
    let (pa, da) = (p2(a0), p2(a1) - p2(a0));
    let (pb, db) = (p2(b0), p2(b1) - p2(b0));
    let den = da.perp_dot(db);
    if den.abs() <= 1e-12 * da.length() * db.length() {
        return None;
    }
    let w = pb - pa;
    let s = w.perp_dot(db) / den;
    let t = w.perp_dot(da) / den;
    Some(0.5 * (a0 + s * (a1 - a0) + b0 + t * (b1 - b0)))
}

/// Tiles of seed 000 §3.3.1–3.3.2 (see the module doc).
pub fn tiles(mesh: &HalfEdgeMesh, opts: &ConvertOptions) -> Result<Tiles, ConstructError> {
    check_options(opts)?;
    let w = opts.tile_depth;
    let nh = mesh.n_halfedges();
    let pos = |h: HalfedgeId| (mesh.position(mesh.origin(h)), mesh.position(mesh.target(h)));
    // Split points: near[h] = origin + (target − origin)/w.
    let near = |h: HalfedgeId| {
        let (p, q) = pos(h);
        p + (q - p) / w
    };
    // Tile vertices per face in parallel (each face sets only its own half-edges); collected in
    // face order, the first degenerate face is reported.
    // Half-edge and corner buffers per worker, reused over its faces.
    let per_face: Vec<Result<Vec<(HalfedgeId, DVec3)>, ConstructError>> = (0..mesh.n_faces() as u32)
        .into_par_iter()
        .map_init(|| (Vec::new(), Vec::new()), |(hs, pts): &mut (Vec<HalfedgeId>, Vec<DVec3>), f| {
            let f = FaceId(f);
            hs.clear();
            hs.extend(mesh.face_halfedges(f));
            let m = hs.len();
            pts.clear();
            pts.extend(hs.iter().map(|&h| pos(h).0));
            let c = pts.iter().copied().sum::<DVec3>() / m as f64;
            let n = newell_normal(pts);
            let scale = pts.iter().map(|p| (*p - c).length_squared()).fold(0.0, f64::max);
            if !(n.length() > 1e-14 * scale) {
                return Err(ConstructError::DegenerateFace { face: f.idx() });
            }
            let n = n.normalize();
            let a = |k: usize| near(hs[k % m]); // a_k near p_k on E_k
            let b = |k: usize| near(mesh.twin(hs[k % m])); // b_k near p_{k+1} on E_k
            Ok((0..m)
                .map(|k| {
                    // Division line of E_j: b_{j−1} → a_{j+1}.
                    let (km1, km2) = ((k + m - 1) % m, (k + m - 2) % m);
                    let (l0, l1) = (b(km2), a(k)); // E_{k−1}
                    let (r0, r1) = (b(km1), a(k + 1)); // E_k
                    (hs[k], intersect_in_plane(l0, l1, r0, r1, c, n).unwrap_or_else(|| 0.5 * (b(km1) + a(k))))
                })
                .collect())
        })
        .collect();
    let mut vertex = vec![DVec3::ZERO; nh];
    for r in per_face {
        for (h, p) in r? {
            vertex[h.idx()] = p;
        }
    }
    let mut split: Vec<DVec3> = mesh.halfedges().map(near).collect();
    let mut center = Vec::with_capacity(mesh.n_vertices());
    let mut normal = Vec::with_capacity(mesh.n_vertices());
    // Ring and corner buffers reused over the vertices.
    let (mut out, mut ring, mut pts) = (Vec::new(), Vec::new(), Vec::new());
    for v in mesh.vertices() {
        tile_ring(mesh, v, &mut out, &mut ring);
        pts.clear();
        pts.extend(ring.iter().map(|&(h, is_split)| if is_split { split[h.idx()] } else { vertex[h.idx()] }));
        let p = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
        let nn = newell_normal(&pts);
        let scale = pts.iter().map(|q| (*q - p).length_squared()).fold(0.0, f64::max);
        if !(nn.length() > 1e-14 * scale) {
            return Err(ConstructError::DegenerateTile { vertex: v.idx() });
        }
        let closed = !mesh.is_boundary_vertex(v);
        let newell = nn.normalize();
        let mut nn = fan_normal(p, &pts, closed, newell, false).ok_or(ConstructError::FoldedTile { vertex: v.idx() })?;
        if closed && !tile_ordered(p, &pts, nn) {
            // Tile vertices out of order (docs/math.md#topology): the plane that orders them too,
            // turned from nn, if it keeps the tangents at least as far from folding.
            let tangents = fan_corners(&fan_dirs(p, &pts, true, false), true);
            if let Some(n1) = fan_normal(p, &pts, closed, nn, true) {
                if fan_margin(&tangents, n1) >= fan_margin(&tangents, nn) {
                    nn = n1;
                }
            }
        }
        if opts.best_plane {
            for &(h, is_split) in &ring {
                let q = if is_split { &mut split[h.idx()] } else { &mut vertex[h.idx()] };
                *q -= nn * nn.dot(*q - p);
            }
        }
        center.push(p);
        normal.push(nn);
    }
    Ok(Tiles { vertex, split, center, normal })
}

/// Whether the closed fan `dirs`, projected along the unit normal `n`, turns once around (its
/// counter-clockwise angle steps sum to 2π, within 1 rad).
fn one_turn(dirs: &[DVec3], n: DVec3) -> bool {
    let ex = n.any_orthonormal_vector();
    let ey = n.cross(ex);
    let m = dirs.len();
    let ang: Vec<f64> = dirs.iter().map(|d| d.dot(ey).atan2(d.dot(ex))).collect();
    let turn: f64 = (0..m).map(|k| (ang[(k + 1) % m] - ang[k]).rem_euclid(std::f64::consts::TAU)).sum();
    (turn - std::f64::consts::TAU).abs() < 1.0
}

/// Whether the plane of unit normal `n` puts the closed tile `ring` (centre p) in order: the
/// interleaved fan t_0, m_0, t_1, … ([`fan_dirs`]) turns counter-clockwise at every corner, once.
fn tile_ordered(p: DVec3, ring: &[DVec3], n: DVec3) -> bool {
    let dirs = fan_dirs(p, ring, true, true);
    fan_margin(&fan_corners(&dirs, true), n) > 0.0 && one_turn(&dirs, n)
}

/// The margin of the plane of unit normal `n` for a fan with corner normals `corners`
/// ([`fan_corners`]): min_k n · ĉ_k (+∞ without corners); > 0 iff every corner turns
/// counter-clockwise in the projection.
fn fan_margin(corners: &[DVec3], n: DVec3) -> f64 {
    corners.iter().map(|c| c.dot(n)).fold(f64::INFINITY, f64::min)
}

/// Margin a tile plane must keep, if it can, for the fan of curve tangents at the tile centre:
/// min_k n · ĉ_k ≥ 0.02 (ĉ_k the unit normal of corner k, see [`fan_normal`]), i.e. every
/// corner of the fan is a proper (non-flat) angle in the projection.
const FAN_MARGIN: f64 = 0.02;

/// Directions of the fan at a tile centre p: the midpoints m_k − p of the tile edges (the
/// curves' C1, seed 000 §3.3.3); with `vertices` (closed tiles only) the tile vertices t_k − p
/// interleaved, t_k before m_k (m_k is the midpoint of t_k t_{k+1}).
fn fan_dirs(p: DVec3, ring: &[DVec3], closed: bool, vertices: bool) -> Vec<DVec3> {
    let m = ring.len();
    let ne = if closed { m } else { m - 1 };
    let mid = |k: usize| 0.5 * (ring[k] + ring[(k + 1) % m]) - p;
    if closed && vertices {
        (0..ne).flat_map(|k| [ring[k] - p, mid(k)]).collect()
    } else {
        (0..ne).map(mid).collect()
    }
}

/// Unit normals ĉ_k = (d_k × d_{k+1}) / |…| of the corners of the fan `dirs` ([`fan_dirs`]),
/// corner k between directions k and k+1 (cyclic for an interior vertex, an open chain at a
/// boundary). Corners whose directions are parallel are left out (they give no direction).
fn fan_corners(dirs: &[DVec3], closed: bool) -> Vec<DVec3> {
    let ne = dirs.len();
    let nc = if closed { ne } else { ne.saturating_sub(1) };
    (0..nc)
        .filter_map(|k| {
            let (a, b) = (dirs[k], dirs[(k + 1) % ne]);
            let c = a.cross(b);
            (c.length() > 1e-12 * a.length() * b.length()).then(|| c.normalize())
        })
        .collect()
}

/// The normal of the best tile plane (seed 000 §3.3.2), made safe against folds.
///
/// Projected along n, the curve tangents m_k − p at the tile centre are in counter-clockwise order,
/// one turn, iff n · ĉ_k > 0 for every corner (projection keeps n · (a × b)) and the projected
/// corner angles sum to 2π. The starting plane `start` (the seed's: the tile's Newell normal) is kept when its
/// margin min_k n · ĉ_k reaches min([`FAN_MARGIN`], m*/2), m* the best margin of any plane.
/// Otherwise (strongly bent tiles, e.g. a valence-5 vertex on a 3×3 torus, where the Newell plane
/// reverses one corner and the network folds) the normal is turned from `start` towards
/// the max-margin normal n* just far enough to reach margin m*/2 (bisection on the chord; the
/// feasible set is a convex cone, so the first feasible point is found). n* = the min-norm point of conv{ĉ_k}, normalized
/// (max_n min_k n·ĉ_k = min_{x ∈ conv ĉ} |x|), by Gilbert's algorithm.
/// `None` when no plane orders the fan (the origin lies in conv{ĉ_k}).
///
/// With `vertices` (closed tiles; not in the seed) the fan is t_0, m_0, t_1, m_1, … ([`fan_dirs`]):
/// the tile vertex t_k (the first-approximation twist of its face's corner, and an end of the two
/// tile edges whose midpoints are the curves' C1) must lie between the tangents m_{k−1} and m_k.
/// The midpoints alone do not force that: at the valence-8 saddle vertices inside OpenSubdiv's
/// loop_toroidal_tet (faces alternating up and down, 120° dihedral angles) the Newell plane keeps
/// the m_k in order but sees a tile vertex 190° from its neighbour, behind the centre; the corner
/// block (p, m_{k−1}, t_k, m_k) of that face is then turned inside out and the patch folds next to
/// the corner (24 patches, 804 self-intersecting pairs). [`tiles`] asks for this fan only where
/// the plane n₀ of the tangents alone leaves a tile vertex out of order ([`tile_ordered`]), starts
/// the turn from n₀, and takes the result n₁ only if the tangents' margin does not drop
/// (min_k n₁·ĉ_k ≥ min_k n₀·ĉ_k over the tangent corners); otherwise, or when no plane orders the
/// interleaved fan, n₀ stays.
fn fan_normal(p: DVec3, ring: &[DVec3], closed: bool, start: DVec3, vertices: bool) -> Option<DVec3> {
    let dirs = fan_dirs(p, ring, closed, vertices);
    let cs = fan_corners(&dirs, closed);
    if cs.is_empty() {
        return Some(start);
    }
    let margin = |n: DVec3| fan_margin(&cs, n);
    let one_turn = |n: DVec3| !closed || one_turn(&dirs, n);
    if margin(start) >= FAN_MARGIN && one_turn(start) {
        return Some(start);
    }
    // Gilbert's algorithm for the min-norm point of conv{ĉ_k}.
    let mut x = cs.iter().copied().sum::<DVec3>() / cs.len() as f64;
    for _ in 0..2000 {
        let xx = x.length_squared();
        if xx < 1e-24 {
            return None;
        }
        let (c, v) = cs.iter().map(|&c| (c, c.dot(x))).fold((x, f64::INFINITY), |b, a| if a.1 < b.1 { a } else { b });
        if v >= 0.95 * xx {
            break; // within 5% of the optimal margin
        }
        let d = c - x;
        let lam = ((xx - v) / d.length_squared()).clamp(0.0, 1.0);
        x += lam * d;
    }
    let best = x.normalize_or_zero();
    let m_best = margin(best);
    if !(m_best > 1e-9) || !one_turn(best) {
        return None;
    }
    if margin(start) >= FAN_MARGIN.min(0.5 * m_best) && one_turn(start) {
        return Some(start);
    }
    let goal = 0.5 * m_best;
    let at = |t: f64| ((1.0 - t) * start + t * best).normalize_or_zero();
    let ok = |n: DVec3| n != DVec3::ZERO && margin(n) >= goal;
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if ok(at(mid)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let n = at(hi);
    Some(if ok(n) && one_turn(n) { n } else { best })
}

/// The tile polygon of v, counter-clockwise: (h, true) = split point on the edge of outgoing h,
/// (h, false) = tile vertex in face(h) for outgoing h. Written to `ring`; `out` is a buffer for
/// the outgoing half-edges (both cleared first).
fn tile_ring(
    mesh: &HalfEdgeMesh,
    v: crate::mesh::VertexId,
    out: &mut Vec<HalfedgeId>,
    ring: &mut Vec<(HalfedgeId, bool)>,
) {
    ring.clear();
    if !mesh.is_boundary_vertex(v) {
        ring.extend(mesh.vertex_outgoing(v).map(|h| (h, false)));
        return;
    }
    out.clear();
    out.extend(mesh.vertex_outgoing(v));
    // out[0] is the boundary half-edge (no face); faces follow from out[1].
    let n = out.len();
    ring.push((out[1 % n], true));
    ring.extend(out[1..].iter().map(|&h| (h, false)));
    ring.push((out[0], true));
}

/// Midpoint of the tile edge of origin(h) across the edge of outgoing h.
fn tile_edge_mid(mesh: &HalfEdgeMesh, t: &Tiles, h: HalfedgeId) -> DVec3 {
    let left = if mesh.face(h).is_some() { t.vertex[h.idx()] } else { t.split[h.idx()] };
    let tw = mesh.twin(h);
    let right = if mesh.face(tw).is_some() { t.vertex[mesh.next(tw).idx()] } else { t.split[h.idx()] };
    0.5 * (left + right)
}

/// The tile curve network of seed 000 §3.3 (nodes = tile centres, index = vertex index).
pub fn topology_network(mesh: &HalfEdgeMesh, opts: &ConvertOptions) -> Result<CurveNetwork, ConstructError> {
    let t = tiles(mesh, opts)?;
    // One curve per edge, built in parallel and collected in edge order.
    let per_edge: Vec<([DVec3; 4], [usize; 2], DVec3)> = (0..mesh.n_edges() as u32)
        .into_par_iter()
        .map(|e| {
            let h = mesh.edge_halfedge(EdgeId(e), 0);
            let tw = mesh.twin(h);
            let (u, v) = (mesh.origin(h), mesh.target(h));
            let curve = [t.center[u.idx()], tile_edge_mid(mesh, &t, h), tile_edge_mid(mesh, &t, tw), t.center[v.idx()]];
            // Edge tile: tile vertices of u and v in face(h) (left) and face(tw) (right).
            let d = match (mesh.face(h), mesh.face(tw)) {
                (Some(_), Some(_)) => {
                    let ml = 0.5 * (t.vertex[h.idx()] + t.vertex[mesh.next(h).idx()]);
                    let mr = 0.5 * (t.vertex[tw.idx()] + t.vertex[mesh.next(tw).idx()]);
                    1.5 * (ml - mr)
                }
                _ => DVec3::ZERO,
            };
            (curve, [u.idx(), v.idx()], d)
        })
        .collect();
    let mut curves: Vec<[DVec3; 4]> = per_edge.iter().map(|x| x.0).collect();
    let curve_nodes: Vec<[usize; 2]> = per_edge.iter().map(|x| x.1).collect();
    let mids: Vec<DVec3> = per_edge.iter().map(|x| x.2).collect();
    let mut corner_twist: Vec<DVec3> = t.vertex.clone();
    let (mut nodes, mut node_normals) = (t.center, t.normal);
    let crease: Vec<f64> = if mesh.has_creases() {
        crease_network(mesh, opts, &mut nodes, &mut node_normals, &mut curves, &mut corner_twist);
        mesh.edges().map(|e| mesh.edge_crease(e)).collect()
    } else {
        Vec::new()
    };
    // One patch per face, built in parallel and collected in face order.
    let patches: Vec<PatchLayout> = (0..mesh.n_faces() as u32)
        .into_par_iter()
        .map(|f| {
            let f = FaceId(f);
            // Side i along hs[i−1] (p_{i−1} → p_i), hs the face's half-edges; corner i = p_i,
            // twist = tile vertex of p_i here.
            let mut sides: Vec<SideUse> =
                mesh.face_halfedges(f).map(|h| SideUse { curve: mesh.edge(h).idx(), reversed: h.0 & 1 == 1 }).collect();
            if !sides.is_empty() {
                sides.rotate_right(1);
            }
            PatchLayout {
                sides,
                corner_twists: mesh.face_halfedges(f).map(|h| corner_twist[h.idx()]).collect(),
                center: None,
                source: PatchSource::Face(f.idx()),
            }
        })
        .collect();
    Ok(CurveNetwork { nodes, node_normals, curves, curve_nodes, mid: mids, patches, crease, end_scale: Vec::new() })
}

/// Control point `k` (1 = next to the start) of the curve of the edge of outgoing half-edge `h`,
/// as seen from origin(h): the curve of edge e runs from origin(2e) to target(2e).
fn curve_point<'a>(curves: &'a mut [[DVec3; 4]], mesh: &HalfEdgeMesh, h: HalfedgeId) -> &'a mut DVec3 {
    let c = &mut curves[mesh.edge(h).idx()];
    if h.0 & 1 == 0 {
        &mut c[1]
    } else {
        &mut c[2]
    }
}

/// Moves the tile network towards the crease polygons (docs/math.md#creases). Per vertex u with
/// incident edge sharpness sorted c_(1) ≥ c_(2) ≥ c_(3) ≥ … and corner sharpness c_u:
/// - crease weight w2 = c_(2), corner weight w3 = max(c_u, c_(3)) (both 0 when u has fewer than
///   two, three sharp edges: they grow continuously from 0 as an edge's sharpness does);
/// - X = (a + 4u + b)/6, a and b the far ends of the two sharpest edges (the limit point of the
///   cubic B-spline of the crease polygon a–u–b; u itself when w2 = 0);
/// - node N = T + w2 (X − T), then N ← N + w3 (u − N), T the tile centre;
/// - every curve point next to u (C1 seen from u) moves with the node (by N − T); on a sharp edge
///   (u, b) of sharpness c it is then pulled to (2u + b)/3: C1 ← C1 + c ((2u + b)/3 − C1) (at
///   c = 1 the curve is the B-spline segment of the crease polygon, or a straight segment at a
///   corner);
/// - with `best_plane`, the tangent plane at N turns from the tile normal n towards the plane
///   containing the crease direction d = (b − a)/|b − a|: n' ∝ n − w2 (n·d) d, and every C1 at u
///   is projected onto it by the fraction 1 − w3 (all tangents coplanar again: G1 at the node
///   across the smooth curves; at a corner, w3 = 1, nothing is projected and the node is a
///   G0 point);
/// - the first-approximation twist at each face corner at u moves from the tile vertex to the
///   parallelogram point of the corner's two curves by max(w2, w3).
///
/// With every sharpness 0 nothing is changed (the caller does not call this at all).
fn crease_network(
    mesh: &HalfEdgeMesh,
    opts: &ConvertOptions,
    nodes: &mut [DVec3],
    normals: &mut [DVec3],
    curves: &mut [[DVec3; 4]],
    corner_twist: &mut [DVec3],
) {
    for u in mesh.vertices() {
        let up = mesh.position(u);
        let out: Vec<HalfedgeId> = mesh.vertex_outgoing(u).collect();
        let mut sharp: Vec<(f64, HalfedgeId)> =
            out.iter().map(|&h| (mesh.edge_crease(mesh.edge(h)), h)).filter(|x| x.0 > 0.0).collect();
        sharp.sort_by(|a, b| b.0.total_cmp(&a.0));
        let cu = mesh.vertex_crease(u);
        if sharp.is_empty() && cu == 0.0 {
            continue;
        }
        let w2 = sharp.get(1).map_or(0.0, |x| x.0);
        let w3 = corner_weight(cu, &sharp);
        let tc = nodes[u.idx()];
        let (x, d) = if sharp.len() >= 2 {
            let a = mesh.position(mesh.target(sharp[0].1));
            let b = mesh.position(mesh.target(sharp[1].1));
            ((a + 4.0 * up + b) / 6.0, (b - a).normalize_or_zero())
        } else {
            (up, DVec3::ZERO)
        };
        let mut node = tc + w2 * (x - tc);
        node += w3 * (up - node);
        let delta = node - tc;
        for &h in &out {
            let c = mesh.edge_crease(mesh.edge(h));
            let p = curve_point(curves, mesh, h);
            *p += delta;
            if c > 0.0 {
                let target = (2.0 * up + mesh.position(mesh.target(h))) / 3.0;
                *p += c * (target - *p);
            }
        }
        let n = normals[u.idx()];
        let np = (n - w2 * n.dot(d) * d).normalize_or_zero();
        if opts.best_plane && np != DVec3::ZERO {
            for &h in &out {
                let p = curve_point(curves, mesh, h);
                *p -= (1.0 - w3) * np * np.dot(*p - node);
            }
            normals[u.idx()] = np;
        }
        nodes[u.idx()] = node;
        // Curve ends at u.
        for &h in &out {
            let c = &mut curves[mesh.edge(h).idx()];
            if h.0 & 1 == 0 {
                c[0] = node;
            } else {
                c[3] = node;
            }
        }
        // Face corners at u: between incoming prev(h) and outgoing h of face(h).
        let wt = w2.max(w3);
        for &h in &out {
            if mesh.face(h).is_none() {
                continue;
            }
            let hin = mesh.twin(mesh.prev(h)); // outgoing from u along the corner's other edge
            let a = *curve_point(curves, mesh, h);
            let b = *curve_point(curves, mesh, hin);
            let par = a + b - node;
            corner_twist[h.idx()] += wt * (par - corner_twist[h.idx()]);
        }
    }
}

/// Corner weight w3 = max(c_u, c_(3)) of a vertex with corner sharpness `cu` and incident
/// edge sharpness `sharp` sorted in decreasing order (docs/math.md#creases).
fn corner_weight(cu: f64, sharp: &[(f64, HalfedgeId)]) -> f64 {
    cu.max(sharp.get(2).map_or(0.0, |x| x.0))
}

/// The warning for corner vertices (w3 > 0) where a smooth interior edge lies next to a creased
/// one: the creased curve's tangent is pulled towards its edge, and at such a node the tangents
/// are projected back onto the tangent plane only by 1 − w3, so the smooth curve's tangent and
/// those of its two neighbouring curves (the other edge at the vertex in each of its two faces)
/// are not coplanar: the surface is not G1 across the smooth curve near the node, and
/// `max_g1_deg` includes it (docs/math.md#corners-with-smooth-curves). Smooth tangents alone are
/// only moved by a linear map of the tangent plane and stay coplanar, so a corner tag without
/// creased edges keeps G1. Vertices in `origin` numbering.
fn corner_warning(mesh: &HalfEdgeMesh, opts: &ConvertOptions, origin: &[usize]) -> Option<String> {
    if !mesh.has_creases() || !opts.best_plane {
        return None;
    }
    let crease = |h: HalfedgeId| mesh.edge_crease(mesh.edge(h));
    let corners: Vec<usize> = mesh
        .vertices()
        .filter(|&u| {
            let mut sharp: Vec<(f64, HalfedgeId)> =
                mesh.vertex_outgoing(u).map(|h| (crease(h), h)).filter(|x| x.0 > 0.0).collect();
            sharp.sort_by(|a, b| b.0.total_cmp(&a.0));
            corner_weight(mesh.vertex_crease(u), &sharp) > 0.0
                && mesh.vertex_outgoing(u).any(|h| {
                    let t = mesh.twin(h);
                    crease(h) == 0.0
                        && mesh.face(h).is_some()
                        && mesh.face(t).is_some()
                        && (crease(mesh.prev(h)) > 0.0 || crease(mesh.next(t)) > 0.0)
                })
        })
        .map(|u| origin.get(u.idx()).copied().unwrap_or(u.idx()))
        .collect();
    let first = corners.iter().min()?;
    Some(format!(
        "{} corner vertices (three or more creased edges, or a corner tag) have a smooth edge next to a creased one (first: vertex {first}): the surface is not G1 across those smooth edges near the corner, and max G1 includes them (docs/math.md#corners-with-smooth-curves)",
        corners.len()
    ))
}

/// Topology-preserving construction (seed 000 §3, §4): interior valence-2 vertices dissolved and
/// concave faces split by [`super::prepare`], then [`topology_network`] and [`assemble`]. One
/// patch per face of the split mesh; its source is the input face it came from, as the user wrote
/// it (a split face, concave or with holes, gives several patches with one source; a face that
/// lost a dissolved vertex has one side fewer). Dissolved
/// vertices are listed in `warnings`. Errors name elements of `mesh`.
pub fn build_topology(mesh: &HalfEdgeMesh, opts: &ConvertOptions) -> Result<Surface, ConstructError> {
    build_topology_ticked(mesh, opts, &mut crate::progress::Ticker::none())
}

/// [`build_topology`] reporting progress to `ticker` (parts measured on a 50k-face UV sphere: preparation,
/// network, then [`super::assemble_ticked`]; see [`crate::progress`]).
pub fn build_topology_ticked(mesh: &HalfEdgeMesh, opts: &ConvertOptions, ticker: &mut crate::progress::Ticker<'_>) -> Result<Surface, ConstructError> {
    let prep = ticker.within(0.0, PREPARE, |_| super::prepare(mesh))?;
    let net = ticker.within(PREPARE, NETWORK, |_| topology_network(&prep.mesh, opts)).map_err(|e| prep.error(e, false))?;
    let (mut s, splits) = ticker.within(NETWORK, 1.0, |t| super::network::assemble_split(&net, opts, t)).map_err(|e| prep.error(e, false))?;
    if net.patches.len() == prep.mesh.n_faces() {
        s.cage = super::network::split_cage(prep.cage_topology(mesh), &splits, s.patches.len());
    }
    for src in &mut s.sources {
        *src = prep.source(*src);
    }
    s.warnings = prep.warnings.into_iter().chain(std::mem::take(&mut s.warnings)).collect();
    s.warnings.extend(corner_warning(&prep.mesh, opts, &prep.vertex_origin));
    s.warnings.extend(super::network::split_warnings(&s.sources, &splits));
    Ok(s)
}

/// Ends of the preparation's and the network's shares of [`build_topology_ticked`].
const PREPARE: f32 = 0.1;
const NETWORK: f32 = 0.4;
