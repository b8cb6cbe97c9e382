//! Certificates that regions of the output are free of self-intersections, so that
//! [`super::validity::self_intersections_certified`] can skip their triangle pairs and still
//! count exactly.
//!
//! # The certificate
//!
//! Let R be a set of output triangles, a a unit vector and f the orthogonal projection onto the
//! plane ⊥ a. Suppose
//! 1. every triangle of R has a geometric normal n with n·a > 0 (output triangles are
//!    counter-clockwise), and
//! 2. the boundary of R — the directed edges of R's triangles whose reverse is not an edge of R
//!    (as a chain: an edge and its reverse cancel) — is ONE closed loop b_0 → b_1 → … → b_0
//!    without a repeated vertex which, projected by f, is strictly star-shaped around the
//!    projection of a vertex q of R not on the loop: every edge turns positively around f(q),
//!    cross(f(b_i) − f(q), f(b_{i+1}) − f(q)) > 0, and the turning angles sum to 2π (winding
//!    number exactly 1).
//!
//! Then f is injective on R, so no two triangles of R that share no vertex meet.
//!
//! Proof. By (1) f is orientation-preserving on every triangle. For a point y off the images of
//! all edges, the number of triangles of R whose image contains y equals the winding number of
//! f(∂R) around y (each triangle contributes the winding number of its own boundary, +1 inside
//! its image and 0 outside, and the sum of the triangles' boundaries is the chain ∂R); as f(∂R)
//! is a simple loop star-shaped around f(q), that number is 1 inside the loop and 0 outside. So
//! every point of R has local degree ≥ 1 where R surrounds it (1 inside triangles and across
//! edges of R, a positive integer at vertices): a point x of R off the boundary loop with
//! f(x) on or outside the loop would cover points just outside it, where the count is 0, so
//! every such x maps strictly inside the loop, and the count 1 there allows at most one
//! preimage; points on the boundary loop map one to one onto the simple loop f(∂R). Hence every
//! y has at most one preimage. Two triangles sharing no vertex index are disjoint pieces of R,
//! so their images are disjoint, and so are they. ∎
//!
//! Floating point: anything uncertain means "not certified", and those pairs go through the
//! exact test as before. Condition (1) is checked per patch on a normal cone (the axis and the
//! largest angle between it and a triangle's unit normal) with a margin of [`CONE_MARGIN`]
//! radians, far above the rounding of unit normals of triangles that are not slivers (a
//! triangle with |e1 × e2| ≤ [`SLIVER`]·|e1||e2| makes its patch uncertifiable; the cone's
//! cosine is the square root of the smallest signed square d·|d|/|n|², d = n·axis, which orders
//! like the cosine d/|n|, rounding a few ulps from it); condition (2)
//! asks cross > [`TURN_MARGIN`]·|f(b_i) − f(q)||f(b_{i+1}) − f(q)|, far above the rounding of
//! the projection (so every turning angle is in (0, π), also for the exact points), and the
//! winding number 1: with positive turns the angles sum to 2πk, k the number of upward
//! crossings of the line through f(q) (half-open, so a vertex on the line counts once).
//! A degenerate triangle, a repeated vertex on the loop, several loops or an edge left twice
//! are refusals.
//!
//! # Regions
//!
//! Stars of nodes: for every node (a corner vertex of a patch, where patches meet), R is all
//! triangles of the patches having that node as a corner, q the node, a the normalised sum of
//! the patches' cone axes. (1) holds when angle(a, axis_p) + half-angle_p < 90° − margin for
//! every patch p of the star; the boundary comes from the patches' boundary loops
//! ([`PatchLoops`], made by the tessellation): their directed edges, those appearing reversed in
//! another patch of the star cancelled. Every pair of patches sharing a vertex or a side lies in
//! one star, so on smooth closed surfaces all neighbouring pairs are certified.
//!
//! Cores (quad layout): a star of many patches that is not certified — around a node of high
//! valence whose patches turn by more than 90° further out, like the sliver patches around the
//! cap of a prism of 1000 sides — is tried with R the sectors at q of its patches only (the
//! quads of each patch's sector around corner q), q the node, a the normalised sum of R's
//! triangle normals. Pairs of triangles of one certified core are skipped; the search then
//! keeps chunks within one sector for the patches of a core.
//!
//! Single patches: a patch in no certified star (around a node of high valence, or a patch of
//! many sides) is tried alone, R its triangles, q its interior vertex nearest the middle of its
//! projected loop, a its cone axis. A planar 1000-gon or a cone's cap of 1000 sides then skips
//! its ~10⁶ pairs of overlapping sliver boxes around the centre.

use crate::progress::{Cancelled, Ticker};
use crate::tessellate::{PatchLoops, SurfaceMesh};
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// Margin (radians) of the normal-cone test of condition (1).
pub const CONE_MARGIN: f64 = 1e-3;
/// Relative margin of the star-shaped test of condition (2).
pub const TURN_MARGIN: f64 = 1e-9;
/// Triangles with |e1 × e2| at most this times |e1||e2| are slivers: their unit normal is not
/// trusted.
pub const SLIVER: f64 = 1e-6;

/// Regions of an output mesh proven free of self-intersections: per patch the certified stars
/// containing it. Pass [`Certified::none`] (or call [`super::self_intersections`]) to test every
/// pair.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Certified {
    /// The triangles of patch p are `tri_start[p]..tri_start[p + 1]`.
    tri_start: Vec<usize>,
    /// The certified stars containing patch p are `stars[star_start[p]..star_start[p + 1]]`,
    /// ascending.
    star_start: Vec<usize>,
    stars: Vec<u32>,
    /// Certified cores of node stars (see the module doc, "Cores"): (patch, sector, region),
    /// ascending; empty when none.
    cores: Vec<(u32, u32, u32)>,
    /// Per triangle its sector (the patch corner of its output face), when `cores` is not empty.
    sector: Vec<u32>,
}

/// |n|² of a triangle's normal n = e1 × e2, or `None` for a sliver (|n| ≤ SLIVER·|e1||e2|), a
/// value that is not finite, or one so small that |n|²·SLIVER² is not a normal f64 (edges below
/// about 1e-74: the divisions of [`normal_cone`] would lose their precision in the subnormal
/// range, and a cone computed from them could come out too narrow).
fn normal_len2(e1: DVec3, e2: DVec3, n: DVec3) -> Option<f64> {
    let len2 = n.length_squared();
    (len2.is_finite() && len2 * (SLIVER * SLIVER) >= f64::MIN_POSITIVE && len2 > SLIVER * SLIVER * e1.length_squared() * e2.length_squared())
        .then_some(len2)
}

/// Normal cone of a patch: unit axis and the cosine of the largest angle between the axis and a
/// triangle's unit normal; `None` when a triangle is degenerate, a sliver or not finite.
fn normal_cone(positions: &[DVec3], triangles: &[[u32; 3]]) -> Option<(DVec3, f64)> {
    // The unit normal of a triangle, None for a sliver. Any axis gives a valid cone (cos is the
    // smallest dot product over all triangles): it is the mean of about 16 spread triangles'
    // normals, then one pass over all of them, without allocating.
    // A triangle's normal n and |n|², None for a sliver.
    let normal = |t: &[u32; 3]| -> Option<(DVec3, f64)> {
        let [a, b, c] = t.map(|i| positions.get(i as usize).copied().unwrap_or(DVec3::NAN));
        let (e1, e2) = (b - a, c - a);
        let n = e1.cross(e2);
        normal_len2(e1, e2, n).map(|len2| (n, len2))
    };
    let unit = |t: &[u32; 3]| normal(t).map(|(n, len2)| n / len2.sqrt());
    let mut sum = DVec3::ZERO;
    for t in triangles.iter().step_by((triangles.len() / 16).max(1)) {
        sum += unit(t)?;
    }
    let axis = sum.normalize_or_zero();
    if axis == DVec3::ZERO {
        return None;
    }
    // The smallest cosine through the smallest signed square c·|c| = d·|d|/|n|² (d = n·axis,
    // c·|c| increases with c): one division per triangle, one square root at the end.
    let mut low = 1.0f64;
    for t in triangles {
        let (n, len2) = normal(t)?;
        let d = n.dot(axis);
        low = low.min(d * d.abs() / len2);
    }
    Some((axis, low.signum() * low.abs().sqrt().min(1.0)))
}

/// The chain of directed `edges` with every edge cancelled against a reverse, chained into one
/// loop of distinct vertices; `None` if that is not one simple loop.
fn single_loop(mut edges: Vec<(u32, u32)>) -> Option<Vec<u32>> {
    edges.sort_unstable_by_key(|&(a, b)| (a.min(b), a.max(b)));
    let mut rest: Vec<(u32, u32)> = Vec::new();
    let mut k = 0;
    while k < edges.len() {
        let key = (edges[k].0.min(edges[k].1), edges[k].0.max(edges[k].1));
        if key.0 == key.1 {
            return None;
        }
        let mut net = 0i64;
        while k < edges.len() && (edges[k].0.min(edges[k].1), edges[k].0.max(edges[k].1)) == key {
            net += if edges[k].0 < edges[k].1 { 1 } else { -1 };
            k += 1;
        }
        match net {
            0 => {}
            1 => rest.push(key),
            -1 => rest.push((key.1, key.0)),
            _ => return None,
        }
    }
    if rest.len() < 3 {
        return None;
    }
    rest.sort_unstable();
    if rest.windows(2).any(|w| w[0].0 == w[1].0) {
        return None;
    }
    let mut out = Vec::with_capacity(rest.len());
    let first = rest[0].0;
    let mut at = first;
    for _ in 0..rest.len() {
        let i = rest.binary_search_by_key(&at, |e| e.0).ok()?;
        out.push(at);
        at = rest[i].1;
        if at == first {
            break;
        }
    }
    (at == first && out.len() == rest.len()).then_some(out)
}

/// Condition (2): `lp` projected along `a` is strictly star-shaped around q with winding number 1.
fn star_shaped(positions: &[DVec3], lp: &[u32], q: u32, a: DVec3) -> bool {
    if lp.contains(&q) {
        return false;
    }
    let Some(&pq) = positions.get(q as usize) else { return false };
    let (e1, e2) = a.any_orthonormal_pair();
    let proj = |v: u32| positions.get(v as usize).map(|&p| {
        let d = p - pq;
        DVec2::new(d.dot(e1), d.dot(e2))
    });
    // With every turn in (0, π) the loop winds k ≥ 1 times, k = its upward crossings of the
    // line through f(q) (all on the positive side, half-open so a vertex on it counts once).
    // Each loop vertex is projected (and its length taken) once, carried to the next edge.
    let mut crossings = 0usize;
    let Some(&last) = lp.last() else { return false };
    let Some(mut u) = proj(last) else { return false };
    let mut lu = u.length();
    for &w in lp {
        let Some(v) = proj(w) else { return false };
        let lv = v.length();
        let cross = u.perp_dot(v);
        if !(cross > TURN_MARGIN * lu * lv) {
            return false;
        }
        crossings += (u.y < 0.0 && v.y >= 0.0) as usize;
        (u, lu) = (v, lv);
    }
    crossings == 1
}

/// Checks the certificate (see the module doc) for the region made of `triangles` (indices into
/// `positions`) around vertex `q`, with a the normalised sum of the triangles' unit normals:
/// true when proven free of self-intersections. For tests and for regions other than stars.
pub fn certify_region(positions: &[DVec3], triangles: &[[u32; 3]], q: u32) -> bool {
    let Some((axis, cos)) = normal_cone(positions, triangles) else { return false };
    if !(cos.clamp(-1.0, 1.0).acos() < std::f64::consts::FRAC_PI_2 - CONE_MARGIN) {
        return false;
    }
    let edges = triangles.iter().flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]).collect();
    single_loop(edges).is_some_and(|lp| star_shaped(positions, &lp, q, axis))
}

/// The star of node q made of `patches` (with their cones): conditions (1) and (2).
/// `walk` is a buffer reused between stars.
fn certify_star(positions: &[DVec3], loops: &PatchLoops, cones: &[Option<(DVec3, f64)>], q: u32, patches: &[u32], walk: &mut Vec<u32>) -> bool {
    let cone = |p: &u32| cones.get(*p as usize).copied().flatten();
    let mut a = DVec3::ZERO;
    for p in patches {
        match cone(p) {
            Some(c) => a += c.0,
            None => return false,
        }
    }
    let a = a.normalize_or_zero();
    if a == DVec3::ZERO {
        return false;
    }
    let limit = std::f64::consts::FRAC_PI_2 - CONE_MARGIN;
    if !patches.iter().filter_map(cone).all(|(axis, cos)| a.dot(axis).clamp(-1.0, 1.0).acos() + cos.clamp(-1.0, 1.0).acos() < limit) {
        return false;
    }
    if star_loop(loops, q, patches, walk) {
        return star_shaped(positions, walk, q, a);
    }
    single_loop(star_edges(loops, patches)).is_some_and(|lp| star_shaped(positions, &lp, q, a))
}

/// The directed edges of the loops of `patches`.
fn star_edges(loops: &PatchLoops, patches: &[u32]) -> Vec<(u32, u32)> {
    let mut edges = Vec::new();
    for &p in patches {
        let lp = loops.of(p as usize);
        edges.extend((0..lp.len()).map(|k| (lp[k], lp[(k + 1) % lp.len()])));
    }
    edges
}

/// The boundary loop of the star of node `q` made of `patches`, in the common case, without
/// sorting (the stars of a smooth surface are almost all of this kind): into `walk`, true when
/// found; false sends the star to [`single_loop`], which decides every case.
///
/// Every loop has q at exactly one corner, no edge from a vertex to itself and at least three
/// sides; leaving q, patch p runs along its out-side (q to its next corner), its outer part, and
/// back along its in-side (its last corner to q). Starting from the first patch, the next one is
/// a patch whose out-side is the current in-side reversed, until the walk returns to the first
/// patch having used each once, and the outer parts concatenated have distinct vertices (at
/// least three). Then the in-sides and out-sides cancel in pairs in the chain of all loops'
/// edges, so the chain is the walk, a simple loop: exactly the loop [`single_loop`] returns (up
/// to the starting vertex, which [`star_shaped`] does not depend on).
fn star_loop(loops: &PatchLoops, q: u32, patches: &[u32], walk: &mut Vec<u32>) -> bool {
    let m = loops.per_side;
    walk.clear();
    if m == 0 || patches.is_empty() || patches.len() > 64 {
        return false;
    }
    // Per patch: its loop and the position of q in it.
    let mut at = [(&[][..], 0usize); 64];
    for (slot, &p) in at.iter_mut().zip(patches) {
        let lp = loops.of(p as usize);
        let len = lp.len();
        if len % m != 0 || len <= 2 * m || lp.windows(2).any(|w| w[0] == w[1]) || lp[0] == lp[len - 1] {
            return false;
        }
        let mut corner = lp.iter().enumerate().step_by(m).filter(|x| *x.1 == q).map(|x| x.0);
        let (Some(k), None) = (corner.next(), corner.next()) else { return false };
        *slot = (lp, k);
    }
    let at = &at[..patches.len()];
    // Entry j (0 ≤ j ≤ len) after q's position k, without a division.
    let vertex = |(lp, k): (&[u32], usize), j: usize| {
        let i = k + j;
        lp[if i >= lp.len() { i - lp.len() } else { i }]
    };
    let mut used = 0u64;
    let mut cur = 0;
    for _ in 0..patches.len() {
        used |= 1 << cur;
        let (lp, k) = at[cur];
        let len = lp.len();
        walk.extend((m..len - m).map(|j| vertex((lp, k), j)));
        // The patch whose out-side (q, …, its first corner) is this in-side reversed.
        let next = (0..patches.len()).find(|&o| (0..=m).all(|j| vertex(at[o], j) == vertex((lp, k), len - j)));
        match next {
            Some(0) if used.count_ones() as usize == patches.len() => {
                cur = 0;
                break;
            }
            Some(o) if used & (1 << o) == 0 => cur = o,
            _ => return false,
        }
    }
    if cur != 0 || used.count_ones() as usize != patches.len() || walk.len() < 3 {
        walk.clear();
        return false;
    }
    // Distinct vertices: sorted on the stack for the common small walk.
    let distinct = |sorted: &mut [u32]| {
        sorted.sort_unstable();
        sorted.windows(2).all(|w| w[0] != w[1])
    };
    let ok = if walk.len() <= 256 {
        let mut buf = [0u32; 256];
        buf[..walk.len()].copy_from_slice(walk);
        distinct(&mut buf[..walk.len()])
    } else {
        distinct(&mut walk.clone())
    };
    if !ok {
        walk.clear();
    }
    ok
}

/// A patch alone as a region (see the module doc, "Regions"): conditions (1) and (2) for its
/// triangles, with q its interior vertex nearest the middle of its projected boundary loop
/// (the domain centre's sample in both layouts).
fn certify_patch(positions: &[DVec3], triangles: &[[u32; 3]], lp: &[u32], cone: Option<(DVec3, f64)>) -> bool {
    let Some((axis, cos)) = cone else { return false };
    if !(cos.clamp(-1.0, 1.0).acos() < std::f64::consts::FRAC_PI_2 - CONE_MARGIN) || lp.is_empty() {
        return false;
    }
    let mut on_loop = lp.to_vec();
    on_loop.sort_unstable();
    let middle = lp.iter().filter_map(|&v| positions.get(v as usize)).sum::<DVec3>() / lp.len() as f64;
    let flat = |p: DVec3| {
        let d = p - middle;
        d - axis * d.dot(axis)
    };
    let q = triangles
        .iter()
        .flatten()
        .filter(|&&v| on_loop.binary_search(&v).is_err())
        .filter_map(|&v| positions.get(v as usize).map(|&p| (flat(p).length_squared(), v)))
        .min_by(|a, b| a.0.total_cmp(&b.0));
    q.is_some_and(|(_, q)| certify_region(positions, triangles, q))
}

/// Stars of more patches than this that are not certified get their cores tried (a core
/// avoids the quadratic number of overlapping sliver pairs around a node of high valence; for
/// small stars it would cost more than it saves).
pub const CORE_MIN_PATCHES: usize = 8;

/// The nodes of a tessellation ([`node_groups`]).
type Nodes = (Vec<(u32, u32)>, Vec<(usize, usize)>);

/// The nodes of `loops`: (corner vertex, patch) pairs sorted by vertex, and the range of each
/// vertex's pairs (its star).
fn node_groups(loops: &PatchLoops) -> Nodes {
    let mut corners: Vec<(u32, u32)> = (0..loops.len()).flat_map(|p| loops.corners(p).map(move |v| (v, p as u32))).collect();
    corners.par_sort_unstable();
    corners.dedup();
    let mut groups: Vec<(usize, usize)> = Vec::new();
    let mut k = 0;
    while k < corners.len() {
        let s = k;
        while k < corners.len() && corners[k].0 == corners[s].0 {
            k += 1;
        }
        groups.push((s, k));
    }
    (corners, groups)
}

/// Stars certified per progress tick.
const STARS_PER_TICK: usize = 2048;

impl Certified {
    /// No certified region: every pair is tested.
    pub fn none() -> Certified {
        Certified::default()
    }

    /// The certified stars of the nodes of a tessellation (see the module doc); none for a mesh
    /// without patch loops (subdivision methods) or whose loops do not match its triangles.
    pub fn of_mesh(mesh: &SurfaceMesh) -> Certified {
        Certified::of_mesh_ticked(mesh, &mut Ticker::none()).unwrap_or_else(|_| Certified::none())
    }

    /// The certified stars of the nodes of `loops` over the mesh (`positions`, `triangles`).
    pub fn of_patches(positions: &[DVec3], triangles: &[[u32; 3]], loops: &PatchLoops) -> Certified {
        Certified::of_patches_ticked(positions, triangles, loops, &mut Ticker::none()).unwrap_or_else(|_| Certified::none())
    }

    /// [`Certified::of_mesh`] reporting progress to `ticker` (see [`crate::progress`]). In the
    /// quad layout, the stars of more than [`CORE_MIN_PATCHES`] patches that are not certified
    /// get their cores tried (see the module doc).
    pub fn of_mesh_ticked(mesh: &SurfaceMesh, ticker: &mut Ticker<'_>) -> Result<Certified, Cancelled> {
        let (mut c, nodes) = Certified::of_patches_nodes(&mesh.positions, &mesh.triangles, &mesh.patch_loops, ticker)?;
        if !mesh.quads.is_empty() && mesh.face_corner.len() == mesh.quads.len() && 2 * mesh.quads.len() == mesh.triangles.len() {
            let sector = || (0..mesh.triangles.len()).map(|t| mesh.face_corner[t / 2]).collect();
            c.add_cores(&mesh.positions, &mesh.triangles, nodes, sector);
        }
        Ok(c)
    }

    /// Tries the cores of the uncertified stars of more than [`CORE_MIN_PATCHES`] patches
    /// (`nodes`: those of [`node_groups`]; `sector()[t]`: the patch corner whose sector holds
    /// triangle t, made only when some star is that large).
    fn add_cores(&mut self, positions: &[DVec3], triangles: &[[u32; 3]], nodes: Nodes, sector: impl FnOnce() -> Vec<u32>) {
        let np = self.patches();
        // Nodes with their patches, as in the stars.
        let (corners, mut groups) = nodes;
        groups.retain(|&(s, e)| e - s > CORE_MIN_PATCHES);
        if np == 0 || groups.is_empty() {
            return;
        }
        let sector = sector();
        if sector.len() != triangles.len() {
            return;
        }
        let tri_start = &self.tri_start;
        let found: Vec<Vec<(u32, u32)>> = groups
            .par_iter()
            .filter_map(|&(s, e)| {
                let q = corners[s].0;
                let ps: Vec<u32> = corners[s..e].iter().map(|c| c.1).collect();
                // Skip stars already certified (all their pairs are skipped anyway).
                let shared = ps.iter().skip(1).fold(self.stars_of(ps[0] as usize).to_vec(), |mut acc, &p| {
                    let st = self.stars_of(p as usize);
                    acc.retain(|x| st.binary_search(x).is_ok());
                    acc
                });
                if !shared.is_empty() {
                    return None;
                }
                // The sector of each patch at q: that of a triangle of it with vertex q.
                let mut members = Vec::with_capacity(ps.len());
                let mut region: Vec<[u32; 3]> = Vec::new();
                for &p in &ps {
                    let range = tri_start[p as usize]..tri_start[p as usize + 1];
                    let i = range.clone().find(|&t| triangles[t].contains(&q)).map(|t| sector[t])?;
                    region.extend(range.filter(|&t| sector[t] == i).map(|t| triangles[t]));
                    members.push((p, i));
                }
                certify_region(positions, &region, q).then_some(members)
            })
            .collect();
        let first = (self.stars.iter().copied().max().map_or(0, |m| m + 1)).max((np + corners.len()) as u32);
        let mut cores: Vec<(u32, u32, u32)> = Vec::new();
        for (r, members) in found.into_iter().enumerate() {
            cores.extend(members.into_iter().map(|(p, i)| (p, i, first + r as u32)));
        }
        cores.sort_unstable();
        if !cores.is_empty() {
            self.cores = cores;
            self.sector = sector;
        }
    }

    /// Number of (patch, sector) pieces lying in a certified core.
    pub fn certified_core_sectors(&self) -> usize {
        self.cores.len()
    }

    /// Patch `p` has sectors in a certified core (its chunks must not span two sectors).
    pub(crate) fn has_cores(&self, p: usize) -> bool {
        let i = self.cores.partition_point(|c| (c.0 as usize) < p);
        self.cores.get(i).is_some_and(|c| c.0 as usize == p)
    }

    /// The sector of triangle t (when cores exist).
    pub(crate) fn sector_of(&self, t: usize) -> Option<u32> {
        self.sector.get(t).copied()
    }

    /// [`Certified::of_patches`] reporting progress to `ticker` (per chunk of stars).
    pub fn of_patches_ticked(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        loops: &PatchLoops,
        ticker: &mut Ticker<'_>,
    ) -> Result<Certified, Cancelled> {
        Certified::of_patches_nodes(positions, triangles, loops, ticker).map(|c| c.0)
    }

    /// [`Certified::of_patches_ticked`] with the nodes it grouped (empty when the loops do not
    /// match the triangles), for [`Certified::add_cores`].
    fn of_patches_nodes(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        loops: &PatchLoops,
        ticker: &mut Ticker<'_>,
    ) -> Result<(Certified, Nodes), Cancelled> {
        let np = loops.len();
        let consistent = np > 0
            && loops.triangles.len() == np + 1
            && loops.triangles[np] == triangles.len()
            && loops.triangles.windows(2).all(|w| w[0] <= w[1])
            && loops.ids.iter().all(|&v| (v as usize) < positions.len());
        if !consistent {
            return Ok((Certified::none(), Nodes::default()));
        }
        let cones: Vec<Option<(DVec3, f64)>> = (0..np)
            .into_par_iter()
            .map(|p| normal_cone(positions, &triangles[loops.triangles[p]..loops.triangles[p + 1]]))
            .collect();
        let (corners, groups) = node_groups(loops);
        ticker.at(1, 10)?;
        let mut certified: Vec<bool> = Vec::with_capacity(groups.len());
        let per_tick = crate::progress::chunk_size(groups.len(), STARS_PER_TICK);
        for part in groups.chunks(per_tick) {
            certified.par_extend(part.par_iter().map_init(|| (Vec::new(), Vec::new()), |(ps, walk), &(s, e)| {
                ps.clear();
                ps.extend(corners[s..e].iter().map(|c| c.1));
                certify_star(positions, loops, &cones, corners[s].0, ps, walk)
            }));
            ticker.at_part(0.1, 1.0, certified.len(), groups.len())?;
        }
        let mut member: Vec<(u32, u32)> = Vec::new();
        for (g, &(s, e)) in groups.iter().enumerate() {
            if certified[g] {
                member.extend(corners[s..e].iter().map(|c| (c.1, g as u32)));
            }
        }
        // Patches in no certified star (around a node of high valence, or a patch of many
        // sides whose stars span more than a half-space): the patch alone as a region, with id
        // groups + p. Its interior pairs are then skipped too (a 1000-sided patch has ~10⁶
        // overlapping boxes around its centre).
        let mut in_star = vec![false; np];
        for m in &member {
            in_star[m.0 as usize] = true;
        }
        let lonely: Vec<usize> = (0..np).filter(|&p| !in_star[p] && loops.triangles[p + 1] > loops.triangles[p]).collect();
        let alone: Vec<bool> = lonely
            .par_iter()
            .map(|&p| {
                let tris = &triangles[loops.triangles[p]..loops.triangles[p + 1]];
                certify_patch(positions, tris, loops.of(p), cones[p])
            })
            .collect();
        member.extend(lonely.iter().zip(&alone).filter(|x| *x.1).map(|(&p, _)| (p as u32, (groups.len() + p) as u32)));
        ticker.at(1, 1)?;
        member.par_sort_unstable();
        let mut star_start = Vec::with_capacity(np + 1);
        let mut k = 0;
        for p in 0..np as u32 {
            star_start.push(k);
            while k < member.len() && member[k].0 == p {
                k += 1;
            }
        }
        star_start.push(member.len());
        let c = Certified { tri_start: loops.triangles.clone(), star_start, stars: member.into_iter().map(|m| m.1).collect(), cores: Vec::new(), sector: Vec::new() };
        Ok((c, (corners, groups)))
    }

    /// Number of patches lying in at least one certified star.
    pub fn certified_patches(&self) -> usize {
        self.star_start.windows(2).filter(|w| w[1] > w[0]).count()
    }

    /// Number of patches.
    pub fn patches(&self) -> usize {
        self.star_start.len().saturating_sub(1)
    }

    /// The certified stars containing patch p (ascending).
    fn stars_of(&self, p: usize) -> &[u32] {
        self.star_start.get(p..p + 2).map_or(&[], |w| &self.stars[w[0]..w[1]])
    }

    /// The triangles of patch p are `tri_start()[p]..tri_start()[p + 1]`.
    pub(crate) fn tri_start(&self) -> &[usize] {
        &self.tri_start
    }

    /// The patch of triangle t, if the certificate covers it.
    pub(crate) fn patch_of(&self, t: usize) -> Option<usize> {
        crate::tessellate::surface::range_of(&self.tri_start, t)
    }

    /// The certified regions containing every triangle of `first..=last` (triangle indices of
    /// the mesh, ascending range; the patches' triangles are consecutive): the stars of its
    /// patch and the core of its sector when every triangle lies in that one sector, for a
    /// range inside one patch; none for any other range (its pairs are then all searched).
    pub(crate) fn chunk_regions(&self, first: usize, last: usize) -> ChunkRegions {
        let none = ChunkRegions { patch: u32::MAX, core: u32::MAX };
        let (Some(p0), Some(p1)) = (self.patch_of(first), self.patch_of(last)) else { return none };
        if p0 != p1 {
            return none;
        }
        let mut core = u32::MAX;
        if !self.cores.is_empty() {
            let (a, b) = (self.sector_of(first), self.sector_of(last));
            if a == b && (first..=last).all(|t| self.sector_of(t) == a) {
                if let Some(i) = a {
                    let k = self.cores.partition_point(|c| (c.0 as usize, c.1) < (p0, i));
                    if let Some(c) = self.cores.get(k).filter(|c| c.0 as usize == p0 && c.1 == i) {
                        core = c.2;
                    }
                }
            }
        }
        ChunkRegions { patch: p0 as u32, core }
    }

    /// Some certified region contains both chunks (the same chunk: some region contains it).
    /// Star ids and core ids are disjoint (cores are numbered above every star), so this is
    /// [`share`] of the two chunks' lists of regions (stars, then the core).
    pub(crate) fn share_region(&self, a: ChunkRegions, b: ChunkRegions) -> bool {
        let stars = |r: ChunkRegions| if r.patch == u32::MAX { &[][..] } else { self.stars_of(r.patch as usize) };
        (a.core != u32::MAX && a.core == b.core) || share(stars(a), stars(b))
    }
}

/// The certified regions of a chunk of triangles ([`Certified::chunk_regions`]): its patch
/// (whose stars contain it) and the core of its sector; `u32::MAX` for none.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ChunkRegions {
    patch: u32,
    core: u32,
}

/// Two ascending lists share an element.
pub(crate) fn share(a: &[u32], b: &[u32]) -> bool {
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => return true,
        }
    }
    false
}

/// Relative margin of the orientation test of [`star_shaped_shells`]: (a − o)·((b − a) × (c − a))
/// must exceed this times |a − o|·|b − a|·|c − a|, far above its rounding (a few ulps of that
/// product), so the exact orientation is positive too.
pub const SHELL_MARGIN: f64 = 1e-9;

/// Shells proven free of self-intersections by central projection. Per triangle: true when its
/// shell (`shell[t]`, any id below `positions.len()`) is certified.
///
/// # The certificate
///
/// Let S be a shell whose triangles form a closed surface (every undirected edge used exactly
/// twice, once in each direction), o the mean of its triangles' vertices, and suppose
/// 1. every triangle (a, b, c) of S is positively oriented seen from o:
///    (a − o)·((b − a) × (c − a)) > 0 (with the margin [`SHELL_MARGIN`]);
/// 2. the signed solid angles Ω_t of its triangles from o (Van Oosterom–Strackee:
///    tan(Ω/2) = det(A, B, C) / (|A||B||C| + (A·B)|C| + (A·C)|B| + (B·C)|A|), A = a − o, …) sum to
///    4π within 1 (the sum is 4π·k for an integer k, the degree of the central projection
///    x ↦ (x − o)/|x − o| onto the unit sphere).
///
/// Then no two triangles of S that share no vertex meet. Proof: the central projection is a
/// continuous map from the closed oriented surface S to the sphere, orientation-preserving on every
/// triangle (1), so every direction off the images of the edges has exactly k = 1 preimages (2).
/// If two triangles met at a point x, every direction near that of x would have a preimage near x
/// in each of them (a triangle, or a triangle and the one across its edge or around its vertex,
/// covers a neighbourhood of the direction of each of its points, because every triangle around
/// it is positively oriented), that is two preimages: a contradiction. ∎
///
/// Star-shaped closed surfaces pass: spheres, cubes, cones, prisms, most single convex parts;
/// their self-intersection search then costs O(triangles). A shell failing either test goes
/// through the search as before. Cost: one pass, plus a sort of the edges of the shells passing
/// the orientation test.
pub fn star_shaped_shells(positions: &[DVec3], triangles: &[[u32; 3]], shell: &[u32]) -> Vec<bool> {
    star_shaped_shells_ticked(positions, triangles, shell, false, &mut Ticker::none()).unwrap_or_else(|_| vec![false; triangles.len()])
}

/// Triangles per progress tick of [`star_shaped_shells_ticked`].
const SHELL_TRIANGLES_PER_TICK: usize = 1 << 16;

/// [`star_shaped_shells`] reporting progress to `ticker` (per chunk of triangles). With
/// `closed` the caller has checked that the whole mesh is a closed two-manifold (every edge in
/// two triangles, in opposite directions), and the edge sort is skipped.
pub fn star_shaped_shells_ticked(positions: &[DVec3], triangles: &[[u32; 3]], shell: &[u32], closed: bool, ticker: &mut Ticker<'_>) -> Result<Vec<bool>, Cancelled> {
    let nv = positions.len();
    if shell.len() != triangles.len() || triangles.iter().flatten().any(|&v| v as usize >= nv) || shell.iter().any(|&s| s as usize >= nv) {
        return Ok(vec![false; triangles.len()]);
    }
    // Centres: the mean of each shell's triangle vertices.
    let mut sum = vec![DVec3::ZERO; nv];
    let mut count = vec![0u64; nv];
    for (t, &s) in triangles.iter().zip(shell) {
        sum[s as usize] += positions[t[0] as usize] + positions[t[1] as usize] + positions[t[2] as usize];
        count[s as usize] += 3;
    }
    let centre: Vec<DVec3> = sum.iter().zip(&count).map(|(&x, &k)| if k > 0 { x / k as f64 } else { DVec3::ZERO }).collect();
    // Orientation and solid angle per triangle, in parallel, in chunks (a tick each).
    let per_tick = crate::progress::chunk_size(triangles.len(), SHELL_TRIANGLES_PER_TICK);
    let mut per: Vec<Option<f64>> = Vec::with_capacity(triangles.len());
    for (k, (part, sh)) in triangles.chunks(per_tick).zip(shell.chunks(per_tick)).enumerate() {
    per.par_extend(part
        .par_iter()
        .zip(sh.par_iter())
        .with_min_len(1 << 12)
        .map(|(t, &s)| {
            let o = centre[s as usize];
            let [a, b, c] = t.map(|v| positions[v as usize] - o);
            let det = a.dot((b - a).cross(c - a));
            let scale = a.length() * (b - a).length() * (c - a).length();
            if !(det > SHELL_MARGIN * scale) || !scale.is_finite() {
                return None;
            }
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
            Some(2.0 * det.atan2(den))
        }));
        ticker.at_part(0.0, if closed { 1.0 } else { 0.7 }, (k + 1) * per_tick, triangles.len())?;
    }
    let mut ok = vec![true; nv];
    let mut total = vec![0.0f64; nv];
    for (&s, w) in shell.iter().zip(&per) {
        match w {
            Some(w) => total[s as usize] += w,
            None => ok[s as usize] = false,
        }
    }
    for s in 0..nv {
        ok[s] = ok[s] && count[s] > 0 && (total[s] - 4.0 * std::f64::consts::PI).abs() < 1.0;
    }
    if closed {
        return Ok(shell.iter().map(|&s| ok[s as usize]).collect());
    }
    // Closed: every undirected edge of a passing shell exactly twice, in opposite directions.
    let mut edges: Vec<(u32, u32, u32, bool)> = triangles
        .iter()
        .zip(shell)
        .filter(|(_, &s)| ok[s as usize])
        .flat_map(|(t, &s)| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])].map(|(a, b)| (s, a.min(b), a.max(b), a < b)))
        .collect();
    edges.par_sort_unstable();
    let mut k = 0;
    while k < edges.len() {
        let e = edges[k];
        let mut j = k;
        while j < edges.len() && (edges[j].0, edges[j].1, edges[j].2) == (e.0, e.1, e.2) {
            j += 1;
        }
        if j - k != 2 || edges[k].3 == edges[k + 1].3 || e.1 == e.2 {
            ok[e.0 as usize] = false;
        }
        k = j;
    }
    Ok(shell.iter().map(|&s| ok[s as usize]).collect())
}

/// The gate before [`star_shaped_shells`]: every triangle positively oriented seen from the mean
/// of all triangle vertices (one parallel pass, no shells). A mesh failing it gets no shell
/// certificate, so a non-star-shaped surface (a torus) pays no shell computation; a mesh of one
/// shell passing it is usually certified. (A mesh of several star-shaped shells that is not
/// star-shaped as a whole is searched as before.) A gate only, never a certificate.
pub fn star_shaped_about_centroid(positions: &[DVec3], triangles: &[[u32; 3]]) -> bool {
    let nv = positions.len();
    if triangles.is_empty() || triangles.iter().flatten().any(|&v| v as usize >= nv) {
        return false;
    }
    let sum = triangles.par_iter().with_min_len(1 << 12).map(|t| t.iter().map(|&v| positions[v as usize]).sum::<DVec3>()).sum::<DVec3>();
    let o = sum / (3 * triangles.len()) as f64;
    triangles.par_iter().with_min_len(1 << 12).all(|t| {
        let [a, b, c] = t.map(|v| positions[v as usize]);
        (a - o).dot((b - a).cross(c - a)) > 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::api::{convert_unchecked, ConvertOptions, Method};
    use crate::gb::Layout;

    /// The undirected-edge-free form of a loop: its directed edges, sorted.
    fn edges_of(lp: &[u32]) -> Vec<(u32, u32)> {
        let mut e: Vec<(u32, u32)> = (0..lp.len()).map(|k| (lp[k], lp[(k + 1) % lp.len()])).collect();
        e.sort_unstable();
        e
    }

    /// Every star of `loops`: where [`star_loop`] finds a loop, [`single_loop`] finds the same
    /// one (as directed edges). Returns how many stars took the sort-free path.
    fn same_loops(loops: &PatchLoops) -> usize {
        let (corners, groups) = node_groups(loops);
        let mut fast = 0;
        let mut walk = Vec::new();
        for &(s, e) in &groups {
            let ps: Vec<u32> = corners[s..e].iter().map(|c| c.1).collect();
            if star_loop(loops, corners[s].0, &ps, &mut walk) {
                fast += 1;
                let slow = single_loop(star_edges(loops, &ps)).expect("the general path finds a loop too");
                assert_eq!(edges_of(&walk), edges_of(&slow), "star of {}", corners[s].0);
            }
        }
        fast
    }

    #[test]
    fn the_sort_free_star_loop_is_the_general_one() {
        let models = [
            crate::mesh::generate::torus(12, 8, 10.0, 3.0).unwrap(),
            crate::mesh::generate::uv_sphere(8, 5).unwrap(),
            crate::mesh::generate::prism(7).unwrap(),
            crate::mesh::generate::cone(9).unwrap(),
        ];
        for mesh in &models {
            for method in [Method::Dual, Method::Topology] {
                for (layout, r) in [(Layout::Quads, 1), (Layout::Quads, 2), (Layout::Triangles, 3)] {
                    let opts = ConvertOptions { method, layout, resolution: r, ..Default::default() };
                    let c = convert_unchecked(mesh, &opts).unwrap();
                    let loops = &c.mesh.patch_loops;
                    let fast = same_loops(loops);
                    // The interior stars of these closed surfaces all take the sort-free path.
                    assert_eq!(fast, node_groups(loops).1.len(), "{method:?} {layout:?} r = {r}");
                }
            }
        }
    }

    #[test]
    fn the_sort_free_star_loop_refuses_what_it_cannot_prove() {
        // A torus tessellation, then damaged loops: each damage sends the stars touching it to
        // the general path (or both paths agree), never to a different loop.
        let opts = ConvertOptions { method: Method::Dual, resolution: 2, ..Default::default() };
        let mesh = crate::mesh::generate::torus(6, 5, 10.0, 3.0).unwrap();
        let base = convert_unchecked(&mesh, &opts).unwrap().mesh.patch_loops;
        let (corners, groups) = node_groups(&base);
        let star = |loops: &PatchLoops, g: usize| -> (bool, Vec<u32>) {
            let (s, e) = groups[g];
            let ps: Vec<u32> = corners[s..e].iter().map(|c| c.1).collect();
            let mut walk = Vec::new();
            (star_loop(loops, corners[s].0, &ps, &mut walk), ps)
        };
        let (ok, ps) = star(&base, 0);
        assert!(ok);
        let first = ps[0] as usize;
        let (a, b) = (base.start[first], base.start[first + 1]);
        // 1. An edge from a vertex to itself in an out-side (q repeated): refused by both.
        let mut dup = base.clone();
        let q = corners[groups[0].0].0;
        let k = dup.ids[a..b].iter().position(|&v| v == q).unwrap();
        let len = b - a;
        dup.ids[a + (k + 1) % len] = q;
        assert!(!star(&dup, 0).0);
        assert!(single_loop(star_edges(&dup, &ps)).is_none());
        // 2. A patch loop reversed: its sides no longer cancel, no sort-free loop.
        let mut rev = base.clone();
        rev.ids[a..b].reverse();
        assert!(!star(&rev, 0).0);
        // 3. An outer vertex of one patch renamed to another vertex of the star's boundary: the
        //    walk repeats a vertex, refused (the general path refuses too).
        let mut rep = base.clone();
        let m = rep.per_side;
        let outer = (k + m + 1) % len;
        let other = (k + 2 * m) % len;
        rep.ids[a + outer] = rep.ids[a + other];
        assert!(!star(&rep, 0).0);
        assert!(single_loop(star_edges(&rep, &ps)).is_none());
        // Every other star of the damaged loops still agrees with the general path.
        for loops in [&dup, &rev, &rep] {
            same_loops(loops);
        }
    }
}
