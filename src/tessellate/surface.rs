//! Watertight tessellation of a whole [`Surface`]: every patch is sampled with the concentric
//! [`SampleLayout`] of its n-sided domain at one common resolution r, then the samples are welded.
//!
//! Welding (no position comparison anywhere, only the adjacency of [`Surface::neighbors`]):
//! - interior samples belong to their patch;
//! - the inner samples (steps 1..r−1) of a shared side are emitted once, by the side with the
//!   smaller `(patch, side)`; the neighbour across it reuses them, its step t being the owner's
//!   step r − t (the two sides traverse the shared curve in opposite directions);
//! - corners (nodes of the curve network) are emitted once for all patches meeting there: corner
//!   c of a patch (domain vertex c, end of side c, start of side c+1) is united with the corners
//!   its two sides meet across their neighbours (union–find over `(patch, corner)`), which is the
//!   walk around the node through the adjacency.
//!
//! Before welding, for every shared side and every step t (corners included) the distance between
//! the two patches' samples (the boundary gap) and the angle between their normals (the G1
//! deviation) are measured. A welded vertex takes the position of the patch that created it (the
//! first in patch order), the normal and curvatures averaged over all patches sharing it, and the
//! largest G1 deviation measured there (0 inside patches and on open boundaries).
//!
//! Sides without neighbour stay open: an open input gives a mesh with boundary edges exactly
//! there. Orientation: every layout triangle is counter-clockwise in the domain, so all output
//! triangles are oriented like the patches (outward for a closed input, see [`Surface`]).

use super::patch::{LayoutError, SampleLayout};
use crate::construct::{Patch, Surface};
use crate::gb::table::{CgbTable, ControlSoa, GbTable, TableError, TILE};
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::Arc;

/// One evaluated sample: position, unit normal (zero when undefined, e.g. at a degenerate corner;
/// the welded mesh then falls back to the average of the other patches' normals or, failing that,
/// the area-weighted triangle normal), mean and Gaussian curvature (0 where undefined).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfacePoint {
    pub position: DVec3,
    pub normal: DVec3,
    pub mean_curvature: f64,
    pub gaussian_curvature: f64,
}

/// Evaluates all samples of one patch. Implementations must be pure (they run in parallel over
/// patches) and must fill `out` with one point per `layout.uv` entry.
pub trait PatchEvaluator: Sync {
    /// The domain polygon (counter-clockwise, vertex i ends side i) in which this evaluator reads
    /// the parameters of an n-sided patch.
    fn domain(&self, n: usize) -> Vec<DVec2> {
        SampleLayout::regular_polygon(n)
    }
    /// Evaluates patch `index` of `surface` at every sample of `layout` into `out` (cleared first).
    fn evaluate(&self, surface: &Surface, index: usize, layout: &SampleLayout, out: &mut Vec<SurfacePoint>);
}

/// The welded triangle mesh of a surface, with the per-vertex quality data of issue 3.
/// Plain arrays (one entry per vertex or per triangle), ready for FFI buffers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceMesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Analytic unit normals (averaged over the patches sharing a boundary vertex).
    pub normals: Vec<DVec3>,
    /// Counter-clockwise triangles (outward for a closed input).
    pub triangles: Vec<[u32; 3]>,
    /// Per vertex: the patch that created it (the smallest patch index sharing it). For subdivision
    /// methods: the face of the input mesh it descends from.
    pub patch: Vec<u32>,
    /// Per triangle: the patch (or input face) it belongs to.
    pub triangle_patch: Vec<u32>,
    /// Per vertex: mean curvature H = (k1 + k2)/2, sign relative to the normal.
    pub mean_curvature: Vec<f64>,
    /// Per vertex: Gaussian curvature K = k1·k2.
    pub gaussian_curvature: Vec<f64>,
    /// Per vertex: largest angle (degrees) between the normals of two patches sharing the vertex;
    /// 0 inside patches and on open boundaries.
    pub g1_deviation_deg: Vec<f64>,
}

/// Measurements taken while welding.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WeldStats {
    /// Largest distance between the two patches' samples of a shared boundary (before welding).
    pub max_boundary_gap: f64,
    /// Largest angle (degrees) between the two patches' normals on shared boundaries.
    pub max_g1_deg: f64,
    /// Mean of the per-vertex G1 deviation over the vertices on shared boundaries (0 if none).
    pub mean_g1_deg: f64,
    /// Number of welded vertices lying on shared boundaries.
    pub shared_vertices: usize,
}

/// Why a surface cannot be tessellated; every variant names the element.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TessellateError {
    /// The sampling layout of a patch could not be built.
    #[error("patch {patch}: {source}")]
    Layout { patch: usize, source: LayoutError },
    /// `neighbors` has no entry for a patch, or one of the wrong length.
    #[error("patch {patch} has {sides} sides but {entries} neighbour entries")]
    NeighborCount { patch: usize, sides: usize, entries: usize },
    /// A neighbour reference points outside the surface or is not reciprocated.
    #[error("side {side} of patch {patch} names neighbour (patch {other_patch}, side {other_side}), which does not name it back")]
    Adjacency { patch: usize, side: usize, other_patch: usize, other_side: usize },
    /// An evaluator returned a wrong number of samples or a non-finite position.
    #[error("patch {patch}: evaluation failed at sample {sample} (non-finite or missing)")]
    Evaluation { patch: usize, sample: usize },
    /// The output needs more than 2^32 − 1 vertices.
    #[error("the output mesh would need {count} vertices, more than u32 indices allow")]
    TooLarge { count: usize },
    /// A patch is malformed (row lengths, degrees, non-finite control points).
    #[error("patch {patch}: {source}")]
    InvalidPatch { patch: usize, source: crate::gb::GbError },
    /// The progress callback asked to stop.
    #[error("cancelled")]
    Cancelled,
}

/// The number of sides of a patch.
pub fn patch_sides(p: &Patch) -> usize {
    match p {
        Patch::Gb(g) => g.ribbons.len(),
        Patch::Cgb(c) => c.ribbons.len(),
    }
}

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[x as usize];
        parent[x as usize] = parent[p as usize];
        x = p;
    }
    x
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        // Keep the smaller root so the node's representative is its first (patch, corner).
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parent[hi as usize] = lo;
    }
}

/// Checks that `neighbors` matches the patches and is reciprocal.
pub fn check_adjacency(surface: &Surface) -> Result<(), TessellateError> {
    for (p, patch) in surface.patches.iter().enumerate() {
        let sides = patch_sides(patch);
        let entries = surface.neighbors.get(p).map_or(0, |v| v.len());
        if entries != sides {
            return Err(TessellateError::NeighborCount { patch: p, sides, entries });
        }
    }
    for (p, sides) in surface.neighbors.iter().enumerate().take(surface.patches.len()) {
        for (i, nb) in sides.iter().enumerate() {
            if let Some(nb) = nb {
                let back = surface.neighbors.get(nb.patch).and_then(|s| s.get(nb.side)).copied().flatten();
                let ok = back.is_some_and(|b| b.patch == p && b.side == i) && (nb.patch, nb.side) != (p, i);
                if !ok {
                    return Err(TessellateError::Adjacency { patch: p, side: i, other_patch: nb.patch, other_side: nb.side });
                }
            }
        }
    }
    Ok(())
}

/// Global vertex ids of every sample of every patch (the welding map), see the module doc.
/// `ids[offsets[p] + s]` is the output vertex of sample s of patch p. Returns the number of
/// vertices and whether each id was created by this sample (the owner).
struct WeldMap {
    offsets: Vec<usize>,
    ids: Vec<u32>,
    owner: Vec<bool>,
    /// The vertices created by patch p are `vstart[p]..vstart[p + 1]`, in sample order.
    vstart: Vec<usize>,
    vertex_count: usize,
}

fn weld_map(surface: &Surface, layouts: &HashMap<usize, SampleLayout>, r: usize) -> Result<WeldMap, TessellateError> {
    let np = surface.patches.len();
    let sides: Vec<usize> = surface.patches.iter().map(patch_sides).collect();
    // Corner numbering: corner c of patch p is corner_base[p] + c.
    let mut corner_base = Vec::with_capacity(np + 1);
    let mut total = 0usize;
    for &n in &sides {
        corner_base.push(total);
        total += n;
    }
    corner_base.push(total);
    let mut parent: Vec<u32> = (0..total as u32).collect();
    for p in 0..np {
        let n = sides[p];
        for i in 0..n {
            if let Some(nb) = surface.neighbors[p][i] {
                let m = sides[nb.patch];
                // Side i of p runs from corner i−1 to corner i; side j of q from corner j−1 to j,
                // in the opposite direction along the shared curve.
                let p_start = corner_base[p] + (i + n - 1) % n;
                let p_end = corner_base[p] + i;
                let q_start = corner_base[nb.patch] + (nb.side + m - 1) % m;
                let q_end = corner_base[nb.patch] + nb.side;
                union(&mut parent, p_start as u32, q_end as u32);
                union(&mut parent, p_end as u32, q_start as u32);
            }
        }
    }
    let mut offsets = Vec::with_capacity(np + 1);
    let mut len = 0usize;
    for &n in &sides {
        offsets.push(len);
        len += SampleLayout::sample_count(n, r);
    }
    offsets.push(len);
    let mut ids = vec![u32::MAX; len];
    let mut owner = vec![false; len];
    let mut node_id = vec![u32::MAX; total];
    let mut next: usize = 0;
    let mut vstart = Vec::with_capacity(np + 1);
    for p in 0..np {
        vstart.push(next);
        let n = sides[p];
        let layout = &layouts[&n];
        let base = offsets[p];
        let first_boundary = layout.ring_index(r, 0, 0);
        for s in 0..first_boundary {
            ids[base + s] = next as u32;
            owner[base + s] = true;
            next += 1;
        }
        for i in 0..n {
            for t in 0..r {
                let s = layout.boundary_index(i, t);
                let id = if t == 0 {
                    let root = find(&mut parent, (corner_base[p] + (i + n - 1) % n) as u32) as usize;
                    if node_id[root] == u32::MAX {
                        node_id[root] = next as u32;
                        owner[base + s] = true;
                        next += 1;
                    }
                    node_id[root]
                } else {
                    match surface.neighbors[p][i] {
                        Some(nb) if (nb.patch, nb.side) < (p, i) => {
                            let q_layout = &layouts[&sides[nb.patch]];
                            ids[offsets[nb.patch] + q_layout.boundary_index(nb.side, r - t)]
                        }
                        _ => {
                            owner[base + s] = true;
                            next += 1;
                            (next - 1) as u32
                        }
                    }
                };
                ids[base + s] = id;
            }
        }
        if next > u32::MAX as usize - 1 {
            return Err(TessellateError::TooLarge { count: next });
        }
    }
    vstart.push(next);
    debug_assert!(ids.iter().all(|&x| x != u32::MAX));
    Ok(WeldMap { offsets, ids, owner, vstart, vertex_count: next })
}

/// Angle in degrees between two unit (or zero) vectors; 0 when either is zero.
fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    if a == DVec3::ZERO || b == DVec3::ZERO {
        return 0.0;
    }
    // atan2 of |a×b| and a·b is accurate also for tiny angles.
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// `v` cut into the pieces `starts[p]..starts[p + 1]` (`starts` ascending, ending at most at
/// `v.len()`).
fn split_by<'a, T>(mut v: &'a mut [T], starts: &[usize]) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(starts.len().saturating_sub(1));
    for w in starts.windows(2) {
        let (a, b) = std::mem::take(&mut v).split_at_mut(w[1] - w[0]);
        out.push(a);
        v = b;
    }
    out
}

/// `len` default values, written in parallel: the first touch of a large fresh allocation (page
/// faults, zeroing) then happens on all threads rather than serially.
fn zeroed<T: Default + Send>(len: usize) -> Vec<T> {
    (0..len).into_par_iter().with_min_len(1 << 14).map(|_| T::default()).collect()
}

/// Patches evaluated per progress step.
const CHUNK: usize = 2048;

/// Tessellates `surface` at resolution `r` (samples per patch side) with `evaluator`, welds the
/// patches (see the module doc) and returns the mesh with the measurements. `progress` is called
/// with the fraction done (0..1) after every chunk of patches; returning false cancels.
pub fn tessellate_surface_with<E: PatchEvaluator>(
    surface: &Surface,
    r: usize,
    evaluator: &E,
    mut progress: Option<&mut dyn FnMut(f32) -> bool>,
) -> Result<(SurfaceMesh, WeldStats), TessellateError> {
    check_adjacency(surface)?;
    let np = surface.patches.len();
    let mut layouts: HashMap<usize, SampleLayout> = HashMap::new();
    for (p, patch) in surface.patches.iter().enumerate() {
        let n = patch_sides(patch);
        if let std::collections::hash_map::Entry::Vacant(e) = layouts.entry(n) {
            let layout = SampleLayout::new(&evaluator.domain(n), r).map_err(|source| TessellateError::Layout { patch: p, source })?;
            e.insert(layout);
        }
    }
    let map = weld_map(surface, &layouts, r)?;

    // Output arrays. The vertices a patch creates are contiguous (see `WeldMap::vstart`), as
    // are its triangles and its boundary samples, so each patch writes its own disjoint pieces
    // and the evaluation runs in parallel without locks.
    let nv = map.vertex_count;
    let mut mesh = SurfaceMesh {
        positions: zeroed(nv),
        normals: zeroed(nv),
        triangles: Vec::new(),
        patch: vec![0; nv],
        triangle_patch: Vec::new(),
        mean_curvature: vec![0.0; nv],
        gaussian_curvature: vec![0.0; nv],
        g1_deviation_deg: vec![0.0; nv],
    };
    let sides_of = |p: usize| patch_sides(&surface.patches[p]);
    let mut tri_start = Vec::with_capacity(np + 1);
    let mut bnd_start = Vec::with_capacity(np + 1);
    let (mut nt, mut nb) = (0usize, 0usize);
    for p in 0..np {
        tri_start.push(nt);
        bnd_start.push(nb);
        nt += SampleLayout::triangle_count(sides_of(p), r);
        nb += sides_of(p) * r;
    }
    tri_start.push(nt);
    bnd_start.push(nb);
    mesh.triangles = vec![[0; 3]; nt];
    mesh.triangle_patch = vec![0; nt];
    // Boundary samples of every patch (ring order), kept for welding and measurements.
    let mut boundary: Vec<SurfacePoint> = zeroed(nb);
    // Per vertex: how many patches contributed a valid normal.
    let mut weight = vec![0u16; nv];

    struct PatchOut<'a> {
        p: usize,
        pos: &'a mut [DVec3],
        nrm: &'a mut [DVec3],
        h: &'a mut [f64],
        k: &'a mut [f64],
        patch: &'a mut [u32],
        weight: &'a mut [u16],
        tris: &'a mut [[u32; 3]],
        tri_patch: &'a mut [u32],
        bnd: &'a mut [SurfacePoint],
    }
    let mut outs: Vec<PatchOut<'_>> = Vec::with_capacity(np);
    {
        let (mut pos, mut nrm, mut h, mut k) = (&mut mesh.positions[..], &mut mesh.normals[..], &mut mesh.mean_curvature[..], &mut mesh.gaussian_curvature[..]);
        let (mut pa, mut w, mut tr, mut tp, mut bd) =
            (&mut mesh.patch[..], &mut weight[..], &mut mesh.triangles[..], &mut mesh.triangle_patch[..], &mut boundary[..]);
        for p in 0..np {
            let cv = map.vstart[p + 1] - map.vstart[p];
            let ct = tri_start[p + 1] - tri_start[p];
            let cb = bnd_start[p + 1] - bnd_start[p];
            let (a, b) = std::mem::take(&mut pos).split_at_mut(cv);
            pos = b;
            let (a2, b2) = std::mem::take(&mut nrm).split_at_mut(cv);
            nrm = b2;
            let (a3, b3) = std::mem::take(&mut h).split_at_mut(cv);
            h = b3;
            let (a4, b4) = std::mem::take(&mut k).split_at_mut(cv);
            k = b4;
            let (a5, b5) = std::mem::take(&mut pa).split_at_mut(cv);
            pa = b5;
            let (a6, b6) = std::mem::take(&mut w).split_at_mut(cv);
            w = b6;
            let (a7, b7) = std::mem::take(&mut tr).split_at_mut(ct);
            tr = b7;
            let (a8, b8) = std::mem::take(&mut tp).split_at_mut(ct);
            tp = b8;
            let (a9, b9) = std::mem::take(&mut bd).split_at_mut(cb);
            bd = b9;
            outs.push(PatchOut { p, pos: a, nrm: a2, h: a3, k: a4, patch: a5, weight: a6, tris: a7, tri_patch: a8, bnd: a9 });
        }
    }
    let mut done = 0usize;
    while done < np {
        let end = (done + CHUNK).min(np);
        outs[done..end].par_iter_mut().try_for_each_init(Vec::new, |buf, o| {
            let p = o.p;
            let layout = &layouts[&sides_of(p)];
            evaluator.evaluate(surface, p, layout, buf);
            if buf.len() != layout.uv.len() {
                return Err(TessellateError::Evaluation { patch: p, sample: buf.len().min(layout.uv.len()) });
            }
            if let Some(s) = buf.iter().position(|x| !x.position.is_finite()) {
                return Err(TessellateError::Evaluation { patch: p, sample: s });
            }
            let base = map.offsets[p];
            let first_boundary = layout.ring_index(r, 0, 0);
            let mut j = 0;
            for (s, sp) in buf.iter().enumerate() {
                if map.owner[base + s] {
                    o.pos[j] = sp.position;
                    o.patch[j] = p as u32;
                    if sp.normal != DVec3::ZERO && sp.normal.is_finite() {
                        o.nrm[j] = sp.normal;
                        o.weight[j] = 1;
                        if sp.mean_curvature.is_finite() && sp.gaussian_curvature.is_finite() {
                            o.h[j] = sp.mean_curvature;
                            o.k[j] = sp.gaussian_curvature;
                        }
                    }
                    j += 1;
                }
            }
            o.bnd.copy_from_slice(&buf[first_boundary..]);
            let ids = &map.ids[base..map.offsets[p + 1]];
            for (t, lt) in o.tris.iter_mut().zip(&layout.triangles) {
                *t = lt.map(|x| ids[x as usize]);
            }
            o.tri_patch.fill(p as u32);
            Ok(())
        })?;
        done = end;
        if let Some(cb) = progress.as_mut() {
            if !cb(done as f32 / np.max(1) as f32) {
                return Err(TessellateError::Cancelled);
            }
        }
    }
    drop(outs);

    // Welding of the non-owner samples (their normals and curvatures are added to the welded
    // vertex) and the gap / G1 measurements along shared sides, each side pair once, from its
    // smaller (patch, side), which also created the pair's inner vertices. So the inner samples
    // run in parallel per patch, writing only that patch's vertices; the corners (nodes shared
    // by any number of patches) follow serially in patch order.
    let valid = |sp: &SurfacePoint| sp.normal != DVec3::ZERO && sp.normal.is_finite();
    let add = |sp: &SurfacePoint, n: &mut DVec3, h: &mut f64, k: &mut f64, w: &mut u16| {
        *n += sp.normal;
        if sp.mean_curvature.is_finite() && sp.gaussian_curvature.is_finite() {
            *h += sp.mean_curvature;
            *k += sp.gaussian_curvature;
        }
        *w = w.saturating_add(1);
    };
    // The larger gap, NaN as soon as one gap is NaN.
    let max_gap = |a: f64, b: f64| if a.is_nan() || b.is_nan() { f64::NAN } else { a.max(b) };
    // Per side count n: the first boundary sample of its layout.
    let mut first_boundary = vec![0usize; layouts.keys().max().map_or(0, |&n| n + 1)];
    for (&n, l) in &layouts {
        first_boundary[n] = l.ring_index(r, 0, 0);
    }
    let sample = |p: usize, s: usize| &boundary[bnd_start[p] + s - first_boundary[sides_of(p)]];
    let mut shared = vec![false; nv];
    let mut stats = WeldStats::default();
    {
        let vstart = &map.vstart;
        let parts = split_by(&mut mesh.normals, vstart)
            .into_iter()
            .zip(split_by(&mut mesh.mean_curvature, vstart))
            .zip(split_by(&mut mesh.gaussian_curvature, vstart))
            .zip(split_by(&mut mesh.g1_deviation_deg, vstart))
            .zip(split_by(&mut shared, vstart))
            .zip(split_by(&mut weight, vstart))
            .enumerate()
            .collect::<Vec<_>>();
        stats.max_boundary_gap = parts
            .into_par_iter()
            .with_min_len(64)
            .map(|(p, (((((nrm, h), k), g1), sh), w))| {
                let lp = &layouts[&sides_of(p)];
                let mut gap_max = 0.0;
                for (i, nb) in surface.neighbors[p].iter().enumerate() {
                    let Some(nb) = nb else { continue };
                    if (nb.patch, nb.side) < (p, i) {
                        continue;
                    }
                    let lq = &layouts[&sides_of(nb.patch)];
                    for t in 1..r {
                        let sa = lp.boundary_index(i, t);
                        let (a, b) = (sample(p, sa), sample(nb.patch, lq.boundary_index(nb.side, r - t)));
                        let v = map.ids[map.offsets[p] + sa] as usize - vstart[p];
                        if valid(b) {
                            add(b, &mut nrm[v], &mut h[v], &mut k[v], &mut w[v]);
                        }
                        gap_max = max_gap(gap_max, a.position.distance(b.position));
                        g1[v] = g1[v].max(angle_deg(a.normal, b.normal));
                        sh[v] = true;
                    }
                }
                gap_max
            })
            .reduce(|| 0.0, max_gap);
    }
    for p in 0..np {
        let n = sides_of(p);
        let lp = &layouts[&n];
        for i in 0..n {
            let s = lp.boundary_index(i, 0);
            let kk = map.offsets[p] + s;
            let sp = sample(p, s);
            if !map.owner[kk] && valid(sp) {
                let v = map.ids[kk] as usize;
                add(sp, &mut mesh.normals[v], &mut mesh.mean_curvature[v], &mut mesh.gaussian_curvature[v], &mut weight[v]);
            }
        }
        for (i, nb) in surface.neighbors[p].iter().enumerate() {
            let Some(nb) = nb else { continue };
            if (nb.patch, nb.side) < (p, i) {
                continue;
            }
            let lq = &layouts[&sides_of(nb.patch)];
            for t in [0, r] {
                let sa = lp.boundary_index(i, t);
                let (a, b) = (sample(p, sa), sample(nb.patch, lq.boundary_index(nb.side, r - t)));
                stats.max_boundary_gap = max_gap(stats.max_boundary_gap, a.position.distance(b.position));
                let v = map.ids[map.offsets[p] + sa] as usize;
                mesh.g1_deviation_deg[v] = mesh.g1_deviation_deg[v].max(angle_deg(a.normal, b.normal));
                shared[v] = true;
            }
        }
    }
    mesh.mean_curvature.par_iter_mut().zip(mesh.gaussian_curvature.par_iter_mut()).zip(weight.par_iter()).for_each(|((h, k), &w)| {
        if w > 1 {
            *h /= w as f64;
            *k /= w as f64;
        }
    });
    let (count, sum, max) = shared
        .par_iter()
        .zip(mesh.g1_deviation_deg.par_iter())
        .filter(|(&s, _)| s)
        .map(|(_, &g)| (1usize, g, g))
        .reduce(|| (0, 0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1, a.2.max(b.2)));
    stats.shared_vertices = count;
    stats.max_g1_deg = max;
    if count > 0 {
        stats.mean_g1_deg = sum / count as f64;
    }

    // Normalize normals; vertices without any analytic normal take the area-weighted normal of
    // their triangles.
    let missing: Vec<usize> = (0..nv).into_par_iter().filter(|&v| weight[v] == 0).collect();
    if !missing.is_empty() {
        let fallback = crate::quality::vertex_normals(&mesh.positions, &mesh.triangles);
        for v in missing {
            mesh.normals[v] = fallback[v];
        }
    }
    mesh.normals.par_iter_mut().for_each(|n| *n = n.normalize_or_zero());
    Ok((mesh, stats))
}

/// Which table a patch uses: GB (n, d) or CGB (per-side degree and layer count).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Kind {
    Gb(usize, usize),
    Cgb(Vec<(usize, usize)>),
}

fn kind_of(p: &Patch) -> Kind {
    match p {
        Patch::Gb(g) => Kind::Gb(g.ribbons.len(), g.ribbons.first().map_or(0, |r| r.degree)),
        Patch::Cgb(c) => Kind::Cgb(c.ribbons.iter().map(|r| (r.degree, r.rows.len())).collect()),
    }
}

/// Tables up to this size are kept in the process-wide caches of [`crate::gb::table`] (the
/// usual resolutions); larger ones are built for one conversion only.
const CACHE_BYTES: u128 = 32 << 20;
/// Above this size no table is built: the weights are evaluated directly at every sample.
const TABLE_BYTES: u128 = 256 << 20;

/// How the patches of one kind are evaluated.
enum Evaluation {
    /// [`GbTable`] with second derivatives.
    Gb(Arc<GbTable>),
    /// [`CgbTable`].
    Cgb(Arc<CgbTable>),
    /// No table (it would be too large): the basis is evaluated at every sample.
    Direct,
}

/// The evaluator of GB and CGB patches used by the conversion: the weight tables of
/// [`crate::gb::table`] ([`GbTable`] with second derivatives for GB patches, [`CgbTable`] for
/// CGB patches), one per (kind, n, degrees, r, weight form), shared through their caches; every
/// patch is then a tile-wise SIMD weighted sum over its control points (seed 000 eq. 2.24 for
/// GB, eq. 3.8 for CGB, with the weight form of [`crate::gb::WeightForm`]). The domain is
/// [`crate::gb::Domain::regular`] (for n = 4 the square of MATH-NOTES).
pub struct GbSurfaceEvaluator {
    evaluations: Vec<Evaluation>,
    /// Per patch: its entry of `evaluations`.
    which: Vec<u32>,
    form: crate::gb::WeightForm,
}

fn gb_domain(n: usize) -> Vec<DVec2> {
    match crate::gb::Domain::regular(n) {
        Ok(d) => d.vertices().to_vec(),
        Err(_) => SampleLayout::regular_polygon(n),
    }
}

fn table_error(patch: usize, e: TableError) -> TessellateError {
    match e {
        TableError::Layout(source) => TessellateError::Layout { patch, source },
        TableError::Patch(source) => TessellateError::InvalidPatch { patch, source },
        _ => TessellateError::Evaluation { patch, sample: 0 },
    }
}

/// The sample record of the surface derivatives: unit normal (zero where undefined) and mean
/// and Gaussian curvature from the fundamental forms (0 where undefined; the formulas and
/// conditions of [`crate::gb::SurfaceDerivs::curvature`], the normal computed once).
#[inline]
fn surface_point(d: &crate::gb::SurfaceDerivs) -> SurfacePoint {
    let Some(n) = d.normal() else {
        return SurfacePoint { position: d.p, ..Default::default() };
    };
    let (e, f, g) = d.first_fundamental_form();
    let (l, m, nn) = (d.suu.dot(n), d.suv.dot(n), d.svv.dot(n));
    let det = e * g - f * f;
    let (mut h, mut k) = (0.0, 0.0);
    if det > 0.0 {
        let mean = (l * g - 2.0 * m * f + nn * e) / (2.0 * det);
        let gaussian = (l * nn - m * m) / det;
        if mean.is_finite() && gaussian.is_finite() {
            (h, k) = (mean, gaussian);
        }
    }
    SurfacePoint { position: d.p, normal: n, mean_curvature: h, gaussian_curvature: k }
}

thread_local! {
    /// Per worker thread: the control vector of the patch being evaluated.
    static CONTROLS: RefCell<ControlSoa> = RefCell::new(ControlSoa::default());
}

impl GbSurfaceEvaluator {
    /// Validates every patch and builds (or fetches) the weight tables for resolution `r`.
    pub fn new(surface: &Surface, r: usize, form: crate::gb::WeightForm) -> Result<Self, TessellateError> {
        let mut which = Vec::with_capacity(surface.patches.len());
        let mut distinct: HashMap<Kind, u32> = HashMap::new();
        let mut firsts: Vec<(Kind, usize)> = Vec::new();
        // Validation in parallel; the first invalid patch (smallest index) is reported.
        let invalid = surface.patches.par_iter().enumerate().find_first(|(_, p)| {
            match p {
                Patch::Gb(g) => g.validate(),
                Patch::Cgb(c) => c.validate(),
            }
            .is_err()
        });
        if let Some((i, p)) = invalid {
            let v = match p {
                Patch::Gb(g) => g.validate(),
                Patch::Cgb(c) => c.validate(),
            };
            v.map_err(|source| TessellateError::InvalidPatch { patch: i, source })?;
        }
        let kinds: Vec<Kind> = surface.patches.par_iter().map(kind_of).collect();
        for (i, k) in kinds.into_iter().enumerate() {
            let id = match distinct.get(&k) {
                Some(&id) => id,
                None => {
                    let id = firsts.len() as u32;
                    distinct.insert(k.clone(), id);
                    firsts.push((k, i));
                    id
                }
            };
            which.push(id);
        }
        let evaluations: Result<Vec<Evaluation>, TessellateError> = firsts
            .into_par_iter()
            .map(|(kind, first)| {
                SampleLayout::new(&gb_domain(patch_sides(&surface.patches[first])), r)
                    .map_err(|source| TessellateError::Layout { patch: first, source })?;
                Ok(match kind {
                    Kind::Gb(n, d) => {
                        let bytes = GbTable::bytes_needed(n, d, r, true);
                        if bytes > TABLE_BYTES {
                            Evaluation::Direct
                        } else if bytes > CACHE_BYTES {
                            Evaluation::Gb(Arc::new(GbTable::with_second_derivatives(n, d, r, form).map_err(|e| table_error(first, e))?))
                        } else {
                            Evaluation::Gb(GbTable::cached_with_second_derivatives(n, d, r, form).map_err(|e| table_error(first, e))?)
                        }
                    }
                    Kind::Cgb(sides) => {
                        let bytes = CgbTable::bytes_needed(&sides, r);
                        if bytes > TABLE_BYTES {
                            Evaluation::Direct
                        } else if bytes > CACHE_BYTES {
                            Evaluation::Cgb(Arc::new(CgbTable::new(&sides, r, form).map_err(|e| table_error(first, e))?))
                        } else {
                            Evaluation::Cgb(CgbTable::cached(&sides, r, form).map_err(|e| table_error(first, e))?)
                        }
                    }
                })
            })
            .collect();
        Ok(GbSurfaceEvaluator { evaluations: evaluations?, which, form })
    }
}

/// Pushes the samples of a table, tile by tile, onto `out`; `tile(t)` evaluates tile t.
#[inline]
fn push_tiles(samples: usize, tiles: usize, out: &mut Vec<SurfacePoint>, tile: impl Fn(usize) -> [crate::gb::SurfaceDerivs; TILE]) {
    for t in 0..tiles {
        let frames = tile(t);
        for d in frames.iter().take(samples - t * TILE) {
            out.push(surface_point(d));
        }
    }
}

impl PatchEvaluator for GbSurfaceEvaluator {
    fn domain(&self, n: usize) -> Vec<DVec2> {
        gb_domain(n)
    }

    fn evaluate(&self, surface: &Surface, index: usize, layout: &SampleLayout, out: &mut Vec<SurfacePoint>) {
        out.clear();
        let (Some(&id), Some(patch)) = (self.which.get(index), surface.patches.get(index)) else { return };
        let Some(evaluation) = self.evaluations.get(id as usize) else { return };
        let samples = layout.uv.len();
        out.reserve(samples);
        CONTROLS.with(|cell| {
            let mut ctrl = cell.borrow_mut();
            match (evaluation, patch) {
                (Evaluation::Gb(t), Patch::Gb(g)) => {
                    ctrl.fill_gb(g);
                    if ctrl.len() != t.control_count() || t.sample_count() != samples {
                        return;
                    }
                    push_tiles(samples, t.tile_count(), out, |k| t.eval_tile_derivs(k, &ctrl));
                }
                (Evaluation::Cgb(t), Patch::Cgb(c)) => {
                    ctrl.fill_cgb(c);
                    if ctrl.len() != t.control_count() || t.sample_count() != samples {
                        return;
                    }
                    push_tiles(samples, t.tile_count(), out, |k| t.eval_tile_derivs(k, &ctrl));
                }
                (Evaluation::Direct, Patch::Gb(g)) => {
                    let Ok(mut ev) = g.evaluator() else { return };
                    out.extend(layout.uv.iter().map(|&uv| surface_point(&g.eval_derivs_with_form(&mut ev, uv, self.form))));
                }
                (Evaluation::Direct, Patch::Cgb(c)) => {
                    let Ok(mut ev) = c.evaluator() else { return };
                    out.extend(layout.uv.iter().map(|&uv| surface_point(&c.eval_derivs_with(&mut ev, uv, self.form))));
                }
                _ => {}
            }
        });
    }
}

/// Tessellates a GB/CGB surface at resolution `r` with [`GbSurfaceEvaluator`] (see
/// [`tessellate_surface_with`]).
pub fn tessellate_surface(
    surface: &Surface,
    r: usize,
    form: crate::gb::WeightForm,
    progress: Option<&mut dyn FnMut(f32) -> bool>,
) -> Result<(SurfaceMesh, WeldStats), TessellateError> {
    let eval = GbSurfaceEvaluator::new(surface, r, form)?;
    tessellate_surface_with(surface, r, &eval, progress)
}

impl SurfaceMesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Positions as a flat `[x0, y0, z0, x1, …]` array (for C buffers).
    pub fn positions_flat(&self) -> Vec<f64> {
        self.positions.iter().flat_map(|p| p.to_array()).collect()
    }

    /// Normals as a flat array.
    pub fn normals_flat(&self) -> Vec<f64> {
        self.normals.iter().flat_map(|p| p.to_array()).collect()
    }

    /// Triangles as a flat index array.
    pub fn triangles_flat(&self) -> Vec<u32> {
        self.triangles.iter().flatten().copied().collect()
    }
}
