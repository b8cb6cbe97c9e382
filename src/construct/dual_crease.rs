//! Creases in the dual structure (docs/math.md#dual-creases): the vertex patches along closed
//! chains of sharp edges are split into sectors, with the crease curves between the sectors.
//!
//! The dual patch of a vertex V spans every face around V, so a feature curve along a cage edge
//! runs through the middle of two vertex patches. Where V has k ≥ 2 *cut* edges (below), its
//! patch is replaced by k *sectors*, one between each pair of consecutive cut edges:
//! - every cut edge e gets a node F_e on its dual curve D_e, which is split there into two halves
//!   A_e (from the right face's centroid) and B_e (to the left face's centroid);
//! - k = 2: one *cut curve* K from F_a to F_b joins the two sectors; k ≥ 3: a *centre node* X and
//!   k *spokes* X → F_e;
//! - sector s: the second half of side j_s, the sides j_s + 1 … j_{s+1} − 1, the first half of side
//!   j_{s+1}, then the cut curve (k = 2) or the spokes j_{s+1} → X → j_s (k ≥ 3).
//!
//! **Cut edges.** An interior edge of sharpness c > 0 between two interior vertices is cut when it
//! lies on a closed chain: the sharp edges are pruned, repeatedly, at vertices with exactly one
//! (a chain's loose end) — what remains is the 2-core of the sharp-edge graph. Pruned sharp edges,
//! sharp boundary edges and corner sharpness at vertices with fewer than three cut edges are
//! ignored with a warning: a chain that ends inside the surface would need a sector boundary that
//! ends inside a patch.
//!
//! **Geometry, continuous in the sharpness.** Each quantity moves linearly from its value on the
//! smooth surface S₀ (the unsplit dual surface, sharpness 0) to the sharp target (sharpness 1),
//! with the edge's sharpness c_e at F_e and the vertex's corner weight w₃ = max(c_V, c₍₃₎) at X
//! (c₍₃₎ the third-largest sharpness of V's cut edges, as in docs/math.md#creases):
//! - F_e = F⁰ + c_e (M_e − F⁰): F⁰ = D_e(½), M_e the edge midpoint;
//! - A_e, B_e: from the de Casteljau halves of D_e at ½ to the open-boundary curves of §4.1
//!   (c_f → M_e: C1 = c_f + ((1−κ)/2)(F′_f − c_f) (= the first de Casteljau point, unchanged),
//!   C2 = c_f + ((3−κ)/4)(M_e − c_f), C3 = M_e), point by point; their face-centroid ends count
//!   twice in the blends' D there (`CurveNetwork::end_scale`: a half's parameter runs twice as
//!   fast as D_e's), so D stays S₀'s and the unsplit neighbours do not move as c → 0;
//! - the crossing direction at F_e: u_e = unit(u⁰ + c_e (u¹ − u⁰)), u⁰ the edge direction
//!   V − W projected into S₀'s tangent plane at F⁰ (spanned by D_e′(½) and D_{0.5}), u¹ =
//!   unit(V − W). Where nothing turns (below), every cut curve and spoke leaves F_e along ±u_e,
//!   so the two halves stay G1 at F_e for every sharpness;
//! - cut curve of V (k = 2), from F_a to F_b: C1 = F_a + ℓ_a u_a, C2 = F_b + ℓ_b u_b (u pointing
//!   towards V); ℓ⁰ from S₀'s derivative along the straight domain segment from the midpoint of
//!   side a to that of side b (the Hermite cubic of S₀ along it, its end tangents projected on
//!   u⁰), ℓ¹ = (2/3)|V − M|, so at sharpness 1 it is the quadratic B-spline (M_a, V, M_b) of the
//!   crease polygon, as on an open boundary (§4.1); its sharpness is min(c_a, c_b);
//! - **turning** (edges with an end of two cut edges): at sharpness 0 such a cut curve leaves F_e
//!   along S₀'s own direction there (S₀'s derivative along the domain segment, in S₀'s plane
//!   at F⁰) with lengths fitted to S₀ along the segment (least squares, parameters corrected to
//!   the nearest curve points), so it lies on S₀ and the sectors tend to S₀ as c → 0. The two
//!   ends of an edge then leave F_e in different directions, which keeps G1 across the halves
//!   only while the halves are S₀'s (their tangents at F_e collinear). So over c ∈ [0, ¼] only
//!   the cut curves turn, linearly, to u⁰ and the Hermite lengths ℓ⁰ (F_e, the halves and their
//!   D_{0.5} stay S₀'s; the corner weight w₃ at X and the crease weight that narrows the blends
//!   keep the edges' own sharpness), and over c ∈ [¼, 1] everything else moves as above with
//!   (c − ¼)/(1 − ¼) in place of c_e, after which both ends' directions are opposite again.
//!   Edges between vertices of three or more cut edges do not turn (their spokes keep u⁰: fitted
//!   spokes folded a sector of the rook);
//! - centre node X = X⁰ + w₃ (V − X⁰), X⁰ = S₀ at the domain centre; spoke X → F_e: C1 = X +
//!   (1 − w₃)·(S₀′ along a domain ray)/3 + w₃ (M_e − V)/3, projected into S₀'s tangent plane at
//!   X⁰ by the fraction 1 − w₃ (the spokes stay coplanar at X until V is a corner), C2 = F_e +
//!   ℓ u_e as for the cut curve with ℓ¹ = |V − M_e|/3 (a straight segment M_e → V at sharpness 1);
//!   its sharpness is c_e. The domain ray of spoke s has angle ¼·(angle of side j_s's midpoint) +
//!   ¾·(angle of spoke 0 + 2πs/k): every angle between consecutive rays stays below π, so the
//!   spokes leave X⁰ as a star even where three crease lines meet in a T;
//! - V is a corner through c₍₃₎ only where the angles between its consecutive sharp edges,
//!   projected along S₀'s normal at X⁰, are all below 170° ([`MAX_CORNER_SECTOR`]): at a
//!   T-junction or a reflex corner one sector would span π or more at V, which a single patch
//!   cannot do without folding; there w₃ = c_V;
//! - D_{0.5}: the halves keep D_e's; a cut curve or spoke gets the mean of its end directions
//!   (λ_L X_L − λ_R X_R)/2 (`end_d`; λ = 1 at F_e and X) from its two sectors' neighbouring
//!   sides, as the high-valence split does (docs/math.md#high-valence-split);
//! - first-approximation twists: eq. 2.11 at the face-centroid corners, the parallelogram point
//!   at F_e and X.
//!
//! At sharpness 1 a closed crease loop is G0 along the quadratic B-spline of its polygon (as if
//! the mesh were cut open there), corners (w₃ = 1) end the spokes at V itself, and the cube with
//! every edge sharp is the cube. **Limit at 0:** for 0 < c ≤ 1 the surface moves continuously, but
//! the sector split itself is not the unsplit patch: as c → 0 the sectors tend to a G1 surface
//! that follows S₀ along its nodes and cut curves, not to S₀ exactly (the unsplit patches do;
//! measured in tests/creases.rs and by examples/crease_limit). Sharpness exactly 0 takes none of
//! these steps.

use crate::gb::Evaluate;
use super::network::{end_d, side_end_scale, side_points, CurveNetwork, PatchLayout, SideUse};
use super::surface::{CageSector, Diagonals, Patch, SectorMap, Surface};
use crate::gb::Domain;
use crate::mesh::{EdgeId, HalfEdgeMesh, HalfedgeId, VertexId};
use crate::options::ConvertOptions;
use glam::{DVec2, DVec3};

/// What [`split_creases`] made: the new network and the cage rows of its patches (when the
/// unsplit ones were given).
pub struct CreaseSplit {
    pub net: CurveNetwork,
    pub cage: Vec<Vec<CageSector>>,
}

/// Which sharp input of a mesh the dual structure builds ([`cuts`]), by prepared-mesh elements.
pub struct Cuts {
    /// Per edge: cut (on a closed chain of interior sharp edges).
    pub cut: Vec<bool>,
    /// Sharp edges left smooth, as vertex pairs (origin and target of the edge's half-edge 0).
    pub ignored_edges: Vec<(VertexId, VertexId)>,
    /// Vertices whose corner sharpness is ignored (fewer than three cut edges).
    pub ignored_corners: Vec<VertexId>,
}

impl Cuts {
    /// True when some edge is cut (the patches are split).
    pub fn any(&self) -> bool {
        self.cut.iter().any(|&c| c)
    }

    /// The number of cut edges at vertex `v` of `mesh`.
    pub fn at(&self, mesh: &HalfEdgeMesh, v: VertexId) -> usize {
        mesh.vertex_outgoing(v).filter(|&h| self.cut[mesh.edge(h).idx()]).count()
    }
}

/// The cuts of `mesh` (module doc): its cut edges, and the sharp edges and corners left out.
pub fn cuts(mesh: &HalfEdgeMesh) -> Cuts {
    let (cut, ignored) = cut_edges(mesh);
    let ignored_edges = ignored
        .iter()
        .map(|&e| {
            let h = mesh.edge_halfedge(e, 0);
            (mesh.origin(h), mesh.target(h))
        })
        .collect();
    let mut cuts = Cuts { cut, ignored_edges, ignored_corners: Vec::new() };
    cuts.ignored_corners = mesh.vertices().filter(|&v| mesh.vertex_crease(v) > 0.0 && cuts.at(mesh, v) < 3).collect();
    cuts
}

/// The cut edges of `mesh` (see the module doc): the 2-core of its interior sharp edges between
/// interior vertices. Returns (cut flag per edge, the sharp edges left out).
fn cut_edges(mesh: &HalfEdgeMesh) -> (Vec<bool>, Vec<EdgeId>) {
    let mut cut = vec![false; mesh.n_edges()];
    let mut count = vec![0usize; mesh.n_vertices()];
    let mut ignored = Vec::new();
    for e in mesh.edges() {
        if mesh.edge_crease(e) <= 0.0 {
            continue;
        }
        let h = mesh.edge_halfedge(e, 0);
        let (a, b) = (mesh.origin(h), mesh.target(h));
        if mesh.is_boundary_edge(e) || mesh.is_boundary_vertex(a) || mesh.is_boundary_vertex(b) {
            ignored.push(e);
            continue;
        }
        cut[e.idx()] = true;
        count[a.idx()] += 1;
        count[b.idx()] += 1;
    }
    let mut stack: Vec<VertexId> = mesh.vertices().filter(|v| count[v.idx()] == 1).collect();
    while let Some(v) = stack.pop() {
        if count[v.idx()] != 1 {
            continue;
        }
        let Some(h) = mesh.vertex_outgoing(v).find(|&h| cut[mesh.edge(h).idx()]) else { continue };
        let e = mesh.edge(h);
        cut[e.idx()] = false;
        ignored.push(e);
        count[v.idx()] -= 1;
        let w = mesh.target(h);
        count[w.idx()] -= 1;
        if count[w.idx()] == 1 {
            stack.push(w);
        }
    }
    ignored.sort_by_key(|e| e.idx());
    (cut, ignored)
}

/// Per cut edge: the node, the crossing directions and the two halves.
struct EdgeCut {
    f: DVec3,
    /// The crossing direction at F_e towards origin(h₀) ([0]) and towards target(h₀) ([1]) at
    /// the edge's sharpness (set once both ends' S₀ directions are known).
    u: [DVec3; 2],
    /// F⁰ = D_e(½).
    f0: DVec3,
    /// The edge direction projected into S₀'s tangent plane at F⁰, towards each end (u⁰).
    u0: [DVec3; 2],
    /// S₀'s direction at F⁰ along the cut curve of each end of two cut edges (`u0` at the
    /// others; module doc).
    ufit: [DVec3; 2],
    /// The edge's [`Sharpness`].
    sharp: Sharpness,
    /// S₀'s tangent plane's normal at F⁰.
    n0: DVec3,
    a: [DVec3; 4],
    b: [DVec3; 4],
    node: usize,
    b_curve: usize,
}

/// The widest sector (170°, between consecutive sharp edges at V, around S₀'s normal) with
/// which three sharp edges still make V a corner.
const MAX_CORNER_SECTOR: f64 = 170.0 * std::f64::consts::PI / 180.0;

/// A point of a crease sector for its cage coordinates: the face centre of V's corner j, the
/// midpoint of the edge of V's outgoing half-edge j, or V itself.
#[derive(Clone, Copy)]
enum Pt {
    Face(usize),
    Edge(usize),
    Vertex,
}

/// A side's midpoint: a point or the mean of two.
#[derive(Clone, Copy)]
enum Mid {
    At(Pt),
    Avg(Pt, Pt),
}

/// The cage coordinates (σ, τ) of `p` in V's cage corner j (face(out_j)): (0,0) V, (1,0) the
/// midpoint of edge out_j, (0,1) that of edge out_{j+1}, (1,1) the face centre; `None` when `p`
/// is not a point of that corner. `n`: V's valence.
fn frame_coords(j: usize, p: Pt, n: usize) -> Option<[f64; 2]> {
    match p {
        Pt::Vertex => Some([0.0, 0.0]),
        Pt::Face(i) => (i == j).then_some([1.0, 1.0]),
        Pt::Edge(i) if i == j => Some([1.0, 0.0]),
        Pt::Edge(i) if i == (j + 1) % n => Some([0.0, 1.0]),
        Pt::Edge(_) => None,
    }
}

/// The cage row of a crease sector (docs/math.md#dual-creases): `corners[i]` = (the point at
/// corner i, the cage corner j of V whose frame its quad sector uses), `mids[i]` = the midpoint
/// of side i. The sector's centre maps to V, or, for a sector within one face, to the mean of its
/// corners. A point's coordinates in frame j are those in the user's cage corner of j
/// (`face_cage(j)`): [`Diagonals::phi`] (the rule across split diagonals, as the unsplit maps do
/// in [`SectorMap::across_diagonals`]) of its coordinates in j or, when it is not a point of j,
/// in another piece of the same split face at V (the pieces agree on the points they share);
/// points outside all of them count as V.
fn sector_cage(
    corners: &[(Pt, usize)],
    mids: &[Mid],
    n: usize,
    one_face: bool,
    face_cage: &dyn Fn(usize) -> Option<CageSector>,
    face_diagonals: &dyn Fn(usize) -> Diagonals,
) -> Vec<Option<CageSector>> {
    let user_corner = |k: usize| face_cage(k).map(|c| (c.face, c.corner));
    let same_corner = |j: usize, k: usize| k == j || (user_corner(k).is_some() && user_corner(k) == user_corner(j));
    let at = |j: usize, p: Pt| {
        let frames = match p {
            Pt::Face(i) => [i, i],
            Pt::Edge(i) => [i, (i + n - 1) % n],
            Pt::Vertex => [j, j],
        };
        std::iter::once(j)
            .chain(frames)
            .filter(|&k| same_corner(j, k))
            .find_map(|k| frame_coords(k, p, n).map(|x| face_diagonals(k).phi(x)))
            .unwrap_or([0.0, 0.0])
    };
    let add = |a: [f64; 2], b: [f64; 2], w: f64| [w * (a[0] + b[0]), w * (a[1] + b[1])];
    let mid = |j: usize, m: Mid| match m {
        Mid::At(p) => at(j, p),
        Mid::Avg(a, b) => add(at(j, a), at(j, b), 0.5),
    };
    let m = corners.len();
    (0..m)
        .map(|i| {
            let (p, j) = corners[i];
            let centre = if one_face {
                let sum = corners.iter().fold([0.0, 0.0], |acc, &(q, _)| add(acc, at(j, q), 1.0));
                [sum[0] / m as f64, sum[1] / m as f64]
            } else {
                [0.0, 0.0]
            };
            let map = SectorMap::corners(centre, mid(j, mids[i]), at(j, p), mid(j, mids[(i + 1) % m]));
            face_cage(j).map(|c| CageSector { map, ..c })
        })
        .collect()
}

/// The lengths (ℓ_a, ℓ_b) of the cubic [a, a + ℓ_a u_a, b + ℓ_b u_b, b] closest, in the least
/// squares sense, to the points `samples` (t, point) at their parameters t; `None` when the
/// normal equations are singular or a length comes out below 0.
fn fit_lengths(a: DVec3, ua: DVec3, b: DVec3, ub: DVec3, samples: &[(f64, DVec3)]) -> Option<(f64, f64)> {
    let (mut m00, mut m01, mut m11, mut r0, mut r1) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for &(t, g) in samples {
        let mut bw = [0.0f64; 4];
        crate::bezier::bernstein::bernstein_all_into(3, t, &mut bw);
        let [b0, b1, b2, b3] = bw;
        let rest = g - (b0 + b1) * a - (b2 + b3) * b;
        let (x, y) = (b1 * ua, b2 * ub);
        m00 += x.dot(x);
        m01 += x.dot(y);
        m11 += y.dot(y);
        r0 += x.dot(rest);
        r1 += y.dot(rest);
    }
    let det = m00 * m11 - m01 * m01;
    if !(det > 1e-12 * m00 * m11) {
        return None;
    }
    let (la, lb) = ((m11 * r0 - m01 * r1) / det, (m00 * r1 - m01 * r0) / det);
    (la > 0.0 && lb > 0.0 && la.is_finite() && lb.is_finite()).then_some((la, lb))
}

/// The end lengths of the cubic [a, a + ℓ_a u_a, b + ℓ_b u_b, b] that follows the points
/// `samples` (t, point) of a smooth surface (module doc: the new curves at sharpness 0): least
/// squares ([`fit_lengths`]) with the samples' parameters moved to their nearest curve points
/// (Newton steps on (B(t) − g)·B′(t)), six rounds. `None` when the first fit fails.
fn fit_curve(a: DVec3, ua: DVec3, b: DVec3, ub: DVec3, mut samples: Vec<(f64, DVec3)>) -> Option<(f64, f64)> {
    let mut l = fit_lengths(a, ua, b, ub, &samples)?;
    for _ in 0..6 {
        let Ok(curve) = crate::bezier::BezierCurve::new(vec![a, a + l.0 * ua, b + l.1 * ub, b]) else { break };
        for (t, g) in samples.iter_mut() {
            for _ in 0..3 {
                let d = curve.derivatives(*t, 2);
                let f = (d[0] - *g).dot(d[1]);
                let df = d[1].dot(d[1]) + (d[0] - *g).dot(d[2]);
                if df > 0.0 {
                    *t = (*t - f / df).clamp(0.0, 1.0);
                }
            }
        }
        match fit_lengths(a, ua, b, ub, &samples) {
            Some(x) => l = x,
            None => break,
        }
    }
    Some(l)
}

/// Below this sharpness, the cut curves of vertices with two cut edges turn from S₀'s directions
/// to the edge's (module doc): the first phase of [`Sharpness`].
const TURN: f64 = 0.25;

/// How an edge's sharpness c drives the geometry (module doc): `turn` ∈ [0, 1] moves the cut
/// curves at F_e from S₀'s directions and fitted lengths to the edge direction's, `geom` moves
/// everything else from S₀ to the sharp target. Edges with an end of two cut edges turn over
/// c ∈ [0, TURN] (geom = 0 there) and then follow geom = (c − TURN)/(1 − TURN); other edges have
/// turn = 1 and geom = c.
#[derive(Clone, Copy)]
struct Sharpness {
    turn: f64,
    geom: f64,
}

impl Sharpness {
    fn new(c: f64, turns: bool) -> Self {
        if turns {
            Sharpness { turn: (c / TURN).min(1.0), geom: ((c - TURN) / (1.0 - TURN)).max(0.0) }
        } else {
            Sharpness { turn: 1.0, geom: c }
        }
    }

    /// A length at F_e: `fit` (S₀'s) → `l0` (along the edge direction) → `l1` (sharp).
    fn length(self, fit: f64, l0: f64, l1: f64) -> f64 {
        if self.turn < 1.0 {
            fit + self.turn * (l0 - fit)
        } else {
            l0 + self.geom * (l1 - l0)
        }
    }
}

/// A domain point a hair inside the patch from `uv` (towards the centre), where S₀'s derivatives
/// at a side midpoint are taken.
fn inside(uv: DVec2) -> DVec2 {
    uv * (1.0 - 1e-7)
}

fn lerp4(x: [DVec3; 4], y: [DVec3; 4], t: f64) -> [DVec3; 4] {
    [0, 1, 2, 3].map(|i| x[i] + t * (y[i] - x[i]))
}

fn rev(c: [DVec3; 4]) -> [DVec3; 4] {
    [c[3], c[2], c[1], c[0]]
}

/// D_{0.5} of a cut curve or spoke `curve` (module doc): at sharpness 0 the direction of S₀'s
/// tangent plane across the curve's middle (n × T, `s0` the S₀ derivatives there), at sharpness
/// 1 the mean of the end directions `d0`, `d1`; the length is always that mean's.
fn mid_constraint(curve: &[DVec3; 4], s0: crate::gb::SurfaceDerivs, d0: DVec3, d1: DVec3, c: f64) -> DVec3 {
    let mean = 0.5 * (d0 + d1);
    let t = curve[3] + curve[2] - curve[1] - curve[0];
    let left = s0.su.cross(s0.sv).cross(t).normalize_or_zero();
    let smooth = if left.dot(mean) >= 0.0 { left } else { -left } * mean.length();
    smooth + c * (mean - smooth)
}

/// Splits the dual network `net` of `mesh` (built by [`super::dual::dual_network`], its patch v
/// the vertex v) along the cut edges of `cuts` (module doc). `smooth` is the surface assembled
/// from `net` (S₀), `cage` its cage rows (or empty), `diagonals(h)` the split diagonals of the
/// cage corner at half-edge h of `mesh` ([`super::prepare::Prepared::diagonals`]). `None` when
/// no edge is cut.
pub fn split_creases(
    mesh: &HalfEdgeMesh,
    cuts: &Cuts,
    net: &CurveNetwork,
    smooth: &Surface,
    cage: &[Vec<CageSector>],
    diagonals: &dyn Fn(HalfedgeId) -> Diagonals,
    opts: &ConvertOptions,
) -> Option<CreaseSplit> {
    let cut = &cuts.cut;
    if !cuts.any() {
        return None;
    }
    let k = opts.fullness;
    let mut out = net.clone();
    if out.crease.is_empty() {
        out.crease = vec![0.0; out.curves.len()];
    }
    let mut out_cage: Vec<Vec<CageSector>> = cage.to_vec();

    // 1. Nodes and halves of every cut edge.
    let mut edge_cut: Vec<Option<EdgeCut>> = (0..mesh.n_edges()).map(|_| None).collect();
    for e in mesh.edges().filter(|e| cut[e.idx()]) {
        let h = mesh.edge_halfedge(e, 0);
        let (v, w) = (mesh.position(mesh.origin(h)), mesh.position(mesh.target(h)));
        // Edges with an end of exactly two cut edges (a cut curve there) turn (`Sharpness`).
        let sharp = Sharpness::new(mesh.edge_crease(e), cuts.at(mesh, mesh.origin(h)) == 2 || cuts.at(mesh, mesh.target(h)) == 2);
        let ce = sharp.geom;
        let d = net.curves[e.idx()];
        let (cr, cl) = (d[0], d[3]);
        // De Casteljau at ½.
        let (p01, p12, p23) = ((d[0] + d[1]) / 2.0, (d[1] + d[2]) / 2.0, (d[2] + d[3]) / 2.0);
        let (q0, q1) = ((p01 + p12) / 2.0, (p12 + p23) / 2.0);
        let f0 = (q0 + q1) / 2.0;
        let m = (v + w) / 2.0;
        let a0 = [d[0], p01, q0, f0];
        let b0 = [f0, q1, p23, d[3]];
        let a1 = [cr, p01, cr + 0.25 * (3.0 - k) * (m - cr), m];
        let b1 = [m, cl + 0.25 * (3.0 - k) * (m - cl), p23, cl];
        // S₀'s tangent plane at F⁰: D_e′(½) and D_{0.5} (into the patch of origin(h)). The
        // crossing directions start as the edge's projected into it (kept where S₀'s own
        // direction is degenerate, below).
        let n0 = (q1 - q0).cross(net.mid[e.idx()]).normalize_or_zero();
        let edge = v - w;
        let u0 = (edge - n0 * n0.dot(edge)).normalize_or_zero();
        let (a, b) = (lerp4(a0, a1, ce), lerp4(b0, b1, ce));
        let node = out.nodes.len();
        out.nodes.push(a[3]);
        out.node_normals.push(n0); // set in step 3
        // A replaces D_e (curve e), B is new.
        out.curves[e.idx()] = a;
        out.curve_nodes[e.idx()] = [net.curve_nodes[e.idx()][0], node];
        let b_curve = out.curves.len();
        out.curves.push(b);
        out.curve_nodes.push([node, net.curve_nodes[e.idx()][1]]);
        out.mid.push(net.mid[e.idx()]);
        out.crease.push(0.0);
        // The halves' parameters run twice as fast as D_e's: at the face centroids their end
        // vectors count twice in the blends' D, which stays S₀'s there.
        out.end_scale.resize(out.curves.len() - 1, [1.0, 1.0]);
        out.end_scale[e.idx()] = [2.0, 1.0];
        out.end_scale.push([1.0, 2.0]);
        edge_cut[e.idx()] = Some(EdgeCut { f: a[3], u: [u0, -u0], f0, u0: [u0, -u0], ufit: [u0, -u0], sharp, n0, a, b, node, b_curve });
    }

    // 2. S₀'s directions at F⁰ of the cut curves (vertices with exactly two cut edges): S₀'s
    // derivative at the side's midpoint along the straight domain segment to the other cut
    // side's midpoint, so that the cut curve leaves F_e along S₀'s image of that segment. Kept
    // only where it points to V's side (the same side as u⁰); elsewhere `ufit` stays u⁰.
    for v in mesh.vertices() {
        let outg: Vec<HalfedgeId> = mesh.vertex_outgoing(v).collect();
        let n = outg.len();
        let js: Vec<usize> = (0..n).filter(|&j| cut[mesh.edge(outg[j]).idx()]).collect();
        if js.len() != 2 {
            continue;
        }
        let Some(patch @ Patch::Gb(_)) = smooth.patches.get(v.idx()) else { return None };
        let Ok(dom) = Domain::regular(n) else { return None };
        for (i, &j) in js.iter().enumerate() {
            let mid = dom.side_point(j, 0.5);
            let along = dom.side_point(js[1 - i], 0.5) - mid;
            let d = patch.eval_derivs(inside(mid), opts.weights);
            let t = (d.su * along.x + d.sv * along.y).normalize_or_zero();
            let h = outg[j];
            let ec = edge_cut[mesh.edge(h).idx()].as_mut().expect("cut edges have nodes");
            let end = (h.0 & 1) as usize; // 0: v = origin(h₀)
            // In S₀'s plane at F⁰ exactly (the patch's derivative is, to G1's precision).
            let t = (t - ec.n0 * ec.n0.dot(t)).normalize_or_zero();
            if t.dot(ec.u0[end]) > 0.0 {
                ec.ufit[end] = t;
            }
        }
    }
    // 3. The crossing directions at each end: from S₀'s (`ufit`) to u⁰ while the edge turns,
    // then u = unit(u⁰ + geom (u¹ − u⁰)), u¹ the edge direction towards that end. While turning
    // the halves are S₀'s (geom = 0) and every direction lies in S₀'s tangent plane at F⁰;
    // after, the two ends' directions are opposite. The node's tangent plane is spanned by the
    // halves' tangent and the mean crossing direction.
    for e in mesh.edges().filter(|e| cut[e.idx()]) {
        let h = mesh.edge_halfedge(e, 0);
        let u1 = (mesh.position(mesh.origin(h)) - mesh.position(mesh.target(h))).normalize_or_zero();
        let ec = edge_cut[e.idx()].as_mut().expect("cut edges have nodes");
        let Sharpness { turn, geom } = ec.sharp;
        let dir = |end: usize, to: DVec3| {
            if turn < 1.0 {
                (ec.ufit[end] + turn * (ec.u0[end] - ec.ufit[end])).normalize_or(ec.u0[end])
            } else {
                (ec.u0[end] + geom * (to - ec.u0[end])).normalize_or_zero()
            }
        };
        let (uo, ut) = (dir(0, u1), dir(1, -u1));
        let nn = (ec.b[1] - ec.a[2]).cross(uo - ut).normalize_or(ec.n0);
        ec.u = [uo, ut];
        out.node_normals[ec.node] = nn;
    }

    // 4. The sectors of every vertex with cut edges.
    for v in mesh.vertices() {
        let outg: Vec<HalfedgeId> = mesh.vertex_outgoing(v).collect();
        let n = outg.len();
        let js: Vec<usize> = (0..n).filter(|&j| cut[mesh.edge(outg[j]).idx()]).collect();
        let kc = js.len();
        if kc < 2 {
            continue;
        }
        let vp = mesh.position(v);
        let lay = &net.patches[v.idx()];
        // Both hold for the dual patch of an interior vertex; if not, nothing is split (the
        // network built so far is dropped, never left half-split).
        let Some(patch @ Patch::Gb(_)) = smooth.patches.get(v.idx()) else { return None };
        let Ok(dom) = Domain::regular(n) else { return None };
        let eval = |uv: DVec2| patch.eval_derivs(uv, opts.weights);
        // Per cut side j (index into js): node, direction towards V, halves as patch V traverses
        // side j: first (corner j−1 → F), second (F → corner j), with their SideUses.
        struct Side {
            f: DVec3,
            u: DVec3,
            f0: DVec3,
            u0: DVec3,
            ufit: DVec3,
            sharp: Sharpness,
            m: DVec3,
            node: usize,
            first: [DVec3; 4],
            second: [DVec3; 4],
            first_use: SideUse,
            second_use: SideUse,
            c: f64,
            mid_uv: DVec2,
        }
        let sides: Vec<Side> = js
            .iter()
            .map(|&j| {
                let h = outg[j];
                let e = mesh.edge(h);
                let ec = edge_cut[e.idx()].as_ref().expect("cut edges have nodes");
                let m = (vp + mesh.position(mesh.target(h))) / 2.0;
                let forward = h.0 & 1 == 0; // v = origin(h₀): the side runs along A then B
                let (first, second, first_use, second_use, u) = if forward {
                    (
                        ec.a,
                        ec.b,
                        SideUse { curve: e.idx(), reversed: false },
                        SideUse { curve: ec.b_curve, reversed: false },
                        ec.u[0],
                    )
                } else {
                    (
                        rev(ec.b),
                        rev(ec.a),
                        SideUse { curve: ec.b_curve, reversed: true },
                        SideUse { curve: e.idx(), reversed: true },
                        ec.u[1],
                    )
                };
                Side {
                    f: ec.f,
                    u,
                    f0: ec.f0,
                    u0: ec.u0[usize::from(!forward)],
                    ufit: ec.ufit[usize::from(!forward)],
                    sharp: ec.sharp,
                    m,
                    node: ec.node,
                    first,
                    second,
                    first_use,
                    second_use,
                    c: mesh.edge_crease(e),
                    mid_uv: dom.side_point(j, 0.5),
                }
            })
            .collect();
        // ℓ⁰ at the F end of a curve leaving F towards the domain direction `along`: S₀′ at the
        // side midpoint (a hair inside) along it, projected on u⁰, over 3.
        let ell0 = |s: &Side, along: DVec2| {
            let d = eval(inside(s.mid_uv));
            let t = d.su * along.x + d.sv * along.y;
            (t.dot(s.u0) / 3.0).max(0.05 * t.length() / 3.0)
        };
        let ell = |s: &Side, l0: f64, l1: f64| s.sharp.length(l0, l0, l1);
        // D at F_e of a curve leaving F_e (eq. 4.7 with the end scales, `end_d`), from the two
        // halves of side s: X of the second half (at its start) on the curve's left when
        // `second_left`, else X of the first half (at its end). The halves' scales are 1 at F_e
        // (2 only at their face-centroid ends), so this is (X_L − X_R)/2.
        let d_at_f = |out: &CurveNetwork, s: &Side, second_left: bool| {
            let xs = (side_end_scale(out, s.second_use, false), 3.0 * (s.second[1] - s.f));
            let xf = (side_end_scale(out, s.first_use, true), 3.0 * (s.first[2] - s.f));
            let ((la, xa), (lb, xb)) = if second_left { (xs, xf) } else { (xf, xs) };
            end_d([la, lb], xa, xb)
        };
        let first_spoke = out.curves.len();
        let mut closing: Vec<Vec<SideUse>> = Vec::with_capacity(kc);
        if kc == 2 {
            let (sa, sb) = (&sides[0], &sides[1]);
            let seg = sb.mid_uv - sa.mid_uv;
            // At sharpness 0 the cut curve follows S₀ along the straight domain segment: its end
            // lengths fitted to S₀ there (the plain Hermite lengths if the fit fails).
            let (l0a, l0b) = (ell0(sa, seg), ell0(sb, -seg));
            let turning = sa.sharp.turn < 1.0 || sb.sharp.turn < 1.0;
            let fitted = turning.then(|| {
                let samples = (1..8).map(|i| i as f64 / 8.0).map(|t| (t, eval(sa.mid_uv + t * seg).p)).collect();
                fit_curve(sa.f0, sa.ufit, sb.f0, sb.ufit, samples)
            });
            let (fa, fb) = fitted.flatten().unwrap_or((l0a, l0b));
            let la = sa.sharp.length(fa, l0a, (2.0 / 3.0) * vp.distance(sa.m));
            let lb = sb.sharp.length(fb, l0b, (2.0 / 3.0) * vp.distance(sb.m));
            let kcurve = [sa.f, sa.f + la * sa.u, sb.f + lb * sb.u, sb.f];
            // Left = sector 1 (runs F_a → F_b forward): at F_a it holds the first half of side a,
            // at F_b the second half of side b.
            let (d0, d1) = (d_at_f(&out, sa, false), d_at_f(&out, sb, true));
            out.curves.push(kcurve);
            out.curve_nodes.push([sa.node, sb.node]);
            out.mid.push(mid_constraint(&kcurve, eval((sa.mid_uv + sb.mid_uv) / 2.0), d0, d1, sa.sharp.geom.min(sb.sharp.geom)));
            out.crease.push(sa.c.min(sb.c));
            closing.push(vec![SideUse { curve: first_spoke, reversed: true }]);
            closing.push(vec![SideUse { curve: first_spoke, reversed: false }]);
        } else {
            let mut cs: Vec<f64> = sides.iter().map(|s| s.c).collect();
            cs.sort_by(|a, b| b.total_cmp(a));
            let d = eval(DVec2::ZERO);
            let x0 = d.p;
            let nx = d.su.cross(d.sv).normalize_or_zero();
            // Three sharp edges make V a corner (w₃ = c₍₃₎) only where the sectors between its
            // edges all open less than π around S₀'s normal: at a T-junction or a reflex corner a
            // sector would have a corner angle of π or more at V, which one patch cannot span
            // without folding. There only the corner sharpness c_V moves X to V.
            let plane = |d: DVec3| (d - nx * nx.dot(d)).normalize_or_zero();
            let ccw = |a: DVec3, b: DVec3| a.cross(b).dot(nx).atan2(a.dot(b)).rem_euclid(std::f64::consts::TAU);
            let convex = (0..kc).all(|i| ccw(plane(sides[i].m - vp), plane(sides[(i + 1) % kc].m - vp)) < MAX_CORNER_SECTOR);
            let w3 = if convex { mesh.vertex_crease(v).max(cs[2]) } else { mesh.vertex_crease(v) };
            let x = x0 + w3 * (vp - x0);
            // Spoke directions at X⁰ in the domain: angle θ_s = ¼·(angle of side j_s's midpoint)
            // + ¾·(that of spoke 0 + 2πs/k), so every angle between consecutive spokes is below
            // π (a domain sector is below 2π, a quarter of it plus ¾·2π/k ≤ π/2 stays below π for
            // k ≥ 3): the spokes leave X⁰ as a star, also where three crease lines meet in a T.
            let angle = |uv: DVec2| uv.y.atan2(uv.x);
            let a0 = angle(sides[0].mid_uv);
            let tau = std::f64::consts::TAU;
            let spokes: Vec<[DVec3; 4]> = sides
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    let dom = a0 + (angle(s.mid_uv) - a0).rem_euclid(tau);
                    let eq = a0 + tau * i as f64 / kc as f64;
                    let th = 0.25 * dom + 0.75 * eq;
                    let ray = s.mid_uv.length() * DVec2::new(th.cos(), th.sin());
                    let t0 = d.su * ray.x + d.sv * ray.y;
                    let mut c1 = x + (1.0 - w3) * t0 / 3.0 + w3 * (s.m - vp) / 3.0;
                    c1 -= (1.0 - w3) * nx * nx.dot(c1 - x);
                    let l = ell(s, ell0(s, -s.mid_uv), vp.distance(s.m) / 3.0);
                    [x, c1, s.f + l * s.u, s.f]
                })
                .collect();
            let node = out.nodes.len();
            out.nodes.push(x);
            out.node_normals.push(nx);
            for (i, s) in sides.iter().enumerate() {
                let (next, prev) = (&spokes[(i + 1) % kc], &spokes[(i + kc - 1) % kc]);
                // Left = sector i: at X its other spoke is i+1; at F it holds the second half.
                let d0 = end_d([1.0, 1.0], 3.0 * (next[1] - x), 3.0 * (prev[1] - x)); // spokes: new curves
                let d1 = d_at_f(&out, s, true);
                out.curves.push(spokes[i]);
                out.curve_nodes.push([node, s.node]);
                out.mid.push(mid_constraint(&spokes[i], eval(s.mid_uv / 2.0), d0, d1, s.sharp.geom));
                out.crease.push(s.c);
            }
            for s in 0..kc {
                closing.push(vec![
                    SideUse { curve: first_spoke + (s + 1) % kc, reversed: true },
                    SideUse { curve: first_spoke + s, reversed: false },
                ]);
            }
        }
        // Sector patches: sides and, per corner (the end of each side), the first-approximation
        // twist of the unsplit patch (face corners) or None (parallelogram), and the cage sector.
        let row = cage.get(v.idx());
        let face_cage = |j: usize| row.and_then(|r| r.get(j % n)).copied();
        let face_diagonals = |j: usize| diagonals(outg[j % n]);
        let mut parts: Vec<(Vec<SideUse>, Vec<Option<DVec3>>, Vec<Option<CageSector>>)> = Vec::new();
        for s in 0..kc {
            let (j0, j1) = (js[s], if s + 1 < kc { js[s + 1] } else { js[0] + n });
            let mut sides_out = vec![sides[s].second_use];
            sides_out.extend((j0 + 1..j1).map(|j| lay.sides[j % n]));
            let s1 = (s + 1) % kc;
            sides_out.push(sides[s1].first_use);
            sides_out.extend(closing[s].iter().copied());
            let mut twists: Vec<Option<DVec3>> = (j0..j1).map(|j| Some(lay.corner_twists[j % n])).collect();
            twists.extend(std::iter::repeat_n(None, closing[s].len() + 1));
            // Cage coordinates (docs/math.md#cage-corners): every corner and side midpoint of
            // the sector as a point of V's cage corners, each quad sector in one face's frame.
            let mut corners: Vec<(Pt, usize)> = (j0..j1).map(|j| (Pt::Face(j % n), j % n)).collect();
            let mut mids: Vec<Mid> = vec![Mid::Avg(Pt::Edge(j0 % n), Pt::Face(j0 % n))];
            mids.extend((j0 + 1..j1).map(|j| Mid::At(Pt::Edge(j % n))));
            mids.push(Mid::Avg(Pt::Face((j1 - 1) % n), Pt::Edge(j1 % n)));
            corners.push((Pt::Edge(j1 % n), (j1 - 1) % n));
            if kc == 2 {
                // The cut curve follows the crease polygon F_a → V → F_b (its quadratic B-spline
                // at sharpness 1): its midpoint maps to V, the one point of every frame it meets.
                mids.push(Mid::At(Pt::Vertex));
            } else {
                // A spoke's midpoint is (V + M_e)/2, or V where the sector it closes at F_e (the
                // one whose last face it follows) spans two faces or more: that sector's X corner
                // is in the frame of its first face, where M_e is no frame point and would count
                // as V in one quad and not in the next (docs/math.md#cage-corners). The same rule
                // in both sectors at the spoke.
                let span = |t: usize| (js[(t + 1) % kc] + n - js[t] - 1) % n + 1;
                let spoke_mid = |e: usize, closes: usize| {
                    if span(closes) >= 2 { Mid::At(Pt::Vertex) } else { Mid::Avg(Pt::Edge(e % n), Pt::Vertex) }
                };
                mids.push(spoke_mid(j1, s));
                mids.push(spoke_mid(j0, (s + kc - 1) % kc));
                corners.push((Pt::Vertex, j0 % n));
            }
            corners.push((Pt::Edge(j0 % n), j0 % n));
            let cage_row = sector_cage(&corners, &mids, n, j1 - j0 == 1, &face_cage, &face_diagonals);
            parts.push((sides_out, twists, cage_row));
        }
        for (i, (sides_out, twists, cage_row)) in parts.into_iter().enumerate() {
            let m = sides_out.len();
            let pts: Vec<[DVec3; 4]> = sides_out.iter().map(|&u| side_points(&out, u)).collect();
            let twists: Vec<DVec3> = (0..m)
                .map(|i| twists[i].unwrap_or_else(|| pts[i][2] + pts[(i + 1) % m][1] - pts[i][3]))
                .collect();
            let part = PatchLayout { sides: sides_out, corner_twists: twists, center: None, source: lay.source };
            let index = if i == 0 { v.idx() } else { out.patches.len() };
            if i == 0 {
                out.patches[index] = part;
            } else {
                out.patches.push(part);
            }
            if row.is_some() {
                let r: Vec<CageSector> = cage_row
                    .into_iter()
                    .map(|c| c.unwrap_or(CageSector { face: u32::MAX, corner: u32::MAX, map: SectorMap::Vertex }))
                    .collect();
                // Parts after the first are appended in patch order.
                if index < out_cage.len() {
                    out_cage[index] = r;
                } else {
                    out_cage.push(r);
                }
            }
        }
    }
    Some(CreaseSplit { net: out, cage: out_cage })
}
