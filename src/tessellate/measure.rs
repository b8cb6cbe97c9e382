//! After evaluation: the welding of the samples that did not create their vertex (their normals
//! and curvatures are added to the welded vertex), the boundary gap and G1 measurements along
//! shared sides, and the normal fallback (see the [`super::surface`] module doc).

use super::surface::{SurfaceMesh, WeldStats};
use super::weld::WeldMap;
use super::{SurfacePoint, TessellateError};
use crate::construct::Surface;
use crate::gb::{angle_deg, SampleLayout};
use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;

/// The boundary samples that did not create their vertex, kept from evaluation for welding and
/// measuring. A sample that created its vertex is not kept: its position is the vertex's, and its
/// normal is the vertex's before any other sample is added to it: the sample's normal when
/// usable, else zero (angle 0, like the NaN angle of a non-finite normal: no G1 deviation).
/// In the quad layout at r = 2 on a closed quad mesh this keeps 9 of the 16 boundary samples of
/// a 4-sided patch.
pub(crate) struct BoundarySamples {
    /// Patch p's kept samples are `samples[start[p]..start[p + 1]]`, in ring order.
    pub samples: Vec<KeptSample>,
    pub start: Vec<usize>,
    /// Per boundary sample of every patch (n·r per patch, ring order, patch p's from `ring[p]`):
    /// its index in `samples`, or [`OWNED`] when it created its vertex.
    slot: Vec<u32>,
    ring: Vec<usize>,
    /// Per side count n: the first boundary sample of its layout.
    first: Vec<usize>,
}

/// What welding and measuring read of a kept boundary sample: the [`SurfacePoint`] without its
/// Jacobian (64 bytes instead of 72).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct KeptSample {
    pub position: DVec3,
    pub normal: DVec3,
    pub mean_curvature: f64,
    pub gaussian_curvature: f64,
}

impl From<&SurfacePoint> for KeptSample {
    fn from(sp: &SurfacePoint) -> Self {
        let (mean_curvature, gaussian_curvature) = (sp.mean_curvature, sp.gaussian_curvature);
        KeptSample { position: sp.position, normal: sp.normal, mean_curvature, gaussian_curvature }
    }
}

/// [`BoundarySamples::slot`] of a sample that created its vertex.
const OWNED: u32 = u32::MAX;

impl BoundarySamples {
    /// Room for the boundary samples (n·r per patch, r boundary steps per side) that did not
    /// create their vertex (`map.owner`), zeroed.
    pub fn new(surface: &Surface, layouts: &HashMap<usize, SampleLayout>, map: &WeldMap) -> Result<Self, TessellateError> {
        let np = surface.patches.len();
        let mut start = Vec::with_capacity(np + 1);
        let mut ring = Vec::with_capacity(np + 1);
        let mut slot = Vec::new();
        let mut nb = 0usize;
        for (p, patch) in surface.patches.iter().enumerate() {
            start.push(nb);
            ring.push(slot.len());
            let first = layouts[&patch.sides()].first_boundary();
            for &own in &map.owner[map.offsets[p] + first..map.offsets[p + 1]] {
                if own {
                    slot.push(OWNED);
                } else {
                    slot.push(nb as u32);
                    nb += 1;
                }
            }
            // Never reached below the memory limits (fewer kept samples than samples).
            if nb >= OWNED as usize {
                return Err(TessellateError::TooLarge { count: nb });
            }
        }
        start.push(nb);
        ring.push(slot.len());
        let mut first = vec![0usize; layouts.keys().max().map_or(0, |&n| n + 1)];
        for (&n, l) in layouts {
            first[n] = l.first_boundary();
        }
        Ok(BoundarySamples { samples: super::surface::zeroed(nb), start, slot, ring, first })
    }

    /// Sample `s` (a boundary sample of its layout) of patch `p` with `n` sides when it is kept,
    /// `None` when it created its vertex.
    #[inline]
    fn kept(&self, p: usize, n: usize, s: usize) -> Option<&KeptSample> {
        let k = self.slot[self.ring[p] + s - self.first[n]];
        (k != OWNED).then(|| &self.samples[k as usize])
    }
}

/// Patches per chunk of the parallel pass of [`join_shared_sides`].
const PATCH_CHUNK: usize = 4096;

/// Vertices per partial sum of the mean G1 deviation. The report's mean depends on it in its last
/// bits (the partial sums are added in order), so it is fixed and its own.
const G1_SUM_CHUNK: usize = 4096;

/// The most vertex ranges the kept corner samples are added over in parallel (each range scans
/// every corner of the surface).
const MAX_CORNER_PARTS: usize = 8;

/// True for a sample with a usable normal.
fn valid(sp: &KeptSample) -> bool {
    sp.normal != DVec3::ZERO && sp.normal.is_finite()
}

/// Adds a sample's normal and curvatures to a welded vertex and counts it (`k` is `None` when
/// the Gaussian curvatures are not kept, see [`super::surface::tessellate_checked`]).
fn add(sp: &KeptSample, n: &mut DVec3, h: &mut f64, k: Option<&mut f64>, w: &mut u16) {
    *n += sp.normal;
    if sp.mean_curvature.is_finite() && sp.gaussian_curvature.is_finite() {
        *h += sp.mean_curvature;
        if let Some(k) = k {
            *k += sp.gaussian_curvature;
        }
    }
    *w = w.saturating_add(1);
}

/// The larger gap, NaN as soon as one gap is NaN.
fn max_gap(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// Welds the non-owner samples into `mesh` and measures gaps along every shared side and G1
/// along every smooth one (creased sides, [`Surface::creases`], are welded and gap-measured but
/// only counted in `crease_sides`, so G1 stays a measure of the smooth joins),
/// each side pair once, from its smaller (patch, side), which also created the pair's inner
/// vertices. So the inner samples run in parallel per patch, writing only that patch's
/// vertices; the corners (nodes shared by any number of patches) follow serially in patch
/// order. `weight[v]` counts the patches that gave vertex v a normal; curvatures end up averaged
/// over them.
pub(crate) fn join_shared_sides(
    surface: &Surface,
    layouts: &HashMap<usize, SampleLayout>,
    map: &WeldMap,
    r: usize,
    boundary: &BoundarySamples,
    mesh: &mut SurfaceMesh,
    weight: &mut [u16],
) -> WeldStats {
    let np = surface.patches.len();
    let nv = map.vertex_count;
    // Side counts by patch, read far more often than once per patch (a patch's own struct is
    // much larger than its count, so reading them there misses the cache at every neighbour).
    let sides: Vec<u32> = surface.patches.iter().map(|p| p.sides() as u32).collect();
    let sides_of = |p: usize| sides[p] as usize;
    let kept = |p: usize, s: usize| boundary.kept(p, sides_of(p), s);
    let vertex = |p: usize, s: usize| map.ids[map.offsets[p] + s] as usize;
    // The layout of every side count by index (a hash lookup per corner cost more than the rest).
    let mut by_n: Vec<Option<&SampleLayout>> = vec![None; layouts.keys().max().map_or(0, |&n| n + 1)];
    for (&n, l) in layouts {
        by_n[n] = Some(l);
    }
    let layout_of = |p: usize| by_n[sides_of(p)].expect("a layout for every side count");
    let mut shared = vec![false; nv];
    let mut stats = WeldStats::default();
    {
        let vstart = &map.vstart;
        let positions = &mesh.positions;
        // Each patch's own vertices, cut off a chunk of patches at a time (a list of the pieces
        // of all patches would cost about 100 bytes per patch).
        use super::surface::take;
        let (mut nrm, mut h, mut k) = (&mut mesh.normals[..], &mut mesh.mean_curvature[..], &mut mesh.gaussian_curvature[..]);
        let (mut g1, mut sh, mut w) = (&mut mesh.g1_deviation_deg[..], &mut shared[..], &mut weight[..]);
        let mut done = 0;
        while done < np {
            let end = np.min(done + PATCH_CHUNK);
            let parts: Vec<_> = (done..end)
                .map(|p| {
                    let len = vstart[p + 1] - vstart[p];
                    (p, (((((take(&mut nrm, len), take(&mut h, len)), take(&mut k, len)), take(&mut g1, len)), take(&mut sh, len)), take(&mut w, len)))
                })
                .collect();
            let gap = parts
                .into_par_iter()
                .with_min_len(64)
                .map(|(p, (((((nrm, h), k), g1), sh), w))| {
                    let lp = layout_of(p);
                    let mut gap_max = 0.0;
                    for (i, nb) in surface.shared_sides_of(p) {
                        let lq = layout_of(nb.patch);
                        for t in 1..r {
                            // p's sample created the vertex (the smaller side emits the inner
                            // samples), the neighbour's is kept.
                            let sa = lp.boundary_index(i, t);
                            let Some(b) = kept(nb.patch, lq.boundary_index(nb.side, r - t)) else { continue };
                            let gv = vertex(p, sa);
                            let v = gv - vstart[p];
                            let (a_position, a_normal) = (positions[gv], nrm[v]);
                            if valid(b) {
                                add(b, &mut nrm[v], &mut h[v], k.get_mut(v), &mut w[v]);
                            }
                            gap_max = max_gap(gap_max, a_position.distance(b.position));
                            if surface.side_crease(p, i) == 0.0 {
                                g1[v] = g1[v].max(angle_deg(a_normal, b.normal));
                                sh[v] = true;
                            }
                        }
                    }
                    gap_max
                })
                .reduce(|| 0.0, max_gap);
            // The NaN-propagating maximum is associative: chunking changes nothing.
            stats.max_boundary_gap = max_gap(stats.max_boundary_gap, gap);
            done = end;
        }
    }
    // The corners (nodes of any number of patches): first measured, reading the samples that
    // created their vertex from the output arrays before any other sample is added there, then
    // the kept samples added in patch order.
    let (positions, normals) = (&mesh.positions, &mesh.normals);
    let corner = |p: usize, s: usize| match kept(p, s) {
        Some(sp) => (sp.position, sp.normal),
        None => (positions[vertex(p, s)], normals[vertex(p, s)]),
    };
    // Measured in parallel a chunk of patches at a time (the reads are scattered over the mesh:
    // serial, this was a third of the welding): each pair gives its gap and, on smooth sides,
    // its angle for its vertex; the angles are then applied serially. Neither result depends on
    // the order: the gap's NaN-propagating maximum is associative and commutative, and so is
    // the per-vertex `f64::max` of the angles (it skips NaN, and the vertex's value starts at 0).
    let mut done = 0;
    while done < np {
        let end = np.min(done + PATCH_CHUNK);
        let (gap, creased, found) = (done..end)
            .into_par_iter()
            .with_min_len(64)
            .fold(
                || (0.0, 0usize, Vec::<(u32, f64)>::new()),
                |(mut gap, mut creased, mut found), p| {
                    let lp = layout_of(p);
                    for (i, nb) in surface.shared_sides_of(p) {
                        let lq = layout_of(nb.patch);
                        let sharpness = surface.side_crease(p, i);
                        let smooth = sharpness == 0.0;
                        creased += usize::from(sharpness > 0.0);
                        for t in [0, r] {
                            let sa = lp.boundary_index(i, t);
                            let (a, b) = (corner(p, sa), corner(nb.patch, lq.boundary_index(nb.side, r - t)));
                            gap = max_gap(gap, a.0.distance(b.0));
                            if smooth {
                                found.push((vertex(p, sa) as u32, angle_deg(a.1, b.1)));
                            }
                        }
                    }
                    (gap, creased, found)
                },
            )
            .reduce(
                || (0.0, 0, Vec::new()),
                |(g, c, mut f), (g2, c2, f2)| {
                    f.extend(f2);
                    (max_gap(g, g2), c + c2, f)
                },
            );
        stats.max_boundary_gap = max_gap(stats.max_boundary_gap, gap);
        stats.crease_sides += creased;
        for (v, angle) in found {
            let v = v as usize;
            mesh.g1_deviation_deg[v] = mesh.g1_deviation_deg[v].max(angle);
            shared[v] = true;
        }
        done = end;
    }
    // The kept corner samples added in patch order (the sums' order fixes their last bits), in
    // parallel over ranges of vertices: every range scans all corners in patch order and adds
    // those of its own vertices, so each vertex gets its samples in the serial order. Every range
    // scans every corner, so their number is capped (MAX_CORNER_PARTS): more would repeat the
    // scan without a gain on a memory-bound pass.
    let parts = rayon::current_num_threads().min(MAX_CORNER_PARTS).clamp(1, np.max(1));
    let mut pieces = Vec::with_capacity(parts);
    {
        use super::surface::take;
        let (mut nrm, mut h, mut k, mut w) = (&mut mesh.normals[..], &mut mesh.mean_curvature[..], &mut mesh.gaussian_curvature[..], &mut weight[..]);
        let mut lo = 0;
        for j in 1..=parts {
            let hi = map.vstart[np * j / parts];
            let len = hi - lo;
            pieces.push((lo, take(&mut nrm, len), take(&mut h, len), take(&mut k, len), take(&mut w, len)));
            lo = hi;
        }
    }
    pieces.into_par_iter().for_each(|(lo, nrm, h, k, w)| {
        for p in 0..np {
            let lp = layout_of(p);
            for i in 0..lp.sides {
                let s = lp.boundary_index(i, 0);
                if let Some(sp) = kept(p, s).filter(|sp| valid(sp)) {
                    let Some(v) = vertex(p, s).checked_sub(lo).filter(|&v| v < nrm.len()) else { continue };
                    add(sp, &mut nrm[v], &mut h[v], k.get_mut(v), &mut w[v]);
                }
            }
        }
    });
    // (An empty array, the Gaussian curvatures when not kept, is left as it is.)
    for curvature in [&mut mesh.mean_curvature, &mut mesh.gaussian_curvature] {
        curvature.par_iter_mut().zip(weight.par_iter()).for_each(|(h, &w)| {
            if w > 1 {
                *h /= w as f64;
            }
        });
    }
    // Summed per fixed chunk, then the chunks in order: the same sum on every run (a rayon
    // `reduce` splits adaptively, and the float sum then varied in its last bits).
    let (count, sum, max) = shared
        .par_chunks(G1_SUM_CHUNK)
        .zip(mesh.g1_deviation_deg.par_chunks(G1_SUM_CHUNK))
        .map(|(s, g)| {
            let on_shared = s.iter().zip(g).filter(|(&s, _)| s);
            on_shared.fold((0usize, 0.0, 0.0f64), |a, (_, &g)| (a.0 + 1, a.1 + g, a.2.max(g)))
        })
        .collect::<Vec<_>>()
        .into_iter()
        .fold((0, 0.0, 0.0f64), |a, b| (a.0 + b.0, a.1 + b.1, a.2.max(b.2)));
    stats.shared_vertices = count;
    stats.max_g1_deg = max;
    if count > 0 {
        stats.mean_g1_deg = sum / count as f64;
    }
    stats
}

/// Normalizes the normals; vertices without any analytic normal (`weight` 0) take the
/// area-weighted normal of their triangles.
pub(crate) fn finish_normals(mesh: &mut SurfaceMesh, weight: &[u16]) {
    let missing: Vec<usize> = (0..mesh.positions.len()).into_par_iter().filter(|&v| weight[v] == 0).collect();
    if !missing.is_empty() {
        let fallback = crate::mesh::geometry::vertex_normals(&mesh.positions, &mesh.triangles);
        for v in missing {
            mesh.normals[v] = fallback[v];
        }
    }
    mesh.normals.par_iter_mut().for_each(|n| *n = n.normalize_or_zero());
}
