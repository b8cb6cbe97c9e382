//! Dual structure (seed 000 §2): one GB patch per mesh vertex, boundary curves between the
//! centroids of the faces adjacent to each mesh edge.
//!
//! Closed part (seed 000 §2.3–2.4):
//! - node of face f: its centroid c_f = (Σ P_i)/m (eq. 2.1); node tangent plane: the plane through
//!   c_f with the face's Newell normal (§3.3.2). With `best_plane` the edge midpoints F of f are
//!   projected onto it (F' = F − n·(F − c_f) n), so all tangents at c_f lie in one plane (§4.4.4).
//! - curve of an interior edge e (faces f on its right, g on its left, seen along the half-edge
//!   2e): C0 = c_f, C1 = κ c_f + (1−κ) F'_f, C2 = κ c_g + (1−κ) F'_g, C3 = c_g (eq. 2.2 with
//!   the typo corrected: C2 uses C3, see docs/math.md#dual).
//! - patch of vertex V with outgoing half-edges h_0..h_{n−1} (CCW): corner i is the centroid of
//!   face(h_i), side i crosses edge h_i; the central control point is V (§2.4.1), fitted to the
//!   boundary for every valence but 4 when the patch is built (docs/math.md#centre-fit).
//! - first-approximation twist at corner f (eq. 2.11): T = κ² c_f + κ(1−κ)(F'_1 + F'_2) + (1−κ)² V,
//!   F_1, F_2 the midpoints of the two edges of f at V.
//! - D_{0.5} of edge (A → B) (eq. 4.29 corrected to a vector): the symmetric difference of the
//!   vectors from the curve towards κF + (1−κ)V of both patches, times three:
//!   D_{0.5} = (3/2)·[(κF + (1−κ)V_A) − (κF + (1−κ)V_B)] = (3/2)(1−κ)(V_A − V_B),
//!   pointing into patch A; the same vector (negated) for B, so both use one blend.
//!
//! Open meshes (not in the seed; defined here). At a boundary edge e = (V, W) with its single
//! face f, the boundary node is the edge midpoint F (not projected). Its curve runs from c_f to F:
//! the first half of the symmetric curve c_f → (2F − c_f) that a mirrored face would give, i.e.
//! C0 = c_f, C1 = c_f + ((1−κ)/2)(F'_f − c_f), C2 = c_f + ((3−κ)/4)(F − c_f), C3 = F (a straight
//! segment for a planar face). A boundary vertex V with outgoing g_0..g_{n−1} (CCW, g_{n−1} the
//! boundary half-edge, n−1 faces f_k = face(g_k)) gets an (n+1)-sided patch with corners
//! F(g_0), c(f_0), …, c(f_{n−2}), F(g_{n−1}); its last side is the open side from F(g_{n−1}) to
//! F(g_0): the quadratic Bézier (F(g_{n−1}), V, F(g_0)) degree-elevated to a cubic. Consecutive open
//! sides therefore join with a common tangent at F (the surface boundary is C1, the
//! quadratic B-spline of the boundary polygon), the three tangents at F are coplanar (two are
//! collinear), and the surface is G1 across every shared side. The first-approximation twist at
//! an F corner is the parallelogram point P10 + P01 − P00 of its corner block.

use super::network::{CurveNetwork, PatchLayout, SideUse};
use super::surface::{PatchSource, Surface};
use super::{check_options, ConstructError};
use crate::options::ConvertOptions;
use crate::mesh::geometry::newell_normal;
use crate::mesh::{FaceId, HalfEdgeMesh, HalfedgeId, VertexId};
use glam::DVec3;
use rayon::prelude::*;

/// The dual curve network of seed 000 §2.3 (with the open-boundary extension described in the
/// module doc). Nodes: one per face (index = face index), then one per boundary edge.
pub fn dual_network(mesh: &HalfEdgeMesh, opts: &ConvertOptions) -> Result<CurveNetwork, ConstructError> {
    check_options(opts)?;
    let k = opts.fullness;
    let nf = mesh.n_faces();
    // Face planes, per face in parallel (collected in face order; first degenerate face reported).
    // A corner buffer per worker, reused over its faces.
    let planes: Vec<Option<(DVec3, DVec3)>> = (0..nf as u32)
        .into_par_iter()
        .map_init(Vec::new, |pts: &mut Vec<DVec3>, f| {
            pts.clear();
            pts.extend(mesh.face_vertices(FaceId(f)).map(|v| mesh.position(v)));
            let c = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
            let n = newell_normal(pts);
            let len = n.length();
            (len > 1e-14 * pts.iter().map(|p| (*p - c).length_squared()).fold(0.0, f64::max)).then(|| (c, n / len))
        })
        .collect();
    let mut centroid = Vec::with_capacity(nf);
    let mut normal = Vec::with_capacity(nf);
    for (f, pl) in planes.into_iter().enumerate() {
        let (c, n) = pl.ok_or(ConstructError::DegenerateFace { face: f })?;
        centroid.push(c);
        normal.push(n);
    }
    let mid = |h: HalfedgeId| 0.5 * (mesh.position(mesh.origin(h)) + mesh.position(mesh.target(h)));
    // Edge midpoint as seen from face f (projected onto its plane with best_plane).
    let fmid = |h: HalfedgeId, f: FaceId| {
        let m = mid(h);
        if opts.best_plane {
            let n = normal[f.idx()];
            m - n * n.dot(m - centroid[f.idx()])
        } else {
            m
        }
    };

    let mut nodes = centroid.clone();
    let mut node_normals = normal.clone();
    let mut curves = Vec::new();
    let mut curve_nodes = Vec::new();
    let mut mids = Vec::new();
    // Curve of each edge; boundary-edge node index.
    let mut edge_curve = vec![usize::MAX; mesh.n_edges()];
    let mut edge_node = vec![usize::MAX; mesh.n_edges()];
    for e in mesh.edges() {
        let h = mesh.edge_halfedge(e, 0);
        let t = mesh.twin(h);
        let va = mesh.position(mesh.origin(h));
        let vb = mesh.position(mesh.target(h));
        edge_curve[e.idx()] = curves.len();
        match (mesh.face(t), mesh.face(h)) {
            (Some(fr), Some(fl)) => {
                // Forward for the patch of origin(h) (side from face(twin h) to face(h)).
                let (cr, cl) = (centroid[fr.idx()], centroid[fl.idx()]);
                curves.push([cr, k * cr + (1.0 - k) * fmid(h, fr), k * cl + (1.0 - k) * fmid(h, fl), cl]);
                curve_nodes.push([fr.idx(), fl.idx()]);
                mids.push(1.5 * (1.0 - k) * (va - vb));
            }
            (a, b) => {
                let (f, bh) = match (a, b) {
                    (Some(f), None) => (f, h),
                    (None, Some(f)) => (f, t),
                    _ => return Err(ConstructError::Internal(format!("edge {} has no face", e.idx()))),
                };
                // bh: the boundary half-edge; its origin's patch traverses c_f → F forward.
                let c = centroid[f.idx()];
                let fm = mid(bh);
                let fp = fmid(bh, f);
                let node = nodes.len();
                nodes.push(fm);
                let ev = mesh.position(mesh.target(bh)) - mesh.position(mesh.origin(bh));
                node_normals.push(ev.cross(fm - c).normalize_or_zero());
                edge_node[e.idx()] = node;
                curves.push([c, c + 0.5 * (1.0 - k) * (fp - c), c + 0.25 * (3.0 - k) * (fm - c), fm]);
                curve_nodes.push([f.idx(), node]);
                let w_fwd = mesh.position(mesh.origin(bh));
                let w_rev = mesh.position(mesh.target(bh));
                mids.push(1.5 * (1.0 - k) * (w_fwd - w_rev));
            }
        }
    }

    let mut patches = Vec::with_capacity(mesh.n_vertices());
    let mut out = Vec::new();
    for v in mesh.vertices() {
        out.clear();
        out.extend(mesh.vertex_outgoing(v));
        let (curves, curve_nodes, mids) = (&mut curves, &mut curve_nodes, &mut mids);
        patches.push(vertex_patch(mesh, v, &out, opts, &centroid, &fmid, &edge_curve, &edge_node, curves, curve_nodes, mids)?);
    }
    let (crease, end_scale) = (Vec::new(), Vec::new());
    Ok(CurveNetwork { nodes, node_normals, curves, curve_nodes, mid: mids, patches, crease, end_scale })
}

/// The patch of vertex `v`; `out` = its outgoing half-edges (`vertex_outgoing`, CCW).
#[allow(clippy::too_many_arguments)]
fn vertex_patch(
    mesh: &HalfEdgeMesh,
    v: VertexId,
    out: &[HalfedgeId],
    opts: &ConvertOptions,
    centroid: &[DVec3],
    fmid: &dyn Fn(HalfedgeId, FaceId) -> DVec3,
    edge_curve: &[usize],
    edge_node: &[usize],
    curves: &mut Vec<[DVec3; 4]>,
    curve_nodes: &mut Vec<[usize; 2]>,
    mids: &mut Vec<DVec3>,
) -> Result<PatchLayout, ConstructError> {
    let k = opts.fullness;
    let vp = mesh.position(v);
    let n = out.len();
    // Side crossing the edge of outgoing h: forward iff h is the edge's half-edge 0.
    let cross_side = |h: HalfedgeId| SideUse { curve: edge_curve[mesh.edge(h).idx()], reversed: h.0 & 1 == 1 };
    // Eq. 2.11 twist at the corner of face f between outgoing a and b (both edges of f at v).
    let face_twist = |f: FaceId, a: HalfedgeId, b: HalfedgeId| {
        let c = centroid[f.idx()];
        k * k * c + k * (1.0 - k) * (fmid(a, f) + fmid(b, f)) + (1.0 - k) * (1.0 - k) * vp
    };
    if !mesh.is_boundary_vertex(v) {
        // Side i crosses out[i]; corner i = face(out[i]), bounded by edges out[i] and out[i+1].
        let mut sides = Vec::with_capacity(n);
        let mut twists = Vec::with_capacity(n);
        for i in 0..n {
            let h = out[i];
            let f = mesh.face(h).ok_or_else(|| ConstructError::Internal(format!("vertex {}: gap", v.idx())))?;
            sides.push(cross_side(h));
            twists.push(face_twist(f, h, out[(i + 1) % n]));
        }
        return Ok(PatchLayout { sides, corner_twists: twists, center: Some(vp), source: PatchSource::Vertex(v.idx()) });
    }
    // Boundary vertex: vertex_outgoing starts at the boundary half-edge (no face). Rotate so that
    // g_{n−1} is that half-edge and g_0 the first face's.
    let g: Vec<HalfedgeId> = (0..n).map(|i| out[(i + 1) % n]).collect();
    if mesh.face(g[n - 1]).is_some() || g[..n - 1].iter().any(|&h| mesh.face(h).is_none()) {
        return Err(ConstructError::Internal(format!("vertex {}: unexpected boundary fan", v.idx())));
    }
    let e0 = mesh.edge(g[0]).idx();
    let el = mesh.edge(g[n - 1]).idx();
    let f_first = edge_node[e0];
    let f_last = edge_node[el];
    let p0 = curves[edge_curve[e0]][3]; // F(g_0)
    let pl = curves[edge_curve[el]][3]; // F(g_{n−1})
    // Open side F(g_{n−1}) → V → F(g_0), quadratic elevated.
    let open = curves.len();
    curves.push([pl, (pl + 2.0 * vp) / 3.0, (2.0 * vp + p0) / 3.0, p0]);
    curve_nodes.push([f_last, f_first]);
    mids.push(DVec3::ZERO);
    // Corners: K_0 = F(g_0), K_j = c(f_{j−1}) (j = 1..n−1), K_n = F(g_{n−1}).
    // Sides: 0 = open (K_n → K_0), 1 = boundary curve of g_0 (reversed), j+1 = crossing g_j
    // (j = 1..n−2), n = boundary curve of g_{n−1} (forward).
    let mut sides = vec![SideUse { curve: open, reversed: false }, SideUse { curve: edge_curve[e0], reversed: true }];
    for &h in &g[1..n - 1] {
        sides.push(cross_side(h));
    }
    sides.push(SideUse { curve: edge_curve[el], reversed: false });
    let m = n + 1;
    let pts = |s: SideUse| {
        let c = curves[s.curve];
        if s.reversed {
            [c[3], c[2], c[1], c[0]]
        } else {
            c
        }
    };
    let mut twists = Vec::with_capacity(m);
    for i in 0..m {
        // Corner i: end of side i, start of side i+1.
        let a = pts(sides[i]);
        let b = pts(sides[(i + 1) % m]);
        let t = if i == 0 || i == n {
            a[2] + b[1] - a[3] // parallelogram at the boundary nodes F
        } else {
            let f = mesh.face(g[i - 1]).expect("checked above");
            face_twist(f, g[i - 1], g[i])
        };
        twists.push(t);
    }
    Ok(PatchLayout { sides, corner_twists: twists, center: Some(vp), source: PatchSource::Vertex(v.idx()) })
}

/// Dual construction (seed 000 §2, §4): interior valence-2 vertices dissolved and concave faces
/// split by [`super::prepare`], then [`dual_network`] and [`assemble`]. Patch p stands for the
/// vertex `sources[p]` of `mesh` (= p unless vertices were dissolved; those have no patch and a
/// warning in `warnings`). Errors name elements of `mesh`.
pub fn build_dual(mesh: &HalfEdgeMesh, opts: &ConvertOptions) -> Result<Surface, ConstructError> {
    build_dual_ticked(mesh, opts, &mut crate::progress::Ticker::none())
}

/// [`build_dual`] reporting progress to `ticker` (parts measured on a 50k-face UV sphere: preparation,
/// network, then [`super::assemble_ticked`]; see [`crate::progress`]).
pub fn build_dual_ticked(mesh: &HalfEdgeMesh, opts: &ConvertOptions, ticker: &mut crate::progress::Ticker<'_>) -> Result<Surface, ConstructError> {
    let prep = ticker.within(0.0, PREPARE, |_| super::prepare(mesh))?;
    let mut net = ticker.within(PREPARE, NETWORK, |_| dual_network(&prep.mesh, opts)).map_err(|e| prep.error(e, true))?;
    let mut cage = prep.cage_dual(mesh);
    let mut crease_warnings = Vec::new();
    if prep.mesh.has_creases() {
        // Creases split the vertex patches along closed sharp chains (docs/math.md#dual-creases),
        // starting from the smooth surface S₀ (assembled only when an edge is cut).
        let cuts = super::dual_crease::cuts(&prep.mesh);
        let v = |x: VertexId| prep.vertex_origin.get(x.idx()).copied().unwrap_or(x.idx());
        if let Some((a, b)) = cuts.ignored_edges.first() {
            crease_warnings.push(format!(
                "the dual structure builds creases only along closed chains of sharp interior edges: {} sharp edge(s) left smooth, the first ({}, {}) (docs/math.md#dual-creases; the topology structure builds them all)",
                cuts.ignored_edges.len(),
                v(*a),
                v(*b)
            ));
        }
        if let Some(c) = cuts.ignored_corners.first() {
            crease_warnings.push(format!(
                "the dual structure builds corners only where three or more sharp edges meet: corner sharpness ignored at {} vertex(es), the first {} (docs/math.md#dual-creases)",
                cuts.ignored_corners.len(),
                v(*c)
            ));
        }
        if cuts.any() {
            let smooth = ticker.within(PREPARE, NETWORK, |t| super::network::assemble_ticked(&net, opts, t)).map_err(|e| prep.error(e, true))?;
            let diagonals = |h| prep.diagonals(h);
            if let Some(split) = super::dual_crease::split_creases(&prep.mesh, &cuts, &net, &smooth, &cage, &diagonals, opts) {
                net = split.net;
                cage = split.cage;
            }
        }
    }
    let (mut s, splits) = ticker.within(NETWORK, 1.0, |t| super::network::assemble_split(&net, opts, t)).map_err(|e| prep.error(e, true))?;
    if cage.len() == net.patches.len() {
        s.cage = super::network::split_cage(cage, &splits, s.patches.len());
    }
    for src in &mut s.sources {
        *src = prep.source(*src);
    }
    s.warnings = prep.warnings.into_iter().chain(std::mem::take(&mut s.warnings)).collect();
    s.warnings.extend(crease_warnings);
    s.warnings.extend(super::network::split_warnings(&s.sources, &splits));
    Ok(s)
}

/// Ends of the preparation's and the network's shares of [`build_dual_ticked`].
const PREPARE: f32 = 0.1;
const NETWORK: f32 = 0.4;
