//! Watertight tessellation of a whole [`Surface`]: every patch is sampled with the
//! [`SampleLayout`] of its n-sided domain (concentric triangles, or the quad layout's bilinear
//! sectors) at one common resolution, then the samples are welded. Below, r is the number of
//! boundary steps per side ([`SampleLayout::per_side`]: the resolution for triangles, twice it for
//! quads); welding and measuring are the same code for both layouts.
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

use super::evaluator::{GbSurfaceEvaluator, PatchEvaluator, SurfacePoint};
use super::measure::{finish_normals, join_shared_sides, BoundarySamples, KeptSample};
use super::fold::{dense_folds_of_ticked, dense_level, flipped_triangles, patch_folds, samples_around, Sectors};
use super::weld::{check_adjacency, WeldMap};
use super::TessellateError;
use crate::construct::Surface;
use crate::gb::{Layout, SampleLayout, Sampling, SectorPoint, WeightForm};
use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;

/// The welded triangle mesh of a surface, with per-vertex quality data (docs/math.md#welding).
/// Plain arrays (one entry per vertex or per triangle), ready for FFI buffers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceMesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Analytic unit normals (averaged over the patches sharing a boundary vertex).
    pub normals: Vec<DVec3>,
    /// Counter-clockwise triangles (outward for a closed input). In the quad layout: quad k
    /// split along its diagonal (0, 2) into triangles 2k and 2k+1, for the checks and measures.
    pub triangles: Vec<[u32; 3]>,
    /// Counter-clockwise quads of the quad layout ([`crate::gb::Layout::Quads`]; empty for the
    /// triangle layout and the subdivision methods). When not empty these are the output faces.
    pub quads: Vec<[u32; 4]>,
    /// Per output face (quads when there are any, else triangles): the corner of its patch whose
    /// sector holds it (domain vertex i, the end of side i; [`SampleLayout::face_corners`]).
    /// Empty for the subdivision methods.
    pub face_corner: Vec<u32>,
    /// Per output face: the cage corner `[face, corner]` it lies in ([`Surface::cage`]: the
    /// face of the control mesh and the position of the vertex in its vertex list;
    /// docs/math.md#cage-corners). Triangle layout: the corner of [`Self::face_corner`]'s
    /// sector. Subdivision methods: `[input face, u32::MAX]` per triangle. `[u32::MAX; 2]` when
    /// the surface has no cage map (hand-built surfaces). Empty when the conversion ran with
    /// [`crate::options::ConvertOptions::cage_maps`] off.
    pub cage_corner: Vec<[u32; 2]>,
    /// Per output face corner (loop: 4 per quad in the order of [`Self::quads`] in the quad
    /// layout, 3 per triangle in the order of [`Self::triangles`] in the triangle layout; empty
    /// for the subdivision methods) its bilinear coordinates (σ, τ) ∈ [0,1]² in its cage corner
    /// (the face's [`Self::cage_corner`] for quads, [`Self::cage_loop_corner`] for triangles):
    /// (0,0) the cage vertex, (1,0) the midpoint of the edge to the face's next vertex, (0,1)
    /// the midpoint of the edge from its previous vertex, (1,1) the face centre
    /// ([`crate::construct::SectorMap`]). Triangle layout: the coordinates of the loop's vertex
    /// in the quad-layout sector it lies in (docs/math.md#cage-corners). Empty when
    /// [`crate::options::ConvertOptions::cage_maps`] is off.
    pub cage_coords: Vec<[f64; 2]>,
    /// Triangle layout only (else empty; also empty when
    /// [`crate::options::ConvertOptions::cage_maps`] is off): per triangle corner (3 per triangle) the cage corner
    /// `[face, corner]` its [`Self::cage_coords`] are in. A triangle can straddle two quad
    /// sectors (in the dual structure two cage faces): each loop takes the triangle's
    /// [`Self::cage_corner`] when its vertex lies in that sector (its closure), else the sector
    /// its vertex lies in. `[u32::MAX; 2]` when the surface has no cage map.
    pub cage_loop_corner: Vec<[u32; 2]>,
    /// Per vertex: the patch that created it (the smallest patch index sharing it). For subdivision
    /// methods: the face of the input mesh it descends from. Empty when the conversion ran
    /// without [`crate::ConvertOptions::quality_arrays`] (as are the next four).
    pub patch: Vec<u32>,
    /// Per triangle: the patch (or input face) it belongs to ([`PatchLoops::patch_of`] gives it
    /// without this array).
    pub triangle_patch: Vec<u32>,
    /// Per vertex: mean curvature H = (k1 + k2)/2, sign relative to the normal.
    pub mean_curvature: Vec<f64>,
    /// Per vertex: Gaussian curvature K = k1·k2.
    pub gaussian_curvature: Vec<f64>,
    /// Per vertex: largest angle (degrees) between the normals of two patches sharing the vertex;
    /// 0 inside patches and on open boundaries.
    pub g1_deviation_deg: Vec<f64>,
    /// Per vertex: 1 where the vertex is folded (of a patch the dense pass finds folded: its
    /// tessellation samples that the fold rule flags, see [`super::fold`], and the vertices
    /// around the dense pass's worst point, [`super::fold::samples_around`]; or a vertex of a
    /// flipped triangle), else 0 (all 0 for subdivision methods).
    pub fold: Vec<u8>,
    /// Per patch: the fold test's result on the tessellation samples (empty for subdivision).
    pub patch_folds: Vec<TessellationFolds>,
    /// Indices of the flipped triangles ([`super::fold::flipped_triangles`]).
    pub flipped_triangles: Vec<u32>,
    /// Per patch: its boundary loop and triangle range (empty for subdivision methods), the
    /// input of the self-intersection certificates ([`crate::quality::certify`]).
    pub patch_loops: PatchLoops,
}

/// The boundary loop of every patch of a tessellation as output vertex ids, and its triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PatchLoops {
    /// The loop of patch p is `ids[start[p]..start[p + 1]]`: its boundary samples in the
    /// layout's order (side 0 steps 0..r−1, side 1, …), counter-clockwise like its triangles, so
    /// every step is a directed edge of one of them. Its corners (nodes of the curve network)
    /// are the entries at multiples of `per_side`.
    pub start: Vec<usize>,
    pub ids: Vec<u32>,
    /// Samples per side (the resolution r).
    pub per_side: usize,
    /// The triangles of patch p are `triangles[p]..triangles[p + 1]` (consecutive).
    pub triangles: Vec<usize>,
}

/// The k with `starts[k] ≤ t < starts[k + 1]` in ascending range starts (one more than there are
/// ranges, the last the end), `None` past the end: the patch of a triangle from per-patch
/// triangle starts ([`PatchLoops::patch_of`], the self-intersection certificates).
pub fn range_of(starts: &[usize], t: usize) -> Option<usize> {
    starts.partition_point(|&s| s <= t).checked_sub(1).filter(|&k| k + 1 < starts.len())
}

impl PatchLoops {
    /// Number of patches.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// True when there is no patch.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The boundary loop of patch p.
    pub fn of(&self, p: usize) -> &[u32] {
        &self.ids[self.start[p]..self.start[p + 1]]
    }

    /// The patch whose triangle range holds triangle t (`None` past the last).
    pub fn patch_of(&self, t: usize) -> Option<usize> {
        range_of(&self.triangles, t)
    }

    /// The corner vertices of patch p, in order.
    pub fn corners(&self, p: usize) -> impl Iterator<Item = u32> + '_ {
        self.of(p).iter().step_by(self.per_side.max(1)).copied()
    }

    /// The loops of all patches from the welding map (`r` boundary steps per side):
    /// O(boundary samples), no hashing.
    fn new(surface: &Surface, layouts: &HashMap<usize, SampleLayout>, map: &WeldMap, r: usize) -> PatchLoops {
        let np = surface.patches.len();
        let mut out = PatchLoops { per_side: r, ..PatchLoops::default() };
        out.start.reserve(np + 1);
        out.triangles.reserve(np + 1);
        // Exactly the loops' length (grown by doubling it took up to twice that, 6.5 bytes per
        // output vertex instead of 4 on a quad mesh at resolution 2).
        let loop_len = |l: &SampleLayout| l.uv.len() - l.first_boundary();
        out.ids.reserve_exact(surface.patches.iter().map(|patch| loop_len(&layouts[&patch.sides()])).sum());
        let mut nt = 0usize;
        for (p, patch) in surface.patches.iter().enumerate() {
            out.start.push(out.ids.len());
            out.triangles.push(nt);
            let layout = &layouts[&patch.sides()];
            nt += layout.triangles.len();
            let first = layout.first_boundary();
            out.ids.extend_from_slice(&map.ids[map.offsets[p] + first..map.offsets[p + 1]]);
        }
        out.start.push(out.ids.len());
        out.triangles.push(nt);
        out
    }
}

/// The fold test's result for one patch on the samples of the tessellation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TessellationFolds {
    /// Folded samples of the patch, counted by the dense pass (0 for a patch the tessellation's
    /// samples clear: such a patch has no folded sample).
    pub samples: usize,
    /// Domain point of the dense pass's worst folded sample.
    pub worst: Option<glam::DVec2>,
    /// The tessellation's samples did not clear the patch ([`super::fold::ClearTest`]), so the
    /// dense pass ([`super::fold::dense_folds_of`]) decided it.
    pub dense: bool,
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
    /// Number of welded vertices lying on smooth shared boundaries (creased sides excluded).
    pub shared_vertices: usize,
    /// Number of shared sides (each pair once) with a crease sharpness above 0: welded but not
    /// G1, so not in the G1 numbers.
    pub crease_sides: usize,
}

/// `len` default values, written in parallel: the first touch of a large fresh allocation (page
/// faults, zeroing) then happens on all threads rather than serially.
pub(crate) fn zeroed<T: Default + Send>(len: usize) -> Vec<T> {
    (0..len).into_par_iter().with_min_len(1 << 14).map(|_| T::default()).collect()
}

/// `len` copies of `value`, reserved with `try_reserve_exact`: an allocation failure is the typed
/// [`TessellateError::OutOfMemory`] naming `what`, never an abort of the host process. Filled in
/// parallel (as [`zeroed`]: the first touch of the fresh pages runs on all threads).
pub(crate) fn try_filled<T: Clone + Send + Sync>(len: usize, value: T, what: &'static str) -> Result<Vec<T>, TessellateError> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| TessellateError::OutOfMemory {
        what,
        bytes: (len as u64).saturating_mul(std::mem::size_of::<T>() as u64),
    })?;
    v.par_extend(rayon::iter::repeat_n(value, len).with_min_len(1 << 14));
    Ok(v)
}

/// Patches evaluated per progress step.
const CHUNK: usize = 512;

/// The end of the setup's share of the progress of [`tessellate_checked`] (layouts, welding map,
/// allocation).
const SETUP: f32 = 0.1;

/// The end of the patch evaluation's share of the progress of [`tessellate_checked`] (then
/// the dense fold pass up to [`EVALUATION`]).
const DENSE: f32 = 0.8;

/// The end of the dense fold pass's share of the progress of [`tessellate_checked`] (then
/// welding and normals).
const EVALUATION: f32 = 0.9;

/// Patches per progress step of the dense fold pass (its level has about (16/r)² times the
/// tessellation's samples per patch at r < 8, so its chunks are [`CHUNK`]/32).
const DENSE_CHUNK: usize = CHUNK / 32;

/// Calls `progress` (if any) with `f`; [`TessellateError::Cancelled`] when it returns false.
fn tick(progress: &mut Option<&mut dyn FnMut(f32) -> bool>, f: f32) -> Result<(), TessellateError> {
    if let Some(cb) = progress.as_mut() {
        if !cb(f) {
            return Err(TessellateError::Cancelled);
        }
    }
    Ok(())
}

/// The sampling layout of every side count n of the surface's patches, in the evaluator's domain.
fn layouts_of<E: PatchEvaluator>(surface: &Surface, r: Sampling, evaluator: &E) -> Result<HashMap<usize, SampleLayout>, TessellateError> {
    let mut layouts: HashMap<usize, SampleLayout> = HashMap::new();
    for (p, patch) in surface.patches.iter().enumerate() {
        let n = patch.sides();
        if let std::collections::hash_map::Entry::Vacant(e) = layouts.entry(n) {
            let layout = SampleLayout::new(&evaluator.domain(n), r).map_err(|source| TessellateError::Layout { patch: p, source })?;
            e.insert(layout);
        }
    }
    Ok(layouts)
}

/// Per side count n: the sampling layout, its fold-test sectors, the patch corner of every output
/// face ([`SampleLayout::face_corners`]) and, for the triangle layout, where every sample lies in
/// the quad sectors ([`SampleLayout::sector_points`]).
type PatchLayout = (SampleLayout, Sectors, Vec<u32>, Vec<SectorPoint>);

/// One patch's pieces of the per-vertex arrays, written while its samples are evaluated (or, in
/// [`Pieces`], the tails not yet handed to a patch).
struct VertexSlices<'a> {
    pos: &'a mut [DVec3],
    nrm: &'a mut [DVec3],
    h: &'a mut [f64],
    k: &'a mut [f64],
    weight: &'a mut [u16],
    /// Its boundary samples that did not create their vertex ([`BoundarySamples`]).
    bnd: &'a mut [KeptSample],
}

/// One patch's pieces of the per-face arrays and of the per-vertex patch ids, written after the
/// welding (when the kept boundary samples are freed, so the two never take memory at the same
/// time), or, in [`Pieces`], the tails not yet handed to a patch.
struct FaceSlices<'a> {
    patch: &'a mut [u32],
    tris: &'a mut [[u32; 3]],
    tri_patch: &'a mut [u32],
    quads: &'a mut [[u32; 4]],
    corner: &'a mut [u32],
    cage: &'a mut [[u32; 2]],
    coords: &'a mut [[f64; 2]],
    loop_cage: &'a mut [[u32; 2]],
}

/// Output slices that can be cut into consecutive per-patch pieces: `len[i]` items off the front
/// of the i-th slice.
trait CutSlices<'a>: Sized {
    fn take_patch(&mut self, len: &[usize; 7]) -> Self;
}

impl<'a> CutSlices<'a> for VertexSlices<'a> {
    /// Lengths: [vertices it creates, kept boundary samples, …].
    fn take_patch(&mut self, len: &[usize; 7]) -> Self {
        VertexSlices {
            pos: take(&mut self.pos, len[0]),
            nrm: take(&mut self.nrm, len[0]),
            h: take(&mut self.h, len[0]),
            k: take(&mut self.k, len[0]),
            weight: take(&mut self.weight, len[0]),
            bnd: take(&mut self.bnd, len[1]),
        }
    }
}

impl<'a> CutSlices<'a> for FaceSlices<'a> {
    /// Lengths: [triangles (and their patch ids), quads, output faces (their patch corners),
    /// cage corners of its faces, cage coordinates of its face loops, loop cage corners, vertices
    /// it creates]; the cage lengths are 0 without cage maps.
    fn take_patch(&mut self, len: &[usize; 7]) -> Self {
        FaceSlices {
            patch: take(&mut self.patch, len[6]),
            tris: take(&mut self.tris, len[0]),
            tri_patch: take(&mut self.tri_patch, len[0]),
            quads: take(&mut self.quads, len[1]),
            corner: take(&mut self.corner, len[2]),
            cage: take(&mut self.cage, len[3]),
            coords: take(&mut self.coords, len[4]),
            loop_cage: take(&mut self.loop_cage, len[5]),
        }
    }
}

/// The first `len` items of `rest`, which keeps the others; fewer when `rest` is shorter, which
/// happens only for the cage arrays, empty when [`crate::options::ConvertOptions::cage_maps`] is off.
pub(crate) fn take<'a, T>(rest: &mut &'a mut [T], len: usize) -> &'a mut [T] {
    let len = len.min(rest.len());
    let (head, tail) = std::mem::take(rest).split_at_mut(len);
    *rest = tail;
    head
}

/// The output arrays not yet handed to a patch: every slice of `rest` is the tail of its array
/// from the first patch not yet taken, so the patches are cut off in order one chunk at a time
/// and no list of the pieces of all patches is held (it would cost about 260 bytes per patch).
/// `starts[i][p]` is where patch p's piece of the i-th slice starts (np + 1 entries each).
struct Pieces<S> {
    next: usize,
    np: usize,
    starts: Vec<Vec<usize>>,
    rest: S,
}

impl<'a, S: CutSlices<'a>> Pieces<S> {
    /// Patch index and pieces of the next patch (`None` after the last).
    fn next_patch(&mut self) -> Option<(usize, S)> {
        let p = self.next;
        if p >= self.np {
            return None;
        }
        self.next += 1;
        let mut len = [0; 7];
        for (l, s) in len.iter_mut().zip(&self.starts) {
            *l = s.get(p + 1).zip(s.get(p)).map_or(0, |(b, a)| b - a);
        }
        Some((p, self.rest.take_patch(&len)))
    }
}

/// The output of one patch's evaluation: its own disjoint pieces of the per-vertex arrays.
struct PatchOut<'a> {
    p: usize,
    o: VertexSlices<'a>,
    fold: &'a mut TessellationFolds,
    /// Output vertices of the folded samples (set in `mesh.fold` after the dense pass, when it
    /// finds the patch folded).
    folded: Vec<u32>,
}

/// Cuts the per-vertex output arrays (allocated by the caller) and the kept boundary samples into
/// per-patch pieces ([`Pieces::next_patch`]), with every patch's fold result (in patch order).
/// The vertices a patch creates are contiguous (see `WeldMap::vstart`), as are its boundary
/// samples, so each patch writes its own disjoint pieces and the evaluation runs in parallel
/// without locks.
fn vertex_pieces<'a>(
    map: &WeldMap,
    mesh: &'a mut SurfaceMesh,
    weight: &'a mut [u16],
    boundary: &'a mut BoundarySamples,
) -> (Pieces<VertexSlices<'a>>, std::slice::IterMut<'a, TessellationFolds>) {
    let pieces = Pieces {
        next: 0,
        np: map.vstart.len().saturating_sub(1),
        starts: vec![map.vstart.clone(), boundary.start.clone()],
        rest: VertexSlices {
            pos: &mut mesh.positions,
            nrm: &mut mesh.normals,
            h: &mut mesh.mean_curvature,
            k: &mut mesh.gaussian_curvature,
            weight,
            bnd: &mut boundary.samples,
        },
    };
    (pieces, mesh.patch_folds.iter_mut())
}

/// Allocates the per-face output arrays (triangles, their patches, quads, face corners and, with
/// `cage_maps`, the cage maps) and the per-vertex patch ids, and writes every patch's pieces in
/// parallel from the welding map (triangles and quads as output vertex ids; docs/math.md#welding;
/// the patch of a vertex is the one that created it, `WeldMap::vstart`). Runs after the welding,
/// so these arrays and the kept boundary samples are never allocated at the same time. Without
/// `patch_ids` the per-vertex and per-triangle patch ids stay empty.
fn write_faces(
    surface: &Surface,
    layouts: &HashMap<usize, PatchLayout>,
    map: &WeldMap,
    mesh: &mut SurfaceMesh,
    cage_maps: bool,
    patch_ids: bool,
    at: &mut dyn FnMut(f32) -> Result<(), TessellateError>,
) -> Result<(), TessellateError> {
    let np = surface.patches.len();
    let mut tri_start = Vec::with_capacity(np + 1);
    let mut quad_start = Vec::with_capacity(np + 1);
    let mut face_start = Vec::with_capacity(np + 1);
    let (mut nt, mut nq, mut nf) = (0usize, 0usize, 0usize);
    for patch in &surface.patches {
        let l = &layouts[&patch.sides()].0;
        tri_start.push(nt);
        quad_start.push(nq);
        face_start.push(nf);
        nt += l.triangles.len();
        nq += l.quads.len();
        nf += if l.quads.is_empty() { l.triangles.len() } else { l.quads.len() };
    }
    tri_start.push(nt);
    quad_start.push(nq);
    face_start.push(nf);
    mesh.triangles = try_filled(nt, [0; 3], "output triangles")?;
    at(0.1)?;
    if patch_ids {
        mesh.triangle_patch = try_filled(nt, 0, "output triangle patches")?;
        mesh.patch = try_filled(map.vertex_count, 0, "output patch indices")?;
        at(0.2)?;
    }
    mesh.quads = try_filled(nq, [0; 4], "output quads")?;
    mesh.face_corner = try_filled(nf, 0, "output face corners")?;
    at(0.3)?;
    // The cage maps (only with `cage_maps`): per face its cage corner, per loop its cage
    // coordinates (4 per quad, or 3 per triangle in the triangle layout, whose loops also get
    // their own cage corner). Without them every piece is empty.
    let triangle_layout = nq == 0;
    let none = || vec![0; np + 1];
    let cage_start = if cage_maps { face_start.clone() } else { none() };
    let loop_start: Vec<usize> = match (cage_maps, triangle_layout) {
        (false, _) => none(),
        (true, true) => tri_start.iter().map(|&t| 3 * t).collect(),
        (true, false) => quad_start.iter().map(|&q| 4 * q).collect(),
    };
    let lc_start = if triangle_layout { loop_start.clone() } else { none() };
    let (nc, nl, nlc) = (cage_start[np], loop_start[np], lc_start[np]);
    mesh.cage_corner = try_filled(nc, [u32::MAX; 2], "output cage corners")?;
    mesh.cage_coords = try_filled(nl, [0.0; 2], "output cage coordinates")?;
    mesh.cage_loop_corner = try_filled(nlc, [u32::MAX; 2], "output loop cage corners")?;
    at(0.5)?;
    let mut pieces = Pieces {
        next: 0,
        np,
        starts: vec![tri_start, quad_start, face_start, cage_start, loop_start, lc_start, map.vstart.clone()],
        rest: FaceSlices {
            patch: &mut mesh.patch,
            tris: &mut mesh.triangles,
            tri_patch: &mut mesh.triangle_patch,
            quads: &mut mesh.quads,
            corner: &mut mesh.face_corner,
            cage: &mut mesh.cage_corner,
            coords: &mut mesh.cage_coords,
            loop_cage: &mut mesh.cage_loop_corner,
        },
    };
    // The first touch of the arrays' pages happened in `try_filled`; the faces are written in
    // chunks of patches, ticking between them.
    loop {
        let chunk: Vec<(usize, FaceSlices<'_>)> = (0..CHUNK).map_while(|_| pieces.next_patch()).collect();
        let Some(&(last, _)) = chunk.last() else { return Ok(()) };
        chunk.into_par_iter().for_each(|(p, mut o)| patch_faces(surface, layouts, map, p, &mut o));
        at(0.5 + 0.5 * (last + 1) as f32 / np.max(1) as f32)?;
    }
}

/// Writes patch p's triangles and quads (layout faces through the welding map), their patch and
/// patch corners, the patch ids of the vertices it created, and the cage maps when `o` has room
/// for them.
fn patch_faces(
    surface: &Surface,
    layouts: &HashMap<usize, PatchLayout>,
    map: &WeldMap,
    p: usize,
    o: &mut FaceSlices<'_>,
) {
    let (layout, _, corners, points) = &layouts[&surface.patches[p].sides()];
    let ids = &map.ids[map.offsets[p]..map.offsets[p + 1]];
    for (t, lt) in o.tris.iter_mut().zip(&layout.triangles) {
        *t = lt.map(|x| ids[x as usize]);
    }
    o.tri_patch.fill(p as u32);
    o.patch.fill(p as u32);
    for (q, lq) in o.quads.iter_mut().zip(&layout.quads) {
        *q = lq.map(|x| ids[x as usize]);
    }
    o.corner.copy_from_slice(corners);
    if !o.cage.is_empty() {
        write_cage(surface.cage.get(p).map(Vec::as_slice), layout, corners, points, o);
    }
}

/// The cage corner of every output face of one patch (`cage`: the patch's [`Surface::cage`] row,
/// `None` when the surface has none) and the cage coordinates of the face corners: for quads
/// from their sector grid, for triangles from `points` ([`SampleLayout::sector_points`]) with
/// each loop's own cage corner (docs/math.md#cage-corners).
fn write_cage(cage: Option<&[crate::construct::CageSector]>, layout: &SampleLayout, corners: &[u32], points: &[SectorPoint], o: &mut FaceSlices<'_>) {
    use crate::construct::SectorMap;
    let sector = |i: u32| cage.and_then(|c| c.get(i as usize));
    for (out, &i) in o.cage.iter_mut().zip(corners) {
        if let Some(c) = sector(i) {
            *out = [c.face, c.corner];
        }
    }
    let r = layout.resolution.max(1);
    let rf = r as f64;
    for (k, q) in o.coords.chunks_exact_mut(4).enumerate().take(layout.quads.len()) {
        let map = sector((k / (r * r)) as u32).map_or(SectorMap::Vertex, |c| c.map);
        let (a, b) = ((k % (r * r)) / r, k % r);
        for (c, (da, db)) in q.iter_mut().zip([(0, 0), (1, 0), (1, 1), (0, 1)]) {
            *c = map.cage_coords((a + da) as f64 / rf, (b + db) as f64 / rf);
        }
    }
    if !layout.quads.is_empty() {
        return;
    }
    let n = layout.sides as u32;
    let loops = o.coords.chunks_exact_mut(3).zip(o.loop_cage.chunks_exact_mut(3));
    for ((tri, (coords, loop_cage)), &face) in layout.triangles.iter().zip(loops).zip(corners) {
        for ((&x, c), lc) in tri.iter().zip(coords).zip(loop_cage) {
            let Some(point) = points.get(x as usize) else { continue };
            // The face's sector when the vertex lies in it, else the vertex's first.
            let (i, st) = match point.in_sector(face, n) {
                Some(st) => (face, st),
                None => (point.first, point.st[0]),
            };
            let c_sector = sector(i);
            *c = c_sector.map_or(SectorMap::Vertex, |c| c.map).cage_coords(st.x, st.y);
            if let Some(cs) = c_sector {
                *lc = [cs.face, cs.corner];
            }
        }
    }
}

/// Evaluates patch `out.p` and writes the samples that create vertices and its kept boundary
/// samples into its pieces (its faces follow after the welding, [`write_faces`]).
fn evaluate_patch<E: PatchEvaluator>(
    surface: &Surface,
    evaluator: &E,
    layouts: &HashMap<usize, PatchLayout>,
    map: &WeldMap,
    folds: bool,
    buf: &mut Vec<SurfacePoint>,
    out: &mut PatchOut<'_>,
) -> Result<(), TessellateError> {
    let (p, o) = (out.p, &mut out.o);
    let (layout, sectors, _, _) = &layouts[&surface.patches[p].sides()];
    evaluator.evaluate(surface, p, layout, buf);
    if buf.len() != layout.uv.len() {
        return Err(TessellateError::Evaluation { patch: p, sample: buf.len().min(layout.uv.len()) });
    }
    if let Some(s) = buf.iter().position(|x| !x.position.is_finite()) {
        return Err(TessellateError::Evaluation { patch: p, sample: s });
    }
    let base = map.offsets[p];
    let (mut j, mut b) = (0, 0);
    for (s, sp) in buf.iter().enumerate() {
        if !map.owner[base + s] {
            // A boundary sample that did not create its vertex: kept for welding.
            o.bnd[b] = KeptSample::from(sp);
            b += 1;
        } else {
            o.pos[j] = sp.position;
            if sp.normal != DVec3::ZERO && sp.normal.is_finite() {
                o.nrm[j] = sp.normal;
                o.weight[j] = 1;
                if sp.mean_curvature.is_finite() && sp.gaussian_curvature.is_finite() {
                    o.h[j] = sp.mean_curvature;
                    if let Some(k) = o.k.get_mut(j) {
                        *k = sp.gaussian_curvature;
                    }
                }
            }
            j += 1;
        }
    }
    if !folds {
        return Ok(());
    }
    let ids = &map.ids[base..map.offsets[p + 1]];
    let folds = patch_folds(&surface.patches[p], sectors, layout, buf);
    // A cleared patch has no folded sample. One its samples do not clear goes to the dense pass
    // after this one (`tessellate_checked`, [`dense_folds_of`]), which decides its count and site
    // alone (its samples are twice as dense, and the reversal between neighbours that the fold
    // rule asks for is only trusted where neighbours are close); these samples' folded ones are
    // kept to mark the region when the dense pass finds a fold.
    out.fold.dense = !folds.cleared;
    out.folded = folds.samples.iter().map(|&s| ids[s as usize]).collect();
    Ok(())
}

/// Tessellates `surface` at resolution `r` (samples per patch side; a bare `usize` is the
/// triangle layout, a [`Sampling`] names the layout) with `evaluator`, welds the patches (see the module doc) and returns the mesh with the measurements. `progress` is called
/// with the fraction done (0..1) after every chunk of patches; returning false cancels.
///
/// Every patch's samples also go through the fold test ([`super::fold`]): the result is in
/// `SurfaceMesh::patch_folds`, `fold` and `flipped_triangles`.
pub fn tessellate_surface_with<E: PatchEvaluator>(
    surface: &Surface,
    r: impl Into<Sampling>,
    evaluator: &E,
    progress: Option<&mut dyn FnMut(f32) -> bool>,
) -> Result<(SurfaceMesh, WeldStats), TessellateError> {
    tessellate_checked(surface, r, evaluator, true, true, true, progress)
}

/// [`tessellate_surface_with`], with the fold test (`folds`) or without it (then `fold` is all
/// 0 and `patch_folds`, `flipped_triangles` are empty; for timing the test's share), and with
/// the cage maps ([`SurfaceMesh::cage_corner`], `cage_coords`, `cage_loop_corner`) or without
/// them (`cage_maps` false: they stay empty; [`crate::options::ConvertOptions::cage_maps`]), and
/// with the quality arrays (the patch ids [`SurfaceMesh::patch`] and `triangle_patch`, the
/// Gaussian curvatures, the G1 deviations) or without them (`patch_ids` false; as
/// [`crate::options::ConvertOptions::quality_arrays`]): then the patch ids and the Gaussian
/// curvatures are never allocated, and the G1 deviations are freed as soon as the welding has
/// measured them (the report's figures need them and the mean curvatures only), so neither is
/// held while the face arrays are written, the peak of the tessellation (8 + 8 bytes per vertex
/// less there).
pub fn tessellate_checked<E: PatchEvaluator>(
    surface: &Surface,
    r: impl Into<Sampling>,
    evaluator: &E,
    folds: bool,
    cage_maps: bool,
    patch_ids: bool,
    mut progress: Option<&mut dyn FnMut(f32) -> bool>,
) -> Result<(SurfaceMesh, WeldStats), TessellateError> {
    // The setup's steps tick at SETUP · k / 8 (k = 1..8, the allocations finer), so a cancel
    // takes effect between them.
    let setup = |k: u8| SETUP * f32::from(k) / 8.0;
    check_adjacency(surface)?;
    tick(&mut progress, setup(1))?;
    let np = surface.patches.len();
    let sampling: Sampling = r.into();
    let layouts = layouts_of(surface, sampling, evaluator)?;
    tick(&mut progress, setup(2))?;
    // Boundary steps per side, the same for every n: what welding and measuring count in.
    let r = sampling.per_side();
    let map = WeldMap::new(surface, &layouts, r)?;
    tick(&mut progress, setup(3))?;
    let with_sectors: HashMap<usize, PatchLayout> = layouts
        .par_iter()
        .map(|(&n, l)| (n, (l.clone(), Sectors::new(&evaluator.domain(n), &l.uv), l.face_corners(), l.sector_points())))
        .collect();
    tick(&mut progress, setup(4))?;
    let nv = map.vertex_count;
    // The output arrays, ticking between them (each is a large first touch).
    let positions = try_filled(nv, DVec3::ZERO, "output positions")?;
    tick(&mut progress, setup(4) + SETUP / 32.0)?;
    let normals = try_filled(nv, DVec3::ZERO, "output normals")?;
    tick(&mut progress, setup(4) + SETUP / 16.0)?;
    let mean_curvature = try_filled(nv, 0.0, "output mean curvature")?;
    tick(&mut progress, setup(4) + 3.0 * SETUP / 32.0)?;
    let gaussian_curvature = if patch_ids { try_filled(nv, 0.0, "output Gaussian curvature")? } else { Vec::new() };
    let g1_deviation_deg = try_filled(nv, 0.0, "output G1 deviation")?;
    let fold = try_filled(nv, 0, "output fold flags")?;
    let mut mesh = SurfaceMesh {
        positions,
        normals,
        triangles: Vec::new(),
        quads: Vec::new(),
        face_corner: Vec::new(),
        cage_corner: Vec::new(),
        cage_coords: Vec::new(),
        cage_loop_corner: Vec::new(),
        patch: Vec::new(),
        triangle_patch: Vec::new(),
        mean_curvature,
        gaussian_curvature,
        g1_deviation_deg,
        fold,
        patch_folds: Vec::new(),
        flipped_triangles: Vec::new(),
        patch_loops: PatchLoops::default(),
    };
    tick(&mut progress, setup(5))?;
    mesh.patch_loops = PatchLoops::new(surface, &layouts, &map, r);
    tick(&mut progress, setup(6))?;
    let mut boundary = BoundarySamples::new(surface, &layouts, &map)?;
    // Per vertex: how many patches contributed a valid normal.
    let mut weight = vec![0u16; nv];
    tick(&mut progress, setup(7))?;
    // Per patch with folded samples: (patch, their output vertices).
    let pending: Vec<(usize, Vec<u32>)> = {
        mesh.patch_folds = vec![TessellationFolds::default(); np];
        let (mut pieces, mut fold) = vertex_pieces(&map, &mut mesh, &mut weight, &mut boundary);
        tick(&mut progress, setup(8))?;
        let mut folded = Vec::new();
        let mut done = 0usize;
        while done < np {
            let end = (done + crate::progress::chunk_size(np, CHUNK)).min(np);
            let mut outs: Vec<PatchOut<'_>> = (done..end)
                .map_while(|_| pieces.next_patch().zip(fold.next()))
                .map(|((p, o), fold)| PatchOut { p, o, fold, folded: Vec::new() })
                .collect();
            outs.par_iter_mut()
                .try_for_each_init(Vec::new, |buf, o| evaluate_patch(surface, evaluator, &with_sectors, &map, folds, buf, o))?;
            folded.extend(outs.iter_mut().filter(|o| !o.folded.is_empty()).map(|o| (o.p, std::mem::take(&mut o.folded))));
            done = end;
            tick(&mut progress, SETUP + (DENSE - SETUP) * done as f32 / np.max(1) as f32)?;
        }
        folded
    };
    // The dense pass on the patches the samples did not clear (docs/math.md#fold-clearing):
    // its folded samples are the patch's count, its worst point is the patch's site, and the
    // output vertices around that point are marked (the star of the nearest sample), with the
    // tessellation's own folded samples of that patch.
    let mut folded: Vec<u32> = Vec::new();
    let uncleared: Vec<usize> = mesh.patch_folds.iter().enumerate().filter(|(_, f)| f.dense).map(|(p, _)| p).collect();
    // It ticks from DENSE to EVALUATION in chunks of at most DENSE_CHUNK patches.
    if let Some(&first) = uncleared.first() {
        let level = dense_level(with_sectors[&surface.patches[first].sides()].0.sampling());
        let nu = uncleared.len();
        let mut on_chunk = |done: usize| tick(&mut progress, DENSE + (EVALUATION - DENSE) * done as f32 / nu as f32);
        let chunk = crate::progress::chunk_size(nu, DENSE_CHUNK);
        let found = dense_folds_of_ticked(surface, &uncleared, level, evaluator.weight_form(), chunk, &mut on_chunk)?;
        for (&p, (count, worst)) in uncleared.iter().zip(found) {
            mesh.patch_folds[p].samples = count;
            let Some(at) = worst else { continue };
            mesh.patch_folds[p].worst = Some(at);
            let ids = &map.ids[map.offsets[p]..map.offsets[p + 1]];
            let layout = &with_sectors[&surface.patches[p].sides()].0;
            folded.extend(samples_around(layout, at).iter().map(|&s| ids[s as usize]));
        }
    }
    for (p, vertices) in pending {
        if mesh.patch_folds[p].samples > 0 {
            folded.extend(vertices);
        }
    }
    for v in folded {
        if let Some(f) = mesh.fold.get_mut(v as usize) {
            *f = 1;
        }
    }
    tick(&mut progress, EVALUATION)?;
    let stats = join_shared_sides(surface, &layouts, &map, r, &boundary, &mut mesh, &mut weight);
    // The kept samples are welded: freed before the face arrays take their place, as are the G1
    // deviations when the caller does not keep them (their figures are in `stats`).
    drop(boundary);
    if !patch_ids {
        mesh.g1_deviation_deg = Vec::new();
    }
    let faces_at = |f: f32| 0.5 * (1.0 + EVALUATION) + 0.25 * (1.0 - EVALUATION) * f;
    tick(&mut progress, faces_at(0.0))?;
    write_faces(surface, &with_sectors, &map, &mut mesh, cage_maps, patch_ids, &mut |f| tick(&mut progress, faces_at(f)))?;
    finish_normals(&mut mesh, &weight);
    tick(&mut progress, 1.0)?;
    if !folds {
        mesh.patch_folds.clear();
        return Ok((mesh, stats));
    }
    mesh.flipped_triangles = flipped_triangles(&mesh.positions, &mesh.normals, &mesh.triangles);
    for &t in &mesh.flipped_triangles {
        for &v in &mesh.triangles[t as usize] {
            if let Some(f) = mesh.fold.get_mut(v as usize) {
                *f = 1;
            }
        }
        // A patch folded only through flipped triangles still gets a site: the domain centroid
        // of its first flipped triangle.
        let Some(p) = mesh.patch_loops.patch_of(t as usize) else { continue };
        if mesh.patch_folds.get(p).is_some_and(|f| f.worst.is_none()) {
            let local = (t as usize).checked_sub(mesh.patch_loops.triangles.get(p).copied().unwrap_or(usize::MAX));
            let layout = layouts.get(&surface.patches[p].sides());
            if let (Some(local), Some(layout)) = (local, layout) {
                if let Some(tri) = layout.triangles.get(local) {
                    let uv = tri.iter().filter_map(|&i| layout.uv.get(i as usize)).copied().sum::<glam::DVec2>() / 3.0;
                    mesh.patch_folds[p].worst = Some(uv);
                }
            }
        }
    }
    Ok((mesh, stats))
}

/// Tessellates a GB/CGB surface at resolution `r` with [`GbSurfaceEvaluator`] (see
/// [`tessellate_surface_with`]).
pub fn tessellate_surface(
    surface: &Surface,
    r: impl Into<Sampling>,
    form: WeightForm,
    progress: Option<&mut dyn FnMut(f32) -> bool>,
) -> Result<(SurfaceMesh, WeldStats), TessellateError> {
    let r: Sampling = r.into();
    let eval = GbSurfaceEvaluator::new(surface, r, form)?;
    tessellate_surface_with(surface, r, &eval, progress)
}

/// [`tessellate_surface`] with or without the fold test, the cage maps and the patch ids (see
/// [`tessellate_checked`]).
pub fn tessellate_surface_checked(
    surface: &Surface,
    r: impl Into<Sampling>,
    form: WeightForm,
    folds: bool,
    cage_maps: bool,
    patch_ids: bool,
    progress: Option<&mut dyn FnMut(f32) -> bool>,
) -> Result<(SurfaceMesh, WeldStats), TessellateError> {
    let r: Sampling = r.into();
    let eval = GbSurfaceEvaluator::new(surface, r, form)?;
    tessellate_checked(surface, r, &eval, folds, cage_maps, patch_ids, progress)
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

    /// Number of output faces: quads when there are any, else triangles.
    pub fn face_count(&self) -> usize {
        if self.quads.is_empty() {
            self.triangles.len()
        } else {
            self.quads.len()
        }
    }

    /// The layout of the output faces.
    pub fn layout(&self) -> Layout {
        if self.quads.is_empty() {
            Layout::Triangles
        } else {
            Layout::Quads
        }
    }

    /// Output face f as vertex ids (3 or 4).
    pub fn face(&self, f: usize) -> &[u32] {
        if self.quads.is_empty() {
            &self.triangles[f]
        } else {
            &self.quads[f]
        }
    }

    /// The patch (or input face) of output face f.
    pub fn face_patch(&self, f: usize) -> u32 {
        let t = if self.quads.is_empty() { f } else { 2 * f };
        self.triangle_patch[t]
    }
}

#[cfg(test)]
mod try_filled_tests {
    use super::*;

    #[test]
    fn an_impossible_allocation_is_a_typed_error() {
        let e = try_filled(usize::MAX / 16, 0.0f64, "output mean curvature").unwrap_err();
        assert!(matches!(e, TessellateError::OutOfMemory { what: "output mean curvature", .. }), "{e}");
        assert_eq!(try_filled(3, 7u32, "x").unwrap(), vec![7, 7, 7]);
    }
}
