//! Validity checks of a conversion's output: folds inside the patches, self-intersections of the
//! output triangle mesh (and of the input cage, so a report can tell new intersections from the
//! input's own), and the largest |H| times the bounding-box diagonal.
//!
//! - Folds: a sample of domain triangle i (centre, v_{i−1}, v_i) with barycentric weights
//!   (a, b, c) on (centre, v_{i−1}, v_i) is folded where its unit normal (S_u × S_v)/|S_u × S_v|
//!   turns against the reference normal R = unit((1 − a)·N_i(s) + a·N̄): N_i(s) the boundary
//!   frame normal T × X of ribbon i ([`ribbon_frame`](crate::construct::check::ribbon_frame)) at
//!   s = c/(b + c), the foot of the sample on side i, and N̄ the unit mean of the ribbons' normals
//!   at their midpoints, or the boundary's unit vector area where that is more than 60° away and
//!   nearer to the patch's normal at its centre ([`crate::tessellate::fold::centre_reference`],
//!   [`crate::tessellate::fold::blended_reference`], docs/math.md#folds, #fold-centre), and a
//!   neighbouring sample's normal points the other way (n·n′ < 0, docs/math.md#fold-neighbours):
//!   the parameterisation turned over. Both normals are oriented alike (side i runs
//!   counter-clockwise, X points into the domain).
//!   Every conversion applies this rule inside the tessellation pass to the samples it evaluates
//!   anyway and, on every patch those samples do not clear
//!   ([`crate::tessellate::fold::ClearTest`]), on a dense grid whose folded samples replace
//!   theirs and whose worst point becomes the patch's site
//!   ([`crate::tessellate::fold::dense_folds_of`], docs/math.md#fold-clearing; collected by
//!   [`Folds::of_tessellation`]), and also counts flipped output triangles (geometric normal
//!   against all three vertex normals). The per-vertex flag `SurfaceMesh::fold` marks both.
//!   [`find_folds`] applies the same rule on every patch at one level (a conversion's:
//!   [`crate::tessellate::fold::dense_level`]) as a reference for tests and studies.
//! - Self-intersections ([`self_intersections`]): pairs of triangles sharing no vertex, in the
//!   same connected shell, that have a point in common. Candidate pairs come from a bounding
//!   volume hierarchy of the boxes of chunks of nearby triangles ([`overlapping_boxes`]); each
//!   pair is decided exactly with Shewchuk's adaptive orientation predicates (crate `robust`): two triangles meet iff an
//!   edge of one meets the other (closed sets; a segment that crosses the other triangle's plane
//!   meets it iff the three orientations of the segment against the triangle's edges agree, a
//!   segment in that plane is tested in 2D). Pairs inside regions certified free of
//!   self-intersections (stars of the patches' nodes, [`super::certify`], with the proof) are
//!   skipped by [`self_intersections_certified`]; every conversion uses it
//!   ([`mesh_self_intersections`]). Closed shells that are star-shaped around their centre
//!   ([`super::certify::star_shaped_shells`], with the proof) leave the search altogether.

use super::certify::{star_shaped_about_centroid, star_shaped_shells, star_shaped_shells_ticked, Certified, ChunkRegions};
use crate::construct::Surface;
use crate::gb::WeightForm;
use crate::tessellate::SurfaceMesh;
use crate::mesh::PolyMesh;
use glam::DVec3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use rayon::prelude::*;
use crate::progress::{Cancelled, Ticker};
use robust::{orient2d, orient3d, Coord, Coord3D};

/// At most this many fold sites are listed in a report.
pub const MAX_FOLD_SITES: usize = 10;

/// Where a patch folds: the patch index and the domain point of its most negative Jacobian
/// (the regular n-gon domain of [`Domain::regular`]).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FoldSite {
    pub patch: usize,
    pub u: f64,
    pub v: f64,
}

/// Result of [`find_folds`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Folds {
    /// Patches with at least one folded sample.
    pub patches: usize,
    /// Folded samples in all.
    pub samples: usize,
    /// The first [`MAX_FOLD_SITES`] patches with folded samples (in patch order) and where.
    pub sites: Vec<FoldSite>,
    /// Output triangles turned over against their vertices' normals (0 from [`find_folds`]).
    pub flipped_triangles: usize,
}

impl Folds {
    /// The folds the tessellation found on its own samples ([`crate::tessellate::fold`]): a
    /// patch folds where it has a folded sample or a flipped triangle.
    pub fn of_tessellation(mesh: &SurfaceMesh) -> Folds {
        let folded = folded_patches(mesh);
        let mut out = Folds { flipped_triangles: mesh.flipped_triangles.len(), ..Folds::default() };
        for (p, (f, &is)) in mesh.patch_folds.iter().zip(&folded).enumerate() {
            if !is {
                continue;
            }
            out.patches += 1;
            out.samples += f.samples;
            if let (Some(uv), true) = (f.worst, out.sites.len() < MAX_FOLD_SITES) {
                out.sites.push(FoldSite { patch: p, u: uv.x, v: uv.y });
            }
        }
        out
    }
}

/// Per patch of the tessellation `mesh`: it folds (a folded sample or a flipped triangle; the
/// triangle's patch from its range in `patch_loops`, as `triangle_patch` may be empty).
fn folded_patches(mesh: &SurfaceMesh) -> Vec<bool> {
    let mut folded: Vec<bool> = mesh.patch_folds.iter().map(|f| f.samples > 0).collect();
    for &t in &mesh.flipped_triangles {
        if let Some(f) = mesh.patch_loops.patch_of(t as usize).and_then(|p| folded.get_mut(p)) {
            *f = true;
        }
    }
    folded
}

/// Vertices where the cage itself turns back: an incident face's Newell normal lies more than
/// 90° from the vertex normal (the sum of the incident faces' Newell normals, so area-weighted).
/// A smooth surface over such a vertex has to turn as sharply, and the folds of public cages
/// sit there (MeshLab's cow; OpenSubdiv's rook: 17 of its 18 dual folds), so the report points
/// at them; it is a diagnosis, not a proof that the cage causes the fold.
pub fn cage_fold_vertices(cage: &crate::mesh::HalfEdgeMesh) -> Vec<bool> {
    use crate::mesh::geometry::newell_normal;
    let normals: Vec<DVec3> = (0..cage.n_faces() as u32)
        .map(|f| {
            let pts: Vec<DVec3> = cage.face_vertices(crate::mesh::FaceId(f)).map(|v| cage.position(v)).collect();
            newell_normal(&pts)
        })
        .collect();
    cage.vertices()
        .map(|v| {
            let faces: Vec<DVec3> = cage.vertex_outgoing(v).filter_map(|h| cage.face(h)).map(|f| normals[f.idx()]).collect();
            let n = faces.iter().copied().sum::<DVec3>();
            faces.iter().any(|f| f.dot(n) < 0.0)
        })
        .collect()
}

/// Of the folded patches of `mesh` (as [`Folds::of_tessellation`] counts them), those whose
/// cage element (`sources`, in the user's numbering: a vertex of `cage`, or a face as written,
/// which is several faces of `cage` when it has holes, [`crate::mesh::HalfEdgeMesh::input_face`])
/// has a vertex where the cage itself folds ([`cage_fold_vertices`]): their number and the first
/// such cage vertex.
pub fn folds_at_cage_folds(mesh: &SurfaceMesh, sources: &[crate::construct::PatchSource], cage: &crate::mesh::HalfEdgeMesh) -> (usize, Option<usize>) {
    use crate::construct::PatchSource;
    let folded = folded_patches(mesh);
    if !folded.iter().any(|&f| f) {
        return (0, None);
    }
    let bad = cage_fold_vertices(cage);
    let at = |v: usize| bad.get(v).copied().unwrap_or(false);
    // Per face as written: its first vertex (piece by piece) where the cage folds.
    let mut face_hit: Vec<Option<usize>> = Vec::new();
    for g in cage.faces() {
        let f = cage.input_face(g);
        if f >= face_hit.len() {
            face_hit.resize(f + 1, None);
        }
        if face_hit[f].is_none() {
            face_hit[f] = cage.face_vertices(g).map(|v| v.idx()).find(|&v| at(v));
        }
    }
    let (mut count, mut first) = (0, None);
    for (p, _) in folded.iter().enumerate().filter(|x| *x.1) {
        let hit = match sources.get(p) {
            Some(&PatchSource::Vertex(v)) => at(v).then_some(v),
            Some(&PatchSource::Face(f)) => face_hit.get(f).copied().flatten(),
            _ => None,
        };
        if let Some(v) = hit {
            count += 1;
            first = first.or(Some(v));
        }
    }
    (count, first)
}

/// Samples every patch of `surface` at `level` (that of a conversion:
/// [`crate::tessellate::fold::dense_level`]) and reports the patches
/// whose Jacobian turns negative against their ribbons' normals (see the module doc).
///
/// The samples are those of a tessellation at resolution `level` (the [`crate::gb::SampleLayout`] of the
/// patch's domain, 1 + n·level(level+1)/2 points, boundary included), evaluated with the same
/// weight-table kernel as the tessellation ([`crate::tessellate::GbSurfaceEvaluator`]); the sign of the unit normal
/// (S_u × S_v)/|S_u × S_v| is that of the Jacobian. Samples whose normal is undefined (a
/// degenerate Jacobian, e.g. at a collapsed corner) are skipped, as the sign is meaningless there.
/// A surface the table evaluator refuses falls back to the direct evaluator on the grids of
/// [`fold_sample_points`](crate::construct::check::fold_sample_points)
/// ([`crate::tessellate::fold::dense_folds_of`], the dense pass of every conversion).
pub fn find_folds(surface: &Surface, level: usize, form: WeightForm) -> Folds {
    let level = level.max(1);
    let all: Vec<usize> = (0..surface.patches.len()).collect();
    let per = crate::tessellate::fold::dense_folds_of(surface, &all, level, form);
    let mut f = Folds::default();
    for (p, (count, at)) in per.into_iter().enumerate() {
        if count == 0 {
            continue;
        }
        f.patches += 1;
        f.samples += count;
        if let (Some(uv), true) = (at, f.sites.len() < MAX_FOLD_SITES) {
            f.sites.push(FoldSite { patch: p, u: uv.x, v: uv.y });
        }
    }
    f
}

fn c3(p: DVec3) -> Coord3D<f64> {
    Coord3D { x: p.x, y: p.y, z: p.z }
}

/// Sign of the orientation of d against the plane (a, b, c): −1, 0 or 1, exact.
fn orient(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> i8 {
    let o = orient3d(c3(a), c3(b), c3(c), c3(d));
    (o > 0.0) as i8 - (o < 0.0) as i8
}

/// Exact 2D orientation sign of points projected by dropping coordinate `drop`.
fn orient_2d(drop: usize, a: DVec3, b: DVec3, c: DVec3) -> i8 {
    let pr = |p: DVec3| {
        let q = match drop {
            0 => (p.y, p.z),
            1 => (p.z, p.x),
            _ => (p.x, p.y),
        };
        Coord { x: q.0, y: q.1 }
    };
    let o = orient2d(pr(a), pr(b), pr(c));
    (o > 0.0) as i8 - (o < 0.0) as i8
}

/// Closed segments [p, q] and [a, b], collinear-aware, in the projection dropping `drop`.
fn segments_meet_2d(drop: usize, p: DVec3, q: DVec3, a: DVec3, b: DVec3) -> bool {
    let (o1, o2) = (orient_2d(drop, p, q, a), orient_2d(drop, p, q, b));
    let (o3, o4) = (orient_2d(drop, a, b, p), orient_2d(drop, a, b, q));
    let keep = |x: DVec3| -> [f64; 2] {
        match drop {
            0 => [x.y, x.z],
            1 => [x.z, x.x],
            _ => [x.x, x.y],
        }
    };
    let on = |s: DVec3, e: DVec3, x: DVec3| {
        let (s, e, x) = (keep(s), keep(e), keep(x));
        (0..2).all(|k| s[k].min(e[k]) <= x[k] && x[k] <= s[k].max(e[k]))
    };
    if o1 * o2 < 0 && o3 * o4 < 0 {
        return true;
    }
    (o1 == 0 && on(p, q, a)) || (o2 == 0 && on(p, q, b)) || (o3 == 0 && on(a, b, p)) || (o4 == 0 && on(a, b, q))
}

/// The closed segment [p, q] meets the closed triangle t (non-degenerate), exactly.
fn segment_meets_triangle(p: DVec3, q: DVec3, t: [DVec3; 3]) -> bool {
    let (sp, sq) = (orient(t[0], t[1], t[2], p), orient(t[0], t[1], t[2], q));
    if sp * sq > 0 {
        return false;
    }
    if sp == 0 && sq == 0 {
        // In the triangle's plane: project along the normal's largest coordinate.
        let nrm = (t[1] - t[0]).cross(t[2] - t[0]).abs();
        let drop = if nrm.x >= nrm.y && nrm.x >= nrm.z { 0 } else if nrm.y >= nrm.z { 1 } else { 2 };
        let inside = |x: DVec3| {
            let o = [orient_2d(drop, t[0], t[1], x), orient_2d(drop, t[1], t[2], x), orient_2d(drop, t[2], t[0], x)];
            !(o.iter().any(|&s| s > 0) && o.iter().any(|&s| s < 0))
        };
        return inside(p) || inside(q) || (0..3).any(|k| segments_meet_2d(drop, p, q, t[k], t[(k + 1) % 3]));
    }
    // Crossing the plane: the line through p, q passes inside (or on) the triangle.
    let o = [orient(p, q, t[0], t[1]), orient(p, q, t[1], t[2]), orient(p, q, t[2], t[0])];
    !(o.iter().any(|&s| s > 0) && o.iter().any(|&s| s < 0))
}

/// The plane of a triangle, for the floating-point filter of [`orient_filtered`]: its first
/// vertex, the rounded normal (e1 × e2 with e1 = b − a, e2 = c − a) and the rounded absolute
/// products of every minor (|e1_j e2_k| + |e1_k e2_j|).
#[derive(Clone, Copy)]
struct FilterPlane {
    a: DVec3,
    n: DVec3,
    m: DVec3,
}

impl FilterPlane {
    fn new(t: [DVec3; 3]) -> FilterPlane {
        let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
        let m = DVec3::new(
            (e1.y * e2.z).abs() + (e1.z * e2.y).abs(),
            (e1.z * e2.x).abs() + (e1.x * e2.z).abs(),
            (e1.x * e2.y).abs() + (e1.y * e2.x).abs(),
        );
        FilterPlane { a: t[0], n: e1.cross(e2), m }
    }

    /// The sign of det(e1, e2, x − a) where floating point proves it, else 0 (see
    /// [`orient_filtered`] for the bound).
    fn side(&self, x: DVec3) -> i8 {
        let w = x - self.a;
        let det = w.dot(self.n);
        let perm = w.abs().dot(self.m);
        // Below 1e-200 (or on overflow) the relative bound does not cover underflow: undecided.
        if !(perm >= 1e-200 && perm < f64::MAX) {
            return 0;
        }
        let bound = FILTER_EPS * perm;
        (det > bound) as i8 - (det < -bound) as i8
    }
}

/// Relative error bound of the filter: 12 u with the unit roundoff u = ε/2 (the derivation in
/// [`orient_filtered`] gives 8.01 u).
const FILTER_EPS: f64 = 12.0 * f64::EPSILON / 2.0;

/// The orientation of `d` against the plane of (a, b, c) decided in floating point where that is
/// provably right, `None` where the exact predicate must decide. `Some(s)` has the sign of
/// det(b − a, c − a, d − a) (the opposite of [`robust::orient3d`]'s, which is positive below).
///
/// Bound: det = Σ ± w_i e1_j e2_k over six products of the differences w = d − a, e1 = b − a,
/// e2 = c − a. In floating point (unit roundoff u = ε/2) every product passes through at most 8
/// roundings (three differences, the product e1_j e2_k, the minor's subtraction, the product with
/// w_i, two additions of the dot product), so |fl(det) − det| ≤ γ₈ P with γ₈ = 8u/(1 − 8u) and
/// P = Σ |w_i e1_j e2_k| of the exact differences (Higham, Accuracy and Stability, §3.1).
/// P ≤ fl(P̂)/((1 − γ₈)(1 − u)³) for the permanent fl(P̂) computed alike from the rounded
/// differences, so |fl(det) − det| < 8.01 u fl(P̂) ≤ 12 u fl(P̂): a rounded det beyond that bound
/// has the exact sign. Underflow adds at most a few subnormal units, far below the bound once
/// fl(P̂) ≥ 1e-200; smaller or non-finite permanents are left undecided.
pub fn orient_filtered(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Option<i8> {
    match FilterPlane::new([a, b, c]).side(d) {
        0 => None,
        s => Some(s),
    }
}

/// All three points strictly on one side of the plane, proven in floating point.
fn separated_by(plane: &FilterPlane, t: &[DVec3; 3]) -> bool {
    let s = t.map(|x| plane.side(x));
    (s[0] == 1 && s[1] == 1 && s[2] == 1) || (s[0] == -1 && s[1] == -1 && s[2] == -1)
}

/// Two closed, non-degenerate triangles have a point in common (exact predicates).
///
/// A floating-point filter with a proven error bound ([`orient_filtered`]) first rejects pairs
/// where one triangle lies strictly on one side of the other's plane, the common case for nearby
/// triangles of a smooth surface; every other pair goes to the exact predicates.
pub fn triangles_intersect(a: [DVec3; 3], b: [DVec3; 3]) -> bool {
    if separated_by(&FilterPlane::new(a), &b) || separated_by(&FilterPlane::new(b), &a) {
        return false;
    }
    triangles_intersect_exact(a, b)
}

/// [`triangles_intersect`] with the exact predicates only.
pub fn triangles_intersect_exact(a: [DVec3; 3], b: [DVec3; 3]) -> bool {
    // Quick rejection: all of one triangle strictly on one side of the other's plane.
    let sb = b.map(|x| orient(a[0], a[1], a[2], x));
    if sb.iter().all(|&s| s > 0) || sb.iter().all(|&s| s < 0) {
        return false;
    }
    let sa = a.map(|x| orient(b[0], b[1], b[2], x));
    if sa.iter().all(|&s| s > 0) || sa.iter().all(|&s| s < 0) {
        return false;
    }
    (0..3).any(|k| segment_meets_triangle(a[k], a[(k + 1) % 3], b)) || (0..3).any(|k| segment_meets_triangle(b[k], b[(k + 1) % 3], a))
}

fn degenerate(t: [DVec3; 3]) -> bool {
    (t[1] - t[0]).cross(t[2] - t[0]) == DVec3::ZERO || t.iter().any(|p| !p.is_finite())
}

/// Shell (connected component through shared vertices) of every triangle.
fn shells(nv: usize, triangles: &[[u32; 3]]) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..nv as u32).collect();
    fn find(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            parent[x as usize] = parent[parent[x as usize] as usize];
            x = parent[x as usize];
        }
        x
    }
    for t in triangles {
        let r0 = find(&mut parent, t[0]);
        for &v in &t[1..] {
            let r = find(&mut parent, v);
            if r != r0 {
                parent[r as usize] = r0;
            }
        }
    }
    triangles.iter().map(|t| find(&mut parent, t[0])).collect()
}

/// Pairs (i, j), i < j, of triangles in the same shell, sharing no vertex index, whose closed
/// triangles meet. `group[i]` ties triangles together (pairs within a group are skipped: a group
/// is one input face cut into triangles; pass `None` for the output mesh). Triangles naming a
/// missing vertex and degenerate ones are skipped; with `sound` the caller has checked there are
/// none ([`crate::quality::check_mesh`]: no bad index and no zero-area triangle, a superset of the
/// degenerate ones), and the filter pass is skipped.
///
/// Chunk pairs whose triangles all lie in one region of `certified` are skipped: such a region
/// is proven free of self-intersections ([`super::certify`]), so the count stays exact. The
/// tree of [`overlapping_boxes`] drops them as it meets them (a chunk lies in the regions of its
/// patch, [`super::certify::Certified::chunk_regions`]: the same pairs as filtering the list
/// afterwards).
///
/// Progress goes to `ticker` (its current range) after every [`PAIRS_PER_TICK`] chunk pairs.
fn intersecting_pairs(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    group: Option<&[u32]>,
    certified: &Certified,
    free: Option<&[bool]>,
    sound: bool,
    ticker: &mut Ticker<'_>,
) -> Result<Vec<(u32, u32)>, Cancelled> {
    let nv = positions.len();
    let all = (0..triangles.len() as u32).into_par_iter().with_min_len(1 << 12);
    let kept: Vec<u32> = if sound {
        all.collect()
    } else {
        all.filter(|&i| {
            let t = &triangles[i as usize];
            t.iter().all(|&v| (v as usize) < nv) && !degenerate(t.map(|v| positions[v as usize]))
        })
        .collect()
    };
    if kept.len() < 2 {
        return Ok(Vec::new());
    }
    ticker.at(1, 20)?;
    // Shells proven free of self-intersections by central projection ([`star_shaped_shells`])
    // leave the search: only pairs within one shell count. `free` (per triangle) when the
    // caller has it ([`free_shells`]).
    let kept: Vec<u32> = match free {
        Some(f) if f.len() == triangles.len() && !f.contains(&true) => kept,
        Some(f) if f.len() == triangles.len() => kept.into_iter().filter(|&i| !f[i as usize]).collect(),
        _ => {
            let tris: Vec<[u32; 3]> = kept.iter().map(|&i| triangles[i as usize]).collect();
            let free = free_shells(positions, &tris);
            kept.into_iter().zip(free).filter(|x| !x.1).map(|x| x.0).collect()
        }
    };
    if kept.len() < 2 {
        return Ok(Vec::new());
    }
    // `kept` ascends: all of them are the triangles themselves (no copy).
    let kept_tris: std::borrow::Cow<[[u32; 3]]> = if kept.len() == triangles.len() {
        std::borrow::Cow::Borrowed(triangles)
    } else {
        std::borrow::Cow::Owned(kept.par_iter().with_min_len(1 << 12).map(|&i| triangles[i as usize]).collect())
    };
    let to_aabb = |lo: DVec3, hi: DVec3| Aabb::new(parry3d_f64::math::Vector::new(lo.x, lo.y, lo.z), parry3d_f64::math::Vector::new(hi.x, hi.y, hi.z));
    // The box of a triangle, computed where needed when certified regions are skipped (most
    // pairs never need one, so no array of boxes is built).
    let compute = |i: usize| {
        let [a, b, c] = kept_tris[i].map(|v| positions[v as usize]);
        to_aabb(a.min(b).min(c), a.max(b).max(c))
    };
    // Without certificates most chunk pairs are searched: then the boxes are kept in an array.
    let boxes: Option<Vec<Aabb>> = (certified.patches() == 0).then(|| (0..kept_tris.len()).into_par_iter().map(compute).collect());
    let bbox = |i: usize| boxes.as_ref().map_or_else(|| compute(i), |b| b[i]);
    // Coarse to fine: chunks of at most [`CHUNK`] spatially close triangles ([`chunk_layout`]) get
    // the union of their triangles' boxes; a BVH over the chunk boxes gives the overlapping chunk
    // pairs (in parallel, [`overlapping_boxes`]). Two triangles whose boxes overlap lie in one chunk or in two chunks
    // whose boxes overlap, so every candidate pair of the triangle-level search is still
    // visited, once.
    let (order, chunk_start) = chunk_layout(positions, &kept, &kept_tris, certified);
    let chunk = |c: u32| &order[chunk_start[c as usize]..chunk_start[c as usize + 1]];
    let chunk_boxes: Vec<Aabb> = (0..chunk_start.len() as u32 - 1)
        .into_par_iter()
        .map(|c| {
            let slots = chunk(c);
            let p0 = positions[kept_tris[slots[0] as usize][0] as usize];
            let (lo, hi) = slots.iter().flat_map(|&i| kept_tris[i as usize]).fold((p0, p0), |(lo, hi), v| {
                let p = positions[v as usize];
                (lo.min(p), hi.max(p))
            });
            to_aabb(lo, hi)
        })
        .collect();
    // Per chunk (its triangles are consecutive, within one patch): the certified regions
    // containing it. Chunk pairs (and a chunk with itself) inside one region are skipped as the
    // tree finds them (see [`overlapping_boxes`]), never collected.
    let regions: Vec<ChunkRegions> = if certified.patches() > 0 {
        (0..chunk_boxes.len() as u32)
            .into_par_iter()
            .map(|c| {
                let slots = chunk(c);
                certified.chunk_regions(kept[slots[0] as usize] as usize, kept[slots[slots.len() - 1] as usize] as usize)
            })
            .collect()
    } else {
        Vec::new()
    };
    let keep = |a: u32, b: u32| regions.is_empty() || !certified.share_region(regions[a as usize], regions[b as usize]);
    let mut chunk_pairs: Vec<(u32, u32)> = overlapping_boxes(&chunk_boxes, keep);
    chunk_pairs.extend((0..chunk_boxes.len() as u32).filter(|&c| keep(c, c)).map(|c| (c, c)));
    // (The shell test is applied to the few hits afterwards: no union-find over all triangles
    // when nothing meets.)
    let candidate = |i: usize, j: usize| -> bool {
        if !bbox(i).intersects(&bbox(j)) {
            return false;
        }
        let (ti, tj) = (&kept_tris[i], &kept_tris[j]);
        if ti.iter().any(|v| tj.contains(v)) {
            return false;
        }
        if let Some(g) = group {
            if g[kept[i] as usize] == g[kept[j] as usize] {
                return false;
            }
        }
        triangles_intersect(ti.map(|v| positions[v as usize]), tj.map(|v| positions[v as usize]))
    };
    ticker.at(2, 20)?;
    let mut hits: Vec<(u32, u32)> = Vec::new();
    let n_pairs = chunk_pairs.len();
    let per_tick = crate::progress::chunk_size(n_pairs, PAIRS_PER_TICK);
    for (k, part) in chunk_pairs.chunks(per_tick).enumerate() {
      let found: Vec<(u32, u32)> = part
        .par_iter()
        .fold(Vec::new, |mut acc, &(ca, cb)| {
            if ca == cb {
                let slots = chunk(ca);
                for (k, &i) in slots.iter().enumerate() {
                    for &j in &slots[k + 1..] {
                        if candidate(i as usize, j as usize) {
                            acc.push((i, j));
                        }
                    }
                }
            } else {
                let (ba, bb) = (chunk_boxes[ca as usize], chunk_boxes[cb as usize]);
                // A chunk has at most [`CHUNK`] triangles: the near ones of b on the stack.
                let (mut near_b, mut nb) = ([0u32; CHUNK], 0);
                for &j in chunk(cb) {
                    if bbox(j as usize).intersects(&ba) {
                        near_b[nb] = j;
                        nb += 1;
                    }
                }
                for &i in chunk(ca).iter().filter(|&&i| bbox(i as usize).intersects(&bb)) {
                    for &j in &near_b[..nb] {
                        if candidate(i as usize, j as usize) {
                            acc.push((i, j));
                        }
                    }
                }
            }
            acc
        })
        .reduce(Vec::new, |mut x, mut y| {
            x.append(&mut y);
            x
        });
      hits.extend(found);
      ticker.at(2 * n_pairs + 18 * (k * per_tick + part.len()), 20 * n_pairs)?;
    }
    if hits.is_empty() {
        return Ok(hits);
    }
    let shell = shells(nv, &kept_tris);
    let mut hits: Vec<(u32, u32)> = hits
        .into_iter()
        .filter(|&(i, j)| shell[i as usize] == shell[j as usize])
        .map(|(i, j)| {
            let (x, y) = (kept[i as usize], kept[j as usize]);
            (x.min(y), x.max(y))
        })
        .collect();
    hits.par_sort_unstable();
    hits.dedup();
    Ok(hits)
}

/// Triangles per chunk of the coarse search in [`intersecting_pairs`] with certificates (most
/// chunk pairs are then skipped whole).
const CHUNK: usize = 64;

/// Triangles per chunk without certificates (the input cage), where every chunk pair is
/// searched triangle against triangle: smaller chunks fit their triangles more tightly (on the
/// 40k-quad torus cage 16 took 0.11 s of CPU, 64 took 0.18 s, 4 took 0.17 s).
const CHUNK_UNCERTIFIED: usize = 16;
const _: () = assert!(CHUNK_UNCERTIFIED <= CHUNK);

/// The chunks of the coarse self-intersection search over the kept triangles (`kept[slot]` is a
/// triangle index, `kept_tris[slot]` its vertices): `order` lists slots and chunk c is
/// `order[start[c]..start[c + 1]]`, never empty.
/// - With a certificate (the triangles of each patch consecutive): the slots in order, a new
///   chunk at every patch change, so a chunk is a compact piece of one patch whatever order
///   the patches come in (the faces of a cage file are often in no spatial order) and its
///   certified stars are its patch's; at most [`CHUNK`] slots.
/// - Without: the slots sorted by the Morton code of their centroids ([`morton_order`]), so
///   consecutive slots are close in space; [`CHUNK_UNCERTIFIED`] slots (the last fewer).
fn chunk_layout(positions: &[DVec3], kept: &[u32], kept_tris: &[[u32; 3]], certified: &Certified) -> (Vec<u32>, Vec<usize>) {
    let n = kept.len();
    if certified.patches() > 0 {
        let mut start = vec![0];
        // Chunks of a patch with certified core sectors also break at every sector change.
        // `kept` ascends, so the patch of each triangle is found by walking the patch starts
        // once (the value of `Certified::patch_of`, without a search per triangle).
        let tri_start = certified.tri_start();
        let end = tri_start.last().copied().unwrap_or(0);
        let mut at = 0usize;
        let mut piece = |t: usize| {
            let p = (t < end).then(|| {
                while tri_start[at + 1] <= t {
                    at += 1;
                }
                at
            });
            let sector = p.filter(|&p| certified.has_cores(p)).and_then(|_| certified.sector_of(t));
            (p, sector)
        };
        let mut patch = piece(kept[0] as usize);
        for (slot, &t) in kept.iter().enumerate().skip(1) {
            let p = piece(t as usize);
            if p != patch || slot - start[start.len() - 1] == CHUNK {
                start.push(slot);
                patch = p;
            }
        }
        start.push(n);
        return ((0..n as u32).collect(), start);
    }
    let centroid = |tri: &[u32; 3]| tri.iter().map(|&v| positions[v as usize]).sum::<DVec3>() / 3.0;
    let centroids: Vec<DVec3> = kept_tris.par_iter().map(centroid).collect();
    let start = (0..n).step_by(CHUNK_UNCERTIFIED).chain(std::iter::once(n)).collect();
    (morton_order(&centroids), start)
}

/// Indices of `points` sorted by their Morton code (Z-order: the bits of the three
/// coordinates, quantised to 21 bits in the points' bounding box, interleaved), so that
/// consecutive indices are close in space. (Interleaving bits is a few lines: no crate.)
fn morton_order(points: &[DVec3]) -> Vec<u32> {
    let (lo, hi) = points
        .par_iter()
        .with_min_len(1 << 12)
        .map(|&c| (c, c))
        .reduce(|| (DVec3::INFINITY, DVec3::NEG_INFINITY), |a, b| (a.0.min(b.0), a.1.max(b.1)));
    let scale = DVec3::splat((1u64 << 21) as f64 - 1.0) / (hi - lo).max(DVec3::splat(f64::MIN_POSITIVE));
    // Spreads the low 21 bits of x to every third bit.
    fn spread(x: u64) -> u64 {
        let mut x = x & 0x1f_ffff;
        x = (x | x << 32) & 0x1f_0000_0000_ffff;
        x = (x | x << 16) & 0x1f_0000_ff00_00ff;
        x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
        x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
        x = (x | x << 2) & 0x1249_2492_4924_9249;
        x
    }
    let mut keyed: Vec<(u64, u32)> = points
        .par_iter()
        .with_min_len(1 << 12)
        .enumerate()
        .map(|(i, &c)| {
            // A non-finite point (a non-finite box) goes to code 0: the order only affects speed.
            let q = ((c - lo) * scale).max(DVec3::ZERO);
            let code = spread(q.x as u64) | spread(q.y as u64) << 1 | spread(q.z as u64) << 2;
            (code, i as u32)
        })
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|k| k.1).collect()
}

/// Boxes per leaf of the tree of [`overlapping_boxes`].
const LEAF: usize = 4;

/// All pairs (a, b), a ≠ b, of `boxes` that overlap (closed boxes, [`Aabb::intersects`]) and
/// that `keep(a, b)` keeps, each once, in no particular order (`keep` is symmetric).
///
/// A bounding volume hierarchy built without a search for splits: the boxes sorted by the
/// Morton code of their centres ([`morton_order`]), leaves of [`LEAF`] consecutive boxes, and
/// above them a complete binary tree over the sorted order (node i of level k+1 is the union of
/// nodes 2i and 2i + 1 of level k; it covers sorted positions [i·LEAF·2^(k+1), (i+1)·LEAF·2^(k+1))).
/// Every box p then descends the tree from the root into the nodes that meet its box and cover
/// a sorted position after p (in parallel over p), so each overlapping pair is found once, by
/// the earlier of its two boxes. Building is linear (parry's binned build of 40k boxes took
/// 50 ms, the chunk boxes of a 40k-quad torus at r = 2).
fn overlapping_boxes(boxes: &[Aabb], keep: impl Fn(u32, u32) -> bool + Sync) -> Vec<(u32, u32)> {
    let n = boxes.len();
    if n < 2 {
        return Vec::new();
    }
    let centres: Vec<DVec3> = boxes
        .iter()
        .map(|b| {
            let c = b.center();
            DVec3::new(c.x, c.y, c.z)
        })
        .collect();
    let order = morton_order(&centres);
    let sorted: Vec<Aabb> = order.iter().map(|&i| boxes[i as usize]).collect();
    // levels[0]: the leaves; the last level has one node.
    let mut levels: Vec<Vec<Aabb>> = vec![sorted.chunks(LEAF).map(|c| c.iter().skip(1).fold(c[0], |a, b| a.merged(b))).collect()];
    while levels[levels.len() - 1].len() > 1 {
        let up = levels[levels.len() - 1].chunks(2).map(|c| if c.len() == 2 { c[0].merged(&c[1]) } else { c[0] }).collect();
        levels.push(up);
    }
    let top = levels.len() - 1;
    (0..n)
        .into_par_iter()
        .with_min_len(64)
        .fold(
            || (Vec::new(), Vec::new()),
            |(mut acc, mut stack): (Vec<(u32, u32)>, Vec<(usize, usize)>), p| {
                let b = &sorted[p];
                stack.clear();
                stack.push((top, 0));
                while let Some((k, i)) = stack.pop() {
                    // Node i of level k covers sorted positions [i·span, (i+1)·span).
                    let span = LEAF << k;
                    if (i + 1) * span <= p + 1 || !levels[k][i].intersects(b) {
                        continue;
                    }
                    if k == 0 {
                        for q in (i * LEAF).max(p + 1)..((i + 1) * LEAF).min(n) {
                            if sorted[q].intersects(b) && keep(order[p], order[q]) {
                                acc.push((order[p], order[q]));
                            }
                        }
                    } else {
                        for c in [2 * i, 2 * i + 1] {
                            if c < levels[k - 1].len() {
                                stack.push((k - 1, c));
                            }
                        }
                    }
                }
                (acc, stack)
            },
        )
        .map(|x| x.0)
        .reduce(Vec::new, |mut x, mut y| {
            x.append(&mut y);
            x
        })
}

/// Chunk pairs of the self-intersection search per progress tick.
const PAIRS_PER_TICK: usize = 256;

/// Number of pairs of triangles of one connected shell that share no vertex and meet (see the
/// module doc). Two separate shells crossing each other do not count.
pub fn self_intersections(positions: &[DVec3], triangles: &[[u32; 3]]) -> usize {
    let none = Certified::none();
    intersecting_pairs(positions, triangles, None, &none, None, false, &mut Ticker::none()).map_or(0, |p| p.len())
}

/// [`self_intersections`] skipping the pairs inside the `certified` regions (proven free of
/// self-intersections, see [`super::certify`]): the same count, faster on smooth surfaces.
pub fn self_intersections_certified(positions: &[DVec3], triangles: &[[u32; 3]], certified: &Certified) -> usize {
    intersecting_pairs(positions, triangles, None, certified, None, false, &mut Ticker::none()).map_or(0, |p| p.len())
}

/// [`self_intersections_certified`] of a tessellation with the certified stars of its nodes
/// ([`Certified::of_mesh`]).
pub fn mesh_self_intersections(mesh: &SurfaceMesh) -> usize {
    mesh_self_intersections_ticked(mesh, &mut Ticker::none()).unwrap_or(0)
}

/// [`mesh_self_intersections`] reporting progress to `ticker` (its current range: the
/// certificates, then the search in chunks; see [`crate::progress`]).
pub fn mesh_self_intersections_ticked(mesh: &SurfaceMesh, ticker: &mut Ticker<'_>) -> Result<usize, Cancelled> {
    let free = free_shells(&mesh.positions, &mesh.triangles);
    mesh_self_intersections_free(mesh, &free, false, ticker)
}

/// [`mesh_self_intersections_ticked`] with the shells certified by central projection already
/// known (`free`, per triangle, from [`free_shells`]): 0 at once when every shell is, else the
/// certificates of the nodes and the search over the other shells (`sound`: see
/// [`intersecting_pairs`]).
fn mesh_self_intersections_free(
    mesh: &SurfaceMesh,
    free: &[bool],
    sound: bool,
    ticker: &mut Ticker<'_>,
) -> Result<usize, Cancelled> {
    if free.len() == mesh.triangles.len() && free.iter().all(|&f| f) {
        return Ok(0);
    }
    // Meshes without patch loops (subdivision methods) have no certificates to compute.
    let share = if mesh.patch_loops.is_empty() { 0.0 } else { CERTIFY };
    let certified = ticker.within(0.0, share, |t| Certified::of_mesh_ticked(mesh, t))?;
    let (positions, triangles) = (&mesh.positions, &mesh.triangles);
    ticker
        .within(share, 1.0, |t| intersecting_pairs(positions, triangles, None, &certified, Some(free), sound, t))
        .map(|p| p.len())
}

/// [`mesh_self_intersections_ticked`] for a mesh the caller has checked (`check`, its
/// [`crate::quality::check_mesh`]): a closed two-manifold has only closed shells, and without bad
/// indices and zero-area triangles the search skips its filter of degenerate triangles. The
/// central-projection certificate ([`star_shaped_shells`]) comes first when the mesh is closed and
/// passes its gate ([`star_shaped_about_centroid`]), with 95 % of the progress range (the search
/// then usually has nothing left to do); otherwise the search has it all.
///
/// `check` must be [`crate::quality::check_mesh`] of exactly these arrays: only its counts are
/// compared with the mesh, so a check of other arrays of the same sizes would let bad indices
/// (a panic) or degenerate triangles into the search. [`crate::api::convert`] checks the mesh
/// it has just built.
pub fn mesh_self_intersections_checked(
    mesh: &SurfaceMesh,
    check: &crate::quality::MeshCheck,
    ticker: &mut Ticker<'_>,
) -> Result<usize, Cancelled> {
    let (positions, triangles) = (&mesh.positions, &mesh.triangles);
    let of_this = check.vertices == positions.len() && check.triangles == triangles.len();
    let closed = of_this && check.is_closed_manifold();
    let sound = of_this && check.bad_indices == 0 && check.zero_area_triangles == 0;
    let count = if closed && star_shaped_about_centroid(positions, triangles) {
        let share = 0.95;
        let shell = shells(positions.len(), triangles);
        let free = ticker.within(0.0, share, |t| star_shaped_shells_ticked(positions, triangles, &shell, true, t))?;
        if free.iter().all(|&f| f) {
            return Ok(0);
        }
        ticker.within(share, 1.0, |t| mesh_self_intersections_free(mesh, &free, sound, t))?
    } else {
        mesh_self_intersections_free(mesh, &vec![false; triangles.len()], sound, ticker)?
    };
    Ok(count)
}

/// Per triangle: its shell (connected through shared vertices) is closed and star-shaped around
/// its centre, so proven free of self-intersections ([`star_shaped_shells`]); all false when a
/// triangle names a missing vertex.
pub fn free_shells(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<bool> {
    // Gated by one parallel pass (no shells computed for a surface that is not star-shaped).
    if !star_shaped_about_centroid(positions, triangles) {
        return vec![false; triangles.len()];
    }
    star_shaped_shells(positions, triangles, &shells(positions.len(), triangles))
}

/// The certificates' share of [`mesh_self_intersections_ticked`].
const CERTIFY: f32 = 0.2;

/// Number of pairs of faces of the input cage, in one shell and sharing no vertex, that meet:
/// every face is split into convex pieces ([`crate::mesh::geometry::convexify`]) and each piece
/// fan-triangulated.
pub fn cage_self_intersections(mesh: &PolyMesh) -> usize {
    cage_self_intersections_ticked(mesh, &mut Ticker::none()).unwrap_or(0)
}

/// [`cage_self_intersections`] reporting progress to `ticker` (see [`crate::progress`]).
pub fn cage_self_intersections_ticked(mesh: &PolyMesh, ticker: &mut Ticker<'_>) -> Result<usize, Cancelled> {
    let (convex, origin) = crate::mesh::geometry::convexify(mesh);
    let mut tris = Vec::new();
    let mut face = Vec::new();
    for (k, f) in convex.faces.iter().enumerate() {
        for i in 1..f.len().saturating_sub(1) {
            tris.push([f[0], f[i], f[i + 1]]);
            face.push(origin.get(k).copied().unwrap_or(k as u32));
        }
    }
    // Two faces sharing a vertex are adjacent even where their fan triangles share none.
    ticker.at(1, 20)?;
    let none = Certified::none();
    let mut pairs: Vec<(u32, u32)> = ticker
        .within(0.05, 1.0, |t| intersecting_pairs(&convex.positions, &tris, Some(&face), &none, None, false, t))?
        .into_iter()
        .filter(|&(i, j)| {
            let (fi, fj) = (&mesh.faces[face[i as usize] as usize], &mesh.faces[face[j as usize] as usize]);
            !fi.iter().any(|v| fj.contains(v))
        })
        .map(|(i, j)| {
            let (a, b) = (face[i as usize], face[j as usize]);
            (a.min(b), a.max(b))
        })
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    Ok(pairs.len())
}

/// Largest |H| over the vertices times the diagonal of the positions' bounding box (0 for an
/// empty mesh; non-finite curvatures are skipped).
pub fn max_abs_mean_curvature_times_diagonal(positions: &[DVec3], mean_curvature: &[f64]) -> f64 {
    let Some(first) = positions.first() else { return 0.0 };
    let (lo, hi) = positions.iter().fold((*first, *first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let h = mean_curvature.iter().filter(|h| h.is_finite()).fold(0.0f64, |m, h| m.max(h.abs()));
    h * lo.distance(hi)
}


#[cfg(test)]
mod tests {
    use super::*;

    /// [`overlapping_boxes`] finds every overlapping pair once, as a brute force over all pairs
    /// does: random boxes of mixed sizes (many overlaps, boxes inside others), boxes that only
    /// touch (closed boxes meet), repeated boxes and flat ones, for sizes around the leaf size
    /// and the tree's powers of two.
    #[test]
    fn overlapping_boxes_is_the_brute_force() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let aabb = |lo: DVec3, hi: DVec3| Aabb::new(parry3d_f64::math::Vector::new(lo.x, lo.y, lo.z), parry3d_f64::math::Vector::new(hi.x, hi.y, hi.z));
        for n in [0, 1, 2, 3, 4, 5, 7, 8, 9, 17, 63, 64, 65, 300, 1000] {
            let mut boxes: Vec<Aabb> = (0..n)
                .map(|k| {
                    let lo = DVec3::new(rnd(), rnd(), rnd()) * 10.0;
                    let size = if k % 7 == 0 { 3.0 } else { 0.4 };
                    let mut d = DVec3::new(rnd(), rnd(), rnd()) * size;
                    if k % 11 == 0 {
                        d.z = 0.0;
                    }
                    aabb(lo, lo + d)
                })
                .collect();
            if n > 4 {
                // Touching along a face, and a repeated box.
                let b = boxes[1];
                boxes[2] = aabb(DVec3::new(b.maxs.x, b.mins.y, b.mins.z), DVec3::new(b.maxs.x + 1.0, b.maxs.y, b.maxs.z));
                boxes[3] = boxes[0];
            }
            let mut fast: Vec<(u32, u32)> = overlapping_boxes(&boxes, |_, _| true).into_iter().map(|(a, b)| (a.min(b), a.max(b))).collect();
            fast.sort_unstable();
            let mut brute = Vec::new();
            for a in 0..n {
                for b in a + 1..n {
                    if boxes[a].intersects(&boxes[b]) {
                        brute.push((a as u32, b as u32));
                    }
                }
            }
            assert_eq!(fast, brute, "{n} boxes");
            if n > 4 {
                assert!(brute.contains(&(1, 2)) && brute.contains(&(0, 3)));
            }
            // A symmetric filter (boxes in one "region", the index's residue mod 3) drops exactly
            // the pairs it rejects, whichever order the tree meets them in.
            let keep = |a: u32, b: u32| a % 3 != b % 3;
            let mut kept: Vec<(u32, u32)> = overlapping_boxes(&boxes, keep).into_iter().map(|(a, b)| (a.min(b), a.max(b))).collect();
            kept.sort_unstable();
            let filtered: Vec<(u32, u32)> = brute.iter().copied().filter(|&(a, b)| keep(a, b)).collect();
            assert_eq!(kept, filtered, "{n} boxes, filtered");
            if n >= 300 {
                assert!(filtered.len() < brute.len() && !filtered.is_empty(), "the filter drops some pairs and keeps some");
            }
        }
    }
}
